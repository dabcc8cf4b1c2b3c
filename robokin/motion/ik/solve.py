r"""Single-target inverse kinematics: :func:`solve_ik`.

The loop is the closed-loop IK scheme of Siciliano et al. (2009, §3.7): at
configuration :math:`q_k` compute the pose error :math:`e_k` and the Jacobian
:math:`J_k`, take the step :math:`\Delta q_k` of the chosen method, clamp to
the joint limits, repeat.  It is written plainly (one configuration at a time,
every iteration recorded); :func:`~robokin.motion.solve_ik_batch` is the
vectorised twin for many targets.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokin.motion._kernels import pose_error_single, random_within_limits
from robokin.motion.ik.methods import IKMethod, make_method
from robokin.motion.ik.polish import polish as polish_rows
from robokin.motion.ik.problem import (
    check_nonnegative_int,
    make_context,
    parse_mask,
    parse_q0,
    parse_stall,
    parse_target,
    parse_tolerance,
)
from robokin.motion.ik.result import IKHistory, IKResult
from robokin.validation import check_chain, check_positive

__all__ = ["solve_ik", "classify_stall", "DEFAULTS"]

#: Default stopping parameters shared by :func:`solve_ik` and :func:`solve_ik_batch`.
DEFAULTS = {
    "tol": 1e-6,
    "restarts": 20,
    "seed": 0,
    "stall_iterations": None,
    "stall_tolerance": None,
    "gradient_tolerance": 1e-2,
}

_LIMIT_EPS = 1e-12
#: Stall tolerance of the final polishing run after all attempts failed.
REFINE_STALL_TOLERANCE = 1e-3


def classify_stall(
    J: np.ndarray, e: np.ndarray, q: np.ndarray, lower: np.ndarray, upper: np.ndarray, gtol: float
) -> np.ndarray:
    r"""Why did the error stop decreasing? Codes 0 = stalled, 1 = unreachable, 2 = joint_limits.

    With :math:`g = J^T e` (the steepest-descent direction of
    :math:`\tfrac12\|e\|^2`) and :math:`g_p` the same with the components that
    push a joint through an active limit removed:

    - ``unreachable``: :math:`\|g\| \le` ``gtol`` :math:`\|J\|_F\|e\|` — a
      stationary point of the error with :math:`e \ne 0` (a least-squares
      "closest" configuration: the target is out of reach, or a local minimum);
    - ``joint_limits``: :math:`\|g_p\|` is that small but :math:`\|g\|` is not —
      the limits block the only descent directions;
    - ``stalled``: otherwise (slow progress, e.g. near a singularity).

    Broadcasts over a leading batch axis.
    """
    g = (np.swapaxes(J, -1, -2) @ e[..., None])[..., 0]
    at_lo = q <= lower + _LIMIT_EPS
    at_hi = q >= upper - _LIMIT_EPS
    blocked = (at_lo & (g < 0)) | (at_hi & (g > 0))
    gp = np.where(blocked, 0.0, g)
    scale = gtol * np.linalg.norm(J, axis=(-2, -1)) * np.linalg.norm(e, axis=-1)
    g_small = np.linalg.norm(g, axis=-1) <= scale
    gp_small = np.linalg.norm(gp, axis=-1) <= scale
    return np.where(g_small, 1, np.where(gp_small, 2, 0))


_STALL_REASONS = ("stalled", "unreachable", "joint_limits")
_POLISH_REASONS = ("stalled", "unreachable", "joint_limits", "max_iterations")


def solve_ik(
    chain: Any,
    target: Any,
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
    record_history: bool = True,
    **options: Any,
) -> IKResult:
    r"""Solve the inverse kinematics of a serial chain for one target.

    Iterates :math:`q_{k+1} = \mathrm{clamp}(q_k + \Delta q_k)` where
    :math:`\Delta q_k` is the step of ``method`` computed from the geometric
    Jacobian :math:`J(q_k)` (rows ``[v; ω]``, base frame) and the pose error

    .. math::
        e = \begin{bmatrix} p_{goal} - p(q) \\ \theta h \end{bmatrix}, \qquad
        \theta h = \log\!\left(R_{goal} R(q)^T\right)

    (position error and angle–axis orientation error in the base frame,
    Siciliano et al. 2009 §3.7.3).  Only the components selected by ``mask``
    are controlled.

    Parameters
    ----------
    chain : chain object
        Offers ``n``, ``limits`` (n, 2), ``fk(q, check=False)`` and
        ``jacobian(q, check=False)``.
    target : array_like, shape (4, 4) or (3,)
        Goal pose ``T_base_goal`` or goal position (m) of the (tool) frame.
    q0 : array_like, shape (n,), optional
        Initial guess (clamped to the limits).  Default: the middle of the
        joint limits (0 for unlimited joints).
    method : str or IKMethod, optional
        ``"lm"`` (default: Levenberg–Marquardt, Sugihara 2011), ``"pinv"``,
        ``"transpose"``, ``"weighted"``, ``"dls"``, ``"nullspace"`` or a method
        object from :mod:`robokin.motion.ik.methods`.
    mask : array_like of 6 bool, optional
        Controlled components ``[x, y, z, rx, ry, rz]`` (default: all six for a
        pose, the position for a position target).
    tool : array_like, shape (4, 4), optional
        Tool transform ``T_flange_tool`` applied after the chain's end-effector;
        the target then refers to the tool frame.
    tol : float or (float, float), optional
        Tolerance on the position error (m) and the orientation error (rad);
        a scalar sets both (default 1e-6 m and 1e-6 rad).  Success means both
        norms are within it.
    max_iterations : int, optional
        Steps per attempt (default: the method's, 100 for most, 1000 for
        ``"transpose"``).
    restarts : int, optional
        Extra attempts from random configurations (uniform within the limits,
        drawn from ``seed``) after an attempt fails.  Default 20; 0 disables.
    seed : int, Generator or None, optional
        Seed of the restarts (default 0: reproducible).
    stall_iterations, stall_tolerance : int, float, optional
        An attempt *stalls* when its best task error norm has not dropped by
        the fraction ``stall_tolerance`` over ``stall_iterations`` steps
        (checked every ``stall_iterations`` steps).  Default: the method's
        (10 steps and one half for the Newton-type methods, which converge
        much faster than that; 50 steps and 0.2 for ``"transpose"``).
    gradient_tolerance : float, optional
        Threshold used to label a stall ``"unreachable"`` or
        ``"joint_limits"`` (see :func:`classify_stall`).
    max_step : float, optional
        Cap on the joint step norm per iteration (rad or m).
    wrap : {"limits", True, False} or array_like of bool (n,), optional
        Angle handling for revolute joints.  ``"limits"`` (default): a joint
        that would leave its range re-enters it by ``±2 pi`` when that lands
        inside (the same pose; matters for ranges of 2 pi or more, e.g. the
        UR10's ±2 pi), otherwise it is clamped.  ``True``: wrap every revolute
        angle into (-pi, pi] after each step (continuous joints).  ``False``:
        clamp only.  Booleans: wrap the selected joints.
    polish : bool, optional
        If every attempt fails, continue from the best configuration with a
        monotone Levenberg–Marquardt iteration (:mod:`~robokin.motion.ik.polish`)
        until the error stops decreasing: the answer is then the locally
        closest configuration and ``reason`` tells why (default True; its
        iterations are counted and, in the history, only its end point is
        recorded, as attempt ``attempts``).  Set False to see a method alone.
    record_history : bool, optional
        Keep the per-iteration :class:`IKHistory` (default True).
    **options
        Options of a named method, e.g. ``damping=0.1`` for ``"dls"``,
        ``weights=...`` for ``"weighted"``, ``objective=...`` for ``"nullspace"``.

    Returns
    -------
    IKResult
        ``q`` (best configuration found), ``success``, ``iterations``,
        ``reason`` (``"converged"``, ``"max_iterations"``, ``"stalled"``,
        ``"unreachable"``, ``"joint_limits"``), final ``position_error``,
        ``orientation_error``, ``errors`` (6,) and ``history``.  Never raises on
        failure; ``success`` is never True with an error above ``tol``.

    Raises
    ------
    ShapeError, DomainError
        Bad target, ``q0``, ``mask``, ``tool``, tolerances or method options
        (both are ``ValueError``); the message names the argument. A target or
        tool translation beyond 1e100 m is rejected (its squared error would
        overflow float64).
    TypeError
        ``chain`` is not a kinematic chain (e.g. ``None``), or an argument of
        the wrong type.

    Notes
    -----
    Joint limits are enforced after every step: a joint resting on a limit
    and pushed outwards is frozen (its Jacobian column removed and the step
    recomputed), the others are clamped (or re-enter by ``±2 pi``, see
    ``wrap``), so every configuration visited, and the answer, lie within the
    limits.

    How a failure is labelled: an attempt ends when it *stalls* (see
    ``stall_iterations``) or runs out of iterations; then the next restart
    begins.  When all attempts failed, the best configuration is polished
    (``polish``) until the error stops decreasing, and the reason is decided
    there by :func:`classify_stall` from the gradient :math:`g = J^T e` of
    :math:`\tfrac12\|e\|^2`: ``"unreachable"`` if :math:`\|g\| \le`
    ``gradient_tolerance`` :math:`\|J\|_F\|e\|` (a stationary point with a
    nonzero error: out of reach, or a local minimum), ``"joint_limits"`` if
    only the limits block the descent directions, ``"stalled"`` otherwise;
    ``"max_iterations"`` if the budget ran out first.

    References
    ----------
    Siciliano et al., *Robotics: Modelling, Planning and Control*, 2009, §3.7.
    Buss, "Introduction to inverse kinematics with Jacobian transpose,
    pseudoinverse and damped least squares methods", 2004.
    Sugihara, "Solvability-unconcerned inverse kinematics by the
    Levenberg–Marquardt method", IEEE T-RO 27(5), 2011.

    Examples
    --------
    >>> from robokin.models import planar_two_link   # doctest: +SKIP
    >>> res = solve_ik(planar_two_link(), [1.2, 0.5, 0.0])  # doctest: +SKIP
    >>> res.success, res.reason                               # doctest: +SKIP
    (True, 'converged')
    """
    check_chain(chain)
    T_goal, is_position = parse_target(target, batched=False)
    m = parse_mask(mask, is_position)
    ctx = make_context(chain, m, tool, wrap)
    tol_p, tol_o = parse_tolerance(tol)
    meth = make_method(method, options)
    max_it = meth.default_max_iterations if max_iterations is None else check_nonnegative_int(
        max_iterations, "max_iterations", 1)
    restarts = check_nonnegative_int(restarts, "restarts")
    stall_iterations, stall_tolerance = parse_stall(meth, stall_iterations, stall_tolerance)
    gtol = check_positive(gradient_tolerance, "gradient_tolerance", scalar=True)
    if max_step is not None:
        max_step = check_positive(max_step, "max_step", scalar=True)
    q_start = parse_q0(q0, ctx.n, ctx.lower, ctx.upper, None)
    if seed is not None and not isinstance(seed, (np.random.Generator, int, np.integer)):
        raise TypeError(f"seed must be an int, a numpy Generator or None; got {type(seed).__name__}")
    rng = seed if isinstance(seed, np.random.Generator) else None  # created on the first restart

    lower, upper, rows, full = ctx.lower, ctx.upper, ctx.rows, ctx.full_mask
    mp, mo = [float(x) for x in m[:3]], [float(x) for x in m[3:]]
    pos_rows = bool(m[:3].all())
    g_pos = T_goal[:3, 3].tolist()
    wrap_any = ctx.wrap is not None

    hist_q: list[np.ndarray] = []
    hist_e: list[np.ndarray] = []
    hist_J: list[np.ndarray] = []
    hist_lam: list[float] = []
    hist_step: list[float] = []
    hist_att: list[int] = []

    best: tuple[float, np.ndarray, np.ndarray, str] = (np.inf, q_start, np.zeros(6), "max_iterations")
    total_iterations = 0
    attempts = 0
    success = False
    stall_k, stall_f = stall_iterations, stall_tolerance
    for attempt in range(restarts + 1):
        attempts += 1
        if attempt == 0:
            q = q_start
        else:
            if rng is None:
                rng = np.random.default_rng(seed)
            q = random_within_limits(rng, lower, upper, 1)[0]
        checkpoint, checkpoint_norm = 0, np.inf  # for stall detection
        attempt_best: tuple[float, np.ndarray, np.ndarray] = (np.inf, q, np.zeros(6))
        it = 0
        on_limit = bool(np.any((q <= lower) | (q >= upper)))
        while True:
            T_flange, T = ctx.pose(q)
            if is_position:
                p = T[:3, 3].tolist()
                e = np.array((g_pos[0] - p[0], g_pos[1] - p[1], g_pos[2] - p[2], 0.0, 0.0, 0.0))
            else:
                e = pose_error_single(T, T_goal)
            ex, ey, ez, rx, ry, rz = e.tolist()
            if pos_rows:
                pe = math.sqrt(ex * ex + ey * ey + ez * ez)
            else:
                pe = math.sqrt(mp[0] * ex * ex + mp[1] * ey * ey + mp[2] * ez * ez)
            oe = math.sqrt(mo[0] * rx * rx + mo[1] * ry * ry + mo[2] * rz * rz)
            converged = pe <= tol_p and oe <= tol_o
            J = None
            if record_history or not converged:
                J = ctx.jacobian(q, T_flange)
            if record_history:
                hist_q.append(q)
                hist_e.append(e)
                hist_J.append(J)
                hist_att.append(attempt)
            if full:
                task_e = e
                norm = math.sqrt(pe * pe + oe * oe)
            else:
                task_e = e[rows]
                norm = math.sqrt(pe * pe + oe * oe)
            if it == 0:
                checkpoint_norm = norm
            if norm < attempt_best[0] or converged:
                attempt_best = (norm, q, e)
            if converged:
                reason = "converged"
                success = True
                break
            if it >= max_it:
                reason = "max_iterations"
                break
            Jt = J if full else J[rows]
            if it - checkpoint >= stall_k:
                # stalled: the best error did not drop by the fraction stall_tolerance
                if attempt_best[0] > (1.0 - stall_f) * checkpoint_norm:
                    reason = _STALL_REASONS[int(classify_stall(Jt, task_e, q, lower, upper, gtol))]
                    break
                checkpoint, checkpoint_norm = it, attempt_best[0]
            dq, lam = meth.step(Jt, task_e, q, ctx)
            if on_limit:
                # limit-aware step: joints resting on a limit and pushed outwards
                # are frozen (their Jacobian columns removed), the step recomputed
                blocked = ((q <= lower) & (dq < 0)) | ((q >= upper) & (dq > 0))
                if blocked.any():
                    dq, lam = meth.step(np.where(blocked, 0.0, Jt), task_e, q, ctx)
                    dq = np.where(blocked, 0.0, dq)
            if max_step is not None:
                s = math.sqrt(float(dq @ dq))
                if s > max_step:
                    dq = dq * (max_step / s)
            q_new = q + dq
            if wrap_any or ((q_new < lower) | (q_new > upper)).any():
                q_new = ctx.project(q_new)
                on_limit = bool(np.any((q_new <= lower) | (q_new >= upper)))
            else:
                on_limit = False
            if record_history:
                hist_lam.append(float(np.asarray(lam)))
                d = q_new - q
                hist_step.append(math.sqrt(float(d @ d)))
            q = q_new
            it += 1
        if record_history:
            hist_lam.append(0.0)
            hist_step.append(0.0)
        total_iterations += it
        if success or attempt_best[0] < best[0]:
            best = (attempt_best[0], attempt_best[1], attempt_best[2], reason)
        if success:
            break

    norm, q_best, e_best, reason = best
    if not success and polish:
        # every attempt failed: polish the best one (monotone LM) so that the
        # answer is the locally closest configuration and the reason says why
        qp, ep_, conv, code, its = polish_rows(
            ctx, q_best[None, :], T_goal[None], is_position, (tol_p, tol_o), max_it,
            stall_k, REFINE_STALL_TOLERANCE, gtol)
        total_iterations += int(its[0])
        q_best, e_best = qp[0], ep_[0]
        success = bool(conv[0])
        reason = "converged" if success else _POLISH_REASONS[int(code[0])]
        if record_history:
            T_flange, _ = ctx.pose(q_best)
            hist_q.append(q_best)
            hist_e.append(e_best)
            hist_J.append(ctx.jacobian(q_best, T_flange))
            hist_att.append(attempts)
            hist_lam.append(0.0)
            hist_step.append(0.0)
    ep = e_best[:3] * m[:3]
    eo = e_best[3:] * m[3:]
    pe = float(np.linalg.norm(ep))
    oe = float(np.linalg.norm(eo))
    ok = bool(success and pe <= tol_p and oe <= tol_o)
    history = None
    if record_history:
        history = IKHistory(
            q=np.array(hist_q),
            error=np.array(hist_e),
            jacobian=np.array(hist_J),
            damping=np.array(hist_lam),
            step_size=np.array(hist_step),
            attempt=np.array(hist_att, dtype=int),
            mask=m,
            limits=np.column_stack((lower, upper)),
        )
    return IKResult(
        q=np.array(q_best, copy=True),
        success=ok,
        iterations=total_iterations,
        reason=reason if not ok else "converged",
        position_error=pe,
        orientation_error=oe,
        errors=np.array(e_best, copy=True),
        attempts=attempts,
        history=history,
        method=meth.name,
    )
