"""Three-joint robot leg of ETH Zürich's Autonomous Mobile Robots exercise 1."""

from __future__ import annotations

import math
from typing import Any

from robokin.chains import Rx, Ry, SerialChain, Ty, Tz
from robokin.validation import check_length

__all__ = ["ETH_LEG_LIMITS", "eth_leg"]

#: Default joint limits (rad) of hip abduction α, hip flexion β and knee γ.
#: A documented teaching range, not hardware data: the exercise sets no limits,
#: so the range only has to contain every configuration the exercise itself
#: asks for, with a margin. The configurations of the exercise (chapter 1)
#: span |α| ≤ 15°, β ∈ [−97.2°, 46.7°] (the circle of task 5 needs β ≈ −97°,
#: the thigh raised above horizontal) and |γ| ≤ 151.2°; the limits below
#: leave at least 25° to spare (tests/test_models.py checks this).
ETH_LEG_LIMITS = [
    [-math.pi / 2, math.pi / 2],  # alpha: leg swings sideways at most to horizontal
    [-3 * math.pi / 4, 3 * math.pi / 4],  # beta: thigh up to 45° above horizontal
    [-math.pi, math.pi],  # gamma: knee, full turn (±π: shank folded onto the thigh)
]


def eth_leg(l_b: Any = 1, l_1: Any = 1, l_2: Any = 1, l_3: Any = 1, *, limits: Any = None) -> SerialChain:
    r"""The 3-DOF leg of ETH Zürich's *Autonomous Mobile Robots*, exercise 1.

    Source: ETH AMR exercise 1 ("Kinematics of a single robot leg"), checked
    against a student report (course material, not distributed with robokin);
    the values here are re-derived.

    Frames ``B, 1, 2, 3, F`` (base, hip-abduction, hip-flexion, knee, foot);
    :math:`\mathbf{q} = [\alpha, \beta, \gamma]`: α about the x axis of frame 1,
    β about the y axis of frame 2, γ about the y axis of frame 3. Offsets
    :math:`{}_B\mathbf{r}_{B1} = [0, l_B, 0]`,
    :math:`{}_1\mathbf{r}_{12} = {}_2\mathbf{r}_{23} = {}_3\mathbf{r}_{3F} = [0, 0, -l_i]`
    (:math:`l_1, l_2, l_3` in turn). ``frames(q)`` gives the frames
    ``B, 1, 2, 3, F`` in the base frame; frames 2 and 3 sit at their joint axes.

    The foot position and its Jacobian follow from the chain (``fk``,
    ``jacobian``; Siciliano et al. 2009, §3.1.3, for the Jacobian of a point);
    chapter 1 of the workbook derives them.

    Parameters
    ----------
    l_b, l_1, l_2, l_3 : float or sympy.Expr, optional
        Lengths in metres (default 1): base-to-hip offset along y (any finite
        number), then the three segment lengths along −z (> 0).
    limits : array_like, shape (3, 2), optional
        Joint limits ``[lower, upper]`` (rad) of α, β, γ. Default
        ``ETH_LEG_LIMITS``: α ∈ [−π/2, π/2], β ∈ [−3π/4, 3π/4], γ ∈ [−π, π].
        The exercise sets no joint limits; this default is a teaching range
        (not hardware data) that contains every configuration of the
        exercise -- its inverse-kinematics goals and the whole circle of
        task 5, which needs β ≈ −97° -- with at least 25° to spare. Pass tighter limits to model a real leg,
        e.g. ``limits=[[-pi/2, pi/2], [-pi/2, pi/2], [-pi, pi]]`` for a hip
        that cannot raise the thigh above horizontal.

    Returns
    -------
    SerialChain
        Joints ``alpha, beta, gamma`` with the given limits.

    Raises
    ------
    ShapeError, DomainError
        ``limits`` not of shape (3, 2), NaN, or a lower limit above its upper one;
        a length that is not finite (or a segment length not positive).
    TypeError
        A length that is neither a number nor a sympy expression.
    """
    l_b = check_length(l_b, "l_b", positive=False)
    l_1, l_2, l_3 = (check_length(v, k) for v, k in ((l_1, "l_1"), (l_2, "l_2"), (l_3, "l_3")))
    return SerialChain(
        [Ty(l_b), Rx("alpha"), Tz(-l_1), Ry("beta"), Tz(-l_2), Ry("gamma"), Tz(-l_3)],
        limits=ETH_LEG_LIMITS if limits is None else limits,
        frame_names=["B", "1", "2", "3", "F"],
        name="eth_leg",
    )
