r"""Kinematic simulation of a joint-velocity controller (explicit Euler).

The robot is treated as a perfect velocity source: the state is ``q`` and the
controller's joint velocity is integrated with the explicit (forward) Euler
rule

.. math::  q_{k+1} = \operatorname{sat}\big(q_k + t_s\, \dot q_k\big),
           \qquad t_{k+1} = t_k + t_s

where ``sat`` clamps to the joint limits.  Explicit Euler is first-order
accurate: for the Cartesian P controller it turns the continuous decay
:math:`e^{-Kt}` into :math:`(1 - K t_s)^k`, which is stable only for
:math:`K t_s < 2` (Siciliano et al. 2009, §3.7 discuss the discrete-time
closed-loop inverse kinematics).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robokin.chains.protocol import Chain
from robokin.errors import DomainError, ShapeError, SingularityWarning
from robokin.motion.control import ControlOutput
from robokin.validation import (
    as_float_array,
    check_callable,
    check_chain,
    check_limits,
    check_positive,
)

__all__ = ["simulate", "SimulationLog", "MAX_STEPS"]

#: Largest number of steps ``floor(t_end / ts)`` of one run (a typo such as ts=1e-9
#: raises instead of allocating gigabytes).
MAX_STEPS = 10_000_000


#: The default of :class:`SimulationLog`'s ``sigma_min`` and ``singular`` until ``__post_init__``
#: replaces it by arrays of the log's length (a marker, compared by identity, never kept in a log).
_NOT_LOGGED = np.empty(0)


@dataclass(frozen=True, eq=False)
class SimulationLog:
    """Arrays logged by :func:`simulate` (one row per time step, K rows).

    Attributes
    ----------
    t : ndarray, shape (K,)
        Times (s), ``t[0] = 0``.
    q : ndarray, shape (K, n)
        Configurations; ``q[k + 1] = sat(q[k] + ts * qdot[k])``.
    qdot : ndarray, shape (K, n)
        Joint velocities actually applied over ``[t_k, t_k + ts]`` (after the
        velocity and position saturation); zero on the last row.
    qdot_command : ndarray, shape (K, n)
        Joint velocities requested by the controller.
    twist : ndarray, shape (K, 6)
        Commanded twist ``[v; omega]`` (NaN if the controller gives none).
    error : ndarray, shape (K, 6)
        Pose error ``[e_P; e_O]`` (NaN if the controller gives none).
    pose : ndarray, shape (K, 4, 4)
        Pose of the controlled frame: the ``pose`` the controller reports in its
        :class:`ControlOutput`, else its ``pose(q)`` when it has one (the tool
        frame of a :class:`CartesianController` with ``tool=``), else the
        chain's end-effector ``fk(q)``; the same frame as ``error``.
    at_limit : ndarray of bool, shape (K, n)
        Joints resting on a limit.
    reason : str
        ``"converged"`` (error below ``tol``) or ``"end_time"``.
    sigma_min : ndarray, shape (K,)
        Smallest singular value of the Jacobian the controller inverted at each
        step (its :attr:`ControlOutput.sigma_min`; m/rad for the position rows),
        NaN where the controller does not report it (a plain function).
    singular : ndarray of bool, shape (K,)
        Steps flagged as (close to) singular: ``sigma_min`` below
        ``singular_threshold``. Where it is True the pseudoinverse commands joint
        rates up to ``|twist| / sigma_min`` (compare ``qdot_command``).
    singular_threshold : float
        The threshold used for ``singular`` (the controller's, or the value
        passed to :func:`simulate`; NaN if neither is known).
    """

    t: np.ndarray
    q: np.ndarray
    qdot: np.ndarray
    qdot_command: np.ndarray
    twist: np.ndarray
    error: np.ndarray
    pose: np.ndarray
    at_limit: np.ndarray
    reason: str
    sigma_min: np.ndarray = field(default_factory=lambda: _NOT_LOGGED)
    singular: np.ndarray = field(default_factory=lambda: _NOT_LOGGED)
    singular_threshold: float = float("nan")

    def __post_init__(self) -> None:
        # not given (a log made without them): NaN, not reported; no step flagged
        K = self.t.shape[0]
        if self.sigma_min is _NOT_LOGGED:
            object.__setattr__(self, "sigma_min", np.full(K, np.nan))
        if self.singular is _NOT_LOGGED:
            object.__setattr__(self, "singular", np.zeros(K, dtype=bool))

    def __len__(self) -> int:
        return self.t.shape[0]

    @property
    def position_error(self) -> np.ndarray:
        """Norm of the position error (m), shape (K,)."""
        return np.linalg.norm(self.error[:, :3], axis=1)

    @property
    def orientation_error(self) -> np.ndarray:
        """Norm of the orientation error (rad), shape (K,)."""
        return np.linalg.norm(self.error[:, 3:], axis=1)


def _joint_limits(chain: Chain, n: int, q0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(lower, upper)`` of the chain (infinite if it has none); ``q0`` must lie within them."""
    lim = getattr(chain, "limits", None)
    lim = np.column_stack((np.full(n, -np.inf), np.full(n, np.inf))) if lim is None else \
        check_limits(lim, n, "chain.limits")
    lower, upper = lim[:, 0], lim[:, 1]
    if np.any(q0 < lower - 1e-12) or np.any(q0 > upper + 1e-12):
        i = int(np.argmax((q0 < lower - 1e-12) | (q0 > upper + 1e-12)))
        raise DomainError(f"q0 must lie within the joint limits; q0[{i}] = {q0[i]:g} is outside "
                          f"[{lower[i]:g}, {upper[i]:g}]")
    return lower, upper


