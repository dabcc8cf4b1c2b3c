"""Singularities in Cartesian control: the per-step flag, the warning, the damped remedy.

Near a singular configuration the pseudoinverse controller commands joint rates
up to |twist| / sigma_min (1e5-1e6 rad/s for a UR10 1e-7 rad from its wrist
singularity). The controller's ControlOutput carries sigma_min and a flag,
simulate / track_position_batch log them and warn once per run, and damped least
squares keeps the rates bounded by |twist| / (2 lambda).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from robokin.errors import SingularityWarning
from robokin.models import planar_two_link, ur10
from robokin.motion import CartesianController, ControlOutput, SimulationLog, simulate
from robokin.motion.control import SINGULAR_THRESHOLD, _pinv_and_singular_values
from robokin.motion.sweeps import track_position_batch

UR10 = ur10()
#: a regular UR10 configuration (elbow bent, wrist away from q5 = 0)
Q_REGULAR = np.array([0.1, -1.2, 1.3, -1.5, -1.4, 0.3])


def _wrist_singular(eps: float = 1e-7) -> np.ndarray:
    q = Q_REGULAR.copy()
    q[4] = eps                     # q5 = 0: wrist axes 4 and 6 aligned
    return q


def _stretched(eps: float = 1e-7) -> np.ndarray:
    return np.array([0.3, -0.4, eps, -1.2, -1.4, 0.2])   # q3 = 0: elbow fully stretched


def _goal_near(q: np.ndarray, dp=(0.02, 0.01, -0.01)) -> np.ndarray:
    T = UR10.fk(q)
    T[:3, 3] += dp
    return T


@pytest.mark.parametrize("q_singular", [_wrist_singular(), _stretched()], ids=["wrist", "stretched elbow"])
def test_pinv_controller_flags_the_singularity_and_simulate_warns_once(q_singular):
    ctrl = CartesianController(UR10, _goal_near(q_singular), 1.0, 1.0)
    out = ctrl(0.0, q_singular)
    assert out.singular and out.sigma_min < 1e-6
    with pytest.warns(SingularityWarning) as record:
        log = simulate(UR10, ctrl, q_singular, 0.01, 0.2, tol=None)
    assert len(record) == 1                                      # once per run, not once per step
    message = str(record[0].message)
    assert "sigma_min" in message and "inverse='dls'" in message and "warn_singular=False" in message
    assert log.singular[0] and log.sigma_min[0] < 1e-6 and log.singular_threshold == SINGULAR_THRESHOLD
    assert log.sigma_min.shape == log.singular.shape == (len(log),)
    assert np.abs(log.qdot_command[0]).max() > 1e4              # the wild rates the flag explains
    # the logged sigma_min is that of the controller's own Jacobian
    J = UR10.jacobian(q_singular)
    assert log.sigma_min[0] == pytest.approx(np.linalg.svd(J, compute_uv=False)[-1], abs=1e-12)


@pytest.mark.parametrize("q_singular", [_wrist_singular(), _stretched()], ids=["wrist", "stretched elbow"])
def test_damped_controller_rates_stay_bounded_at_the_singularity(q_singular):
    lam = 0.05
    pinv = CartesianController(UR10, _goal_near(q_singular), 1.0, 1.0)
    dls = CartesianController(UR10, _goal_near(q_singular), 1.0, 1.0, inverse="dls", damping=lam)
    with pytest.warns(SingularityWarning, match="damped least-squares"):
        log = simulate(UR10, dls, q_singular, 0.01, 0.5, tol=None)
    speed = np.linalg.norm(log.qdot_command, axis=1)
    bound = np.linalg.norm(log.twist, axis=1) / (2 * lam)       # sigma / (sigma^2 + lam^2) <= 1 / (2 lam)
    assert np.all(speed <= bound + 1e-9)
    assert speed.max() < 1.0
    assert np.linalg.norm(pinv(0.0, q_singular).qdot) > 1e4 * speed.max()
    assert log.singular[0]                                       # the flag describes the geometry


def test_no_flag_no_warning_away_from_singularities():
    ctrl = CartesianController(UR10, _goal_near(Q_REGULAR), 1.0, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        log = simulate(UR10, ctrl, Q_REGULAR, 0.05, 2.0)
    assert not log.singular.any() and np.all(log.sigma_min > 0.05)


def test_planar_arm_is_not_flagged_for_its_zero_z_row():
    arm = planar_two_link()
    q = np.array([0.3, 1.2])
    ctrl = CartesianController(arm, arm.fk(q)[:3, 3] + [0.05, 0.02, 0.0], 2.0)
    assert ctrl.task_rank == 2
    out = ctrl(0.0, q)
    assert not out.singular and out.sigma_min == pytest.approx(np.linalg.svd(arm.position_jacobian(q))[1][1])
    stretched = np.array([0.3, 1e-6])
    assert ctrl(0.0, stretched).singular


def test_silencing_and_threshold_override():
    q = _wrist_singular()
    ctrl = CartesianController(UR10, _goal_near(q), 1.0, 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        quiet = simulate(UR10, ctrl, q, 0.01, 0.05, tol=None, warn_singular=False)
        assert quiet.singular.all()                              # still flagged in the log
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SingularityWarning)  # the standard filter works too
            simulate(UR10, ctrl, q, 0.01, 0.05, tol=None)
        never = simulate(UR10, ctrl, q, 0.01, 0.05, tol=None, singular_threshold=0.0)
        assert not never.singular.any() and never.singular_threshold == 0.0
        off = CartesianController(UR10, _goal_near(q), 1.0, 1.0, singular_threshold=0.0)
        assert not off(0.0, q).singular
    with pytest.warns(SingularityWarning):                       # a stricter threshold flags a regular pose
        log = simulate(UR10, CartesianController(UR10, _goal_near(Q_REGULAR)), Q_REGULAR, 0.05, 0.1,
                       tol=None, singular_threshold=10.0)
    assert log.singular.all() and log.singular_threshold == 10.0


def test_plain_function_controller_reports_no_sigma_min():
    arm = planar_two_link()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        log = simulate(arm, lambda t, q: np.array([0.1, 0.0]), [0.2, 0.3], 0.1, 0.3)
    assert np.isnan(log.sigma_min).all() and not log.singular.any() and np.isnan(log.singular_threshold)


def test_sweep_flags_runs_and_warns_once_per_call():
    arm = planar_two_link()
    Q0 = np.array([[0.3, 1.2], [0.3, 1e-6], [-0.5, 2.0]])          # run 1 starts with the elbow stretched
    P = arm.fk(Q0)[:, None, :3, 3] + np.zeros((3, 5, 3))
    V = np.tile([0.05, 0.0, 0.0], (3, 5, 1))
    with pytest.warns(SingularityWarning) as record:
        log = track_position_batch(arm, Q0, 0.01, P, V, clamp=False)
    assert len(record) == 1 and "1 of 3 runs" in str(record[0].message)
    assert log.singular.shape == (3, 5) and log.task_rank == 2
    assert log.singular[1, 0] and not log.singular[0].any() and not log.singular[2].any()
    assert np.array_equal(log.singular, log.singular_values[..., 1] < SINGULAR_THRESHOLD)
    assert np.linalg.norm(log.qdot[1, 0]) > 1e3                   # the rate the flag explains
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        quiet = track_position_batch(arm, Q0, 0.01, P, V, clamp=False, warn_singular=False)
        assert quiet.singular[1, 0]
        track_position_batch(arm, Q0[[0, 2]], 0.01, P[[0, 2]], V[[0, 2]], clamp=False)
    ur = track_position_batch(UR10, Q_REGULAR, 0.01, np.tile(UR10.fk(Q_REGULAR)[:3, 3], (3, 1)), np.zeros((3, 3)))
    assert ur.task_rank == 3 and np.array_equal(ur.singular, ur.sigma_min < SINGULAR_THRESHOLD)


def test_pinv_is_unchanged_bit_for_bit():
    """The controller reuses one SVD for the pseudoinverse and sigma_min: same numbers as before."""
    rng = np.random.default_rng(3)
    for m, n in [(3, 7), (6, 6), (6, 7), (3, 2), (6, 3)]:
        for _ in range(50):
            J = rng.normal(size=(m, n))
            if rng.random() < 0.3:
                J[:, 0] = J[:, 1]                                # rank deficient
            P, s = _pinv_and_singular_values(J, 1e-8)
            assert np.array_equal(P, np.linalg.pinv(J, rcond=1e-8))
            assert np.allclose(s, np.linalg.svd(J, compute_uv=False))


def test_new_fields_are_backward_compatible():
    out = ControlOutput(np.zeros(2), np.zeros(6), np.zeros(6))      # the three-field form still works
    assert np.isnan(out.sigma_min) and out.singular is False
    log = SimulationLog(t=np.zeros(2), q=np.zeros((2, 1)), qdot=np.zeros((2, 1)), qdot_command=np.zeros((2, 1)),
                        twist=np.zeros((2, 6)), error=np.zeros((2, 6)), pose=np.zeros((2, 4, 4)),
                        at_limit=np.zeros((2, 1), bool), reason="end_time")
    assert log.sigma_min.shape == (2,) and not log.singular.any()


def test_plot_history_marks_the_singular_steps():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from robokin.views.plots import SINGULAR_COLOR, plot_history

    q = _wrist_singular(1e-3)
    ctrl = CartesianController(UR10, _goal_near(q, (0.0, 0.0, 0.0)), 1.0, 1.0)
    with pytest.warns(SingularityWarning):
        log = simulate(UR10, ctrl, q, 0.05, 1.0, tol=None, singular_threshold=2e-3)
    assert log.singular.any()
    fig = plot_history(log)
    try:
        labels = [ax.get_ylabel() for ax in fig.axes]
        assert any("σ_min" in lab for lab in labels)               # a sigma_min panel
        bands = [p for ax in fig.axes for p in ax.patches
                 if matplotlib.colors.to_hex(p.get_facecolor()[:3]) == SINGULAR_COLOR.lower()]
        assert len(bands) >= len(fig.axes)                         # marked on every panel
    finally:
        plt.close(fig)
    regular = simulate(UR10, CartesianController(UR10, _goal_near(Q_REGULAR)), Q_REGULAR, 0.05, 0.2, tol=None)
    fig = plot_history(regular)
    try:
        assert not any(ax.patches for ax in fig.axes)
    finally:
        plt.close(fig)
