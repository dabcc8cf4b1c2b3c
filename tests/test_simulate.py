"""Kinematic simulation: exponential error decay, limits, stopping, bad input."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from support.ik_support import planar_3r, ur10

from robokin.errors import DomainError, ShapeError
from robokin.motion import CartesianController, SimulationLog, circle_trajectory, simulate
from robokin.transforms import rotation_exp, transform

Q0 = np.array([0.1, -1.2, 1.3, -1.5, -1.4, 0.3])


def _goal(chain, dp, dw):
    T = chain.fk(Q0)
    return transform(rotation_exp(dw) @ T[:3, :3], T[:3, 3] + dp)


@pytest.mark.parametrize("K", [1.0, 5.0])
def test_error_decays_exponentially_at_the_gain_rate(K):
    chain = ur10()
    G = _goal(chain, [0.004, -0.003, 0.002], [0.003, 0.002, -0.004])
    ts = 0.01
    log = simulate(chain, CartesianController(chain, G, K, K), Q0, ts, 1.0, tol=None)
    assert isinstance(log, SimulationLog) and log.reason == "end_time"
    k = np.arange(len(log))
    euler = (1 - K * ts) ** k
    for err in (log.position_error, log.orientation_error):
        ratio = err / err[0]
        # discrete decay (1 - K ts)^k, up to the second-order kinematic residual
        assert np.allclose(ratio, euler, rtol=2e-3, atol=1e-5)
        # and close to the continuous e^{-K t} for small K ts
        assert np.allclose(ratio, np.exp(-K * log.t), atol=0.02)
    # the error vector keeps its direction (straight-line convergence)
    e0 = log.error[0, :3] / np.linalg.norm(log.error[0, :3])
    e = log.error[50, :3] / np.linalg.norm(log.error[50, :3])
    assert e @ e0 > 1 - 1e-4


def test_stops_on_convergence():
    chain = ur10()
    G = _goal(chain, [0.01, 0.0, 0.0], [0.0, 0.0, 0.01])
    log = simulate(chain, CartesianController(chain, G, 5.0, 5.0), Q0, 0.02, 20.0, tol=1e-6)
    assert log.reason == "converged"
    assert log.position_error[-1] <= 1e-6 and log.orientation_error[-1] <= 1e-6
    assert log.t[-1] < 20.0
    assert log.q.shape == (len(log), 6) and log.pose.shape == (len(log), 4, 4)
    assert np.allclose(log.pose[-1], chain.fk(log.q[-1]))


def test_stops_at_a_joint_limit_without_crossing_it():
    lim = [[-1.0, 1.0], [-0.5, 0.5], [-1.0, 1.0]]
    chain = planar_3r(limits=lim)
    q0 = np.array([0.0, 0.2, 0.0])
    goal = chain.fk([0.0, 1.2, 0.0])[:3, 3]  # needs q2 = 1.2 > 0.5 ... or another posture
    log = simulate(chain, CartesianController(chain, goal, 2.0), q0, 0.01, 5.0)
    lo, hi = np.array(lim).T
    assert np.all((log.q >= lo) & (log.q <= hi))
    assert log.at_limit.any()
    first = np.argmax(log.at_limit.any(axis=1))
    j = int(np.argmax(log.at_limit[first]))
    assert np.all(np.isin(log.q[first:, j], lim[j]))  # stays on the limit
    # applied velocity is zero into the limit
    assert np.all(np.abs(log.qdot[first:-1, j]) < 1e-12) or np.all(log.q[first:, j] == log.q[first, j])


def test_velocity_limits_scale_the_command():
    chain = ur10()
    G = _goal(chain, [0.2, 0.0, 0.0], [0.0, 0.0, 0.0])
    log = simulate(chain, CartesianController(chain, G, 5.0, 5.0), Q0, 0.01, 0.5, qdot_limits=0.1)
    assert np.all(np.abs(log.qdot) <= 0.1 + 1e-12)
    k = 0
    c = log.qdot_command[k]
    assert np.allclose(log.qdot[k], c / np.max(np.abs(c) / 0.1))


def test_tracking_a_circle_with_feedforward():
    chain = planar_3r()
    q0 = np.array([0.3, 0.6, 0.4])
    p0 = chain.fk(q0)[:3, 3]
    centre = p0 - [0.1, 0.0, 0.0]

    def ref(t):
        return circle_trajectory(t, centre, 0.1, normal=[0, 0, 1], angular_speed=1.0, axes=None)

    goal = lambda t: ref(t).positions  # noqa: E731
    ff = lambda t: ref(t).velocities  # noqa: E731
    log = simulate(chain, CartesianController(chain, goal, 10.0, feedforward=ff), q0, 0.005, 3.0)
    assert log.reason == "end_time"
    assert log.position_error.max() < 2e-3
    assert log.position_error[-1] < 1e-3


def test_plain_callable_controller():
    chain = planar_3r()
    log = simulate(chain, lambda t, q: np.array([0.1, 0.0, -0.1]), np.zeros(3), 0.1, 1.0)
    assert np.allclose(log.q[-1], [0.1, 0.0, -0.1])
    assert np.all(np.isnan(log.error))
    with pytest.raises(ShapeError, match="controller"):
        simulate(chain, lambda t, q: np.zeros(2), np.zeros(3), 0.1, 1.0)


@pytest.mark.parametrize(
    ("kwargs", "exc", "word"),
    [
        ({"ts": 0.0}, DomainError, "ts"),
        ({"ts": -0.01}, DomainError, "ts"),
        ({"t_end": -1.0}, DomainError, "t_end"),
        ({"q0": np.zeros(2)}, ShapeError, "q0"),
        ({"q0": [5.0, 0.0, 0.0]}, DomainError, "q0"),
        ({"qdot_limits": [1.0, -1.0, 1.0]}, DomainError, "qdot_limits"),
        ({"qdot_limits": [1.0, 1.0]}, ShapeError, "qdot_limits"),
        ({"tol": -1.0}, DomainError, "tol"),
    ],
)
def test_simulate_bad_input(kwargs, exc, word):
    chain = planar_3r()
    args: dict[str, Any] = {"q0": np.zeros(3), "ts": 0.01, "t_end": 1.0}
    args.update(kwargs)
    ctrl = CartesianController(chain, [1.5, 0.5, 0.0])
    with pytest.raises(exc, match=word):
        simulate(chain, ctrl, args.pop("q0"), args.pop("ts"), args.pop("t_end"), **args)


def test_logged_pose_is_the_controlled_tool_frame():
    """With a tool, the logged pose is the tool's, the frame the error refers to."""
    from robokin.models import ur10
    from robokin.motion import CartesianController, simulate
    from robokin.transforms import translation

    arm = ur10()
    q0 = np.deg2rad([0.0, -90.0, 90.0, -90.0, -90.0, 0.0])
    tool = translation([0.0, 0.0, 0.1])
    goal = arm.fk(q0) @ tool @ translation([0.05, 0.0, 0.0])
    log = simulate(arm, CartesianController(arm, goal, tool=tool), q0, 0.01, 1.0)
    for pose, error in zip(log.pose[::10], log.error[::10]):
        np.testing.assert_allclose(goal[:3, 3] - pose[:3, 3], error[:3], atol=1e-12)
    np.testing.assert_allclose(log.pose[0], arm.fk(q0) @ tool, atol=1e-12)
