r"""Exercise checks of chapter 9: Statics and the velocity and force ellipsoids.

=================  ==========================================  ==========
check              the student's answer                         inputs
=================  ==========================================  ==========
``tool_position``  p(q): tool position (x, y) in m, shape (2,)  q1, q2
``tool_jacobian``  J(q) = ∂p/∂q: 2×2, in m/rad                 q1, q2
=================  ==========================================  ==========

Every reference comes from the chapter's robot model (one model definition); the
diagnoses are the standard ones for a vector (a sign, degrees for radians, swapped
or negated inputs). See the book's page "Adding a chapter" for the pattern.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import Check, Variable
from robokin.check._registry import exercise

__all__ = ["tool_position", "tool_jacobian"]

_CHAPTER = "statics_ellipsoids"

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back (``tool_position = ...fk``) is flagged for review by hand
#: (tools/grading_bridge/delegation.py reads this literal table without importing the module)
DELEGATION = {
    "tool_position": {"fk": "SerialChain.fk", "frames": "SerialChain.frames"},
    "tool_jacobian": {"position_jacobian": "SerialChain.position_jacobian", "jacobian": "SerialChain.jacobian"},
}


@lru_cache(maxsize=1)
def _arm():
    from robokin.models import planar_two_link

    return planar_two_link()


tool_position = exercise(_CHAPTER, "tool_position", Check(
    name="tool_position",
    reference=lambda x: np.asarray(_arm().fk(x))[:2, 3],
    variables=[Variable("q1"), Variable("q2")],
    groups=[("q", [0, 1])],
    diagnoses=dg.standard("vector"),
    noun="angles",
    doc="Check tool_position(q): the tool position (x, y) in m of the two-link arm, shape (2,).",
))

tool_jacobian = exercise(_CHAPTER, "tool_jacobian", Check(
    name="tool_jacobian",
    reference=lambda x: np.asarray(_arm().position_jacobian(x))[:2],
    variables=[Variable("q1"), Variable("q2")],
    groups=[("q", [0, 1])],
    diagnoses=dg.standard("jacobian"),
    noun="angles",
    doc="Check tool_jacobian(q): the 2x2 Jacobian of the tool position, in m/rad.",
))
