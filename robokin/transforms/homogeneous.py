r"""Homogeneous transforms :math:`T \in SE(3)`.

.. math::
    T_{AB} = \begin{bmatrix} R_{AB} & p_{AB,A} \\ 0^\mathsf{T} & 1 \end{bmatrix},
    \qquad p_A = T_{AB}\, p_B

``T_AB`` maps B-coordinates to A-coordinates; compose by matching inner
letters, ``T_AC = compose(T_AB, T_BC)``.

Numeric results have shape (4, 4) or, batched, (N, 4, 4); sympy input gives a
4x4 ``sympy.Matrix``.

References: Siciliano et al. (2009) §2.7; Lynch & Park (2017) §3.3.1.
"""

from __future__ import annotations

from functools import reduce
from typing import Any

import numpy as np

from robokin._dispatch import is_symbolic, to_sympy
from robokin.errors import ShapeError
from robokin.validation import as_float_array, check_result_finite, check_rotation_matrix, check_transform

__all__ = [
    "transform",
    "translation",
    "transform_inverse",
    "compose",
    "rotation_of",
    "translation_of",
    "transform_point",
]


def _sym_matrix(x: Any, shape: tuple[int, int], name: str) -> Any:
    m = to_sympy(x)
    if shape[1] == 1 and m.shape == (1, shape[0]):
        m = m.T
    if m.shape != shape:
        raise ShapeError(f"{name} must have shape {shape}; got a sympy Matrix of shape {m.shape}")
    return m


def _sym_transform(R: Any, p: Any) -> Any:
    import sympy as sp

    return sp.Matrix.vstack(sp.Matrix.hstack(R, p), sp.Matrix([[0, 0, 0, 1]]))


def _points(p: Any, name: str = "p") -> np.ndarray:
    a = as_float_array(p, name)
    if a.ndim not in (1, 2) or a.shape[-1] != 3:
        raise ShapeError(f"{name} must have shape (3,) or (N, 3); got shape {a.shape}")
    return a


def _transforms(T: Any, check: bool, name: str = "T") -> np.ndarray:
    if check:
        return check_transform(T, name=name)
    a = as_float_array(T, name)
    if a.ndim not in (2, 3) or a.shape[-2:] != (4, 4):
        raise ShapeError(f"{name} must have shape (4, 4) or (N, 4, 4); got shape {a.shape}")
    return a


