"""Tests of robokin.motion.tool: tool transform, rigid-body Jacobian, tool Jacobian, chain with tool.

References are independent of the module: the tool Jacobian is compared with
central finite differences of the tool pose and with the chain's own Jacobian
of a point fixed in the end-effector frame; the transport matrix with the
cross-product formula v_T = v_E + ω × r.
"""

from __future__ import annotations

import numpy as np
import pytest

from robokin.chains import SerialChain
from robokin.errors import DomainError, ShapeError
from robokin.models import ur10
from robokin.models.panda import panda
from robokin.motion import CartesianController
from robokin.motion.tool import (
    chain_with_tool,
    rigid_body_jacobian,
    tool_jacobian,
)
from robokin.transforms import rotx, roty, rotz, transform_from_rpy
from support.finite_differences import pose_jacobian

# A tool turned by pi/10 about z_E (rpy = (0, 0, pi/10)) and offset 0.2 m along x_E. (The course reads
# its own triple as (yaw, pitch, roll), i.e. a roll about x_E: see Chapter 4 and genova_arm.)
ETA_TOOL = np.array([0.0, 0.0, np.pi / 10])
OFFSET = np.array([0.2, 0.0, 0.0])




@pytest.mark.parametrize("rpy, R_expected", [
    ((0.0, 0.0, np.pi / 10), rotz(np.pi / 10)),
    ((np.pi / 10, 0.0, 0.0), rotx(np.pi / 10)),
    ((0.0, 0.3, 0.0), roty(0.3)),
    ((-3.02, -0.40, -1.33), rotz(-1.33) @ roty(-0.40) @ rotx(-3.02)),
])
def test_transform_from_rpy_reference(rpy, R_expected):
    T = transform_from_rpy(rpy, [-0.14, -0.85, 0.6])
    assert np.allclose(T[:3, :3], R_expected)
    assert np.allclose(T[:3, 3], [-0.14, -0.85, 0.6])
    assert np.allclose(T[3], [0, 0, 0, 1])


def test_transform_from_rpy_old_import_paths():
    """transform_from_rpy moved to robokin.transforms; chapter 4 imports it from robokin.motion.tool."""
    import robokin
    import robokin.motion
    import robokin.motion.tool

    assert robokin.motion.tool.transform_from_rpy is transform_from_rpy
    assert robokin.motion.transform_from_rpy is transform_from_rpy
    assert robokin.transform_from_rpy is transform_from_rpy


def test_transform_from_rpy_goal_values():
    # goal frame of the exercise; entries of Rz(yaw) Ry(pitch) Rx(roll) multiplied out
    # (Siciliano eq. 2.22) and rounded to 4 decimals
    T = transform_from_rpy([-3.02, -0.40, -1.33], [-0.14, -0.85, 0.6])
    assert np.allclose(T[:3, :3], [[0.2197, -0.9527, 0.2100], [-0.8945, -0.2826, -0.3465],
                                   [0.3894, -0.1117, -0.9143]], atol=1e-4)
    assert np.isclose(np.linalg.det(T[:3, :3]), 1.0)


def test_transform_from_rpy_batch():
    rng = np.random.default_rng(0)
    rpy, p = rng.uniform(-3, 3, (5, 3)), rng.uniform(-1, 1, (5, 3))
    T = transform_from_rpy(rpy, p)
    assert T.shape == (5, 4, 4)
    for k in range(5):
        assert np.allclose(T[k], transform_from_rpy(rpy[k], p[k]))


def test_rigid_body_jacobian_cross_product():
    rng = np.random.default_rng(1)
    for _ in range(20):
        r, v, w = rng.normal(size=(3, 3))
        nu = rigid_body_jacobian(r) @ np.r_[v, w]
        assert np.allclose(nu, np.r_[v + np.cross(w, r), w])
    # the angular-first form [[I, 0], [skew(r)^T, I]] is the same map with the blocks swapped
    r = rng.normal(size=3)
    P = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])
    Sk = np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    S_ang_first = np.block([[np.eye(3), np.zeros((3, 3))], [Sk.T, np.eye(3)]])
    assert np.allclose(P @ rigid_body_jacobian(r) @ P, S_ang_first)
    # composition and inverse: S(a) S(b) = S(a + b), S(r)^-1 = S(-r)
    a, b = rng.normal(size=(2, 3))
    assert np.allclose(rigid_body_jacobian(a) @ rigid_body_jacobian(b), rigid_body_jacobian(a + b))
    assert rigid_body_jacobian(np.stack([a, b])).shape == (2, 6, 6)


