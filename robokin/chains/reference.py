r"""Forward kinematics and the geometric Jacobian as the book writes them.

:class:`~robokin.chains.SerialChain` computes both with a performance engine
(``robokin.chains._engine``: constant blocks, 7×7 screw matrices, per-thread
workspaces). This module is the textbook beside it, written for reading, not for
speed: a product of link transforms (Siciliano et al. 2009, §2.8; Lynch & Park
2017, §4.1) and the column-by-column Jacobian (Siciliano et al. 2009, §3.1.3,
eq. 3.30). ``tests/test_chains_reference.py`` checks the engine against it, for
every model of :mod:`robokin.models`, to 1e-12.

Conventions (``book/conventions.md``): poses are 4×4 homogeneous transforms of
the base frame; the Jacobian is 6×n, rows ``[v; ω]``, both in the base frame.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robokin.chains.chain import SerialChain
from robokin.chains.elements import Element, elementary_transform
from robokin.validation import as_vector

__all__ = ["link_transform", "forward_kinematics", "geometric_jacobian"]


def link_transform(element: Element, joint_value: float = 0.0) -> np.ndarray:
    """The 4×4 transform of one element; a joint element moves by ``sign * q + offset``.

    Parameters
    ----------
    element : Element
        A constant translation or rotation, a joint, or a ``Fixed`` transform.
    joint_value : float
        The joint variable ``q`` (rad or m); ignored by a constant element.

    Returns
    -------
    numpy.ndarray, shape (4, 4)
    """
    if element.kind == "F":
        return np.asarray(element.matrix, dtype=float)
    if element.is_joint:
        value = element.sign * joint_value + float(element.offset)
    else:
        value = float(element.value)
    return np.asarray(elementary_transform(element.kind, element.axis, value), dtype=float)


def forward_kinematics(chain: SerialChain, q: ArrayLike) -> np.ndarray:
    r"""End-effector pose: the product of the link transforms, then the tool.

    .. math:: {}^B\mathbf{T}_E(\mathbf{q}) = E_1 E_2 \cdots E_m\, \mathbf{T}_{tool}

    Parameters
    ----------
    chain : SerialChain
    q : array_like, shape (n,)
        Joint values (rad or m).

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        :math:`{}^B\mathbf{T}_E`.
    """
    joint_values = as_vector(q, chain.n, "q")
    T = np.eye(4)
    joint = 0
    for element in chain.elements:
        if element.is_joint:
            T = T @ link_transform(element, joint_values[joint])
            joint += 1
        else:
            T = T @ link_transform(element)
    return T @ chain.tool


def geometric_jacobian(chain: SerialChain, q: ArrayLike) -> np.ndarray:
    r"""Geometric Jacobian of the end-effector, in the base frame, rows ``[v; ω]``.

    Joint i moves about (revolute) or along (prismatic) the unit axis
    :math:`\mathbf{z}_i` through the point :math:`\mathbf{o}_i`, both read from the
    running product of link transforms; :math:`\mathbf{p}` is the end-effector's
    origin. Column i is (Siciliano et al. 2009, eq. 3.30)

    .. math::

        \mathbf{J}_i = \begin{bmatrix} \mathbf{z}_i \times (\mathbf{p} - \mathbf{o}_i) \\
        \mathbf{z}_i \end{bmatrix} \text{ (revolute)}, \qquad
        \mathbf{J}_i = \begin{bmatrix} \mathbf{z}_i \\ \mathbf{0} \end{bmatrix} \text{ (prismatic)}.

    Parameters
    ----------
    chain : SerialChain
    q : array_like, shape (n,)
        Joint values (rad or m).

    Returns
    -------
    numpy.ndarray, shape (6, n)
        :math:`\mathbf{J} = [\mathbf{J}_v; \mathbf{J}_\omega]`.
    """
    joint_values = as_vector(q, chain.n, "q")
    T = np.eye(4)
    axes: list[np.ndarray] = []
    origins: list[np.ndarray] = []
    revolute: list[bool] = []
    for element in chain.elements:
        if not element.is_joint:
            T = T @ link_transform(element)
            continue
        T = T @ link_transform(element, joint_values[len(axes)])
        # a rotation about (a translation along) its own axis leaves that axis where it was
        local_axis = np.zeros(3)
        local_axis[element.axis] = element.sign
        axes.append(T[:3, :3] @ local_axis)
        origins.append(T[:3, 3])
        revolute.append(element.kind == "R")
    p = (T @ chain.tool)[:3, 3]
    J = np.zeros((6, chain.n))
    for i, (z, o) in enumerate(zip(axes, origins)):
        if revolute[i]:
            J[:3, i] = np.cross(z, p - o)
            J[3:, i] = z
        else:
            J[:3, i] = z
    return J
