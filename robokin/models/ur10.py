"""Universal Robots UR10 (CB3) arm."""

from __future__ import annotations

import math


from robokin.chains import Rx, Rz, SerialChain, Tx, Tz, from_dh, from_modified_dh

__all__ = ["ur10", "UR10_DH"]

_PI = math.pi

#: Manufacturer standard DH parameters of the UR10 (CB3), rows (d, θ_offset, a, α), SI units.
UR10_DH = [
    [0.1273, 0, 0, _PI / 2],
    [0, 0, -0.612, 0],
    [0, 0, -0.5723, 0],
    [0.163941, 0, 0, _PI / 2],
    [0.1157, 0, 0, -_PI / 2],
    [0.0922, 0, 0, 0],
]

_LIMITS = [[-2 * math.pi, 2 * math.pi]] * 6
_NAMES = ["shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"]
_FRAMES = ["base", "shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3", "tool0"]


def ur10(description: str = "dh") -> SerialChain:
    r"""Universal Robots UR10 (CB3 series), 6 revolute joints.

    Source: Universal Robots, "DH parameters for calculations of kinematics and
    dynamics" (support article), UR10 CB3 standard DH table, metres/radians:

    ====  ========  =======  ========  =====
    i     d_i       a_i      α_i       θ_i
    ====  ========  =======  ========  =====
    1     0.1273    0        π/2       q1
    2     0         −0.612   0         q2
    3     0         −0.5723  0         q3
    4     0.163941  0        π/2       q4
    5     0.1157    0        −π/2      q5
    6     0.0922    0        0         q6
    ====  ========  =======  ========  =====

    Joint limits ±2π (the controller's range) for all joints. The base frame is
    the robot's ``base`` frame (z up along joint 1), the end-effector the tool
    flange (``tool0``: z out of the flange).

    Cross-checked (``tests/test_urdf.py``, 1,000 configurations, 1e-9 m / 1e-9 rad)
    against example-robot-data's ``ur10_robot.urdf``
    (``from_urdf(robot_description("ur10"), base_link, tip_link)``), same q:
    from the URDF links ``base`` to ``tool0`` the base and tool transforms are the
    identity; from the URDF's root ``base_link`` to ``ee_link``,
    :math:`{}^{base\_link}\mathbf{T}_{ee\_link}(q) = \mathbf{R}_z(\pi)\,
    {}^{B}\mathbf{T}_E(q)\,\mathbf{R}_x(\pi/2)\,\mathbf{R}_z(\pi/2)`. That URDF limits
    the elbow to ±π; this model keeps ±2π on purpose.

    Parameters
    ----------
    description : {'dh', 'mdh', 'ets'}, optional
        Which (equivalent) description builds the chain: the standard DH table
        (default), the same arm as a modified (Craig) DH table
        (:math:`a_{i-1}, \alpha_{i-1}` shifted by one row), or hand-written
        elementary transforms. All three give the same ``fk`` and ``jacobian``;
        their intermediate joint frames sit at different points on the joint
        axes.

    Returns
    -------
    SerialChain
    """
    if description == "dh":
        return from_dh(UR10_DH, joint_names=_NAMES, limits=_LIMITS, frame_names=_FRAMES, name="ur10")
    if description == "mdh":
        rows = []
        prev_a: float = 0
        prev_alpha: float = 0
        for d, off, a, alpha in UR10_DH:
            rows.append([d, off, prev_a, prev_alpha])
            prev_a, prev_alpha = a, alpha
        # the last standard-DH row has a6 = alpha6 = 0, so no tool transform is needed
        return from_modified_dh(rows, joint_names=_NAMES, limits=_LIMITS, frame_names=_FRAMES,
                                name="ur10")
    if description == "ets":
        d1, a2, a3, d4, d5, d6 = 0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922
        els = [
            Tz(d1), Rz(_NAMES[0]), Rx(_PI / 2),
            Rz(_NAMES[1]), Tx(a2),
            Rz(_NAMES[2]), Tx(a3), Tz(d4),
            Rz(_NAMES[3]), Rx(_PI / 2), Tz(d5),
            Rz(_NAMES[4]), Rx(-_PI / 2), Tz(d6),
            Rz(_NAMES[5]),
        ]
        return SerialChain(els, limits=_LIMITS, frame_names=_FRAMES, name="ur10")
    raise ValueError(f"description must be 'dh', 'mdh' or 'ets'; got {description!r}")
