"""Tests of robokin.models.genova_arm: the course's 7-joint arm with a prismatic joint 6.

References are independent of robokin's chain engine: forward kinematics at
configurations worked out by hand from the link table, the link-table product
multiplied out with plain numpy, and central finite differences for the
Jacobian (the prismatic column included).
"""

from __future__ import annotations

import numpy as np
import pytest

from robokin.errors import DomainError, ShapeError
from robokin.models import genova_arm
from robokin.models.genova_arm import (
    GENOVA_ARM_JOINT_TYPES,
    GENOVA_ARM_LIMITS,
    genova_arm_link_transforms,
)

# The table of the course, typed again here (not imported): R_i rows and p_i in metres.
TABLE = [
    (np.eye(3), [0, 0, 0.105]),
    ([[0, 1, 0], [0, 0, 1], [1, 0, 0]], [0, 0, 0.110]),
    ([[0, 0, 1], [0, -1, 0], [1, 0, 0]], [0.1, 0, 0]),
    ([[0, 0, 1], [0, -1, 0], [1, 0, 0]], [0, 0, 0.325]),
    ([[0, 0, 1], [-1, 0, 0], [0, -1, 0]], [0.095, 0, 0]),
    (np.diag([-1, -1, 1]), [0, 0, 0.095]),
    (np.eye(3), [0, 0, 0.355]),
]
PRISMATIC = 5  # index of joint 6


def homogeneous(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def fk_by_hand(q):
    """prod_i T0_i · Rz(q_i) (revolute) or T0_i · Tz(q_i) (prismatic), with plain numpy."""
    T = np.eye(4)
    for i, (R, p) in enumerate(TABLE):
        if i == PRISMATIC:
            motion = homogeneous(np.eye(3), [0, 0, q[i]])
        else:
            c, s = np.cos(q[i]), np.sin(q[i])
            motion = homogeneous([[c, -s, 0], [s, c, 0], [0, 0, 1]], [0, 0, 0])
        T = T @ homogeneous(R, p) @ motion
    return T


@pytest.fixture(scope="module")
def arm():
    return genova_arm()


def test_structure(arm):
    assert arm.n == 7 and arm.name == "genova_arm"
    assert arm.joint_types == ["revolute"] * 5 + ["prismatic", "revolute"]
    assert GENOVA_ARM_JOINT_TYPES == ("R", "R", "R", "R", "R", "P", "R")
    assert np.array_equal(arm.limits, [[-3.14, 3.14]] * 5 + [[0.0, 1.0]] + [[-3.14, 3.14]])
    assert np.array_equal(arm.limits, GENOVA_ARM_LIMITS)
    assert arm.joint_names == [f"q{i}" for i in range(1, 8)]
    assert list(arm.frame_names) == ["B", "1", "2", "3", "4", "5", "6", "7", "E"]
    assert np.array_equal(arm.joint_axes, np.tile([0.0, 0.0, 1.0], (7, 1)))   # every joint on its z axis


def test_link_transforms_are_the_table():
    mats = genova_arm_link_transforms()
    assert len(mats) == 7
    for T, (R, p) in zip(mats, TABLE):
        assert np.array_equal(T, homogeneous(R, p))
        assert np.isclose(np.linalg.det(T[:3, :3]), 1.0)                  # proper rotations
        assert np.allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3))


# Configurations worked out by hand from the table. At q = 0 the product of the R_i
# is the identity and every frame is parallel to the base: the arm stands straight up
# with E at the sum of the offsets, 1.185 m. Sliding joint 6 by d moves E up by d
# (z_6 = z_B there). Joint 2 sits at height 0.105 + 0.110 = 0.215 m and its axis
# z_2 = R_2 e_z = y_B: q2 = +pi/2 swings the 0.970 m above it about +y_B onto +x_B.
HAND = [
    (np.zeros(7), np.eye(3), [0.0, 0.0, 1.185]),
    ([0, 0, 0, 0, 0, 0.5, 0], np.eye(3), [0.0, 0.0, 1.685]),
    ([0, np.pi / 2, 0, 0, 0, 0, 0], [[0, 0, 1], [0, 1, 0], [-1, 0, 0]], [0.970, 0.0, 0.215]),
    ([np.pi / 2, 0, 0, 0, 0, 0.2, 0], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], [0.0, 0.0, 1.385]),
]