def _assemble(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    batch = np.broadcast_shapes(R.shape[:-2], p.shape[:-1])
    out = np.zeros(batch + (4, 4))
    out[..., :3, :3] = R
    out[..., :3, 3] = p
    out[..., 3, 3] = 1.0
    return out


def transform(R: Any, p: Any, check: bool = True) -> Any:
    r"""Homogeneous transform from a rotation and a translation.

    .. math:: T = \begin{bmatrix} R & p \\ 0 & 1 \end{bmatrix}

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3), or sympy.Matrix
        Rotation part.
    p : array_like, shape (3,) or (N, 3), or sympy vector
        Translation part. A single ``R`` and a batch of ``p`` (or vice versa)
        broadcast.
    check : bool, optional
        Validate that ``R`` is a rotation matrix (numeric input).

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4), or sympy.Matrix (4x4)

    Raises
    ------
    ShapeError
        Wrong shapes, or batch sizes that do not match.
    DomainError
        ``R`` is not a rotation (with ``check``), or non-finite entries.
    """
    if is_symbolic(R, p):
        return _sym_transform(_sym_matrix(R, (3, 3), "R"), _sym_matrix(p, (3, 1), "p"))
    if check:
        Ra = check_rotation_matrix(R, name="R")
    else:
        Ra = as_float_array(R, "R")
        if Ra.ndim not in (2, 3) or Ra.shape[-2:] != (3, 3):
            raise ShapeError(f"R must have shape (3, 3) or (N, 3, 3); got shape {Ra.shape}")
    pa = _points(p)
    try:
        return _assemble(Ra, pa)
    except ValueError:
        raise ShapeError(
            f"R and p have incompatible batch sizes: R has shape {Ra.shape}, p has shape {pa.shape}"
        ) from None


def translation(p: Any) -> Any:
    r"""Pure translation :math:`T = \begin{bmatrix} I & p \\ 0 & 1 \end{bmatrix}`.

    Parameters
    ----------
    p : array_like, shape (3,) or (N, 3), or sympy vector
        Translation(s).

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4), or sympy.Matrix (4x4)
    """
    if is_symbolic(p):
        import sympy as sp

        return _sym_transform(sp.eye(3), _sym_matrix(p, (3, 1), "p"))
    return _assemble(np.eye(3), _points(p))


def transform_inverse(T: Any, check: bool = True) -> Any:
    r"""Inverse of a homogeneous transform, using :math:`R^{-1} = R^\mathsf{T}`.

    .. math::
        T^{-1} = \begin{bmatrix} R^\mathsf{T} & -R^\mathsf{T} p \\ 0 & 1 \end{bmatrix},
        \qquad T_{BA} = T_{AB}^{-1}

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4), or sympy.Matrix
        Transform(s).
    check : bool, optional
        Validate that ``T`` is a homogeneous transform (numeric input). Without
        the check the result is only the inverse if ``T`` is one.

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4), or sympy.Matrix (4x4)
    """
    if is_symbolic(T):
        M = _sym_matrix(T, (4, 4), "T")
        R, p = M[:3, :3], M[:3, 3]
        return _sym_transform(R.T, -R.T * p)
    a = _transforms(T, check)
    Rt = np.swapaxes(a[..., :3, :3], -1, -2)
    p = a[..., :3, 3]
    if not check:
        return _assemble(Rt, -(Rt @ p[..., None])[..., 0])
    with np.errstate(all="ignore"):
        out = _assemble(Rt, -(Rt @ p[..., None])[..., 0])
    return check_result_finite(out, "the inverse transform", T=a)


def compose(*Ts: Any, check: bool = True) -> Any:
    r"""Product of transforms, left to right: ``compose(T_AB, T_BC) = T_AB @ T_BC``.

    .. math:: T_{AC} = T_{AB}\,T_{BC}

    Parameters
    ----------
    *Ts : array_like, shape (4, 4) or (N, 4, 4), or sympy.Matrix
        Transforms; batched ones broadcast against single ones. No argument
        gives the identity.
    check : bool, optional
        Validate every factor (numeric input) and that the product does not
        overflow (translations near the float64 limit).

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4), or sympy.Matrix (4x4)

    Raises
    ------
    ShapeError, DomainError
        A factor of the wrong shape or not a transform (the message names
        ``Ts[i]``), batch sizes that do not match, or a product that overflows.
    """
    if not Ts:
        return np.eye(4)
    if is_symbolic(*Ts):
        return reduce(lambda A, B: A * B,
                      [_sym_matrix(T, (4, 4), f"Ts[{i}]") for i, T in enumerate(Ts)])
    arrs = [_transforms(T, check, f"Ts[{i}]") for i, T in enumerate(Ts)]
    try:
        with np.errstate(all="ignore"):
            out = reduce(np.matmul, arrs) if len(arrs) > 1 else arrs[0].copy()
    except ValueError:
        raise ShapeError(
            "transforms have incompatible batch sizes: shapes "
            + ", ".join(str(a.shape) for a in arrs)
        ) from None
    if check:
        check_result_finite(out, "the product", **{f"Ts[{i}]": a for i, a in enumerate(arrs)})
    return out


def rotation_of(T: Any, check: bool = True) -> Any:
    """Rotation part ``T[:3, :3]``.

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4), or sympy.Matrix
    check : bool, optional
        Validate that ``T`` is a homogeneous transform (numeric input): a
        matrix whose upper-left block is not a rotation, or whose bottom row is
        not ``[0, 0, 0, 1]``, raises instead of returning a block that is no
        rotation. ``False`` just copies the block.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3) (a copy), or sympy.Matrix (3x3)

    Raises
    ------
    ShapeError, DomainError
        ``T`` of the wrong shape, non-finite, or (with ``check``) not a
        homogeneous transform.
    """
    if is_symbolic(T):
        return _sym_matrix(T, (4, 4), "T")[:3, :3]
    return _transforms(T, check)[..., :3, :3].copy()


def translation_of(T: Any, check: bool = True) -> Any:
    """Translation part ``T[:3, 3]``.

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4), or sympy.Matrix
    check : bool, optional
        Validate that ``T`` is a homogeneous transform (numeric input), as in
        :func:`rotation_of`.

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3) (a copy), or sympy.Matrix (3x1)

    Raises
    ------
    ShapeError, DomainError
        ``T`` of the wrong shape, non-finite, or (with ``check``) not a
        homogeneous transform.
    """
    if is_symbolic(T):
        return _sym_matrix(T, (4, 4), "T")[:3, 3]
    return _transforms(T, check)[..., :3, 3].copy()


def transform_point(T: Any, p: Any, check: bool = True) -> Any:
    r"""Apply a transform to point(s): :math:`p_A = R_{AB}\,p_B + p_{AB}`.

    Leading axes broadcast:

    - ``T`` (4, 4),    ``p`` (3,)   -> (3,)
    - ``T`` (4, 4),    ``p`` (M, 3) -> (M, 3)  (all points by one transform)
    - ``T`` (N, 4, 4), ``p`` (3,)   -> (N, 3)  (one point by every transform)
    - ``T`` (N, 4, 4), ``p`` (N, 3) -> (N, 3)  (pairwise)

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4), or sympy.Matrix
        Transform(s) ``T_AB``.
    p : array_like, shape (3,) or (M, 3), or sympy vector
        Point(s) in B-coordinates.
    check : bool, optional
        Validate ``T`` (numeric input) and that the result does not overflow.

    Returns
    -------
    numpy.ndarray, shape (3,), (M, 3) or (N, 3), or sympy.Matrix (3x1)

    Raises
    ------
    ShapeError, DomainError
        Wrong shapes, ``T`` not a transform, non-finite entries, or a result
        that overflows float64 (coordinates near 1e308).
    """
    if is_symbolic(T, p):
        M = _sym_matrix(T, (4, 4), "T")
        return M[:3, :3] * _sym_matrix(p, (3, 1), "p") + M[:3, 3]
    a = _transforms(T, check)
    pa = _points(p)
    try:
        with np.errstate(all="ignore"):
            out = (a[..., :3, :3] @ pa[..., None])[..., 0] + a[..., :3, 3]
    except ValueError:
        raise ShapeError(
            f"T and p have incompatible batch sizes: T has shape {a.shape}, p has shape {pa.shape}"
        ) from None
    return check_result_finite(out, "the transformed point", T=a, p=pa) if check else out
