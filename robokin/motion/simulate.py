r"""Kinematic simulation of a joint-velocity controller (explicit Euler).

The robot is treated as a perfect velocity source: the state is ``q`` and the
controller's joint velocity is integrated with the explicit (forward) Euler
rule

.. math::  q_{k+1} = \operatorname{sat}\big(q_k + t_s\, \dot q_k\big),
           \qquad t_{k+1} = t_k + t_s

where ``sat`` clamps to the joint limits.  Explicit Euler is first-order
accurate: for the Cartesian P controller it turns the continuous decay
:math:`e^{-Kt}` into :math:`(1 - K t_s)^k`, which is stable only for
:math:`K t_s < 2` (Siciliano et al. 2009, §3.7.1 discuss the discrete-time
closed-loop inverse kinematics).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.motion.control import ControlOutput
from robokin.validation import as_float_array, check_positive

__all__ = ["simulate", "SimulationLog"]


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
        Pose of the controlled frame: the controller's ``pose(q)`` when it has
        one (the tool frame of a :class:`CartesianController` with ``tool=``),
        else the chain's end-effector ``fk(q)``; the same frame as ``error``.
    at_limit : ndarray of bool, shape (K, n)
        Joints resting on a limit.
    reason : str
        ``"converged"`` (error below ``tol``) or ``"end_time"``.
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


def simulate(
    chain: Any,
    controller: Any,
    q0: Any,
    ts: float,
    t_end: float,
    *,
    qdot_limits: Any = None,
    tol: float | tuple[float, float] | None = 1e-6,
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

    Returns
    -------
    SimulationLog
        ``t``, ``q``, ``qdot``, ``qdot_command``, ``twist``, ``error``, ``pose``,
        ``at_limit`` and the stopping ``reason``.

    Raises
    ------
    DomainError
        ``ts`` or ``t_end`` not positive, negative ``qdot_limits``, ``q0``
        outside the limits (all ``ValueError``; the message names the argument).
    ShapeError
        ``q0`` or ``qdot_limits`` of the wrong shape, or a controller returning
        the wrong shape.

    Notes
    -----
    Joint limits are enforced by clamping after each step: a joint that
    reaches a limit stops there (its applied velocity is reduced accordingly)
    and never crosses it, while the others keep following the controller.
    """
    n = int(chain.n)
    q = as_float_array(q0, "q0", (n,)).copy()
    ts = check_positive(ts, "ts")
    t_end = check_positive(t_end, "t_end")
    lim = np.asarray(getattr(chain, "limits", np.column_stack((np.full(n, -np.inf), np.full(n, np.inf)))),
                     dtype=float)
    lower, upper = lim[:, 0], lim[:, 1]
    if np.any(q < lower - 1e-12) or np.any(q > upper + 1e-12):
        i = int(np.argmax((q < lower - 1e-12) | (q > upper + 1e-12)))
        raise DomainError(f"q0 must lie within the joint limits; q0[{i}] = {q[i]:g} is outside "
                          f"[{lower[i]:g}, {upper[i]:g}]")
    vmax = None
    if qdot_limits is not None:
        v = as_float_array(qdot_limits, "qdot_limits")
        if v.ndim == 0:
            v = np.full(n, float(v))
        elif v.shape != (n,):
            raise ShapeError(f"qdot_limits must be a scalar or have shape ({n},); got shape {v.shape}")
        check_positive(v, "qdot_limits")
        vmax = v
    if tol is None:
        tol_p = tol_o = None
    elif np.ndim(tol) == 0:
        tol_p = tol_o = check_positive(tol, "tol")
    else:
        tp = as_float_array(tol, "tol", (2,))
        check_positive(tp, "tol")
        tol_p, tol_o = float(tp[0]), float(tp[1])
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
    controlled_pose = getattr(controller, "pose", None) or (lambda q_: chain.fk(q_, check=False))
    reason = "end_time"
    k = 0
    for k in range(K):
        t = k * ts
        T_log[k] = t
        Q[k] = q
        P[k] = controlled_pose(q)
        L[k] = (q <= lower) | (q >= upper)
        out = controller(t, q)
        if isinstance(out, ControlOutput) or hasattr(out, "qdot"):
            qdot = np.asarray(out.qdot, dtype=float)
            if getattr(out, "twist", None) is not None:
                TW[k] = out.twist
            if getattr(out, "error", None) is not None:
                E[k] = out.error
        else:
            qdot = np.asarray(out, dtype=float)
        if qdot.shape != (n,):
            raise ShapeError(f"controller must return a joint velocity of shape ({n},); got shape {qdot.shape}")
        QDc[k] = qdot
        if can_stop and not np.isnan(E[k, 0]):
            if np.linalg.norm(E[k, :3]) <= tol_p and np.linalg.norm(E[k, 3:]) <= tol_o:
                reason = "converged"
                break
        if k == K - 1:
            break
        if vmax is not None:
            ratio = np.max(np.abs(qdot) / vmax)
            if ratio > 1.0:
                qdot = qdot / ratio
        q_new = np.minimum(np.maximum(q + ts * qdot, lower), upper)
        QD[k] = (q_new - q) / ts
        q = q_new
    K = k + 1
    return SimulationLog(
        t=T_log[:K], q=Q[:K], qdot=QD[:K], qdot_command=QDc[:K], twist=TW[:K], error=E[:K],
        pose=P[:K], at_limit=L[:K], reason=reason,
    )
