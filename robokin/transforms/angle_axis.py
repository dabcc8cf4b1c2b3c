r"""Angle–axis representation and the exponential / logarithm maps of SO(3).

A rotation by angle :math:`\theta` about the unit axis :math:`h` is written as
the rotation vector :math:`w = \theta h`. Rodrigues' formula
(Siciliano et al. 2009, §2.5; Lynch & Park 2017, §3.2.3):

.. math::
    R = \exp([w]_\times) = I + \frac{\sin\theta}{\theta}[w]_\times
        + \frac{1 - \cos\theta}{\theta^2}[w]_\times^2

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
from robokin.validation import as_batch, as_float_array, check_rotation_matrix

__all__ = [
    "rotation_exp",
    "rotation_log",
    "rotation_from_angle_axis",
    "angle_axis_from_rotation",
]

_TAYLOR_TOL = 1e-3  # below this angle the Taylor series are used
_NEAR_PI_COS = -0.9  # below this cos(theta) rotation_log uses the symmetric part
DEFAULT_AXIS = np.array([1.0, 0.0, 0.0])


def _vectors(v: Any, name: str) -> np.ndarray:
    return as_batch(v, 3, name)[0]


def _sym_vector(v: Any, name: str) -> Any:
    m = to_sympy(v)
    if m.shape not in ((3, 1), (1, 3)):
        raise ShapeError(f"{name} must have 3 entries; got a sympy Matrix of shape {m.shape}")
    return m.reshape(3, 1)


def rotation_exp(w: Any) -> Any:
    r"""Rotation matrix of a rotation vector (Rodrigues' formula).

    .. math::
        R = I + A(\theta)[w]_\times + B(\theta)[w]_\times^2,\quad
        A = \frac{\sin\theta}{\theta},\; B = \frac{1-\cos\theta}{\theta^2},\;
        \theta = \|w\|

    For :math:`\theta < 10^{-3}` the Taylor series
    :math:`A = 1 - \theta^2/6 + \theta^4/120`,
    :math:`B = 1/2 - \theta^2/24 + \theta^4/720` are used, so small rotation
    vectors (and exactly zero) are handled without division by zero
    (Lynch & Park 2017, §3.2.3.3; Siciliano et al. 2009, §2.5).

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
        from the unit axis, :math:`R = \cos\theta I + \sin\theta [h]_\times +
        (1 - \cos\theta) h h^\mathsf{T}`, so the result is always a rotation.

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


def _log(R: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return (w, theta, h) for a (..., 3, 3) stack; h = default axis at theta = 0."""
    v = np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0],
                  R[..., 1, 0] - R[..., 0, 1]], axis=-1)  # = 2 sin(theta) h
    s2 = np.linalg.norm(v, axis=-1)  # 2 sin(theta)
    c2 = np.trace(R, axis1=-2, axis2=-1) - 1.0  # 2 cos(theta)
    theta = np.arctan2(s2, c2)
    cos_t = np.clip(0.5 * c2, -1.0, 1.0)

    # generic / small angle: h = v / (2 sin theta)
    pos = s2 > 0.0
    h_gen = np.where(pos[..., None], v / np.where(pos, s2, 1.0)[..., None], DEFAULT_AXIS)

    # near pi: (R + R^T)/2 - cos(theta) I = (1 - cos(theta)) h h^T
    near_pi = cos_t < _NEAR_PI_COS
    if np.any(near_pi):
        Bm = 0.5 * (R + np.swapaxes(R, -1, -2)) - cos_t[..., None, None] * np.eye(3)
        M = Bm / np.where(near_pi, 1.0 - cos_t, 1.0)[..., None, None]
        diag = np.diagonal(M, axis1=-2, axis2=-1)
        k = np.argmax(diag, axis=-1)
        col = np.take_along_axis(M, k[..., None, None], axis=-1)[..., 0]  # M[..., :, k]
        ncol = np.linalg.norm(col, axis=-1, keepdims=True)
        h_pi = col / np.where(ncol > 0.0, ncol, 1.0)  # ncol = 0 only outside near_pi
        sign = np.where(np.einsum("...i,...i->...", h_pi, v) < 0.0, -1.0, 1.0)
        h_pi = sign[..., None] * h_pi
        h = np.where(near_pi[..., None], h_pi, h_gen)
    else:
        h = h_gen

    # w = theta h; for small theta use w = v * theta / (2 sin theta) with a series
    th2 = theta * theta
    small = theta < _TAYLOR_TOL
    w_small = 0.5 * (1.0 + th2 / 6.0 + 7.0 * th2 * th2 / 360.0)[..., None] * v
    w = np.where(small[..., None], w_small, theta[..., None] * h)
    return w, theta, h


def _log_single(R: np.ndarray) -> tuple[np.ndarray, float, np.ndarray]:
    """Scalar fast path of _log for one (3, 3) matrix (same branches)."""
    (r11, r12, r13), (r21, r22, r23), (r31, r32, r33) = R.tolist()
    vx, vy, vz = r32 - r23, r13 - r31, r21 - r12
    s2 = math.sqrt(vx * vx + vy * vy + vz * vz)
    c2 = r11 + r22 + r33 - 1.0
    theta = math.atan2(s2, c2)
    cos_t = min(1.0, max(-1.0, 0.5 * c2))
    if cos_t < _NEAR_PI_COS:
        k1 = 1.0 - cos_t
        M = [
            [(r11 - cos_t) / k1, 0.5 * (r12 + r21) / k1, 0.5 * (r13 + r31) / k1],
            [0.5 * (r12 + r21) / k1, (r22 - cos_t) / k1, 0.5 * (r23 + r32) / k1],
            [0.5 * (r13 + r31) / k1, 0.5 * (r23 + r32) / k1, (r33 - cos_t) / k1],
        ]
        k = max(range(3), key=lambda i: M[i][i])
        col = [M[0][k], M[1][k], M[2][k]]
        n = math.sqrt(col[0] ** 2 + col[1] ** 2 + col[2] ** 2)
        sign = -1.0 if (col[0] * vx + col[1] * vy + col[2] * vz) < 0.0 else 1.0
        h = [sign * c / n for c in col]
    elif s2 > 0.0:
        h = [vx / s2, vy / s2, vz / s2]
    else:
        h = DEFAULT_AXIS.tolist()
    if theta < _TAYLOR_TOL:
        th2 = theta * theta
        f = 0.5 * (1.0 + th2 / 6.0 + 7.0 * th2 * th2 / 360.0)
        w = [f * vx, f * vy, f * vz]
    else:
        w = [theta * c for c in h]
    return np.array(w), theta, np.array(h)


def _rotation_input(R: Any, check: bool) -> np.ndarray:
    if check:
        return check_rotation_matrix(R, name="R")
    a = as_float_array(R, "R")
    if a.ndim not in (2, 3) or a.shape[-2:] != (3, 3):
        raise ShapeError(f"R must have shape (3, 3) or (N, 3, 3); got shape {a.shape}")
    return a


def rotation_log(R: Any, check: bool = True) -> np.ndarray:
    r"""Rotation vector :math:`w = \theta h` of a rotation matrix (inverse of :func:`rotation_exp`).

    .. math::
        \theta = \operatorname{atan2}\!\Big(\tfrac12\|\operatorname{vee}(R - R^\mathsf{T})\|,\;
                 \tfrac12(\operatorname{tr}R - 1)\Big) \in [0, \pi], \qquad
        w = \frac{\theta}{2\sin\theta}\operatorname{vee}(R - R^\mathsf{T})

    Robust everywhere:

    - :math:`\theta \to 0`: the factor :math:`\theta / (2\sin\theta)` is
      replaced by its Taylor series :math:`\tfrac12(1 + \theta^2/6 + 7\theta^4/360)`.
    - :math:`\theta \to \pi` (:math:`\cos\theta < -0.9`): no division by
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
    a = _rotation_input(R, check)
    return _log_single(a)[0] if a.ndim == 2 else _log(a)[0]


def rotation_from_angle_axis(axis: Any, angle: Any) -> Any:
    r"""Rotation by ``angle`` about ``axis`` (normalised first).

    .. math::
        R = \cos\theta\, I + \sin\theta\, [h]_\times + (1 - \cos\theta)\, h h^\mathsf{T},
        \qquad h = \frac{\text{axis}}{\|\text{axis}\|}

    (Siciliano et al. 2009, §2.5.)

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
    try:
        n = vector_norms(a)
    except DomainError:
        raise DomainError(f"axis is too large: its norm overflows float64 (largest |axis| = "
                          f"{float(np.abs(a).max()):.3g})") from None
    if np.any(n < 1e-12):
        raise DomainError(
            f"axis must be non-zero; got norm {float(np.min(n)):.3g}"
            + (f" at index {int(np.argmin(n))}" if a.ndim == 2 else "")
        )
    h = a / n[..., None]
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


def vector_norms(a: np.ndarray) -> np.ndarray:
    """Euclidean norms of the rows of ``a`` (..., k), without overflow for huge entries.

    The plain ``np.linalg.norm`` everywhere it is finite (so ordinary input gives
    the same bits as before); rows whose squares overflow are scaled first.
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
            raise DomainError(f"the norm of a vector overflows float64 (largest entry {float(m.max()):.3g})")
    return n


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
    a = _rotation_input(R, check)
    if a.ndim == 2:
        _, theta, h = _log_single(a)
        return h, theta
    _, thetas, hs = _log(a)
    return hs, thetas
