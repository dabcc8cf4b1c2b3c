r"""Denavit–Hartenberg and link tables translated into elementary transforms.

The table formats are described in :mod:`robokin.chains.builders`; this module
reads and validates a table and returns the chain's elements
(:mod:`robokin.chains.elements`). It imports no chain, so that both
:class:`~robokin.chains.SerialChain`'s alternative constructors and the
builders use it without importing each other.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from robokin.chains.elements import Element, Fixed, Rx, Rz, Tx, Tz, check_parameter_value
from robokin.errors import DomainError, ShapeError
from robokin.validation import check_transform

__all__ = ["dh_elements", "link_table_elements"]

_COLUMNS = ("d", "theta_offset", "a", "alpha")

_REV = {"r", "revolute", "0"}
_PRI = {"p", "prismatic", "1"}


def _joint_type(x: Any, where: str) -> str:
    if isinstance(x, (float, np.floating)) and not float(x).is_integer():
        raise DomainError(f"{where} must be 'R'/'revolute'/0 or 'P'/'prismatic'/1; got {x!r}")
    key = str(int(x)) if isinstance(x, (int, float, np.integer, np.floating)) else str(x).strip().lower()
    if key in _REV:
        return "revolute"
    if key in _PRI:
        return "prismatic"
    raise DomainError(f"{where} must be 'R'/'revolute'/0 or 'P'/'prismatic'/1; got {x!r}")


def _is_zero(x: Any) -> bool:
    try:
        return bool(x == 0)
    except TypeError:
        return False


def _rows(table: Any, name: str = "table") -> list[list[Any]]:
    """Rows of a DH table given as a list of rows, a NumPy array or a sympy Matrix."""
    if hasattr(table, "tolist"):  # numpy array or sympy Matrix
        table = table.tolist()
    try:
        rows = [list(r) for r in table]
    except TypeError:
        raise ShapeError(
            f"{name} must be a 2-D table of shape (n, 4) or (n, 5); got {type(table).__name__}"
        ) from None
    widths = sorted({len(r) for r in rows})
    if not rows or len(widths) != 1 or widths[0] not in (4, 5):
        raise ShapeError(
            f"{name} must have shape (n, 4) or (n, 5) with columns (d, theta_offset, a, alpha"
            f"[, type]); got {len(rows)} rows of length(s) {widths}"
        )
    for i, row in enumerate(rows):  # numbers or sympy expressions, finite
        for j, x in enumerate(row[:4]):
            check_parameter_value(x, f"{name}[{i}][{j}] ({_COLUMNS[j]})")
    return rows


def _names(joint_names: Sequence[str] | None, n: int) -> list[str]:
    if joint_names is None:
        return [f"q{i + 1}" for i in range(n)]
    if isinstance(joint_names, str) or not hasattr(joint_names, "__iter__"):
        raise TypeError(f"joint_names must be a sequence of {n} strings; got {type(joint_names).__name__} "
                        f"{joint_names!r}")
    bad = [x for x in joint_names if not isinstance(x, (str, int, np.integer))]
    if bad:
        raise TypeError(f"joint_names must contain strings; got {type(bad[0]).__name__} {bad[0]!r}")
    names = [str(x) for x in joint_names]
    if len(names) != n:
        raise ShapeError(f"joint_names must have {n} entries; got {len(names)}")
    return names


def _dh_elements(rows: list[list[Any]], names: list[str], modified: bool) -> list[Element]:
    els: list[Element] = []
    for i, row in enumerate(rows):
        d, off, a, alpha = row[:4]
        jt = _joint_type(row[4], f"table[{i}][4]") if len(row) == 5 else "revolute"
        if jt == "revolute":
            z_part = [Rz(names[i], offset=off)] + ([] if _is_zero(d) else [Tz(d)])
        else:
            z_part = ([] if _is_zero(off) else [Rz(off)]) + [Tz(names[i], offset=d)]
        x_part = ([] if _is_zero(a) else [Tx(a)]) + ([] if _is_zero(alpha) else [Rx(alpha)])
        els += (x_part + z_part) if modified else (z_part + x_part)
    return els


def dh_elements(table: Any, joint_names: Sequence[str] | None, modified: bool) -> list[Element]:
    r"""The elements of a standard or modified DH table.

    Parameters
    ----------
    table : array_like, shape (n, 4) or (n, 5)
        Rows ``(d, theta_offset, a, alpha[, type])`` (m, rad; sympy expressions allowed).
    joint_names : sequence of str, length n, or None
        Default ``q1..qn``.
    modified : bool
        Modified (Craig) DH: :math:`R_x(\alpha_{i-1})\,T_x(a_{i-1})\,R_z\,T_z` per row;
        else standard DH: :math:`R_z\,T_z\,T_x(a_i)\,R_x(\alpha_i)`.

    Returns
    -------
    list of Element
        Zero offsets and lengths are left out.

    Raises
    ------
    ShapeError
        ``table`` does not have 4 or 5 columns, or ``joint_names`` the wrong length.
    DomainError
        A non-finite entry or an unknown joint type.
    """
    rows = _rows(table)
    return _dh_elements(rows, _names(joint_names, len(rows)), modified)


def link_table_elements(
    transforms: Any, joint_types: Sequence[Any], joint_names: Sequence[str] | None
) -> list[Element]:
    """The elements of a link table: each fixed transform, then the joint about / along z.

    Parameters
    ----------
    transforms : sequence of (4, 4) arrays or sympy matrices, length n or n+1
        The link transforms at q = 0 (and the end-effector's).
    joint_types : sequence, length n
        ``'revolute'``/``'R'``/0 or ``'prismatic'``/``'P'``/1.
    joint_names : sequence of str, length n, or None
        Default ``q1..qn``.

    Returns
    -------
    list of Element
        Identity transforms are left out.

    Raises
    ------
    ShapeError
        Wrong number of transforms, or a transform not 4×4.
    DomainError
        A numeric transform that is not homogeneous, or an unknown joint type.
    """
    for arg, what in ((joint_types, "joint_types"), (transforms, "transforms")):
        if isinstance(arg, str) or not hasattr(arg, "__iter__"):
            raise TypeError(f"{what} must be a sequence; got {type(arg).__name__} {arg!r}"[:200])
    types = [_joint_type(t, f"joint_types[{i}]") for i, t in enumerate(joint_types)]
    n = len(types)
    mats = list(transforms)
    if len(mats) not in (n, n + 1):
        raise ShapeError(
            f"transforms must have n = {n} or n + 1 = {n + 1} entries (one per joint "
            f"[, end-effector]); got {len(mats)}"
        )
    names = _names(joint_names, n)
    els: list[Element] = []
    for i, T in enumerate(mats):
        arr = None if hasattr(T, "free_symbols") else check_transform(T, name=f"transforms[{i}]")
        if arr is not None and arr.shape != (4, 4):
            raise ShapeError(f"transforms[{i}] must have shape (4, 4); got shape {arr.shape}")
        if arr is None or not np.array_equal(arr, np.eye(4)):
            els.append(Fixed(T))
        if i < n:
            els.append(Rz(names[i]) if types[i] == "revolute" else Tz(names[i]))
    return els
