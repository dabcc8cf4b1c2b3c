"""Tests of robokin.motion.sweeps: initial-condition sweeps, batched resolved-rate tracking."""

from __future__ import annotations

import numpy as np
import pytest

from robokin.errors import DomainError, ShapeError, SingularityWarning
from robokin.models import baxter_left, planar_two_link
from robokin.motion import CartesianController, circle_trajectory, simulate
from robokin.motion.sweeps import initial_condition_sweep, track_position_batch

ARM = baxter_left(base="shoulder")
LIM = ARM.limits
Q_MID = LIM.mean(axis=1)


def circle(ts, steps, centre, radius=0.05, omega=np.pi / 2):
    t = np.arange(steps + 1) * ts
    return circle_trajectory(t, centre, radius, normal=[0, 0, 1], angular_speed=omega)


# ---------------------------------------------------------------- initial_condition_sweep
def test_sweep_layout_and_values():
    f = np.array([0.1, 0.5, 0.9])
    Q = initial_condition_sweep(LIM, f)
    assert Q.shape == (21, 7)
    span = LIM[:, 1] - LIM[:, 0]
    for j in range(7):
        block = Q[3 * j:3 * j + 3]
        assert np.allclose(block[:, j], LIM[j, 0] + f * span[j])
        others = np.delete(block, j, axis=1)
        assert np.allclose(others, np.delete(Q_MID, j))
    assert np.all(ARM.within_limits(Q))


def test_sweep_reproduces_tutorial_matrix_with_theta4_range():
    # the tutorial's printed AnglesInit columns use 0.2 + (i-1)/10 of joint 4's range for every joint
    lim = np.array([[-1.7016, 1.7016], [-2.147, 1.047], [-3.0541, 3.0541], [-0.05, 2.618],
                    [-3.059, 3.059], [-1.5707, 2.094], [-3.059, 3.059]])
    span4 = lim[3, 1] - lim[3, 0]
    # give every joint twice joint 4's range, and halve the fractions (the last one, 1.1, exceeds 1)
    fake = np.column_stack([lim[:, 0], lim[:, 0] + 2 * span4])
    Q = initial_condition_sweep(fake, (0.2 + np.arange(10) / 10) / 2, nominal=0.1)
    printed_row1 = [-1.1680, -0.9012, -0.6344, -0.3676, -0.1008, 0.1660, 0.4328, 0.6996, 0.9664, 1.2332]
    assert np.allclose(Q[:10, 0], printed_row1, atol=1e-4)
    assert np.allclose(Q[0], [-1.1680, -1.6134, -2.5205, 0.4836, -2.5254, -1.0371, -2.5254], atol=1e-4)
    assert np.allclose(Q[10:20, 1], [-1.6134, -1.3466, -1.0798, -0.8130, -0.5462, -0.2794, -0.0126,
                                     0.2542, 0.5210, 0.7878], atol=1e-4)


@pytest.mark.parametrize("kwargs, err, text", [
    ({"limits": np.zeros((7, 3)), "fractions": [0.5]}, ShapeError, "limits"),
    ({"limits": LIM, "fractions": [0.2, 1.1]}, DomainError, "fractions\\[1\\] = 1.1"),
    ({"limits": LIM, "fractions": [[0.2]]}, ShapeError, "fractions"),
    ({"limits": LIM, "fractions": []}, ShapeError, "fractions"),
    ({"limits": LIM, "fractions": [0.5], "nominal": [0.5, 0.5]}, ShapeError, "nominal"),
    ({"limits": LIM, "fractions": [0.5], "nominal": 1.5}, DomainError, "nominal"),
    ({"limits": [[-np.inf, 1.0]], "fractions": [0.5]}, DomainError, "finite"),
])
def test_sweep_bad_input(kwargs, err, text):
    with pytest.raises(err, match=text):
        initial_condition_sweep(**kwargs)


