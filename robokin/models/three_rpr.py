r"""Planar 3-RPR parallel robots: the chapter-3 exercise robot and a classic test case.

Both constructors return a :class:`robokin.parallel.Planar3RPR`. The platform frame
has its origin at the platform anchor :math:`B_1` and its :math:`x` axis along
:math:`B_1B_2`, so the pose :math:`(x, y, \varphi)` is the position of
:math:`B_1` and the direction of the side :math:`B_1B_2` -- the parameterisation of
the exercise, with the side lengths :math:`l_2 = |B_1B_2|`, :math:`l_3 = |B_1B_3|` and
the angle :math:`\theta` between the two sides at :math:`B_1`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokin.errors import DomainError
from robokin.parallel import Planar3RPR
from robokin.validation import check_positive

__all__ = ["CLASSIC_RHO", "EXERCISE_BASE", "three_rpr", "three_rpr_classic"]

#: Base anchors A1, A2, A3 of the exercise (m): an equilateral triangle with unit sides.
EXERCISE_BASE = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, math.sqrt(3.0) / 2.0]])

#: Leg lengths (m) at which :func:`three_rpr_classic` has six real assembly modes.
CLASSIC_RHO = np.array([1.498, 1.538, 1.2])


def _platform(l2: float, l3: float, theta: float) -> np.ndarray:
    return np.array([[0.0, 0.0], [l2, 0.0], [l3 * math.cos(theta), l3 * math.sin(theta)]])


def three_rpr(platform_side: Any = 1.0, stroke: Any = (0.0, 2.0)) -> Planar3RPR:
    r"""The 3-RPR robot of the chapter-3 exercise.

    Base anchors :math:`A_1 = (0, 0)`, :math:`A_2 = (1, 0)`, :math:`A_3 = (1/2, \sqrt3/2)` m;
    the platform is an equilateral triangle with side ``platform_side`` (the
    exercise's :math:`l_2 = l_3`, with :math:`\theta = \pi/3`), anchors in the platform
    frame :math:`b_1 = (0, 0)`, :math:`b_2 = (l, 0)`, :math:`b_3 = l(\tfrac12, \tfrac{\sqrt3}{2})`.

    With the default side 1 m the platform is congruent to the base, a special
    architecture whose assembly modes chapter 3 of the workbook studies (Merlet 2006,
    ch. 4).

    Parameters
    ----------
    platform_side : float, optional
        Side of the platform triangle, metres (default 1.0, the exercise).
    stroke : array_like, shape (2,) or (3, 2), optional
        Leg length limits ``(ρ_min, ρ_max)`` in metres (default ``(0, 2)``).

    Returns
    -------
    Planar3RPR
    """
    side = check_positive(platform_side, "platform_side", scalar=True)
    try:
        platform = _platform(side, side, math.pi / 3)
        Planar3RPR(EXERCISE_BASE, platform)  # the platform triangle's checks, before the stroke's
    except DomainError as exc:
        raise DomainError(f"platform_side = {side:g} m gives an invalid platform: {exc}") from None
    return Planar3RPR(EXERCISE_BASE, platform, stroke=stroke, name="3-RPR (exercise)")


def three_rpr_classic(stroke: Any = (0.0, 3.0)) -> Planar3RPR:
    r"""A generic 3-RPR robot with six real assembly modes at :data:`CLASSIC_RHO`.

    The test case that goes back to Gosselin, Sefrioui & Richard (1992) and is used
    throughout the literature on the direct kinematics of planar parallel robots
    (Merlet 2006, ch. 4), scaled by 1/10 to metres: :math:`A_1 = (0, 0)`,
    :math:`A_2 = (1.591, 0)`, :math:`A_3 = (0, 1.0)`; :math:`l_2 = 1.704`,
    :math:`l_3 = 2.084`, :math:`\theta = 0.882603` rad; leg lengths
    :math:`\rho = (1.498, 1.538, 1.2)` give six real solutions.

    Parameters
    ----------
    stroke : array_like, shape (2,) or (3, 2), optional
        Leg length limits in metres (default ``(0, 3)``).

    Returns
    -------
    Planar3RPR
    """
    base = np.array([[0.0, 0.0], [1.591, 0.0], [0.0, 1.0]])
    return Planar3RPR(base, _platform(1.704, 2.084, 0.882603), stroke=stroke, name="3-RPR (classic)")