@pytest.mark.parametrize("q, R, p", HAND, ids=["zero", "slide", "shoulder", "turn_and_slide"])
def test_fk_by_hand(arm, q, R, p):
    T = arm.fk(np.asarray(q, dtype=float))
    assert np.allclose(T[:3, :3], R, atol=1e-12)
    assert np.allclose(T[:3, 3], p, atol=1e-12)


def test_fk_equals_the_table_product(arm):
    Q = arm.random_configurations(50, seed=0)
    Q = np.vstack([Q, [np.pi / 2, -np.pi / 4, 0, -np.pi / 4, 0, 0.15, np.pi / 4]])   # the exercise's start
    assert np.allclose(arm.fk(Q), np.stack([fk_by_hand(q) for q in Q]), atol=1e-12)
    # the frames too: frame 6 of the chain is the product up to and including Tz(q6)
    q = Q[0]
    F = arm.frames(q)
    T6 = np.eye(4)
    for i in range(6):
        R, p = TABLE[i]
        motion = homogeneous(np.eye(3), [0, 0, q[i]]) if i == PRISMATIC else \
            homogeneous([[np.cos(q[i]), -np.sin(q[i]), 0], [np.sin(q[i]), np.cos(q[i]), 0], [0, 0, 1]], [0, 0, 0])
        T6 = T6 @ homogeneous(R, p) @ motion
    assert np.allclose(F[6], T6, atol=1e-12)
    assert np.allclose(F[-1], arm.fk(q)) and np.allclose(F[7], F[-1])      # E is frame 7


def fd_jacobian(q, h=1e-6):
    J = np.empty((6, 7))
    for i in range(7):
        dq = np.zeros(7)
        dq[i] = h
        Tp, Tm = fk_by_hand(q + dq), fk_by_hand(q - dq)
        J[:3, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        A = Tp[:3, :3] @ Tm[:3, :3].T
        J[3:, i] = 0.5 * np.array([A[2, 1] - A[1, 2], A[0, 2] - A[2, 0], A[1, 0] - A[0, 1]]) / (2 * h)
    return J


def test_jacobian_finite_differences(arm):
    for q in arm.random_configurations(10, seed=1):
        J = arm.jacobian(q)
        assert J.shape == (6, 7)
        assert np.allclose(J, fd_jacobian(q), atol=1e-8)


def test_prismatic_column(arm):
    """Joint 6 slides along z_6: its column is [z_6; 0] -- a velocity, no rotation."""
    for q in arm.random_configurations(10, seed=2):
        z6 = arm.frames(q)[6][:3, 2]
        col = arm.jacobian(q)[:, PRISMATIC]
        assert np.allclose(col[:3], z6, atol=1e-12) and np.allclose(col[3:], 0.0, atol=1e-12)
        # and moving q6 by d translates E by d z_6 without turning it
        dq = np.zeros(7)
        dq[PRISMATIC] = 0.01
        T, Td = arm.fk(q), arm.fk(q + dq)
        assert np.allclose(Td[:3, 3] - T[:3, 3], 0.01 * z6, atol=1e-12)
        assert np.allclose(Td[:3, :3], T[:3, :3], atol=1e-12)


def test_limits_override_and_validation():
    tight = [[-1.0, 1.0]] * 5 + [[0.1, 0.5]] + [[-1.0, 1.0]]
    assert np.array_equal(genova_arm(limits=tight).limits, tight)
    with pytest.raises(ShapeError, match="limits"):
        genova_arm(limits=[[0.0, 1.0]] * 6)
    with pytest.raises(DomainError, match="limits"):
        genova_arm(limits=[[1.0, 0.0]] * 7)
    with pytest.raises(TypeError, match="limits"):
        genova_arm(limits="wide")


def test_random_configurations_respect_the_slide(arm):
    Q = arm.random_configurations(200, seed=3)
    assert (Q[:, PRISMATIC] >= 0.0).all() and (Q[:, PRISMATIC] <= 1.0).all()
    assert arm.within_limits(Q).all()


def test_joints_5_and_7_turn_about_one_line(arm):
    """Only q5 + q7 matters: e5 - e7 is in the null space of J everywhere, and the rank is 6."""
    shift = np.array([0, 0, 0, 0, 1.0, 0, -1.0])
    for q in arm.random_configurations(20, seed=6):
        assert np.allclose(fk_by_hand(q + 0.7 * shift), fk_by_hand(q), atol=1e-12)
        J = arm.jacobian(q)
        assert np.allclose(J @ shift, 0.0, atol=1e-12)
        assert np.linalg.svd(J, compute_uv=False)[-1] > 1e-3          # rank 6 at these samples
