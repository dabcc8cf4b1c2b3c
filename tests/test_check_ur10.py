"""Tests of the chapter-2 exercise checks (robokin.check.ur10).

The correct answers are written independently of the reference formulas: the
weighted pseudoinverse from the KKT system of min ΔqᵀWΔq s.t. JΔq = e, the DLS
step from the normal equations (JᵀJ + λ²I)Δq = Jᵀe, the projector from an
orthonormal basis of the null space (SVD).
"""

from __future__ import annotations

import importlib

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

    assert set(_REGISTRY["ur10"]) == {"weighted_pinv", "dls_step", "nullspace_projector", "ik_position"}


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


WRONG_LOOP = {
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
        touched = np.any(np.isclose(res.history.q, chain.limits[:, 0]) | np.isclose(res.history.q, chain.limits[:, 1]))
        if res.success and not touched:
            assert out[6] == 1.0 and out[7] == res.iterations
            np.testing.assert_allclose(out[:6], res.q, atol=1e-9)
            compared += 1
    assert compared >= 4