# ---------------------------------------------------------------- track_position_batch
def test_single_run_equals_simulate_with_cartesian_controller():
    ts, steps = 0.01, 200
    c = ARM.fk(Q_MID)[:3, 3] - [0.05, 0, 0]
    ref = circle(ts, steps, c)
    ctrl = CartesianController(
        ARM, lambda t: circle_trajectory(t, c, 0.05, normal=[0, 0, 1], angular_speed=np.pi / 2).positions,
        position_gain=5.0,
        feedforward=lambda t: circle_trajectory(t, c, 0.05, normal=[0, 0, 1], angular_speed=np.pi / 2).velocities)
    log = simulate(ARM, ctrl, Q_MID, ts, steps * ts, tol=None)
    batch = track_position_batch(ARM, Q_MID, ts, ref.positions, ref.velocities, gain=5.0)
    assert batch.q.shape == (1, steps + 1, 7)
    assert np.allclose(batch.q[0], log.q, atol=1e-12)
    assert np.allclose(batch.qdot[0], log.qdot_command, atol=1e-10)
    assert np.allclose(batch.position[0], log.pose[:, :3, 3], atol=1e-12)
    assert np.allclose(batch.error[0], log.error[:, :3], atol=1e-12)


def test_batch_equals_runs_one_by_one_and_logs_singular_values():
    rng = np.random.default_rng(0)
    Q0 = Q_MID + rng.uniform(-0.3, 0.3, (4, 7))
    ts, steps = 0.01, 50
    rel = circle(ts, steps, np.zeros(3))
    P0 = ARM.fk(Q0)[:, :3, 3]
    P = P0[:, None, :] + (rel.positions - [0.05, 0, 0])[None]
    batch = track_position_batch(ARM, Q0, ts, P, rel.velocities, gain=10.0)
    for m in range(4):
        one = track_position_batch(ARM, Q0[m], ts, P[m], rel.velocities, gain=10.0)
        assert np.allclose(one.q[0], batch.q[m], atol=1e-12)
    k = 17
    s = np.linalg.svd(ARM.position_jacobian(batch.q[2, k]), compute_uv=False)
    assert np.allclose(batch.singular_values[2, k], s)
    assert np.isclose(batch.manipulability[2, k], ARM.manipulability(batch.q[2, k], position_only=True))
    assert np.isclose(batch.sigma_min[2, k], s[-1])


def test_commanded_velocity_is_realised_to_first_order():
    # J qdot = v_des + K e at every sample (pinv, full rank): hand velocity matches finite differences
    ts, steps = 1e-3, 100
    c = ARM.fk(Q_MID)[:3, 3] - [0.05, 0, 0]
    ref = circle(ts, steps, c)
    b = track_position_batch(ARM, Q_MID, ts, ref.positions, ref.velocities, gain=0.0)
    v_fd = np.diff(b.position[0], axis=0) / ts
    assert np.allclose(v_fd, ref.velocities[:-1], atol=5e-4)
    assert b.position_error.max() < 1e-5


def test_closed_loop_removes_drift_open_loop_keeps_it():
    ts, steps = 0.02, 200                           # a coarse step makes the Euler drift visible
    c = ARM.fk(Q_MID)[:3, 3] - [0.05, 0, 0]
    ref = circle(ts, steps, c)
    open_ = track_position_batch(ARM, Q_MID, ts, ref.positions, ref.velocities, gain=0.0)
    closed = track_position_batch(ARM, Q_MID, ts, ref.positions, ref.velocities, gain=10.0)
    assert closed.position_error.max() < 0.2 * open_.position_error.max()


