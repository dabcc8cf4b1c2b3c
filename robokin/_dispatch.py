"""Float / NumPy / sympy dispatch helpers.

These let one implementation of a formula serve three kinds of input:

- a Python or NumPy scalar  -> NumPy result of the natural shape, e.g. (3, 3);
- a NumPy array of shape S  -> NumPy result of shape S + natural shape (batched);
- a sympy expression/symbol -> ``sympy.Matrix`` with exact, readable entries.

Example (this is the whole of :func:`robokin.transforms.rotz`)::

    angle = scalar_input(angle, "angle")
    c, s = trig(angle)
    return stack_matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]], like=angle)

Constants in formulas should be written as Python ``int`` (``0``, ``1``,
``2``) so that symbolic results stay exact.

sympy is imported lazily: if nobody has imported sympy, no input can be a
sympy object, so numeric code never pays for importing it.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from typing import Any

import numpy as np

from robokin.errors import DomainError
from robokin.validation import as_float_array

__all__ = [
    "is_symbolic",
    "to_sympy",
    "scalar_input",
    "trig",
    "sqrt",
    "atan2",
    "stack_matrix",
    "stack_vector",
    "matmul",
    "transpose",
]


def _sympy():
    import sympy

    return sympy


def is_symbolic(*xs: Any) -> bool:
    """True if any argument is, or contains, a sympy object.

    Looks into ``sympy.Basic`` (symbols, expressions, exact numbers such as
    ``sympy.pi``), ``sympy`` matrices, lists/tuples and object arrays.
    """
    sp = sys.modules.get("sympy")
    if sp is None:
        return False
    for x in xs:
        if isinstance(x, (float, int, complex)) or x is None:
            continue
        if isinstance(x, np.ndarray):
            if x.dtype == object and any(is_symbolic(e) for e in x.flat):
                return True
            continue
        if isinstance(x, (sp.Basic, sp.MatrixBase)):
            return True
        if isinstance(x, (list, tuple)) and any(is_symbolic(e) for e in x):
            return True
    return False


def _exact(e: Any) -> Any:
    """sympify a number, turning integral floats (1.0) into exact Integers."""
    sp = _sympy()
    if isinstance(e, (bool, np.bool_)):
        return sp.Integer(int(e))
    if isinstance(e, (int, np.integer)):
        return sp.Integer(int(e))
    if isinstance(e, (float, np.floating)):
        f = float(e)
        if not math.isfinite(f):
            raise DomainError(f"symbolic input must be finite; got {f}")
        return sp.Integer(int(f)) if f.is_integer() else sp.Float(f)
    return sp.sympify(e)


def to_sympy(x: Any) -> Any:
    """Convert a number, sequence or matrix to sympy, keeping integers exact.

    Scalars become sympy expressions; sequences / arrays / matrices become a
    ``sympy.Matrix`` (1-D input gives a column vector).
    """
    sp = _sympy()
    if isinstance(x, sp.MatrixBase):
        return sp.Matrix(x).applyfunc(_exact)
    if isinstance(x, (list, tuple, np.ndarray)):
        a = np.asarray(x, dtype=object)
        if a.ndim == 1:
            return sp.Matrix([_exact(e) for e in a])
        if a.ndim == 2:
            return sp.Matrix([[_exact(e) for e in row] for row in a])
        raise ValueError(f"cannot convert an array of shape {a.shape} to a sympy Matrix")
    return _exact(x)


def scalar_input(x: Any, name: str) -> Any:
    """Prepare an angle-like input: float, finite float array, or sympy expression.

    Returns a Python ``float`` for scalars (fast path), a float64 array for
    arrays of any shape, or a sympy expression for symbolic input.

    Raises
    ------
    DomainError
        NaN or infinite entries.
    TypeError
        Non-numeric input.
    """
    if type(x) is float or type(x) is int or isinstance(x, (np.floating, np.integer)):
        v = float(x)
        if not math.isfinite(v):
            raise DomainError(f"{name} must be finite; got {v}")
        return v
    if is_symbolic(x):
        sp = _sympy()
        if isinstance(x, sp.Basic):
            return x
        if isinstance(x, sp.MatrixBase):
            raise TypeError(f"{name} must be a scalar expression; got a sympy Matrix {x.shape}")
        raise TypeError(
            f"{name} must be one number, a numeric array or one sympy expression; "
            "batches of symbolic values are not supported"
        )
    a = as_float_array(x, name)
    return float(a) if a.ndim == 0 else a


def trig(x: Any) -> tuple[Any, Any]:
    """Return ``(cos x, sin x)`` using math, NumPy or sympy as appropriate."""
    if isinstance(x, float):
        return math.cos(x), math.sin(x)
    if isinstance(x, np.ndarray) and x.dtype != object:
        return np.cos(x), np.sin(x)
    if is_symbolic(x):
        sp = _sympy()
        return sp.cos(x), sp.sin(x)
    return np.cos(x), np.sin(x)


def sqrt(x: Any) -> Any:
    """Square root for floats, arrays or sympy expressions."""
    if is_symbolic(x):
        return _sympy().sqrt(x)
    return np.sqrt(x)


def atan2(y: Any, x: Any) -> Any:
    """Two-argument arctangent for floats, arrays or sympy expressions."""
    if is_symbolic(y, x):
        return _sympy().atan2(y, x)
    return np.arctan2(y, x)


def stack_matrix(rows: Sequence[Sequence[Any]], like: Any = None) -> Any:
    """Assemble a matrix from entries that may be scalars, arrays or sympy.

    Parameters
    ----------
    rows : sequence of sequences
        ``rows[i][j]`` is entry (i, j): a number, an array (all arrays must
        broadcast together, common shape ``S``) or a sympy expression.
    like : object, optional
        If ``like`` is symbolic the result is symbolic even when every entry
        happens to be a number.

    Returns
    -------
    numpy.ndarray, shape S + (r, c), or sympy.Matrix (r x c)
        Symbolic if ``like`` or any entry is symbolic; numeric entries are then
        converted exactly (``1.0`` -> ``1``).
    """
    symbolic = is_symbolic(like) or any(is_symbolic(e) for row in rows for e in row)
    if symbolic:
        sp = _sympy()
        return sp.Matrix([[_exact(e) for e in row] for row in rows])
    shapes = [np.shape(e) for row in rows for e in row if not isinstance(e, (int, float))]
    if not shapes or all(s == () for s in shapes):
        return np.array(rows, dtype=float)
    batch = np.broadcast_shapes(*shapes)
    out = np.empty(batch + (len(rows), len(rows[0])))
    for i, row in enumerate(rows):
        for j, e in enumerate(row):
            out[..., i, j] = e
    return out


def stack_vector(entries: Sequence[Any], like: Any = None) -> Any:
    """Assemble a vector; numeric result shape ``S + (n,)``, symbolic a column Matrix."""
    symbolic = is_symbolic(like) or any(is_symbolic(e) for e in entries)
    if symbolic:
        sp = _sympy()
        return sp.Matrix([_exact(e) for e in entries])
    shapes = [np.shape(e) for e in entries if not isinstance(e, (int, float))]
    if not shapes or all(s == () for s in shapes):
        return np.array(entries, dtype=float)
    batch = np.broadcast_shapes(*shapes)
    out = np.empty(batch + (len(entries),))
    for i, e in enumerate(entries):
        out[..., i] = e
    return out


def matmul(A: Any, B: Any) -> Any:
    """Matrix product for NumPy (broadcasting over leading axes) or sympy.

    If either factor is symbolic both are converted to ``sympy.Matrix``
    (integral floats become exact integers) and the product is a Matrix.
    """
    if is_symbolic(A, B):
        return to_sympy(A) * to_sympy(B)
    return np.matmul(A, B)


def transpose(M: Any) -> Any:
    """Transpose of the last two axes (NumPy) or of a sympy Matrix."""
    if is_symbolic(M):
        return to_sympy(M).T
    return np.swapaxes(M, -1, -2)
