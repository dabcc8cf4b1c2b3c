r"""Many-target inverse kinematics: :func:`solve_ik_batch`.

The same algorithm as :func:`~robokin.motion.solve_ik`, vectorised over the
targets: each iteration evaluates the chain's batched ``fk``/``jacobian`` on
all attempts still working, computes every step with one batched linear-algebra
call, and drops targets as they converge (or restarts them from random
configurations when an attempt fails).  No history is kept.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any

import numpy as np

from robokin.chains.protocol import Chain
from robokin.motion._kernels import random_within_limits
from robokin.motion.ik.methods import IKMethod
from robokin.motion.ik.polish import polish as polish_rows
from robokin.motion.ik.problem import IKContext
from robokin.motion.ik.result import REASON_NAMES, IKBatchResult, Outcome
from robokin.motion.ik.settings import DEFAULTS, IKSettings, parse_settings
from robokin.motion.ik.stall import classify_stall, stall_check
from robokin.motion.pose_error import pose_error_unchecked

__all__ = ["solve_ik_batch"]


@dataclass
class AttemptRows:
    """The attempts in progress, one row each (a target may have several).

    Attributes
    ----------
    target : ndarray of int, shape (R,)
        Index of the target of each row.
    q : ndarray, shape (R, n)
        Current configuration.
    iteration : ndarray of int, shape (R,)
        Steps taken in this attempt.
    checkpoint, reference : ndarray, shape (R,)
        Iteration and best error norm of the last stall check.
    best_norm, best_q, best_error : ndarray, shapes (R,), (R, n), (R, 6)
        Best configuration of the attempt so far.
    """

    target: np.ndarray
    q: np.ndarray
    iteration: np.ndarray
    checkpoint: np.ndarray
    reference: np.ndarray
    best_norm: np.ndarray
    best_q: np.ndarray
    best_error: np.ndarray

    @classmethod
    def start(cls, targets: np.ndarray, q: np.ndarray) -> AttemptRows:
        """New attempts of ``targets`` (R,) from configurations ``q`` (R, n)."""
        R = targets.size
        return cls(targets, q, np.zeros(R, dtype=int), np.zeros(R, dtype=int), np.full(R, np.inf),
                   np.full(R, np.inf), q.copy(), np.zeros((R, 6)))

    def take(self, keep: np.ndarray) -> AttemptRows:
        """The rows selected by ``keep`` (bool or indices)."""
        return AttemptRows(*(getattr(self, f.name)[keep] for f in fields(self)))

    def extend(self, other: AttemptRows) -> AttemptRows:
        return AttemptRows(*(np.concatenate((getattr(self, f.name), getattr(other, f.name))) for f in fields(self)))


@dataclass
class TargetBest:
    """Per target (N): the best configuration over its attempts and how that attempt ended
    (``outcome``: :class:`~robokin.motion.ik.result.Outcome` codes)."""

    norm: np.ndarray
    q: np.ndarray
    error: np.ndarray
    outcome: np.ndarray
    success: np.ndarray
    attempts: np.ndarray
    iterations: np.ndarray

    @classmethod
    def start(cls, q_init: np.ndarray) -> TargetBest:
        N = q_init.shape[0]
        return cls(np.full(N, np.inf), q_init.copy(), np.zeros((N, 6)), np.full(N, Outcome.MAX_ITERATIONS),
                   np.zeros(N, dtype=bool), np.ones(N, dtype=int), np.zeros(N, dtype=int))

    def keep(self, targets: np.ndarray, norm: np.ndarray, q: np.ndarray, error: np.ndarray, outcome: Any) -> None:
        """Make the given configurations (one per entry of ``targets``) the targets' best."""
        self.norm[targets], self.q[targets], self.error[targets], self.outcome[targets] = norm, q, error, outcome

    def keep_better(self, rows: AttemptRows, index: np.ndarray, outcomes: np.ndarray) -> None:
        """The ended attempts ``index`` (in order): keep each one's best if it beats its target's."""
        for row, outcome in zip(index, outcomes):
            target = rows.target[row]
            if rows.best_norm[row] < self.norm[target]:
                self.keep(target, rows.best_norm[row], rows.best_q[row], rows.best_error[row], outcome)


def steps_within_limits(
    method: IKMethod, J: np.ndarray, e: np.ndarray, q: np.ndarray, ctx: IKContext
) -> np.ndarray:
    """Batched limit-aware step (see ``limit_aware_step`` in :mod:`~robokin.motion.ik.solve`).

    ``J`` (R, m, n), ``e`` (R, m), ``q`` (R, n) -> ``dq`` (R, n): joints resting
    on a limit and pushed outwards are frozen and the step recomputed.
    """
    dq = method.step(J, e, q, ctx)[0]
    blocked = ((q <= ctx.lower) & (dq < 0)) | ((q >= ctx.upper) & (dq > 0))
    some_blocked = np.flatnonzero(blocked.any(axis=1))
    if some_blocked.size:
        frozen = blocked[some_blocked]
        dq_free = method.step(np.where(frozen[:, None, :], 0.0, J[some_blocked]), e[some_blocked],
                              q[some_blocked], ctx)[0]
        dq[some_blocked] = np.where(frozen, 0.0, dq_free)
    return dq


