"""Rethink Robotics Baxter, left arm (7 DOF)."""

from __future__ import annotations

import math

import numpy as np

from robokin.chains import Rz, SerialChain, Tx, Ty, Tz, from_link_table, from_modified_dh
from robokin.transforms import transform_from_rpy

__all__ = ["baxter_left", "baxter_left_urdf", "BAXTER_LEFT_LIMITS", "BAXTER_LEFT_URDF"]

_PI = math.pi

#: Joint limits (rad) of the left arm, joints s0, s1, e0, e1, w0, w1, w2
#: (Rethink URDF ``baxter.urdf``; the Imperial College tutorial lists the same values rounded).
BAXTER_LEFT_LIMITS = [
    [-1.70167993878, 1.70167993878],
    [-2.147, 1.047],
    [-3.05417993878, 3.05417993878],
    [-0.05, 2.618],
    [-3.059, 3.059],
    [-1.57079632679, 2.094],
    [-3.059, 3.059],
]

_NAMES = ["s0", "s1", "e0", "e1", "w0", "w1", "w2"]

#: Joint origins of the left arm in RethinkRobotics/baxter_common
#: baxter_description/urdf/baxter.urdf: (name, xyz, rpy) of each joint's fixed
#: transform parent -> child; every revolute joint turns about the child's z axis.
BAXTER_LEFT_URDF = [
    ("left_torso_arm_mount", (0.024645, 0.219645, 0.118588), (0.0, 0.0, 0.7854)),
    ("left_s0", (0.055695, 0.0, 0.011038), (0.0, 0.0, 0.0)),
    ("left_s1", (0.069, 0.0, 0.27035), (-1.57079632679, 0.0, 0.0)),
    ("left_e0", (0.102, 0.0, 0.0), (1.57079632679, 0.0, 1.57079632679)),
    ("left_e1", (0.069, 0.0, 0.26242), (-1.57079632679, -1.57079632679, 0.0)),
    ("left_w0", (0.10359, 0.0, 0.0), (1.57079632679, 0.0, 1.57079632679)),
    ("left_w1", (0.01, 0.0, 0.2707), (-1.57079632679, -1.57079632679, 0.0)),
    ("left_w2", (0.115975, 0.0, 0.0), (1.57079632679, 0.0, 1.57079632679)),
    ("left_hand", (0.0, 0.0, 0.11355), (0.0, 0.0, 0.0)),
    ("left_endpoint", (0.0, 0.0, 0.05), (0.0, 0.0, 0.0)),
]