def _speed_limits(qdot_limits: Any, n: int) -> np.ndarray | None:
    """The joint speed limits (n,) (rad/s or m/s), or None for no limit."""
    if qdot_limits is None:
        return None
    v = as_float_array(qdot_limits, "qdot_limits")
    if v.ndim == 0:
        v = np.full(n, float(v))
    elif v.shape != (n,):
        raise ShapeError(f"qdot_limits must be a scalar or have shape ({n},); got shape {v.shape}")
    check_positive(v, "qdot_limits")
    return v


def _tolerances(tol: Any) -> tuple[float | None, float | None]:
    """``(position, orientation)`` tolerances of the stop test, or ``(None, None)``."""
    if tol is None:
        return None, None
    if np.ndim(tol) == 0:
        value = check_positive(tol, "tol", scalar=True)
        return value, value
    tp = as_float_array(tol, "tol", (2,))
    check_positive(tp, "tol")
    return float(tp[0]), float(tp[1])


def simulate(
    chain: Chain,
    controller: Any,
    q0: Any,
    ts: float,
    t_end: float,
    *,
    qdot_limits: Any = None,
    tol: float | tuple[float, float] | None = 1e-6,
    singular_threshold: float | None = None,
    warn_singular: bool = True,
) -> SimulationLog:
    r"""Simulate ``q' = controller(t, q)`` with explicit Euler steps of ``ts``.

    Parameters
    ----------
    chain : chain object
        Offers ``n``, ``limits`` (n, 2) and ``fk(q, check=False)``.
    controller : callable ``(t, q) -> ControlOutput`` or ``-> qdot (n,)``
        E.g. a :class:`~robokin.motion.CartesianController`.
    q0 : array_like, shape (n,)
        Initial configuration (must lie within the limits).
    ts : float
        Time step (s), > 0.
    t_end : float
        Final time (s), > 0; ``floor(t_end / ts)`` steps are taken.
    qdot_limits : float or array_like (n,), optional
        Joint-speed limits (rad/s, m/s), > 0.  A command exceeding them is
        scaled down as a whole (keeping its direction, hence the Cartesian
        path), not clipped joint by joint.
    tol : float, (float, float) or None, optional
        Stop as soon as the position error (m) and the orientation error
        (rad) are both within ``tol`` — only for controllers with a constant
        goal (``controller.static`` True) that report an error.  None never
        stops early.  Default 1e-6.
    singular_threshold : float or None, optional
        Flag the steps whose ``sigma_min`` (reported by the controller, e.g.
        :class:`~robokin.motion.CartesianController`) is below this value.
        None (default) uses the controller's own ``singular`` flag and
        ``singular_threshold`` (1e-3 by default); 0 flags nothing.
    warn_singular : bool, optional
        Issue one :class:`~robokin.errors.SingularityWarning` per run when any
        step is flagged (default True). The warning is a normal Python warning:
        ``warnings.simplefilter("ignore", robokin.errors.SingularityWarning)``
        silences it too.

    Returns
    -------
    SimulationLog
        ``t``, ``q``, ``qdot``, ``qdot_command``, ``twist``, ``error``, ``pose``,
        ``at_limit``, the stopping ``reason``, and per step ``sigma_min`` (the
        smallest singular value of the controller's Jacobian) and ``singular``
        (the flag), with the ``singular_threshold`` used.

    Raises
    ------
    DomainError
        ``ts`` or ``t_end`` not positive, more than :data:`MAX_STEPS` steps,
        negative ``qdot_limits``, ``q0`` outside the limits, a controller
        returning NaN or inf (all ``ValueError``; the message names the argument).
    ShapeError
        ``q0`` or ``qdot_limits`` of the wrong shape, or a controller returning
        the wrong shape.
    TypeError
        ``chain`` is not a kinematic chain, ``controller`` is not callable.

    Warns
    -----
    SingularityWarning
        Once per run, when some step is flagged ``singular``: the message gives
        the time and value of the smallest ``sigma_min`` and the peak commanded
        joint speed, and points to ``log.singular`` and ``inverse="dls"``.

    Notes
    -----
    Joint limits are enforced by clamping after each step: a joint that
    reaches a limit stops there (its applied velocity is reduced accordingly)
    and never crosses it, while the others keep following the controller.
    """
    check_chain(chain, "chain", ("fk",))
    check_callable(controller, "controller", "(t, q) -> ControlOutput or joint velocity (n,)")
    n = int(chain.n)
    q = as_float_array(q0, "q0", (n,)).copy()
    ts = check_positive(ts, "ts", scalar=True)
    t_end = check_positive(t_end, "t_end", scalar=True)
    ratio = t_end / ts
    if not ratio <= MAX_STEPS:
        raise DomainError(f"t_end / ts must be at most {MAX_STEPS:,} steps; got t_end = {t_end:g} s, "
                          f"ts = {ts:g} s ({ratio:.3g} steps)")
    if singular_threshold is not None:
        singular_threshold = check_positive(singular_threshold, "singular_threshold", allow_zero=True, scalar=True)
    lower, upper = _joint_limits(chain, n, q)
    vmax = _speed_limits(qdot_limits, n)
    tol_p, tol_o = _tolerances(tol)
    can_stop = tol_p is not None and bool(getattr(controller, "static", False))

    steps = int(np.floor(t_end / ts + 1e-9))
    K = steps + 1
    T_log = np.empty(K)
    Q = np.empty((K, n))
    QD = np.zeros((K, n))
    QDc = np.zeros((K, n))
    TW = np.full((K, 6), np.nan)
    E = np.full((K, 6), np.nan)
    P = np.empty((K, 4, 4))
    L = np.zeros((K, n), dtype=bool)
    S = np.full(K, np.nan)
    F = np.zeros(K, dtype=bool)
    controlled_pose = getattr(controller, "pose", None) or (lambda q_: chain.fk(q_, check=False))
    reason = "end_time"
    k = 0
    for k in range(K):
        t = k * ts
        T_log[k] = t
        Q[k] = q
        L[k] = (q <= lower) | (q >= upper)
        out = controller(t, q)
        pose = out.pose if isinstance(out, ControlOutput) else None  # reported: no second FK
        P[k] = controlled_pose(q) if pose is None else pose
        if isinstance(out, ControlOutput) or hasattr(out, "qdot"):
            qdot = as_float_array(out.qdot, "controller(t, q).qdot")
            if getattr(out, "twist", None) is not None:
                TW[k] = out.twist
            if getattr(out, "error", None) is not None:
                E[k] = out.error
            S[k] = getattr(out, "sigma_min", math.nan)
            F[k] = bool(getattr(out, "singular", False))
        else:
            qdot = as_float_array(out, "controller(t, q)")
        if qdot.shape != (n,):
            raise ShapeError(f"controller must return a joint velocity of shape ({n},); got shape {qdot.shape}")
        QDc[k] = qdot
        if can_stop and not np.isnan(E[k, 0]):
            assert tol_p is not None and tol_o is not None  # can_stop: a tolerance was given
            if np.linalg.norm(E[k, :3]) <= tol_p and np.linalg.norm(E[k, 3:]) <= tol_o:
                reason = "converged"
                break
        if k == K - 1:
            break
        if vmax is not None:
            ratio = np.max(np.abs(qdot) / vmax)
            if ratio > 1.0:
                qdot = qdot / ratio
        with np.errstate(all="ignore"):
            q_new = np.minimum(np.maximum(q + ts * qdot, lower), upper)
        total = sum(q_new.tolist())
        if total - total != 0.0:  # ts * qdot overflowed (a command near 1e308)
            raise DomainError(f"controller commanded a joint velocity too large to integrate at t = {t:g} s "
                              f"(largest |qdot| = {float(np.abs(qdot).max()):.3g}, ts = {ts:g} s)")
        QD[k] = (q_new - q) / ts
        q = q_new
    K = k + 1
    if singular_threshold is not None:
        F = S < singular_threshold  # NaN (not reported) compares False
        threshold = singular_threshold
    else:
        threshold = getattr(controller, "singular_threshold", math.nan)
        threshold = float(threshold) if isinstance(threshold, (int, float, np.number)) else math.nan
    sigma_min, singular = S[:K], F[:K]
    log = SimulationLog(
        t=T_log[:K], q=Q[:K], qdot=QD[:K], qdot_command=QDc[:K], twist=TW[:K], error=E[:K],
        pose=P[:K], at_limit=L[:K], reason=reason, sigma_min=sigma_min, singular=singular,
        singular_threshold=threshold,
    )
    if warn_singular and singular.any():
        damped = getattr(controller, "inverse", None) == "dls" and getattr(controller, "damping", 0) > 0
        warnings.warn(SingularityWarning(singularity_message("simulate", log.t, sigma_min, singular,
                                                             log.qdot_command, threshold, damped=damped)),
                      stacklevel=2)
    return log


