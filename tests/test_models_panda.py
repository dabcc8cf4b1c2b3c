"""Tests of robokin.models.panda: three independent descriptions, FD Jacobian, reference poses."""

from __future__ import annotations

import numpy as np
import pytest

from robokin.models.panda import PANDA_LIMITS, PANDA_READY, panda, panda_link_transforms
from robokin.transforms import rotx

DESCRIPTIONS = ("link_table", "mdh", "urdf")


@pytest.fixture(scope="module")
def robots():
    return {d: panda(d) for d in DESCRIPTIONS}


def mdh_by_hand(q):
    """Craig's link transform Rx(alpha) Tx(a) Rz(theta) Tz(d), multiplied out (Franka's table)."""
    a = [0, 0, 0, 0.0825, -0.0825, 0, 0.088]
    d = [0.333, 0, 0.316, 0, 0.384, 0, 0]
    al = [0, -np.pi / 2, np.pi / 2, np.pi / 2, -np.pi / 2, np.pi / 2, np.pi / 2]
    T = np.eye(4)
    for i in range(7):
        ct, st, ca, sa = np.cos(q[i]), np.sin(q[i]), np.cos(al[i]), np.sin(al[i])
        T = T @ np.array([[ct, -st, 0, a[i]], [st * ca, ct * ca, -sa, -sa * d[i]],
                          [st * sa, ct * sa, ca, ca * d[i]], [0, 0, 0, 1]])
    F = np.eye(4)
    F[2, 3] = 0.107
    return T @ F


def test_descriptions_agree(robots):
    Q = robots["mdh"].random_configurations(100, seed=0)
    ref = np.stack([mdh_by_hand(q) for q in Q])
    for d in DESCRIPTIONS:
        r = robots[d]
        assert r.n == 7 and np.allclose(r.limits, PANDA_LIMITS)
        assert np.allclose(r.fk(Q), ref, atol=1e-12), d
        assert np.allclose(r.jacobian(Q), robots["mdh"].jacobian(Q), atol=1e-12), d


@pytest.mark.parametrize("q, p_expected, z_expected", [
    (np.zeros(7), [0.088, 0.0, 0.926], [0, 0, -1]),          # 0.333 + 0.316 + 0.384 - 0.107
    (PANDA_READY, [0.30689, 0.0, 0.59028], [0, 0, -1]),      # franka "ready" pose
])
def test_reference_poses(robots, q, p_expected, z_expected):
    T = robots["link_table"].fk(q)
    assert np.allclose(T[:3, 3], p_expected, atol=1e-4)
    assert np.allclose(T[:3, 2], z_expected, atol=1e-9)


def test_jacobian_finite_differences(robots):
    r = robots["link_table"]
    h = 1e-6
    for q in r.random_configurations(10, seed=1):
        J = r.jacobian(q)
        for i in range(7):
            dq = np.zeros(7)
            dq[i] = h
            Tp, Tm = r.fk(q + dq), r.fk(q - dq)
            assert np.allclose(J[:3, i], (Tp[:3, 3] - Tm[:3, 3]) / (2 * h), atol=1e-8)
            A = Tp[:3, :3] @ Tm[:3, :3].T
            w = 0.5 * np.array([A[2, 1] - A[1, 2], A[0, 2] - A[2, 0], A[1, 0] - A[0, 1]])
            assert np.allclose(J[3:, i], w / (2 * h), atol=1e-8)


def test_link_transforms_are_the_geometric_model():
    mats = panda_link_transforms()
    assert len(mats) == 8
    assert np.allclose(mats[1][:3, :3], rotx(-np.pi / 2))
    assert np.allclose(mats[4][:3, 3], [-0.0825, 0.384, 0.0])   # Rx(-pi/2) Tx(-0.0825) Tz(0.384): d ends up along +y
    for T in mats:
        assert np.allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3)) and np.allclose(T[3], [0, 0, 0, 1])


def test_ready_pose_within_limits_and_regular(robots):
    r = robots["link_table"]
    assert r.within_limits(np.array(PANDA_READY))
    assert np.linalg.matrix_rank(r.jacobian(PANDA_READY)) == 6


def test_unknown_description():
    with pytest.raises(ValueError, match="description"):
        panda("dh")
