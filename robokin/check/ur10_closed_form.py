r"""Exercise checks of chapter 7: closed-form inverse kinematics of the UR10.

Every reference is computed from the DH table of :func:`robokin.models.ur10`
(``robokin.models.ur10.UR10_DH``, the manufacturer's signs: ``a2``, ``a3`` < 0,
``d4`` > 0). A check samples 20 configurations ``q`` (away from the poses at
which two branches of a step meet, the chapter's last task), builds the flange
pose ``T = fk(q)`` and calls the student's function on it.

=======================  ===========================================================  ===========================
check                    the student's answer                                          compared with
=======================  ===========================================================  ===========================
``wrist_centre``         ``f(T)`` -> the origin of frame 5, shape (3,), in m            ``frames(q)[6]``
``shoulder_angles``      ``f(T)`` -> both q1 (rad), shape (2,)                          the two shoulder solutions
``wrist_angles``         ``f(T, q1)`` -> both ``(q5, q6)`` (rad), shape (2, 2)          the two wrist solutions
``arm_angles``           ``f(T, q1, q5, q6)`` -> both ``(q2, q3, q4)``, shape (2, 3)    the two elbow solutions
``all_solutions``        ``f(T)`` -> every solution, shape (k, 6)                       :func:`robokin.models.ur10_ik`
``coinciding_branches``  ``f(q)`` -> the steps whose two solutions coincide at fk(q)    configurations of its own
=======================  ===========================================================  ===========================

Sets of solutions are compared in any order, angles modulo 2π
(:class:`robokin.check.SolutionSetCheck`). Typical mistakes named in the messages:
the arguments of ``atan2`` swapped, a ``±`` branch dropped or the wrong second
branch, the sign of ``d4`` or of an axis, ``a2``/``a3`` taken positive, an offset
of the table used for another, the flange point used for the wrist centre, the
wrist point used for the planar problem, degrees for radians.

``reference_wrist_centre``, ``reference_shoulder_angles``, ``reference_wrist_angles`` and
``reference_arm_angles`` are robokin's answers to the steps of Tasks 1-3, with the student's
signatures: the graded tests of a later step pass them to the student's function in place of
the student's own steps, so that a mistake in one step costs the points of that step only. The
checks of the later steps pass them too, to the keyword parameters through which the student's
function takes its steps (``wrist_centre=``, ``shoulder_angles=``, ...), so that their verdict
(and the grading report's) is on that step alone.

Usage::

    from robokin import check
    check.ur10_closed_form.shoulder_angles(my_shoulder_angles)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import lru_cache, partial
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    AnswerError, Check, CheckResult, FunctionCheck, MatrixArgumentsCheck, Variable, alternatives, not_a_function,
    with_reference_steps,
)
from robokin.check._registry import exercise
from robokin.check.solutions import SolutionSetCheck
from robokin.validation import as_float_array, as_scalar, check_transform

__all__ = [
    "all_solutions",
    "arm_angles",
    "coinciding_branches",
    "reference_arm_angles",
    "reference_shoulder_angles",
    "reference_wrist_angles",
    "reference_wrist_centre",
    "shoulder_angles",
    "wrist_angles",
    "wrist_centre",
]

_CHAPTER = "ur10_closed_form"

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back (``all_solutions = ur10_ik``) is flagged for review by hand
#: (tools/grading/bridge/delegation.py reads this literal table without importing the module)
DELEGATION = {
    "wrist_centre": {"ur10_ik": "robokin.models.ur10_ik", "ur10_ik_batch": "robokin.models.ur10_ik_batch",
                     "reference_wrist_centre": "robokin.check.ur10_closed_form.reference_wrist_centre"},
    "shoulder_angles": {"ur10_ik": "robokin.models.ur10_ik", "ur10_ik_batch": "robokin.models.ur10_ik_batch",
                        "reference_wrist_centre": "robokin.check.ur10_closed_form.reference_wrist_centre",
                        "reference_shoulder_angles": "robokin.check.ur10_closed_form.reference_shoulder_angles"},
    "wrist_angles": {"ur10_ik": "robokin.models.ur10_ik", "ur10_ik_batch": "robokin.models.ur10_ik_batch",
                     "reference_wrist_angles": "robokin.check.ur10_closed_form.reference_wrist_angles"},
    "arm_angles": {"ur10_ik": "robokin.models.ur10_ik", "ur10_ik_batch": "robokin.models.ur10_ik_batch",
                   "reference_wrist_centre": "robokin.check.ur10_closed_form.reference_wrist_centre",
                   "reference_arm_angles": "robokin.check.ur10_closed_form.reference_arm_angles"},
    "all_solutions": {"ur10_ik": "robokin.models.ur10_ik", "ur10_ik_batch": "robokin.models.ur10_ik_batch",
                      "reference_wrist_centre": "robokin.check.ur10_closed_form.reference_wrist_centre",
                      "reference_shoulder_angles": "robokin.check.ur10_closed_form.reference_shoulder_angles",
                      "reference_wrist_angles": "robokin.check.ur10_closed_form.reference_wrist_angles",
                      "reference_arm_angles": "robokin.check.ur10_closed_form.reference_arm_angles",
                      "solve_ik": "robokin.motion.solve_ik", "solve_ik_batch": "robokin.motion.solve_ik_batch"},
    # the flags of robokin's closed form (.singular) name the coinciding branches
    "coinciding_branches": {"ur10_ik": "robokin.models.ur10_ik", "ur10_ik_batch": "robokin.models.ur10_ik_batch"},
}


@lru_cache(maxsize=1)
def _robot():
    from robokin.models import ur10

    return ur10()


@lru_cache(maxsize=1)
def _lengths() -> tuple[float, float, float, float, float, float]:
    """d1, a2, a3, d4, d5, d6 (m) of the UR10 table."""
    from robokin.models.ur10 import UR10_DH

    t = [[float(v) for v in row] for row in UR10_DH]
    return t[0][0], t[1][2], t[2][2], t[3][0], t[4][0], t[5][0]


def _wrap(a: Any) -> np.ndarray:
    """Angles wrapped into (−π, π]."""
    return np.pi - np.mod(np.pi - np.asarray(a, dtype=float), 2 * np.pi)


def _pose(x: np.ndarray) -> np.ndarray:
    return np.asarray(_robot().fk(np.asarray(x, dtype=float), check=False), dtype=float)


# The sampled configurations: q3 and q5 in (0.35, 2.8) (the other branch has the negative
# angle), so that no sample is near the elbow or wrist singularity; q2 in a band that keeps
# the wrist centre away from the base axis (checked in the tests: 4 or 8 solutions, none singular).
_Q = [
    Variable("q1", low=-math.pi, high=math.pi),
    Variable("q2", low=-2.6, high=-0.6),
    Variable("q3", low=0.35, high=2.8),
    Variable("q4", low=-math.pi, high=math.pi),
    Variable("q5", low=0.35, high=2.8),
    Variable("q6", low=-math.pi, high=math.pi),
]
_GROUP = [("q", [0, 1, 2, 3, 4, 5])]


# ------------------------------------------------------------------ the steps, right and wrong
def _centre(T: np.ndarray) -> np.ndarray:
    return T[:3, 3] - _lengths()[5] * T[:3, 2]


def _shoulder(T: np.ndarray, *, swap: bool = False, d4_sign: float = 1.0, flange: bool = False,
              second: str = "") -> np.ndarray:
    x, y, _ = T[:3, 3] if flange else _centre(T)
    r = math.hypot(x, y)
    psi = math.atan2(x, y) if swap else math.atan2(y, x)
    ratio = max(-1.0, min(1.0, d4_sign * _lengths()[3] / r))
    if second == "minus_arcsin":  # sin(q1 - psi) = d4/r solved as q1 - psi = ±arcsin(d4/r)
        return _wrap(np.array([psi + math.asin(ratio), psi - math.asin(ratio)]))
    if second == "cosine":  # r cos(q1 - psi) = d4 solved instead of r sin(q1 - psi) = d4
        return _wrap(np.array([psi + math.acos(ratio), psi - math.acos(ratio)]))
    beta = math.acos(ratio)
    return _wrap(np.array([psi + math.pi / 2 + beta, psi + math.pi / 2 - beta]))


def _wrist(T: np.ndarray, q1: float, *, swap: bool = False, q6_sign: float = 1.0, z1_sign: float = 1.0,
           flip: bool = True) -> np.ndarray:
    z1 = z1_sign * np.array([math.sin(q1), -math.cos(q1), 0.0])
    x6z, y6z, c5 = T[:3, :3].T @ z1
    out = []
    for sign in (1.0, -1.0):
        s5 = sign * math.hypot(x6z, y6z)
        s6_divisor = s5 if flip else abs(s5)  # not flip: q6 kept when the wrist flips
        q6 = (math.atan2(x6z / s6_divisor, -y6z / s6_divisor) if swap
              else math.atan2(-q6_sign * y6z / s6_divisor, x6z / s6_divisor))
        out.append([math.atan2(s5, c5), q6])
    return _wrap(np.array(out))


def _arm(T: np.ndarray, q1: float, q5: float, q6: float, *, a_sign: float = 1.0, swap: bool = False,
         wrist_point: bool = False, phi_swap: bool = False, inner_sign: float = -1.0, q3_in_q4: bool = True,
         shoulder_height: bool = True) -> np.ndarray:
    d1, a2, a3, _d4, d5, _d6 = _lengths()
    a2, a3 = a_sign * a2, a_sign * a3
    R = T[:3, :3]
    c1, s1, c5, s5, c6, s6 = (math.cos(q1), math.sin(q1), math.cos(q5), math.sin(q5), math.cos(q6),
                              math.sin(q6))
    z4 = R @ np.array([-s6, -c6, 0.0])
    x4 = R @ np.array([c5 * c6, -c5 * s6, -s5])
    o4 = _centre(T) - (0.0 if wrist_point else d5) * z4
    X, Y = c1 * o4[0] + s1 * o4[1], o4[2] - (d1 if shoulder_height else 0.0)
    c3 = (X * X + Y * Y - a2 * a2 - a3 * a3) / (2 * a2 * a3)
    if abs(c3) > 1.0:
        return np.zeros((0, 3))
    in_plane = (x4[2], c1 * x4[0] + s1 * x4[1])
    phi = math.atan2(in_plane[1], in_plane[0]) if phi_swap else math.atan2(*in_plane)
    out = []
    for q3 in (math.acos(c3), -math.acos(c3)):
        to_target = math.atan2(X, Y) if swap else math.atan2(Y, X)
        q2 = to_target + inner_sign * math.atan2(a3 * math.sin(q3), a2 + a3 * math.cos(q3))
        out.append([q2, q3, phi - q2 - (q3 if q3_in_q4 else 0.0)])
    return _wrap(np.array(out))


def _all(T: np.ndarray) -> np.ndarray:
    from robokin.models.ur_ik import ur10_ik

    return np.asarray(ur10_ik(T, check=False).q, dtype=float)


def _rows_in(S: np.ndarray, R: np.ndarray, atol: float) -> bool:
    """Every row of S is a different row of R (angles modulo 2π)."""
    found = []
    for row in S:
        close = np.all(np.abs(_wrap(R - row)) <= atol, axis=1)
        if not close.any():
            return False
        found.append(int(np.argmax(close)))
    return len(set(found)) == len(found)


def _same_rows(S: np.ndarray, W: np.ndarray, atol: float) -> bool:
    """S and W hold the same rows (angles modulo 2π; a repeated row may stand for itself twice)."""
    if len(S) != len(W):
        return False
    close = np.all(np.abs(_wrap(S[:, None, :] - W[None, :, :])) <= atol, axis=2)
    return bool(close.any(axis=1).all() and close.any(axis=0).all())


# ------------------------------------------------------------------ the check class
class _ShortRepr:
    """A check's repr (what ``help()`` and a bare name in a notebook show): its name and
    signature only. The dataclass repr listed every field, the messages of the typical
    mistakes with the closed forms among them, before the student had written a line."""

    name: str
    signature: str

    def __repr__(self) -> str:
        return f"<robokin.check.{_CHAPTER}.{self.name}: {self.signature}>"


class _CentreCheck(_ShortRepr, MatrixArgumentsCheck):
    """The check of ``wrist_centre``: a :class:`MatrixArgumentsCheck` with the short repr."""


@dataclass(repr=False)
class _PoseSetCheck(_ShortRepr, SolutionSetCheck):
    """A :class:`SolutionSetCheck` of a function of the flange pose (and earlier angles).

    ``arguments(q)`` gives the student's function's arguments for the generating
    configuration ``q``; ``mistakes`` are ``(code, set_function(q), message)``: a student's
    answer that returns that set at every sample is named by the message. A proper
    subset of the reference at every sample is a dropped branch (``branch_message``).
    """

    arguments: Callable[[np.ndarray], tuple] | None = None
    signature: str = ""
    mistakes: list[tuple[str, Callable[[np.ndarray], np.ndarray], str]] = field(default_factory=list)
    branch_message: str = ""
    columns: int = 0
    steps: Callable[[], dict[str, Callable[..., Any]]] = dict

    def evaluate(self, answer: Any) -> CheckResult:
        """Call ``answer(*arguments(q))`` at the sampled configurations and compare the sets;
        a keyword parameter of ``answer`` that ``steps()`` names gets robokin's step."""
        if answer is not None and not callable(answer):
            return not_a_function(self.name, self.signature, answer)
        if answer is None or self.arguments is None:
            return super().evaluate(answer)
        build, student = self.arguments, with_reference_steps(answer, self.steps())

        def call(q: np.ndarray) -> Any:
            out = student(*build(np.asarray(q, dtype=float)))
            if self.columns == 1 and isinstance(out, (list, tuple, np.ndarray)):
                try:  # one angle per solution: the rows of a column
                    return np.asarray(out, dtype=float).reshape(-1, 1)
                except (TypeError, ValueError):
                    return out
            return out

        result = super().evaluate(call)
        if result.diagnosis == "degrees":  # every angle it returns is in degrees
            return CheckResult(result.name, False, result.message, "degrees_output", result.samples)
        if result.passed or result.diagnosis == "error":
            return result
        try:
            X, refs, got = self._sets(call)
        except AnswerError:
            return result
        width = refs[0].shape[-1]
        if any(S.ndim != 2 or S.shape[-1] != width or not np.all(np.isfinite(S)) for S in got):
            return result
        with np.errstate(all="ignore"):
            for code, wrong, message in self.mistakes:
                if all(_same_rows(S, np.asarray(wrong(x), dtype=float).reshape(-1, width), self.atol)
                       for S, x in zip(got, X)):
                    return self._fail(code, message.format(name=self.name), len(X))
            subsets = [0 < len(S) < len(R) and _rows_in(S, R, self.atol) for S, R in zip(got, refs)]
        if self.branch_message and all(subsets):
            return self._fail("branch_dropped", self.branch_message.format(name=self.name), len(X))
        return result




