"""AR-601 humanoid robot leg (6 DOF)."""

from __future__ import annotations

import math
from typing import Any

from robokin.chains import Rx, Ry, Rz, SerialChain, Tz
from robokin.validation import check_length

__all__ = ["ar601_leg"]

#: Teaching limits (rad) for q1..q6; not published by the manufacturer.
AR601_LEG_LIMITS = [
    [-math.pi / 2, math.pi / 2],  # q1 hip yaw (z)
    [-math.pi / 2, math.pi / 2],  # q2 hip roll (y)
    [-math.pi / 2, math.pi / 2],  # q3 hip pitch (x)
    [-math.pi / 2, math.pi / 2],  # q4 knee (x)
    [-math.pi / 2, math.pi / 2],  # q5 ankle roll (y)
    [-math.pi / 2, math.pi / 2],  # q6 ankle pitch (x)
]


def ar601_leg(l1: Any = 0.3, l2: Any = 0.3, l3: Any = 0.1) -> SerialChain:
    r"""Leg of the AR-601 humanoid: spherical hip (3), knee (1), ankle (2).

    Source: transform sequence of a 2020 student homework report on the
    AR-601 leg (course material, not distributed with robokin):

    .. math::

        {}^B\mathbf{T}_F = R_z(q_1) R_y(q_2) R_x(q_3)\, T_z(-L_1)\, R_x(q_4)\,
        T_z(-L_2)\, R_y(q_5) R_x(q_6)\, T_z(-L_3).

    (The report's ``T_zL_i`` translates by −L_i.) With all q = 0 the leg hangs
    straight down, foot at z = −(L1 + L2 + L3), as the report checks.

    Frames: the base frame ``B`` at the hip, z up along the straight leg; ``frames(q)``
    gives ``B``, the six joint frames in the order of the product (each at its joint) and
    the foot frame ``F`` at the sole. At q = 0 all frames are parallel to the base. Of the
    report, only the transform sequence and the printed X, Y, Z formulas (which agree with
    it) are used here; chapter 6 of the workbook examines the rest.

    Parameters
    ----------
    l1, l2, l3 : float or sympy.Expr, optional
        Thigh (hip–knee), shank (knee–ankle) and ankle–sole lengths in metres (> 0).
        Defaults 0.3, 0.3, 0.1 m are round teaching values of the order of the
        AR-601's dimensions (the report itself uses 10 units each).

    Returns
    -------
    SerialChain
        Joints ``q1..q6``; limits ±π/2 each (a teaching choice, not hardware data).
    """
    l1, l2, l3 = (check_length(v, k) for v, k in ((l1, "l1"), (l2, "l2"), (l3, "l3")))
    return SerialChain(
        [Rz("q1"), Ry("q2"), Rx("q3"), Tz(-l1), Rx("q4"), Tz(-l2), Ry("q5"), Rx("q6"), Tz(-l3)],
        limits=AR601_LEG_LIMITS,
        frame_names=["B", "hip_yaw", "hip_roll", "hip_pitch", "knee", "ankle_roll", "ankle_pitch", "F"],
        name="ar601_leg",
    )
