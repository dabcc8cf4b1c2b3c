"""Small, validation-free numeric kernels used inside the motion loops.

These are private: they assume well-formed float arrays and never check
their arguments, so that the per-iteration overhead of the solvers and the
simulator stays small.  The public, validated versions of the same maths live
in :mod:`robokin.transforms` and :func:`robokin.motion.pose_error`.

All functions broadcast over leading axes: a single rotation has shape
``(3, 3)``, a batch ``(N, 3, 3)``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "rotation_log_fast",
    "tool_jacobian",
    "clamp_to_limits",
    "distance_to_limits",
    "random_within_limits",
    "wrap_angles",
    "rotation_log_single",
    "generic_rank",
]

# Below this angle the series expansion of theta / (2 sin theta) is used.
_SMALL_ANGLE = 1e-4
# Above pi - this angle the axis is taken from the symmetric part of R.
_NEAR_PI = 1e-3


def rotation_log_fast(R: np.ndarray) -> np.ndarray:
    """Rotation vector ``w = theta h`` of ``R`` (..., 3, 3) -> (..., 3), theta in [0, pi].

    ``theta = atan2(|vee(R - R^T)|, trace(R) - 1)`` (the two arguments are
    ``2 sin(theta)`` and ``2 cos(theta)``: accurate to the last digits for
    every angle, unlike ``arccos((trace(R) - 1) / 2)``, which loses half of
    them near 0 and pi) and ``w = theta / (2 sin theta) * vee(R - R^T)`` away
    from 0 and pi, the series ``1/2 + theta^2/12`` of that factor near 0, and
    near pi the axis from the symmetric part
    ``(R + R^T)/2 = cos(theta) I + (1 - cos(theta)) h h^T`` (the column of its
    largest diagonal entry), its sign from ``vee(R - R^T) = 2 sin(theta) h``
    (Siciliano et al. 2009, §2.5, and its singular cases; the same maths
    as :func:`robokin.transforms.rotation_log`).  At exactly ``theta = pi``
    (``vee = 0``) the sign of ``h`` is undefined; the component of ``h`` of
    largest magnitude (the first of equals) is then made positive.
    """
    R = np.asarray(R, dtype=float)
    vee = np.stack(
        (R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]),
        axis=-1,
    )
    two_sin = np.sqrt(np.einsum("...i,...i->...", vee, vee))
    two_cos = R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0
    theta = np.arctan2(two_sin, two_cos)
    small = theta < _SMALL_ANGLE
    near_pi = theta > np.pi - _NEAR_PI
    factor = np.where(small, 0.5 + theta * theta / 12.0, theta / np.where(small | near_pi, 1.0, two_sin))
    w = factor[..., None] * vee
    if np.any(near_pi):
        Rn = R[near_pi]
        cn = np.clip(0.5 * two_cos[near_pi], -1.0, 1.0)
        sym = 0.5 * (Rn + np.swapaxes(Rn, -1, -2))
        hh = (sym - cn[:, None, None] * np.eye(3)) / (1.0 - cn)[:, None, None]
        diag = np.einsum("kii->ki", hh)
        col = np.argmax(diag, axis=-1)
        h = hh[np.arange(len(col)), :, col] / np.sqrt(np.maximum(diag[np.arange(len(col)), col], 1e-300))[:, None]
        sign = np.sign(np.einsum("ki,ki->k", h, vee[near_pi]))
        sign[sign == 0] = 1.0
        h = h * sign[:, None]
        h /= np.linalg.norm(h, axis=-1, keepdims=True)
        w[near_pi] = theta[near_pi][:, None] * h
    return w


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


def rotation_log_single(R: np.ndarray) -> list[float]:
    """:func:`rotation_log_fast` for one (3, 3) matrix, in plain Python floats (fast)."""
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R.tolist()
    vx, vy, vz = r21 - r12, r02 - r20, r10 - r01
    two_sin = math.sqrt(vx * vx + vy * vy + vz * vz)
    theta = math.atan2(two_sin, r00 + r11 + r22 - 1.0)
    if theta < _SMALL_ANGLE:
        f = 0.5 + theta * theta / 12.0
        return [f * vx, f * vy, f * vz]
    if theta <= math.pi - _NEAR_PI:
        f = theta / two_sin
        return [f * vx, f * vy, f * vz]
    w = rotation_log_fast(R)
    return [float(w[0]), float(w[1]), float(w[2])]


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
