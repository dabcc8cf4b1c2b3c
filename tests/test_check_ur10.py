"""Tests of the chapter-2 exercise checks (robokin.check.ur10).

The correct answers are written independently of the reference formulas: the
weighted pseudoinverse from the KKT system of min ΔqᵀWΔq s.t. JΔq = e, the DLS
step from the normal equations (JᵀJ + λ²I)Δq = Jᵀe, the projector from an
orthonormal basis of the null space (SVD).
"""

from __future__ import annotations

import importlib
from typing import Any

import numpy as np
import pytest

ur = importlib.import_module("robokin.check.ur10")


# ---------------------------------------------------------------- correct answers
def weighted_kkt(J, W):
    """Columns: argmin ΔqᵀWΔq s.t. J Δq = e_k, from the KKT system."""
    m, n = J.shape
    K = np.block([[W, J.T], [J, np.zeros((m, m))]])
    rhs = np.vstack([np.zeros((n, m)), np.eye(m)])
    return np.linalg.solve(K, rhs)[:n]


def dls_normal(J, e, damping):
    n = J.shape[1]
    return np.linalg.solve(J.T @ J + damping**2 * np.eye(n), J.T @ e)


def projector_svd(J):
    _, s, Vt = np.linalg.svd(J)
    N = Vt[np.sum(s > 1e-10):].T
    return N @ N.T


def test_correct_answers_pass():
    for check, answer in ((ur.weighted_pinv, weighted_kkt), (ur.dls_step, dls_normal),
                          (ur.nullspace_projector, projector_svd)):
        r = check(answer, quiet=True)
        assert r.passed and r.diagnosis is None, r.message
        assert r.samples == 20


def test_pass_prints_one_line(capsys):
    ur.nullspace_projector(projector_svd)
    assert capsys.readouterr().out == "✔ nullspace_projector(J) is correct (checked at 20 random configurations).\n"


# ---------------------------------------------------------------- diagnosed mistakes
def inv(A):
    return np.linalg.inv(A)


WRONG_WEIGHTED = {
    "weights_not_inverted": lambda J, W: W @ J.T @ inv(J @ W @ J.T),
    "weights_after_pinv": lambda J, W: inv(W) @ np.linalg.pinv(J),
    "weights_after_pinv/inner_factor": lambda J, W: inv(W) @ J.T @ inv(J @ J.T),  # = W⁻¹ J⁺
    "unweighted": lambda J, W: np.linalg.pinv(J),
    "shape": lambda J, W: weighted_kkt(J, W).T,
    "error": lambda J, W: np.linalg.inv(J),  # J is not square
}

WRONG_DLS = {
    "damping_not_squared": lambda J, e, lam: J.T @ np.linalg.solve(J @ J.T + lam * np.eye(3), e),
    "undamped": lambda J, e, lam: np.linalg.pinv(J) @ e,
    "damping_sign": lambda J, e, lam: J.T @ np.linalg.solve(J @ J.T - lam**2 * np.eye(3), e),
    "error_sign": lambda J, e, lam: -dls_normal(J, e, lam),
    "jacobian_transpose": lambda J, e, lam: J.T @ e,
    "mismatch": lambda J, e, lam: 2 * dls_normal(J, e, lam) + 1.0,
}

WRONG_PROJECTOR = {
    "range_projector": lambda J: np.linalg.pinv(J) @ J,
    "transpose_for_pinv": lambda J: np.eye(6) - J.T @ J,
    "sign": lambda J: -projector_svd(J),
    "shape": lambda J: np.eye(3) - J @ np.linalg.pinv(J),
}


@pytest.mark.parametrize("code", sorted(WRONG_WEIGHTED))
def test_weighted_mistakes(code):
    r = ur.weighted_pinv(WRONG_WEIGHTED[code], quiet=True)
    assert not r.passed and r.diagnosis == code.split("/")[0], r.message
    assert r.message.startswith("✘ ")


