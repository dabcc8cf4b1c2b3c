r"""The 7-joint arm of the Genova *Modelling and Control of Manipulators* course.

Source: University of Genova (DIBRIS), *Modelling and Control of Manipulators*,
assignments 2 and 3 (Cartesian control of a tool frame, chapter 4 of this
book). The course does not give the arm a name or a DH table: it hands it to
the students as a *geometric model*, the constant link transforms
:math:`{}^{i-1}\mathbf{T}_i(0) = [\mathbf{R}_i,\ \mathbf{p}_i]` at
:math:`\mathbf{q} = \mathbf{0}` plus the joint types, each joint moving about
(revolute) or along (prismatic) the :math:`z` axis of its *child* frame:

.. math::

    {}^{i-1}\mathbf{T}_i(q_i) = {}^{i-1}\mathbf{T}_i(0)\,\mathbf{R}_z(q_i)
    \quad\text{or}\quad {}^{i-1}\mathbf{T}_i(0)\,\mathbf{T}_z(q_i).

Joint types ``R R R R R P R``: joint 6 is **prismatic**. Units: metres and
radians (``q6`` in metres). The data (rows of :math:`\mathbf{R}_i`, and
:math:`\mathbf{p}_i` in metres, written in frame :math:`i-1`):

===  ===========================  ===================
i    R_i (rows)                   p_i (m)
===  ===========================  ===================
1    identity                     (0, 0, 0.105)
2    [0 1 0; 0 0 1; 1 0 0]        (0, 0, 0.110)
3    [0 0 1; 0 −1 0; 1 0 0]       (0.1, 0, 0)
4    [0 0 1; 0 −1 0; 1 0 0]       (0, 0, 0.325)
5    [0 0 1; −1 0 0; 0 −1 0]      (0.095, 0, 0)
6    diag(−1, −1, 1)              (0, 0, 0.095)
7    identity                     (0, 0, 0.355)
===  ===========================  ===================

The end-effector frame E is frame 7 (there is no extra flange transform):
:math:`{}^{B}\mathbf{T}_{E}(\mathbf{q}) = \prod_i {}^{i-1}\mathbf{T}_i(q_i)`. At
:math:`\mathbf{q} = \mathbf{0}` every frame is parallel to the base and the arm
stands straight up, E at height 0.105 + 0.110 + 0.1 + 0.325 + 0.095 + 0.095 +
0.355 = 1.185 m. Joint limits of the course: ±3.14 rad for the revolute joints,
[0, 1] m for the prismatic one.

Joints 5, 6 and 7 share one line: everything between the rotation of joint 5
and that of joint 7 (the half turn of :math:`\mathbf{R}_6` about z, the slide
:math:`\mathbf{T}_z(q_6)`, offsets along z) commutes with a rotation about z,
so the pose depends on :math:`q_5 + q_7` only. The arm has seven joints but
six independent motions; :math:`\mathbf{e}_5 - \mathbf{e}_7` spans the null
space of its Jacobian at every configuration.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.chains import SerialChain, from_link_table
from robokin.transforms import transform

__all__ = [
    "GENOVA_ARM_JOINT_TYPES",
    "GENOVA_ARM_LIMITS",
    "GENOVA_ARM_OFFSETS",
    "GENOVA_ARM_ROTATIONS",
    "genova_arm",
    "genova_arm_link_transforms",
]

#: Rotation blocks :math:`\mathbf{R}_i` of :math:`{}^{i-1}\mathbf{T}_i(0)`, i = 1..7 (rows).
GENOVA_ARM_ROTATIONS = (
    ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
    ((0, 1, 0), (0, 0, 1), (1, 0, 0)),
    ((0, 0, 1), (0, -1, 0), (1, 0, 0)),
    ((0, 0, 1), (0, -1, 0), (1, 0, 0)),
    ((0, 0, 1), (-1, 0, 0), (0, -1, 0)),
    ((-1, 0, 0), (0, -1, 0), (0, 0, 1)),
    ((1, 0, 0), (0, 1, 0), (0, 0, 1)),
)

#: Origins :math:`\mathbf{p}_i` of :math:`{}^{i-1}\mathbf{T}_i(0)` (m), written in frame i−1.
GENOVA_ARM_OFFSETS = (
    (0.0, 0.0, 0.105),
    (0.0, 0.0, 0.110),
    (0.1, 0.0, 0.0),
    (0.0, 0.0, 0.325),
    (0.095, 0.0, 0.0),
    (0.0, 0.0, 0.095),
    (0.0, 0.0, 0.355),
)

#: Joint types, joints 1..7: ``'R'`` revolute (about z_i), ``'P'`` prismatic (along z_i).
GENOVA_ARM_JOINT_TYPES = ("R", "R", "R", "R", "R", "P", "R")

#: The course's joint limits ``[lower, upper]``: rad for joints 1–5 and 7, metres for joint 6.
GENOVA_ARM_LIMITS = (
    (-3.14, 3.14),
    (-3.14, 3.14),
    (-3.14, 3.14),
    (-3.14, 3.14),
    (-3.14, 3.14),
    (0.0, 1.0),
    (-3.14, 3.14),
)

_JOINT_NAMES = [f"q{i}" for i in range(1, 8)]
_FRAME_NAMES = ["B", "1", "2", "3", "4", "5", "6", "7", "E"]


def genova_arm_link_transforms() -> list[np.ndarray]:
    r"""The geometric model: :math:`{}^{i-1}\mathbf{T}_i(0)`, i = 1..7.

    Returns
    -------
    list of numpy.ndarray, 7 arrays of shape (4, 4)
        :math:`\begin{bmatrix}\mathbf{R}_i & \mathbf{p}_i\\ \mathbf{0}^\top & 1\end{bmatrix}`
        from :data:`GENOVA_ARM_ROTATIONS` and :data:`GENOVA_ARM_OFFSETS`
        (metres); the joint motion :math:`\mathbf{R}_z(q_i)` or
        :math:`\mathbf{T}_z(q_i)` follows each of them.
    """
    return [transform(R, p) for R, p in zip(GENOVA_ARM_ROTATIONS, GENOVA_ARM_OFFSETS)]


def genova_arm(*, limits: Any = None) -> SerialChain:
    r"""The course's 7-joint arm (joint 6 prismatic), base B to end-effector E.

    Built with :func:`robokin.chains.from_link_table` from
    :func:`genova_arm_link_transforms` and :data:`GENOVA_ARM_JOINT_TYPES`, so
    the chain is the product
    :math:`\prod_{i=1}^{7} {}^{i-1}\mathbf{T}_i(0)\,\mathbf{J}_i(q_i)` with
    :math:`\mathbf{J}_i = \mathbf{R}_z` (revolute) or :math:`\mathbf{T}_z`
    (prismatic, joint 6).

    Parameters
    ----------
    limits : array_like, shape (7, 2), optional
        Joint limits ``[lower, upper]`` (rad; metres for joint 6). Default
        :data:`GENOVA_ARM_LIMITS`, the course's ±3.14 rad and [0, 1] m.

    Returns
    -------
    SerialChain
        ``n = 7``, joint names ``q1..q7``, ``joint_types`` with
        ``'prismatic'`` at index 5, frames ``B, 1..7, E`` (E = frame 7).

    Raises
    ------
    ShapeError, DomainError, TypeError
        ``limits`` not of shape (7, 2), NaN, non-numeric, or a lower limit
        above its upper one (the message names ``limits``).

    Examples
    --------
    >>> arm = genova_arm()
    >>> arm.joint_types[5]
    'prismatic'
    >>> float(arm.fk([0, 0, 0, 0, 0, 0, 0])[2, 3])      # straight up: sum of the offsets
    1.185
    """
    return from_link_table(
        genova_arm_link_transforms(),
        list(GENOVA_ARM_JOINT_TYPES),
        joint_names=_JOINT_NAMES,
        limits=GENOVA_ARM_LIMITS if limits is None else limits,
        frame_names=_FRAME_NAMES,
        name="genova_arm",
    )
