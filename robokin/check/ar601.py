r"""Exercise checks of chapter 6: closed-form inverse kinematics of the AR-601 leg.

Every reference comes from :func:`robokin.models.ar601_leg` (lengths
``L1 = L2 = 0.3 m``, ``L3 = 0.1 m``) and
:func:`robokin.models.ar601_ik.ar601_leg_ik`.

=======================  ==========================================================  ======================
check                    the student's answer                                        inputs
=======================  ==========================================================  ======================
``foot_transform``       B T_F(q): sympy Matrix in q1..q6 (L1, L2, L3 allowed) or    q = (q1, ..., q6)
                         a function f(q) -> 4×4
``knee_angle``           function f(d, l1, l2) -> q4 ≥ 0 (rad) from the hip–ankle    d, l1, l2
                         distance d
``ankle_point``          function ankle_point(T) -> (3,): where the ankle axes meet   20 random foot poses
``ankle_angles``         function ankle_angles(u, q4) -> every (q5, q6) pair with     20 random foot poses
                         R_y(q5) R_x(q6) u = v(q4), each once
``ik_solution``          q (6,) or several solutions (k, 6) for :data:`T_GOAL`        --
``ik_solver``            function f(T) -> q (6,) or (k, 6): every returned row must   20 random foot poses
                         reproduce T (any solution is accepted)
``k_regular``            the number of solutions of a regular reachable pose (int)    20 random foot poses
``leg_ik``               function my_leg_ik(T) -> (k, 6): every solution, each once   20 random foot poses
``unreachable_reason``   function f(T) -> None, or why T is out of reach:             targets near the
                         ``"too_far"``, ``"ankle_range"`` or ``"joint_limits"``       boundaries
``sole_sweep``           function f(heights, leg_ik) -> (counts, sigma_min): the      6 heights, with an
                         rows leg_ik returns for the sole level at each height and    inverse kinematics
                         sigma_min of J at the first (NaN where there is none)        of the check's own
``hip_angles``           function f(R_H) -> both triples (q1, q2, q3) of R_H,        20 random hip
                         R_z(q1) R_y(q2) R_x(q3) = R_H, cos q2 > 0 first             rotations
``different_solutions``  function f(Q) -> int: how many rows of Q (k, 6) are         5 sets of rows of
                         different solutions (equal modulo 2π to 1e-9 rad: one)       the check's own
=======================  ==========================================================  ======================

A solution that puts the foot at the right *place* but with the wrong
*orientation* is recognised and explained (a 6-DOF leg has to match all six
numbers of the pose). One with the right orientation but the wrong place is
explained by the step the numbers single out: a typical wrong ankle point
(``ankle_point_base_z``, ``ankle_point_sign``, ``ankle_point_missing``), a knee
angle that does not fit the hip–ankle distance (``hip_ankle_distance``: the ankle
point or the knee is wrong), or ankle angles that put the ankle elsewhere at the
right distance (``ankle_angles``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    FAIL,
    PASS,
    Check,
    CheckResult,
    FunctionCheck,
    Variable,
    alternatives,
    report,
    fmt,
    with_reference_steps,
)
from robokin.check._registry import exercise
from robokin.errors import DomainError
from robokin.validation import (
    as_float_array, as_scalar, as_vector, check_int, check_length, check_rotation_matrix, check_transform,
)

__all__ = [
    "LENGTHS",
    "P_GOAL",
    "RPY_GOAL",
    "T_GOAL",
    "ankle_angles",
    "ankle_point",
    "different_solutions",
    "foot_transform",
    "hip_angles",
    "ik_solution",
    "ik_solver",
    "k_regular",
    "knee_angle",
    "leg_ik",
    "reference_ankle_angles",
    "reference_ankle_point",
    "reference_hip_angles",
    "reference_knee_angle",
    "sole_sweep",
    "unreachable_reason",
]

_CHAPTER = "ar601"
#: Link lengths L1, L2, L3 (m) used by the checks (the model's defaults).
LENGTHS = (0.3, 0.3, 0.1)
#: Foot position (m) of the chapter's IK target, in the hip frame B.
P_GOAL = np.array([0.05, 0.10, -0.58])
#: Foot orientation of the target as roll–pitch–yaw (rad): R = Rz(yaw) Ry(pitch) Rx(roll).
RPY_GOAL = np.array([0.1, 0.0, 0.2])


def _goal() -> np.ndarray:
    from robokin.transforms import rotation_from_rpy, transform

    return transform(rotation_from_rpy(RPY_GOAL), P_GOAL)


#: The chapter's target foot pose B T_F (4×4).
T_GOAL = _goal()

_LENGTH_NAMES = {
    0: ("L1", "l1", "L_1", "l_1"),
    1: ("L2", "l2", "L_2", "l_2"),
    2: ("L3", "l3", "L_3", "l_3"),
}


@lru_cache(maxsize=1)
def _leg():
    from robokin.models.ar601 import ar601_leg

    return ar601_leg(*LENGTHS)


def _fk(q) -> np.ndarray:
    return _leg().fk(np.asarray(q, dtype=float), check=False)


# ------------------------------------------------------------------ foot transform
def _element(kind: str, v: float) -> np.ndarray:
    """The 4×4 elementary transform ``Tz(v)`` (kind "z") or ``Rx/Ry/Rz(v)``."""
    from robokin.transforms import rotx, roty, rotz, transform, translation

    if kind == "z":
        return translation((0.0, 0.0, v))
    return transform({"Rx": rotx, "Ry": roty, "Rz": rotz}[kind](float(v)), (0.0, 0.0, 0.0), check=False)


def _product(seq: list[tuple[str, Any]], q: np.ndarray, sign: float = -1.0) -> np.ndarray:
    """Product of elementary transforms; ("Rz", i) uses q[i], ("z", k) is Tz(sign·L_k)."""
    out = np.eye(4)
    for kind, arg in seq:
        out = out @ (_element("z", sign * LENGTHS[arg]) if kind == "z" else _element(kind, q[arg]))
    return out


_SEQ = [("Rz", 0), ("Ry", 1), ("Rx", 2), ("z", 0), ("Rx", 3), ("z", 1), ("Ry", 4), ("Rx", 5), ("z", 2)]


def _forward_kinematics_mistakes():
    def seq_fn(seq, sign=-1.0):
        return lambda x: _product(seq, np.asarray(x, dtype=float), sign)

    hip_xyz = [("Rx", 2), ("Ry", 1), ("Rz", 0)] + _SEQ[3:]
    ankle_swapped = _SEQ[:6] + [("Rx", 5), ("Ry", 4), ("z", 2)]
    knee_late = [_SEQ[0], _SEQ[1], _SEQ[2], ("z", 0), ("z", 1), ("Rx", 3)] + _SEQ[6:]
    return [
        alternatives("positive_lengths", [(seq_fn(_SEQ, +1.0), (
            "{name} translates by +L_i: the leg then points up (at q = 0 the foot is at "
            "z = +(L1 + L2 + L3)). With z up, each link is T_z(−L_i).")),
        ]),
        alternatives("missing_sole", [(seq_fn(_SEQ[:-1]), (
            "{name} stops at the ankle: the factor T_z(−L3) from the ankle axes to the sole is "
            "missing.")),
        ]),
        alternatives("hip_order", [(seq_fn(hip_xyz), (
            "{name} composes the hip as R_x(q3) R_y(q2) R_z(q1); the joints follow each other "
            "from the body outwards: R_z(q1) R_y(q2) R_x(q3).")),
        ]),
        alternatives("ankle_order", [(seq_fn(ankle_swapped), (
            "{name} composes the ankle as R_x(q6) R_y(q5); q5 comes first (nearer the body): "
            "R_y(q5) R_x(q6).")),
        ]),
        alternatives("knee_position", [(seq_fn(knee_late), (
            "{name} puts the knee rotation R_x(q4) after T_z(−L2), i.e. at the ankle. The knee "
            "sits L1 below the hip: ... T_z(−L1) R_x(q4) T_z(−L2) ...")),
        ]),
        *dg.standard("transform"),
    ]


@dataclass(repr=False)
class _FixedLengthsCheck(Check):
    """A check whose sympy answers may keep the symbols L1, L2, L3 (set to :data:`LENGTHS`)."""

    def evaluate(self, answer: Any) -> CheckResult:
        import sys

        sp = sys.modules.get("sympy")
        if sp is not None and isinstance(answer, (sp.Basic, sp.MatrixBase)):
            values = {}
            for s in answer.free_symbols:
                for k, names in _LENGTH_NAMES.items():
                    if s.name in names:
                        values[s] = LENGTHS[k]
            answer = answer.subs(values)
        return super().evaluate(answer)


_Q = [Variable(f"q{i}", "angle", -math.pi / 2, math.pi / 2, aliases=(f"q_{i}", f"theta{i}"))
      for i in range(1, 7)]

foot_transform = exercise(_CHAPTER, "foot_transform", _FixedLengthsCheck(
    name="T_BF",
    reference=_fk,
    variables=_Q,
    groups=[("q", list(range(6)))],
    diagnoses=_forward_kinematics_mistakes(),
    noun="configurations",
    hint="Build it as R_z(q1) R_y(q2) R_x(q3) T_z(−L1) R_x(q4) T_z(−L2) R_y(q5) R_x(q6) T_z(−L3).",
    doc=(
        "Check the foot pose B T_F(q1..q6) (4×4) of the AR-601 leg with L1 = L2 = 0.3 m, "
        "L3 = 0.1 m (a sympy Matrix may keep the symbols L1, L2, L3)."
    ),
))


# ------------------------------------------------------------------ knee angle
def _knee(x) -> np.ndarray:
    d, l1, l2 = x
    return np.array(math.acos((d * d - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)))


def _knee_mistakes():
    def interior(x):
        d, l1, l2 = x
        return np.array(math.acos((l1 * l1 + l2 * l2 - d * d) / (2.0 * l1 * l2)))

    def no_two(x):
        d, l1, l2 = x
        c = (d * d - l1 * l1 - l2 * l2) / (l1 * l2)
        return np.array(math.acos(c)) if abs(c) <= 1 else np.array(np.nan)

    def sole_included(x):
        d, l1, l2 = x
        c = (d * d - l1 * l1 - (l2 + LENGTHS[2]) ** 2) / (2.0 * l1 * (l2 + LENGTHS[2]))
        return np.array(math.acos(c)) if abs(c) <= 1 else np.array(np.nan)

    return [
        alternatives("interior_angle", [(interior, (
            "{name} is the interior angle between thigh and shank, π − q4 (the law of cosines "
            "with −2 L1 L2 cos). q4 is measured from the STRETCHED leg (q4 = 0 when d = L1 + L2), "
            "so the angle of the triangle at the knee is π − q4.")),
        ]),
        alternatives("negative_branch", [(lambda x: -_knee(x), (
            "{name} returns −q4: that is the other knee solution (both are valid); this check "
            "asks for the non-negative one, arccos(...) ≥ 0.")),
        ]),
        alternatives("missing_factor_two", [(no_two, (
            "{name} forgets the factor 2 in front of L1 L2 in the law of cosines.")),
        ]),
        alternatives("sole_in_shank", [(sole_included, (
            "{name} uses the distance to the sole with L2 + L3 as the shank. The knee "
            "triangle is hip–knee–ankle: take d to the ANKLE point (p + L3 z_F) and the sides L1, L2.")),
        ]),
        dg.degrees_output(),
    ]


knee_angle = exercise(_CHAPTER, "knee_angle", Check(
    name="knee_angle(d, l1, l2)",
    reference=_knee,
    variables=[Variable("d", "length", 0.12, 0.48), Variable("l1", "length", 0.25, 0.35),
               Variable("l2", "length", 0.25, 0.35)],
    diagnoses=_knee_mistakes(),
    noun="distances and lengths",
    hint="At d = L1 + L2 (stretched) the answer must be 0, at d = √(L1² + L2²) it is π/2.",
    doc="Check a function knee_angle(d, l1, l2) -> q4 ≥ 0 (rad) from the hip–ankle distance d.",
))


# ------------------------------------------------------------------ inverse kinematics
_TOL_P = 1e-6   # m
_TOL_R = 1e-6   # rad
_TOL_ANKLE = 1e-5  # m: ankle points closer than this are the same (the orientation is right to 1e-4 rad)


def _pose_errors(q: np.ndarray, T: np.ndarray) -> tuple[float, float]:
    F = _fk(q)
    dp = float(np.linalg.norm(F[:3, 3] - T[:3, 3]))
    Rrel = F[:3, :3].T @ T[:3, :3]
    c = float(np.clip((np.trace(Rrel) - 1.0) / 2.0, -1.0, 1.0))
    s = float(np.linalg.norm([Rrel[2, 1] - Rrel[1, 2], Rrel[0, 2] - Rrel[2, 0], Rrel[1, 0] - Rrel[0, 1]])) / 2
    return dp, math.atan2(s, c)


def _as_rows(answer: Any, name: str) -> tuple[np.ndarray | None, str, str]:
    """(rows (k, 6), code, message); rows None on failure."""
    try:
        a = np.asarray(answer)
        if a.dtype.kind == "c":
            return None, "error", f"{name} has complex entries; expected 6 real joint angles in radians."
        a = np.array(a, dtype=float)
    except (TypeError, ValueError):
        return None, "error", f"{name} must be 6 joint angles in radians (or k×6); got {type(answer).__name__}."
    if a.ndim == 1 and a.size == 6:
        a = a[None, :]
    if a.ndim == 2 and a.shape == (0, 6):
        return None, "no_solution", (
            f"{name} holds no solution, but the pose is reachable (it is the forward kinematics of "
            "a configuration within the joint limits)."
        )
    if a.ndim != 2 or a.shape[1] != 6 or a.shape[0] == 0:
        return None, "shape", f"{name} must have shape (6,) or (k, 6); got shape {a.shape}."
    if not np.all(np.isfinite(a)):
        return None, "error", f"{name} contains NaN or infinite values."
    return a, "", ""


def _ankle_point(T: np.ndarray) -> np.ndarray:
    """The ankle point a = p + L3 R e_z (3,) of a foot pose T (4×4), in m."""
    return T[:3, 3] + LENGTHS[2] * T[:3, 2]


def _position_diagnosis(q: np.ndarray, T: np.ndarray, dp: float, name: str) -> tuple[str, str]:
    """(code, message) for a solution ``q`` whose orientation is right but whose position is not.

    Only the hip–ankle distance depends on the knee alone (|a|² = L1² + L2² + 2 L1 L2 cos q4),
    so a diagnosis names a step only when the numbers single it out: the ankle point of the
    solution is one of the typical wrong ankle points; or q4 does not fit the target's
    hip–ankle distance (then the ankle point or the knee is wrong, and the message says
    both); or q4 fits it and the ankle angles put the ankle elsewhere on that sphere.
    """
    ankle_reached = _ankle_point(_fk(q))
    p, R = T[:3, 3], T[:3, :3]
    ankle_target = _ankle_point(T)
    lead = f"{name} turns the foot correctly but puts it {fmt(dp, 4)} m away from the target. "
    wrong_ankles = [
        ("ankle_point_base_z", p + LENGTHS[2] * np.array([0.0, 0.0, 1.0]),
         "Its ankle point is p + L3 e_z, backed off from the sole along the BASE z axis; that is "
         "right only while the sole is level. The ankle point is a = p + L3 R e_z, along the "
         "FOOT's z axis (the third column of R)."),
        ("ankle_point_sign", p - LENGTHS[2] * R[:, 2],
         "Its ankle point is p − L3 R e_z, L3 BELOW the sole. The sole is L3 below the ankle, so "
         "the ankle point is a = p + L3 R e_z."),
        ("ankle_point_missing", p,
         "It treats the sole point p as the ankle point: the ankle is L3 above the sole, "
         "a = p + L3 R e_z, and the knee comes from |a|."),
    ]
    for code, ankle, text in wrong_ankles:
        if np.linalg.norm(ankle_reached - ankle) <= _TOL_ANKLE:
            return code, lead + text
    d_target, d_reached = float(np.linalg.norm(ankle_target)), float(np.linalg.norm(ankle_reached))
    if abs(d_reached - d_target) > _TOL_ANKLE:
        return "hip_ankle_distance", lead + (
            "Its knee angle q4 does not give the target's hip–ankle distance d = |p + L3 R e_z|: "
            "the ankle point or the knee angle is wrong (check q4 at the stretched leg, d = L1 + L2).")
    return "ankle_angles", lead + (
        "Its knee angle fits the target's hip–ankle distance, but the ankle lands "
        f"{fmt(float(np.linalg.norm(ankle_reached - ankle_target)), 4)} m from the target's ankle "
        "point: look at the ankle angles (q5, q6 from u = Rᵀ a) and the hip angles.")


def _verdict(rows: np.ndarray, T: np.ndarray, name: str) -> tuple[bool, str, str]:
    """(passed, code, message) for solutions ``rows`` of target ``T``."""
    errs = np.array([_pose_errors(q, T) for q in rows])
    ok = (errs[:, 0] <= _TOL_P) & (errs[:, 1] <= _TOL_R)
    if ok.all():
        return True, "", ""
    bad = int(np.argmin(ok))
    which = f" (row {bad + 1} of {len(rows)})" if len(rows) > 1 else ""
    if all(max(_pose_errors(np.deg2rad(q), T)) <= 1e-4 for q in rows):
        return False, "degrees_output", (
            f"{name} is in degrees: np.deg2rad({name}) reproduces the target. robokin works in radians."
        )
    dp, dr = errs[bad]
    if dp <= 1e-4 and dr > 1e-4:
        return False, "position_only", (
            f"{name}{which} puts the foot at the right place but turned by {fmt(math.degrees(dr), 1)}° "
            "from the target orientation. A 6-joint leg has to match the whole pose, position "
            "and orientation: solve with the target's rotation too."
        )
    if dr <= 1e-4 < dp:
        return (False, *_position_diagnosis(rows[bad], T, dp, f"{name}{which}"))
    return False, "mismatch", (
        f"{name}{which} does not reach the target: the foot is {fmt(dp, 4)} m away and turned by "
        f"{fmt(math.degrees(dr), 1)}°. Check it with forward kinematics."
    )


def ik_solution(
    q: Any, T_target: Any = None, *, name: str = "Q_mine", raise_on_fail: bool = False,
    quiet: bool = False,
) -> CheckResult:
    """Check joint angles that should put the foot at ``T_target`` (default :data:`T_GOAL`).

    Any solution is accepted, one row or several: each row is compared with
    the pose by the model's forward kinematics.

    Parameters
    ----------
    q : array_like, shape (6,) or (k, 6)
        One solution or several (rad); every row must reproduce the pose within
        1e-6 m and 1e-6 rad.
    T_target : array_like, shape (4, 4), optional
        Foot pose in the hip frame B (default :data:`T_GOAL`).
    name : str, optional
        The answer's name in the messages (default ``"Q_mine"``, the notebook's).
    raise_on_fail, quiet : bool, optional
        Raise ``AssertionError`` on failure; print nothing.

    Returns
    -------
    CheckResult
    """
    T = T_GOAL if T_target is None else check_transform(T_target, name="T_target")
    if T.shape != (4, 4):
        from robokin.errors import ShapeError

        raise ShapeError(f"T_target must have shape (4, 4); got shape {T.shape}")
    rows, code, msg = _as_rows(q, name)
    if rows is not None:
        passed, code, msg = _verdict(rows, T, name)
        if passed:
            what = "reproduces" if len(rows) == 1 else f"({len(rows)} solutions) all reproduce"
            distinct = len({tuple(np.round(np.mod(r + np.pi, 2 * np.pi), 6)) for r in rows})
            text = f"{PASS} {name} is correct: {what} the target foot pose"
            text += "." if distinct == len(rows) else f" ({distinct} of them distinct)."
            return report(CheckResult(name, True, text, None, 1), raise_on_fail=raise_on_fail, quiet=quiet)
    return report(CheckResult(name, False, f"{FAIL} {msg}", code, 1), raise_on_fail=raise_on_fail, quiet=quiet)


def _random_targets(n: int, seed: int) -> np.ndarray:
    Q = _leg().random_configurations(n, seed=seed)
    return _leg().fk(Q)


def ik_solver(
    f: Any, *, samples: int = 20, seed: int = 0, raise_on_fail: bool = False, quiet: bool = False
) -> CheckResult:
    """Check an IK function ``f(T) -> q (6,) or (k, 6)`` on random reachable foot poses.

    The poses are the forward kinematics of seeded random configurations within
    the joint limits; every row returned must reproduce its pose by the model's
    forward kinematics (within 1e-6 m and 1e-6 rad). The message says how many
    solutions per pose the function returns.

    Parameters
    ----------
    f : callable
        ``f(T)`` with ``T`` (4, 4) returning joint angles (6,) or (k, 6), rad.
    samples : int, optional
        Number of random poses.
    seed : int, optional
        Seed of the poses.
    raise_on_fail, quiet : bool, optional
        Raise ``AssertionError`` on failure; print nothing.

    Returns
    -------
    CheckResult
    """
    samples = check_int(samples, "samples", 1, 10_000)
    seed = seed if seed is None else check_int(seed, "seed", 0)
    checker = _IKSolverCheck(name="ik(T)", signature="f(T) -> q", samples=samples, seed=seed)
    return report(checker.evaluate(f), raise_on_fail=raise_on_fail, quiet=quiet)


class _IKSolverCheck(FunctionCheck):
    """The verdict on an IK function at ``samples`` random reachable poses (see :func:`ik_solver`)."""

    def judge(self, answer: Any) -> CheckResult:
        name, samples = self.name, self.samples
        counts = []
        for k, T in enumerate(_random_targets(samples, self.seed)):
            out = self.call(answer, (T.copy(),), samples=k + 1)
            rows, code, msg = _as_rows(out, "the value returned by ik(T)")
            if rows is None:
                return self.failure(code, msg, k + 1)
            passed, code, msg = _verdict(rows, T, f"{name} at pose {k + 1}")
            if not passed:
                return self.failure(code, msg, k + 1)
            counts.append(len(rows))
        lo, hi = min(counts), max(counts)
        per = f"{lo}" if lo == hi else f"{lo} to {hi}"
        more = "" if lo >= 8 else "; a pose may have more"
        return self.success(f"{name} is correct: every returned solution reproduces its pose (checked at "
                            f"{samples} random poses; {per} solution{'s' if hi > 1 else ''} per pose{more}).",
                            samples)


# ------------------------------------------------------------------ every solution
#: check -> {robokin function that solves its task: how the review report names it}
#: (an answer that hands one back is flagged for review by hand).
DELEGATION = {
    # the product written out, not the model evaluated (T_sym = leg.fk(list(q_sym)))
    "foot_transform": {"ar601_leg": "robokin.models.ar601_leg (its fk)", "leg.fk": "leg.fk (SerialChain.fk)"},
    "ankle_point": {"reference_ankle_point": "robokin.check.ar601.reference_ankle_point"},
    "ankle_angles": {"reference_ankle_angles": "robokin.check.ar601.reference_ankle_angles"},
    "leg_ik": {"ar601_leg_ik": "robokin.models.ar601_leg_ik",
               "reference_ankle_point": "robokin.check.ar601.reference_ankle_point",
               "reference_knee_angle": "robokin.check.ar601.reference_knee_angle",
               "reference_ankle_angles": "robokin.check.ar601.reference_ankle_angles",
               "reference_hip_angles": "robokin.check.ar601.reference_hip_angles",
               "ar601_leg_ik_batch": "robokin.models.ar601_leg_ik_batch",
               "solve_ik": "robokin.motion.solve_ik"},
    "unreachable_reason": {"ar601_leg_ik": "robokin.models.ar601_leg_ik",
                           "ar601_leg_ik_batch": "robokin.models.ar601_leg_ik_batch"},
    # the ZYX angles read off by hand, both branches (rpy_from_rotation gives one)
    "hip_angles": {"rpy_from_rotation": "robokin.transforms.rpy_from_rotation",
                   "reference_hip_angles": "robokin.check.ar601.reference_hip_angles",
                   "ar601_leg_ik": "robokin.models.ar601_leg_ik"},
    # the sweep counts the rows of the inverse kinematics it is given (leg_ik), not robokin's
    "sole_sweep": {"ar601_leg_ik": "robokin.models.ar601_leg_ik",
                   "ar601_leg_ik_batch": "robokin.models.ar601_leg_ik_batch"},
}


def _wrap(a: np.ndarray) -> np.ndarray:
    return (np.asarray(a, dtype=float) + np.pi) % (2.0 * np.pi) - np.pi


def _closed_form(T: np.ndarray, mistake: str = "") -> np.ndarray:
    """Every solution (k, 6) of the foot pose ``T`` by the construction of Task 3, or the
    rows a typical ``mistake`` leaves (the codes of :data:`leg_ik`'s diagnoses)."""
    from robokin.transforms import rotx, roty

    l1, l2, l3 = LENGTHS
    R = T[:3, :3]
    a = T[:3, 3] + l3 * R[:, 2]
    c4 = (float(a @ a) - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
    if abs(c4) > 1.0 + 1e-9:
        return np.zeros((0, 6))
    q4_abs = math.acos(min(1.0, max(-1.0, c4)))
    rows = []
    for q4 in ((q4_abs,) if mistake == "knee_branch_missing" else (q4_abs, -q4_abs)):
        u = R.T @ a
        rho, phi = math.hypot(u[1], u[2]), math.atan2(u[2], u[1])
        c6 = -l1 * math.sin(q4) / rho
        if abs(c6) > 1.0:
            continue
        k = l1 * math.cos(q4) + l2
        q6s = (math.acos(c6) - phi, -math.acos(c6) - phi)
        for q6 in (q6s[:1] if mistake == "ankle_branch_missing" else q6s):
            w = rotx(q6) @ u
            q5 = (math.atan2(-w[2] / k, w[0] / k) if mistake == "ankle_atan2_swapped"
                  else math.atan2(w[0] / k, -w[2] / k))
            M = rotx(q4) @ roty(q5) @ rotx(q6)
            R_H = M.T @ R if mistake == "hip_product_side" else R @ M.T
            if mistake == "hip_order":  # R_H read as Rx(q3) Ry(q2) Rz(q1)
                R_H = R_H.T
            for sign in ((1.0,) if mistake == "hip_branch_missing" else (1.0, -1.0)):
                c2 = sign * math.hypot(R_H[0, 0], R_H[1, 0])
                q2 = math.atan2(-R_H[2, 0], c2)
                if mistake == "hip_atan2_swapped":
                    q1 = math.atan2(R_H[0, 0] / c2, R_H[1, 0] / c2)
                    q3 = math.atan2(R_H[2, 2] / c2, R_H[2, 1] / c2)
                else:
                    q1 = math.atan2(R_H[1, 0] / c2, R_H[0, 0] / c2)
                    q3 = math.atan2(R_H[2, 1] / c2, R_H[2, 2] / c2)
                # hip_order: Rx(a) Ry(b) Rz(c) = R_H read off R_Hᵀ = Rz(−c) Ry(−b) Rx(−a),
                # and c (about z) taken as q1, a (about x) as q3
                hip = (-q1, -q2, -q3) if mistake == "hip_order" else (q1, q2, q3)
                rows.append([*hip, q4, q5, q6])
    return np.array(rows, dtype=float).reshape(-1, 6)


def _same_rows(A: np.ndarray, B: np.ndarray, atol: float = 1e-6) -> bool:
    """Equal as sets of configurations (angles modulo 2π), each row once."""
    if A.shape != B.shape:
        return False
    unused = list(range(len(B)))
    for row in A:
        hit = [j for j in unused if np.abs(_wrap(row - B[j])).max() <= atol]
        if not hit:
            return False
        unused.remove(hit[0])
    return True


def _distinct(A: np.ndarray, atol: float = 1e-6) -> int:
    kept: list[np.ndarray] = []
    for row in A:
        if not any(np.abs(_wrap(row - k)).max() <= atol for k in kept):
            kept.append(row)
    return len(kept)


_LEG_IK_MISTAKES = [
    ("knee_branch_missing",
     "{name} returns only the knee solutions with q4 ≥ 0. The law of cosines fixes cos q4 only: "
     "q4 and −q4 both put the ankle at the hip–ankle distance d; keep the solutions with the "
     "knee bent either way."),
    ("ankle_branch_missing",
     "{name} takes one of the two arccos branches of q6 only: an arccos gives an angle and its "
     "negative, and both solve the equation for q6; keep both."),
    ("hip_branch_missing",
     "{name} keeps only the hip triple with cos q2 > 0. The same hip rotation R_H has a second "
     "triple, with cos q2 < 0: take both signs of cos q2."),
    ("hip_atan2_swapped",
     "{name} swaps the arguments of atan2 in the hip angles q1 and q3: atan2(y, x) takes first "
     "the entry proportional to the angle's sine, then the one proportional to its cosine."),
    ("ankle_atan2_swapped",
     "{name} swaps the arguments of atan2 for q5: atan2(y, x) takes first the entry of "
     "w = R_x(q6) u proportional to sin q5, then the one proportional to cos q5."),
    ("hip_order",
     "{name} reads the hip angles of R_H as if R_H = R_x(q3) R_y(q2) R_z(q1). The hip yaw q1 "
     "comes first from the body: R_H = R_z(q1) R_y(q2) R_x(q3) (ZYX); read the angles off that "
     "product's entries."),
    ("hip_product_side",
     "{name} computes R_H = (R_x(q4) R_y(q5) R_x(q6))ᵀ R. The hip comes first in the product, "
     "R = R_H R_x(q4) R_y(q5) R_x(q6): solve that for R_H."),
]


# ------------------------------------------------------------------ the steps of Task 3
def _ankle_point_of(T: np.ndarray, mistake: str = "") -> np.ndarray:
    """The ankle point of the foot pose ``T``, or what a typical ``mistake`` makes of it."""
    l3, p, R = LENGTHS[2], T[:3, 3], T[:3, :3]
    return {
        "": p + l3 * R[:, 2],
        "ankle_point_base_z": p + np.array([0.0, 0.0, l3]),
        "ankle_point_sign": p - l3 * R[:, 2],
        "ankle_point_missing": p.copy(),
        "ankle_point_row": p + l3 * R[2, :],
    }[mistake]


_ANKLE_POINT_MISTAKES = [
    ("ankle_point_base_z",
     "{name} backs off from the sole along the BASE z axis, p + L3 e_z: right only while the "
     "sole is level. The last factor T_z(−L3) is along the FOOT's z axis: a = p + L3 R e_z (the "
     "third column of R)."),
    ("ankle_point_sign",
     "{name} goes down from the sole, p − L3 R e_z: the sole is L3 BELOW the ankle along the "
     "foot's z axis, so the ankle is a = p + L3 R e_z."),
    ("ankle_point_missing",
     "{name} returns the sole's position p: the ankle axes meet L3 above it, a = p + L3 R e_z."),
    ("ankle_point_row",
     "{name} uses the third ROW of R: the foot's z axis in B is the third COLUMN, R e_z."),
]


class _AnklePointCheck(FunctionCheck):
    """``ankle_point(T) -> (3,)``: where the ankle axes meet, in B."""

    def judge(self, answer: Any) -> CheckResult:
        X = self.sample_points()
        name, n = self.name, len(X)
        poses = [_fk(x) for x in X]
        got = []
        for k, T in enumerate(poses):
            a = np.asarray(self.call(answer, (T.copy(),), f"at pose {k + 1}", n), dtype=float)
            if a.size != 3:
                return self.failure("shape", f"{name} should return the point (3,); got shape "
                                    f"{a.shape} at pose {k + 1}.", n)
            got.append(a.reshape(3))
        if all(np.allclose(a, _ankle_point_of(T), atol=1e-9) for a, T in zip(got, poses)):
            return self.success(f"{name} is correct (checked at {n} random foot poses).", n)
        named = self.diagnose(_ANKLE_POINT_MISTAKES, lambda code: all(
            np.allclose(a, _ankle_point_of(T, code), atol=1e-9) for a, T in zip(got, poses)), n)
        if named is not None:
            return named
        k = next(i for i, (a, T) in enumerate(zip(got, poses))
                 if not np.allclose(a, _ankle_point_of(T), atol=1e-9))
        off = float(np.linalg.norm(got[k] - _ankle_point_of(poses[k])))
        return self.failure("mismatch", (
            f"{name} at pose {k + 1} (the foot pose of q = {fmt(X[k])}) returns a point {fmt(off, 4)} m "
            "from where the ankle axes meet (the origin of the model's ankle frames, "
            "leg.frames(q)[5])."), n)


ankle_point = exercise(_CHAPTER, "ankle_point", _AnklePointCheck(
    name="ankle_point",
    signature="ankle_point(T) -> (3,) array",
    variables=_Q,
    noun="foot poses",
    doc=("Check a function ankle_point(T) -> (3,) that returns the point where the two ankle "
         "axes meet, in B, for a foot pose T (4×4), at 20 random poses."),
))


def _ankle_pairs(u: np.ndarray, q4: float, mistake: str = "", l1: float = LENGTHS[0],
                 l2: float = LENGTHS[1]) -> np.ndarray:
    """Every ``(q5, q6)`` with R_y(q5) R_x(q6) u = v(q4), shape (k, 2), or what a typical
    ``mistake`` makes of them."""
    from robokin.transforms import rotx

    rho, phi = math.hypot(u[1], u[2]), math.atan2(u[2], u[1])
    c6 = -l1 * math.sin(q4) / rho
    if abs(c6) > 1.0:
        return np.zeros((0, 2))
    k = l1 * math.cos(q4) + l2
    q6s = (math.acos(c6) - phi, -math.acos(c6) - phi)
    rows = []
    for q6 in (q6s[:1] if mistake == "ankle_branch_missing" else q6s):
        w = rotx(q6) @ u
        q5 = (math.atan2(-w[2] / k, w[0] / k) if mistake == "ankle_atan2_swapped"
              else math.atan2(w[0] / k, -w[2] / k))
        rows.append([-q5 if mistake == "ankle_q5_sign" else q5, q6])
    return np.array(rows)


def reference_ankle_point(T: Any, L3_: float = LENGTHS[2]) -> np.ndarray:
    """robokin's answer to the step ``ankle_point`` of Task 3 (the tests' stand-in).

    As :func:`reference_ankle_angles`, for the ankle point: the tests of the later steps pass
    it to the student's ``my_leg_ik`` as its argument ``ankle``.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        A foot pose in B.
    L3_ : float
        The length from the ankle to the sole (m), the model's by default.

    Returns
    -------
    numpy.ndarray, shape (3,)
        The point where the two ankle axes meet, in B (m).
    """
    T = as_float_array(T, "T", (4, 4))
    return T[:3, 3] + float(check_length(L3_, "L3_")) * T[:3, 2]


def reference_knee_angle(d: float, l1_: float = LENGTHS[0], l2_: float = LENGTHS[1]) -> float:
    """robokin's answer to the step ``knee_angle`` of Task 3 (the tests' stand-in).

    As :func:`reference_ankle_angles`, for the knee: the tests of the later steps pass it to
    the student's ``my_leg_ik`` as its argument ``knee``.

    Parameters
    ----------
    d : float
        The hip–ankle distance (m).
    l1_, l2_ : float
        The thigh and shank lengths (m), the model's by default.

    Returns
    -------
    float
        The knee angle q4 ≥ 0 (rad) that puts the ankle at the distance d from the hip
        (q4 = 0: the stretched leg, d = l1 + l2; a cosine of q4 that rounding puts past ±1 by
        at most 1e-9 counts as ±1), ``nan`` for a distance out of reach.
    """
    d = as_scalar(d, "d")
    if d < 0.0:
        raise DomainError(f"d must be a distance >= 0 (m); got {d:g}")
    l1_, l2_ = float(check_length(l1_, "l1_")), float(check_length(l2_, "l2_"))
    # (d² − l1² − l2²) / (2 l1 l2), in ratios that neither overflow nor divide by 0
    cos4 = ((d / l1_) * (d / l2_) - l1_ / l2_ - l2_ / l1_) / 2.0
    if not abs(cos4) <= 1.0 + 1e-9:  # out of reach (nan: lengths too far apart to compare)
        return math.nan
    return math.acos(min(1.0, max(-1.0, cos4)))


def reference_ankle_angles(u: Any, q4: float, l1_: float = LENGTHS[0],
                           l2_: float = LENGTHS[1]) -> list[tuple[float, float]]:
    """robokin's answer to the step ``ankle_angles`` of Task 3 (the tests' stand-in).

    The graded tests of the steps after it (``my_leg_ik`` and what is computed from it) pass
    this function to the student's ``my_leg_ik`` in place of the student's own, so that a
    mistake in ``ankle_angles`` costs the points of its own test only.

    Parameters
    ----------
    u : array_like, shape (3,)
        The hip–ankle vector in foot coordinates (m).
    q4 : float
        The knee angle (rad).
    l1_, l2_ : float
        The thigh and shank lengths (m), the model's by default.

    Returns
    -------
    list of (float, float)
        Every pair ``(q5, q6)`` (rad) with R_y(q5) R_x(q6) u = v(q4), each once; ``[]`` if
        there is none.
    """
    u, q4 = as_vector(u, 3, "u"), as_scalar(q4, "q4")
    l1_, l2_ = float(check_length(l1_, "l1_")), float(check_length(l2_, "l2_"))
    if math.hypot(u[1], u[2]) == 0.0:
        raise DomainError("u has y = z = 0: the foot's x axis along the leg leaves q6 undetermined")
    return [(float(q5), float(q6)) for q5, q6 in _ankle_pairs(u, q4, l1=l1_, l2=l2_)]


def reference_hip_angles(R_H: Any) -> list[tuple[float, float, float]]:
    """robokin's answer to the step ``hip_angles`` of Task 3 (the tests' stand-in).

    As :func:`reference_ankle_angles`, for the hip: the tests of the later steps pass it to
    the student's ``my_leg_ik``.

    Parameters
    ----------
    R_H : array_like, shape (3, 3)
        A rotation matrix, the hip rotation R_z(q1) R_y(q2) R_x(q3).

    Returns
    -------
    list of (float, float, float)
        Both triples ``(q1, q2, q3)`` (rad) that give ``R_H``, the one with cos q2 ≥ 0 first
        (away from cos q2 = 0, where the two coincide and only q1 ∓ q3 is defined).
    """
    from robokin.transforms import rpy_from_rotation

    R_H = check_rotation_matrix(as_float_array(R_H, "R_H", (3, 3)), name="R_H")
    q3, q2, q1 = (float(a) for a in rpy_from_rotation(R_H))
    p1, p2, p3 = (float(a) for a in _wrap(np.array([q1 + math.pi, math.pi - q2, q3 + math.pi])))
    return [(q1, q2, q3), (p1, p2, p3)]


_ANKLE_ANGLE_MISTAKES = [
    ("ankle_q5_sign",
     "{name} returns q5 with the wrong sign: R_y(q5) turns z towards x (its first row is "
     "[c5, 0, s5]); write R_y(q5) w = v out row by row with that matrix."),
    ("ankle_atan2_swapped",
     "{name} swaps the arguments of atan2 for q5: atan2(y, x) takes first the entry of "
     "w = R_x(q6) u proportional to sin q5, then the one proportional to cos q5."),
    ("ankle_branch_missing",
     "{name} returns one (q5, q6) pair only: the equation for q6 (the y row, which R_y leaves "
     "alone) has two solutions in a full turn; keep both."),
]


def _ankle_pairs_fault(pairs: np.ndarray, u: np.ndarray, q4: float, where: str) -> tuple[str, str]:
    """(code, message) for ankle pairs that are not every solution, each once: what is wrong
    with the pairs themselves, without the right ones."""
    from robokin.transforms import rotx, roty

    l1, l2 = LENGTHS[:2]
    v = np.array([0.0, -l1 * math.sin(q4), -(l1 * math.cos(q4) + l2)])
    for q5, q6 in pairs:
        miss = float(np.linalg.norm(roty(q5) @ rotx(q6) @ u - v))
        if miss > 1e-7:
            return "mismatch", (
                f"{where} returns the pair (q5, q6) = {fmt(np.array([q5, q6]), 4)} rad, which misses "
                f"R_y(q5) R_x(q6) u = v(q4) by {fmt(miss, 3)} m: check the equations of q6 (the y "
                "row) and q5 (the x and z rows).")
    if _distinct(np.hstack([pairs, np.zeros((len(pairs), 4))])) < len(pairs):
        return "duplicate", f"{where} returns a pair twice (angles compared modulo 2π): each pair once."
    if len(pairs) == 0:
        return "missing", f"{where} returns no pair, but this u has solutions (it comes from a configuration)."
    return "missing", (
        f"{where} returns {len(pairs)} pair(s), each a solution, but misses another: keep every "
        "q6 in a full turn that solves its equation, each with its q5.")


class _AnkleAnglesCheck(FunctionCheck):
    """``ankle_angles(u, q4) -> [(q5, q6), ...]``: every ankle pair, each once, in any order."""

    def judge(self, answer: Any) -> CheckResult:
        X = self.sample_points()
        name, n = self.name, len(X)
        cases = []
        for x in X:
            T = _fk(x)
            cases.append((T[:3, :3].T @ _ankle_point_of(T), float(x[3])))
        got = []
        for k, (u, q4) in enumerate(cases):
            pairs = np.asarray(self.call(answer, (u.copy(), q4), f"at case {k + 1}", n), dtype=float)
            if pairs.size == 0:
                pairs = pairs.reshape(0, 2)
            if pairs.ndim != 2 or pairs.shape[1] != 2:
                return self.failure("shape", f"{name} should return a list of (q5, q6) pairs; got "
                                    f"shape {pairs.shape} at case {k + 1}.", n)
            got.append(pairs)
        refs = [_ankle_pairs(u, q4) for u, q4 in cases]
        if all(_same_rows(S, R) for S, R in zip(got, refs)):
            return self.success(f"{name} is correct: both (q5, q6) pairs, each once (checked at {n} "
                                "random foot poses).", n)
        if all(_same_rows(np.deg2rad(S), R) for S, R in zip(got, refs)):
            return self.failure("degrees_output", f"{name} returns degrees: np.deg2rad of it solves "
                                "the problem. robokin works in radians.", n)
        def explains(code: str) -> bool:
            if code == "ankle_branch_missing":  # either branch alone
                return all(len(S) == 1 and len(R) == 2 and any(_same_rows(S, R[i:i + 1]) for i in (0, 1))
                           for S, R in zip(got, refs))
            return all(_same_rows(S, _ankle_pairs(u, q4, code)) for S, (u, q4) in zip(got, cases))

        named = self.diagnose(_ANKLE_ANGLE_MISTAKES, explains, n)
        if named is not None:
            return named
        k = next(i for i, (S, R) in enumerate(zip(got, refs)) if not _same_rows(S, R))
        u, q4 = cases[k]
        where = f"{name}(u = {fmt(u, 4)} m, q4 = {q4:.4g} rad)"
        return self.failure(*_ankle_pairs_fault(got[k], u, q4, where), n)


ankle_angles = exercise(_CHAPTER, "ankle_angles", _AnkleAnglesCheck(
    name="ankle_angles",
    signature="ankle_angles(u, q4) -> list of (q5, q6)",
    variables=_Q,
    noun="foot poses",
    doc=("Check a function ankle_angles(u, q4) -> [(q5, q6), ...] that returns every pair with "
         "R_y(q5) R_x(q6) u = v(q4), u the hip–ankle vector in foot coordinates, at 20 random "
         "foot poses."),
))


@dataclass(repr=False)
class _CountCheck(Check):
    """``k_regular``: how many solutions a regular reachable foot pose has (an int)."""

    def evaluate(self, answer: Any) -> CheckResult:
        name = self.name
        if answer is None:
            return CheckResult(name, False, f"{FAIL} {name} is None: did you forget to define it?", "error", 0)
        if isinstance(answer, (bool, np.bool_)) or not isinstance(answer, (int, float, np.integer, np.floating)):
            return CheckResult(name, False, f"{FAIL} {name} should be an int (a number of solutions); got "
                               f"{type(answer).__name__}.", "type", 0)
        X = self.sample_points()
        counts = {len(_closed_form(_fk(x))) for x in X}
        expected = counts.pop() if len(counts) == 1 else None
        if expected is not None and float(answer) == expected:
            return CheckResult(name, True, f"{PASS} {name} is correct (the count at {len(X)} random foot "
                               "poses).", None, len(X))
        if expected is not None and float(answer) in (expected / 2, expected / 4):
            return CheckResult(name, False, (
                f"{FAIL} {name} = {answer} leaves out a branch: count the values each step (knee, "
                "ankle, hip) allows at a regular pose, for each value of the step before."),
                "branch_missing", len(X))
        return CheckResult(name, False, (
            f"{FAIL} {name} = {answer} is not the number of solutions of a regular reachable "
            "foot pose: count the choices each step leaves (knee, ankle, hip)."), "count", len(X))


k_regular = exercise(_CHAPTER, "k_regular", _CountCheck(
    name="k_regular",
    reference=lambda x: np.array([len(_closed_form(_fk(x)))]),
    variables=_Q,
    noun="foot poses",
    doc="Check k_regular, the number of solutions of a regular reachable foot pose (an int).",
))


def _reference_steps() -> dict[str, Any]:
    """robokin's steps by the names of the keyword parameters the chapter's later functions take
    (``my_leg_ik(T, ankle=, knee=, ankle_angles=, hip_angles=)``, ``unreachable_reason(T,
    leg_ik=)``): a check of a later function judges it alone, and the grading report blames no
    later function for an earlier step."""
    return {"ankle": reference_ankle_point, "knee": reference_knee_angle,
            "ankle_angles": reference_ankle_angles, "hip_angles": reference_hip_angles,
            "leg_ik": _closed_form}


class _LegIKCheck(FunctionCheck):
    """``my_leg_ik(T) -> (k, 6)``: every solution of a foot pose, each once, in any order; called
    with robokin's steps for those of its keyword parameters that name them (:func:`_reference_steps`)."""

    def evaluate(self, answer: Any) -> CheckResult:
        """:meth:`FunctionCheck.evaluate` of ``answer`` given robokin's steps."""
        if callable(answer):
            answer = with_reference_steps(answer, _reference_steps())
        return super().evaluate(answer)

    def judge(self, answer: Any) -> CheckResult:
        X = self.sample_points()
        name, n = self.name, len(X)
        poses = [_fk(x) for x in X]
        got = []
        for k, T in enumerate(poses):
            S = np.asarray(self.call(answer, (T.copy(),), f"at pose {k + 1} (the foot pose of q = {fmt(X[k])})",
                                     n), dtype=float)
            if S.size == 0:
                S = S.reshape(0, 6)
            if S.ndim == 1 and S.size == 6:
                S = S[None, :]
            if S.ndim != 2 or S.shape[1] != 6:
                return self.failure("shape", f"{name} should return an array (k, 6), one solution per "
                                    f"row; got shape {S.shape} at pose {k + 1}.", n)
            if not np.all(np.isfinite(S)):
                return self.failure("not_finite", f"{name} returns NaN or infinite angles at pose {k + 1} "
                                    f"(the foot pose of q = {fmt(X[k])}).", n)
            got.append(S)
        refs = [_closed_form(T) for T in poses]
        if all(_same_rows(S, R) for S, R in zip(got, refs)):
            return self.success(f"{name} is correct: all 8 solutions, each once (checked at {n} random "
                                "foot poses).", n)
        if all(_same_rows(np.deg2rad(S), R) for S, R in zip(got, refs)):
            return self.failure("degrees_output", f"{name} returns degrees: np.deg2rad of it solves the "
                                "problem. robokin works in radians.", n)
        named = self.diagnose(_LEG_IK_MISTAKES, lambda code: all(
            _same_rows(S, _closed_form(T, code)) for S, T in zip(got, poses)), n)
        if named is not None:
            return named
        k = next(i for i, (S, R) in enumerate(zip(got, refs)) if not _same_rows(S, R))
        S, T, where = got[k], poses[k], f"{name} at pose {k + 1}"
        if len(S):
            passed, code, msg = _verdict(S, T, where)
            if not passed:
                return self.failure(code, msg, n)
        n_distinct = _distinct(S)
        if n_distinct < len(S):
            return self.failure("duplicate", (
                f"{where} returns {len(S)} rows but only {n_distinct} different "
                "solutions (angles compared modulo 2π): return each solution once."), n)
        return self.failure("missing", (
            f"{where} (the foot pose of q = {fmt(X[k])}) returns {len(S)} solution(s); "
            "every one reproduces the pose, but the pose has more: keep every value each step "
            "(knee, ankle angles, hip angles) allows."), n)


leg_ik = exercise(_CHAPTER, "leg_ik", _LegIKCheck(
    name="my_leg_ik",
    signature="my_leg_ik(T) -> (k, 6) array",
    variables=_Q,
    noun="foot poses",
    doc=("Check a function my_leg_ik(T) -> (k, 6) that returns every solution of a foot pose "
         "T (4×4) of the leg, each once (angles compared modulo 2π), at 20 random poses; "
         "robokin's steps are passed for its keyword parameters ankle, knee, ankle_angles and "
         "hip_angles, so that it is judged on its own."),
))


# ------------------------------------------------------------------ why a target is out of reach
_REASONS = (None, "too_far", "ankle_range", "joint_limits")


def _reason(T: np.ndarray) -> str | None:
    """Why the foot pose ``T`` has no solution within the joint limits (None: it has one)."""
    rows = _closed_form(T)
    if len(rows) == 0:
        l1, l2, l3 = LENGTHS
        a = T[:3, 3] + l3 * T[:3, 2]
        c4 = (float(a @ a) - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
        return "too_far" if abs(c4) > 1.0 + 1e-9 else "ankle_range"
    return None if np.any(_leg().within_limits(rows)) else "joint_limits"


def _reason_targets(seed: int, per_reason: int = 4) -> list[tuple[np.ndarray, str | None]]:
    """``per_reason`` foot poses of each reason (None first), from a seeded random pool:
    configurations within and beyond the joint limits, feet tilted far about y, and
    ankle points 1 mm to 5 cm beyond the reach L1 + L2."""
    from robokin.transforms import rotation_from_rpy, roty, transform

    rng = np.random.default_rng(seed)
    found: dict[str | None, list[np.ndarray]] = {r: [] for r in _REASONS}
    for _ in range(400):
        kind = rng.integers(4)
        if kind == 0:
            T = _fk(rng.uniform(-1.5, 1.5, 6))
        elif kind == 1:
            T = _fk(rng.uniform(-math.pi, math.pi, 6))
        elif kind == 2:
            R = roty(rng.choice([-1.0, 1.0]) * rng.uniform(1.2, 1.55))
            a = np.array([rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), -rng.uniform(0.35, 0.55)])
            T = transform(R, a - LENGTHS[2] * R[:, 2])
        else:
            R = rotation_from_rpy(rng.uniform(-0.4, 0.4, 3))
            direction = np.array([rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), -1.0])
            a = direction / np.linalg.norm(direction) * (sum(LENGTHS[:2]) + rng.uniform(0.001, 0.05))
            T = transform(R, a - LENGTHS[2] * R[:, 2])
        reason = _reason(T)
        if len(found[reason]) < per_reason:
            found[reason].append(T)
        if all(len(v) == per_reason for v in found.values()):
            break
    return [(T, r) for r in _REASONS for T in found[r]]


_REASON_HELP = {
    None: "a solution within the joint limits exists: return None",
    "too_far": ("the hip–ankle distance d = |p + L3 R e_z| exceeds L1 + L2 (|cos q4| > 1): "
                "\"too_far\""),
    "ankle_range": ("the knee reaches (|cos q4| <= 1), but no (q5, q6) turns the foot to R at "
                    "that distance (ankle_angles returns [] for both knee signs): \"ankle_range\""),
    "joint_limits": ("solutions exist, but none is within the joint limits "
                     "(leg.within_limits): \"joint_limits\""),
}


class _ReasonCheck(FunctionCheck):
    """``unreachable_reason(T) -> None | "too_far" | "ankle_range" | "joint_limits"``; called with
    robokin's inverse kinematics for a keyword parameter ``leg_ik`` (:func:`_reference_steps`)."""

    def evaluate(self, answer: Any) -> CheckResult:
        """:meth:`FunctionCheck.evaluate` of ``answer`` given robokin's steps."""
        if callable(answer):
            answer = with_reference_steps(answer, _reference_steps())
        return super().evaluate(answer)

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        targets = _reason_targets(self.seed if self.seed is not None else 0)
        n = len(targets)
        for k, (T, expected) in enumerate(targets):
            got = self.call(answer, (T.copy(),), f"at target {k + 1} (expected {expected!r})", n)
            if got is None or isinstance(got, str):
                if got == expected:
                    continue
                where = (f"{name} returns {got!r} for a target whose answer is "
                         f"{expected!r} (foot at {fmt(T[:3, 3], 3)} m)")
                if got is not None and got not in _REASONS:
                    return self.failure("unknown_reason", where + ": the reasons are \"too_far\", "
                                        "\"ankle_range\" and \"joint_limits\" (None when reachable "
                                        "within the limits).", n)
                code = f"{expected}_as_{got}".replace("None", "reachable")
                return self.failure(code, where + ": " + _REASON_HELP[expected] + ".", n)
            return self.failure("type", f"{name} should return None or one of \"too_far\", "
                                f"\"ankle_range\", \"joint_limits\"; got {type(got).__name__} at "
                                f"target {k + 1}.", n)
        return self.success(f"{name} is correct (checked at {n} targets: reachable, too far, beyond the "
                            "ankle's range, beyond the joint limits).", n)


unreachable_reason = exercise(_CHAPTER, "unreachable_reason", _ReasonCheck(
    name="unreachable_reason",
    signature="unreachable_reason(T) -> None or a reason",
    noun="targets",
    doc=("Check a function unreachable_reason(T) -> None (a solution within the joint limits "
         "exists) or why the foot pose T is out of reach: \"too_far\", \"ankle_range\", "
         "\"joint_limits\"; robokin's inverse kinematics is passed for its keyword parameter "
         "leg_ik, so that it is judged on its own."),
))


# ------------------------------------------------------------------ the sweep of the sole's height
#: The sweep's heights (m below the hip) and how many rows the check's inverse kinematics
#: returns at each (not a count of the leg's: the sweep is judged on its own).
_SWEEP_ROWS = {0.42: 2, 0.5: 0, 0.57: 4, 0.63: 1, 0.69: 3, 0.74: 0}


class _SoleSweepCheck(FunctionCheck):
    """``sole_sweep(heights, leg_ik) -> (n_solutions, sigma_min)``, called with an inverse
    kinematics of the check's own that returns the first k_h rows of a fixed set of configurations."""

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        leg = _leg()
        # four configurations, within the joint limits and beyond them alternately
        rng = np.random.default_rng(self.seed if self.seed is not None else 0)
        pool = rng.uniform(-1.2, 1.2, (4, 6)) * np.array([[1.0], [2.5], [1.0], [2.5]])
        heights = np.array(list(_SWEEP_ROWS))
        asked: list[np.ndarray] = []

        def check_ik(T: Any) -> np.ndarray:
            """The first k_h rows of the pool, for the height nearest the pose's."""
            T = np.asarray(T, dtype=float)
            asked.append(T)
            h = min(_SWEEP_ROWS, key=lambda height: abs(height + T[2, 3]))
            return pool[: _SWEEP_ROWS[h]].copy()

        n = len(heights)
        got = self.call(answer, (heights.copy(), check_ik), "with an inverse kinematics of the check's own", n)
        try:
            counts, sigmas = (np.asarray(part, dtype=float).reshape(-1) for part in got)
        except (TypeError, ValueError):
            return self.failure("type", f"{name} should return two arrays (n_solutions, sigma_min), one "
                                f"entry per height; got {type(got).__name__}.", n)
        if not asked:
            return self.failure("leg_ik_ignored", f"{name} never calls the inverse kinematics passed as "
                                "its argument leg_ik: call leg_ik(T), not my_leg_ik(T).", n)
        if counts.shape != heights.shape or sigmas.shape != heights.shape:
            return self.failure("shape", f"{name} should return one count and one sigma_min per height "
                                f"({len(heights)} here); got {counts.size} and {sigmas.size}.", n)
        poses = np.array(asked)
        if not (np.allclose(poses[:, :3, :3], np.eye(3)) and np.allclose(poses[:, :2, 3], 0.0)):
            return self.failure("pose", f"{name} asks leg_ik for poses that are not the sole level "
                                "(rotation I) straight below the hip: T = transform(I, [0, 0, -h]).", n)
        depth = -poses[:, 2, 3]
        if not all(np.isclose(np.abs(heights - z).min(), 0.0, atol=1e-12) for z in depth):
            if all(np.isclose(np.abs(heights + z).min(), 0.0, atol=1e-12) for z in depth):
                return self.failure("height_sign", f"{name} puts the sole above the hip: the heights are "
                                    "below it, T[2, 3] = -h.", n)
            return self.failure("pose", f"{name} asks leg_ik for the sole at other heights than those "
                                "given: T = transform(I, [0, 0, -h]) for each h.", n)
        expected_counts = np.array([float(_SWEEP_ROWS[h]) for h in _SWEEP_ROWS])
        inside = np.cumsum(np.r_[0, leg.within_limits(pool)])[expected_counts.astype(int)]
        if np.array_equal(counts, inside) and not np.array_equal(inside, expected_counts):
            return self.failure("within_limits_only", f"{name} counts only the rows within the joint "
                                "limits: n_solutions is every row leg_ik returns.", n)
        if not np.array_equal(counts, expected_counts):
            return self.failure("count", f"{name}'s n_solutions should count every row leg_ik returns "
                                f"(here {expected_counts.astype(int).tolist()}); got "
                                f"{counts.tolist()}.", n)
        sigma_of = [leg.singular_values(q)[-1] for q in pool]
        first = np.where(expected_counts > 0, sigma_of[0], np.nan)

        def same(values: np.ndarray) -> bool:
            return bool(np.allclose(sigmas, values, rtol=1e-6, atol=1e-12, equal_nan=True))

        if same(first):
            return self.success(f"{name} is correct (checked at {n} heights with an inverse kinematics "
                                "of its own).", n)
        k = expected_counts.astype(int)
        mistakes = (
            ("zero_for_none", np.where(k > 0, sigma_of[0], 0.0),
             f"{name} gives 0 where leg_ik returns no row: that is NaN (there is no Jacobian to measure)."),
            ("sigma_last_row", np.array([sigma_of[c - 1] if c else np.nan for c in k]),
             f"{name} takes sigma_min at the last row leg_ik returns: the task asks for the first."),
            ("sigma_smallest_of_rows", np.array([min(sigma_of[:c]) if c else np.nan for c in k]),
             f"{name} takes the smallest sigma_min over the rows: the task asks for the first row's."),
            ("largest_singular_value",
             np.where(k > 0, leg.singular_values(pool[0])[0], np.nan),
             f"{name} takes the largest singular value: sigma_min is the smallest, "
             "leg.singular_values(q)[-1]."),
        )
        for code, values, text in mistakes:
            if same(values):
                return self.failure(code, text, n)
        return self.failure("sigma", f"{name}'s sigma_min should be the smallest singular value of the "
                            "leg's Jacobian at the first row leg_ik returns (NaN where it returns "
                            "none).", n)


sole_sweep = exercise(_CHAPTER, "sole_sweep", _SoleSweepCheck(
    name="sole_sweep",
    signature="sole_sweep(heights, leg_ik) -> (n_solutions, sigma_min)",
    noun="heights",
    doc=("Check a function sole_sweep(heights, leg_ik) -> (n_solutions, sigma_min): for the sole "
         "level at each height below the hip, the number of rows leg_ik returns and sigma_min of "
         "the Jacobian at the first (NaN where there is none), with an inverse kinematics of the "
         "check's own."),
))


# ------------------------------------------------------------------ different solutions among rows
def _count_apart(Q: np.ndarray, apart: Any) -> int:
    """How many rows of ``Q`` differ from every earlier kept row by ``apart(q, kept) > 0``."""
    kept: list[np.ndarray] = []
    for row in Q:
        if all(apart(row, other) for other in kept):
            kept.append(row)
    return len(kept)


def _different_count(Q: np.ndarray, mistake: str = "") -> int:
    """The number of different solutions among the rows of ``Q`` (angles modulo 2π, to 1e-9 rad),
    or what a typical ``mistake`` counts."""
    if mistake == "rows_counted":
        return len(Q)
    if mistake == "no_wrapping":
        return _count_apart(Q, lambda q, k: np.abs(q - k).max() > 1e-9)
    if mistake == "tolerance_too_loose":
        return _count_apart(Q, lambda q, k: np.abs(_wrap(q - k)).max() > 1e-4)
    return _count_apart(Q, lambda q, k: np.abs(_wrap(q - k)).max() > 1e-9)


_DIFFERENT_MISTAKES = [
    ("rows_counted",
     "{name} counts every row: rows that are one solution written twice (the same angles, "
     "or the same up to full turns) count once."),
    ("no_wrapping",
     "{name} compares the joint angles as they are: a row turned by full turns (2π in some "
     "joints) is the same solution. Compare the differences modulo 2π (wrapped into [−π, π))."),
    ("exact_equality",
     "{name} asks for exactly equal angles: copies that rounding moved by 1e-12 rad count "
     "twice. Two rows are one solution when they agree to 1e-9 rad (modulo 2π)."),
    ("tolerance_too_loose",
     "{name} merges rows that are 1e-6 rad apart: those are different solutions. The "
     "statement's tolerance is 1e-9 rad (modulo 2π)."),
]


class _DifferentSolutionsCheck(FunctionCheck):
    """``different_solutions(Q) -> int``: rows that agree modulo 2π (to 1e-9 rad) count once."""

    def judge(self, answer: Any) -> CheckResult:
        from robokin.transforms import transform

        name = self.name
        rng = np.random.default_rng(self.seed if self.seed is not None else 0)
        turns = 2.0 * math.pi * rng.integers(-2, 3, (8, 6))
        straight = _closed_form(transform(np.eye(3), [0.0, 0.0, -sum(LENGTHS)]))  # 8 rows, 4 apart
        regular = _closed_form(_fk(rng.uniform(-1.2, 1.2, 6)))
        single = regular[:1]
        cases = [
            straight,                                                        # each solution twice
            np.vstack([regular, regular[:3] + turns[:3]]),                   # full turns
            np.vstack([regular, regular[:2] + 1e-12]),                       # rounding
            np.vstack([single, single + 1e-6, single + turns[5]]),           # 1e-6 rad apart
            single,
        ]
        n = len(cases)
        got = []
        for k, Q in enumerate(cases):
            value = self.call(answer, (Q.copy(),), f"at case {k + 1}", n)
            try:
                if value is None or isinstance(value, str):
                    raise TypeError(type(value).__name__)
                count = float(np.asarray(value, dtype=float).reshape(()))
            except (TypeError, ValueError):
                return self.failure("type", f"{name} should return one number, how many rows are "
                                    f"different solutions; got {type(value).__name__} at case {k + 1}.", n)
            got.append(count)
        if all(count == _different_count(Q) for count, Q in zip(got, cases)):
            return self.success(f"{name} is correct (checked at {n} sets of rows: copies turned by full "
                                "turns, moved by rounding, and rows 1e-6 rad apart).", n)

        def explains(code: str) -> bool:
            if code == "exact_equality":  # the turned copies may or may not round back exactly
                return got[2] == len(cases[2]) and all(
                    got[i] == _different_count(cases[i]) for i in (0, 4))
            return all(count == _different_count(Q, code) for count, Q in zip(got, cases))

        named = self.diagnose(_DIFFERENT_MISTAKES, explains, n)
        if named is not None:
            return named
        k = next(i for i, (count, Q) in enumerate(zip(got, cases)) if count != _different_count(Q))
        return self.failure("count", (
            f"{name} miscounts case {k + 1} ({len(cases[k])} rows): two rows are one solution when every "
            "joint angle agrees up to full turns (2π), to 1e-9 rad; count each solution once."), n)


different_solutions = exercise(_CHAPTER, "different_solutions", _DifferentSolutionsCheck(
    name="different_solutions",
    signature="different_solutions(Q) -> int",
    noun="sets of rows",
    doc=("Check a function different_solutions(Q) -> int: how many rows of Q (k, 6) are "
         "different solutions (rows that agree modulo 2π to 1e-9 rad are one), on sets of rows "
         "of the check's own."),
))


# ------------------------------------------------------------------ the hip angles
def _hip_triples(R_H: np.ndarray, mistake: str = "") -> np.ndarray:
    """Both ``(q1, q2, q3)`` with R_z(q1) R_y(q2) R_x(q3) = R_H, cos q2 > 0 first (k, 3), or
    what a typical ``mistake`` (the codes of :data:`_HIP_MISTAKES`) makes of them."""
    R = R_H.T if mistake in ("hip_transposed", "hip_order") else R_H
    rows = []
    for sign in ((1.0,) if mistake == "hip_branch_missing" else (1.0, -1.0)):
        c2 = sign * math.hypot(R[0, 0], R[1, 0])
        q2 = math.atan2(-R[2, 0], c2)
        if mistake == "hip_atan2_swapped":
            q1, q3 = math.atan2(R[0, 0] / c2, R[1, 0] / c2), math.atan2(R[2, 2] / c2, R[2, 1] / c2)
        else:
            q1, q3 = math.atan2(R[1, 0] / c2, R[0, 0] / c2), math.atan2(R[2, 1] / c2, R[2, 2] / c2)
        if mistake == "hip_order":  # Rx(a) Ry(b) Rz(c) = R_H read off R_Hᵀ = Rz(−c) Ry(−b) Rx(−a)
            q1, q2, q3 = -q1, -q2, -q3
        rows.append((q3, q2, q1) if mistake == "hip_reversed" else (q1, q2, q3))
    return np.array(rows, dtype=float)


_HIP_MISTAKES = [
    ("hip_branch_missing",
     "{name} returns one triple only: the same R_H has a second triple, with cos q2 of the "
     "other sign; return both."),
    ("hip_atan2_swapped",
     "{name} swaps the arguments of atan2 in q1 and q3: atan2(y, x) takes first the entry "
     "proportional to the angle's sine, then the one proportional to its cosine."),
    ("hip_reversed",
     "{name} returns the angles in the order (q3, q2, q1), as roll, pitch, yaw: the task asks "
     "for (q1, q2, q3), q1 about z first."),
    ("hip_order",
     "{name} reads the angles as if R_H = R_x(q3) R_y(q2) R_z(q1). The hip yaw q1 comes first "
     "from the body: R_H = R_z(q1) R_y(q2) R_x(q3) (ZYX); read the angles off that product."),
    ("hip_transposed",
     "{name} reads the angles off R_Hᵀ: the product R_z(q1) R_y(q2) R_x(q3) is R_H itself, "
     "not its transpose."),
]


class _HipAnglesCheck(FunctionCheck):
    """``hip_angles(R_H) -> [(q1, q2, q3), ...]``: both triples, the one with cos q2 > 0 first."""

    def judge(self, answer: Any) -> CheckResult:
        from robokin.transforms import rotx, roty, rotz

        X = self.sample_points()
        name, n = self.name, len(X)
        cases = [rotz(x[0]) @ roty(x[1]) @ rotx(x[2]) for x in X]
        got = []
        for k, R_H in enumerate(cases):
            out = np.asarray(self.call(answer, (R_H.copy(),), f"at rotation {k + 1}", n), dtype=float)
            if out.size == 0:
                out = out.reshape(0, 3)
            if out.ndim == 1 and out.size == 3:
                out = out[None, :]
            if out.ndim != 2 or out.shape[1] != 3:
                return self.failure("shape", f"{name} should return a list of (q1, q2, q3) triples; got "
                                    f"shape {out.shape} at rotation {k + 1}.", n)
            got.append(out)
        refs = [_hip_triples(R_H) for R_H in cases]
        if all(_same_rows(S, R) for S, R in zip(got, refs)):
            if all(math.cos(S[0, 1]) > 0 for S in got):
                return self.success(f"{name} is correct: both triples, the one with cos q2 > 0 first "
                                    f"(checked at {n} random hip rotations).", n)
            return self.failure("first_branch", f"{name} returns both triples, but not always the one "
                                "with cos q2 > 0 first, as the task asks.", n)
        if all(_same_rows(np.deg2rad(S), R) for S, R in zip(got, refs)):
            return self.failure("degrees_output", f"{name} returns degrees: np.deg2rad of it solves the "
                                "problem. robokin works in radians.", n)
        named = self.diagnose(_HIP_MISTAKES, lambda code: all(
            _same_rows(S, _hip_triples(R_H, code)) for S, R_H in zip(got, cases)), n)
        if named is not None:
            return named
        k = next(i for i, (S, R) in enumerate(zip(got, refs)) if not _same_rows(S, R))
        where = f"{name} at rotation {k + 1}"
        for q1, q2, q3 in got[k]:
            miss = float(np.abs(rotz(q1) @ roty(q2) @ rotx(q3) - cases[k]).max())
            if miss > 1e-7:
                return self.failure("mismatch", (
                    f"{where} returns (q1, q2, q3) = {fmt(np.array([q1, q2, q3]), 4)} rad, whose "
                    f"R_z(q1) R_y(q2) R_x(q3) differs from R_H by up to {fmt(miss, 3)} in an entry."), n)
        if _distinct(np.hstack([got[k], np.zeros((len(got[k]), 3))])) < len(got[k]):
            return self.failure("duplicate", f"{where} returns a triple twice (angles compared modulo "
                                "2π): each triple once.", n)
        if len(got[k]) == 0:
            return self.failure("missing", f"{where} returns no triple, but every rotation R_H has "
                                "its hip angles.", n)
        return self.failure("missing", (
            f"{where} returns {len(got[k])} triple(s), each right, but misses another: the same "
            "R_H has a triple with cos q2 of either sign."), n)


hip_angles = exercise(_CHAPTER, "hip_angles", _HipAnglesCheck(
    name="hip_angles",
    signature="hip_angles(R_H) -> list of (q1, q2, q3)",
    variables=_Q,
    noun="hip rotations",
    doc=("Check a function hip_angles(R_H) -> [(q1, q2, q3), ...] that returns both triples with "
         "R_z(q1) R_y(q2) R_x(q3) = R_H, the one with cos q2 > 0 first, at 20 random hip "
         "rotations."),
))