# ------------------------------------------------------------------ the checks
def _wrist_centre_mistakes():
    d6 = _lengths()[5]
    return [
        alternatives("flange_point", [(lambda x: _pose(x)[:3, 3], (
            "{name} is the flange position p: the wrist centre is the origin of frame 5, "
            "p − d6 z6, d6 back along the tool's z axis."))]),
        alternatives("d6_sign", [(lambda x: _pose(x)[:3, 3] + d6 * _pose(x)[:3, 2], (
            "{name} is p + d6 z6: the flange lies d6 beyond the wrist centre along z6, "
            "so the centre is p − d6 z6."))]),
        alternatives("wrong_axis", [(lambda x: _pose(x)[:3, 3] - d6 * _pose(x)[2, :3], (
            "{name} uses the third row of R for z6: the tool's z axis is the third column, "
            "R[:, 2] (the columns of R are the flange's axes in the base frame)."))]),
        alternatives("d5_for_d6", [(lambda x: _pose(x)[:3, 3] - _lengths()[4] * _pose(x)[:3, 2], (
            "{name} steps back d5 along z6: d5 is the offset from frame 4 to frame 5; the last "
            "row of the table, d6, is the one from the wrist centre to the flange."))]),
    ]


wrist_centre = exercise(_CHAPTER, "wrist_centre", _CentreCheck(
    name="wrist_centre",
    reference=lambda x: np.asarray(_robot().frames(np.asarray(x, dtype=float))[6][:3, 3], dtype=float),
    variables=_Q,
    groups=_GROUP,
    arguments=lambda x: (_pose(x),),
    signature="wrist_centre(T) -> (3,) array in m",
    diagnoses=_wrist_centre_mistakes(),
    noun="configurations",
    atol=1e-9,
    doc="Check wrist_centre(T): the origin of frame 5 (m, base frame) for the flange pose T (4, 4).",
))