@pytest.mark.parametrize("make", [lambda: panda(), lambda: ur10()], ids=["panda", "ur10"])
def test_tool_jacobian_matches_finite_differences(make):
    robot = make()
    T_et = transform_from_rpy(ETA_TOOL, OFFSET)
    tooled = chain_with_tool(robot, T_et)
    for q in robot.random_configurations(10, seed=2):
        T_be = robot.fk(q)
        J_t = tool_jacobian(robot.jacobian(q), T_be[:3, :3], OFFSET)
        assert np.allclose(J_t, pose_jacobian(tooled, q), atol=1e-7)
        assert np.allclose(J_t, tooled.jacobian(q), atol=1e-12)
        assert np.allclose(J_t, robot.jacobian(q, point=OFFSET), atol=1e-12)
        assert np.allclose(tooled.fk(q), T_be @ T_et)
        # robokin's controller with its tool option uses the same Jacobian
        ctrl = CartesianController(robot, np.eye(4), tool=T_et)
        assert np.allclose(ctrl.jacobian(q), J_t)


def test_tool_jacobian_batch_and_unrotated_offset_is_wrong():
    robot = panda()
    Q = robot.random_configurations(4, seed=3)
    J_t = tool_jacobian(robot.jacobian(Q), robot.fk(Q)[:, :3, :3], OFFSET)
    assert J_t.shape == (4, 6, 7)
    assert np.allclose(J_t, robot.jacobian(Q, point=OFFSET))
    wrong = rigid_body_jacobian(OFFSET) @ robot.jacobian(Q[0])      # offset not rotated into B
    assert not np.allclose(wrong, J_t[0], atol=1e-3)


def test_chain_with_tool_keeps_the_robot():
    robot = panda()
    tooled = chain_with_tool(robot, transform_from_rpy(ETA_TOOL, OFFSET), name="panda_tool")
    assert isinstance(tooled, SerialChain)
    assert tooled.name == "panda_tool" and tooled.n == 7
    assert np.allclose(tooled.limits, robot.limits)
    assert tooled.joint_names == robot.joint_names and tooled.frame_names == robot.frame_names


@pytest.mark.parametrize("call, exc, words", [
    (lambda: transform_from_rpy([0, 0], [0, 0, 0]), ShapeError, "rpy"),
    (lambda: transform_from_rpy([0, 0, 0], [0, 0]), ShapeError, "position"),
    (lambda: transform_from_rpy(np.zeros((2, 3)), np.zeros((3, 3))), ShapeError, "same number"),
    (lambda: transform_from_rpy([0, np.nan, 0], [0, 0, 0]), DomainError, "rpy"),
    (lambda: rigid_body_jacobian([1.0, 2.0]), ShapeError, "r must"),
    (lambda: tool_jacobian(np.zeros((3, 7)), np.eye(3), OFFSET), ShapeError, "J_ee"),
    (lambda: tool_jacobian(np.zeros((6, 7)), 2 * np.eye(3), OFFSET), DomainError, "R_be"),
    (lambda: tool_jacobian(np.zeros((6, 7)), np.eye(3), [0.2, 0.0]), ShapeError, "p_et"),
    (lambda: tool_jacobian(np.zeros((2, 6, 7)), np.eye(3), OFFSET), ShapeError, "R_be"),
    (lambda: chain_with_tool(panda(), np.eye(3)), ShapeError, "T_et"),
])
def test_bad_input(call, exc, words):
    with pytest.raises(exc, match=words):
        call()
