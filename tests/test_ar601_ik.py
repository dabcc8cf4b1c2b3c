"""Tests of the closed-form inverse kinematics of the AR-601 leg (robokin.models.ar601_ik).

References: the model's forward kinematics (every solution must reproduce the
pose), the generating configuration (must be among the solutions), the
numerical solver robokin.motion.solve_ik, and hand-made singular poses.
"""

from __future__ import annotations

import numpy as np
import pytest

from robokin.chains import SerialChain
from robokin.errors import DomainError, ShapeError
from robokin.models.ar601 import ar601_leg
from robokin.models.ar601_ik import (
    REASONS,
    AR601IKResult,
    ar601_leg_ik,
    ar601_leg_ik_batch,
)
from robokin.motion import solve_ik
from robokin.transforms import (
    rotation_from_rpy,
    rotx,
    roty,
    rotz,
    rpy_from_rotation,
    transform,
)

LEG = ar601_leg()
WIDE = SerialChain(LEG.elements, limits=[[-np.pi, np.pi]] * 6, name="ar601_wide")


def wrapped(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def pose_gap(chain, q, T):
    F = chain.fk(q)
    return np.linalg.norm(F[:3, 3] - T[:3, 3]), np.abs(F[:3, :3] - T[:3, :3]).max()


# ---------------------------------------------------------------- random reachable poses
@pytest.fixture(scope="module")
def random_cases():
    Q = LEG.random_configurations(300, seed=42)
    return Q, LEG.fk(Q), ar601_leg_ik_batch(LEG.fk(Q))


def test_every_solution_reproduces_the_pose(random_cases):
    Q, T, results = random_cases
    for _q, Tq, res in zip(Q, T, results):
        assert res.success and res.reason == "solved"
        F = LEG.fk(res.q)
        assert np.allclose(F, Tq, atol=1e-10)
        assert res.position_residual.max() < 1e-12 and res.orientation_residual.max() < 1e-12


def test_generating_configuration_is_found(random_cases):
    Q, _, results = random_cases
    for q, res in zip(Q, results):
        assert np.abs(wrapped(res.q - q)).max(axis=1).min() < 1e-8


def test_eight_distinct_solutions_in_general(random_cases):
    _, _, results = random_cases
    for res in results:
        assert len(res) == 8 and res.q.shape == (8, 6)
        gaps = np.abs(wrapped(res.q[:, None, :] - res.q[None, :, :])).max(axis=2)
        assert np.all(gaps[~np.eye(8, dtype=bool)] > 1e-6)
        # all sign combinations (knee, ankle, hip) appear once
        assert {tuple(b) for b in res.branches} == {(a, b, c) for a in (1, -1) for b in (1, -1) for c in (1, -1)}
        assert np.all(np.sign(res.q[:, 3]) == res.branches[:, 0])
        assert np.all((np.abs(res.q[:, 1]) <= np.pi / 2 + 1e-12) == (res.branches[:, 2] == 1))
        assert np.all(np.abs(res.q) <= np.pi + 1e-12)


def test_hip_angles_are_the_rpy_of_the_hip_rotation(random_cases):
    _, _, results = random_cases
    for res in results[:50]:
        for q, b in zip(res.q, res.branches):
            R_hip = rotz(q[0]) @ roty(q[1]) @ rotx(q[2])
            if b[2] == 1:   # the principal branch is robokin's roll-pitch-yaw (roll = q3, yaw = q1)
                assert np.allclose(rpy_from_rotation(R_hip), [q[2], q[1], q[0]], atol=1e-9)


def test_within_limits_filter(random_cases):
    Q, T, results = random_cases
    for _q, Tq, res in zip(Q[:40], T[:40], results[:40]):
        assert np.array_equal(res.within_limits, LEG.within_limits(res.q))
        inside = ar601_leg_ik(Tq, within_limits=True)
        assert inside.success and np.all(LEG.within_limits(inside.q))
        assert len(inside) == int(res.within_limits.sum()) >= 1   # at least the generating one


def test_agrees_with_numerical_ik(random_cases):
    _, T, results = random_cases
    rng = np.random.default_rng(7)
    for Tq, res in zip(T[:12], results[:12]):
        for q in res.q:
            start = q + rng.normal(scale=0.05, size=6)
            num = solve_ik(WIDE, Tq, q0=start, restarts=0, tol=1e-10, wrap=True)
            assert num.success
            assert np.abs(wrapped(num.q - q)).max() < 1e-6


def test_other_lengths():
    leg = ar601_leg(0.35, 0.25, 0.08)
    Q = leg.random_configurations(30, seed=3)
    for q, T in zip(Q, leg.fk(Q)):
        res = ar601_leg_ik(T, 0.35, 0.25, 0.08)
        assert res.success and len(res) == 8
        assert np.allclose(leg.fk(res.q), T, atol=1e-10)
        assert np.abs(wrapped(res.q - q)).max(axis=1).min() < 1e-8


# ---------------------------------------------------------------- exercise-style reference values
@pytest.mark.parametrize("q, z_foot", [
    (np.zeros(6), -0.7),                                  # straight leg: foot at -(L1 + L2 + L3)
    (np.array([0.0, 0.0, 0.0, np.pi / 2, 0.0, -np.pi / 2]), None),
    (np.array([0.3, 0.1, 0.6, -1.2, -0.1, 0.6]), None),   # a walking-like pose, sole level
])
def test_reference_poses(q, z_foot):
    T = LEG.fk(q)
    if z_foot is not None:
        assert np.allclose(T[:3, 3], [0, 0, z_foot])
    res = ar601_leg_ik(T)
    assert res.success
    assert np.abs(wrapped(res.q - q)).max(axis=1).min() < 1e-8
    assert np.isclose(res.distance, np.linalg.norm(T[:3, 3] + 0.1 * T[:3, 2]))


def test_report_example_in_metres():
    # the report's lengths 10, 10, 10 and straight leg: foot at z = -30 (units), not -10
    leg = ar601_leg(10.0, 10.0, 10.0)
    T = leg.fk(np.zeros(6))
    assert np.allclose(T[:3, 3], [0, 0, -30])
    res = ar601_leg_ik(T, 10.0, 10.0, 10.0)
    assert res.success and "stretched_knee" in res.singular
    assert np.allclose(leg.fk(res.q), T, atol=1e-9)


# ---------------------------------------------------------------- singular cases
def test_stretched_knee():
    q = np.array([0.2, 0.3, -0.4, 0.0, 0.5, 0.1])
    res = ar601_leg_ik(LEG.fk(q))
    assert res.success and "stretched_knee" in res.singular
    assert len(res) == 4 and np.allclose(res.q[:, 3], 0.0)
    assert np.allclose(LEG.fk(res.q), LEG.fk(q), atol=1e-10)
    assert np.abs(wrapped(res.q - q)).max(axis=1).min() < 1e-8


def test_nearly_stretched_knee_is_accurate():
    for eps in (1e-4, 1e-6, 1e-9):
        q = np.array([0.2, 0.3, -0.4, eps, 0.5, 0.1])
        res = ar601_leg_ik(LEG.fk(q))
        assert res.success
        assert res.position_residual.max() < 1e-9 and res.orientation_residual.max() < 1e-9


@pytest.mark.parametrize("s2", [1.0, -1.0])
def test_hip_gimbal(s2):
    q = np.array([0.2, s2 * np.pi / 2, -0.4, 0.7, 0.5, 0.1])
    T = LEG.fk(q)
    res = ar601_leg_ik(T)
    assert res.success and "hip_gimbal" in res.singular
    assert np.allclose(LEG.fk(res.q), T, atol=1e-10)
    locked = np.isclose(np.abs(res.q[:, 1]), np.pi / 2)
    assert locked.any() and np.allclose(res.q[locked, 0], 0.0)   # representative: q1 = 0
    # the family: only q1 - s2 q3 is determined
    member = res.q[locked & np.isclose(res.q[:, 1], s2 * np.pi / 2)
                   & np.isclose(res.q[:, 3], q[3])][0]
    assert np.isclose(wrapped(member[0] - s2 * member[2]), wrapped(q[0] - s2 * q[2]))
    assert len(res) < 8


def test_near_gimbal_is_accurate():
    for eps in (1e-5, 1e-8, 1e-11):
        q = np.array([0.2, np.pi / 2 - eps, -0.4, 0.7, 0.5, 0.1])
        res = ar601_leg_ik(LEG.fk(q))
        assert res.success
        assert res.position_residual.max() < 1e-9 and res.orientation_residual.max() < 1e-9


# ---------------------------------------------------------------- unreachable targets
def test_too_far():
    T = LEG.fk(np.zeros(6))
    T[2, 3] -= 0.01
    res = ar601_leg_ik(T)
    assert not res.success and res.reason == "too_far" and len(res) == 0
    assert res.q.shape == (0, 6) and np.isclose(res.distance, 0.61)


def test_too_close():
    leg = ar601_leg(0.4, 0.2, 0.1)
    T = transform(np.eye(3), [0.0, 0.0, -0.25])     # ankle 0.15 m from the hip < 0.4 - 0.2
    res = ar601_leg_ik(T, 0.4, 0.2, 0.1)
    assert not res.success and res.reason == "too_close"
    num = solve_ik(SerialChain(leg.elements, limits=[[-np.pi, np.pi]] * 6), T, restarts=10)
    assert not num.success


def test_ankle_cannot_orient_the_foot():
    R = roty(np.deg2rad(80.0))
    T = transform(R, np.array([0.0, 0.0, -0.5]) - 0.1 * R[:, 2])
    res = ar601_leg_ik(T)
    assert not res.success and res.reason == "ankle_range"
    num = solve_ik(WIDE, T, restarts=20)   # the numerical solver cannot do it either
    assert not num.success and num.position_error + num.orientation_error > 1e-3


def test_joint_limits_reason():
    T = transform(rotation_from_rpy([0.0, 0.0, 3.0]), [0.0, 0.0, -0.6])   # foot turned by 172°
    res = ar601_leg_ik(T)
    assert res.success and not res.within_limits.any()
    limited = ar601_leg_ik(T, within_limits=True)
    assert not limited.success and limited.reason == "joint_limits" and len(limited) == 0
    assert all(r in REASONS for r in (res.reason, limited.reason))


def test_result_repr_and_len():
    res = ar601_leg_ik(LEG.fk(np.full(6, 0.2)))
    assert isinstance(res, AR601IKResult) and len(res) == 8
    assert repr(res).startswith("AR601IKResult(solutions=8, success=True")


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("T, error", [
    (np.eye(3), ShapeError),
    (np.zeros((4, 4)), DomainError),
    (np.full((4, 4), np.nan), DomainError),
    (np.stack([np.eye(4)] * 2), ShapeError),
])
def test_bad_target(T, error):
    with pytest.raises(error, match="T_target"):
        ar601_leg_ik(T)


@pytest.mark.parametrize("lengths, name", [((-0.3, 0.3, 0.1), "l1"), ((0.3, 0.0, 0.1), "l2"),
                                           ((0.3, 0.3, np.inf), "l3")])
def test_bad_lengths(lengths, name):
    with pytest.raises(DomainError, match=name):
        ar601_leg_ik(np.eye(4), *lengths)


def test_batch():
    Q = LEG.random_configurations(5, seed=1)
    results = ar601_leg_ik_batch(LEG.fk(Q))
    assert len(results) == 5 and all(r.success for r in results)
    assert len(ar601_leg_ik_batch(LEG.fk(Q[0]))) == 1
    with pytest.raises(ShapeError, match="T_targets"):
        ar601_leg_ik_batch(np.zeros((2, 3, 3)))


def test_hip_on_the_ankle_axis():
    # stretched knee and ankle roll of 90 deg: the hip lies on the q6 axis, q6 is free
    q = np.array([0.1, 0.2, 0.3, 0.0, np.pi / 2, 0.4])
    T = LEG.fk(q)
    res = ar601_leg_ik(T)
    assert res.success and {"stretched_knee", "ankle_axis"} <= set(res.singular)
    assert np.allclose(LEG.fk(res.q), T, atol=1e-10) and np.allclose(res.q[:, 5], 0.0)


@pytest.mark.parametrize("lengths", [(0.3, 0.3, 0.1), (0.35, 0.25, 0.1)])
def test_folded_knee(lengths):
    leg = ar601_leg(*lengths)
    q = np.array([0.1, 0.2, 0.3, np.pi, 0.3, 0.4])
    res = ar601_leg_ik(leg.fk(q), *lengths)
    assert res.success and "folded_knee" in res.singular
    assert np.allclose(np.abs(res.q[:, 3]), np.pi) and np.allclose(leg.fk(res.q), leg.fk(q), atol=1e-10)
    assert not res.within_limits.any()
