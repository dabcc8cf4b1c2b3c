r"""Single-target inverse kinematics: :func:`solve_ik` and :func:`solve_ik_once`.

The algorithm is the closed-loop IK scheme of Siciliano et al. (2009, §3.7),
the Newton–Raphson iteration of Lynch & Park (2017, §6.2.2): at configuration
:math:`q_k` compute the pose error :math:`e_k` and the Jacobian :math:`J_k`,
take the step :math:`\Delta q_k` of the chosen method, bring :math:`q_k +
\Delta q_k` back within the joint limits, repeat.  :func:`run_attempt` is
that loop; :func:`solve_ik` adds random restarts and the final LM polish;
:func:`~robokin.motion.solve_ik_batch` is the vectorised twin for many targets.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from robokin.chains.protocol import Chain
from robokin.motion._kernels import random_within_limits
from robokin.motion.ik.methods import IKMethod, StepResult
from robokin.motion.ik.polish import polish
from robokin.motion.ik.problem import IKContext
from robokin.motion.ik.result import IKHistory, IKResult, Outcome
from robokin.motion.ik.settings import DEFAULTS, IKSettings, parse_settings
from robokin.motion.ik.stall import StallWatch, classify_stall
from robokin.motion.pose_error import pose_error_unchecked

__all__ = ["solve_ik", "solve_ik_once", "run_attempt", "classify_stall", "DEFAULTS"]


class Goal:
    """The target of one solve and how far a pose is from it (plain floats: runs every iteration).

    Parameters
    ----------
    T_goal : ndarray, shape (4, 4)
        Goal pose (identity rotation for a position target).
    settings : IKSettings
        For the task mask and whether the target is a position.
    """

    __slots__ = ("T", "R", "position", "is_position", "full_mask", "mask_position", "mask_orientation")

    def __init__(self, T_goal: np.ndarray, settings: IKSettings) -> None:
        self.T = T_goal
        self.R = np.ascontiguousarray(T_goal[:3, :3])
        self.position = T_goal[:3, 3].tolist()
        self.is_position = settings.is_position
        mask = settings.ctx.mask_list
        self.full_mask = settings.ctx.full_mask
        self.mask_position, self.mask_orientation = mask[:3], mask[3:]

    def error(self, T: np.ndarray) -> tuple[np.ndarray, float, float]:
        """Error ``[p_goal - p; theta h]`` (6,) of pose ``T`` and its masked position and orientation norms."""
        if self.is_position:  # no orientation to reach
            p, g = T[:3, 3].tolist(), self.position
            ex, ey, ez = g[0] - p[0], g[1] - p[1], g[2] - p[2]
            rx = ry = rz = 0.0
        else:
            ex, ey, ez, rx, ry, rz = pose_error_unchecked(T, self.R, self.position)
        if self.full_mask:  # the same bits as the masked sums below, whose factors are all 1.0
            position_error = math.sqrt(ex * ex + ey * ey + ez * ez)
            orientation_error = math.sqrt(rx * rx + ry * ry + rz * rz)
        else:
            mp, mo = self.mask_position, self.mask_orientation
            position_error = math.sqrt(mp[0] * ex * ex + mp[1] * ey * ey + mp[2] * ez * ez)
            orientation_error = math.sqrt(mo[0] * rx * rx + mo[1] * ry * ry + mo[2] * rz * rz)
        return np.array((ex, ey, ez, rx, ry, rz)), position_error, orientation_error


class HistoryRecorder:
    """Collects the rows of an :class:`IKHistory` while the attempts run."""

    def __init__(self) -> None:
        self.q: list[np.ndarray] = []
        self.error: list[np.ndarray] = []
        self.jacobian: list[np.ndarray] = []
        self.attempt: list[int] = []
        self.damping: list[float] = []
        self.step_size: list[float] = []

    def add_point(self, q: np.ndarray, e: np.ndarray, J: np.ndarray, attempt: int) -> None:
        """One evaluated configuration: ``q`` (n,), its error (6,) and Jacobian (6, n)."""
        self.q.append(q)
        self.error.append(e)
        self.jacobian.append(J)
        self.attempt.append(attempt)

    def add_step(self, damping: float | np.ndarray, q: np.ndarray, q_new: np.ndarray) -> None:
        """The step taken from the last point: its damping and its length ``||q_new - q||``."""
        self.damping.append(float(np.asarray(damping)))
        d = q_new - q
        self.step_size.append(math.sqrt(float(d @ d)))

    def end_attempt(self) -> None:
        """The last point of an attempt takes no step."""
        self.damping.append(0.0)
        self.step_size.append(0.0)

    def history(self, ctx: IKContext) -> IKHistory:
        return IKHistory(
            q=np.array(self.q),
            error=np.array(self.error),
            jacobian=np.array(self.jacobian),
            damping=np.array(self.damping),
            step_size=np.array(self.step_size),
            attempt=np.array(self.attempt, dtype=int),
            mask=ctx.mask,
            limits=np.column_stack((ctx.lower, ctx.upper)),
        )


def limit_aware_step(
    method: IKMethod, J: np.ndarray, e: np.ndarray, q: np.ndarray, ctx: IKContext, on_limit: bool
) -> StepResult:
    """The method's step, with the joints that rest on a limit and are pushed outwards frozen.

    Frozen joints get their Jacobian columns removed and the step is recomputed
    without them (the others then do the work).  ``J`` (m, n), ``e`` (m,), ``q`` (n,).
    """
    step = method.step(J, e, q, ctx)
    if not on_limit:
        return step
    dq = step[0]
    blocked = ((q <= ctx.lower) & (dq < 0)) | ((q >= ctx.upper) & (dq > 0))
    if not blocked.any():
        return step
    dq, damping = method.step(np.where(blocked, 0.0, J), e, q, ctx)
    return StepResult(np.where(blocked, 0.0, dq), damping)


def cap_step(dq: np.ndarray, max_step: float | None) -> np.ndarray:
    """Scale the step ``dq`` (n,) down to norm ``max_step`` if it is longer (None: no cap)."""
    if max_step is None:
        return dq
    size = math.sqrt(float(dq @ dq))
    return dq * (max_step / size) if size > max_step else dq


class Attempt(NamedTuple):
    """Outcome of one attempt: the best configuration it visited and why it ended."""

    q: np.ndarray
    error: np.ndarray
    norm: float
    outcome: Outcome
    iterations: int


def run_attempt(
    settings: IKSettings, goal: Goal, q: np.ndarray, attempt: int = 0, history: HistoryRecorder | None = None
) -> Attempt:
    r"""One attempt of the method from ``q`` (n,): iterate until converged, stalled or out of steps.

    :math:`q_{k+1} = \mathrm{clamp}(q_k + \Delta q_k)`, :math:`\Delta q_k` the
    step of ``settings.method`` from the task rows of :math:`J(q_k)` and
    :math:`e(q_k)`.  Returns the best configuration visited (smallest error norm).
    """
    ctx, method, tol_p, tol_o = settings.ctx, settings.method, settings.tol_position, settings.tol_orientation
    max_iterations, max_step = settings.max_iterations, settings.max_step
    rows = None if ctx.full_mask else ctx.rows  # task rows of a masked task
    watch = StallWatch(settings.stall_iterations, settings.stall_tolerance)
    best_norm, best_q, best_e = math.inf, q, np.zeros(6)
    on_limit = ctx.touches_limit(q)
    k = 0
    while True:
        _, T, J = ctx.pose_and_jacobian(q)
        e, position_error, orientation_error = goal.error(T)
        converged = position_error <= tol_p and orientation_error <= tol_o
        if history is not None:
            assert J is not None  # computed whenever a history is kept
            history.add_point(q, e, J, attempt)
        norm = math.sqrt(position_error * position_error + orientation_error * orientation_error)
        if norm < best_norm or converged:
            best_norm, best_q, best_e = norm, q, e
        if converged:
            outcome = Outcome.CONVERGED
            break
        if k >= max_iterations:
            outcome = Outcome.MAX_ITERATIONS
            break
        assert J is not None  # computed whenever not converged
        J_task, e_task = (J, e) if rows is None else (J[rows], e[rows])
        if watch.stalled(k, best_norm):
            verdict = classify_stall(J_task, e_task, q, ctx.lower, ctx.upper, settings.gradient_tolerance)
            outcome = Outcome(int(verdict))
            break
        dq, damping = limit_aware_step(method, J_task, e_task, q, ctx, on_limit)  # the method's step
        q_new, on_limit = ctx.advance(q, cap_step(dq, max_step))
        if history is not None:
            history.add_step(damping, q, q_new)
        q = q_new
        k += 1
    if history is not None:
        history.end_attempt()
    return Attempt(best_q, best_e, best_norm, outcome, k)


def _polish_best(
    settings: IKSettings, goal: Goal, best: Attempt, attempts: int, history: HistoryRecorder | None
) -> Attempt:
    """Every attempt failed: polish the best one (monotone LM) so that the reason says why."""
    q, e, _, outcome, iterations = polish(settings, best.q[None, :], goal.T[None])
    if history is not None:
        T_flange, _ = settings.ctx.pose(q[0])
        history.add_point(q[0], e[0], settings.ctx.jacobian(q[0], T_flange), attempts)
        history.end_attempt()
    return Attempt(q[0], e[0], math.nan, Outcome(int(outcome[0])), int(iterations[0]))


def _result(settings: IKSettings, best: Attempt, iterations: int, attempts: int,
            history: HistoryRecorder | None) -> IKResult:
    ctx, e = settings.ctx, best.error
    if ctx.full_mask:  # the mask would multiply every component by 1
        position, orientation = e[:3], e[3:]
    else:
        position, orientation = e[:3] * ctx.mask[:3], e[3:] * ctx.mask[3:]
    position_error = math.sqrt(float(position.dot(position)))
    orientation_error = math.sqrt(float(orientation.dot(orientation)))
    ok = bool(best.outcome == Outcome.CONVERGED and position_error <= settings.tol_position
              and orientation_error <= settings.tol_orientation)
    return IKResult(
        q=best.q.copy(),
        success=ok,
        iterations=iterations,
        reason=best.outcome.reason,
        position_error=position_error,
        orientation_error=orientation_error,
        errors=e.copy(),
        attempts=attempts,
        history=None if history is None else history.history(settings.ctx),
        method=settings.method.name,
    )


def _solve(settings: IKSettings, T_goal: np.ndarray, q_start: np.ndarray, record_history: bool) -> IKResult:
    """Attempts from ``q_start``, then from random configurations, then the polish."""
    ctx, seed = settings.ctx, settings.seed
    goal = Goal(T_goal, settings)
    history = HistoryRecorder() if record_history else None
    rng = seed if isinstance(seed, np.random.Generator) else None  # created on the first restart
    best = Attempt(q_start, np.zeros(6), math.inf, Outcome.MAX_ITERATIONS, 0)
    iterations = attempts = 0
    for attempt in range(settings.restarts + 1):
        attempts += 1
        if attempt == 0:
            q = q_start
        else:
            rng = np.random.default_rng(seed) if rng is None else rng
            q = random_within_limits(rng, ctx.lower, ctx.upper, 1)[0]
        result = run_attempt(settings, goal, q, attempt, history)
        iterations += result.iterations
        if result.outcome == Outcome.CONVERGED or result.norm < best.norm:
            best = result
        if result.outcome == Outcome.CONVERGED:
            break
    if best.outcome != Outcome.CONVERGED and settings.polish:
        best = _polish_best(settings, goal, best, attempts, history)
        iterations += best.iterations
    return _result(settings, best, iterations, attempts, history)


def solve_ik(
    chain: Chain,
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
        ``jacobian(q, check=False)``; ``fk_and_jacobian(q, check=False)`` if it
        has one (a :class:`~robokin.chains.SerialChain` does: one pass per iteration).
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
        recorded, as attempt ``attempts``).  Set False to see a method alone
        (:func:`solve_ik_once` is one attempt of the method alone).
    record_history : bool, optional
        Keep the per-iteration :class:`IKHistory` (default True).
    **options
        Options of a named method, e.g. ``damping=0.1`` for ``"dls"``,
        ``weights=...`` for ``"weighted"``, ``objective=...`` and ``gain=...``
        for ``"nullspace"`` (the gain :math:`k` multiplies the gradient of any
        objective; its default is in :class:`~robokin.motion.ik.NullSpace`).

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
    settings, T_goal, q_start = parse_settings(
        chain, target, q0, method, options, batched=False, mask=mask, tool=tool, tol=tol,
        max_iterations=max_iterations, restarts=restarts, seed=seed, stall_iterations=stall_iterations,
        stall_tolerance=stall_tolerance, gradient_tolerance=gradient_tolerance, max_step=max_step,
        wrap=wrap, polish=polish)
    return _solve(settings, T_goal, q_start, record_history)


def solve_ik_once(
    chain: Chain,
    target: Any,
    q0: Any = None,
    method: str | IKMethod = "lm",
    *,
    mask: Any = None,
    tool: Any = None,
    tol: float | tuple[float, float] = DEFAULTS["tol"],
    max_iterations: int | None = None,
    stall_iterations: int | None = DEFAULTS["stall_iterations"],
    stall_tolerance: float | None = DEFAULTS["stall_tolerance"],
    gradient_tolerance: float = DEFAULTS["gradient_tolerance"],
    max_step: float | None = None,
    wrap: bool | str | Any = "limits",
    record_history: bool = True,
    **options: Any,
) -> IKResult:
    r"""One attempt of an IK method alone, from ``q0``: no restarts, no polish.

    The textbook iteration (Siciliano et al. 2009, §3.7, the closed-loop
    inverse kinematics algorithm; Lynch & Park 2017, §6.2.2, the numerical
    inverse kinematics algorithm, Newton–Raphson): starting from :math:`q_0`,

    .. math::
        e_k = \begin{bmatrix} p_{goal} - p(q_k) \\ \log\!\left(R_{goal} R(q_k)^T\right)
              \end{bmatrix}, \qquad
        q_{k+1} = \mathrm{clamp}\!\left(q_k + \Delta q(J(q_k), e_k)\right)

    until :math:`\|e_{P,k}\| \le` ``tol`` and :math:`\|e_{O,k}\| \le`
    ``tol`` (converged), the error stops decreasing (stalled) or
    ``max_iterations`` steps are taken.  :math:`\Delta q` is the step of
    ``method``, e.g. :math:`J^+ e` for ``"pinv"`` (Siciliano §3.7.1),
    :math:`J^T(JJ^T + \lambda^2 I)^{-1} e` for ``"dls"`` (eq. 3.59),
    :math:`(J^TJ + (\tfrac{c}{2}\|e\|^2 + \bar w) I)^{-1} J^T e` for
    ``"lm"`` (Sugihara 2011); :math:`J` (6, n) is the geometric Jacobian of the
    (tool) frame in the base frame, rows ``[v; ω]``, reduced to the rows of
    ``mask``.  The result equals, bit for bit,
    ``solve_ik(chain, target, q0, method, restarts=0, polish=False, ...)``.

    Parameters
    ----------
    chain : chain object
        Offers ``n``, ``limits`` (n, 2), ``fk(q, check=False)`` and
        ``jacobian(q, check=False)``; ``fk_and_jacobian(q, check=False)`` if it
        has one (a :class:`~robokin.chains.SerialChain` does: one pass per iteration).
    target : array_like, shape (4, 4) or (3,)
        Goal pose ``T_base_goal`` or goal position (m).
    q0 : array_like, shape (n,), optional
        Initial guess (clamped to the limits); default the middle of the limits.
    method : str or IKMethod, optional
        The step rule (default ``"lm"``); see :func:`solve_ik`.
    mask, tool, tol, max_iterations, stall_iterations, stall_tolerance, gradient_tolerance, max_step, wrap
        As for :func:`solve_ik`.
    record_history : bool, optional
        Keep every iterate, error (K, 6), Jacobian (K, 6, n), damping and step
        size in ``history`` (default True).
    **options
        Options of a named method (e.g. ``damping=0.1`` for ``"dls"``).

    Returns
    -------
    IKResult
        As for :func:`solve_ik`, with ``attempts == 1``; ``reason`` is
        ``"converged"``, ``"max_iterations"`` or, when the attempt stalled,
        ``"stalled"``, ``"unreachable"`` or ``"joint_limits"``
        (see :func:`classify_stall`).

    Raises
    ------
    ShapeError, DomainError, TypeError
        As for :func:`solve_ik`.

    References
    ----------
    Siciliano et al., *Robotics: Modelling, Planning and Control*, 2009, §3.7.
    Lynch and Park, *Modern Robotics*, 2017, §6.2.2.
    Sugihara, "Solvability-unconcerned inverse kinematics by the
    Levenberg–Marquardt method", IEEE T-RO 27(5), 2011.
    """
    settings, T_goal, q_start = parse_settings(
        chain, target, q0, method, options, batched=False, mask=mask, tool=tool, tol=tol,
        max_iterations=max_iterations, restarts=0, seed=None, stall_iterations=stall_iterations,
        stall_tolerance=stall_tolerance, gradient_tolerance=gradient_tolerance, max_step=max_step,
        wrap=wrap, polish=False)
    return _solve(settings, T_goal, q_start, record_history)