def _pose_set_check(name: str, solve: Callable[..., np.ndarray], arguments: Callable[[np.ndarray], tuple], *,
                    signature: str, branch_message: str, doc: str,
                    mistakes: Sequence[tuple[str, dict[str, Any], str]] = (), columns: int = 0,
                    steps: Callable[[], dict[str, Callable[..., Any]]] = dict) -> Check:
    """The chapter's check of a step ``solve(*arguments(q))`` over the sampled configurations.

    Parameters
    ----------
    name : str
        The student's function, as the messages name it.
    solve : callable
        The step written right (``_shoulder``, ``_wrist``, ...), whose keywords make its mistakes.
    arguments : callable
        ``arguments(q)``: the function's arguments (the flange pose, earlier angles) at ``q`` (6,).
    signature, branch_message, doc : str
        As for :class:`_PoseSetCheck`.
    mistakes : sequence of (str, dict, str)
        ``(code, keywords of solve, message)``: the answer ``solve(*arguments(q), **keywords)``.
    columns : int, optional
        1 where the answer is one angle per solution (a column).
    steps : callable, optional
        ``steps()``: robokin's earlier steps by the names of the keyword parameters through
        which the student's function takes them (``wrist_centre=``, ...), passed in place of
        the student's own.

    Returns
    -------
    Check
        Registered as ``robokin.check.ur10_closed_form.<name>``.
    """
    def solved(x: np.ndarray, **keywords: Any) -> np.ndarray:
        out = solve(*arguments(x), **keywords)
        return out.reshape(-1, 1) if columns == 1 else out

    return exercise(_CHAPTER, name, _PoseSetCheck(
        name=name,
        reference=solved,
        variables=_Q,
        groups=_GROUP,
        arguments=arguments,
        signature=signature,
        mistakes=[(code, partial(solved, **keywords), message) for code, keywords, message in mistakes],
        branch_message=branch_message,
        columns=columns,
        steps=steps,
        diagnoses=[dg.degrees_output()],  # named by evaluate: every returned angle in degrees
        noun="configurations",
        atol=1e-7,
        doc=doc,
    ))