def test_dls_bounds_joint_speed_near_a_singularity():
    # planar two-link arm with a stretched elbow: pinv explodes, DLS stays bounded by |v| / (2 lambda)
    arm = planar_two_link()
    q0 = np.array([0.0, 1e-3])
    p0 = arm.fk(q0)[:3, 3]
    v = np.tile([0.1, 0.0, 0.0], (3, 1))          # outward, along the stretched arm
    P = np.tile(p0, (3, 1))
    with pytest.warns(SingularityWarning, match="track_position_batch"):
        pinv = track_position_batch(arm, q0, 0.01, P, v, clamp=False)
    with pytest.warns(SingularityWarning, match="damped"):
        dls = track_position_batch(arm, q0, 0.01, P, v, inverse="dls", damping=0.05, clamp=False)
    assert np.abs(pinv.qdot[0, 0]).max() > 10
    assert np.linalg.norm(dls.qdot[0, 0]) <= 0.1 / (2 * 0.05) + 1e-9
    assert pinv.singular[0, 0] and pinv.task_rank == 2   # the planar arm's z row is no singularity


def test_clamping_at_the_limits():
    q0 = Q_MID.copy()
    q0[3] = LIM[3, 1]                               # elbow at its upper limit
    ts, steps = 0.01, 20
    c = ARM.fk(q0)[:3, 3] - [0.05, 0, 0]
    ref = circle(ts, steps, c)
    b = track_position_batch(ARM, q0, ts, ref.positions, 50 * ref.velocities, gain=0.0)
    assert np.all(ARM.within_limits(b.q[0]))
    assert b.at_limit[0, 0, 3]


@pytest.mark.parametrize("kwargs, err, text", [
    ({"q0": np.zeros(6)}, ShapeError, "q0"),
    ({"q0": LIM[:, 1] + 0.1}, DomainError, "q0"),
    ({"ts": 0.0}, DomainError, "ts"),
    ({"gain": -1.0}, DomainError, "gain"),
    ({"positions": np.zeros((5, 2))}, ShapeError, "positions"),
    ({"velocities": np.zeros((4, 3))}, ShapeError, "velocities"),
    ({"inverse": "svd"}, ValueError, "inverse"),
    ({"damping": -0.1}, DomainError, "damping"),
    ({"positions": np.full((5, 3), np.nan)}, DomainError, "positions"),
])
def test_track_bad_input(kwargs, err, text):
    args = {"q0": Q_MID, "ts": 0.01, "positions": np.zeros((5, 3)), "velocities": np.zeros((5, 3))}
    args.update(kwargs)
    with pytest.raises(err, match=text):
        track_position_batch(ARM, args.pop("q0"), args.pop("ts"), args.pop("positions"), args.pop("velocities"),
                             **args)


@pytest.mark.parametrize("damping", [None, 0.02])
def test_gram_path_equals_the_svd_of_j_also_near_singularities(damping):
    """The step from the eigen-decomposition of J Jᵀ equals V Σ# Uᵀ v from the SVD of J,
    for well-conditioned rows and (through the SVD fallback) ill-conditioned ones."""
    from robokin.motion.sweeps import GRAM_MAX_CONDITION, _rates_and_singular_values

    rng = np.random.default_rng(3)
    Q = ARM.random_configurations(40, seed=3)
    Q[:10, 5] = 1e-9 * rng.standard_normal(10)  # wrist W1 at zero: J_v (nearly) rank-deficient
    Q[10:15, 3] = 1e-6  # elbow E1 stretched
    J = ARM.position_jacobian(Q)
    v = rng.standard_normal((40, 3))
    gram_rates, gram_s = _rates_and_singular_values(J, v, 1e-8, damping, True)
    svd_rates, svd_s = _rates_and_singular_values(J, v, 1e-8, damping, False)
    assert np.allclose(gram_s, np.linalg.svd(J, compute_uv=False), rtol=0, atol=1e-14)
    assert np.allclose(gram_s, svd_s, rtol=0, atol=1e-14)
    ill = svd_s[:, 2] * GRAM_MAX_CONDITION < svd_s[:, 0]
    assert ill.any() and not ill.all()  # both paths are exercised
    assert np.array_equal(gram_rates[ill], svd_rates[ill])  # the SVD itself there
    scale = np.linalg.norm(svd_rates, axis=1, keepdims=True)
    assert np.allclose(gram_rates, svd_rates, rtol=0, atol=1e-12 * scale.max())
    assert np.all(np.abs(gram_rates - svd_rates) <= 1e-12 * scale)