@pytest.mark.parametrize("code", sorted(WRONG_DLS))
def test_dls_mistakes(code):
    r = ur.dls_step(WRONG_DLS[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


@pytest.mark.parametrize("code", sorted(WRONG_PROJECTOR))
def test_projector_mistakes(code):
    r = ur.nullspace_projector(WRONG_PROJECTOR[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_weights_message_says_large_weight_moves_less():
    r = ur.weighted_pinv(WRONG_WEIGHTED["weights_not_inverted"], quiet=True)
    assert "W⁻¹" in r.message and "LARGE" in r.message


def test_non_function_answer_is_explained():
    r = ur.weighted_pinv(np.eye(3), quiet=True)
    assert not r.passed and "Python function" in r.message


def test_raise_on_fail():
    with pytest.raises(AssertionError, match="λ"):
        ur.dls_step(WRONG_DLS["undamped"], raise_on_fail=True, quiet=True)


def test_samples_are_regular_and_reproducible():
    """The sampled Jacobians are well conditioned, so the references are well defined."""
    X1 = ur.weighted_pinv.sample_points()
    X2 = ur.weighted_pinv.sample_points()
    np.testing.assert_array_equal(X1, X2)
    for x in X1:
        s = np.linalg.svd(ur._position_jacobian(x[:6]), compute_uv=False)
        assert s[-1] > 0.02


def test_references_match_robokin_solvers():
    """The references agree with the step rules of robokin.motion."""
    from robokin.motion import DampedLeastSquares, WeightedPseudoInverse

    x = ur.dls_step.sample_points()[0]
    J, e, lam = ur._damped_least_squares_arguments(x)
    dq, _ = DampedLeastSquares(damping=lam).step(J, e, None, None)
    np.testing.assert_allclose(dq, ur._damped_least_squares_reference(x), atol=1e-12)
    x = ur.weighted_pinv.sample_points()[0]
    J, W = ur._weighted_pinv_arguments(x)
    dq, _ = WeightedPseudoInverse(weights=np.diag(W)).step(J, e, None, None)
    np.testing.assert_allclose(dq, ur._weighted_pinv_reference(x) @ e, atol=1e-12)


def test_registered():
    from robokin.check._registry import _REGISTRY

    assert set(_REGISTRY["ur10"]) == {"weighted_pinv", "dls_step", "nullspace_projector", "joint_limit_objective",
                                      "joint_limit_gradient", "ik_position", "summary", "self_motion",
                                      "ik_restarts", "bisect"}


# ---------------------------------------------------------------- the joint-limit objective (task 2 c)
def objective_written(q, limits=ur.WORK_LIMITS, *, variant=""):
    """H of eq. 3.57 written independently of the check (the joints in a loop, the middle as
    lower + half the range), and its typical mistakes."""
    q = np.asarray(q, dtype=float)
    limits = ur.WORK_LIMITS if variant == "default_limits" else np.asarray(limits, dtype=float)
    n = limits.shape[0]
    total = np.zeros(q.shape[:-1])
    for i, (lower, upper) in enumerate(limits):
        centre = 0.0 if variant == "not_centred" else lower + (upper - lower) / 2
        scale = 1.0 if variant == "not_normalised" else upper - lower
        total = total + ((q[..., i] - centre) / scale) ** 2
    if variant == "batch_summed_whole":
        total = total.sum()
    factor = {"no_factor": -1.0, "sign": 1.0 / (2 * n), "factor": -1.0 / n}.get(variant, -1.0 / (2 * n))
    return factor * total


def gradient_written(q, limits=ur.WORK_LIMITS, *, variant=""):
    """∇H written independently of the check (the derivative of each square by the chain rule,
    joint by joint), and its typical mistakes."""
    q = np.asarray(q, dtype=float)
    limits = ur.WORK_LIMITS if variant == "default_limits" else np.asarray(limits, dtype=float)
    n = len(limits)
    out = []
    for i, (lower, upper) in enumerate(limits):
        inner = (q[i] - (0.0 if variant == "not_centred" else (lower + upper) / 2))
        scale = {"not_normalised": 1.0, "span_not_squared": upper - lower}.get(variant, (upper - lower) ** 2)
        derivative = {"square_not_brought_down": 1.0}.get(variant, 2.0) * inner / scale  # d/dq of inner²/range²
        out.append({"no_factor": -1.0, "sign": 1.0 / (2 * n)}.get(variant, -1.0 / (2 * n)) * derivative)
    return np.array(out)


def test_joint_limit_answers_written_independently_pass(capsys):
    assert ur.joint_limit_objective(objective_written).passed
    assert ur.joint_limit_gradient(gradient_written).passed
    out = capsys.readouterr().out
    assert "✔ joint_limit_objective is correct" in out and "✔ joint_limit_gradient is correct" in out


def test_joint_limit_answers_agree_with_robokin():
    """The functions written above are robokin's JointLimitDistance, its value and gradient, on the
    check's own configurations and limits."""
    from robokin.motion import JointLimitDistance

    for _, limits, Q in ur._limit_cases():
        limits = ur.WORK_LIMITS if limits is None else limits
        H = JointLimitDistance(limits)
        assert np.allclose(objective_written(Q, limits), H.value(Q), rtol=1e-12, atol=0.0)
        for q in Q:
            assert np.allclose(gradient_written(q, limits), H.gradient(q), rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("variant, code", [
    ("sign", "sign"), ("no_factor", "no_factor"), ("factor", "factor"), ("not_normalised", "not_normalised"),
    ("not_centred", "not_centred"), ("default_limits", "default_limits"), ("batch_summed_whole", "batch"),
])
def test_joint_limit_objective_mistakes(variant, code):
    r = ur.joint_limit_objective(lambda *args: objective_written(*args, variant=variant), quiet=True)
    assert not r.passed and r.diagnosis == code, r.message
    assert "joint_limit_objective" in r.message


def test_joint_limit_objective_other_factor_is_named_by_its_value():
    r = ur.joint_limit_objective(lambda *args: objective_written(*args, variant="factor"), quiet=True)
    assert "2 × H" in r.message and "1/(2n)" in r.message


@pytest.mark.parametrize("code", ["sign", "no_factor", "square_not_brought_down", "span_not_squared",
                                  "not_normalised", "not_centred", "default_limits"])
def test_joint_limit_gradient_mistakes(code):
    r = ur.joint_limit_gradient(lambda *args: gradient_written(*args, variant=code), quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_joint_limit_gradient_mismatch_names_entries_not_values():
    """A gradient no typical mistake explains (one joint's term left out): the message names the
    wrong entry and central differences as the way to see it; it states neither the closed form
    asked for nor the gradient's values."""
    def one_term_missing(q, limits=ur.WORK_LIMITS):
        out = gradient_written(q, limits)
        out[2] = 0.0
        return out

    r = ur.joint_limit_gradient(one_term_missing, quiet=True)
    assert not r.passed and r.diagnosis == "mismatch", r.message
    assert "in its entries [3]: compare them with central differences of your H" in r.message
    assert "give" not in r.message
    for code in ("sign", "no_factor", "square_not_brought_down", "span_not_squared"):
        def mistake(*args, code=code):
            return gradient_written(*args, variant=code)

        assert "(1/n)" not in ur.joint_limit_gradient(mistake, quiet=True).message
    assert "(1/n)" not in r.message


def test_joint_limit_bad_answers():
    assert ur.joint_limit_gradient(lambda q, limits=None: gradient_written(q)[:3], quiet=True).diagnosis == "shape"
    assert ur.joint_limit_objective(lambda q, limits=None: "H", quiet=True).diagnosis == "type"
    assert ur.joint_limit_objective(None, quiet=True).diagnosis == "error"
    assert ur.joint_limit_gradient(lambda q, limits=None: 1 / 0, quiet=True).diagnosis == "error"


# ---------------------------------------------------------------- the IK loop
def loop_for(chain, p_goal, q0, step, max_step=0.5, tol=1e-9, max_iterations=100, *,
             sign=1.0, cap=True, per_joint=False, clamp=True, early_stop=True):
    """An IK loop written independently of the check's reference (a for loop that
    returns from inside, the cap as a division, the limits with minimum/maximum)."""
    lower, upper = chain.limits[:, 0], chain.limits[:, 1]
    q = np.array(q0, dtype=float)
    for iteration in range(max_iterations + 1):
        e = sign * (p_goal - chain.fk(q)[:3, 3])
        if early_stop and np.sqrt(e @ e) <= tol:
            return q, True, iteration
        if iteration == max_iterations:
            return q, bool(np.sqrt(e @ e) <= tol), iteration
        dq = step(chain.position_jacobian(q), e, q)
        length = np.sqrt(dq @ dq)
        if per_joint:
            dq = np.clip(dq, -max_step, max_step)
        elif cap and length > max_step:
            dq = dq / length * max_step
        q = q + dq
        if clamp:
            q = np.minimum(np.maximum(q, lower), upper)


WRONG_LOOP: dict[str, dict[str, Any]] = {
    "error_sign": dict(sign=-1.0),
    "no_step_cap": dict(cap=False),
    "step_cap_per_joint": dict(per_joint=True),
    "no_joint_limits": dict(clamp=False),
    "no_early_stop": dict(early_stop=False),
}


def test_loop_correct_passes():
    r = ur.ik_position(loop_for, quiet=True)
    assert r.passed and r.samples == 20, r.message


@pytest.mark.parametrize("code", sorted(WRONG_LOOP))
def test_loop_mistakes(code):
    def wrong(*args):
        return loop_for(*args, **WRONG_LOOP[code])

    r = ur.ik_position(wrong, quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_loop_mistake_without_a_name_is_shown_in_the_student_terms():
    """A loop that counts one step too many: the example names the call and the returned
    `iterations`, not the sampled scalars or a packed index."""
    def one_too_many(*args):
        q, converged, iterations = loop_for(*args)
        return q, converged, iterations + 1

    r = ur.ik_position(one_too_many, quiet=True)
    assert not r.passed and r.diagnosis == "mismatch", r.message
    assert "ik_position(cell, p_goal = [" in r.message and "max_iterations = " in r.message
    assert "iterations should be" in r.message and "dq1" not in r.message


def test_loop_must_return_a_tuple():
    r = ur.ik_position(lambda *args: loop_for(*args)[0], quiet=True)
    assert not r.passed and r.diagnosis == "error" and "(q, converged, iterations)" in r.message


def test_loop_samples_exercise_every_branch():
    """Some sampled runs converge within their budget and some do not, and the
    check's goals make the cap and the limits act at some samples."""
    X = ur.ik_position.sample_points()
    R = np.array([ur._loop_ref(x) for x in X])
    assert 0 < R[:, 6].sum() < len(X)
    for kwargs in (dict(cap=None), dict(clamp=False)):
        M = np.array([ur._loop(*ur._loop_args(x), **kwargs) for x in X])
        assert (~np.all(np.isclose(M, R, atol=1e-7), axis=1)).sum() >= 2


def test_loop_reference_matches_solve_ik():
    """Where no joint reaches a limit, the reference loop takes solve_ik's steps."""
    from robokin.motion import solve_ik

    chain = ur._cell()
    compared = 0
    for x in ur.ik_position.sample_points()[:8]:
        _, p_goal, q0, _, max_step, tol, _ = ur._loop_args(x)
        out = ur._loop(chain, p_goal, q0, ur._pinv_step, max_step, tol, 100)
        res = solve_ik(chain, p_goal, q0=q0, method="pinv", max_step=max_step, tol=tol,
                       restarts=0, polish=False, max_iterations=100)
        assert res.history is not None
        touched = np.any(np.isclose(res.history.q, chain.limits[:, 0]) | np.isclose(res.history.q, chain.limits[:, 1]))
        if res.success and not touched:
            assert out[6] == 1.0 and out[7] == res.iterations
            np.testing.assert_allclose(out[:6], res.q, atol=1e-9)
            compared += 1
    assert compared >= 4


# ---------------------------------------------------------------- bisection (task 6)
def bisect_written(f, low, high, tol=1e-13, *, keep="sign", fixed_halvings=0, check_bracket=True):
    """A bisection written independently of the check (a recursion on the bracket), and
    its typical mistakes."""
    f_low, f_high = f(low), f(high)
    if f_low * f_high > 0:
        if check_bracket:
            raise ValueError("f(low) and f(high) have the same sign")
        return (low + high) / 2
    for _ in range(fixed_halvings or 10_000):
        if not fixed_halvings and high - low <= 2 * tol:
            break
        middle = low + (high - low) / 2
        if middle in (low, high):
            break
        f_middle = f(middle)
        root_right = (f_middle * f_low > 0) if keep == "sign" else (f_middle < 0)
        if keep == "wrong_half":
            root_right = not root_right
        if root_right:
            low, f_low = middle, f_middle
        else:
            high = middle
    return (low + high) / 2


def test_bisect_correct(capsys):
    assert ur.bisect(bisect_written).passed
    assert "✔ bisect is correct" in capsys.readouterr().out


@pytest.mark.parametrize("kwargs, code", [
    (dict(keep="wrong_half"), "wrong_half"),
    (dict(keep="rising"), "rising_only"),
    (dict(fixed_halvings=20), "tolerance"),
    (dict(check_bracket=False), "no_value_error"),
])
def test_bisect_mistakes(kwargs, code):
    r = ur.bisect(lambda f, low, high, tol=1e-13: bisect_written(f, low, high, tol, **kwargs), quiet=True)
    assert not r.passed and r.diagnosis == code, r.message
    assert "bisect" in r.message


def test_bisect_wrong_exception_and_bad_answers():
    def raises_runtime(f, low, high, tol=1e-13):
        if f(low) * f(high) > 0:
            raise RuntimeError("no bracket")
        return bisect_written(f, low, high, tol)

    assert ur.bisect(raises_runtime, quiet=True).diagnosis == "wrong_exception"
    assert ur.bisect(lambda f, low, high, tol=1e-13: (low, high), quiet=True).diagnosis == "type"
    assert ur.bisect(None, quiet=True).diagnosis == "error"
    assert ur.bisect(0.5, quiet=True).diagnosis == "constant"
    with pytest.raises(AssertionError, match="ValueError"):
        ur.bisect(lambda f, low, high, tol=1e-13: bisect_written(f, low, high, tol, check_bracket=False),
                  raise_on_fail=True)


def test_bisect_cases_bracket_their_roots():
    for _, f, low, high, _, root, rising in ur._bisect_cases():
        assert low < root < high and f(low) * f(high) < 0 and abs(f(root)) < 1e-12
        assert (f(high) > 0) == rising


# ---------------------------------------------------------------- restarts (task 5)
def restarts_written(chain, p_goal, starts, step, *, variant=""):
    """ik_restarts written independently of the check (a while loop over the starts), on the
    independently written loop above, and its typical mistakes."""
    k, total, q_from, first_q = 0, 0, starts[0], None
    converged = False
    while k < len(starts):
        q, ok, iterations = loop_for(chain, p_goal, q_from if variant == "continue_from_last" else starts[k],
                                     step)
        first_q = q if first_q is None else first_q
        total = iterations if variant == "last_attempt_only" else total + iterations
        converged = converged or ok
        k += 1
        q_from = q
        if variant == "no_restart" or (ok and variant != "no_break"):
            break
    if variant == "first_attempt_q":
        q = first_q
    return q, converged, k - 1 if variant == "attempts_from_zero" else k, total


def test_restarts_correct(capsys):
    assert ur.ik_restarts(restarts_written).passed
    assert "✔ ik_restarts is correct" in capsys.readouterr().out


def test_restart_cases_cover_the_three_outcomes():
    outcomes = [tuple(ur._restarts(goal, starts)[6:8]) for _, goal, starts in ur._restart_cases()]
    assert outcomes == [(1.0, 1.0), (1.0, 2.0), (0.0, 3.0)]


@pytest.mark.parametrize("code", ["last_attempt_only", "no_restart", "continue_from_last",
                                  "attempts_from_zero", "no_break", "first_attempt_q"])
def test_restarts_mistakes(code):
    r = ur.ik_restarts(lambda *args: restarts_written(*args, variant=code), quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_restarts_bad_answers():
    assert ur.ik_restarts(lambda *args: restarts_written(*args)[:3], quiet=True).diagnosis == "type"
    off_by_one = ur.ik_restarts(lambda *args: (lambda r: (*r[:3], r[3] + 1))(restarts_written(*args)),
                                quiet=True)
    assert off_by_one.diagnosis == "mismatch" and "iterations (expected 6)" in off_by_one.message
    assert ur.ik_restarts(lambda *args: 1 / 0, quiet=True).diagnosis == "error"



def test_restarts_on_a_wrong_loop_send_the_student_to_the_loop():
    """A right restart loop around a wrong ik_position (the cap joint by joint): the message
    says that the cause may be the student's ik_position, and names no restart mistake."""
    def restarts_on_clipped_loop(chain, p_goal, starts, step):
        runs = []
        for q_start in starts:
            runs.append(loop_for(chain, p_goal, q_start, step, per_joint=True))
            if runs[-1][1]:
                break
        return runs[-1][0], runs[-1][1], len(runs), sum(run[2] for run in runs)

    r = ur.ik_restarts(restarts_on_clipped_loop, quiet=True)
    assert not r.passed and r.diagnosis == "mismatch", r.message
    assert "fix ik_position first" in r.message

# ---------------------------------------------------------------- the figures of a run (task 3)
def summary_written(chain, p_goal, path, wrong=None):
    """summary written independently of the check: robokin's own measures of a run."""
    from robokin.motion import JointLimitDistance

    path = np.asarray(path, dtype=float)
    lower, upper = chain.limits.T
    near = np.array([min((q - lower).min(), (upper - q).min()) for q in path])
    w = chain.manipulability(path, position_only=True)
    out = dict(
        iterations=path.shape[0] - 1,
        error_nm=np.linalg.norm(chain.fk(path[-1])[:3, 3] - p_goal) * 1e9,
        path=sum(np.linalg.norm(b - a) for a, b in zip(path[:-1], path[1:])),
        min_limit=near[1:].min(), end_limit=near[-1],
        end_H=JointLimitDistance(chain.limits).value(path[-1]),
        min_w=w[1:].min(), end_w=w[-1],
    )
    for key, value in (wrong or {}).items():
        out[key] = value(chain, p_goal, path)
    return out


def test_summary_correct():
    assert ur.summary(summary_written, quiet=True).passed


def test_summary_cases_tell_the_start_apart():
    for _, chain, _, path in ur._summary_cases():
        near = ur._limit_distance(path, chain.limits)
        w = chain.manipulability(path, position_only=True)
        assert near[0] < near[1:].min() and w[0] < w[1:].min()


@pytest.mark.parametrize("wrong, code", [
    (dict(iterations=lambda c, p, path: len(path)), "iterations_rows"),
    (dict(error_nm=lambda c, p, path: np.linalg.norm(c.fk(path[-1])[:3, 3] - p)), "error_in_m"),
    (dict(path=lambda c, p, path: np.linalg.norm(path[-1] - path[0])), "path_chord"),
    (dict(path=lambda c, p, path: np.abs(np.diff(path, axis=0)).sum()), "path_l1"),
    (dict(min_limit=lambda c, p, path: np.min(np.minimum(path - c.limits[:, 0], c.limits[:, 1] - path))),
     "min_limit_with_start"),
    (dict(min_limit=lambda c, p, path: np.min(path - c.limits[:, 0], axis=1)[1:].min()), "lower_limits_only"),
    (dict(end_H=lambda c, p, path: ur._objective(path[-1], ur.WORK_LIMITS)), "H_default_limits"),
    (dict(min_w=lambda c, p, path: c.manipulability(path, position_only=True).min()), "min_w_with_start"),
    (dict(end_w=lambda c, p, path: c.manipulability(path[-1], position_only=True) ** 2), "w_squared"),
])
def test_summary_mistakes(wrong, code):
    r = ur.summary(lambda c, p, path: summary_written(c, p, path, wrong), quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_summary_bad_answers():
    assert ur.summary(lambda c, p, path: [1, 2], quiet=True).diagnosis == "type"
    short = ur.summary(lambda c, p, path: {k: v for k, v in summary_written(c, p, path).items() if k != "end_w"},
                       quiet=True)
    assert short.diagnosis == "missing_key" and "end_w" in short.message
    assert ur.summary(lambda c, p, path: dict(summary_written(c, p, path), min_w=7.0),
                      quiet=True).diagnosis == "min_w_wrong"


# ---------------------------------------------------------------- self-motion (task 4)
def self_motion_written(chain, p_goal, q_start, gain, steps, *, variant=""):
    """The self-motion written independently of the check: robokin's gradient and projector
    by the SVD, and its typical mistakes."""
    from robokin.motion import JointLimitDistance

    limits = ur.WORK_LIMITS if variant == "default_limits" else chain.limits
    H = JointLimitDistance(limits)
    q, rows = np.asarray(q_start, dtype=float), []
    for _ in range(steps):
        if variant != "rows_after_step":
            rows.append(q)
        J = chain.position_jacobian(q)
        kernel = np.linalg.svd(J)[2][3:]
        e = p_goal - chain.fk(q)[:3, 3]
        push = {"gradient_sign": -gain, "no_gain": 1.0}.get(variant, gain) * H.gradient(q)
        q = q + (0 if variant == "no_correction" else np.linalg.lstsq(J, e, rcond=None)[0]) + (
            push if variant == "not_projected" else kernel.T @ (kernel @ push))
        if variant == "rows_after_step":
            rows.append(q)
    return np.array(rows)


def test_self_motion_correct():
    assert ur.self_motion(self_motion_written, quiet=True).passed


@pytest.mark.parametrize("code", ["no_correction", "not_projected", "gradient_sign", "no_gain",
                                  "rows_after_step", "default_limits"])
def test_self_motion_mistakes(code):
    r = ur.self_motion(lambda *args: self_motion_written(*args, variant=code), quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_self_motion_bad_answers():
    r = ur.self_motion(lambda *args: self_motion_written(*args)[:-1], quiet=True)
    assert r.diagnosis == "shape" and "q_start" in r.message
    assert ur.self_motion(lambda *args: "rows", quiet=True).diagnosis == "type"
    assert ur.self_motion(None, quiet=True).diagnosis == "error"


def test_self_motion_keeps_the_flange_and_climbs_H():
    for _, chain, goal, q0, gain, steps in ur._self_motion_cases():
        rows = ur._self_motion(chain, goal, q0, gain, steps)
        H = [ur._objective(q, chain.limits) for q in rows]
        assert np.all(np.diff(H) > 0)
        assert np.linalg.norm(chain.fk(rows[-1])[:3, 3] - goal) < 1e-3


def test_self_motion_mismatch_names_the_answers_it_calls():
    """A self-motion with a gradient n times too large (the 1/n of H left out in Task 2): the
    message says that the cause may be the student's gradient or projector."""
    r = ur.self_motion(lambda chain, p_goal, q_start, gain, steps: self_motion_written(
        chain, p_goal, q_start, ur.N_JOINTS * gain, steps), quiet=True)
    assert not r.passed and r.diagnosis == "mismatch", r.message
    assert "joint_limit_gradient" in r.message and "fix those first" in r.message


def test_later_steps_are_judged_on_robokins_earlier_steps():
    """summary, self_motion and ik_restarts take the steps they build on as keyword arguments
    (the student's own by default): their checks pass robokin's in their place, so that a wrong
    earlier step is not blamed on them (the grading report asks these checks about the bare
    answers, whose defaults are the student's steps)."""
    def objective_without_2n(q, limits=ur.WORK_LIMITS):  # H without its factor 1/(2n)
        return 2 * ur.N_JOINTS * ur.reference_joint_limit_objective(q, limits)

    def gradient_descending(q, limits=ur.WORK_LIMITS):  # the sign of the gradient flipped
        return -ur.reference_joint_limit_gradient(q, limits)

    def row_space_projector(J):  # J+ J for I - J+ J
        return np.linalg.pinv(J) @ J

    def loop_capped_per_joint(chain, p_goal, q0, step):
        return loop_for(chain, p_goal, q0, step, per_joint=True)

    def summary_with(chain, p_goal, path, objective=objective_without_2n):
        out = summary_written(chain, p_goal, path)
        out["end_H"] = objective(np.asarray(path, dtype=float)[-1], chain.limits)
        return out

    def self_motion_with(chain, p_goal, q_start, gain, steps, projector=row_space_projector,
                         gradient=gradient_descending):
        q, rows = np.array(q_start, dtype=float), []
        for _ in range(steps):
            rows.append(q)
            J = chain.position_jacobian(q)
            q = q + np.linalg.pinv(J) @ (p_goal - chain.fk(q)[:3, 3]) + projector(J) @ (
                gain * gradient(q, chain.limits))
        return np.array(rows)

    def restarts_with(chain, p_goal, starts, step, solve=loop_capped_per_joint):
        total, attempts = 0, 0
        for q_start in starts:
            q, converged, iterations = solve(chain, p_goal, q_start, step)
            total, attempts = total + iterations, attempts + 1
            if converged:
                break
        return q, converged, attempts, total

    for check, answer in [(ur.summary, summary_with), (ur.self_motion, self_motion_with),
                          (ur.ik_restarts, restarts_with)]:
        assert check(answer, quiet=True).passed, check(answer, quiet=True).message
        # called without its keyword parameters, it runs on the wrong steps it holds
        assert not check(lambda *arguments, f=answer: f(*arguments), quiet=True).passed


# ---------------------------------------------------------------- robokin's steps (the tests' stand-ins)
def test_reference_steps_are_the_correct_answers():
    """Each reference_* agrees with the answers written independently above, at random
    configurations of the work cell, and H's gradient with central differences of H."""
    cell = ur._cell()
    rng = np.random.default_rng(5)
    for q in cell.random_configurations(5, seed=51):
        J = cell.position_jacobian(q)
        W, e, damping = np.diag(rng.uniform(0.5, 4.0, 6)), rng.uniform(-0.1, 0.1, 3), rng.uniform(0.01, 0.5)
        assert np.allclose(ur.reference_weighted_pinv(J, W), weighted_kkt(J, W))
        assert np.allclose(ur.reference_dls_step(J, e, damping), dls_normal(J, e, damping))
        assert np.allclose(ur.reference_nullspace_projector(J), projector_svd(J))
        from robokin.motion import JointLimitDistance

        H = JointLimitDistance(ur.WORK_LIMITS)
        assert np.isclose(ur.reference_joint_limit_objective(q), H.value(q))
        central = np.array([(ur.reference_joint_limit_objective(q + h) - ur.reference_joint_limit_objective(q - h))
                            / 2e-6 for h in 1e-6 * np.eye(6)])
        assert np.allclose(ur.reference_joint_limit_gradient(q), central, atol=1e-9)
    Q = cell.random_configurations(4, seed=52)
    other = ur._other_limits_chain().limits
    assert np.allclose(ur.reference_joint_limit_objective(Q, other),
                       [ur.reference_joint_limit_objective(q, other) for q in Q])
    with pytest.raises(ValueError):
        ur.reference_joint_limit_gradient(Q)
    with pytest.raises(ValueError):
        ur.reference_weighted_pinv(np.ones((3, 6)), np.eye(5))


def test_reference_loop_is_the_loop_and_passes_its_check():
    """reference_ik_position passes the check of ik_position, agrees with the loop written
    independently above, and runs on PseudoinverseStep, the step rule the tests hand on."""
    assert ur.ik_position(ur.reference_ik_position, quiet=True).passed
    cell = ur._cell()
    q0 = cell.random_configurations(1, seed=53)[0]
    goal = cell.fk(cell.random_configurations(1, seed=54)[0])[:3, 3]
    q, converged, iterations = ur.reference_ik_position(cell, goal, q0, ur.PseudoinverseStep())
    q_written, converged_written, iterations_written = loop_for(cell, goal, q0, ur._pinv_step)
    assert converged == converged_written and iterations == iterations_written
    assert np.allclose(q, q_written, atol=1e-12)


def test_restarts_on_the_reference_loop_pass():
    """A restart loop that takes its loop as an argument passes with robokin's."""
    def restarts_with_solve(chain, p_goal, starts, step, solve=None):
        total, attempts = 0, 0
        for q_start in starts:
            q, converged, iterations = solve(chain, p_goal, q_start, step)
            total, attempts = total + iterations, attempts + 1
            if converged:
                break
        return q, converged, attempts, total

    assert ur.ik_restarts(lambda chain, p_goal, starts, step: restarts_with_solve(
        chain, p_goal, starts, step, solve=ur.reference_ik_position), quiet=True).passed


def test_pseudoinverse_step_crosses_the_bridge_as_data():
    """PseudoinverseStep is a robokin dataclass: the grading bridge sends it as data (rebuilt on
    the other side), not as a function of the test."""
    from tools.grading.bridge import codec

    encoded = codec.encode(ur.PseudoinverseStep(), {})
    assert encoded == {"$robokin": ["robokin.check.ur10", "PseudoinverseStep", {}]}
    assert isinstance(codec.decode(encoded), ur.PseudoinverseStep)


# ---------------------------------------------------------------- the graded tests' machinery
#: The chapter's start, goals and weights (notebooks/02_ur10_ik.ipynb).
Q_PARKED = np.array([0.0, -2.6, 2.6, -np.pi / 2, -np.pi / 2, 0.0])
GOALS = {"A": np.array([-0.8, -0.4, 0.8]), "B": np.array([-0.6, -0.9, 0.4])}
WEIGHTS = np.array([2.0, 2.0, 2.0, 1.0, 1.0, 1.0])


def steps_written(damping=None, gain=6 * np.pi**2 / 2):
    """The three step rules of Task 2 (d), written with the independent answers above (the
    damping lambda^2 = 0.1 by default)."""
    from robokin.motion import JointLimitDistance

    damping = np.sqrt(0.1) if damping is None else damping
    H = JointLimitDistance(ur.WORK_LIMITS)
    return {
        "weighted": lambda J, e, q: weighted_kkt(J, np.diag(WEIGHTS)) @ e,
        "DLS": lambda J, e, q: dls_normal(J, e, damping),
        "null space": lambda J, e, q: np.linalg.lstsq(J, e, rcond=None)[0] + projector_svd(J) @ (gain * H.gradient(q)),
    }


def test_step_rules_are_the_steps_of_part_d():
    """robokin's rules (the defaults) agree with the rules written independently, and rules built
    on other steps use them."""
    rules, written = ur.step_rules(WEIGHTS), steps_written()
    assert np.isclose(ur.NULLSPACE_GAIN, 6 * np.pi**2 / 2)
    cell = ur._cell()
    for q in cell.random_configurations(4, seed=61):
        J, e = cell.position_jacobian(q), np.array([0.03, 0.02, -0.05])
        for name in written:
            assert np.allclose(rules[name](J, e, q), written[name](J, e, q))
    doubled = ur.step_rules(WEIGHTS, 0.5, 2.0, dls_step=lambda J, e, damping: 2 * dls_normal(J, e, damping))
    assert np.allclose(doubled["DLS"](J, e, q), 2 * dls_normal(J, e, 0.5))
    with pytest.raises(TypeError):
        ur.step_rules(WEIGHTS, weighted_pinv=None)


def test_assert_steps_follow_takes_either_rule_and_names_a_wrong_step():
    cell = ur._cell()
    Q = cell.random_configurations(3, seed=44)
    wrong_dls = lambda J, e, damping: dls_normal(J, e, damping**2)  # noqa: E731 - λ for λ²
    on_wrong_part = ur.step_rules(WEIGHTS, dls_step=wrong_dls)
    rules = [on_wrong_part, ur.step_rules(WEIGHTS)]
    ur.assert_steps_follow(cell, Q, steps_written(), rules)      # robokin's formula
    ur.assert_steps_follow(cell, Q, dict(on_wrong_part), rules)  # the formula on a wrong part of its own
    with pytest.raises(AssertionError, match="STEPS\\['DLS'\\]"):
        ur.assert_steps_follow(cell, Q, dict(steps_written(), DLS=steps_written(damping=0.1)["DLS"]),
                               [ur.step_rules(WEIGHTS)])
    with pytest.raises(AssertionError, match="keys"):
        ur.assert_steps_follow(cell, Q, {"weighted": steps_written()["weighted"]}, rules)
    raising = ur.step_rules(WEIGHTS, nullspace_projector=lambda J: 1 / 0)
    ur.assert_steps_follow(cell, Q, steps_written(), [raising, ur.step_rules(WEIGHTS)])


def test_loop_as_solve_ik_passes_a_loop_and_rejects_a_mistake():
    """The loop written independently takes solve_ik_once's steps on the chapter's three runs; a
    loop without the step cap does not."""
    cell = ur._cell()
    for goal, method in (("A", "weighted"), ("A", "DLS"), ("B", "null space")):
        q, iterations = ur.loop_as_solve_ik(cell, GOALS[goal], Q_PARKED, method, WEIGHTS, 0.5, loop=loop_for)
        assert np.linalg.norm(cell.fk(q)[:3, 3] - GOALS[goal]) < 1e-9 and iterations > 1
    with pytest.raises(AssertionError, match="weighted"):
        ur.loop_as_solve_ik(cell, GOALS["A"], Q_PARKED, "weighted", WEIGHTS, 0.5,
                            loop=lambda *args: loop_for(*args, cap=False))


def test_assert_self_motion_rows():
    cell = ur._cell()
    q_start = cell.random_configurations(1, seed=62)[0]
    goal = cell.fk(q_start)[:3, 3] + 0.001
    ur.assert_self_motion_rows(self_motion_written(cell, goal, q_start, 0.75, 8), cell, goal, 0.75)
    with pytest.raises(AssertionError, match="row 1 "):
        ur.assert_self_motion_rows(self_motion_written(cell, goal, q_start, 0.75, 8, variant="no_gain"),
                                   cell, goal, 0.75)


def test_assert_path_figures():
    """The figures of a path computed another way pass; one wrong figure is named."""
    from robokin.motion import JointLimitDistance

    cell = ur._cell()
    path = cell.random_configurations(5, seed=63)
    goal = np.array([-0.6, -0.9, 0.4])
    H = JointLimitDistance(cell.limits)
    figures = {
        "H": H.value(path),
        "error": [np.sqrt(np.sum((goal - cell.fk(q)[:3, 3]) ** 2)) for q in path],
        "JN": [np.abs(cell.position_jacobian(q) @ projector_svd(cell.position_jacobian(q))).max() for q in path],
        "distance": [min(np.min(q - cell.limits[:, 0]), np.min(cell.limits[:, 1] - q)) for q in path],
    }
    ur.assert_path_figures(cell, goal, path, figures, H.value, projector_svd)
    with pytest.raises(AssertionError, match="distance"):
        ur.assert_path_figures(cell, goal, path, dict(figures, distance=np.zeros(5)), H.value, projector_svd)
    with pytest.raises(AssertionError, match="expected"):
        ur.assert_path_figures(cell, goal, path, {"H": figures["H"]}, H.value, projector_svd)


def test_assert_summary_of_path():
    """The summary written independently passes on random paths; a wrong figure is named."""
    cell = ur._cell()
    goal = np.array([0.3, -0.5, 0.6])
    for seed in (64, 65):
        path = cell.random_configurations(6, seed=seed)
        ur.assert_summary_of_path(cell, goal, path, summary_written(cell, goal, path))
    figures = summary_written(cell, goal, path)
    with pytest.raises(AssertionError, match="min_w"):
        ur.assert_summary_of_path(cell, goal, path, dict(figures, min_w=figures["end_w"] + 1.0))
    with pytest.raises(AssertionError, match="iterations"):
        ur.assert_summary_of_path(cell, goal, path, dict(figures, iterations=6))