shoulder_angles = _pose_set_check(
    "shoulder_angles", _shoulder, lambda x: (_pose(x),),
    signature="shoulder_angles(T) -> (2,) array of q1 in rad",
    columns=1,
    steps=lambda: {"wrist_centre": reference_wrist_centre},
    mistakes=[
        ("atan2_swapped", {"swap": True},
         "{name} uses atan2(x, y) for the direction of the wrist centre: atan2 takes the y "
         "coordinate first, ψ = atan2(y, x)."),
        ("d4_sign", {"d4_sign": -1.0},
         "{name} has the sign of d4 wrong: the wrist centre lies at +d4 along z1 (the table's "
         "d4 = +0.1639 m), not at −d4."),
        ("flange_point", {"flange": True},
         "{name} uses the flange position p instead of the wrist centre p5 = p − d6 z6: only "
         "the wrist centre is at the height d4 along z1."),
        ("arcsin_branch", {"second": "minus_arcsin"},
         "{name} gives q1 = ψ ± arcsin(d4/r): the second solution of sin(q1 − ψ) = d4/r is "
         "q1 − ψ = π − arcsin(d4/r), not −arcsin(d4/r)."),
        ("cosine_for_sine", {"second": "cosine"},
         "{name} gives q1 = ψ ± arccos(d4/r), the solutions of cos(q1 − ψ) = d4/r; the component "
         "of the wrist centre along z1 = (s1, −c1, 0) is x s1 − y c1 = r sin(q1 − ψ)."),
    ],
    branch_message="{name} returns only one of the two shoulder solutions: the equation for q1 "
                   "has two solutions in a full turn; return both.",
    doc="Check shoulder_angles(T): both solutions q1 (rad) for the flange pose T (4, 4).",
)

