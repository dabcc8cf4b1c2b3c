r"""Angle–axis representation and the exponential / logarithm maps of SO(3).

A rotation by angle :math:`\theta` about the unit axis :math:`h` is written as
the rotation vector :math:`w = \theta h`; its rotation matrix is the matrix
exponential :math:`R = \exp([w]_\times)`, in closed form by Rodrigues' formula
(Siciliano et al. 2009, §2.5; Lynch & Park 2017, §3.2.3).

The logarithm returns :math:`\theta \in [0, \pi]`. At :math:`\theta = \pi`
both :math:`w` and :math:`-w` describe the same rotation; the one returned
has a positive component along the axis of the largest diagonal entry of
:math:`R`. At :math:`\theta = 0` the axis is undefined;
:func:`angle_axis_from_rotation` returns the axis ``[1, 0, 0]`` there.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokin._dispatch import is_symbolic, scalar_input, to_sympy
from robokin.errors import DomainError, ShapeError
from robokin.transforms.rotations import skew
from robokin.validation import as_batch, as_rotation_matrix

__all__ = [
    "rotation_exp",
    "rotation_log",
    "rotation_from_angle_axis",
    "angle_axis_from_rotation",
]

_TAYLOR_TOL = 1e-3  # below this angle rotation_exp uses the Taylor series
#: Below this angle (rad) the rotation log's factor theta / (2 sin theta) is its series 1/2 + theta^2/12.
SMALL_ANGLE = 1e-4
#: Below this cos(theta) (theta above 2.69 rad) the rotation log takes the axis from the symmetric part of R.
NEAR_PI_COS = -0.9
DEFAULT_AXIS = np.array([1.0, 0.0, 0.0])


def _vectors(v: Any, name: str) -> np.ndarray:
    return as_batch(v, 3, name)[0]


def _sym_vector(v: Any, name: str) -> Any:
    m = to_sympy(v)
    if m.shape not in ((3, 1), (1, 3)):
        raise ShapeError(f"{name} must have 3 entries; got a sympy Matrix of shape {m.shape}")
    return m.reshape(3, 1)


def rotation_exp(w: Any) -> Any:
    r"""Rotation matrix of a rotation vector: :math:`\exp([w]_\times)` (Rodrigues' formula).

    Exact for small rotation vectors, zero included (Taylor series of the coefficients
    below :math:`\theta = \|w\| = 10^{-3}`; Lynch & Park 2017, §3.2.3.3; Siciliano et al.
    2009, §2.5).

    Parameters
    ----------
    w : array_like, shape (3,) or (N, 3), or sympy vector
        Rotation vector(s) :math:`\theta h` in radians.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3), or sympy.Matrix (3x3)
        For symbolic input the closed form with :math:`\theta = \sqrt{w^\mathsf{T} w}`;
        prefer :func:`rotation_from_angle_axis` for readable symbolic results.
        Huge rotation vectors (:math:`\theta^2` beyond float64) are computed
        from the unit axis, so the result is always a rotation.

    Raises
    ------
    ShapeError, DomainError
        ``w`` not of shape (3,) / (N, 3), non-finite entries, or a norm that
        overflows float64 (entries near 1e308).
    """
    if is_symbolic(w):
        import sympy as sp

        wv = _sym_vector(w, "w")
        theta = sp.sqrt((wv.T * wv)[0, 0])
        K = skew(wv)
        return sp.eye(3) + sp.sin(theta) / theta * K + (1 - sp.cos(theta)) / theta**2 * K * K
    a = _vectors(w, "w")
    if a.ndim == 1:
        return _exp_single(*a.tolist())
    with np.errstate(all="ignore"):
        th2 = np.einsum("...i,...i->...", a, a)
        th = np.sqrt(th2)
        small = th < _TAYLOR_TOL
        th_safe = np.where(small, 1.0, th)
        A = np.where(small, 1.0 - th2 / 6.0 + th2 * th2 / 120.0, np.sin(th_safe) / th_safe)
        B = np.where(small, 0.5 - th2 / 24.0 + th2 * th2 / 720.0,
                     2.0 * np.sin(0.5 * th_safe) ** 2 / th_safe**2)
        K = skew(a)
        R = np.eye(3) + A[..., None, None] * K + B[..., None, None] * (K @ K)
    huge = ~np.isfinite(th2)  # |w| > 1.3e154: θ² overflows; use the unit axis instead
    if huge.any():
        R[huge] = [_exp_single(*row) for row in a[huge].tolist()]
    return R


def _exp_huge(x: float, y: float, z: float) -> np.ndarray:
    """rotation_exp for |w| so large that θ² overflows: R = cos θ I + sin θ [h]x + (1 − cos θ) h hᵀ."""
    m = max(abs(x), abs(y), abs(z))
    u, v, t = x / m, y / m, z / m
    r = math.sqrt(u * u + v * v + t * t)
    th = m * r
    if not math.isfinite(th):
        raise DomainError(f"w is too large: its norm overflows float64 (largest |w| = {m:.3g})")
    hx, hy, hz = u / r, v / r, t / r
    c, s = math.cos(th), math.sin(th)
    k = 1.0 - c
    return np.array(
        [
            [c + k * hx * hx, k * hx * hy - s * hz, k * hx * hz + s * hy],
            [k * hx * hy + s * hz, c + k * hy * hy, k * hy * hz - s * hx],
            [k * hx * hz - s * hy, k * hy * hz + s * hx, c + k * hz * hz],
        ]
    )


def _exp_single(x: float, y: float, z: float) -> np.ndarray:
    """Scalar fast path of rotation_exp: R = I + A [w]x + B (w wᵀ − θ² I)."""
    th2 = x * x + y * y + z * z
    if not th2 < math.inf:
        return _exp_huge(x, y, z)
    if th2 < _TAYLOR_TOL * _TAYLOR_TOL:
        A = 1.0 - th2 / 6.0 + th2 * th2 / 120.0
        B = 0.5 - th2 / 24.0 + th2 * th2 / 720.0
    else:
        th = math.sqrt(th2)
        A = math.sin(th) / th
        B = 2.0 * math.sin(0.5 * th) ** 2 / th2
    d = 1.0 - B * th2
    return np.array(
        [
            [d + B * x * x, B * x * y - A * z, B * x * z + A * y],
            [B * x * y + A * z, d + B * y * y, B * y * z - A * x],
            [B * x * z - A * y, B * y * z + A * x, d + B * z * z],
        ]
    )


def rotation_log_unchecked(R: np.ndarray) -> Any:
    r""":func:`rotation_log` without validation: the one implementation of the rotation log.

    ``R`` must be a float rotation matrix (3, 3), or a stack (..., 3, 3). One matrix gives a
    tuple of three floats, computed in plain Python floats (the IK loop calls this every
    iteration, and numpy's per-call cost would dominate); a stack gives an array (..., 3).
    Both follow the same branches with the same thresholds (see :func:`rotation_log`):
    ``SMALL_ANGLE`` and ``NEAR_PI_COS``.
    """
    if R.ndim == 2:
        (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R.tolist()
        vx, vy, vz = r21 - r12, r02 - r20, r10 - r01  # vee(R - R^T) = 2 sin(theta) h
        two_sin = math.sqrt(vx * vx + vy * vy + vz * vz)
        two_cos = r00 + r11 + r22 - 1.0
        theta = math.atan2(two_sin, two_cos)
        if theta < SMALL_ANGLE:
            f = 0.5 + theta * theta / 12.0
            return f * vx, f * vy, f * vz
        cos_theta = 0.5 * two_cos
        if cos_theta >= NEAR_PI_COS:
            f = theta / two_sin
            return f * vx, f * vy, f * vz
        # (R + R^T)/2 - cos(theta) I = (1 - cos(theta)) h h^T: its column of largest diagonal is along h
        d0, d1, d2 = r00 - cos_theta, r11 - cos_theta, r22 - cos_theta
        if d0 >= d1 and d0 >= d2:
            cx, cy, cz = d0, 0.5 * (r10 + r01), 0.5 * (r20 + r02)
        elif d1 >= d2:
            cx, cy, cz = 0.5 * (r01 + r10), d1, 0.5 * (r21 + r12)
        else:
            cx, cy, cz = 0.5 * (r02 + r20), 0.5 * (r12 + r21), d2
        sign = -1.0 if cx * vx + cy * vy + cz * vz < 0.0 else 1.0  # vee = 2 sin(theta) h, sin(theta) >= 0
        f = sign * theta / math.sqrt(cx * cx + cy * cy + cz * cz)
        return f * cx, f * cy, f * cz
    v = np.stack((R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]), axis=-1)
    two_sin = np.sqrt(np.einsum("...i,...i->...", v, v))
    two_cos = R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2] - 1.0
    theta = np.arctan2(two_sin, two_cos)
    small = theta < SMALL_ANGLE
    near_pi = ~small & (0.5 * two_cos < NEAR_PI_COS)
    factor = np.where(small, 0.5 + theta * theta / 12.0, theta / np.where(small | near_pi, 1.0, two_sin))
    w = factor[..., None] * v
    if np.any(near_pi):
        cosines = 0.5 * two_cos[near_pi]
        Rn = R[near_pi]
        sym = 0.5 * (Rn + np.swapaxes(Rn, -1, -2)) - cosines[:, None, None] * np.eye(3)
        k = np.argmax(np.einsum("kii->ki", sym), axis=-1)
        column = sym[np.arange(k.size), :, k]
        signs = np.where(np.einsum("ki,ki->k", column, v[near_pi]) < 0.0, -1.0, 1.0)
        w[near_pi] = (signs * theta[near_pi] / np.linalg.norm(column, axis=-1))[:, None] * column
    return w


def rotation_log(R: Any, check: bool = True) -> np.ndarray:
    r"""Rotation vector :math:`w = \theta h` of a rotation matrix (inverse of :func:`rotation_exp`).

    .. math::
        \theta = \operatorname{atan2}\!\Big(\tfrac12\|\operatorname{vee}(R - R^\mathsf{T})\|,\;
                 \tfrac12(\operatorname{tr}R - 1)\Big) \in [0, \pi], \qquad
        w = \frac{\theta}{2\sin\theta}\operatorname{vee}(R - R^\mathsf{T})

    Robust everywhere:

    - :math:`\theta \to 0` (below ``SMALL_ANGLE``, 1e-4 rad): the factor
      :math:`\theta / (2\sin\theta)` is replaced by its Taylor series
      :math:`\tfrac12 + \theta^2/12` (the next term, :math:`7\theta^4/720`, is below 1e-18).
    - :math:`\theta \to \pi` (:math:`\cos\theta <` ``NEAR_PI_COS``, -0.9): no division by
      :math:`\sin\theta`; the axis comes from the symmetric part
      :math:`\tfrac12(R + R^\mathsf{T}) - \cos\theta\, I = (1 - \cos\theta) h h^\mathsf{T}`
      using the column of its largest diagonal entry, with the sign fixed by
      :math:`\operatorname{vee}(R - R^\mathsf{T}) = 2 \sin\theta\, h`.
      At exactly :math:`\theta = \pi` that component of :math:`h` is positive.

    (Lynch & Park 2017, §3.2.3.3, Algorithm; Siciliano et al. 2009, §2.5.)

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrix / matrices.
    check : bool, optional
        Validate that ``R`` is a rotation matrix (``R Rᵀ = I``, ``det R = 1``).

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3)
        Rotation vector(s) with norm in [0, π].

    Raises
    ------
    ShapeError, DomainError
        Wrong shape; not a rotation (with ``check``); non-finite entries.
    """
    if is_symbolic(R):
        raise TypeError("rotation_log needs a numeric R; got a symbolic matrix")
    a = as_rotation_matrix(R, check)
    return np.array(rotation_log_unchecked(a)) if a.ndim == 2 else rotation_log_unchecked(a)


def rotation_from_angle_axis(axis: Any, angle: Any) -> Any:
    r"""Rotation by ``angle`` about ``axis`` (normalised first).

    The active rotation, counterclockwise about the axis seen from its tip (Siciliano et al.
    2009, §2.5).

    Parameters
    ----------
    axis : array_like, shape (3,) or (N, 3), or sympy vector
        Rotation axis, any non-zero length.
    angle : float, array_like of shape (N,), or sympy expression
        Angle(s) in radians; broadcasts against the axes.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3), or sympy.Matrix (3x3)

    Raises
    ------
    DomainError
        Zero-length axis, or non-finite input.
    ShapeError
        Axis not of length 3, or batch sizes that do not match.

    Examples
    --------
    >>> import sympy as sp
    >>> t = sp.Symbol("theta")
    >>> rotation_from_angle_axis([0, 0, 1], t)
    Matrix([
    [cos(theta), -sin(theta), 0],
    [sin(theta),  cos(theta), 0],
    [         0,           0, 1]])
    """
    if is_symbolic(axis, angle):
        import sympy as sp

        a = _sym_vector(axis, "axis")
        n2 = (a.T * a)[0, 0]
        if n2 == 0:
            raise DomainError("axis must be non-zero; got the zero vector")
        h = a / sp.sqrt(n2)
        t = to_sympy(scalar_input(angle, "angle"))
        c, s = sp.cos(t), sp.sin(t)
        return c * sp.eye(3) + s * skew(h) + (1 - c) * h * h.T
    a = _vectors(axis, "axis")
    h = unit_vectors(a, "axis", "non-zero")
    t = np.asarray(scalar_input(angle, "angle"), dtype=float)
    if t.ndim > 1:
        raise ShapeError(f"angle must be a scalar or have shape (N,); got shape {t.shape}")
    c, s = np.cos(t)[..., None, None], np.sin(t)[..., None, None]
    try:
        hh = h[..., :, None] * h[..., None, :]
        return c * np.eye(3) + s * skew(h) + (1.0 - c) * hh
    except ValueError:
        raise ShapeError(
            f"axis and angle have incompatible batch sizes: axis has shape {a.shape}, "
            f"angle has shape {t.shape}"
        ) from None


def unit_vectors(a: np.ndarray, name: str, nonzero: str) -> np.ndarray:
    """The rows of ``a`` (..., k) divided by their Euclidean norms, without overflow for huge entries.

    The norms are the plain ``np.linalg.norm`` everywhere it is finite (so ordinary
    input gives the same bits as before); rows whose squares overflow are scaled first.

    Parameters
    ----------
    a : numpy.ndarray, shape (k,) or (N, k)
        Finite vectors (an axis, a quaternion).
    name : str
        Argument name for messages.
    nonzero : str
        What ``a`` must be, for the message on a zero row (``"non-zero"``,
        ``"a non-zero quaternion"``).

    Returns
    -------
    numpy.ndarray, shape of ``a``

    Raises
    ------
    DomainError
        A norm below 1e-12 (for a batch, the message names its index) or one that
        overflows float64.
    """
    with np.errstate(over="ignore"):
        n = np.linalg.norm(a, axis=-1)
    huge = ~np.isfinite(n)
    if huge.any():
        rows = a[huge]
        m = np.abs(rows).max(axis=-1)
        n = np.array(n, dtype=float, copy=True)
        with np.errstate(over="ignore"):
            n[huge] = m * np.linalg.norm(rows / m[:, None], axis=-1)
        if not np.isfinite(n).all():
            raise DomainError(f"{name} is too large: its norm overflows float64 (largest |{name}| = "
                              f"{float(np.abs(a).max()):.3g})")
    if np.any(n < 1e-12):
        raise DomainError(
            f"{name} must be {nonzero}; got norm {float(np.min(n)):.3g}"
            + (f" at index {int(np.argmin(n))}" if a.ndim == 2 else "")
        )
    return a / n[..., None]


def angle_axis_from_rotation(R: Any, check: bool = True) -> tuple[np.ndarray, Any]:
    r"""Axis and angle of a rotation matrix, angle in [0, π].

    Computed with :func:`rotation_log`; see there for the treatment near
    θ = 0 and θ = π. **At θ = 0 the axis is undefined and** ``[1, 0, 0]``
    **is returned.**

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrix / matrices.
    check : bool, optional
        Validate that ``R`` is a rotation.

    Returns
    -------
    axis : numpy.ndarray, shape (3,) or (N, 3)
        Unit axis.
    angle : float or numpy.ndarray of shape (N,)
        Angle in radians, in [0, π].
    """
    if is_symbolic(R):
        raise TypeError("angle_axis_from_rotation needs a numeric R; got a symbolic matrix")
    a = as_rotation_matrix(R, check)
    if a.ndim == 2:
        w = rotation_log_unchecked(a)
        theta = min(math.hypot(*w), math.pi)  # |w| = theta to rounding
        return (np.array(w) / theta if theta > 0.0 else DEFAULT_AXIS.copy()), theta
    ws = rotation_log_unchecked(a)
    thetas = np.minimum(np.linalg.norm(ws, axis=-1), np.pi)
    positive = thetas > 0.0
    hs = np.where(positive[..., None], ws / np.where(positive, thetas, 1.0)[..., None], DEFAULT_AXIS)
    return hs, thetas
