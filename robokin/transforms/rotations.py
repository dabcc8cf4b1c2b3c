r"""Elementary rotations and the skew-symmetric (hat) operator.

Every function accepts

- a float                          -> ``numpy.ndarray`` of shape (3, 3);
- an array of angles of shape S    -> array of shape S + (3, 3) (e.g. (N,) -> (N, 3, 3));
- a sympy symbol or expression     -> ``sympy.Matrix`` 3x3 with exact entries.

References: Siciliano et al. (2009) §2.2 (elementary rotations), §3.1.1
(skew-symmetric matrices); Lynch & Park (2017) §3.2.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin._dispatch import is_symbolic, scalar_input, stack_matrix, stack_vector, to_sympy, trig
from robokin.errors import DomainError, ShapeError
from robokin.validation import as_float_array

__all__ = ["rotx", "roty", "rotz", "skew", "unskew"]


def rotx(angle: Any) -> Any:
    r"""Rotation about the x axis by ``angle`` (radians).

    The active rotation: it turns a vector counterclockwise about the x axis
    seen from its tip (right-hand rule; Siciliano et al. 2009, §2.2.1).

    Parameters
    ----------
    angle : float, array_like of shape S, or sympy expression
        Rotation angle(s) in radians.

    Returns
    -------
    numpy.ndarray of shape (3, 3) or S + (3, 3), or sympy.Matrix (3x3)

    Raises
    ------
    DomainError
        NaN or infinite angle.

    Examples
    --------
    >>> rotx(0.0)
    array([[ 1.,  0.,  0.],
           [ 0.,  1., -0.],
           [ 0.,  0.,  1.]])
    """
    angle = scalar_input(angle, "angle")
    c, s = trig(angle)
    if type(angle) is float:  # one number (the common call): the entries as they are, no dispatch
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    return stack_matrix([[1, 0, 0], [0, c, -s], [0, s, c]], like=angle)


def roty(angle: Any) -> Any:
    r"""Rotation about the y axis by ``angle`` (radians).

    The active rotation: it turns a vector counterclockwise about the y axis
    seen from its tip (right-hand rule; Siciliano et al. 2009, §2.2.1).

    Parameters
    ----------
    angle : float, array_like of shape S, or sympy expression
        Rotation angle(s) in radians.

    Returns
    -------
    numpy.ndarray of shape (3, 3) or S + (3, 3), or sympy.Matrix (3x3)
    """
    angle = scalar_input(angle, "angle")
    c, s = trig(angle)
    if type(angle) is float:  # one number (the common call): the entries as they are, no dispatch
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return stack_matrix([[c, 0, s], [0, 1, 0], [-s, 0, c]], like=angle)


def rotz(angle: Any) -> Any:
    r"""Rotation about the z axis by ``angle`` (radians).

    The active rotation: it turns a vector counterclockwise about the z axis
    seen from its tip (right-hand rule; Siciliano et al. 2009, §2.2.1).

    Parameters
    ----------
    angle : float, array_like of shape S, or sympy expression
        Rotation angle(s) in radians.

    Returns
    -------
    numpy.ndarray of shape (3, 3) or S + (3, 3), or sympy.Matrix (3x3)

    Examples
    --------
    ``rotz(pi/2)`` maps the x axis onto the y axis:

    >>> import numpy as np
    >>> np.round(rotz(np.pi / 2) @ [1.0, 0.0, 0.0], 12) + 0.0
    array([0., 1., 0.])
    """
    angle = scalar_input(angle, "angle")
    c, s = trig(angle)
    if type(angle) is float:  # one number (the common call): the entries as they are, no dispatch
        return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    return stack_matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]], like=angle)


def _symbolic_vector(v: Any, name: str, n: int = 3) -> Any:
    m = to_sympy(v)
    if m.shape not in ((n, 1), (1, n)):
        raise ShapeError(f"{name} must have shape ({n},); got a sympy Matrix of shape {m.shape}")
    return m.reshape(n, 1)


def skew(v: Any) -> Any:
    r"""Skew-symmetric matrix of a 3-vector ("hat" operator).

    The matrix :math:`[v]_\times` with :math:`[v]_\times u = v \times u` for every
    :math:`u` (Siciliano et al. 2009, §3.1.1; Lynch & Park 2017, §3.2).

    Parameters
    ----------
    v : array_like, shape (3,) or (N, 3), or sympy vector
        Vector(s).

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3), or sympy.Matrix (3x3)

    Raises
    ------
    ShapeError
        Last axis not of length 3.
    """
    if is_symbolic(v):
        x, y, z = _symbolic_vector(v, "v")
        return stack_matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    a = as_float_array(v, "v")
    if a.ndim not in (1, 2) or a.shape[-1] != 3:
        raise ShapeError(f"v must have shape (3,) or (N, 3); got shape {a.shape}")
    x, y, z = a[..., 0], a[..., 1], a[..., 2]
    return stack_matrix([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def unskew(S: Any, check: bool = True, tol: float = 1e-6) -> Any:
    r"""Vector of a skew-symmetric matrix ("vee" operator), inverse of :func:`skew`.

    Returns :math:`v = (S_{32}, S_{13}, S_{21})` computed from the
    skew-symmetric part :math:`(S - S^\mathsf{T})/2`, so a slightly
    non-skew input gives the nearest answer.

    Parameters
    ----------
    S : array_like, shape (3, 3) or (N, 3, 3), or sympy.Matrix
        Skew-symmetric matrix / matrices.
    check : bool, optional
        Verify that ``S + Sᵀ ≈ 0`` (numeric input only).
    tol : float, optional
        Tolerance of the check.

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3), or sympy.Matrix (3x1)

    Raises
    ------
    ShapeError
        Wrong shape.
    DomainError
        ``check`` and ``max |S + Sᵀ| > tol``.
    """
    if is_symbolic(S):
        M = to_sympy(S)
        if M.shape != (3, 3):
            raise ShapeError(f"S must have shape (3, 3); got a sympy Matrix of shape {M.shape}")
        return stack_vector([M[2, 1], M[0, 2], M[1, 0]])
    a = as_float_array(S, "S")
    if a.ndim not in (2, 3) or a.shape[-2:] != (3, 3):
        raise ShapeError(f"S must have shape (3, 3) or (N, 3, 3); got shape {a.shape}")
    if check:
        with np.errstate(over="ignore"):  # huge entries: |S + Sᵀ| may overflow to inf (then not skew)
            err = float(np.abs(a + np.swapaxes(a, -1, -2)).max(initial=0.0))
        if err > tol:
            raise DomainError(
                f"S is not skew-symmetric: max |S + Sᵀ| = {err:.3g} (tolerance {tol:g})"
            )
    h = 0.5 * a  # halve first: (S32 - S23) / 2 of two huge entries would overflow
    return np.stack(
        [h[..., 2, 1] - h[..., 1, 2], h[..., 0, 2] - h[..., 2, 0], h[..., 1, 0] - h[..., 0, 1]],
        axis=-1,
    )