wrist_angles = _pose_set_check(
    "wrist_angles", _wrist, lambda x: (_pose(x), float(x[0])),
    signature="wrist_angles(T, q1) -> (2, 2) array of rows (q5, q6) in rad",
    mistakes=[
        ("atan2_swapped", {"swap": True},
         "{name} has the arguments of atan2 swapped in q6: atan2(y, x) takes first the "
         "component of z1 in flange coordinates proportional to sin q6, then the one "
         "proportional to cos q6."),
        ("q6_sign", {"q6_sign": -1.0},
         "{name} gives q6 with the wrong sign: write z1 in flange coordinates, R_6ᵀ z1, out as a "
         "function of q5 and q6 and read the sign of its y component."),
        ("q6_not_flipped", {"flip": False},
         "{name} keeps q6 when the wrist flips: with s5 → −s5, the components (c6 s5, −s6 s5) "
         "keep their values only if q6 turns by π too."),
        ("z1_sign", {"z1_sign": -1.0},
         "{name} uses −z1 for the axis of the parallel joints: work out z1 = R_z(q1) R_x(π/2) e_z "
         "(α1 = π/2 in the table) and keep its sign."),
    ],
    branch_message="{name} returns only one wrist solution: sin q5 may take either sign; "
                   "return both, each with its q6.",
    doc="Check wrist_angles(T, q1): both rows (q5, q6) (rad) for the flange pose T and the shoulder angle q1.",
)

