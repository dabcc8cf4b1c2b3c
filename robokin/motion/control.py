r"""Cartesian (task-space) kinematic control: a P controller with feed-forward.

The controller commands the end-effector twist (linear part first, base frame)

.. math::
    \nu_d = \begin{bmatrix} v_d \\ \omega_d \end{bmatrix}
          = \begin{bmatrix} K_P\, e_P + v_{ff} \\ K_O\, e_O + \omega_{ff} \end{bmatrix}

with the pose error :math:`e = [p_{goal} - p;\ \theta h]` of
:func:`~robokin.motion.pose_error`, and maps it to joint velocities through
the pseudoinverse, :math:`\dot q = J^+ \nu_d`, or damped least squares,
:math:`\dot q = J^T(JJ^T + \lambda^2 I)^{-1}\nu_d` (Siciliano et al. 2009,
§3.7.1; §3.5.2, eq. 3.59).  With :math:`J\dot q = \nu_d` the error
obeys :math:`\dot e = -K e` (for a constant goal), i.e. it decays as
:math:`e(t) = e^{-Kt} e(0)`; the Euler-discretised loop with step
:math:`t_s` gives :math:`e_k \approx (1 - K t_s)^k e_0` (stable for
:math:`K t_s < 2`, no overshoot for :math:`K t_s \le 1`).

Singularities. The pseudoinverse multiplies the component of :math:`\nu_d`
along the smallest singular direction by :math:`1/\sigma_{min}`, so near a
singular configuration it commands joint rates up to
:math:`\|\nu_d\|/\sigma_{min}` (Siciliano et al. 2009, §3.3 and §3.5.2); damped
least squares bounds them by :math:`\|\nu_d\|/(2\lambda)`. Every
:class:`ControlOutput` therefore carries :math:`\sigma_{min}` of the Jacobian
used and a flag ``singular`` (:math:`\sigma_{min}` below the controller's
``singular_threshold``), which :func:`~robokin.motion.simulate` logs and
reports with a :class:`~robokin.errors.SingularityWarning`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from robokin.chains.protocol import Chain
from robokin.errors import DomainError, ShapeError
from robokin.motion._kernels import generic_rank
from robokin.motion.pose_error import pose_error_unchecked
from robokin.validation import (
    as_float_array,
    as_scalar,
    as_vector,
    check_callable,
    check_chain,
    check_choice,
    check_positive,
    check_result_finite,
    check_transform,
)

#: Default ``singular_threshold``: a step is flagged when the smallest singular value of
#: the controller's Jacobian is below it (m/rad for the position rows; the pinv then
#: turns 1 mm/s into up to 1 rad/s).
SINGULAR_THRESHOLD = 1e-3

__all__ = ["CartesianController", "ControlOutput", "SINGULAR_THRESHOLD"]


@dataclass(frozen=True, eq=False)
class ControlOutput:
    """What a controller returns for one time step.

    Attributes
    ----------
    qdot : ndarray, shape (n,)
        Joint velocity command (rad/s, m/s).
    twist : ndarray, shape (6,)
        Commanded twist ``[v; omega]`` (base frame).
    error : ndarray, shape (6,)
        Pose error ``[e_P; e_O]`` at this step (orientation part zero for a
        position-only goal).
    sigma_min : float
        Smallest singular value of the Jacobian the controller inverted (the
        3×n position rows for a position goal, else the 6×n Jacobian of the
        controlled frame), among those that are non-zero at a generic
        configuration: the ``r``-th largest, ``r`` the task's generic rank (the
        position of a planar arm has ``r = 2``: its z row is always zero, which
        is no singularity). m/rad for the position rows. NaN when a custom
        controller does not report it.
    singular : bool
        ``sigma_min`` is below the controller's ``singular_threshold``: the
        configuration is (close to) singular and the pseudoinverse asks for
        joint rates up to ``|twist| / sigma_min``.
    pose : ndarray, shape (4, 4), or None
        Pose of the controlled frame at this step (the frame of ``error``), when
        the controller computed it; :func:`~robokin.motion.simulate` logs it
        instead of computing it again. None (default) when not reported.
    """

    qdot: np.ndarray
    twist: np.ndarray
    error: np.ndarray
    sigma_min: float = float("nan")
    singular: bool = False
    pose: np.ndarray | None = None


def _pinv_and_singular_values(J: np.ndarray, rcond: float) -> tuple[np.ndarray, np.ndarray]:
    """``np.linalg.pinv(J, rcond)`` and the singular values of ``J`` from one SVD.

    The same operations, in the same order, as NumPy's ``pinv``, so the result is
    identical to it bit for bit (tested); the singular values come for free.
    """
    u, s, vt = np.linalg.svd(J, full_matrices=False)
    sv = s.copy()
    large = s > rcond * s[0]  # s[0]: the largest singular value (svd sorts them)
    s = np.divide(1, s, where=large, out=s)
    s[~large] = 0
    return np.matmul(vt.T, np.multiply(s[:, None], u.T)), sv


def _gain(value: Any, name: str) -> np.ndarray:
    """Scalar, (3,) diagonal or (3, 3) positive semidefinite gain -> (3, 3)."""
    K = as_float_array(value, name)
    if K.ndim == 0:
        check_positive(float(K), name, allow_zero=True)
        return float(K) * np.eye(3)
    if K.shape == (3,):
        check_positive(K, name, allow_zero=True)
        return np.diag(K)
    if K.shape == (3, 3):
        if not np.allclose(K, K.T, atol=1e-12):
            raise DomainError(f"{name} must be symmetric; got a non-symmetric (3, 3) matrix")
        if np.linalg.eigvalsh(K).min() < -1e-12:
            raise DomainError(f"{name} must be positive semidefinite; got smallest eigenvalue "
                              f"{np.linalg.eigvalsh(K).min():.3g}")
        return K.copy()
    raise ShapeError(f"{name} must be a scalar, shape (3,) or (3, 3); got shape {K.shape}")


class CartesianController:
    r"""Resolved-rate Cartesian P controller with optional feed-forward.

    Parameters
    ----------
    chain : chain object
        Offers ``n``, ``fk(q, check=False)``, ``jacobian(q, check=False)``.
    goal : array_like (4, 4) or (3,), or callable ``t -> (4, 4) / (3,)``
        Goal pose, goal position (position-only control with the 3×n
        position Jacobian), or a time-varying reference.
    position_gain : float, array_like (3,) or (3, 3), optional
        :math:`K_P` (1/s), >= 0.  Default 1.
    orientation_gain : float, array_like (3,) or (3, 3), optional
        :math:`K_O` (1/s), >= 0.  Default 1.
    feedforward : callable ``t -> (6,)`` (or ``(3,)`` for a position goal), optional
        Reference twist :math:`[v_{ff}; \omega_{ff}]`, e.g. the velocity of a
        trajectory (see :mod:`robokin.motion.trajectories`).
    inverse : {"pinv", "dls"}, optional
        How the twist is mapped to joint velocities (default ``"pinv"``).
    damping : float, optional
        :math:`\lambda` for ``"dls"`` (default 0.01), >= 0.
    rcond : float, optional
        Relative cut-off of small singular values for ``"pinv"``.
    tool : array_like (4, 4), optional
        Extra tool transform after the chain's end-effector.
    singular_threshold : float, optional
        Flag a step as ``singular`` when the smallest singular value of the
        Jacobian is below this value (default ``1e-3``; m/rad for the position
        rows, rad/rad for the orientation rows), >= 0; 0 never flags.
        :func:`~robokin.motion.simulate` warns once per run when a step is flagged.

    Raises
    ------
    DomainError
        Negative gains, damping or threshold (names the argument).
    ShapeError
        Goal, gains or tool of the wrong shape.
    TypeError
        ``chain`` is not a kinematic chain, ``feedforward`` not callable.

    Notes
    -----
    Calling the controller, ``controller(t, q)``, validates ``t`` (a finite
    number) and ``q`` (shape (n,), finite) and returns a :class:`ControlOutput`
    whose ``sigma_min`` and ``singular`` fields tell how close ``q`` is to a
    singularity. ``inverse="dls"`` keeps the joint rates bounded there.

    Examples
    --------
    >>> ctrl = CartesianController(chain, T_goal, position_gain=2.0)   # doctest: +SKIP
    >>> out = ctrl(0.0, q)            # ControlOutput(qdot, twist, error)  # doctest: +SKIP
    """

    def __init__(
        self,
        chain: Chain,
        goal: Any,
        position_gain: Any = 1.0,
        orientation_gain: Any = 1.0,
        *,
        feedforward: Callable[[float], Any] | None = None,
        inverse: str = "pinv",
        damping: float = 0.01,
        rcond: float = 1e-8,
        tool: Any = None,
        singular_threshold: float = SINGULAR_THRESHOLD,
    ) -> None:
        self.chain = check_chain(chain)
        self.n = int(chain.n)
        self.Kp = _gain(position_gain, "position_gain")
        self.Ko = _gain(orientation_gain, "orientation_gain")
        self.inverse = check_choice(inverse, ("pinv", "dls"), "inverse")
        self.damping = check_positive(damping, "damping", allow_zero=True, scalar=True)
        self.rcond = check_positive(rcond, "rcond", scalar=True)
        self.singular_threshold = check_positive(singular_threshold, "singular_threshold", allow_zero=True, scalar=True)
        if feedforward is not None:
            check_callable(feedforward, "feedforward", "t -> twist (6,) (or (3,) for a position goal)")
        self.feedforward = feedforward
        self.tool = None
        if tool is not None:
            self.tool = check_transform(tool, name="tool")
            if self.tool.shape != (4, 4):
                raise ShapeError(f"tool must have shape (4, 4); got shape {self.tool.shape}")
        if callable(goal):
            self._goal_fn = goal
            self.static = False
            probe = self._call_goal(0.0, None)
            self.position_only = probe.shape == (3,)
            self._goal = None
        else:
            self._goal_fn = None
            self.static = feedforward is None
            self._goal = self._parse_goal(goal)
            self.position_only = self._goal.shape == (3,)
        self._rank: int | None = None  # generic rank of the task Jacobian, found on first use

    @property
    def task_rank(self) -> int:
        """Rank of the task Jacobian at a generic configuration (3 or 6 for most arms, 2 for
        the position of a planar arm); ``sigma_min`` is the singular value of that order."""
        if self._rank is None:
            lim = getattr(self.chain, "limits", None)
            lim = np.tile([-np.inf, np.inf], (self.n, 1)) if lim is None else np.asarray(lim, dtype=float)
            rows = slice(0, 3) if self.position_only else slice(0, 6)
            jac = lambda Q: np.stack([self._jacobian(q)[rows] for q in Q])  # noqa: E731
            self._rank = generic_rank(jac, lim[:, 0], lim[:, 1])
        return self._rank

    @staticmethod
    def _parse_goal(goal: Any) -> np.ndarray:
        a = as_float_array(goal, "goal")
        if a.shape == (3,):
            return a.copy()
        if a.shape == (4, 4):
            return check_transform(a, name="goal").copy()
        raise ShapeError(f"goal must have shape (4, 4) (a pose) or (3,) (a position); got shape {a.shape}")

    def _call_goal(self, t: float, want: tuple[int, ...] | None) -> np.ndarray:
        """Evaluate the goal function at ``t``; check its shape and finiteness (names ``goal``)."""
        try:
            g = as_float_array(self._goal_fn(t), "goal(t)")
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"goal (a function of t) returned an invalid value at t = {t:g}: {exc}") from None
        if g.shape not in ((3,), (4, 4)) or (want is not None and g.shape != want):
            expected = want if want is not None else "(3,) or (4, 4)"
            raise ShapeError(f"goal(t) must return shape {expected}; got shape {g.shape} at t = {t:g}")
        if g.shape == (4, 4):
            check_transform(g, name="goal(t)")
        return g

    def goal(self, t: float) -> np.ndarray:
        """Goal pose (4, 4) or position (3,) at time ``t`` (a finite number)."""
        t = as_scalar(t, "t")
        return self._goal_at(t)

    def _goal_at(self, t: float) -> np.ndarray:
        if self._goal is not None:  # a constant goal (None for a function of t)
            return self._goal
        return self._call_goal(t, (3,) if self.position_only else (4, 4))

    def pose(self, q: Any) -> np.ndarray:
        """End-effector (tool) pose (4, 4) at ``q`` (n,)."""
        return self._pose(as_vector(q, self.n, "q"))

    def _pose(self, q: np.ndarray) -> np.ndarray:
        T = self.chain.fk(q, check=False)
        return T if self.tool is None else T @ self.tool

    def jacobian(self, q: Any) -> np.ndarray:
        """Geometric Jacobian (6, n) of the (tool) frame at ``q`` (n,)."""
        return self._jacobian(as_vector(q, self.n, "q"))

    def _jacobian(self, q: np.ndarray, T_flange: np.ndarray | None = None) -> np.ndarray:
        """Jacobian of the controlled frame; ``T_flange``: the chain's ``fk(q)`` if already known."""
        J = self.chain.jacobian(q, check=False)
        if self.tool is not None:
            from robokin.motion._kernels import tool_jacobian

            if T_flange is None:
                T_flange = self.chain.fk(q, check=False)
            J = tool_jacobian(J, T_flange[:3, :3], self.tool[:3, 3])
        return J

    def error(self, q: Any, t: float = 0.0) -> np.ndarray:
        """Pose error ``[e_P; e_O]`` (6,) at ``q`` (n,) and time ``t``."""
        return self._error(as_vector(q, self.n, "q"), as_scalar(t, "t"))

    def _error(self, q: np.ndarray, t: float) -> np.ndarray:
        return self._error_at_pose(self._pose(q), t)

    def _error_at_pose(self, T: np.ndarray, t: float) -> np.ndarray:
        g = self._goal_at(t)
        if self.position_only:
            e = np.zeros(6)
            e[:3] = g - T[:3, 3]
            return e
        return np.array(pose_error_unchecked(T, g[:3, :3], g[:3, 3]))

    def __call__(self, t: float, q: Any) -> ControlOutput:
        """Joint-velocity command at time ``t`` (s) and configuration ``q`` (n,).

        Returns
        -------
        ControlOutput
            ``qdot``, ``twist``, ``error``, the singularity measure
            ``sigma_min`` / flag ``singular`` and the ``pose`` of the controlled
            frame of this step.

        Raises
        ------
        ShapeError, DomainError, TypeError
            ``q`` not of shape (n,) or not finite, ``t`` not a finite number;
            a goal or feed-forward function returning the wrong shape; a goal so
            far away that the commanded twist overflows.
        """
        t = as_scalar(t, "t")
        q = as_vector(q, self.n, "q")
        T_flange = self.chain.fk(q, check=False)
        T = T_flange if self.tool is None else T_flange @ self.tool  # self._pose(q)
        e = self._error_at_pose(T, t)
        twist = np.zeros(6)
        with np.errstate(all="ignore"):
            twist[:3] = self.Kp @ e[:3]
            if not self.position_only:
                twist[3:] = self.Ko @ e[3:]
        if self.feedforward is not None:
            try:
                ff = as_float_array(self.feedforward(t), "feedforward(t)")
            except (TypeError, ValueError) as exc:
                raise type(exc)(f"feedforward returned an invalid value at t = {t:g}: {exc}") from None
            if self.position_only and ff.shape == (3,):
                twist[:3] += ff
            elif ff.shape == (6,):
                twist += ff
            else:
                raise ShapeError(f"feedforward(t) must return shape (6,){' or (3,)' if self.position_only else ''}; "
                                 f"got shape {ff.shape}")
        total = sum(twist.tolist())
        if total - total != 0.0:  # a goal near 1e308 m: the twist overflowed
            check_result_finite(twist, "the commanded twist", goal=self._goal_at(t))
        J = self._jacobian(q, T_flange)
        rows = slice(0, 3) if self.position_only else slice(0, 6)
        Jt, nu = J[rows], twist[rows]
        if self.inverse == "dls" and self.damping > 0:
            A = Jt @ Jt.T
            A.flat[:: A.shape[0] + 1] += self.damping**2
            qdot = Jt.T @ np.linalg.solve(A, nu)
            s = np.linalg.svd(Jt, compute_uv=False)
        else:
            pinv, s = _pinv_and_singular_values(Jt, self.rcond)
            qdot = pinv @ nu
        r = self.task_rank
        sigma_min = float(s[r - 1]) if s.size >= r else 0.0
        return ControlOutput(qdot=qdot, twist=twist, error=e, sigma_min=sigma_min,
                             singular=bool(sigma_min < self.singular_threshold), pose=T)

    def __repr__(self) -> str:
        kp = np.diag(self.Kp) if np.allclose(self.Kp, np.diag(np.diag(self.Kp))) else self.Kp
        ko = np.diag(self.Ko) if np.allclose(self.Ko, np.diag(np.diag(self.Ko))) else self.Ko
        return (f"CartesianController(n={self.n}, position_gain={kp}, orientation_gain={ko}, "
                f"inverse={self.inverse!r}{', position only' if self.position_only else ''})")
