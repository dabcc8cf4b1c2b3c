"""Tests of robokin.chains.reference, and of the engine of SerialChain against it.

Every model of :mod:`robokin.models`, in each of its descriptions, is evaluated at random
configurations (inside and beyond its joint limits) by the engine (``fk``, ``jacobian``,
``fk_and_jacobian``; one configuration and batches) and by :mod:`robokin.chains.reference`
(a product of link transforms; columns z × (p − o), z for revolute joints and z, 0 for
prismatic ones): they agree to 1e-12. The reference itself is checked against finite
differences and known poses.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable

import numpy as np
import pytest

import robokin.models
from robokin.chains import Rx, SerialChain, Tx, Ty, Tz
from robokin.chains.reference import forward_kinematics, geometric_jacobian, link_transform
from robokin.errors import ShapeError
from robokin.models import ar601_leg, baxter_left, eth_leg, genova_arm, panda, planar_two_link, ur10
from robokin.models.baxter import baxter_left_urdf
from support.finite_differences import pose_jacobian

#: engine against reference: both are products of the same float matrices, in other orders
TOLERANCE = 1e-12
SAMPLES = 40

MODELS: dict[str, Callable[[], SerialChain]] = {
    "planar_two_link": planar_two_link,
    "eth_leg": eth_leg,
    "ur10": ur10,
    "ur10_mdh": lambda: ur10("mdh"),
    "ur10_ets": lambda: ur10("ets"),
    "baxter_left": baxter_left,
    "baxter_left_shoulder_gripper": lambda: baxter_left(base="shoulder", end="gripper"),
    "baxter_left_urdf": baxter_left_urdf,
    "ar601_leg": ar601_leg,
    "genova_arm": genova_arm,
    "panda": panda,
    "panda_mdh": lambda: panda("mdh"),
    "panda_urdf": lambda: panda("urdf"),
}


@pytest.fixture(scope="module", params=list(MODELS))
def chain(request) -> SerialChain:
    return MODELS[request.param]()


def configurations(chain: SerialChain, seed: int = 0) -> np.ndarray:
    """Half inside the joint limits, half anywhere in [-2π, 2π] (or [-2, 2] m)."""
    rng = np.random.default_rng(seed)
    inside = chain.random_configurations(SAMPLES // 2, seed=rng)
    beyond = rng.uniform(-2 * math.pi, 2 * math.pi, (SAMPLES // 2, chain.n))
    prismatic = np.array([kind == "prismatic" for kind in chain.joint_types])
    beyond[:, prismatic] /= math.pi
    return np.vstack([inside, beyond])


def test_every_model_factory_is_checked():
    """A model added to robokin.models (a factory returning a SerialChain) must be listed above."""
    factories = {name for name in robokin.models.__all__
                 if inspect.isfunction(getattr(robokin.models, name))
                 and inspect.signature(getattr(robokin.models, name)).return_annotation
                 in (SerialChain, "SerialChain")
                 and all(p.default is not p.empty or p.kind is p.VAR_KEYWORD
                         for p in inspect.signature(getattr(robokin.models, name)).parameters.values())}
    assert factories, "no model factory found"
    assert factories <= set(MODELS), f"not checked against the reference: {sorted(factories - set(MODELS))}"


def test_engine_fk_equals_the_product_of_link_transforms(chain):
    Q = configurations(chain)
    expected = np.array([forward_kinematics(chain, q) for q in Q])
    for q, T in zip(Q, expected):
        np.testing.assert_allclose(chain.fk(q), T, rtol=0, atol=TOLERANCE)
        np.testing.assert_allclose(chain.fk(q, check=False), T, rtol=0, atol=TOLERANCE)
    np.testing.assert_allclose(chain.fk(Q), expected, rtol=0, atol=TOLERANCE)


def test_engine_jacobian_equals_the_columns_of_the_book(chain):
    Q = configurations(chain, seed=1)
    expected = np.array([geometric_jacobian(chain, q) for q in Q])
    for q, J in zip(Q, expected):
        np.testing.assert_allclose(chain.jacobian(q), J, rtol=0, atol=TOLERANCE)
        np.testing.assert_allclose(chain.jacobian(q, check=False), J, rtol=0, atol=TOLERANCE)
    np.testing.assert_allclose(chain.jacobian(Q), expected, rtol=0, atol=TOLERANCE)


def test_engine_fk_and_jacobian_equal_the_reference(chain):
    Q = configurations(chain, seed=2)
    for q in Q:
        T, J = chain.fk_and_jacobian(q)
        np.testing.assert_allclose(T, forward_kinematics(chain, q), rtol=0, atol=TOLERANCE)
        np.testing.assert_allclose(J, geometric_jacobian(chain, q), rtol=0, atol=TOLERANCE)
    T, J = chain.fk_and_jacobian(Q)
    np.testing.assert_allclose(T, [forward_kinematics(chain, q) for q in Q], rtol=0, atol=TOLERANCE)
    np.testing.assert_allclose(J, [geometric_jacobian(chain, q) for q in Q], rtol=0, atol=TOLERANCE)


def test_reference_jacobian_equals_finite_differences(chain):
    class ReferenceChain:
        """fk of the reference, for the finite differences (independent of the engine)."""

        def fk(self, q):
            return forward_kinematics(chain, q)

    for q in configurations(chain, seed=3)[::8]:
        np.testing.assert_allclose(geometric_jacobian(chain, q), pose_jacobian(ReferenceChain(), q),
                                   rtol=0, atol=1e-7)


def test_reference_known_poses():
    # the ETH leg: foot 3 m below the hip's 1 m offset at q = 0, 2 m behind with the knee at 90°
    leg = eth_leg()
    np.testing.assert_allclose(forward_kinematics(leg, np.array([0.0, 0.0, 0.0]))[:3, 3], [0.0, 1.0, -3.0], atol=1e-15)
    np.testing.assert_allclose(forward_kinematics(leg, np.array([0.0, math.pi / 2, 0.0]))[:3, 3], [-2.0, 1.0, -1.0],
                               atol=1e-15)
    # planar RR arm, unit links: J_v = [[-s1 - s12, -s12], [c1 + c12, c12]], ω = z
    arm = planar_two_link()
    q1, q2 = 0.3, 0.7
    J = geometric_jacobian(arm, np.array([q1, q2]))
    s1, c1, s12, c12 = math.sin(q1), math.cos(q1), math.sin(q1 + q2), math.cos(q1 + q2)
    np.testing.assert_allclose(J[:2], [[-s1 - s12, -s12], [c1 + c12, c12]], atol=1e-15)
    np.testing.assert_allclose(J[2:], [[0, 0], [0, 0], [0, 0], [1, 1]], atol=1e-15)


def test_prismatic_column_and_joint_sign_and_offset():
    # a prismatic joint along −x after a revolute joint about x with an offset of 0.5 rad
    chain = SerialChain([Rx("a", offset=0.5), Ty(0.2), Tx("-d"), Tz(0.1)])
    q = np.array([0.3, 0.4])
    np.testing.assert_allclose(geometric_jacobian(chain, q)[:, 1], [-1, 0, 0, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(link_transform(chain.elements[0], 0.3)[1:3, 1:3],
                               [[math.cos(0.8), -math.sin(0.8)], [math.sin(0.8), math.cos(0.8)]], atol=1e-15)
    np.testing.assert_allclose(chain.jacobian(q), geometric_jacobian(chain, q), rtol=0, atol=TOLERANCE)


def test_bad_configuration_names_q():
    with pytest.raises(ShapeError, match="q"):
        forward_kinematics(ur10(), np.array([0.0, 1.0]))
    with pytest.raises(ShapeError, match="q"):
        geometric_jacobian(ur10(), np.zeros(7))
