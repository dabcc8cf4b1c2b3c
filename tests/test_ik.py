"""Single-target IK: interface, methods, history, limits, options, bad input."""

from __future__ import annotations

import inspect
from typing import Any

import numpy as np
import pytest
from support.ik_support import baxter_left, planar_3r, reachable_targets, ur10, within_limits

from robokin.errors import DomainError, ShapeError
from robokin.motion import (
    REASONS,
    DampedLeastSquares,
    IKHistory,
    IKResult,
    JacobianTranspose,
    LevenbergMarquardt,
    NullSpace,
    PseudoInverse,
    WeightedPseudoInverse,
    pose_error,
    solve_ik,
    solve_ik_batch,
    solve_ik_once,
)
from robokin.motion._kernels import tool_jacobian
from robokin.motion.ik.objectives import JointLimitDistance, Manipulability
from robokin.motion.ik.problem import make_context
from robokin.motion.ik.result import Outcome
from robokin.motion.ik.settings import parse_settings
from robokin.motion.ik.solve import classify_stall
from robokin.motion.pose_error import pose_error_unchecked
from robokin.transforms import rotation_exp, rotation_log, rotx, transform

METHOD_OPTIONS: dict[str, dict[str, Any]] = {
    "lm": {},
    "pinv": {},
    "dls": {"damping": 0.01},
    "weighted": {"weights": [1.0, 2.0, 3.0, 1.0, 1.0, 1.0]},
    "nullspace": {},
}


@pytest.fixture(scope="module")
def arm():
    chain = ur10()
    Q, T = reachable_targets(chain, 20, seed=11)
    return chain, Q, T


# --------------------------------------------------------------------- the keywords
def _parameters(function) -> list[tuple[str, Any, Any, Any]]:
    return [(p.name, p.kind, p.default, p.annotation) for p in inspect.signature(function).parameters.values()]


def test_the_solvers_keywords_agree_with_solve_ik():
    """solve_ik_once and solve_ik_batch write solve_ik's keywords out again (a typed, introspectable
    signature each), and parse_settings takes them by name: the names, order, kinds, defaults and
    annotations agree, less the ones a solver has no use for."""
    full = _parameters(solve_ik)
    once = [p for p in full if p[0] not in ("restarts", "seed", "polish")]
    assert _parameters(solve_ik_once) == once
    batch = [p for p in full if p[0] != "record_history"]
    batch[1] = ("targets", *batch[1][1:])
    assert _parameters(solve_ik_batch) == batch
    keywords = [name for name, kind, _, _ in full if kind is inspect.Parameter.KEYWORD_ONLY]
    parsed = [p.name for p in inspect.signature(parse_settings).parameters.values()
              if p.kind is inspect.Parameter.KEYWORD_ONLY]
    assert parsed == ["batched", *(name for name in keywords if name != "record_history")]


# --------------------------------------------------------------------- result
@pytest.mark.parametrize("method", sorted(METHOD_OPTIONS))
def test_every_method_solves_a_reachable_pose(arm, method):
    chain, Q, T = arm
    res = solve_ik(chain, T[0], q0=Q[0] + 0.2, method=method, **METHOD_OPTIONS[method])
    assert isinstance(res, IKResult)
    assert res.success and res.reason == "converged"
    assert res.position_error <= 1e-6 and res.orientation_error <= 1e-6
    assert res.q.shape == (6,) and res.errors.shape == (6,)
    assert np.allclose(chain.fk(res.q), T[0], atol=1e-5)
    assert res.method == method
    assert res.iterations >= 1


def test_default_is_lm_and_reproducible(arm):
    chain, _, T = arm
    a = solve_ik(chain, T[3])
    b = solve_ik(chain, T[3])
    assert a.method == "lm" and a.success
    assert np.array_equal(a.q, b.q) and a.iterations == b.iterations