def baxter_left(base: str = "torso", end: str = "hand") -> SerialChain:
    r"""Left arm of the Rethink Robotics Baxter, 7 revolute joints (s0 … w2).

    Source: RethinkRobotics/baxter_common, ``baxter_description/urdf/baxter.urdf``
    (joint origins, limits); modified DH form as in Ju, Yang & Ma,
    "Kinematics modeling and experimental verification of Baxter robot",
    Chinese Control Conference 2014. Metres and radians.

    Modified DH table (rows :math:`a_{i-1}, \alpha_{i-1}, d_i, \theta_i`):

    ====  ===========  ==============  ============  ===============
    i     a_{i-1} [m]  α_{i-1} [rad]   d_i [m]       θ_i
    ====  ===========  ==============  ============  ===============
    1     0            0               0.27035       q1 (s0)
    2     0.069        −π/2            0             q2 + π/2 (s1)
    3     0            π/2             0.36442       q3 (e0)
    4     0.069        −π/2            0             q4 (e1)
    5     0            π/2             0.37429       q5 (w0)
    6     0.010        −π/2            0             q6 (w1)
    7     0            π/2             0             q7 (w2)
    ====  ===========  ==============  ============  ===============

    followed by :math:`T_z(0.229525)` to the hand flange (``left_hand``), or
    :math:`T_z(0.279525)` to ``left_gripper`` (``end='gripper'``).
    :math:`d_3 = 0.102 + 0.26242 = 0.36442` m is the URDF value (Rethink's
    hardware page and Ju et al. print 0.36435); the θ₂ offset π/2 makes q = 0
    the URDF zero pose (arm stretched horizontally).

    The Imperial College tutorial table (course material, not distributed with
    robokin) has the same structure but rounds the lengths (0.2703, 0.3644,
    0.3743, 0.2295) and twists (±1.571) and omits the θ₂ offset π/2, so its
    q = 0 is a different pose;
    with q2 → q2 + π/2 it agrees with this model to 0.3 mm.

    Cross-checked (``tests/test_urdf.py``, 1,000 configurations, 1e-9 m / 1e-9 rad)
    against example-robot-data's ``baxter.urdf``
    (``from_urdf(robot_description("baxter"), "torso", "left_hand_link")``), same
    q (thanks to the θ₂ offset) and limits; tool transform the identity
    (``end='hand'`` is ``left_hand_link``). Base transform: that URDF writes the
    mount yaw as 0.7854 where this model has π/4, so
    :math:`{}^{torso}\mathbf{T}_{hand}^{URDF}(q) = \mathbf{T}(\mathbf{p}_m)\,
    \mathbf{R}_z(0.7854 - \pi/4)\,\mathbf{T}(-\mathbf{p}_m)\;{}^{B}\mathbf{T}_E(q)` with
    :math:`\mathbf{p}_m = (0.024645, 0.219645, 0.118588)` m, a 1.8e-6 rad
    rounding (up to 2e-6 m at the hand). With ``base='shoulder'`` the base
    transform from the URDF link ``left_arm_mount`` is :math:`\mathbf{T}(0.055695, 0, 0.011038)`.
    (Its ``left_gripper`` is an electric gripper 0.1577 m beyond the hand, not
    the 0.05 m of ``end='gripper'``.)

    Parameters
    ----------
    base : {'torso', 'shoulder'}, optional
        ``'torso'`` (default): base frame = Baxter's ``base``/``torso`` frame;
        the arm mount is at (0.024645, 0.219645, 0.118588) m turned π/4 about
        z, and the s0 frame a further (0.055695, 0, 0.011038) m along the
        mount frame. ``'shoulder'``: base frame = the s0 joint frame
        (z along the s0 axis), as in the Imperial College tutorial.
    end : {'hand', 'gripper'}, optional
        End-effector frame: the ``left_hand`` flange (default) or the
        ``left_gripper`` endpoint 5 cm further along z.

    Returns
    -------
    SerialChain
        Joint limits from the URDF (see ``BAXTER_LEFT_LIMITS``).
    """
    table = [
        [0.27035, 0, 0, 0],
        [0, _PI / 2, 0.069, -_PI / 2],
        [0.36442, 0, 0, _PI / 2],
        [0, 0, 0.069, -_PI / 2],
        [0.37429, 0, 0, _PI / 2],
        [0, 0, 0.010, -_PI / 2],
        [0, 0, 0, _PI / 2],
    ]
    if base not in ("torso", "shoulder"):
        raise ValueError(f"base must be 'torso' or 'shoulder'; got {base!r}")
    if end not in ("hand", "gripper"):
        raise ValueError(f"end must be 'hand' or 'gripper'; got {end!r}")
    tool = np.eye(4)
    tool[2, 3] = 0.229525 if end == "hand" else 0.279525
    chain = from_modified_dh(
        table,
        joint_names=_NAMES,
        limits=BAXTER_LEFT_LIMITS,
        tool=tool,
        frame_names=["base", *_NAMES, end],
        name="baxter_left",
    )
    if base == "torso":
        mount = [Tx(0.024645), Ty(0.219645), Tz(0.118588), Rz(_PI / 4), Tx(0.055695), Tz(0.011038)]
        chain = SerialChain(mount + list(chain.elements), limits=BAXTER_LEFT_LIMITS, tool=tool,
                            frame_names=["base", *_NAMES, end], name="baxter_left")
    return chain


def baxter_left_urdf(end: str = "hand") -> SerialChain:
    """The left arm built directly from the URDF joint origins (for verification).

    A link-table chain: each joint's fixed ``<origin>`` transform followed by a
    rotation about the child's z axis; base frame = torso.
    """
    if end not in ("hand", "gripper"):
        raise ValueError(f"end must be 'hand' or 'gripper'; got {end!r}")
    origins = [transform_from_rpy(rpy, xyz) for _, xyz, rpy in BAXTER_LEFT_URDF]
    mount = origins[0]
    transforms = origins[1:8]
    last = origins[8] if end == "hand" else origins[8] @ origins[9]
    return from_link_table(transforms + [last], ["R"] * 7, joint_names=_NAMES,
                           limits=BAXTER_LEFT_LIMITS, base=mount, name="baxter_left_urdf")
