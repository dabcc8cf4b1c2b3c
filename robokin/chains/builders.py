r"""Build :class:`~robokin.chains.SerialChain` objects from DH and link tables.

All builders translate their table into elementary transforms, the chain's only
internal representation.

Standard DH (Siciliano et al. 2009, §2.8.2; Corke 2017, §7.2)
    table rows ``(d, theta_offset, a, alpha[, type])``; row i is

    .. math:: {}^{i-1}\mathbf{T}_i = R_z(\theta_i)\,T_z(d_i)\,T_x(a_i)\,R_x(\alpha_i),

    with :math:`\theta_i = q_i + \theta_{off,i}` for a revolute joint and
    :math:`d_i = q_i + d` for a prismatic joint.

Modified DH (Craig 2005, §3.4)
    same column order ``(d, theta_offset, a, alpha[, type])`` where ``a`` and
    ``alpha`` are :math:`a_{i-1}, \alpha_{i-1}` of row i:

    .. math:: {}^{i-1}\mathbf{T}_i = R_x(\alpha_{i-1})\,T_x(a_{i-1})\,R_z(\theta_i)\,T_z(d_i).

Link table (as in some courses)
    fixed transforms :math:`{}^{i-1}\mathbf{T}_i(0)` of the joint frames at
    q = 0, each followed by a motion of joint i about / along the *child* frame's
    z axis: :math:`{}^{i-1}\mathbf{T}_i(q_i) = {}^{i-1}\mathbf{T}_i(0)\,R_z(q_i)` or
    :math:`{}^{i-1}\mathbf{T}_i(0)\,T_z(q_i)`.

The joint type column accepts ``'R'``/``'revolute'``/0 and ``'P'``/``'prismatic'``/1.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from robokin.chains.chain import SerialChain
from robokin.chains.elements import Element, Fixed, Rx, Rz, Tx, Tz, check_parameter_value
from robokin.errors import DomainError, ShapeError
from robokin.validation import check_transform

_COLUMNS = ("d", "theta_offset", "a", "alpha")

__all__ = ["from_dh", "from_modified_dh", "from_link_table"]

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


def from_dh(
    table: Any,
    *,
    joint_names: Sequence[str] | None = None,
    limits: Any = None,
    tool: Any = None,
    base: Any = None,
    frame_names: Sequence[str] | None = None,
    name: str = "dh_chain",
) -> SerialChain:
    r"""Chain from a standard Denavit–Hartenberg table.

    Parameters
    ----------
    table : array_like, shape (n, 4) or (n, 5)
        Rows ``(d, theta_offset, a, alpha[, type])`` in m / rad; entries may be
        sympy expressions. Row i gives
        :math:`R_z(q_i + \theta_{off})\,T_z(d)\,T_x(a)\,R_x(\alpha)` (revolute) or
        :math:`R_z(\theta_{off})\,T_z(q_i + d)\,T_x(a)\,R_x(\alpha)` (prismatic).
    joint_names : sequence of str, optional
        Default ``q1..qn``.
    limits, tool, base, frame_names, name
        As for :class:`SerialChain`.

    Raises
    ------
    ShapeError
        ``table`` does not have 4 or 5 columns.
    DomainError
        Unknown joint type.

    Notes
    -----
    Siciliano et al. 2009, §2.8.2, eq. (2.52); Corke 2017, §7.2.
    Frame i of the chain (after joint i) has the origin and z axis of DH frame
    i−1, so the joint axis passes through it.
    """
    rows = _rows(table)
    names = _names(joint_names, len(rows))
    return SerialChain(_dh_elements(rows, names, False), limits=limits, tool=tool, base=base,
                       frame_names=frame_names, name=name)


def from_modified_dh(
    table: Any,
    *,
    joint_names: Sequence[str] | None = None,
    limits: Any = None,
    tool: Any = None,
    base: Any = None,
    frame_names: Sequence[str] | None = None,
    name: str = "mdh_chain",
) -> SerialChain:
    r"""Chain from a modified (Craig) DH table.

    Parameters
    ----------
    table : array_like, shape (n, 4) or (n, 5)
        Rows ``(d_i, theta_offset_i, a_{i-1}, alpha_{i-1}[, type])`` — the same
        column order as :func:`from_dh`, but ``a`` and ``alpha`` describe the link
        *before* joint i. Row i gives
        :math:`R_x(\alpha_{i-1})\,T_x(a_{i-1})\,R_z(q_i+\theta_{off})\,T_z(d_i)`.
    joint_names, limits, tool, base, frame_names, name
        As for :func:`from_dh`. The final :math:`T_x(a_n) R_x(\alpha_n)` of a
        standard-DH arm goes into ``tool``.

    Notes
    -----
    Craig 2005, §3.4, eq. (3.6).
    """
    rows = _rows(table)
    names = _names(joint_names, len(rows))
    return SerialChain(_dh_elements(rows, names, True), limits=limits, tool=tool, base=base,
                       frame_names=frame_names, name=name)


def from_link_table(
    transforms: Any,
    joint_types: Sequence[Any],
    *,
    joint_names: Sequence[str] | None = None,
    limits: Any = None,
    tool: Any = None,
    base: Any = None,
    frame_names: Sequence[str] | None = None,
    name: str = "link_table_chain",
) -> SerialChain:
    r"""Chain from fixed link transforms at q = 0 and joint types.

    Parameters
    ----------
    transforms : sequence of (4, 4) arrays or sympy matrices, length n or n+1
        :math:`{}^{i-1}\mathbf{T}_i(0)`, the pose of joint frame i in frame i−1
        when all joints are at zero. An optional (n+1)-th matrix is the constant
        transform from frame n to the end-effector.
    joint_types : sequence, length n
        ``'revolute'`` (rotation about the child frame's z axis) or
        ``'prismatic'`` (translation along it); ``'R'``/``'P'`` also accepted.
    joint_names, limits, tool, base, frame_names, name
        As for :class:`SerialChain`.

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
    return SerialChain(els, limits=limits, tool=tool, base=base, frame_names=frame_names, name=name)