def singularity_message(where: str, t: np.ndarray, sigma_min: np.ndarray, singular: np.ndarray,
                        qdot_command: np.ndarray, threshold: float, *, damped: bool = False,
                        runs: str = "") -> str:
    """Text of the :class:`~robokin.errors.SingularityWarning` of a run (or of a sweep's runs).

    ``sigma_min``, ``singular`` have shape (K,) or (N, K), ``qdot_command`` one more
    axis (n); ``runs`` is an optional prefix such as ``"3 of 63 runs: "``.
    """
    s = np.where(singular, sigma_min, np.inf)
    k = np.unravel_index(int(np.argmin(s)), s.shape)
    speed = np.linalg.norm(qdot_command, axis=-1)
    peak = float(np.max(np.where(singular, speed, 0.0)))
    count = int(singular.sum())
    run = f"run {int(k[0])}, " if len(k) > 1 else ""
    advice = ("The damped least-squares inverse keeps the joint rates bounded there (by |twist| / (2 lambda)) "
              "at the price of a tracking error." if damped else
              "Near a singularity the pseudoinverse asks for joint rates up to |twist| / sigma_min; damped "
              "least squares (inverse='dls') keeps them bounded.")
    return (f"{where}: {runs}{count} of {singular.size} steps came within sigma_min < {threshold:g} of a "
            f"singular configuration (smallest sigma_min = {float(sigma_min[k]):.3g} at {run}"
            f"t = {float(t[k[-1]]):.4g} s; peak commanded joint speed on those steps {peak:.3g} rad/s). "
            f"{advice} Per-step values: the log's sigma_min and singular fields. Silence with "
            f"warn_singular=False.")
