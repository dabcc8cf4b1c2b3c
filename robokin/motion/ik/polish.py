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

from robokin.motion._kernels import pose_error_vector
from robokin.motion.ik.problem import IKContext
from robokin.motion.ik.settings import REFINE_STALL_TOLERANCE, IKSettings
from robokin.motion.ik.stall import STALL_REASONS, classify_stall

__all__ = ["polish", "POLISH_REASONS"]

#: Names of the codes returned by :func:`polish` (3: out of iterations).
POLISH_REASONS = (*STALL_REASONS, "max_iterations")


def _task(ctx: IKContext, q: np.ndarray, T_goal: np.ndarray, is_position: bool):
    T_flange, T = ctx.pose(q)
    e = pose_error_vector(T, T_goal)
    if is_position:
        e[:, 3:] = 0.0
    te = e if ctx.full_mask else e[:, ctx.rows]
    return T_flange, e, te


def polish(
    settings: IKSettings, q: np.ndarray, T_goal: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Polish rows ``q`` (N, n) towards ``T_goal`` (N, 4, 4).

    Uses the tolerances, ``max_iterations``, ``stall_iterations`` (window of
    the stationarity test, with the relative decrease
    :data:`~robokin.motion.ik.settings.REFINE_STALL_TOLERANCE`) and
    ``gradient_tolerance`` of ``settings``.

    Returns ``(q, e (N, 6), converged (N,), code (N,), iterations (N,))``,
    ``code`` as in :func:`classify_stall` (0 stalled, 1 unreachable,
    2 joint_limits) or 3 for max_iterations (names in :data:`POLISH_REASONS`).
    """
    ctx, is_position = settings.ctx, settings.is_position
    tol = (settings.tol_position, settings.tol_orientation)
    max_iterations, window = settings.max_iterations, settings.stall_iterations
    min_decrease, gtol = REFINE_STALL_TOLERANCE, settings.gradient_tolerance
    N, n = q.shape
    lower, upper = ctx.lower, ctx.upper
    tol_p, tol_o = tol
    m = ctx.mask
    q = q.copy()
    T_flange, e, te = _task(ctx, q, T_goal, is_position)
    f = 0.5 * np.sum(te * te, axis=1)
    J = ctx.jacobian(q, T_flange)
    Jt = J if ctx.full_mask else J[:, ctx.rows, :]
    mu = np.full(N, 1e-3)
    ref = f.copy()
    since = np.zeros(N, dtype=int)
    its = np.zeros(N, dtype=int)
    code = np.full(N, 3)
    conv = np.zeros(N, dtype=bool)
    active = np.ones(N, dtype=bool)
    eye = np.eye(n)
    for _ in range(max_iterations * 4):  # accepted + rejected trials
        pe = np.linalg.norm(e[:, :3] * m[:3], axis=1)
        oe = np.linalg.norm(e[:, 3:] * m[3:], axis=1)
        newly = active & (pe <= tol_p) & (oe <= tol_o)
        conv |= newly
        active &= ~newly
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        Ja, ea, qa = Jt[idx], te[idx], q[idx]
        g = (np.swapaxes(Ja, 1, 2) @ ea[:, :, None])[:, :, 0]
        blocked = ((qa <= lower) & (g < 0)) | ((qa >= upper) & (g > 0))
        Jf = np.where(blocked[:, None, :], 0.0, Ja)
        gf = np.where(blocked, 0.0, g)
        JtJ = np.swapaxes(Jf, 1, 2) @ Jf
        scale = np.maximum(np.einsum("kii->k", JtJ) / n, 1e-12)
        A = JtJ + (mu[idx] * scale)[:, None, None] * eye
        dq = np.linalg.solve(A, gf[:, :, None])[:, :, 0]
        q_try = ctx.project(qa + dq)
        Tf_try, e_try, te_try = _task(ctx, q_try, T_goal[idx], is_position)
        f_try = 0.5 * np.sum(te_try * te_try, axis=1)
        ok = f_try < f[idx]
        acc = idx[ok]
        rej = idx[~ok]
        mu[rej] *= 8.0
        if acc.size:
            mu[acc] = np.maximum(mu[acc] / 3.0, 1e-9)
            q[acc] = q_try[ok]
            e[acc] = e_try[ok]
            te[acc] = te_try[ok]
            f[acc] = f_try[ok]
            Jn = ctx.jacobian(q_try[ok], Tf_try[ok])
            Jt[acc] = Jn if ctx.full_mask else Jn[:, ctx.rows, :]
            its[acc] += 1
            since[acc] += 1
        # stationary: no relative decrease of min_decrease over `window` accepted
        # steps, or the damping exploded (no descent possible)
        done_win = active & (since >= window)
        stuck = done_win & (f > (1.0 - min_decrease) ** 2 * ref)
        ref = np.where(done_win & ~stuck, f, ref)
        since = np.where(done_win & ~stuck, 0, since)
        stuck |= active & (mu > 1e8)
        stuck |= active & (its >= max_iterations)
        if stuck.any():
            s = np.flatnonzero(stuck)
            codes = classify_stall(Jt[s], te[s], q[s], lower, upper, gtol)
            codes = np.where(mu[s] > 1e8, np.where(codes == 0, 1, codes), codes)
            code[s] = np.where(its[s] >= max_iterations, 3, codes)
            active[s] = False
    code[conv] = -1
    return q, e, conv, code, its
