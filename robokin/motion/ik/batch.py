r"""Many-target inverse kinematics: :func:`solve_ik_batch`.

The same algorithm as :func:`~robokin.motion.solve_ik`, vectorised over the
targets: each iteration evaluates the chain's batched ``fk``/``jacobian`` on
all targets still working, computes every step with one batched linear-algebra
call, and drops targets as they converge (or restarts them from random
configurations when an attempt fails).  No history is kept.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.motion._kernels import pose_error_vector, random_within_limits
from robokin.motion.ik.methods import IKMethod, make_method
from robokin.motion.ik.problem import (
    check_nonnegative_int,
    make_context,
    parse_mask,
    parse_q0,
    parse_stall,
    parse_target,
    parse_tolerance,
)
from robokin.motion.ik.result import IKBatchResult
from robokin.motion.ik.polish import polish as polish_rows
from robokin.motion.ik.solve import DEFAULTS, REFINE_STALL_TOLERANCE, classify_stall
from robokin.validation import check_chain, check_positive

__all__ = ["solve_ik_batch"]

_REASON_NAMES = np.array(["stalled", "unreachable", "joint_limits", "max_iterations", "converged"])
_STALLED, _UNREACHABLE, _JOINT_LIMITS, _MAX_IT, _CONVERGED = range(5)


def solve_ik_batch(
    chain: Any,
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
    check_chain(chain)
    T_goal, is_position = parse_target(targets, batched=True)
    N = T_goal.shape[0]
    m = parse_mask(mask, is_position)
    ctx = make_context(chain, m, tool, wrap)
    n = ctx.n
    tol_p, tol_o = parse_tolerance(tol)
    meth = make_method(method, options)
    max_it = meth.default_max_iterations if max_iterations is None else check_nonnegative_int(
        max_iterations, "max_iterations", 1)
    restarts = check_nonnegative_int(restarts, "restarts")
    stall_iterations, stall_tolerance = parse_stall(meth, stall_iterations, stall_tolerance)
    gtol = check_positive(gradient_tolerance, "gradient_tolerance", scalar=True)
    if max_step is not None:
        max_step = check_positive(max_step, "max_step", scalar=True)
    q_init = parse_q0(q0, n, ctx.lower, ctx.upper, N).copy()
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    lower, upper, rows, full = ctx.lower, ctx.upper, ctx.rows, ctx.full_mask
    m_pos = m[:3].astype(float)
    m_ori = m[3:].astype(float)

    # per target
    best_norm = np.full(N, np.inf)
    best_q = q_init.copy()
    best_e = np.zeros((N, 6))
    best_reason = np.full(N, _MAX_IT)
    success = np.zeros(N, dtype=bool)
    attempts = np.ones(N, dtype=int)
    total_it = np.zeros(N, dtype=int)
    # per row (one row = one attempt in progress; a target may have several)
    r_t = np.arange(N)
    r_q = q_init
    r_it = np.zeros(N, dtype=int)
    r_ck = np.zeros(N, dtype=int)
    r_ckn = np.full(N, np.inf)
    r_bn = np.full(N, np.inf)
    r_bq = q_init.copy()
    r_be = np.zeros((N, 6))

    while r_t.size:
        T_flange, T = ctx.pose(r_q)
        e = pose_error_vector(T, T_goal[r_t])
        if is_position:
            e[:, 3:] = 0.0
        pe = np.linalg.norm(e[:, :3] * m_pos, axis=1)
        oe = np.linalg.norm(e[:, 3:] * m_ori, axis=1)
        task_e = e if full else e[:, rows]
        norm = np.sqrt(pe * pe + oe * oe)
        fresh = r_it == 0
        r_ckn[fresh] = norm[fresh]
        better = norm < r_bn
        r_bn[better] = norm[better]
        r_bq[better] = r_q[better]
        r_be[better] = e[better]

        conv = (pe <= tol_p) & (oe <= tol_o)
        if conv.any():
            ci = np.flatnonzero(conv)
            tc = r_t[ci]
            success[tc] = True
            best_norm[tc] = norm[ci]
            best_q[tc] = r_q[ci]
            best_e[tc] = e[ci]
            best_reason[tc] = _CONVERGED
        alive = ~success[r_t]  # drops every row of a solved target
        maxed = alive & (r_it >= max_it)
        rest = alive & ~maxed
        end_code = np.where(maxed, _MAX_IT, -1)
        go = np.zeros(r_t.size, dtype=bool)
        new_q = r_q
        if rest.any():
            ri = np.flatnonzero(rest)
            qr = r_q[ri]
            J = ctx.jacobian(qr, T_flange[ri])
            Jt = J if full else J[:, rows, :]
            er = task_e[ri]
            # stall: every stall_iterations steps the best error must have
            # dropped by the fraction stall_tolerance
            check = (r_it[ri] - r_ck[ri]) >= stall_iterations
            stalled = check & (r_bn[ri] > (1.0 - stall_tolerance) * r_ckn[ri])
            if stalled.any():
                end_code[ri[stalled]] = classify_stall(Jt[stalled], er[stalled], qr[stalled], lower, upper, gtol)
            moved = ri[check & ~stalled]
            r_ck[moved] = r_it[moved]
            r_ckn[moved] = r_bn[moved]
            keep = ~stalled
            gi = ri[keep]
            if gi.size:
                qg, Jg, eg = qr[keep], Jt[keep], er[keep]
                dq, _ = meth.step(Jg, eg, qg, ctx)
                # limit-aware step (see solve_ik): freeze joints pushed through a limit
                blocked = ((qg <= lower) & (dq < 0)) | ((qg >= upper) & (dq > 0))
                rb = np.flatnonzero(blocked.any(axis=1))
                if rb.size:
                    bl = blocked[rb]
                    dq_b, _ = meth.step(np.where(bl[:, None, :], 0.0, Jg[rb]), eg[rb], qg[rb], ctx)
                    dq[rb] = np.where(bl, 0.0, dq_b)
                if max_step is not None:
                    s = np.linalg.norm(dq, axis=1, keepdims=True)
                    dq = dq * np.minimum(1.0, max_step / np.maximum(s, 1e-300))
                new_q = r_q.copy()
                new_q[gi] = ctx.project(qg + dq)
                go[gi] = True
                np.add.at(total_it, r_t[gi], 1)

        # attempts that ended without converging: keep their best, maybe restart
        ended = np.flatnonzero(end_code >= 0)
        spawn_targets: list[int] = []
        for k in ended:
            t = r_t[k]
            if r_bn[k] < best_norm[t]:
                best_norm[t] = r_bn[k]
                best_q[t] = r_bq[k]
                best_e[t] = r_be[k]
                best_reason[t] = end_code[k]
        ended_targets = r_t[ended]
        r_t, r_q, r_it = r_t[go], new_q[go], r_it[go] + 1
        r_ck, r_ckn, r_bn, r_bq, r_be = r_ck[go], r_ckn[go], r_bn[go], r_bq[go], r_be[go]
        if ended.size and restarts:
            # a target whose attempts have all ended gets new ones from random
            # configurations, several in parallel (1, 2, 6, 18, ... at a time)
            live = np.bincount(r_t, minlength=N)
            spawn_targets = [t for t in np.unique(ended_targets)
                             if live[t] == 0 and not success[t] and attempts[t] <= restarts]
        if spawn_targets:
            st = np.array(spawn_targets)
            count = np.minimum(restarts + 1 - attempts[st], 2 * attempts[st])
            attempts[st] += count
            nt = np.repeat(st, count)
            nq = random_within_limits(rng, lower, upper, nt.size)
            z = np.zeros(nt.size, dtype=int)
            r_t = np.concatenate((r_t, nt))
            r_q = np.concatenate((r_q, nq))
            r_it = np.concatenate((r_it, z))
            r_ck = np.concatenate((r_ck, z))
            r_ckn = np.concatenate((r_ckn, np.full(nt.size, np.inf)))
            r_bn = np.concatenate((r_bn, np.full(nt.size, np.inf)))
            r_bq = np.concatenate((r_bq, nq))
            r_be = np.concatenate((r_be, np.zeros((nt.size, 6))))

    failed = np.flatnonzero(~success)
    if polish and failed.size:
        # as in solve_ik: polish the best attempt of every failed target
        qp, ep_, conv, code, its = polish_rows(
            ctx, best_q[failed], T_goal[failed], is_position, (tol_p, tol_o), max_it,
            stall_iterations, REFINE_STALL_TOLERANCE, gtol)
        best_q[failed] = qp
        best_e[failed] = ep_
        success[failed] = conv
        best_reason[failed] = np.where(conv, _CONVERGED, np.where(code == 3, _MAX_IT, code))
        total_it[failed] += its
    pe = np.linalg.norm(best_e[:, :3] * m_pos, axis=1)
    oe = np.linalg.norm(best_e[:, 3:] * m_ori, axis=1)
    ok = success & (pe <= tol_p) & (oe <= tol_o)
    reason = _REASON_NAMES[best_reason]
    reason = np.where(ok, "converged", np.where(best_reason == _CONVERGED, "max_iterations", reason))
    return IKBatchResult(
        q=best_q,
        success=ok,
        iterations=total_it,
        reason=reason,
        position_error=pe,
        orientation_error=oe,
        errors=best_e,
        attempts=attempts,
        method=meth.name,
    )
