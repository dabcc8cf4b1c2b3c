r"""When an IK attempt stops making progress, and why: :class:`StallWatch`, :func:`classify_stall`.

An attempt *stalls* when its best task error norm has not dropped by the
fraction ``stall_tolerance`` over ``stall_iterations`` steps (checked every
``stall_iterations`` steps).  :func:`classify_stall` then tells from the
gradient of :math:`\tfrac12\|e\|^2` whether the target looks out of reach,
blocked by the joint limits, or merely slow.
"""

from __future__ import annotations

import numpy as np

from robokin.motion.ik.result import Outcome

__all__ = ["classify_stall", "StallWatch", "stall_check"]

_LIMIT_EPS = 1e-12


def classify_stall(
    J: np.ndarray, e: np.ndarray, q: np.ndarray, lower: np.ndarray, upper: np.ndarray, gtol: float
) -> np.ndarray:
    r"""Why did the error stop decreasing? ``robokin.motion.ik.result.Outcome`` ``STALLED``,
    ``UNREACHABLE`` or ``JOINT_LIMITS``.

    With :math:`g = J^T e` (the steepest-descent direction of
    :math:`\tfrac12\|e\|^2`) and :math:`g_p` the same with the components that
    push a joint through an active limit removed:

    - ``unreachable``: :math:`\|g\| \le` ``gtol`` :math:`\|J\|_F\|e\|` — a
      stationary point of the error with :math:`e \ne 0` (a least-squares
      "closest" configuration: the target is out of reach, or a local minimum);
    - ``joint_limits``: :math:`\|g_p\|` is that small but :math:`\|g\|` is not —
      the limits block the only descent directions;
    - ``stalled``: otherwise (slow progress, e.g. near a singularity).

    Parameters
    ----------
    J : ndarray, shape (..., m, n)
        Task Jacobian.
    e : ndarray, shape (..., m)
        Task error.
    q : ndarray, shape (..., n)
        Configuration.
    lower, upper : ndarray, shape (n,)
        Joint limits.
    gtol : float
        Relative gradient threshold.

    Returns
    -------
    ndarray of int, shape (...)
        The ``robokin.motion.ik.result.Outcome`` codes (broadcasts over a leading batch axis).
    """
    g = (np.swapaxes(J, -1, -2) @ e[..., None])[..., 0]
    at_lo = q <= lower + _LIMIT_EPS
    at_hi = q >= upper - _LIMIT_EPS
    blocked = (at_lo & (g < 0)) | (at_hi & (g > 0))
    gp = np.where(blocked, 0.0, g)
    scale = gtol * np.linalg.norm(J, axis=(-2, -1)) * np.linalg.norm(e, axis=-1)
    g_small = np.linalg.norm(g, axis=-1) <= scale
    gp_small = np.linalg.norm(gp, axis=-1) <= scale
    return np.where(g_small, Outcome.UNREACHABLE, np.where(gp_small, Outcome.JOINT_LIMITS, Outcome.STALLED))


class StallWatch:
    """Stall test of one attempt (plain floats: it runs every iteration).

    Every ``window`` steps the best error norm must have dropped below
    ``(1 - min_decrease)`` times its value at the previous check; the first
    call (iteration 0) takes the reference, the error norm at the start.

    Parameters
    ----------
    window : int
        ``stall_iterations``.
    min_decrease : float
        ``stall_tolerance``, in [0, 1).
    """

    __slots__ = ("window", "factor", "checkpoint", "reference")

    def __init__(self, window: int, min_decrease: float) -> None:
        self.window = window
        self.factor = 1.0 - min_decrease
        self.checkpoint = 0
        self.reference: float | None = None

    def stalled(self, iteration: int, best_norm: float) -> bool:
        """True if a window has passed since the last check without enough progress."""
        if self.reference is None:
            self.checkpoint, self.reference = iteration, best_norm
        if iteration - self.checkpoint < self.window:
            return False
        if best_norm > self.factor * self.reference:
            return True
        self.checkpoint, self.reference = iteration, best_norm
        return False


def stall_check(
    iteration: np.ndarray,
    checkpoint: np.ndarray,
    reference: np.ndarray,
    best_norm: np.ndarray,
    window: int,
    min_decrease: float,
) -> tuple[np.ndarray, np.ndarray]:
    """:class:`StallWatch` for many attempts at once (arrays of shape (R,)).

    Returns ``(stalled, passed)``: the attempts that stalled, and those whose
    window passed with enough progress (their ``checkpoint``/``reference`` are
    to be moved to ``iteration``/``best_norm``).
    """
    check = (iteration - checkpoint) >= window
    stalled = check & (best_norm > (1.0 - min_decrease) * reference)
    return stalled, check & ~stalled