arm_angles = _pose_set_check(
    "arm_angles", _arm, lambda x: (_pose(x), float(x[0]), float(x[4]), float(x[5])),
    signature="arm_angles(T, q1, q5, q6) -> (2, 3) array of rows (q2, q3, q4) in rad",
    steps=lambda: {"wrist_centre": reference_wrist_centre},
    mistakes=[
        ("a_sign", {"a_sign": -1.0},
         "{name} uses positive a2, a3: the table's a2 = −0.612 m and a3 = −0.5723 m are negative "
         "(with q = 0 the arm points along −x1), which turns q2 and q4 by π."),
        ("atan2_swapped", {"swap": True},
         "{name} has the arguments of atan2 swapped in q2: the direction to the point (X, Y) in "
         "the arm's plane is atan2(Y, X), the Y coordinate first."),
        ("wrist_point", {"wrist_point": True},
         "{name} solves the planar problem for the wrist centre p5; the three parallel links end "
         "at the origin of frame 4, p4 = p5 − d5 z4."),
        ("shoulder_height", {"shoulder_height": False},
         "{name} measures the height of p4 from the base; the planar links start at the origin "
         "of frame 1, (0, 0, d1), so the arm's plane has Y = p4·e_z − d1."),
        ("atan2_swapped_phi", {"phi_swap": True},
         "{name} has the arguments of atan2 swapped in q2 + q3 + q4: the angle of x4 in the arm's "
         "plane takes its Y component first, then its X component."),
        ("inner_angle_sign", {"inner_sign": 1.0},
         "{name} adds the angle of the elbow triangle to the direction of p4: the links point "
         "at q2 plus that angle, so q2 is the direction of p4 minus it."),
        ("q3_missing_in_q4", {"q3_in_q4": False},
         "{name} leaves q3 out of q4: the angle of x4 in the arm's plane is q2 + q3 + q4, so "
         "q4 is that angle minus q2 and q3."),
    ],
    branch_message="{name} returns only one elbow solution: the law of cosines fixes cos q3 "
                   "only, so q3 may take either sign; return both, with q2 and q4 for each.",
    doc="Check arm_angles(T, q1, q5, q6): both rows (q2, q3, q4) (rad), elbow up and down.",
)

all_solutions = _pose_set_check(
    "all_solutions", _all, lambda x: (_pose(x),),
    signature="all_solutions(T) -> (k, 6) array of solutions in rad",
    steps=lambda: {"shoulder_angles": reference_shoulder_angles, "wrist_angles": reference_wrist_angles,
                   "arm_angles": reference_arm_angles},
    branch_message="{name} misses solutions: every one it returns is right, but it leaves "
                   "some out; loop over every branch of every step.",
    doc="Check all_solutions(T): every joint solution (k, 6) (rad) for the flange pose T (4, 4).",
)



# ------------------------------------------------------------------ robokin's steps, the tests' stand-ins
def _flange_pose(T: Any) -> np.ndarray:
    """``T`` as one flange pose (4, 4): a rigid transform, or an error naming ``T``."""
    return check_transform(as_float_array(T, "T", shape=(4, 4)), name="T")


def reference_wrist_centre(T: Any) -> np.ndarray:
    """robokin's answer to the step ``wrist_centre`` of Task 1 (the tests' stand-in).

    The graded tests of the steps built on it (``shoulder_angles``, ``arm_angles``,
    ``coinciding_branches``) pass this function to the student's function in place of the
    student's own ``wrist_centre``, so that a mistake in the wrist centre costs the points of
    its own test only.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        A flange pose in the base frame (m).

    Returns
    -------
    numpy.ndarray, shape (3,)
        The origin of DH frame 5 in the base frame (m).
    """
    return _centre(_flange_pose(T))


