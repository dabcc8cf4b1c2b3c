"""Result containers of the inverse-kinematics solvers.

:class:`IKHistory` holds one row per evaluated configuration (arrays over
iterations, ready to plot or animate), :class:`IKResult` the outcome of one
solve, :class:`IKBatchResult` the outcome of many solves at once.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from functools import cached_property

import numpy as np

__all__ = ["IKHistory", "IKResult", "IKBatchResult", "Outcome", "REASONS", "REASON_NAMES"]


class Outcome(IntEnum):
    """How an IK attempt ended, as one code for the single, batched and polishing solvers.

    A result's ``reason`` is the member's :attr:`reason` (its name in lower case).
    ``STALLED``, ``UNREACHABLE`` and ``JOINT_LIMITS`` are the verdicts of
    :func:`~robokin.motion.ik.stall.classify_stall` on an attempt that stopped progressing.
    """

    CONVERGED = 0
    MAX_ITERATIONS = 1
    STALLED = 2
    UNREACHABLE = 3
    JOINT_LIMITS = 4

    @property
    def reason(self) -> str:
        """The name a result reports: ``"converged"``, ``"max_iterations"``, ..."""
        return self.name.lower()


#: Possible values of ``reason`` (see :func:`robokin.motion.solve_ik`), in the order of :class:`Outcome`.
REASONS = tuple(outcome.reason for outcome in Outcome)
#: :data:`REASONS` as an array, to turn an array of :class:`Outcome` codes into reasons at once.
REASON_NAMES = np.array(REASONS)


@dataclass(frozen=True, eq=False)
class IKHistory:
    """Per-iteration record of an IK solve (one row per evaluated configuration).

    Row ``k`` describes configuration ``q[k]``: its task error, the Jacobian
    there and the step taken from it (zero on the last row of an attempt).
    With random restarts the attempts are stacked; ``attempt[k]`` tells which
    attempt row ``k`` belongs to.

    Attributes
    ----------
    q : ndarray, shape (K, n)
        Configurations, ``q[0]`` the initial guess.
    error : ndarray, shape (K, 6)
        Error ``[e_p; e_o]`` (m, rad) in the base frame; components outside the
        task mask are still reported (zero orientation for position targets).
    jacobian : ndarray, shape (K, 6, n)
        Geometric Jacobian ``[J_v; J_w]`` of the (tool) frame at ``q[k]``.
    damping : ndarray, shape (K,)
        Damping ``lambda`` used for the step (regulariser ``lambda^2 I``); 0 for
        undamped methods.
    step_size : ndarray, shape (K,)
        ``||q[k+1] - q[k]||`` after clamping; 0 on the last row of an attempt.
    attempt : ndarray of int, shape (K,)
        Attempt index (0 = the given ``q0``, 1... = random restarts; a final
        row with index ``attempts`` is the end point of the LM polish run
        when every attempt failed).
    mask : ndarray of bool, shape (6,)
        Task components used.
    limits : ndarray, shape (n, 2)
        Joint limits, for :attr:`limit_distance`.
    """

    q: np.ndarray
    error: np.ndarray
    jacobian: np.ndarray
    damping: np.ndarray
    step_size: np.ndarray
    attempt: np.ndarray
    mask: np.ndarray = field(repr=False)
    limits: np.ndarray = field(repr=False)

    def __len__(self) -> int:
        return self.q.shape[0]

    @cached_property
    def error_norm(self) -> np.ndarray:
        """Norm of the task error (selected components), shape (K,)."""
        return np.linalg.norm(self.error[:, self.mask], axis=-1)

    @cached_property
    def position_error(self) -> np.ndarray:
        """Norm of the selected position components (m), shape (K,)."""
        return np.linalg.norm(self.error[:, :3] * self.mask[:3], axis=-1)

    @cached_property
    def orientation_error(self) -> np.ndarray:
        """Norm of the selected orientation components (rad), shape (K,)."""
        return np.linalg.norm(self.error[:, 3:] * self.mask[3:], axis=-1)

    @cached_property
    def smallest_singular_value(self) -> np.ndarray:
        """Smallest singular value of the task Jacobian (masked rows), shape (K,)."""
        if len(self) == 0:
            return np.empty(0)
        s = np.linalg.svd(self.jacobian[:, self.mask, :], compute_uv=False)
        return s[:, -1] if s.shape[1] <= self.q.shape[1] else np.zeros(len(self))

    @cached_property
    def limit_distance(self) -> np.ndarray:
        """Distance to the nearest joint limit (rad or m), shape (K,)."""
        lo, hi = self.limits[:, 0], self.limits[:, 1]
        return np.min(np.minimum(self.q - lo, hi - self.q), axis=-1)

    @property
    def iterations(self) -> np.ndarray:
        """Row index, shape (K,) (the x-axis of convergence plots)."""
        return np.arange(len(self))


@dataclass(frozen=True, eq=False)
class IKResult:
    """Outcome of :func:`robokin.motion.solve_ik`.

    Attributes
    ----------
    q : ndarray, shape (n,)
        Best configuration found (within the joint limits).
    success : bool
        True only if both ``position_error <= position_tolerance`` and
        ``orientation_error <= orientation_tolerance`` (selected components).
    iterations : int
        Steps taken, summed over all attempts.
    reason : str
        One of :data:`REASONS`; for a failure, the reason of the best attempt.
    position_error : float
        Norm of the selected position components of the final error (m).
    orientation_error : float
        Norm of the selected orientation components of the final error (rad).
    errors : ndarray, shape (6,)
        Final error ``[p_goal - p; theta h]`` in the base frame.
    attempts : int
        Attempts made (1 + restarts used).
    history : IKHistory or None
        Per-iteration record (None if ``record_history=False``).
    method : str
        Name of the method used.
    """

    q: np.ndarray
    success: bool
    iterations: int
    reason: str
    position_error: float
    orientation_error: float
    errors: np.ndarray
    attempts: int
    history: IKHistory | None
    method: str


@dataclass(frozen=True, eq=False)
class IKBatchResult:
    """Outcome of :func:`robokin.motion.solve_ik_batch` for N targets.

    Attributes
    ----------
    q : ndarray, shape (N, n)
    success : ndarray of bool, shape (N,)
    iterations : ndarray of int, shape (N,)
        Steps per target, summed over attempts.
    reason : ndarray of str, shape (N,)
    position_error, orientation_error : ndarray, shape (N,)
    errors : ndarray, shape (N, 6)
    attempts : ndarray of int, shape (N,)
    method : str
    """

    q: np.ndarray
    success: np.ndarray
    iterations: np.ndarray
    reason: np.ndarray
    position_error: np.ndarray
    orientation_error: np.ndarray
    errors: np.ndarray
    attempts: np.ndarray
    method: str

    def __len__(self) -> int:
        return self.q.shape[0]

    @property
    def success_rate(self) -> float:
        """Fraction of targets solved."""
        return float(np.mean(self.success)) if len(self) else float("nan")