def test_method_objects_are_accepted(arm):
    chain, Q, T = arm
    for m in (PseudoInverse(), LevenbergMarquardt(bias=1e-6), DampedLeastSquares(0.02, adaptive="singular_value")):
        assert solve_ik(chain, T[1], q0=Q[1] + 0.1, method=m).success
    with pytest.raises(TypeError, match="options"):
        solve_ik(chain, T[1], method=PseudoInverse(), damping=0.1)


def test_history_arrays(arm):
    chain, Q, T = arm
    res = solve_ik(chain, T[2], q0=Q[2] + 0.3, method="dls", damping=0.05, restarts=0)
    h = res.history
    assert isinstance(h, IKHistory)
    K = len(h)
    assert K == res.iterations + 1
    assert h.q.shape == (K, 6) and h.error.shape == (K, 6) and h.jacobian.shape == (K, 6, 6)
    for arr in (h.error_norm, h.position_error, h.orientation_error, h.smallest_singular_value,
                h.damping, h.step_size, h.limit_distance, h.attempt):
        assert arr.shape == (K,)
    assert np.allclose(h.damping[:-1], 0.05) and h.damping[-1] == 0.0
    assert np.allclose(h.step_size[:-1], np.linalg.norm(np.diff(h.q, axis=0), axis=1))
    assert np.array_equal(h.q[-1], res.q)
    assert h.error_norm[-1] < 1e-6 < h.error_norm[0]
    assert np.all(h.limit_distance >= 0)
    assert np.allclose(h.smallest_singular_value,
                       np.linalg.svd(h.jacobian, compute_uv=False)[:, -1])
    assert solve_ik(chain, T[2], record_history=False).history is None


def test_lm_damping_follows_the_error(arm):
    chain, Q, T = arm
    res = solve_ik(chain, T[4], q0=Q[4] + 0.3, restarts=0)
    h = res.history
    assert h is not None
    lam2 = 0.5 * 0.1 * h.error_norm[:-1] ** 2 + 1e-7
    assert np.allclose(h.damping[:-1] ** 2, lam2)


def test_success_is_never_claimed_above_tolerance(arm):
    chain, Q, T = arm
    for tol in (1e-3, 1e-8, (1e-4, 1e-2)):
        for it in (1, 2, 5, 50):
            res = solve_ik(chain, T[5], q0=Q[5] + 0.5, tol=tol, max_iterations=it, restarts=0, polish=False)
            tp, to = tol if isinstance(tol, tuple) else (tol, tol)
            within = res.position_error <= tp and res.orientation_error <= to
            assert res.success == within
            assert (res.reason == "converged") == res.success
            assert res.reason in REASONS


# ------------------------------------------------------------ hard targets
@pytest.mark.parametrize("make", [ur10, baxter_left])
def test_unreachable_target_returns_best_configuration(make):
    chain = make()
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.5]
    res = solve_ik(chain, far)
    assert not res.success
    assert res.reason == "unreachable"
    assert within_limits(chain, res.q)
    assert res.position_error > 3.0
    # the best configuration is at least as good as the start and as every attempt
    h = res.history
    assert h is not None
    assert res.position_error <= h.position_error[0] + 1e-12
    assert np.linalg.norm(res.errors) <= h.error_norm.min() + 1e-9
    # the reported error is that of the returned configuration
    p = chain.fk(res.q)[:3, 3]
    assert np.allclose(far[:3, 3] - p, res.errors[:3])


def test_unreachable_position_target_planar():
    chain = planar_3r()
    res = solve_ik(chain, [3.0, 1.0, 0.0])
    assert not res.success and res.reason == "unreachable"
    # stretched arm pointing at the target: distance = |target| - reach
    assert res.position_error == pytest.approx(np.hypot(3.0, 1.0) - 2.3, abs=1e-4)


def test_joint_limits_are_respected_and_reported():
    lim = [[-0.3, 0.3], [-0.3, 0.3], [-0.3, 0.3]]
    chain = planar_3r(limits=lim)
    # needs q1 = 1.0: outside the limits
    res = solve_ik(chain, chain.fk([1.0, 0.0, 0.0])[:3, 3])
    assert not res.success
    assert res.reason == "joint_limits"
    assert within_limits(chain, res.q)
    assert res.history is not None
    assert np.all(within_limits(chain, res.history.q))
    assert res.q[0] == pytest.approx(0.3)