def reference_shoulder_angles(T: Any) -> np.ndarray:
    """robokin's answer to the step ``shoulder_angles`` of Task 1 (the tests' stand-in).

    The graded test of ``all_solutions`` passes it to the student's ``all_solutions`` in
    place of the student's own step.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        A flange pose in the base frame (m).

    Returns
    -------
    numpy.ndarray, shape (2,) or (0,)
        Both shoulder angles q1 (rad, in (−π, π]), or none when the pose has no shoulder
        solution.
    """
    T = _flange_pose(T)
    x, y, _ = (float(v) for v in _centre(T))
    if math.hypot(x, y) < abs(_lengths()[3]):
        return np.zeros(0)
    return _shoulder(T)


def reference_wrist_angles(T: Any, q1: Any) -> np.ndarray:
    """robokin's answer to the step ``wrist_angles`` of Task 2 (the tests' stand-in).

    The graded test of ``all_solutions`` passes it to the student's ``all_solutions`` in
    place of the student's own step.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        A flange pose in the base frame (m).
    q1 : float
        A shoulder angle (rad).

    Returns
    -------
    numpy.ndarray, shape (2, 2)
        Both rows (q5, q6) (rad, in (−π, π]), the one with sin q5 > 0 first. Where q6 is
        undefined the rows hold q6 = 0 and q6 = π.
    """
    T, q1 = _flange_pose(T), as_scalar(q1, "q1")
    z1 = np.array([math.sin(q1), -math.cos(q1), 0.0])
    along_x, along_y, along_z = (float(v) for v in T[:3, :3].T @ z1)
    if math.hypot(along_x, along_y) < 1e-12:  # q6 undefined: robokin's choice, as ur10_ik
        q5 = math.atan2(0.0, along_z)
        return _wrap(np.array([[q5, 0.0], [-q5, math.pi]]))
    return _wrist(T, q1)


def reference_arm_angles(T: Any, q1: Any, q5: Any, q6: Any) -> np.ndarray:
    """robokin's answer to the step ``arm_angles`` of Task 3 (the tests' stand-in).

    The graded test of ``all_solutions`` passes it to the student's ``all_solutions`` in
    place of the student's own step.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        A flange pose in the base frame (m).
    q1, q5, q6 : float
        The angles (rad) of one shoulder and wrist solution.

    Returns
    -------
    numpy.ndarray, shape (2, 3) or (0, 3)
        Both rows (q2, q3, q4) (rad, in (−π, π]), the one with sin q3 ≥ 0 first, or none
        when the two links cannot reach the origin of frame 4.
    """
    T = _flange_pose(T)
    angles = [as_scalar(value, name) for value, name in ((q1, "q1"), (q5, "q5"), (q6, "q6"))]
    d1, a2, a3, d4, d5, _d6 = _lengths()
    if math.hypot(*(float(v) for v in _centre(T))) > d1 + abs(a2) + abs(a3) + d4 + d5:
        return np.zeros((0, 3))  # beyond every link together (and no overflow in the squares)
    return _arm(T, *angles)


# ------------------------------------------------------------------ where two branches meet
_STEPS = ("shoulder", "wrist", "elbow")


def _shoulder_case(q2: float | None, q3: float, q5: float) -> np.ndarray:
    """A configuration with the wrist centre on the cylinder r = |d4| (its X in frame 1,
    a2 c2 + a3 c23 + d5 s234, is 0): q4 solved for it, or with q2 None, q2 from
    a2 c2 + a3 c23 = 0 and q4 = −q2 − q3."""
    _d1, a2, a3, _d4, d5, _d6 = _lengths()
    if q2 is None:
        q2 = math.atan2(a2 + a3 * math.cos(q3), a3 * math.sin(q3))
        return np.array([0.4, q2, q3, -q2 - q3, q5, -0.7])
    s234 = -(a2 * math.cos(q2) + a3 * math.cos(q2 + q3)) / d5
    return np.array([0.4, q2, q3, math.asin(s234) - q2 - q3, q5, -0.7])


