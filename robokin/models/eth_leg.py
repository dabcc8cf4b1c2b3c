"""Three-joint robot leg of ETH Zürich's Autonomous Mobile Robots exercise 1."""

from __future__ import annotations

import math
from typing import Any

from robokin.chains import Rx, Ry, SerialChain, Ty, Tz

__all__ = ["eth_leg"]

#: Default joint limits (rad): hip abduction α, hip flexion β, knee γ.
ETH_LEG_LIMITS = [
    [-math.pi / 2, math.pi / 2],  # alpha: leg swings sideways at most to horizontal
    [-math.pi / 2, math.pi / 2],  # beta: thigh forward/backward at most to horizontal
    [-math.pi, math.pi],  # gamma: knee, full turn minus the folded-back pose
]


def eth_leg(l_b: Any = 1, l_1: Any = 1, l_2: Any = 1, l_3: Any = 1) -> SerialChain:
    r"""The 3-DOF leg of ETH Zürich's *Autonomous Mobile Robots*, exercise 1.

    Source: ETH AMR exercise 1 ("Kinematics of a single robot leg"), checked
    against a student report (in /work/shared/seeds/000_*), whose printed
    Jacobian (eq. 20) has a sign slip in entry (3, 3); the values here are
    re-derived.

    Frames ``B, 1, 2, 3, F`` (base, hip-abduction, hip-flexion, knee, foot);
    :math:`\mathbf{q} = [\alpha, \beta, \gamma]`: α about the x axis of frame 1,
    β about the y axis of frame 2, γ about the y axis of frame 3. Offsets
    :math:`{}_B\mathbf{r}_{B1} = [0, l_B, 0]`,
    :math:`{}_1\mathbf{r}_{12} = {}_2\mathbf{r}_{23} = {}_3\mathbf{r}_{3F} = [0, 0, -l_i]`.
    Elementary transforms::

        Ty(l_b) Rx(alpha) Tz(-l_1) Ry(beta) Tz(-l_2) Ry(gamma) Tz(-l_3)

    Note that the joint frames 2 and 3 of the chain sit at the joint axes,
    i.e. ``frames(q)[2]`` is the pose after ``Tz(-l_1) Ry(beta)``.

    With unit lengths the foot position is

    .. math::

        {}_B\mathbf{r}_{BF} = \begin{bmatrix}
            -\sin\beta - \sin(\beta+\gamma) \\
            \sin\alpha\,(1 + \cos\beta + \cos(\beta+\gamma)) + 1 \\
            -\cos\alpha\,(1 + \cos\beta + \cos(\beta+\gamma)) \end{bmatrix}.

    Parameters
    ----------
    l_b, l_1, l_2, l_3 : float or sympy.Expr, optional
        Lengths in metres (default 1): base-to-hip offset along y, then the
        three segment lengths along −z.

    Returns
    -------
    SerialChain
        Joints ``alpha, beta, gamma``; limits (rad) α, β ∈ [−π/2, π/2],
        γ ∈ [−π, π] (a teaching choice, not from hardware).
    """
    return SerialChain(
        [Ty(l_b), Rx("alpha"), Tz(-l_1), Ry("beta"), Tz(-l_2), Ry("gamma"), Tz(-l_3)],
        limits=ETH_LEG_LIMITS,
        frame_names=["B", "1", "2", "3", "F"],
        name="eth_leg",
    )