@pytest.mark.parametrize("method", ["lm", "pinv", "dls", "transpose"])
def test_iterates_stay_within_limits(method):
    chain = baxter_left()
    Q, T = reachable_targets(chain, 5, seed=5)
    for i in range(5):
        res = solve_ik(chain, T[i], method=method, max_iterations=30, restarts=1)
        assert res.history is not None
        assert np.all(within_limits(chain, res.history.q))


def test_wrap_option_keeps_angles_in_minus_pi_pi(arm):
    chain, Q, T = arm
    res = solve_ik(chain, T[6], q0=np.full(6, 3.0), wrap=True)
    assert res.success
    assert res.history is not None
    assert np.all(np.abs(res.history.q) <= np.pi + 1e-12)
    with pytest.raises(ValueError, match="wrap"):
        solve_ik(chain, T[6], wrap="sometimes")


def test_restarts_are_seeded(arm):
    chain, _, T = arm
    # one iteration per attempt: needs many attempts, all from the seed
    a = solve_ik(chain, T[7], max_iterations=1, restarts=5, seed=1, polish=False)
    b = solve_ik(chain, T[7], max_iterations=1, restarts=5, seed=1, polish=False)
    c = solve_ik(chain, T[7], max_iterations=1, restarts=5, seed=2, polish=False)
    assert a.history is not None and b.history is not None
    assert a.attempts == 6 and np.array_equal(a.history.q, b.history.q)
    assert c.history is not None
    assert not np.array_equal(a.history.q, c.history.q)
    assert np.array_equal(np.unique(a.history.attempt), np.arange(6))
    lim = np.asarray(chain.limits)
    assert np.all((a.history.q >= lim[:, 0]) & (a.history.q <= lim[:, 1]))


# -------------------------------------------------------- targets and tools
def test_position_only_target(arm):
    chain, Q, T = arm
    res = solve_ik(chain, T[8][:3, 3])
    assert res.success and res.orientation_error == 0.0
    assert np.allclose(chain.fk(res.q)[:3, 3], T[8][:3, 3], atol=1e-6)
    assert np.all(res.errors[3:] == 0.0)


def test_mask_selects_components(arm):
    chain, Q, T = arm
    mask = [True, True, True, False, False, True]  # position + rotation about z
    target = T[9] @ transform(rotx(0.3), [0, 0, 0])  # rx/ry parts of the goal change
    res = solve_ik(chain, target, mask=mask)
    assert res.success
    e = res.errors
    assert np.all(np.abs(e[[0, 1, 2, 5]]) <= 1e-6)
    assert res.position_error <= 1e-6 and abs(e[5]) <= 1e-6
    assert res.orientation_error == pytest.approx(abs(e[5]))


def test_tool_frame(arm):
    chain, Q, T = arm
    tool = transform(rotx(0.4), [0.0, 0.05, 0.2])
    target = chain.fk(Q[10]) @ tool
    res = solve_ik(chain, target, tool=tool)
    assert res.success
    assert np.allclose(chain.fk(res.q) @ tool, target, atol=1e-5)
    # the tool Jacobian is the Jacobian of the tool frame
    q = Q[10]
    J = tool_jacobian(chain.jacobian(q), chain.fk(q)[:3, :3], tool[:3, 3])
    h = 1e-6
    for i in range(6):
        dq = np.zeros(6)
        dq[i] = h
        dp = ((chain.fk(q + dq) @ tool)[:3, 3] - (chain.fk(q - dq) @ tool)[:3, 3]) / (2 * h)
        assert np.allclose(dp, J[:3, i], atol=1e-7)


