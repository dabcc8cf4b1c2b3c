"""Planar two-link (RR) arm."""

from __future__ import annotations

import math
from typing import Any

from robokin.chains import Rz, SerialChain, Tx
from robokin.validation import check_length

__all__ = ["planar_two_link"]


def planar_two_link(l1: Any = 1.0, l2: Any = 1.0) -> SerialChain:
    r"""Planar RR arm moving in the x–y plane of the base frame.

    Elementary transforms: ``Rz(q1) Tx(l1) Rz(q2) Tx(l2)``; both joints rotate
    about z. The end-effector position is

    .. math::

        \mathbf{p} = \begin{bmatrix} l_1 c_1 + l_2 c_{12} \\ l_1 s_1 + l_2 s_{12} \\ 0 \end{bmatrix}

    (Siciliano et al. 2009, §2.9.1; Lynch & Park 2017, §4.1).

    Parameters
    ----------
    l1, l2 : float or sympy.Expr, optional
        Link lengths in metres (default 1.0), > 0. Sympy symbols give a chain whose
        symbolic kinematics keep the lengths as parameters (use ``.subs`` before
        numeric evaluation).

    Returns
    -------
    SerialChain
        Joints ``q1, q2`` with limits ±π; frames ``base, 1, 2, ee``: frame 1 at
        the base origin (shoulder), frame 2 at the elbow, ``ee`` at the tip.

    Raises
    ------
    TypeError, DomainError
        A length that is not a number (or sympy expression), not finite or not positive.
    """
    l1, l2 = check_length(l1, "l1"), check_length(l2, "l2")
    return SerialChain(
        [Rz("q1"), Tx(l1), Rz("q2"), Tx(l2)],
        limits=[[-math.pi, math.pi]] * 2,
        frame_names=["base", "1", "2", "ee"],
        name="planar_two_link",
    )
