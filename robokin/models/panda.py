r"""Franka Emika Panda arm (7 revolute joints), built from a link table.

The Genova *Modelling and Control of Manipulators* course gives its industrial
arm as a *geometric model*: the constant link transforms
:math:`{}^{i-1}\mathbf{T}_i(0)` at :math:`\mathbf{q} = \mathbf{0}` plus the joint
types, every joint moving about (or along) the child frame's :math:`z` axis.
That description is what :func:`robokin.chains.from_link_table` builds: the
course's own arm is :func:`robokin.models.genova_arm`; the Panda, an industrial
7-DOF arm of the same kind in the same format, is Chapter 4's *Going further*.

Source: Franka Emika, *Robot and interface specifications* (FCI
documentation), modified (Craig) DH parameters, metres/radians:

====  =========  =========  =========  =====
i     a_{i-1}    d_i        α_{i-1}    θ_i
====  =========  =========  =========  =====
1     0          0.333      0          q1
2     0          0          −π/2       q2
3     0          0.316      π/2        q3
4     0.0825     0          π/2        q4
5     −0.0825    0.384      −π/2       q5
6     0          0          π/2        q6
7     0.088      0          π/2        q7
F     0          0.107      0          —
====  =========  =========  =========  =====

Row F is the flange: the end-effector frame E of this package sits on the
flange face, :math:`z_E` pointing out of it. Joint limits (rad) are those of
the same document. The base frame is the robot's ``panda_link0`` frame (z up
along joint 1).

Cross-checked (``tests/test_urdf.py``, 1,000 configurations, 1e-9 m / 1e-9 rad)
against example-robot-data's ``panda.urdf``
(``from_urdf(robot_description("panda"), "panda_link0", "panda_link8")``), same
q and limits: base and tool transforms are the identity (the flange is
``panda_link8``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokin.chains import Rz, SerialChain, from_link_table, from_modified_dh
from robokin.chains.elements import Fixed
from robokin.transforms import rotx, transform, transform_from_rpy, translation

__all__ = [
    "PANDA_FLANGE",
    "PANDA_LIMITS",
    "PANDA_MDH",
    "PANDA_READY",
    "PANDA_URDF",
    "panda",
    "panda_link_transforms",
]

_PI = math.pi

#: Modified (Craig) DH rows ``(d_i, theta_offset_i, a_{i-1}, alpha_{i-1})`` (m, rad).
PANDA_MDH = [
    [0.333, 0.0, 0.0, 0.0],
    [0.0, 0.0, 0.0, -_PI / 2],
    [0.316, 0.0, 0.0, _PI / 2],
    [0.0, 0.0, 0.0825, _PI / 2],
    [0.384, 0.0, -0.0825, -_PI / 2],
    [0.0, 0.0, 0.0, _PI / 2],
    [0.0, 0.0, 0.088, _PI / 2],
]

#: Distance (m) from the frame of joint 7 to the flange face, along z7.
PANDA_FLANGE = 0.107

#: Joint limits ``[lower, upper]`` (rad), joints 1..7.
PANDA_LIMITS = [
    [-2.8973, 2.8973],
    [-1.7628, 1.7628],
    [-2.8973, 2.8973],
    [-3.0718, -0.0698],
    [-2.8973, 2.8973],
    [-0.0175, 3.7525],
    [-2.8973, 2.8973],
]

#: The "ready" configuration of the Franka tools (rad): elbow up, flange pointing down.
PANDA_READY = [0.0, -_PI / 4, 0.0, -3 * _PI / 4, 0.0, _PI / 2, _PI / 4]

#: Joint origins of franka_description ``panda_arm.urdf``: ``(xyz, rpy)`` of each
#: fixed parent -> child transform (``Trans(xyz) Rz(y) Ry(p) Rx(r)``); the last is the flange.
PANDA_URDF = [
    ((0.0, 0.0, 0.333), (0.0, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (-_PI / 2, 0.0, 0.0)),
    ((0.0, -0.316, 0.0), (_PI / 2, 0.0, 0.0)),
    ((0.0825, 0.0, 0.0), (_PI / 2, 0.0, 0.0)),
    ((-0.0825, 0.384, 0.0), (-_PI / 2, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (_PI / 2, 0.0, 0.0)),
    ((0.088, 0.0, 0.0), (_PI / 2, 0.0, 0.0)),
    ((0.0, 0.0, 0.107), (0.0, 0.0, 0.0)),
]

_NAMES = [f"joint{i}" for i in range(1, 8)]
_FRAMES = ["base"] + [f"link{i}" for i in range(1, 8)] + ["flange"]


def panda_link_transforms() -> list[np.ndarray]:
    r"""The geometric model: :math:`{}^{i-1}\mathbf{T}_i(0)`, i = 1..7, and the flange.

    Returns
    -------
    list of numpy.ndarray, 8 arrays of shape (4, 4)
        :math:`{}^{i-1}\mathbf{T}_i(0) = \mathbf{R}_x(\alpha_{i-1})\,\mathbf{T}_x(a_{i-1})\,
        \mathbf{T}_z(d_i)` from :data:`PANDA_MDH` (the joint rotation
        :math:`\mathbf{R}_z(q_i)` follows it; it commutes with :math:`\mathbf{T}_z(d_i)`),
        then :math:`{}^{7}\mathbf{T}_F = \mathbf{T}_z(0.107)`.
    """
    mats = [transform(rotx(alpha), (0.0, 0.0, 0.0)) @ translation((a, 0.0, d)) for d, _, a, alpha in PANDA_MDH]
    mats.append(translation((0.0, 0.0, PANDA_FLANGE)))
    return mats


def panda(description: str = "link_table") -> SerialChain:
    r"""Franka Emika Panda, 7 revolute joints, base ``panda_link0`` to the flange.

    Parameters
    ----------
    description : {'link_table', 'mdh', 'urdf'}, optional
        Which (equivalent) description builds the chain:

        ``'link_table'`` (default)
            the course's geometric-model format, :func:`panda_link_transforms`
            with all joints revolute (:func:`robokin.chains.from_link_table`);
        ``'mdh'``
            the manufacturer's modified DH table (:func:`robokin.chains.from_modified_dh`,
            flange as the tool transform);
        ``'urdf'``
            the joint origins of franka_description's URDF (:data:`PANDA_URDF`),
            each followed by :math:`\mathbf{R}_z(q_i)`.

        All three give the same ``fk`` and ``jacobian`` (tested).

    Returns
    -------
    SerialChain
        ``n = 7``, limits :data:`PANDA_LIMITS` (rad), joint names
        ``joint1..joint7``, frames ``base, link1..link7, flange``.

    Notes
    -----
    Craig 2005, §3.4 (modified DH); Siciliano et al. 2009, §2.8–2.9 (the
    kinematic chain as a product of link transforms).
    """
    kw: dict[str, Any] = {"joint_names": _NAMES, "limits": PANDA_LIMITS, "frame_names": _FRAMES, "name": "panda"}
    if description == "link_table":
        return from_link_table(panda_link_transforms(), ["R"] * 7, **kw)
    if description == "mdh":
        return from_modified_dh(PANDA_MDH, tool=translation((0.0, 0.0, PANDA_FLANGE)), **kw)
    if description == "urdf":
        els = []
        for i, (xyz, rpy) in enumerate(PANDA_URDF):
            els.append(Fixed(transform_from_rpy(rpy, xyz)))
            if i < 7:
                els.append(Rz(_NAMES[i]))
        return SerialChain(els, limits=PANDA_LIMITS, frame_names=_FRAMES, name="panda")
    raise ValueError(f"description must be 'link_table', 'mdh' or 'urdf'; got {description!r}")