def test_transpose_reduces_the_error():
    chain = planar_3r()
    target = chain.fk([0.4, 0.5, -0.3])[:3, 3]
    res = solve_ik(chain, target, q0=[0.1, 0.1, 0.1], method="transpose", tol=1e-4, restarts=0, polish=False)
    h = res.history
    assert h is not None
    assert res.success and h.error_norm[-1] < 1e-4
    assert h.error_norm[-1] < 1e-2 * h.error_norm[0]
    # Buss' step length: the error never grows much
    assert np.all(np.diff(h.error_norm) <= 1e-9 + 0.5 * h.error_norm[:-1])


# -------------------------------------------------------------- step rules
@pytest.fixture(scope="module")
def redundant():
    chain = baxter_left()
    q = chain.random_configurations(1, seed=4)[0]
    ctx = make_context(chain, np.ones(6, bool), None, "limits")
    J = chain.jacobian(q)
    e = np.array([0.01, -0.02, 0.015, 0.02, 0.01, -0.03])
    return chain, q, ctx, J, e


def test_pinv_step_is_the_minimum_norm_solution(redundant):
    _, q, ctx, J, e = redundant
    dq, _ = PseudoInverse().step(J, e, q, ctx)
    assert np.allclose(dq, np.linalg.pinv(J) @ e)
    assert np.allclose(J @ dq, e)


def test_weighted_step_formula(redundant):
    _, q, ctx, J, e = redundant
    w = np.array([10.0, 1.0, 1.0, 2.0, 1.0, 5.0, 1.0])
    dq, _ = WeightedPseudoInverse(w).step(J, e, q, ctx)
    Wi = np.diag(1 / w)
    assert np.allclose(dq, Wi @ J.T @ np.linalg.solve(J @ Wi @ J.T, e))
    assert np.allclose(J @ dq, e)
    # the heavily weighted joint moves less than with the plain pseudoinverse
    plain = np.linalg.pinv(J) @ e
    assert abs(dq[0]) < abs(plain[0])
    # a full SPD matrix gives the same as the formula too
    A = np.random.default_rng(0).normal(size=(7, 7))
    W = A @ A.T + 7 * np.eye(7)
    dq, _ = WeightedPseudoInverse(W).step(J, e, q, ctx)
    assert np.allclose(dq, np.linalg.inv(W) @ J.T @ np.linalg.solve(J @ np.linalg.inv(W) @ J.T, e))


def test_dls_steps(redundant):
    _, q, ctx, J, e = redundant
    dq, lam = DampedLeastSquares(damping=0.1).step(J, e, q, ctx)
    assert lam == 0.1
    assert np.allclose(dq, J.T @ np.linalg.solve(J @ J.T + 0.01 * np.eye(6), e))
    # error-dependent damping (Sugihara): lambda^2 = e.e / 2 + bias
    dq, lam = DampedLeastSquares(adaptive="error", bias=1e-3).step(J, e, q, ctx)
    assert lam**2 == pytest.approx(0.5 * e @ e + 1e-3)
    # manipulability-based: no damping far from singularities, lambda_0 at one
    s = np.linalg.svd(J, compute_uv=False)
    d = DampedLeastSquares(damping=0.2, adaptive="manipulability", threshold=np.prod(s) / 2)
    dq, lam = d.step(J, e, q, ctx)
    assert lam == 0.0 and np.allclose(dq, np.linalg.pinv(J) @ e)
    Js = J.copy()
    Js[:, 1:] = Js[:, [0]]  # rank one: manipulability 0
    dq, lam = d.step(Js[:, :6], e, q, ctx)
    assert lam == pytest.approx(0.2)
    assert np.all(np.isfinite(dq))
    d = DampedLeastSquares(damping=0.2, adaptive="singular_value", threshold=2 * s[-1])
    _, lam = d.step(J, e, q, ctx)
    assert lam**2 == pytest.approx(0.04 * (1 - 0.25))


def test_transpose_step(redundant):
    _, q, ctx, J, e = redundant
    dq, _ = JacobianTranspose().step(J, e, q, ctx)
    g = J.T @ e
    alpha = (e @ J @ g) / np.sum((J @ g) ** 2)
    assert np.allclose(dq, alpha * g)
    dq, _ = JacobianTranspose(gain=0.5).step(J, e, q, ctx)
    assert np.allclose(dq, 0.5 * g)


