"""Printing numbers the same way on every machine.

A notebook's stored outputs are compared with a fresh run (nbval), on the
author's machine and on every student's. Two things make printed digits differ
between machines although the computation is right on all of them:

* **Negative zeros.** A value that is zero in exact arithmetic comes out as
  ``+1e-17`` on one CPU and ``-1e-17`` on another (BLAS kernels and SIMD math
  round differently). Rounded to four decimals both are zero, but NumPy prints
  the second as ``-0.``. :func:`rounded` rounds and then drops the sign of
  zero, so both print ``0.``.
* **Digits the conditioning does not support.** A quantity amplified by an
  ill-conditioned step (a pseudoinverse near a singularity, a chaotic sweep)
  differs between machines in its leading digits. No formatting fixes that:
  print a bound that every run satisfies, or a verdict (Chapter 5 shows how).

Use :func:`rounded` wherever an array is printed with NumPy's own printing,
and :func:`format_array` for one-line text such as ``[0.1000, -0.2500, 0.0000]``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["rounded", "format_array"]


def rounded(values: Any, decimals: int = 4) -> Any:
    """Round to ``decimals`` places and turn ``-0.0`` into ``0.0``.

    Parameters
    ----------
    values : float or array_like
        Any real number or array (shape kept).
    decimals : int
        Decimal places kept (may be negative: ``-1`` rounds to tens).

    Returns
    -------
    float or numpy.ndarray
        A Python float for a scalar input, otherwise a float array of the input's shape.

    Examples
    --------
    >>> rounded(-1e-17)
    0.0
    >>> rounded([0.123456, -0.00001], 3)
    array([0.123, 0.   ])
    """
    if not isinstance(decimals, (int, np.integer)) or isinstance(decimals, bool):
        raise TypeError(f"decimals must be an integer, got {decimals!r}")
    array = np.round(np.asarray(values, dtype=float), int(decimals)) + 0.0  # -0.0 + 0.0 == +0.0
    return float(array) if array.ndim == 0 else array


def format_array(values: Any, decimals: int = 4, separator: str = ", ") -> str:
    """Text of a number or array with a fixed number of decimals and no ``-0``.

    Parameters
    ----------
    values : float or array_like
        A scalar, a vector ``(n,)`` or any nested array.
    decimals : int
        Decimal places printed (every entry gets exactly this many).
    separator : str
        Between entries of one row.

    Returns
    -------
    str
        ``"0.5000"`` for a scalar, ``"[0.5000, -1.0000]"`` for a vector, nested
        brackets for a matrix (one row per line).

    Examples
    --------
    >>> format_array([0.5, -1e-12, 2.0], 2)
    '[0.50, 0.00, 2.00]'
    """
    array = np.asarray(rounded(values, decimals))
    if array.ndim == 0:
        return f"{float(array):.{decimals}f}"
    return np.array2string(
        array,
        separator=separator,
        formatter={"float_kind": lambda x: f"{x:.{decimals}f}"},
        max_line_width=10_000,
        threshold=10_000,
    )