def cap_steps(dq: np.ndarray, max_step: float | None) -> np.ndarray:
    """Scale the rows of ``dq`` (R, n) longer than ``max_step`` down to it (None: no cap)."""
    if max_step is None:
        return dq
    size = np.linalg.norm(dq, axis=1, keepdims=True)
    return dq * np.minimum(1.0, max_step / np.maximum(size, 1e-300))


def _errors(settings: IKSettings, rows: AttemptRows, T_goal: np.ndarray):
    """Pose errors (R, 6), their masked position and orientation norms, the flange poses and
    the tool Jacobians (R, 6, n) when the chain gives them from the same pass (else None)."""
    ctx = settings.ctx
    T_flange, T, J = ctx.poses_and_jacobians(rows.q)
    goal = T_goal[rows.target]
    e = pose_error_unchecked(T, goal[:, :3, :3], goal[:, :3, 3])
    if settings.is_position:
        e[:, 3:] = 0.0
    mask = ctx.mask
    position_error = np.linalg.norm(e[:, :3] * mask[:3].astype(float), axis=1)
    orientation_error = np.linalg.norm(e[:, 3:] * mask[3:].astype(float), axis=1)
    return e, position_error, orientation_error, T_flange, J


def _iterate(settings: IKSettings, rows: AttemptRows, best: TargetBest, T_goal: np.ndarray
             ) -> tuple[AttemptRows, np.ndarray]:
    """One iteration of every attempt in progress.

    Returns the rows that go on (stepped) and the indices of the targets
    whose attempts ended unsolved in this iteration.
    """
    ctx, method = settings.ctx, settings.method
    e, position_error, orientation_error, T_flange, J_rows = _errors(settings, rows, T_goal)
    norm = np.sqrt(position_error * position_error + orientation_error * orientation_error)
    fresh = rows.iteration == 0
    rows.reference[fresh] = norm[fresh]
    better = norm < rows.best_norm
    rows.best_norm[better], rows.best_q[better], rows.best_error[better] = norm[better], rows.q[better], e[better]
    converged = np.flatnonzero((position_error <= settings.tol_position)
                               & (orientation_error <= settings.tol_orientation))
    if converged.size:
        best.success[rows.target[converged]] = True
        best.keep(rows.target[converged], norm[converged], rows.q[converged], e[converged], Outcome.CONVERGED)
    alive = ~best.success[rows.target]  # drops every row of a solved target
    maxed = alive & (rows.iteration >= settings.max_iterations)
    going_on = -1  # not an Outcome: the attempt has not ended
    end_outcome = np.where(maxed, Outcome.MAX_ITERATIONS, going_on)
    go = np.zeros(rows.target.size, dtype=bool)
    running = np.flatnonzero(alive & ~maxed)
    new_q = rows.q
    if running.size:
        J = ctx.jacobian(rows.q[running], T_flange[running]) if J_rows is None else J_rows[running]
        J_task, e_task = (J, e[running]) if ctx.full_mask else (J[:, ctx.rows, :], e[running][:, ctx.rows])
        stalled, passed = stall_check(rows.iteration[running], rows.checkpoint[running], rows.reference[running],
                                      rows.best_norm[running], settings.stall_iterations, settings.stall_tolerance)
        if stalled.any():
            end_outcome[running[stalled]] = classify_stall(J_task[stalled], e_task[stalled], rows.q[running][stalled],
                                                           ctx.lower, ctx.upper, settings.gradient_tolerance)
        moved = running[passed]
        rows.checkpoint[moved], rows.reference[moved] = rows.iteration[moved], rows.best_norm[moved]
        keep = ~stalled
        stepping = running[keep]
        if stepping.size:
            q_stepping = rows.q[stepping]
            dq = cap_steps(steps_within_limits(method, J_task[keep], e_task[keep], q_stepping, ctx),
                           settings.max_step)
            new_q = rows.q.copy()
            new_q[stepping] = ctx.project(q_stepping + dq)
            go[stepping] = True
            np.add.at(best.iterations, rows.target[stepping], 1)
    ended = np.flatnonzero(end_outcome != going_on)
    best.keep_better(rows, ended, end_outcome[ended])
    rows.q = new_q
    going = rows.take(go)
    going.iteration += 1
    return going, rows.target[ended]


def _restart(settings: IKSettings, rows: AttemptRows, best: TargetBest, ended_targets: np.ndarray,
             rng: np.random.Generator) -> AttemptRows:
    """Targets whose attempts have all ended get new ones, several in parallel (1, 2, 6, 18, ...)."""
    restarts = settings.restarts
    if not (ended_targets.size and restarts):
        return rows
    live = np.bincount(rows.target, minlength=best.success.size)
    spawn = [t for t in np.unique(ended_targets)
             if live[t] == 0 and not best.success[t] and best.attempts[t] <= restarts]
    if not spawn:
        return rows
    spawning = np.array(spawn)
    count = np.minimum(restarts + 1 - best.attempts[spawning], 2 * best.attempts[spawning])
    best.attempts[spawning] += count
    targets = np.repeat(spawning, count)
    q = random_within_limits(rng, settings.ctx.lower, settings.ctx.upper, targets.size)
    return rows.extend(AttemptRows.start(targets, q))


