"""Pose error representations and the Cartesian P controller."""

from __future__ import annotations

import numpy as np
import pytest
from support.ik_support import planar_3r, ur10

from robokin.errors import DomainError, ShapeError
from robokin.motion import CartesianController, ControlOutput, pose_error
from robokin.transforms import rotation_exp, rotation_from_rpy, rotx, rotz, transform


def _pose(w, p):
    return transform(rotation_exp(w), p)


# ----------------------------------------------------------------- pose error
def test_angle_axis_error_is_base_frame_rotation_vector():
    rng = np.random.default_rng(1)
    for _ in range(20):
        T = _pose(rng.normal(size=3), rng.normal(size=3))
        w = rng.normal(size=3)
        w *= rng.uniform(0, 3.0) / np.linalg.norm(w)
        G = transform(rotation_exp(w) @ T[:3, :3], T[:3, 3] + [0.1, -0.2, 0.3])
        e = pose_error(T, G)
        assert np.allclose(e[:3], [0.1, -0.2, 0.3])
        assert np.allclose(e[3:], w, atol=1e-9)


def test_error_is_zero_for_equal_poses_and_batched():
    rng = np.random.default_rng(2)
    T = np.stack([_pose(rng.normal(size=3), rng.normal(size=3)) for _ in range(5)])
    for rep in ("angle_axis", "quaternion", "rpy"):
        assert np.allclose(pose_error(T, T, rep), 0.0, atol=1e-12)
        G = T.copy()
        G[:, :3, 3] += 1.0
        e = pose_error(T, G, rep)
        assert e.shape == (5, 6) and np.allclose(e[:, :3], 1.0)


def test_representations_agree_for_small_errors_and_differ_for_large():
    T = _pose([0.3, -0.2, 0.1], [0, 0, 0])
    small = transform(rotation_exp([1e-4, -2e-4, 3e-4]) @ T[:3, :3], [0, 0, 0])
    e_aa = pose_error(T, small)
    e_q = pose_error(T, small, "quaternion")
    assert np.allclose(e_q, e_aa, atol=1e-10)
    # quaternion: 2 sin(theta / 2) h -> the norm saturates at 2
    big = transform(rotation_exp([0.0, 0.0, 3.0]) @ T[:3, :3], [0, 0, 0])
    assert np.linalg.norm(pose_error(T, big, "quaternion")[3:]) == pytest.approx(2 * np.sin(1.5))
    assert np.linalg.norm(pose_error(T, big)[3:]) == pytest.approx(3.0)
    # rpy: differences of angles, wrapped into (-pi, pi]
    A = transform(rotation_from_rpy(0.1, 0.2, 3.1), [0, 0, 0])
    B = transform(rotation_from_rpy(0.1, 0.2, -3.1), [0, 0, 0])
    assert np.allclose(pose_error(A, B, "rpy")[3:], [0, 0, 2 * np.pi - 6.2], atol=1e-9)
    # ... which is not the base-frame rotation vector in general
    C = transform(rotation_from_rpy(0.5, 0.4, 0.3), [0, 0, 0])
    assert not np.allclose(pose_error(np.eye(4), C, "rpy")[3:], pose_error(np.eye(4), C)[3:], atol=1e-2)


def test_pose_error_bad_input():
    with pytest.raises(ValueError, match="representation"):
        pose_error(np.eye(4), np.eye(4), "euler")
    with pytest.raises(ShapeError, match="T_current"):
        pose_error(np.eye(3), np.eye(4))
    with pytest.raises(DomainError, match="T_goal"):
        pose_error(np.eye(4), np.full((4, 4), np.nan))


# ----------------------------------------------------------------- controller
@pytest.fixture(scope="module")
def ur():
    chain = ur10()
    q = np.array([0.1, -1.2, 1.3, -1.5, -1.4, 0.3])
    return chain, q


def test_commanded_twist_and_joint_velocity(ur):
    chain, q = ur
    T = chain.fk(q)
    G = transform(rotation_exp([0.01, 0.0, -0.02]) @ T[:3, :3], T[:3, 3] + [0.02, 0.0, -0.01])
    ctrl = CartesianController(chain, G, position_gain=2.0, orientation_gain=[1.0, 3.0, 0.5])
    out = ctrl(0.0, q)
    assert isinstance(out, ControlOutput)
    e = pose_error(T, G)
    assert np.allclose(out.error, e)
    assert np.allclose(out.twist, np.r_[2.0 * e[:3], [1.0, 3.0, 0.5] * e[3:]])
    assert np.allclose(chain.jacobian(q) @ out.qdot, out.twist)
    dls = CartesianController(chain, G, 2.0, 1.0, inverse="dls", damping=0.05)(0.0, q)
    J = chain.jacobian(q)
    assert np.allclose(dls.qdot, J.T @ np.linalg.solve(J @ J.T + 0.0025 * np.eye(6), dls.twist))


def test_feedforward_and_time_varying_goal(ur):
    chain, q = ur
    T = chain.fk(q)
    ff = np.array([0.01, 0.02, 0.0, 0.0, 0.0, 0.1])
    ctrl = CartesianController(chain, lambda t: T, 1.0, 1.0, feedforward=lambda t: ff)
    out = ctrl(0.5, q)
    assert np.allclose(out.twist, ff) and not ctrl.static
    assert np.allclose(chain.jacobian(q) @ out.qdot, ff)


def test_position_only_controller():
    chain = planar_3r()
    q = np.array([0.3, 0.4, 0.5])
    goal = chain.fk(q)[:3, 3] + [0.05, -0.02, 0.0]
    ctrl = CartesianController(chain, goal, position_gain=3.0)
    out = ctrl(0.0, q)
    assert ctrl.position_only
    assert np.allclose(out.twist[:3], 3.0 * np.array([0.05, -0.02, 0.0]))
    assert np.allclose(out.twist[3:], 0.0)
    assert np.allclose(chain.position_jacobian(q) @ out.qdot, out.twist[:3])


@pytest.mark.parametrize(
    ("kwargs", "exc", "word"),
    [
        ({"position_gain": -1.0}, DomainError, "position_gain"),
        ({"orientation_gain": [1.0, -2.0, 1.0]}, DomainError, "orientation_gain"),
        ({"orientation_gain": -np.eye(3)}, DomainError, "orientation_gain"),
        ({"position_gain": np.ones(4)}, ShapeError, "position_gain"),
        ({"damping": -0.1, "inverse": "dls"}, DomainError, "damping"),
        ({"inverse": "transpose"}, ValueError, "inverse"),
        ({"goal": np.zeros(5)}, ShapeError, "goal"),
        ({"goal": [np.nan, 0, 0]}, DomainError, "goal"),
    ],
)
def test_controller_bad_input(ur, kwargs, exc, word):
    chain, q = ur
    kwargs = dict(kwargs)
    goal = kwargs.pop("goal", chain.fk(q))
    with pytest.raises(exc, match=word):
        CartesianController(chain, goal, **kwargs)


def test_rotz_rotx_sanity():
    # pose_error doc example
    assert np.allclose(pose_error(np.eye(4), transform(rotz(0.5), [1, 0, 0])), [1, 0, 0, 0, 0, 0.5])
    assert np.allclose(pose_error(np.eye(4), transform(rotx(-0.2), [0, 0, 0]))[3:], [-0.2, 0, 0])
