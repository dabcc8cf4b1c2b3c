r"""Monotone Levenberg–Marquardt polishing of failed IK attempts.

When every attempt of a solver has failed, :func:`polish` continues from the
best configuration found with a *monotone* Levenberg–Marquardt iteration
(Marquardt's rule: a step is accepted only if it lowers the error, otherwise
the damping :math:`\mu` is raised and the step recomputed from the same
Jacobian; Nocedal & Wright 2006, §10.3).  It converges to a stationary point
of :math:`\tfrac12\|e\|^2` within the joint limits, which gives

- the closest configuration (in the least-squares sense, locally) to an
  unreachable target, and
- a meaningful ``reason`` from :func:`~robokin.motion.ik.stall.classify_stall`
  (``"unreachable"``, ``"joint_limits"`` or ``"stalled"``).

Vectorised over rows: ``q`` has shape ``(N, n)``.
"""

from __future__ import annotations

import numpy as np

from robokin.motion.ik.problem import IKContext
from robokin.motion.ik.result import Outcome
from robokin.motion.ik.settings import REFINE_STALL_TOLERANCE, IKSettings
from robokin.motion.ik.stall import classify_stall
from robokin.motion.pose_error import pose_error_unchecked

__all__ = ["polish"]

#: Damping factors of Marquardt's rule: after a rejected step, after an accepted one; its bounds.
_RAISE, _LOWER = 8.0, 3.0
_INITIAL_DAMPING, _SMALLEST_DAMPING, _LARGEST_DAMPING = 1e-3, 1e-9, 1e8


def _task(ctx: IKContext, q: np.ndarray, T_goal: np.ndarray, is_position: bool
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Flange poses (N, 4, 4), pose errors (N, 6) and their task rows (N, m) at ``q`` (N, n)."""
    T_flange, T = ctx.pose(q)
    error = pose_error_unchecked(T, T_goal[:, :3, :3], T_goal[:, :3, 3])
    if is_position:
        error[:, 3:] = 0.0
    task_error = error if ctx.full_mask else error[:, ctx.rows]
    return T_flange, error, task_error


def polish(
    settings: IKSettings, q: np.ndarray, T_goal: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Polish rows ``q`` (N, n) towards ``T_goal`` (N, 4, 4).

    Uses the tolerances, ``max_iterations``, ``stall_iterations`` (window of
    the stationarity test, with the relative decrease
    :data:`~robokin.motion.ik.settings.REFINE_STALL_TOLERANCE`) and
    ``gradient_tolerance`` of ``settings``.

    Returns ``(q, e (N, 6), converged (N,), outcome (N,), iterations (N,))``,
    ``outcome`` an :class:`~robokin.motion.ik.result.Outcome` code: ``CONVERGED``, a
    verdict of :func:`classify_stall` or ``MAX_ITERATIONS``.
    """
    ctx, is_position = settings.ctx, settings.is_position
    max_iterations, window = settings.max_iterations, settings.stall_iterations
    tol_position, tol_orientation = settings.tol_position, settings.tol_orientation
    N, n = q.shape
    lower, upper, mask = ctx.lower, ctx.upper, ctx.mask
    q = q.copy()
    T_flange, error, task_error = _task(ctx, q, T_goal, is_position)
    cost = 0.5 * np.sum(task_error * task_error, axis=1)
    J = ctx.jacobian(q, T_flange)
    task_jacobian = J if ctx.full_mask else J[:, ctx.rows, :]
    damping = np.full(N, _INITIAL_DAMPING)
    reference_cost = cost.copy()
    accepted_since_check = np.zeros(N, dtype=int)
    iterations = np.zeros(N, dtype=int)
    outcome = np.full(N, Outcome.MAX_ITERATIONS)
    converged = np.zeros(N, dtype=bool)
    active = np.ones(N, dtype=bool)
    identity = np.eye(n)
    for _ in range(max_iterations * 4):  # accepted + rejected trials
        position_error = np.linalg.norm(error[:, :3] * mask[:3], axis=1)
        orientation_error = np.linalg.norm(error[:, 3:] * mask[3:], axis=1)
        newly = active & (position_error <= tol_position) & (orientation_error <= tol_orientation)
        converged |= newly
        active &= ~newly
        rows = np.flatnonzero(active)
        if rows.size == 0:
            break
        J_rows, e_rows, q_rows = task_jacobian[rows], task_error[rows], q[rows]
        gradient = (np.swapaxes(J_rows, 1, 2) @ e_rows[:, :, None])[:, :, 0]
        # joints on a limit that the gradient pushes outwards take no part in the step
        blocked = ((q_rows <= lower) & (gradient < 0)) | ((q_rows >= upper) & (gradient > 0))
        J_free = np.where(blocked[:, None, :], 0.0, J_rows)
        gradient_free = np.where(blocked, 0.0, gradient)
        JtJ = np.swapaxes(J_free, 1, 2) @ J_free
        scale = np.maximum(np.einsum("kii->k", JtJ) / n, 1e-12)
        A = JtJ + (damping[rows] * scale)[:, None, None] * identity
        dq = np.linalg.solve(A, gradient_free[:, :, None])[:, :, 0]
        q_trial = ctx.project(q_rows + dq)
        T_flange_trial, error_trial, task_error_trial = _task(ctx, q_trial, T_goal[rows], is_position)
        cost_trial = 0.5 * np.sum(task_error_trial * task_error_trial, axis=1)
        lower_cost = cost_trial < cost[rows]
        accepted = rows[lower_cost]
        rejected = rows[~lower_cost]
        damping[rejected] *= _RAISE
        if accepted.size:
            damping[accepted] = np.maximum(damping[accepted] / _LOWER, _SMALLEST_DAMPING)
            q[accepted] = q_trial[lower_cost]
            error[accepted] = error_trial[lower_cost]
            task_error[accepted] = task_error_trial[lower_cost]
            cost[accepted] = cost_trial[lower_cost]
            J_new = ctx.jacobian(q_trial[lower_cost], T_flange_trial[lower_cost])
            task_jacobian[accepted] = J_new if ctx.full_mask else J_new[:, ctx.rows, :]
            iterations[accepted] += 1
            accepted_since_check[accepted] += 1
        # stationary: no relative decrease of REFINE_STALL_TOLERANCE over `window` accepted
        # steps, or the damping exploded (no descent possible)
        checked = active & (accepted_since_check >= window)
        stuck = checked & (cost > (1.0 - REFINE_STALL_TOLERANCE) ** 2 * reference_cost)
        reference_cost = np.where(checked & ~stuck, cost, reference_cost)
        accepted_since_check = np.where(checked & ~stuck, 0, accepted_since_check)
        stuck |= active & (damping > _LARGEST_DAMPING)
        stuck |= active & (iterations >= max_iterations)
        if stuck.any():
            ended = np.flatnonzero(stuck)
            verdicts = classify_stall(task_jacobian[ended], task_error[ended], q[ended], lower, upper,
                                      settings.gradient_tolerance)
            # a damping that exploded means no descent direction: a stall there is out of reach
            exploded = damping[ended] > _LARGEST_DAMPING
            verdicts = np.where(exploded & (verdicts == Outcome.STALLED), Outcome.UNREACHABLE, verdicts)
            outcome[ended] = np.where(iterations[ended] >= max_iterations, Outcome.MAX_ITERATIONS, verdicts)
            active[ended] = False
    outcome[converged] = Outcome.CONVERGED
    return q, error, converged, outcome, iterations
