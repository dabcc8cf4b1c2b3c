"""Argument checks shared by the whole package.

Every function takes the argument's *name* so that error messages say which
argument was wrong, what was expected and what came in, e.g.::

    ShapeError: q must have shape (6,) or (N, 6); got shape (5,)
    DomainError: R is not a rotation matrix: R Rᵀ − I has max |entry| 0.31
                 (tolerance 1e-06), det(R) = -1.0

Each check returns the validated (and, where needed, converted) value, so the
idiom is ``q = as_vector(q, 6, "q")``.

Shape specifications are tuples in which ``-1`` or ``None`` means "any length";
they are printed with ``N`` in that place, e.g. ``(N, 3)``.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from typing import Any, TypeVar

import numpy as np

from robokin.errors import DomainError, ShapeError

__all__ = [
    "as_float_array",
    "check_finite",
    "as_vector",
    "as_batch",
    "as_scalar",
    "check_rotation_matrix",
    "as_rotation_matrix",
    "check_transform",
    "check_limits",
    "check_positive",
    "check_length",
    "check_int",
    "check_choice",
    "check_callable",
    "check_chain",
    "check_result_finite",
    "format_shape",
]

ShapeSpec = Sequence[int | None]


def format_shape(shape: ShapeSpec) -> str:
    """Format a shape specification, writing ``N`` for free dimensions.

    >>> format_shape((None, 3))
    '(N, 3)'
    >>> format_shape((6,))
    '(6,)'
    """
    parts = ["N" if (d is None or d == -1) else str(int(d)) for d in shape]
    if len(parts) == 1:
        return f"({parts[0]},)"
    return "(" + ", ".join(parts) + ")"


def _shape_matches(actual: tuple[int, ...], spec: ShapeSpec) -> bool:
    if len(actual) != len(spec):
        return False
    return all(d is None or d == -1 or a == d for a, d in zip(actual, spec))


def _describe(x: Any) -> str:
    """Short description of an input value for error messages."""
    r = repr(x)
    if len(r) > 60:
        r = r[:57] + "..."
    return f"{type(x).__name__} {r}"


def _first_nonfinite(a: np.ndarray) -> str:
    bad = ~np.isfinite(a)
    idx = tuple(int(i) for i in np.argwhere(bad)[0])
    val = a[idx]
    where = f" at index {idx}" if a.ndim > 0 else ""
    return f"{val}{where}"


def as_float_array(x: Any, name: str, shape: ShapeSpec | None = None) -> np.ndarray:
    """Convert ``x`` to a finite float64 array, optionally checking its shape.

    Parameters
    ----------
    x : array_like
        Numbers: a scalar, a (nested) list/tuple or an array.
    name : str
        Name of the argument, used in error messages.
    shape : tuple of int or None, optional
        Expected shape; ``-1`` or ``None`` entries accept any length.
        ``None`` (the default) accepts any shape.

    Returns
    -------
    numpy.ndarray
        ``float64`` array (a view of ``x`` if it already was one).

    Raises
    ------
    TypeError
        If ``x`` is not numeric (strings, objects, complex numbers, sympy
        expressions with free symbols, ...).
    ShapeError
        If the shape does not match ``shape`` (or ``x`` is ragged).
    DomainError
        If any entry is NaN or infinite.
    """
    if isinstance(x, np.ndarray) and x.dtype == np.float64:
        a = x
    else:
        try:
            a = np.asarray(x)
        except ValueError:  # ragged nested sequences
            raise ShapeError(
                f"{name} must be a rectangular array of numbers; got a ragged sequence "
                f"{_describe(x)}"
            ) from None
        if a.dtype.kind in "biuf":
            a = a.astype(np.float64, copy=False)
        else:
            try:
                if a.dtype.kind in "cUSV" or any(e is None for e in a.flat):
                    raise TypeError
                a = a.astype(np.float64)
            except (TypeError, ValueError):
                raise TypeError(
                    f"{name} must contain real numbers; got {_describe(x)}"
                    + (f" (dtype {a.dtype})" if a.dtype != object else "")
                ) from None
    if shape is not None and not _shape_matches(a.shape, shape):
        raise ShapeError(
            f"{name} must have shape {format_shape(shape)}; got shape {a.shape}"
        )
    if not np.isfinite(a).all():
        raise DomainError(f"{name} must be finite; got {_first_nonfinite(a)}")
    return a


def check_finite(x: Any, name: str) -> np.ndarray:
    """Check that every entry of ``x`` is finite (no NaN, no ±inf).

    Parameters
    ----------
    x : array_like
        Numbers of any shape.
    name : str
        Argument name for messages.

    Returns
    -------
    numpy.ndarray
        ``x`` as a float64 array.

    Raises
    ------
    DomainError
        If an entry is NaN or infinite; the message gives the first such entry.
    TypeError
        If ``x`` is not numeric.
    """
    return as_float_array(x, name)


def as_vector(x: Any, length: int | None, name: str) -> np.ndarray:
    """Convert ``x`` to a finite float vector of shape ``(length,)``.

    Parameters
    ----------
    x : array_like
        Sequence of numbers.
    length : int or None
        Required length; ``None`` accepts any length.
    name : str
        Argument name for messages.

    Returns
    -------
    numpy.ndarray, shape (length,)

    Raises
    ------
    ShapeError
        E.g. ``p must have shape (3,); got shape (2,)``.
    DomainError, TypeError
        As in :func:`as_float_array`.
    """
    return as_float_array(x, name, (length,))


def as_batch(x: Any, width: int | None, name: str) -> tuple[np.ndarray, bool]:
    """Accept a single row ``(width,)`` or a batch ``(N, width)``.

    Parameters
    ----------
    x : array_like, shape (width,) or (N, width)
        One vector or a batch of vectors (e.g. joint configurations).
    width : int or None
        Length of each vector; ``None`` accepts any.
    name : str
        Argument name for messages.

    Returns
    -------
    array : numpy.ndarray, shape (width,) or (N, width)
        ``x`` as a finite float array, *in the shape it came in*. Use
        ``array.reshape(-1, width)`` to always work on a batch.
    is_batched : bool
        ``True`` if ``x`` was 2-D.

    Raises
    ------
    ShapeError
        E.g. ``q must have shape (6,) or (N, 6); got shape (5,)``.
    DomainError, TypeError
        As in :func:`as_float_array`.
    """
    a = as_float_array(x, name)
    if a.ndim == 1 and _shape_matches(a.shape, (width,)):
        return a, False
    if a.ndim == 2 and _shape_matches(a.shape, (None, width)):
        return a, True
    raise ShapeError(
        f"{name} must have shape {format_shape((width,))} or "
        f"{format_shape((None, width))}; got shape {a.shape}"
    )


def _as_square_stack(x: Any, n: int, name: str) -> np.ndarray:
    a = as_float_array(x, name)
    if a.ndim not in (2, 3) or a.shape[-2:] != (n, n):
        raise ShapeError(
            f"{name} must have shape ({n}, {n}) or (N, {n}, {n}); got shape {a.shape}"
        )
    return a


def _rotation_defect(R: np.ndarray) -> tuple[Any, Any]:
    """Max |R Rᵀ − I| and det(R): floats for one (3, 3) matrix, arrays (N,) for a stack."""
    if R.ndim == 2:  # fast path for a single matrix
        (a, b, c), (d, e, f), (g, h, i) = R.tolist()
        err = max(
            abs(a * a + b * b + c * c - 1.0),
            abs(d * d + e * e + f * f - 1.0),
            abs(g * g + h * h + i * i - 1.0),
            abs(a * d + b * e + c * f),
            abs(a * g + b * h + c * i),
            abs(d * g + e * h + f * i),
        )
        det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
        return err, det
    err = np.abs(R @ np.swapaxes(R, -1, -2) - np.eye(3)).max(axis=(-2, -1))
    det = np.linalg.det(R)
    return err, det


def check_rotation_matrix(R: Any, tol: float = 1e-6, name: str = "R") -> np.ndarray:
    r"""Check that ``R`` is a rotation matrix (or a stack of them).

    A rotation matrix satisfies :math:`R R^\mathsf{T} = I` and
    :math:`\det R = +1` (Siciliano et al. 2009, §2.2).

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Candidate rotation matrix / matrices.
    tol : float, optional
        Tolerance on ``max |R Rᵀ − I|`` and on ``|det R − 1|``.
    name : str, optional
        Argument name for messages.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3)
        ``R`` as a float array.

    Raises
    ------
    ShapeError
        Wrong shape.
    DomainError
        Not orthonormal or a reflection (det −1). For a stack the message names
        the first bad index.
    """
    a = _as_square_stack(R, 3, name)
    err, det = _rotation_defect(a)
    if a.ndim == 2:
        if err <= tol and abs(det - 1.0) <= tol:
            return a
        bad = np.array(True)
    else:
        bad = (err > tol) | (np.abs(det - 1.0) > tol)
    if np.any(bad):
        if a.ndim == 3:
            i = int(np.argmax(bad))
            where, e, d = f"{name}[{i}]", err[i], det[i]
        else:
            where, e, d = name, err, det
        raise DomainError(
            f"{where} is not a rotation matrix: {name} {name}ᵀ − I has max |entry| "
            f"{float(e):.3g} (tolerance {tol:g}), det({name}) = {float(d):.6g}"
        )
    return a


def as_rotation_matrix(R: Any, check: bool = True, name: str = "R") -> np.ndarray:
    """``R`` as a float array of rotation matrices: checked as one (``check``) or by shape only.

    The input of the conversions from a rotation matrix (angle–axis, Euler angles,
    quaternions), whose ``check=False`` skips the orthonormality test in hot loops.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrix / matrices.
    check : bool, optional
        Also check that ``R`` is a rotation (:func:`check_rotation_matrix`); else
        only its shape.
    name : str, optional
        Argument name for messages.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or (N, 3, 3)

    Raises
    ------
    ShapeError
        Wrong shape.
    DomainError
        Non-finite entries, or (``check``) not a rotation.
    """
    return check_rotation_matrix(R, name=name) if check else _as_square_stack(R, 3, name)


def check_transform(T: Any, tol: float = 1e-6, name: str = "T") -> np.ndarray:
    """Check that ``T`` is a homogeneous transform (or a stack of them).

    ``T = [[R, p], [0, 0, 0, 1]]`` with ``R`` a rotation matrix
    (Siciliano et al. 2009, §2.7).

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4)
        Candidate transform(s).
    tol : float, optional
        Tolerance for the bottom row and the rotation part.
    name : str, optional
        Argument name for messages.

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4)

    Raises
    ------
    ShapeError
        Wrong shape.
    DomainError
        Bottom row not ``[0, 0, 0, 1]`` or rotation part not a rotation.
    """
    a = _as_square_stack(T, 4, name)
    bottom = a[..., 3, :]
    dev = np.abs(bottom - np.array([0.0, 0.0, 0.0, 1.0])).max(axis=-1)
    if np.any(dev > tol):
        if a.ndim == 3:
            i = int(np.argmax(dev > tol))
            where, row = f"{name}[{i}]", bottom[i]
        else:
            where, row = name, bottom
        raise DomainError(
            f"{where} is not a homogeneous transform: bottom row must be [0, 0, 0, 1] "
            f"(tolerance {tol:g}); got {np.array2string(row, precision=6)}"
        )
    check_rotation_matrix(a[..., :3, :3], tol=tol, name=f"{name}[:3, :3]")
    return a


def check_limits(limits: Any, n: int | None, name: str = "limits") -> np.ndarray:
    """Check joint limits given as rows ``(lower, upper)``.

    Parameters
    ----------
    limits : array_like, shape (n, 2)
        ``limits[i] = (lower_i, upper_i)``. Infinite values are allowed
        (``(-inf, inf)`` means unlimited), NaN is not.
    n : int or None
        Number of joints; ``None`` accepts any.
    name : str, optional
        Argument name for messages.

    Returns
    -------
    numpy.ndarray, shape (n, 2)

    Raises
    ------
    ShapeError
        Wrong shape.
    DomainError
        NaN entries, or ``lower > upper`` for some joint.
    TypeError
        Non-numeric entries.
    """
    try:
        a = np.asarray(limits)
        if a.dtype.kind not in "biuf":
            if a.dtype.kind in "cUSV":
                raise TypeError
            a = a.astype(np.float64)
        a = a.astype(np.float64, copy=False)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must contain real numbers; got {_describe(limits)}") from None
    if not _shape_matches(a.shape, (n, 2)):
        raise ShapeError(f"{name} must have shape {format_shape((n, 2))}; got shape {a.shape}")
    if np.isnan(a).any():
        raise DomainError(f"{name} must not contain NaN; got NaN at index "
                          f"{tuple(int(i) for i in np.argwhere(np.isnan(a))[0])}")
    bad = a[:, 0] > a[:, 1]
    if bad.any():
        i = int(np.argmax(bad))
        raise DomainError(
            f"{name} must have lower <= upper in every row; row {i} has "
            f"lower = {a[i, 0]:g} > upper = {a[i, 1]:g}"
        )
    return a


def check_positive(value: Any, name: str, allow_zero: bool = False, *, scalar: bool = False) -> Any:
    """Check that a number (or every entry of an array) is positive.

    Parameters
    ----------
    value : float or array_like
        Number(s) to check; must be finite.
    name : str
        Argument name for messages.
    allow_zero : bool, optional
        Accept 0 (i.e. check ``>= 0`` instead of ``> 0``).
    scalar : bool, optional
        Require a single number (a tolerance, a gain, a time step): an array
        raises :class:`ShapeError`.

    Returns
    -------
    float or numpy.ndarray
        A Python ``float`` for scalar input, otherwise a float array.

    Raises
    ------
    DomainError
        ``value`` not finite or not positive (non-negative).
    ShapeError
        ``scalar`` and ``value`` is an array of several numbers.
    TypeError
        Non-numeric ``value`` (or a bool).
    """
    if scalar:
        value = as_scalar(value, name)
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        v = float(value)
        if not math.isfinite(v):
            raise DomainError(f"{name} must be finite; got {v}")
        ok = v >= 0.0 if allow_zero else v > 0.0
        if not ok:
            what = "non-negative (>= 0)" if allow_zero else "positive (> 0)"
            raise DomainError(f"{name} must be {what}; got {v:g}")
        return v
    a = as_float_array(value, name)
    ok_entries = a >= 0.0 if allow_zero else a > 0.0
    if not np.all(ok_entries):
        what = "non-negative (>= 0)" if allow_zero else "positive (> 0)"
        if a.ndim == 0:
            raise DomainError(f"{name} must be {what}; got {float(a):g}")
        idx = tuple(int(i) for i in np.argwhere(~ok_entries)[0])
        raise DomainError(f"{name} must be {what}; got {a[idx]:g} at index {idx}")
    return float(a) if a.ndim == 0 else a


def as_scalar(x: Any, name: str) -> float:
    """Convert one real number to a finite Python ``float``.

    Parameters
    ----------
    x : float, int, numpy scalar or 0-d / single-element array
        The number (e.g. a time ``t`` or a tolerance).
    name : str
        Argument name for messages.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        Not a real number (None, a string, a complex number, a bool, ...).
    ShapeError
        An array with more than one entry, e.g. ``t must be a single number; got shape (2,)``.
    DomainError
        NaN or infinite.
    """
    if type(x) is float or (type(x) is int):
        v = float(x)
    elif isinstance(x, (bool, np.bool_)):
        raise TypeError(f"{name} must be a real number; got {_describe(x)}")
    elif isinstance(x, (int, float, np.integer, np.floating)):
        v = float(x)
    else:
        a = as_float_array(x, name)
        if a.size != 1:
            raise ShapeError(f"{name} must be a single number; got shape {a.shape}")
        return float(a.reshape(()))
    if not math.isfinite(v):
        raise DomainError(f"{name} must be finite; got {v}")
    return v


def check_length(value: Any, name: str, *, positive: bool = True) -> Any:
    """Check a length parameter of a model: a finite real number or a sympy expression.

    Parameters
    ----------
    value : float or sympy.Expr
        The length (metres). Sympy symbols and expressions are returned
        unchanged (they are the model's parameters); numeric sympy constants are
        checked like numbers.
    name : str
        Argument name for messages.
    positive : bool, optional
        Require ``value > 0`` (a link length); ``False`` accepts any finite
        number (an offset).

    Returns
    -------
    float or sympy.Expr
        The value as given (a Python number stays a number).

    Raises
    ------
    TypeError
        Not a number or a sympy expression.
    DomainError
        NaN, infinite, or not positive (with ``positive``).
    """
    sp = sys.modules.get("sympy")
    if sp is not None and isinstance(value, sp.Basic):
        if not getattr(value, "is_number", False):
            return value
        try:
            v = float(value)
        except TypeError:
            raise TypeError(f"{name} must be a real length; got {value!r}") from None
    else:
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise TypeError(f"{name} must be a number (metres) or a sympy expression; got {_describe(value)}")
        v = float(value)
    if not math.isfinite(v):
        raise DomainError(f"{name} must be finite; got {v}")
    if positive and not v > 0.0:
        raise DomainError(f"{name} must be a positive length (> 0, metres); got {v:g}")
    return value


def check_int(value: Any, name: str, minimum: int | None = None, maximum: int | None = None) -> int:
    """Check that ``value`` is an integer (not a bool, not a float) within bounds.

    Parameters
    ----------
    value : int or numpy integer
    name : str
        Argument name for messages.
    minimum, maximum : int, optional
        Inclusive bounds. ``maximum`` guards counts that size arrays (a typo
        such as ``N=10**12`` raises here instead of exhausting the memory).

    Returns
    -------
    int

    Raises
    ------
    TypeError
        Not an integer, e.g. ``restarts must be an integer; got float 1.5``.
    DomainError
        Outside ``[minimum, maximum]``.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer; got {_describe(value)}")
    v = int(value)
    if minimum is not None and v < minimum:
        raise DomainError(f"{name} must be >= {minimum}; got {v}")
    if maximum is not None and v > maximum:
        raise DomainError(f"{name} must be <= {maximum:,}; got {v:,}")
    return v


def check_choice(value: Any, choices: Sequence[Any], name: str) -> Any:
    """Check that ``value`` is one of ``choices`` (strings such as ``"pinv"``/``"dls"``).

    Raises
    ------
    ValueError
        E.g. ``inverse must be one of 'pinv', 'dls'; got 'pseudo'``.
    """
    ok = any(value is c or (isinstance(value, str) and isinstance(c, str) and value == c) for c in choices)
    if not ok:
        listed = ", ".join(repr(c) for c in choices)
        raise ValueError(f"{name} must be one of {listed}; got {_describe(value)}")
    return value


def check_callable(value: Any, name: str, signature: str = "") -> Any:
    """Check that ``value`` is callable; ``signature`` describes the expected call in the message.

    Raises
    ------
    TypeError
        E.g. ``feedforward must be a function t -> twist (6,); got NoneType None``.
    """
    if not callable(value):
        what = f"a function {signature}" if signature else "callable"
        raise TypeError(f"{name} must be {what}; got {_describe(value)}")
    return value


ChainT = TypeVar("ChainT")


def check_chain(chain: ChainT, name: str = "chain", methods: Sequence[str] = ("fk", "jacobian")) -> ChainT:
    """Check that ``chain`` is a kinematic chain: an integer ``n >= 1`` and the given methods.

    Parameters
    ----------
    chain : object
        Usually a :class:`robokin.chains.SerialChain` (e.g. ``robokin.models.ur10()``);
        any object with ``n`` and the ``methods`` is accepted (duck typing).
    name : str, optional
        Argument name for messages.
    methods : sequence of str, optional
        Methods the caller needs (default ``fk`` and ``jacobian``).

    Returns
    -------
    object
        ``chain`` itself.

    Raises
    ------
    TypeError
        E.g. ``chain must be a kinematic chain such as robokin.models.ur10() (an object
        with n, fk(q), jacobian(q)); got NoneType None``.
    """
    n = getattr(chain, "n", None)
    ok = (isinstance(n, (int, np.integer)) and not isinstance(n, (bool, np.bool_)) and n >= 1
          and all(callable(getattr(chain, m, None)) for m in methods))
    if not ok:
        needs = ", ".join(["n", *(f"{m}(q)" for m in methods)])
        raise TypeError(f"{name} must be a kinematic chain such as robokin.models.ur10() (an object with "
                        f"{needs}); got {_describe(chain)}")
    return chain


def check_result_finite(result: Any, what: str, **inputs: Any) -> Any:
    """Raise a :class:`DomainError` if a result computed from finite inputs is not finite.

    Huge but finite inputs (``1e300``) can overflow inside a computation; this
    turns the ``inf``/``NaN`` that would come out into an error that names the
    inputs and their largest magnitude.

    Parameters
    ----------
    result : array_like
        The computed value.
    what : str
        What was computed, for the message (``"the transformed point"``).
    **inputs : array_like
        The arguments it was computed from, by name.

    Returns
    -------
    The ``result`` unchanged when it is finite.

    Raises
    ------
    DomainError
        E.g. ``p is too large: computing the transformed point overflows float64 (largest |p| = 1.7e+308)``.
    """
    a = np.asarray(result)
    if a.dtype.kind in "fc" and not np.isfinite(a).all():
        parts = []
        for key, value in inputs.items():
            try:
                big = float(np.max(np.abs(np.asarray(value, dtype=float)), initial=0.0))
            except (TypeError, ValueError):
                continue
            parts.append(f"largest |{key}| = {big:.3g}")
        names = ", ".join(inputs)
        verb = "is" if len(inputs) == 1 else "are"
        head = f"{names} {verb} too large: " if inputs else ""
        raise DomainError(f"{head}computing {what} overflows float64" + (f" ({'; '.join(parts)})" if parts else ""))
    return result