def _coinciding_cases() -> list[tuple[np.ndarray, set[str]]]:
    """Configurations and the steps whose two solutions coincide there (the conditions hold
    to rounding or are missed by 2e-3 in a sine or more)."""
    rng = np.random.default_rng(77)
    generic: list[tuple[np.ndarray, set[str]]] = [(q, set()) for q in rng.uniform(-math.pi, math.pi, (4, 6))
               if min(abs(math.sin(q[2])), abs(math.sin(q[4]))) > 0.05]
    base = np.array([-0.6, -1.3, 0.8, 0.5, 1.1, 0.3])

    def with_angles(**angles: float) -> np.ndarray:
        q = base.copy()
        for index, value in angles.items():
            q[int(index[1:]) - 1] = value
        return q

    return [
        *generic,
        (with_angles(q5=0.0), {"wrist"}),
        (with_angles(q5=math.pi), {"wrist"}),
        (with_angles(q3=0.0), {"elbow"}),
        (with_angles(q3=math.pi), {"elbow"}),
        (_shoulder_case(None, 1.1, 0.9), {"shoulder"}),
        (with_angles(q3=math.pi, q5=0.0), {"elbow", "wrist"}),
        (_shoulder_case(1.5, 0.0, math.pi), {"shoulder", "wrist", "elbow"}),
        (with_angles(q5=2e-3), set()),
        (with_angles(q3=math.pi - 2e-3), set()),
    ]


_WHERE = {
    "shoulder": "the two shoulder angles q1 of Task 1",
    "wrist": "the two wrist rows (q5, q6) of Task 2",
    "elbow": "the two elbow rows (q2, q3, q4) of Task 3",
}


class _CoincidingCheck(_ShortRepr, FunctionCheck):
    """``coinciding_branches(q) -> list of "shoulder", "wrist", "elbow"``; called with robokin's
    wrist centre for a keyword parameter ``wrist_centre``."""

    def evaluate(self, answer: Any) -> CheckResult:
        """:meth:`FunctionCheck.evaluate` of ``answer`` given robokin's wrist centre."""
        if callable(answer):
            answer = with_reference_steps(answer, {"wrist_centre": reference_wrist_centre})
        return super().evaluate(answer)

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        cases = _coinciding_cases()
        n = len(cases)
        got = []
        for k, (q, _) in enumerate(cases):
            out = self.call(answer, (q.copy(),), f"at configuration {k + 1}", n)
            if isinstance(out, str) or not isinstance(out, (list, tuple, set, np.ndarray)):
                return self.failure("type", f"{name} should return a list of step names (\"shoulder\", "
                                    f"\"wrist\", \"elbow\"); got {type(out).__name__}.", n)
            names = {str(item) for item in out}
            unknown = names - set(_STEPS)
            if unknown:
                return self.failure("unknown_name", f"{name} returns {sorted(unknown)}: the steps are "
                                    "named \"shoulder\", \"wrist\" and \"elbow\".", n)
            got.append(names)
        if all(names == expected for names, (_, expected) in zip(got, cases)):
            return self.success(f"{name} is correct (checked at {n} configurations: none, one, two and "
                                "all three steps with coinciding solutions).", n)
        for step in _STEPS:
            missed = [k for k, (names, (_, expected)) in enumerate(zip(got, cases))
                      if step in expected and step not in names]
            extra = [k for k, (names, (_, expected)) in enumerate(zip(got, cases))
                     if step in names and step not in expected]
            held = sum(step in expected for _, expected in cases)
            if missed and len(missed) < held:
                return self.failure(f"{step}_partly", (
                    f"{name} finds some configurations where {_WHERE[step]} coincide, but not all "
                    f"(configuration {missed[0] + 1}): the condition holds at more than one value; "
                    "derive it from the ± of that step."), n)
            if missed:
                return self.failure(f"{step}_missed", (
                    f"{name} never names \"{step}\", not even where {_WHERE[step]} coincide "
                    f"(configuration {missed[0] + 1}): derive when the ± of that step has one value."), n)
            if extra:
                return self.failure(f"{step}_extra", (
                    f"{name} names \"{step}\" at configuration {extra[0] + 1}, where {_WHERE[step]} "
                    "differ (by 2e-3 in a sine, or more): the condition or its tolerance is wrong."), n)
        return self.failure("mismatch", f"{name} names other steps than those whose solutions coincide.", n)


coinciding_branches = exercise(_CHAPTER, "coinciding_branches", _CoincidingCheck(
    name="coinciding_branches",
    signature="coinciding_branches(q) -> list of step names",
    noun="configurations",
    doc=("Check coinciding_branches(q): the steps (\"shoulder\", \"wrist\", \"elbow\") whose two "
         "solutions coincide at the pose fk(q), at configurations of the check's own (robokin's "
         "wrist centre passed for its keyword parameter wrist_centre)."),
))