def solve_ik_batch(
    chain: Chain,
    targets: Any,
    q0: Any = None,
    method: str | IKMethod = "lm",
    *,
    mask: Any = None,
    tool: Any = None,
    tol: float | tuple[float, float] = DEFAULTS["tol"],
    max_iterations: int | None = None,
    restarts: int = DEFAULTS["restarts"],
    seed: int | np.random.Generator | None = DEFAULTS["seed"],
    stall_iterations: int | None = DEFAULTS["stall_iterations"],
    stall_tolerance: float | None = DEFAULTS["stall_tolerance"],
    gradient_tolerance: float = DEFAULTS["gradient_tolerance"],
    max_step: float | None = None,
    wrap: bool | str | Any = "limits",
    polish: bool = True,
    **options: Any,
) -> IKBatchResult:
    r"""Solve the inverse kinematics for N targets at once (vectorised over targets).

    Parameters
    ----------
    chain : chain object
        As for :func:`~robokin.motion.solve_ik`; its ``fk``/``jacobian`` must
        accept a batch ``q`` of shape ``(N, n)``.
    targets : array_like, shape (N, 4, 4) or (N, 3)
        Goal poses or goal positions.
    q0 : array_like, shape (n,) or (N, n), optional
        Initial guess(es); default the middle of the joint limits.
    method, mask, tool, tol, max_iterations, restarts, seed, stall_iterations,
    stall_tolerance, gradient_tolerance, max_step, wrap, polish, **options
        As for :func:`~robokin.motion.solve_ik` (one mask/tool for all targets).

    Returns
    -------
    IKBatchResult
        Arrays over the targets: ``q`` (N, n), ``success`` (N,),
        ``iterations`` (N,), ``reason`` (N,) str, ``position_error`` (N,),
        ``orientation_error`` (N,), ``errors`` (N, 6), ``attempts`` (N,).

    Raises
    ------
    ShapeError, DomainError, TypeError
        As for :func:`~robokin.motion.solve_ik`; an empty batch ``(0, 3)`` /
        ``(0, 4, 4)`` is fine and gives empty results.

    Notes
    -----
    Each row of the working arrays is one attempt.  A target whose attempts
    have all failed gets new ones from random configurations *in parallel*
    (1, then 2, 6, 18, ... at a time, up to ``restarts`` in all), so the few
    hard targets finish in a handful of rounds instead of dragging the loop
    through ``restarts`` sequential attempts.  As soon as one attempt of a
    target converges, all its attempts stop.  Targets that fail every attempt
    are polished together (see ``polish`` in :func:`~robokin.motion.solve_ik`).

    The restart configurations are drawn from one generator in the order the
    failures occur, so results are reproducible for a given ``seed`` and
    batch but may differ from solving each target alone.
    """
    settings, T_goal, q_init = parse_settings(
        chain, targets, q0, method, options, batched=True, mask=mask, tool=tool, tol=tol,
        max_iterations=max_iterations, restarts=restarts, seed=seed, stall_iterations=stall_iterations,
        stall_tolerance=stall_tolerance, gradient_tolerance=gradient_tolerance, max_step=max_step,
        wrap=wrap, polish=polish)
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    best = TargetBest.start(q_init)
    rows = AttemptRows.start(np.arange(q_init.shape[0]), q_init)
    while rows.target.size:
        rows, ended_targets = _iterate(settings, rows, best, T_goal)
        rows = _restart(settings, rows, best, ended_targets, rng)
    return _batch_result(settings, best, T_goal)


def _batch_result(settings: IKSettings, best: TargetBest, T_goal: np.ndarray) -> IKBatchResult:
    failed = np.flatnonzero(~best.success)
    if settings.polish and failed.size:
        # as in solve_ik: polish the best attempt of every failed target
        q, e, converged, outcome, iterations = polish_rows(settings, best.q[failed], T_goal[failed])
        best.q[failed], best.error[failed], best.success[failed] = q, e, converged
        best.outcome[failed] = outcome
        best.iterations[failed] += iterations
    mask = settings.ctx.mask
    position_error = np.linalg.norm(best.error[:, :3] * mask[:3].astype(float), axis=1)
    orientation_error = np.linalg.norm(best.error[:, 3:] * mask[3:].astype(float), axis=1)
    ok = best.success & (position_error <= settings.tol_position) & (orientation_error <= settings.tol_orientation)
    # a converged attempt whose masked error is above the tolerance after all reports max_iterations
    outcome = np.where(ok, Outcome.CONVERGED,
                       np.where(best.outcome == Outcome.CONVERGED, Outcome.MAX_ITERATIONS, best.outcome))
    return IKBatchResult(
        q=best.q,
        success=ok,
        iterations=best.iterations,
        reason=REASON_NAMES[outcome],
        position_error=position_error,
        orientation_error=orientation_error,
        errors=best.error,
        attempts=best.attempts,
        method=settings.method.name,
    )
