r"""Build :class:`~robokin.chains.SerialChain` objects from DH and link tables.

All builders translate their table into elementary transforms, the chain's only
internal representation.

Standard DH (Siciliano et al. 2009, §2.8.2; Corke 2017, ch. 7)
    table rows ``(d, theta_offset, a, alpha[, type])``; row i is

    .. math:: {}^{i-1}\mathbf{T}_i = R_z(\theta_i)\,T_z(d_i)\,T_x(a_i)\,R_x(\alpha_i),

    with :math:`\theta_i = q_i + \theta_{off,i}` for a revolute joint and
    :math:`d_i = q_i + d` for a prismatic joint.

Modified DH (Craig 2005, §3.4; the link transform, §3.5)
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

from robokin.chains.chain import SerialChain
from robokin.chains.tables import dh_elements, link_table_elements

__all__ = ["from_dh", "from_modified_dh", "from_link_table"]


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
    Siciliano et al. 2009, §2.8.2, eq. (2.52); Corke 2017, ch. 7.
    Frame i of the chain (after joint i) has the origin and z axis of DH frame
    i−1, so the joint axis passes through it.
    """
    return SerialChain(dh_elements(table, joint_names, modified=False), limits=limits, tool=tool, base=base,
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
    Craig 2005, §3.5, eq. (3.6).
    """
    return SerialChain(dh_elements(table, joint_names, modified=True), limits=limits, tool=tool, base=base,
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
    return SerialChain(link_table_elements(transforms, joint_types, joint_names), limits=limits, tool=tool,
                       base=base, frame_names=frame_names, name=name)
