r"""Cartesian (task-space) kinematic control: a P controller with feed-forward.

The controller commands the end-effector twist (linear part first, base frame)

.. math::
    \nu_d = \begin{bmatrix} v_d \\ \omega_d \end{bmatrix}
          = \begin{bmatrix} K_P\, e_P + v_{ff} \\ K_O\, e_O + \omega_{ff} \end{bmatrix}

with the pose error :math:`e = [p_{goal} - p;\ \theta h]` of
:func:`~robokin.motion.pose_error`, and maps it to joint velocities through
the pseudoinverse, :math:`\dot q = J^+ \nu_d`, or damped least squares,
:math:`\dot q = J^T(JJ^T + \lambda^2 I)^{-1}\nu_d` (Siciliano et al. 2009,
§3.7.1, eq. 3.70; §3.5.2 / 3.59).  With :math:`J\dot q = \nu_d` the error
obeys :math:`\dot e = -K e` (for a constant goal), i.e. it decays as
:math:`e(t) = e^{-Kt} e(0)`; the Euler-discretised loop with step
:math:`t_s` gives :math:`e_k \approx (1 - K t_s)^k e_0` (stable for
:math:`K t_s < 2`, no overshoot for :math:`K t_s \le 1`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.motion._kernels import pose_error_single
from robokin.validation import as_float_array, check_positive, check_transform

__all__ = ["CartesianController", "ControlOutput"]


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
    """

    qdot: np.ndarray
    twist: np.ndarray
    error: np.ndarray


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

    Raises
    ------
    DomainError
        Negative gains or damping (names the argument).
    ShapeError
        Goal, gains or tool of the wrong shape.

    Examples
    --------
    >>> ctrl = CartesianController(chain, T_goal, position_gain=2.0)   # doctest: +SKIP
    >>> out = ctrl(0.0, q)            # ControlOutput(qdot, twist, error)  # doctest: +SKIP
    """

    def __init__(
        self,
        chain: Any,
        goal: Any,
        position_gain: Any = 1.0,
        orientation_gain: Any = 1.0,
        *,
        feedforward: Callable[[float], Any] | None = None,
        inverse: str = "pinv",
        damping: float = 0.01,
        rcond: float = 1e-8,
        tool: Any = None,
    ) -> None:
        self.chain = chain
        self.n = int(chain.n)
        self.Kp = _gain(position_gain, "position_gain")
        self.Ko = _gain(orientation_gain, "orientation_gain")
        if inverse not in ("pinv", "dls"):
            raise ValueError(f"inverse must be 'pinv' or 'dls'; got {inverse!r}")
        self.inverse = inverse
        self.damping = check_positive(damping, "damping", allow_zero=True)
        self.rcond = check_positive(rcond, "rcond")
        if feedforward is not None and not callable(feedforward):
            raise TypeError(f"feedforward must be callable t -> twist; got {type(feedforward).__name__}")
        self.feedforward = feedforward
        self.tool = None if tool is None else check_transform(tool, name="tool")
        if callable(goal):
            self._goal_fn = goal
            self.static = False
            probe = np.asarray(goal(0.0), dtype=float)
            self.position_only = probe.shape == (3,)
            self._goal = None
        else:
            self._goal_fn = None
            self.static = feedforward is None
            self._goal = self._parse_goal(goal)
            self.position_only = self._goal.shape == (3,)

    @staticmethod
    def _parse_goal(goal: Any) -> np.ndarray:
        a = as_float_array(goal, "goal")
        if a.shape == (3,):
            return a.copy()
        if a.shape == (4, 4):
            return check_transform(a, name="goal").copy()
        raise ShapeError(f"goal must have shape (4, 4) (a pose) or (3,) (a position); got shape {a.shape}")

    def goal(self, t: float) -> np.ndarray:
        """Goal pose (4, 4) or position (3,) at time ``t``."""
        if self._goal_fn is None:
            return self._goal
        g = np.asarray(self._goal_fn(t), dtype=float)
        want = (3,) if self.position_only else (4, 4)
        if g.shape != want:
            raise ShapeError(f"goal(t) must return shape {want}; got shape {g.shape} at t = {t:g}")
        return g

    def pose(self, q: np.ndarray) -> np.ndarray:
        """End-effector (tool) pose at ``q``."""
        T = self.chain.fk(q, check=False)
        return T if self.tool is None else T @ self.tool

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """Geometric Jacobian (6, n) of the (tool) frame at ``q``."""
        J = self.chain.jacobian(q, check=False)
        if self.tool is not None:
            from robokin.motion._kernels import tool_jacobian  # noqa: PLC0415

            J = tool_jacobian(J, self.chain.fk(q, check=False)[:3, :3], self.tool[:3, 3])
        return J

    def error(self, q: Any, t: float = 0.0) -> np.ndarray:
        """Pose error ``[e_P; e_O]`` (6,) at ``q`` and time ``t``."""
        T = self.pose(np.asarray(q, dtype=float))
        g = self.goal(t)
        if self.position_only:
            e = np.zeros(6)
            e[:3] = g - T[:3, 3]
            return e
        return pose_error_single(T, g)

    def __call__(self, t: float, q: Any) -> ControlOutput:
        """Joint-velocity command at time ``t`` and configuration ``q``."""
        q = np.asarray(q, dtype=float)
        e = self.error(q, t)
        twist = np.zeros(6)
        twist[:3] = self.Kp @ e[:3]
        if not self.position_only:
            twist[3:] = self.Ko @ e[3:]
        if self.feedforward is not None:
            ff = np.asarray(self.feedforward(t), dtype=float)
            if self.position_only and ff.shape == (3,):
                twist[:3] += ff
            elif ff.shape == (6,):
                twist += ff
            else:
                raise ShapeError(f"feedforward(t) must return shape (6,){' or (3,)' if self.position_only else ''}; "
                                 f"got shape {ff.shape}")
        J = self.jacobian(q)
        rows = slice(0, 3) if self.position_only else slice(0, 6)
        Jt, nu = J[rows], twist[rows]
        if self.inverse == "dls":
            A = Jt @ Jt.T
            A.flat[:: A.shape[0] + 1] += self.damping**2
            qdot = Jt.T @ np.linalg.solve(A, nu) if self.damping > 0 else np.linalg.pinv(Jt, self.rcond) @ nu
        else:
            qdot = np.linalg.pinv(Jt, rcond=self.rcond) @ nu
        return ControlOutput(qdot=qdot, twist=twist, error=e)

    def __repr__(self) -> str:
        kp = np.diag(self.Kp) if np.allclose(self.Kp, np.diag(np.diag(self.Kp))) else self.Kp
        ko = np.diag(self.Ko) if np.allclose(self.Ko, np.diag(np.diag(self.Ko))) else self.Ko
        return (f"CartesianController(n={self.n}, position_gain={kp}, orientation_gain={ko}, "
                f"inverse={self.inverse!r}{', position only' if self.position_only else ''})")