def test_lm_step_equals_damped_normal_equations(redundant):
    _, q, ctx, J, e = redundant
    dq, lam = LevenbergMarquardt(bias=1e-4, error_damping=1.0).step(J, e, q, ctx)
    lam2 = 0.5 * e @ e + 1e-4
    assert lam**2 == pytest.approx(lam2)
    assert np.allclose(dq, np.linalg.solve(J.T @ J + lam2 * np.eye(7), J.T @ e))
    # batched call gives the same rows
    dqb, _ = LevenbergMarquardt(bias=1e-4, error_damping=1.0).step(np.stack([J, J]), np.stack([e, e]), q, ctx)
    assert np.allclose(dqb, dq)


# ------------------------------------------------------------- null space
def test_nullspace_projection_leaves_the_task_unchanged(redundant):
    chain, q, ctx, J, _ = redundant
    method = NullSpace("joint_limits", gain=1.0)
    dq, _ = method.step(J, np.zeros(6), q, ctx)  # pure self-motion
    grad = JointLimitDistance().gradient(q, ctx)
    P = np.eye(7) - np.linalg.pinv(J) @ J
    assert np.allclose(dq, P @ grad)
    assert np.allclose(J @ dq, 0.0, atol=1e-12)
    assert grad @ dq > 0  # H increases to first order


def test_self_motion_increases_the_objective_and_keeps_the_pose():
    chain = baxter_left()
    q = np.array([1.2, -1.5, 2.5, 2.3, -2.5, 1.8, 2.5])  # close to several limits
    T0 = chain.fk(q)
    ctx = make_context(chain, np.ones(6, bool), None, "limits")
    H = JointLimitDistance()
    method = NullSpace("joint_limits")
    values = [H.value(q, ctx)]
    for _ in range(30):
        T = chain.fk(q)
        e = np.r_[T0[:3, 3] - T[:3, 3], rotation_log(T0[:3, :3] @ T[:3, :3].T)]
        dq, _ = method.step(chain.jacobian(q), e, q, ctx)
        q = q + dq
        values.append(H.value(q, ctx))
    assert np.all(np.diff(np.array(values)) > -1e-12)
    assert values[-1] > values[0] + 1e-3
    assert np.allclose(chain.fk(q), T0, atol=1e-6)
    assert np.all(within_limits(chain, q))


def test_nullspace_solve_prefers_mid_range():
    chain = baxter_left()
    Q, T = reachable_targets(chain, 10, seed=9)
    H = JointLimitDistance()
    ctx = make_context(chain, np.ones(6, bool), None, "limits")
    better = 0
    for i in range(10):
        a = solve_ik(chain, T[i], q0=Q[i] * 0.5, method="pinv")
        b = solve_ik(chain, T[i], q0=Q[i] * 0.5, method="nullspace")
        assert a.success and b.success
        better += int(H.value(b.q, ctx) > H.value(a.q, ctx))
    assert better >= 8


def test_objective_gradients():
    chain = baxter_left()
    q = chain.random_configurations(1, seed=2)[0]
    ctx = make_context(chain, np.ones(6, bool), None, "limits")
    h = 1e-6
    for obj in (JointLimitDistance(), Manipulability()):
        g = obj.gradient(q, ctx)
        num = np.array([(obj.value(q + h * d, ctx) - obj.value(q - h * d, ctx)) / (2 * h) for d in np.eye(7)])
        assert np.allclose(g, num, atol=1e-5)
    assert JointLimitDistance().value(np.mean(np.asarray(chain.limits), axis=1), ctx) == 0.0
    # batched evaluation
    Qb = np.stack([q, q])
    assert np.allclose(Manipulability().gradient(Qb, ctx)[1], Manipulability().gradient(q, ctx))


