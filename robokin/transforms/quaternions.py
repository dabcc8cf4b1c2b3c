r"""Unit quaternions, scalar first: :math:`q = (w, x, y, z) = (\cos\tfrac\theta2,\ \sin\tfrac\theta2\, h)`.

:math:`q` and :math:`-q` describe the same rotation; conversions *to*
quaternions return the one with :math:`w \ge 0` (and, if :math:`w = 0`, the
one whose first non-zero vector component is positive). Products are
Hamilton products, so :math:`R(p \otimes q) = R(p)\,R(q)`.

References: Siciliano et al. (2009) §2.6 (unit quaternion, :math:`\eta = w`,
:math:`\epsilon = (x, y, z)`); Lynch & Park (2017) App. B.3.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokin._dispatch import is_symbolic, stack_matrix, stack_vector, to_sympy
from robokin.errors import DomainError, ShapeError
from robokin.transforms.angle_axis import unit_vectors
from robokin.validation import as_batch, as_float_array, as_rotation_matrix, check_result_finite

__all__ = [
    "quaternion_from_rotation",
    "rotation_from_quaternion",
    "quaternion_multiply",
    "quaternion_conjugate",
    "quaternion_slerp",
]


def _quats(q: Any, name: str) -> np.ndarray:
    return as_batch(q, 4, name)[0]


def _sym_quat(q: Any, name: str) -> Any:
    m = to_sympy(q)
    if m.shape not in ((4, 1), (1, 4)):
        raise ShapeError(f"{name} must have 4 entries; got a sympy Matrix of shape {m.shape}")
    return list(m)


def quaternion_from_rotation(R: Any, check: bool = True) -> np.ndarray:
    r"""Unit quaternion of a rotation matrix (Shepperd's method), :math:`w \ge 0`.

    With :math:`t = \operatorname{tr} R`, the symmetric matrix

    .. math::
        4 q q^\mathsf{T} = \begin{bmatrix}
        1 + t & r_{32} - r_{23} & r_{13} - r_{31} & r_{21} - r_{12} \\
        \cdot & 1 + 2r_{11} - t & r_{12} + r_{21} & r_{13} + r_{31} \\
        \cdot & \cdot & 1 + 2r_{22} - t & r_{23} + r_{32} \\
        \cdot & \cdot & \cdot & 1 + 2r_{33} - t \end{bmatrix}

    is formed and :math:`q` is read off the row with the largest diagonal entry
    (so the division is always by a number :math:`\ge 1/2`), normalised, and
    its sign chosen so that :math:`w \ge 0`
    (Shepperd 1978; Siciliano et al. 2009, eq. 2.34).

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrix / matrices.
    check : bool, optional
        Validate that ``R`` is a rotation.

    Returns
    -------
    numpy.ndarray, shape (4,) or (N, 4)
        ``(w, x, y, z)`` with unit norm and ``w >= 0``.
    """
    if is_symbolic(R):
        raise TypeError("quaternion_from_rotation needs a numeric R; got a symbolic matrix")
    a = as_rotation_matrix(R, check)
    if a.ndim == 2:
        return _quaternion_single(a)
    r = lambda i, j: a[..., i - 1, j - 1]  # noqa: E731  (1-based, as in the books)
    t = r(1, 1) + r(2, 2) + r(3, 3)
    a01, a02, a03 = r(3, 2) - r(2, 3), r(1, 3) - r(3, 1), r(2, 1) - r(1, 2)
    a12, a13, a23 = r(1, 2) + r(2, 1), r(1, 3) + r(3, 1), r(2, 3) + r(3, 2)
    Q = np.stack(
        [
            np.stack([1.0 + t, a01, a02, a03], axis=-1),
            np.stack([a01, 1.0 + 2.0 * r(1, 1) - t, a12, a13], axis=-1),
            np.stack([a02, a12, 1.0 + 2.0 * r(2, 2) - t, a23], axis=-1),
            np.stack([a03, a13, a23, 1.0 + 2.0 * r(3, 3) - t], axis=-1),
        ],
        axis=-2,
    )
    k = np.argmax(np.diagonal(Q, axis1=-2, axis2=-1), axis=-1)
    q = np.take_along_axis(Q, k[..., None, None], axis=-2)[..., 0, :]
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return _canonical(q)


def _quaternion_single(R: np.ndarray) -> np.ndarray:
    """Scalar fast path of Shepperd's method for one (3, 3) matrix."""
    (r11, r12, r13), (r21, r22, r23), (r31, r32, r33) = R.tolist()
    t = r11 + r22 + r33
    a01, a02, a03 = r32 - r23, r13 - r31, r21 - r12
    a12, a13, a23 = r12 + r21, r13 + r31, r23 + r32
    rows = (
        (1.0 + t, a01, a02, a03),
        (a01, 1.0 + 2.0 * r11 - t, a12, a13),
        (a02, a12, 1.0 + 2.0 * r22 - t, a23),
        (a03, a13, a23, 1.0 + 2.0 * r33 - t),
    )
    k = max(range(4), key=lambda i: rows[i][i])
    row = rows[k]
    n = math.sqrt(row[0] ** 2 + row[1] ** 2 + row[2] ** 2 + row[3] ** 2)
    lead = next((c for c in row if c != 0.0), 1.0)
    s = (1.0 if lead > 0.0 else -1.0) / n
    return np.array([s * c for c in row])


def _canonical(q: np.ndarray) -> np.ndarray:
    """Flip sign so that w > 0, or w == 0 and the first non-zero of x, y, z > 0."""
    nz = q != 0.0
    first = np.argmax(nz, axis=-1)  # first non-zero component (w if w != 0)
    lead = np.take_along_axis(q, first[..., None], axis=-1)[..., 0]
    return np.where((lead < 0.0)[..., None], -q, q)


def rotation_from_quaternion(q: Any) -> Any:
    r"""Rotation matrix of a quaternion ``(w, x, y, z)`` (normalised first).

    .. math::
        R = \begin{bmatrix}
        1 - 2(y^2 + z^2) & 2(xy - wz) & 2(xz + wy) \\
        2(xy + wz) & 1 - 2(x^2 + z^2) & 2(yz - wx) \\
        2(xz - wy) & 2(yz + wx) & 1 - 2(x^2 + y^2) \end{bmatrix}

    (Siciliano et al. 2009, eq. 2.33.)

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4), or sympy vector
        Quaternion(s), scalar first; any non-zero norm (numeric input is
        normalised). Symbolic input is **assumed to have unit norm**.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3), or sympy.Matrix (3x3)

    Raises
    ------
    DomainError
        Zero (norm < 1e-12) or non-finite quaternion.
    ShapeError
        Not of length 4.
    """
    if is_symbolic(q):
        w, x, y, z = _sym_quat(q, "q")
    else:
        a = unit_vectors(_quats(q, "q"), "q", "a non-zero quaternion")
        w, x, y, z = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    return stack_matrix(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quaternion_multiply(p: Any, q: Any) -> Any:
    r"""Hamilton product :math:`p \otimes q`, so that :math:`R(p \otimes q) = R(p) R(q)`.

    .. math::
        p \otimes q = \big(p_w q_w - p_v \cdot q_v,\;
                      p_w q_v + q_w p_v + p_v \times q_v\big)

    The result is not renormalised and its sign is not changed.

    Parameters
    ----------
    p, q : array_like, shape (4,) or (N, 4), or sympy vectors
        Quaternions ``(w, x, y, z)``; batches broadcast.

    Returns
    -------
    numpy.ndarray, shape (4,) or (N, 4), or sympy.Matrix (4x1)
    """
    if is_symbolic(p, q):
        pw, px, py, pz = _sym_quat(p, "p")
        qw, qx, qy, qz = _sym_quat(q, "q")
    else:
        pa, qa = _quats(p, "p"), _quats(q, "q")
        try:
            np.broadcast_shapes(pa.shape, qa.shape)
        except ValueError:
            raise ShapeError(
                f"p and q have incompatible batch sizes: p has shape {pa.shape}, "
                f"q has shape {qa.shape}"
            ) from None
        pw, px, py, pz = np.moveaxis(pa, -1, 0)
        qw, qx, qy, qz = np.moveaxis(qa, -1, 0)
        with np.errstate(all="ignore"):
            out = stack_vector(
                [
                    pw * qw - px * qx - py * qy - pz * qz,
                    pw * qx + px * qw + py * qz - pz * qy,
                    pw * qy - px * qz + py * qw + pz * qx,
                    pw * qz + px * qy - py * qx + pz * qw,
                ]
            )
        return check_result_finite(out, "the product", p=pa, q=qa)
    return stack_vector(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ]
    )


def quaternion_conjugate(q: Any) -> Any:
    r"""Conjugate :math:`q^* = (w, -x, -y, -z)` (the inverse of a unit quaternion).

    Parameters
    ----------
    q : array_like, shape (4,) or (N, 4), or sympy vector

    Returns
    -------
    numpy.ndarray, shape (4,) or (N, 4), or sympy.Matrix (4x1)
    """
    if is_symbolic(q):
        w, x, y, z = _sym_quat(q, "q")
        return stack_vector([w, -x, -y, -z])
    a = _quats(q, "q")
    return a * np.array([1.0, -1.0, -1.0, -1.0])


def _unit_quaternion(q: Any, name: str) -> np.ndarray:
    """``q`` (4,) divided by its norm, scaled first so that no square overflows or underflows."""
    a = as_float_array(q, name, shape=(4,))
    largest = float(np.max(np.abs(a)))
    if largest == 0.0:
        raise DomainError(f"{name} must be a non-zero quaternion (w, x, y, z); got {a.tolist()}")
    scaled = a / largest
    return scaled / math.sqrt(float(scaled @ scaled))


def quaternion_slerp(q0: Any, q1: Any, s: Any) -> np.ndarray:
    r"""Spherical linear interpolation between two rotations, the short way, at a constant rate.

    The quaternion runs along a great circle of the unit sphere from ``q0`` towards the end
    rotation, its angle from ``q0`` growing in proportion to ``s``: the rotation turns about a
    fixed axis, by the smaller of the two angles that reach the end rotation, at a constant
    angular rate (Shoemake 1985, "Animating rotation with quaternion curves"). Accurate for
    equal and nearly equal rotations too.

    Parameters
    ----------
    q0, q1 : array_like, shape (4,)
        Quaternions ``(w, x, y, z)`` of the start and end rotations (normalised first).
    s : float or array_like, shape (T,)
        Interpolation parameter(s); 0 gives ``q0``, 1 the end rotation. Values outside [0, 1]
        extrapolate along the same great circle.

    Returns
    -------
    numpy.ndarray, shape (4,) or (T, 4)
        Unit quaternions on the arc from ``q0`` (the sign is ``q0``'s side: the path is
        continuous, and its ``w`` may change sign; the rotation is what counts).

    Raises
    ------
    ShapeError, DomainError
        A quaternion not of shape (4,), zero or not finite; ``s`` not finite or of more than
        one dimension.
    """
    a = _unit_quaternion(q0, "q0")
    b = _unit_quaternion(q1, "q1")
    parameter = as_float_array(s, "s")
    if parameter.ndim > 1:
        raise ShapeError(f"s must be a scalar or have shape (T,); got shape {parameter.shape}")
    if a @ b < 0.0:   # -q1 is the same rotation, the short way round
        b = -b
    # the angle between two unit vectors, accurate at both ends: 2 atan2(|a - b|, |a + b|)
    omega = 2.0 * math.atan2(float(np.linalg.norm(a - b)), float(np.linalg.norm(a + b)))
    x = np.atleast_1d(parameter)
    with np.errstate(all="ignore"):
        if omega < 1e-6:   # weights sin(x omega)/sin(omega) = x (1 + (1 - x^2) omega^2 / 6 + ...)
            first = (1.0 - x) * (1.0 + (1.0 - (1.0 - x) ** 2) * omega * omega / 6.0)
            second = x * (1.0 + (1.0 - x * x) * omega * omega / 6.0)
        else:
            first = np.sin((1.0 - x) * omega) / math.sin(omega)
            second = np.sin(x * omega) / math.sin(omega)
        out = first[:, None] * a + second[:, None] * b
        out /= np.linalg.norm(out, axis=-1, keepdims=True)
    check_result_finite(out, "the interpolated quaternions", s=parameter)
    return out[0] if parameter.ndim == 0 else out
