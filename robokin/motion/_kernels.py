"""Small, validation-free numeric kernels used inside the motion loops.

These are private: they assume well-formed float arrays and never check
their arguments, so that the per-iteration overhead of the solvers and the
simulator stays small. (The rotation log and the pose error have one
implementation each, with their public functions:
:func:`robokin.transforms.angle_axis.rotation_log_unchecked` and
:func:`robokin.motion.pose_error.pose_error_unchecked`.)
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "tool_jacobian",
    "clamp_to_limits",
    "distance_to_limits",
    "random_within_limits",
    "wrap_angles",
    "generic_rank",
]

def tool_jacobian(J: np.ndarray, R: np.ndarray, p_tool: np.ndarray) -> np.ndarray:
    """Move the reference point of a geometric Jacobian by ``p_tool`` (flange coordinates).

    ``v_tool = v + omega x r`` with ``r = R p_tool``, so ``J_v' = J_v - [r]x J_w``
    (Siciliano et al. 2009, §3.1.2; ``[r]x`` is the skew-symmetric matrix of ``r``,
    the rigid-body Jacobian of :func:`robokin.motion.tool.rigid_body_jacobian`).
    ``J`` (..., 6, n), ``R`` (..., 3, 3).
    """
    r = R @ p_tool
    Jw = J[..., 3:, :]
    cross = np.stack(
        (
            r[..., 1, None] * Jw[..., 2, :] - r[..., 2, None] * Jw[..., 1, :],
            r[..., 2, None] * Jw[..., 0, :] - r[..., 0, None] * Jw[..., 2, :],
            r[..., 0, None] * Jw[..., 1, :] - r[..., 1, None] * Jw[..., 0, :],
        ),
        axis=-2,
    )
    out = J.copy()
    out[..., :3, :] -= cross  # omega x r = -(r x omega)
    return out


def clamp_to_limits(q: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """``min(max(q, lower), upper)`` elementwise (in a new array)."""
    return np.minimum(np.maximum(q, lower), upper)


def distance_to_limits(q: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Distance (rad or m) of each configuration to its nearest joint limit, (...,)."""
    return np.min(np.minimum(q - lower, upper - q), axis=-1)


def wrap_angles(q: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Wrap the entries selected by ``mask`` into ``(-pi, pi]``."""
    wrapped = np.where(mask, np.pi - np.mod(np.pi - q, 2.0 * np.pi), q)
    return wrapped


def random_within_limits(
    rng: np.random.Generator, lower: np.ndarray, upper: np.ndarray, size: int
) -> np.ndarray:
    """``size`` configurations drawn uniformly within the limits, (size, n).

    Infinite limits are replaced by ``[-pi, pi]`` (revolute) or ``[-1, 1]`` m
    (anything else) for sampling only.
    """
    lo = np.where(np.isfinite(lower), lower, np.minimum(-np.pi, upper - 2 * np.pi))
    hi = np.where(np.isfinite(upper), upper, np.maximum(np.pi, lo + 2 * np.pi))
    return lo + (hi - lo) * rng.random((size, lower.shape[-1]))


def generic_rank(jacobian, lower: np.ndarray, upper: np.ndarray, samples: int = 4) -> int:
    """Rank of a task Jacobian at a generic configuration (its largest rank over a few samples).

    ``jacobian(Q)`` maps configurations (samples, n) to Jacobians (samples, m, n).
    The configurations are drawn from a fixed seed, so the answer is reproducible;
    a singular value counts when it exceeds 1e-9 times the largest one. This is the
    number of directions the task can move in at all: 2 for the position of a
    planar arm (its z row is always zero), 3 for the position of a spatial arm.
    A singularity is a configuration where the rank drops below it.
    """
    rng = np.random.default_rng(0)
    Q = random_within_limits(rng, lower, upper, samples)
    s = np.linalg.svd(jacobian(Q), compute_uv=False)
    top = np.maximum(s[:, :1], 1e-300)
    return max(1, int((s > 1e-9 * top).sum(axis=1).max()))
