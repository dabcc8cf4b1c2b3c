"""Tests of robokin.chains.screws: the product of exponentials and Lynch & Park's Jacobians.

For every model factory of :mod:`robokin.models`, at random configurations: the product of
exponentials equals ``SerialChain.fk``; the space and body Jacobians equal the book's geometric
Jacobian through the relations of ``book/conventions.md``; and all three equal the Modern
Robotics library's ``FKinSpace``, ``JacobianSpace`` and ``JacobianBody`` given the same screw
axes (a test-only dependency).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable

import numpy as np
import pytest

import robokin.models
from robokin.chains import SerialChain
from robokin.chains.screws import body_jacobian, product_of_exponentials, screw_axes, space_jacobian
from robokin.errors import ShapeError
from robokin.transforms import skew

mr = pytest.importorskip("modern_robotics", reason="modern_robotics (requirements.txt) cross-checks the Jacobians")

#: products of a few float matrices with unit-size entries (lengths about 1 m)
TOLERANCE = 1e-12


def model_factories() -> dict[str, Callable[[], SerialChain]]:
    """Every factory of robokin.models that builds a SerialChain without arguments."""
    out: dict[str, Callable[[], SerialChain]] = {}
    for name in robokin.models.__all__:
        factory = getattr(robokin.models, name)
        if not inspect.isfunction(factory):
            continue
        signature = inspect.signature(factory)
        if signature.return_annotation in (SerialChain, "SerialChain") and all(
                p.default is not p.empty or p.kind is p.VAR_KEYWORD for p in signature.parameters.values()):
            out[name] = factory
    return out


MODELS = model_factories()


@pytest.fixture(scope="module", params=sorted(MODELS))
def chain(request) -> SerialChain:
    return MODELS[request.param]()


def configurations(chain: SerialChain) -> np.ndarray:
    return chain.random_configurations(8, seed=3)


def test_models_are_found():
    assert {"ur10", "baxter_left", "panda", "eth_leg", "genova_arm"} <= set(MODELS)


def test_screw_axes_of_revolute_joints_have_zero_pitch(chain):
    """ω unit and v ⟂ ω (v = −ω × q); prismatic joints: ω = 0, v unit."""
    M, S = screw_axes(chain)
    assert np.allclose(M, chain.fk(np.zeros(chain.n)), rtol=0, atol=TOLERANCE)
    for kind, row in zip(chain.joint_types, S):
        if kind == "revolute":
            assert abs(np.linalg.norm(row[:3]) - 1) < TOLERANCE and abs(row[:3] @ row[3:]) < TOLERANCE
        else:
            assert np.array_equal(row[:3], np.zeros(3)) and abs(np.linalg.norm(row[3:]) - 1) < TOLERANCE


def test_product_of_exponentials_equals_fk(chain):
    q = configurations(chain)
    assert np.allclose(product_of_exponentials(chain, q), chain.fk(q), rtol=0, atol=TOLERANCE)


def test_space_jacobian_from_the_geometric_jacobian(chain):
    """J_s = [J_ω; J_v + [p] J_ω]: the spatial twist's v_s is the velocity of the point at the base origin."""
    q = configurations(chain)
    J, p = chain.jacobian(q), chain.fk(q)[:, :3, 3]
    expected = np.concatenate([J[:, 3:], J[:, :3] + skew(p) @ J[:, 3:]], axis=1)
    assert np.allclose(space_jacobian(chain, q), expected, rtol=0, atol=TOLERANCE)
    assert np.allclose(chain.space_jacobian(q), expected, rtol=0, atol=TOLERANCE)


def test_body_jacobian_from_the_geometric_jacobian(chain):
    """J_b = [Rᵀ J_ω; Rᵀ J_v]: the end-effector's twist in its own frame."""
    q = configurations(chain)
    J, R = chain.jacobian(q), chain.fk(q)[:, :3, :3]
    Rt = np.swapaxes(R, 1, 2)
    expected = np.concatenate([Rt @ J[:, 3:], Rt @ J[:, :3]], axis=1)
    assert np.allclose(body_jacobian(chain, q), expected, rtol=0, atol=TOLERANCE)
    assert np.allclose(chain.body_jacobian(q), expected, rtol=0, atol=TOLERANCE)


def test_equal_to_modern_robotics(chain):
    M, S = chain.screw_axes()
    B = mr.Adjoint(mr.TransInv(M)) @ S.T   # body screw axes (Lynch & Park 2017, eq. 4.16)
    for q in configurations(chain):
        assert np.allclose(product_of_exponentials(chain, q), mr.FKinSpace(M, S.T, q), rtol=0, atol=TOLERANCE)
        assert np.allclose(mr.FKinBody(M, B, q), chain.fk(q), rtol=0, atol=TOLERANCE)
        assert np.allclose(space_jacobian(chain, q), mr.JacobianSpace(S.T, q), rtol=0, atol=TOLERANCE)
        assert np.allclose(body_jacobian(chain, q), mr.JacobianBody(B, q), rtol=0, atol=TOLERANCE)


def test_single_configurations_equal_batch_rows(chain):
    q = configurations(chain)[:3]
    for function, shape in ((product_of_exponentials, (4, 4)), (space_jacobian, (6, chain.n)),
                            (body_jacobian, (6, chain.n))):
        batch = function(chain, q)
        assert batch.shape == (3, *shape)
        for k in range(3):
            assert np.allclose(function(chain, q[k]), batch[k], rtol=0, atol=1e-15)
        assert function(chain, np.zeros((0, chain.n))).shape == (0, *shape)


def test_a_configuration_of_the_wrong_length_is_named():
    arm = robokin.models.ur10()
    with pytest.raises(ShapeError, match=r"q must have shape \(6,\) or \(N, 6\); got shape \(5,\)"):
        arm.space_jacobian(np.zeros(5))