def test_user_gradient_callable_is_used():
    chain = baxter_left()
    Q, T = reachable_targets(chain, 1, seed=3)
    target_q = np.zeros(7)
    res = solve_ik(chain, T[0], method="nullspace", objective=lambda q: -(q - target_q), gain=0.5)
    assert res.success
    with pytest.raises(ShapeError, match="gradient"):
        solve_ik(chain, T[0], q0=Q[0] + 0.3, method="nullspace", objective=lambda q: np.zeros(3))


# ------------------------------------------------------------ kernels
#: a few ulp of pi (measured: 8.9e-16 at most, over the angles below)
LOG_TOLERANCE = 2e-15


def test_pose_error_uses_the_one_rotation_log_for_one_pose_and_for_stacks():
    """One pair of poses (plain floats) and a stack (arrays) give the rotation log of R_goal R^T to
    a few ulp at any angle, also within 1e-3 of pi, and the same position error bit for bit."""
    rng = np.random.default_rng(0)
    axes = rng.normal(size=(3000, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    angles = np.concatenate((np.pi - rng.uniform(0.0, 1e-3, 1000), np.pi - np.logspace(-16, -3, 500),
                             rng.uniform(0.0, np.pi, 1000), np.logspace(-12, -3, 500)))
    goals = np.tile(np.eye(4), (len(angles), 1, 1))
    goals[:, :3, :3] = rotation_exp(angles[:, None] * axes)
    goals[:, :3, 3] = rng.normal(size=(len(angles), 3))
    start = transform(np.eye(3), [0.1, -0.2, 0.3])
    stacked = pose_error_unchecked(start, goals[:, :3, :3], goals[:, :3, 3])
    single = np.array([pose_error_unchecked(start, goal[:3, :3], goal[:3, 3]) for goal in goals])
    np.testing.assert_array_equal(stacked[:, :3], goals[:, :3, 3] - start[:3, 3])
    np.testing.assert_array_equal(single[:, :3], stacked[:, :3])
    expected = angles[:, None] * axes
    # within 1e-7 of pi the sign of the axis is a rounding away from flipping: both are right there
    flip = (angles > np.pi - 1e-7) & (np.einsum("ki,ki->k", stacked[:, 3:], expected) < 0)
    expected[flip] *= -1
    np.testing.assert_allclose(stacked[:, 3:], expected, rtol=0, atol=LOG_TOLERANCE)
    np.testing.assert_allclose(single[:, 3:], stacked[:, 3:], rtol=0, atol=LOG_TOLERANCE)


def test_pose_error_at_exactly_pi_makes_the_largest_axis_component_positive():
    """At theta = pi both axis signs are right; pose_error returns the one whose largest-magnitude
    component is positive (as its docstring says)."""
    for axis in ([0.0, 0.0, -1.0], [0.6, -0.8, 0.0], [-1.0, 0.0, 0.0]):
        h = np.asarray(axis)
        R = 2.0 * np.outer(h, h) - np.eye(3)  # rotation by pi about h, exactly symmetric
        e = pose_error(np.eye(4), transform(R, np.zeros(3)))[3:]
        expected = np.pi * h * np.sign(h[np.argmax(np.abs(h))])
        assert np.allclose(e, expected, atol=1e-15)


def test_classify_stall():
    J = np.eye(2, 3)
    lo, hi = np.full(3, -1.0), np.full(3, 1.0)
    e = np.array([1.0, 0.0])
    assert classify_stall(J, e, np.zeros(3), lo, hi, 1e-2) == Outcome.STALLED  # gradient free to act
    assert classify_stall(J, e, np.array([1.0, 0, 0]), lo, hi, 1e-2) == Outcome.JOINT_LIMITS  # pushed into a limit
    J2 = np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    assert classify_stall(J2, e, np.zeros(3), lo, hi, 1e-2) == Outcome.UNREACHABLE  # e orthogonal to range(J)


def test_one_outcome_enum_names_every_reason():
    """Single, batched and polishing solvers share Outcome; REASONS lists its names."""
    assert REASONS == ("converged", "max_iterations", "stalled", "unreachable", "joint_limits")
    assert [Outcome(code).reason for code in range(len(REASONS))] == list(REASONS)


# -------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("kwargs", "exc", "word"),
    [
        ({"target": [np.nan, 0.0, 0.0]}, DomainError, "target"),
        ({"target": np.zeros((3, 3))}, ShapeError, "target"),
        ({"target": np.zeros(4)}, ShapeError, "target"),
        ({"target": 2 * np.eye(4)}, DomainError, "target"),
        ({"method": "weighted", "weights": [1, 1, -1, 1, 1, 1]}, DomainError, "weights"),
        ({"method": "weighted", "weights": -np.eye(6)}, DomainError, "weights"),
        ({"method": "weighted", "weights": [[1, 2], [3, 4]]}, DomainError, "weights"),
        ({"method": "dls", "damping": -0.1}, DomainError, "damping"),
        ({"method": "pinv", "gain": -1.0}, DomainError, "gain"),
        ({"method": "transpose", "gain": 0.0}, DomainError, "gain"),
        ({"method": "nullspace", "gain": -2.0}, DomainError, "gain"),
        ({"method": "lm", "bias": -1e-3}, DomainError, "bias"),
        ({"method": "dls", "adaptive": "magic"}, ValueError, "adaptive"),
        ({"method": "newton"}, ValueError, "method"),
        ({"q0": np.zeros(5)}, ShapeError, "q0"),
        ({"q0": [np.nan] * 6}, DomainError, "q0"),
        ({"mask": [True] * 5}, ShapeError, "mask"),
        ({"mask": [False] * 6}, DomainError, "mask"),
        ({"tol": -1e-6}, DomainError, "tol"),
        ({"tol": 0.0}, DomainError, "tol"),
        ({"tool": np.ones((4, 4))}, DomainError, "tool"),
        ({"max_iterations": 0}, DomainError, "max_iterations"),
        ({"restarts": -1}, DomainError, "restarts"),
        ({"max_step": -0.1}, DomainError, "max_step"),
        ({"stall_tolerance": 1.5}, DomainError, "stall_tolerance"),
    ],
)
def test_bad_input_raises_naming_the_argument(arm, kwargs, exc, word):
    chain, _, T = arm
    kwargs = dict(kwargs)
    target = kwargs.pop("target", T[0])
    with pytest.raises(exc, match=word):
        solve_ik(chain, target, **kwargs)


def test_position_target_with_orientation_mask_is_rejected(arm):
    chain, _, T = arm
    with pytest.raises(DomainError, match="mask"):
        solve_ik(chain, T[0][:3, 3], mask=[1, 1, 1, 1, 0, 0])


def test_weights_of_the_wrong_size(arm):
    chain, _, T = arm
    with pytest.raises(ShapeError, match="weights"):
        solve_ik(chain, T[0], method="weighted", weights=np.ones(7))


# ------------------------------------------------------- property tests
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_angles = st.floats(-3.0, 3.0, allow_nan=False)


@settings(max_examples=40, deadline=None)
@given(q=st.tuples(_angles, _angles, _angles), q0=st.tuples(_angles, _angles, _angles))
def test_property_planar_reachable_positions_are_solved(q, q0):
    chain = planar_3r()
    target = chain.fk(np.array(q))[:3, 3]
    res = solve_ik(chain, target, q0=np.array(q0))
    assert res.success
    assert np.linalg.norm(chain.fk(res.q)[:3, 3] - target) <= 1e-6
    assert within_limits(chain, res.q)


@settings(max_examples=40, deadline=None)
@given(w=st.tuples(_angles, _angles, _angles), method=st.sampled_from(["lm", "pinv", "dls"]))
def test_property_success_implies_tolerance(w, method):
    chain = ur10()
    q = np.array([0.2, -1.0, 1.2, -1.0, 1.0, 0.0]) + np.r_[w, w] * 0.3
    target = chain.fk(np.clip(q, -6.28, 6.28))
    res = solve_ik(chain, target, method=method, max_iterations=6, restarts=0, polish=False, tol=1e-7)
    assert res.success == (res.position_error <= 1e-7 and res.orientation_error <= 1e-7)
