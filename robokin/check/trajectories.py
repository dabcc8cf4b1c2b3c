r"""Exercise checks of chapter 10: trajectories in joint and task space.

=======================  =====================================================  ===================
check                    the student's answer                                   compared with
=======================  =====================================================  ===================
``cubic_scaling``        ``cubic_scaling(t, T)`` -> ``[s, ṡ, s̈]`` (3,)          the cubic law
``quintic_scaling``      ``quintic_scaling(t, T)`` -> ``[s, ṡ, s̈]`` (3,)        the quintic law
``peak_factors``         (2, 2): rows cubic, quintic; columns c_v, c_a          the laws' maxima
``trapezoid_time``       ``trapezoid_time(distance, v_max, a_max)`` -> T (s)    the minimum time
``synchronised_motion``  ``synchronised_motion(t, q_start, q_end, v_max,        ``joint_trajectory``
                         a_max)`` -> positions, velocities, accelerations
``least_duration``       ``least_duration(q_start, q_end, v_max, a_max)`` -> T  robokin's duration
``via_point_cubics``     ``via_point_cubics(points, durations)`` -> (m, 4, n)   cubics through the via
                         coefficients a0..a3 per segment and joint              points, rule's velocities
``slerp``                ``slerp(q0, q1, s)`` -> unit quaternion (4,)           ``quaternion_slerp``
``line_reference``       ``line_reference(t, T_start, T_end, duration)``        ``pose_trajectory``
                         -> pose (4, 4), twist [v; ω] (6,)
``track``                ``track(q0, poses, twists, ts, gain)`` -> (N, 6)       the resolved-rate loop
=======================  =====================================================  ===================

The timing laws are those of Siciliano et al. (2009), §4.2.1, and Lynch & Park (2017), §9.2.2;
the synchronised trapezoids are compared with robokin's
:func:`~robokin.motion.joint_trajectory`. The via-point cubics take the velocity at an interior
via point as the mean of the two adjacent slopes, or 0 where their signs differ, and rest at both
ends (Siciliano et al. 2009, ch. 4; robokin's :func:`~robokin.motion.via_point_trajectory`).
The functions are called at seeded random inputs of the checks' own and compared with the
reference; a function that takes an earlier step as a keyword argument (``least_duration``'s
``trapezoid_time``, ``synchronised_motion``'s ``least_duration``, ``line_reference``'s
``quintic_scaling`` and ``slerp``) is given robokin's step (``reference_*`` below), so that
each check judges its own step; a wrong answer is explained when one of the chapter's typical mistakes reproduces
it (a derivative in the wrong variable, a case of the trapezoid missed, the limits swapped, the
wrong joint setting the pace, a velocity that jumps at a via point, the ends not at rest, the
durations mixed up, slerp the wrong way round or NaN for nearly equal rotations, degrees for
radians; a peak factor of the other law, signed, read at the wrong τ, or the peaks of a motion
other than D = 1, T = 1).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    Check,
    CheckResult,
    FunctionCheck,
    LaterStepCheck,
    MatrixArgumentsCheck,
    Variable,
    alternatives,
    fmt,
    with_reference_steps,
)
from robokin.check._registry import exercise
from robokin.errors import DomainError, ShapeError
from robokin.validation import as_float_array, as_scalar, as_vector, check_positive, check_result_finite

__all__ = ["cubic_scaling", "quintic_scaling", "peak_factors", "trapezoid_time", "synchronised_motion",
           "least_duration", "via_point_cubics", "slerp", "line_reference", "track", "PROBLEM",
           "reference_cubic_scaling", "reference_quintic_scaling", "reference_trapezoid_time",
           "reference_least_duration", "reference_slerp"]

_CHAPTER = "trajectories"

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back is flagged for review by hand
#: (tools/grading/bridge/delegation.py reads this literal table without importing the module)
DELEGATION = {
    "cubic_scaling": {"time_law": "robokin.motion.time_law", "joint_trajectory": "robokin.motion.joint_trajectory",
                      "reference_cubic_scaling": "robokin.check.trajectories.reference_cubic_scaling"},
    "quintic_scaling": {"time_law": "robokin.motion.time_law",
                        "joint_trajectory": "robokin.motion.joint_trajectory",
                        "reference_quintic_scaling": "robokin.check.trajectories.reference_quintic_scaling"},
    # the visible test reads the peaks off robokin's laws on a grid: a copy of that is flagged
    "peak_factors": {"time_law": "robokin.motion.time_law",
                     "reference_cubic_scaling": "robokin.check.trajectories.reference_cubic_scaling",
                     "reference_quintic_scaling": "robokin.check.trajectories.reference_quintic_scaling"},
    "trapezoid_time": {"joint_trajectory_duration": "robokin.motion.joint_trajectory_duration",
                       "joint_trajectory": "robokin.motion.joint_trajectory",
                       "reference_trapezoid_time": "robokin.check.trajectories.reference_trapezoid_time",
                       "reference_least_duration": "robokin.check.trajectories.reference_least_duration"},
    "least_duration": {"joint_trajectory_duration": "robokin.motion.joint_trajectory_duration",
                       "joint_trajectory": "robokin.motion.joint_trajectory",
                       "reference_least_duration": "robokin.check.trajectories.reference_least_duration"},
    "synchronised_motion": {"joint_trajectory": "robokin.motion.joint_trajectory",
                            "joint_trajectory_duration": "robokin.motion.joint_trajectory_duration"},
    "via_point_cubics": {"via_point_trajectory": "robokin.motion.via_point_trajectory"},
    "slerp": {"quaternion_slerp": "robokin.transforms.quaternion_slerp",
              "pose_trajectory": "robokin.motion.pose_trajectory",
              "reference_slerp": "robokin.check.trajectories.reference_slerp"},
    "line_reference": {"pose_trajectory": "robokin.motion.pose_trajectory",
                       "quaternion_slerp": "robokin.transforms.quaternion_slerp"},
    "track": {"CartesianController": "robokin.motion.CartesianController", "simulate": "robokin.motion.simulate",
              "solve_ik": "robokin.motion.solve_ik", "ur10_ik": "robokin.models.ur10_ik"},
}

#: The exercise's data (the notebook's problem statement): the UR10's two configurations (deg)
#: and the per-joint limits (deg/s, rad/s²).
PROBLEM = {
    "q_a_deg": (-30.0, -100.0, 110.0, -100.0, -90.0, 0.0),
    "q_b_deg": (75.0, -60.0, 60.0, -130.0, -90.0, 45.0),
    "v_max_deg": (120.0, 120.0, 180.0, 180.0, 180.0, 180.0),
    "a_max": (2.5, 2.5, 4.0, 5.0, 5.0, 5.0),
}


# ------------------------------------------------------------------ timing laws
def _law(tau: np.ndarray, law: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """s, ds/dτ, d²s/dτ² of a rest-to-rest law on τ in [0, 1], written out (no robokin call)."""
    if law == "cubic":
        return 3 * tau**2 - 2 * tau**3, 6 * tau - 6 * tau**2, 6 - 12 * tau
    if law == "quintic":
        return (10 * tau**3 - 15 * tau**4 + 6 * tau**5, 30 * tau**2 - 60 * tau**3 + 30 * tau**4,
                60 * tau - 180 * tau**2 + 120 * tau**3)
    return tau, np.ones_like(tau), np.zeros_like(tau)


def _scaling(x: np.ndarray, law: str, *, per_tau: bool = False) -> np.ndarray:
    tau, duration = float(x[0]), float(x[1])
    s, ds, dds = _law(np.asarray(tau), law)
    if per_tau:
        return np.array([s, ds, dds], dtype=float)
    return np.array([s, ds / duration, dds / duration**2], dtype=float)


_TIMES = [Variable("tau", "other", 0.0, 1.0), Variable("T", "other", 0.5, 4.0)]
#: the entries of [s, ṡ, s̈], as a message names them
_RATE_NAMES = ("s (entry 0)", "ṡ (entry 1)", "s̈ (entry 2)")


def _scaling_mistakes(law: str):
    other = "quintic" if law == "cubic" else "cubic"
    return [
        alternatives("tau_derivatives", [(lambda x: _scaling(x, law, per_tau=True), (
            "{name} returns ds/dτ and d²s/dτ² with τ = t/T: the rates in time are ṡ = (ds/dτ)/T and "
            "s̈ = (d²s/dτ²)/T² (the chain rule)."
        ))]),
        alternatives("other_law", [(lambda x: _scaling(x, other), (
            f"{{name}} is the {other} law: the {law} law has "
            + ("4 coefficients fixed by s and ṡ at both ends." if law == "cubic"
               else "6 coefficients fixed by s, ṡ and s̈ at both ends.")
        ))]),
        alternatives("no_rest", [(lambda x: _scaling(x, "linear"), (
            "{name} is s = t/T, a timing law without rest at the ends: ṡ jumps from 0 to 1/T at t = 0 "
            "(an infinite acceleration)."
        ))]),
    ]


def _scaling_check(law: str) -> MatrixArgumentsCheck:
    name = f"{law}_scaling"
    return MatrixArgumentsCheck(
        name=name,
        reference=lambda x: _scaling(x, law),
        variables=_TIMES,
        diagnoses=_scaling_mistakes(law),
        noun="times",
        arguments=lambda x: (float(x[0] * x[1]), float(x[1])),
        signature=f"{name}(t, T) -> array [s, ṡ, s̈] of shape (3,)",
        describe=lambda x: f"t = {fmt(x[0] * x[1])} s, T = {fmt(x[1])} s",
        entry_label=lambda index: _RATE_NAMES[index[0]],
        hint="Write s(τ) as a polynomial in τ = t/T, fix its coefficients by the boundary conditions, "
             "and differentiate with respect to t.",
        doc=f"Check {name}(t, T) -> [s, ṡ, s̈]: the {law} rest-to-rest timing law at time t of a motion "
            "of duration T (s dimensionless, ṡ in 1/s, s̈ in 1/s²).",
    )


cubic_scaling = exercise(_CHAPTER, "cubic_scaling", _scaling_check("cubic"))
quintic_scaling = exercise(_CHAPTER, "quintic_scaling", _scaling_check("quintic"))

#: peak speed c_v D/T and peak acceleration c_a D/T² of the cubic and quintic laws
_PEAKS = np.array([[1.5, 6.0], [15.0 / 8.0, 10.0 / math.sqrt(3.0)]])
_LAWS = ("cubic", "quintic")
_FACTORS = ("c_v", "c_a")
#: where the quintic's acceleration is largest in size: the jerk d³s/dτ³ vanishes there
_QUINTIC_JERK_ZERO = 0.5 - math.sqrt(3.0) / 6.0


def _rate(law: str, order: int, tau: float) -> float:
    """d^order s/dτ^order of ``law`` at ``tau`` (order 1 or 2), from the laws written out."""
    return float(_law(np.asarray(tau), law)[order])


def _peak_entry_mistakes(row: int, column: int) -> list[tuple[str, float, str]]:
    """The typical wrong values of one entry of peak_factors: (code, value, message), rebuilt
    from the laws; ``{name}`` is replaced by the answer's name."""
    law, other = _LAWS[row], _LAWS[1 - row]
    entry = f"the {law}'s {_FACTORS[column]} (entry ({row + 1}, {column + 1}) of {{name}})"
    if column == 0:
        return [
            ("speed_other_law", _rate(other, 1, 0.5), (
                f"{entry} is the {other} law's speed factor: the {law}'s own ds/dτ peaks at "
                "τ = 1/2.")),
            ("mean_speed", 1.0, (
                f"{entry} is the mean speed D/T (c_v = 1): the {law} starts and ends at rest, so its "
                "speed in the middle is above the mean; c_v is the largest ds/dτ, at τ = 1/2.")),
        ]
    braking = 1.0 if law == "cubic" else 1.0 - _QUINTIC_JERK_ZERO
    mistakes = [
        ("acceleration_sign", _rate(law, 2, braking), (
            f"{entry} is negative, the acceleration where the {law} brakes (τ = {braking:.4g}): c_a is "
            "the largest size |s̈|, the same when it speeds up and when it brakes.")),
        ("acceleration_other_law", _PEAKS[1 - row, 1], (
            f"{entry} is the {other} law's acceleration factor.")),
    ]
    if law == "cubic":
        mistakes.append(("acceleration_at_middle", _rate(law, 2, 0.5), (
            f"{entry} is the cubic's acceleration at τ = 1/2, where the speed peaks and s̈ = 0: "
            "d²s/dτ² = 6 − 12τ is largest in size at the ends, τ = 0 and τ = 1.")))
    else:
        mistakes.append(("quintic_acceleration", _rate(law, 2, 0.5), (
            f"{entry} is zero, the quintic's acceleration at τ = 1/2 (where its speed peaks) and at "
            "the ends: its largest acceleration is where the jerk d³s/dτ³ vanishes.")))
        mistakes.append(("acceleration_at_quarter", _rate(law, 2, 0.25), (
            f"{entry} is the quintic's acceleration at τ = 1/4, halfway to the speed's peak: it is "
            "largest where the jerk d³s/dτ³ vanishes.")))
    return mistakes


def _scaled_peaks(answer: np.ndarray) -> tuple[float, float] | None:
    """(D, T) when ``answer`` is the peak speeds c_v D/T and accelerations c_a D/T² of a
    motion other than D = 1, T = 1 (the factors read off at that motion), else None."""
    speed, acceleration = answer[0] / _PEAKS[0]
    if not (speed > 0 and acceleration > 0):
        return None
    duration = speed / acceleration             # D/T over D/T²
    distance = speed * duration
    if np.allclose([distance, duration], 1.0, rtol=1e-6):
        return None
    scaled = _PEAKS * np.array([distance / duration, distance / duration**2])
    return (distance, duration) if np.allclose(answer, scaled, atol=1e-8, rtol=1e-6) else None


def _peak_cause(values: np.ndarray, name: str) -> tuple[str, str] | None:
    """(code, message) of the typical mistakes that reproduce the wrong factors ``values`` (2, 2):
    the whole array's (rows or columns swapped, the peaks of a motion other than D = 1, T = 1), else
    each wrong entry's, the code of the first (row by row); None when a wrong entry has no typical
    mistake that explains it."""
    wrong = ~np.isclose(values, _PEAKS, atol=1e-8, rtol=1e-6)
    for code, swapped, text in (
            ("rows_swapped", _PEAKS[::-1], "the rows swapped: row 0 is the cubic law, row 1 the quintic"),
            ("columns_swapped", _PEAKS[:, ::-1], "the columns swapped: column 0 is the speed factor "
                                                 "c_v, column 1 the acceleration factor c_a")):
        if np.allclose(values, swapped, atol=1e-8, rtol=1e-6):
            return code, f"{name} has {text}."
    scaled = _scaled_peaks(values)
    if scaled is not None:
        distance, duration = scaled
        return "scaled", (
            f"{name} holds the peak speed and acceleration of a motion of D = {distance:.4g} in "
            f"T = {duration:.4g} s: the factors are per unit of τ = t/T and of D, c_v = "
            "(T/D) max|ṡ| and c_a = (T²/D) max|s̈|.")
    causes = []
    for row, column in np.argwhere(wrong):
        found = [(code, message.format(name=name))
                 for code, value, message in _peak_entry_mistakes(int(row), int(column))
                 if math.isclose(values[row, column], value, rel_tol=1e-6, abs_tol=1e-8)]
        if not found:
            return None     # an entry no typical mistake explains: the mismatch message says more
        causes.append(found[0])
    return causes[0][0], " ".join(message[:1].upper() + message[1:] for _, message in causes)


def _peak_mismatch(values: np.ndarray | None, name: str, hint: str) -> str:
    """The message for wrong factors that no typical mistake explains: the factors that differ,
    not the values they should have (those are the answer), and the hint."""
    if values is None or values.shape != _PEAKS.shape:
        return f"{name} is not correct. {hint}"
    wrong = np.argwhere(~np.isclose(values, _PEAKS, atol=1e-8, rtol=1e-6))
    named = [f"the {_LAWS[row]}'s {_FACTORS[column]} (entry ({row + 1}, {column + 1}))"
             for row, column in wrong]
    return (f"{name} is not correct: {', '.join(named)} differ{'s' if len(named) == 1 else ''}. "
            f"{hint}")


class _PeakFactorsCheck(Check):
    """The factors (2, 2); a wrong one is explained by the whole array's mistakes or by the
    typical wrong value of the entry that differs first; otherwise the message names the factors
    that differ, not their values (the check has one input: its reference is the answer)."""

    def evaluate(self, answer: Any) -> CheckResult:
        result = super().evaluate(answer)
        if result.passed or result.diagnosis != "mismatch":
            return result
        try:
            values = np.asarray(answer, dtype=float)
        except (TypeError, ValueError):      # not an array of numbers (a function, a sympy matrix)
            values = None
        cause = _peak_cause(values, self.name) if values is not None and values.shape == (2, 2) else None
        if cause is None:
            return self._fail("mismatch", _peak_mismatch(values, self.name, self.hint), result.samples)
        return self._fail(cause[0], cause[1], result.samples)


peak_factors = exercise(_CHAPTER, "peak_factors", _PeakFactorsCheck(
    name="peak_factors",
    reference=lambda x: _PEAKS,
    hint="c_v = max ds/dτ and c_a = max |d²s/dτ²| over τ in [0, 1]: ṡ peaks where s̈ = 0, "
         "s̈ at an end or where the jerk vanishes.",
    doc="Check peak_factors (2, 2): rows cubic, quintic; columns c_v, c_a with peak speed c_v D/T and "
        "peak acceleration c_a D/T².",
))


# ------------------------------------------------------------------ the trapezoid
def _trapezoid_time(distance: float, v_max: float, a_max: float, *, threshold: float = 1.0,
                    triangle: bool = True, ramps: float = 1.0, triangle_factor: float = 2.0) -> float:
    """Minimum rest-to-rest time, written out; keyword arguments make the typical mistakes."""
    if triangle and distance < threshold * v_max * v_max / a_max:
        return triangle_factor * math.sqrt(distance / a_max)
    return distance / v_max + ramps * v_max / a_max


_TRAPEZOID = [Variable("distance", "angle", 0.02, 3.0), Variable("v_max", "other", 0.3, 2.5),
              Variable("a_max", "other", 0.5, 5.0)]


def _trapezoid_mistakes():
    return [
        alternatives("triangular_missed", [(lambda x: np.asarray(_trapezoid_time(*x, triangle=False)), (
            "{name} always uses T = D/v_max + v_max/a_max. For a short move its cruise time "
            "D/v_max − v_max/a_max is negative: the joint never reaches v_max, and the profile is "
            "a triangle."
        ))]),
        alternatives("swapped_limits", [(lambda x: np.asarray(_trapezoid_time(x[0], x[2], x[1])), (
            "{name} swaps v_max and a_max (check the units: D/v_max is in s, v_max/a_max in s)."
        ))]),
        alternatives("threshold", [
            (lambda x: np.asarray(_trapezoid_time(*x, threshold=0.5)), (
                "{name} switches to the triangle at D = v_max²/(2 a_max); the two ramps to v_max and back cover "
                "a distance of their own: the triangle is needed when that is more than D."
            )),
            (lambda x: np.asarray(_trapezoid_time(*x, threshold=2.0)), (
                "{name} switches to the triangle at D = 2 v_max²/a_max; the two ramps to v_max and back cover "
                "a distance of their own: the triangle is needed when that is more than D."
            )),
        ]),
        alternatives("ramps_added", [
            (lambda x: np.asarray(_trapezoid_time(*x, ramps=2.0)), (
                "{name} adds the two ramps' times 2 v_max/a_max to D/v_max: but the ramps also cover "
                "distance, so the cruise at v_max covers less than D and lasts less than D/v_max."
            )),
            (lambda x: np.asarray(x[0] / x[1]), (
                "{name} ignores the acceleration limit (T = D/v_max): the joint cannot jump to v_max."
            )),
        ]),
        dg.degrees(),
        alternatives("triangle_time", [
            (lambda x: np.asarray(_trapezoid_time(*x, triangle_factor=1.0)), (
                "{name}'s triangle is too short: it speeds up at a_max over D/2 and brakes over the "
                "other D/2, each half from rest (or to rest)."
            )),
            (lambda x: np.asarray(_trapezoid_time(*x, triangle_factor=2.0 * math.sqrt(2.0))), (
                "{name}'s triangle is too long: it speeds up at a_max over D/2 and brakes over the "
                "other D/2, each half from rest (or to rest)."
            )),
        ]),
    ]


trapezoid_time = exercise(_CHAPTER, "trapezoid_time", Check(
    name="trapezoid_time",
    reference=lambda x: np.asarray(_trapezoid_time(*x)),
    variables=_TRAPEZOID,
    diagnoses=_trapezoid_mistakes(),
    noun="moves",
    hint="Accelerate at a_max, cruise at v_max, decelerate at a_max; when the distance is too short to "
         "reach v_max, accelerate to the middle and decelerate at once.",
    doc="Check trapezoid_time(distance, v_max, a_max) -> the minimum rest-to-rest time (s) of one joint.",
))


# ------------------------------------------------------------------ the later steps, judged alone



# ------------------------------------------------------------------ the least duration of a move
#: a move of four joints: start angles, steps to the end (joint 3 at rest), speed and acceleration
#: limits; the limits' ranges put some joints on the triangle and some on the trapezoid
_MOVE = ([Variable(f"q_start_{i}", "other", -2.0, 2.0) for i in range(1, 5)]
         + [Variable(f"step_{i}", "other", -3.0, 3.0) for i in range(1, 5)]
         + [Variable(f"v_max_{i}", "other", 0.3, 2.5) for i in range(1, 5)]
         + [Variable(f"a_max_{i}", "other", 0.5, 5.0) for i in range(1, 5)])


def _move(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(q_start, q_end, v_max, a_max) of the sample ``x``: joint 3 stays at rest."""
    x = np.asarray(x, dtype=float)
    step = x[4:8] * [1.0, 1.0, 0.0, 1.0]
    return x[:4].copy(), x[:4] + step, x[8:12].copy(), x[12:16].copy()


def _joint_times(x: np.ndarray, swapped: bool = False) -> np.ndarray:
    start, end, v_max, a_max = _move(x)
    if swapped:
        v_max, a_max = a_max, v_max
    return np.array([_trapezoid_time(abs(e - s), v, a) for s, e, v, a in zip(start, end, v_max, a_max)])


def _moving_min(times: np.ndarray) -> float:
    return float(np.min(times[times > 0]))


least_duration = exercise(_CHAPTER, "least_duration", LaterStepCheck(
    name="least_duration",
    steps=lambda: {"trapezoid_time": reference_trapezoid_time},
    reference=lambda x: np.asarray(np.max(_joint_times(x))),
    variables=_MOVE,
    diagnoses=[
        alternatives("fastest_joint", [
            (lambda x: np.asarray(_moving_min(_joint_times(x))), (
                "{name} is the fastest moving joint's time: the slowest joint sets the duration "
                "(every other joint can slow down, none can go faster)."
            )),
            (lambda x: np.asarray(np.min(_joint_times(x))), (
                "{name} is 0 for every move here, in each of which one joint stays at rest: the "
                "shortest of the joints' times, or no duration at all? The slowest joint sets the "
                "duration (every other joint can slow down, none can go faster)."
            )),
        ]),
        alternatives("swapped_limits", [(lambda x: np.asarray(np.max(_joint_times(x, swapped=True))), (
            "{name} swaps v_max and a_max."
        ))]),
        alternatives("sum", [(lambda x: np.asarray(np.sum(_joint_times(x))), (
            "{name} is the sum of the joints' times: the joints move at the same time, so the motion "
            "lasts as long as the slowest joint's."
        ))]),
    ],
    noun="moves",
    arguments=_move,
    signature="least_duration(q_start, q_end, v_max, a_max) -> T (s, a float)",
    describe=lambda x: "least_duration({})".format(", ".join(
        f"{name} = {fmt(value)}" for name, value in zip(("q_start", "q_end", "v_max", "a_max"), _move(x)))),
    hint="Each joint alone needs its trapezoid time; all of them must arrive together.",
    doc="Check least_duration(q_start, q_end, v_max, a_max) -> the least duration (s) of a synchronised "
        "rest-to-rest move of n joints within their speed and acceleration limits.",
))


# ------------------------------------------------------------------ synchronised motion
def _profiles(t: np.ndarray, start: np.ndarray, end: np.ndarray, accel: np.ndarray, cruise: np.ndarray,
              duration: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Trapezoids (ramps at ``accel``, cruise speed ``cruise``, own ``duration`` each), at t (N,)."""
    tt = np.asarray(t, dtype=float)[:, None]
    direction = np.sign(end - start)
    distance = np.abs(end - start)
    with np.errstate(all="ignore"):
        ramp = np.where(accel > 0, cruise / np.where(accel > 0, accel, 1.0), 0.0)
    time = np.clip(tt, 0.0, duration)
    to_end = duration - time
    rising, falling = time < ramp, time > duration - ramp
    travelled = np.where(rising, 0.5 * accel * time**2,
                         np.where(falling, distance - 0.5 * accel * to_end**2, cruise * (time - 0.5 * ramp)))
    speed = np.where(rising, accel * time, np.where(falling, accel * to_end, cruise))
    acceleration = np.where(rising, accel, np.where(falling, -accel, 0.0))
    moving = (tt > 0.0) & (tt < duration)
    return (start + direction * travelled, np.where(moving, direction * speed, 0.0),
            np.where(moving, direction * acceleration, 0.0))


def _cruise_for(duration: Any, distance: np.ndarray, accel: np.ndarray) -> np.ndarray:
    discriminant = np.maximum(accel * accel * duration * duration - 4.0 * accel * distance, 0.0)
    return 0.5 * (accel * duration - np.sqrt(discriminant))


def _motion(t, start, end, v_max, a_max, mistake: str = "") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The synchronised trapezoids (written out, not robokin's), or a typical mistake of them."""
    distance = np.abs(end - start)
    if mistake == "swapped_limits":
        v_max, a_max = a_max, v_max
    times = np.array([_trapezoid_time(d, v, a, triangle=mistake != "triangular_missed")
                      for d, v, a in zip(distance, v_max, a_max)])
    if mistake == "unsynchronised":
        cruise = np.array([min(v, math.sqrt(d * a)) for d, v, a in zip(distance, v_max, a_max)])
        return _profiles(t, start, end, a_max, cruise, times)
    moving = times > 0
    duration = float(np.max(times)) if mistake != "fastest_joint" else float(np.min(times[moving]))
    if mistake == "same_shape":
        # every joint's profile the slowest joint's shape, stretched: v_i, a_i scaled by D_i / D_slow
        slow = int(np.argmax(times))
        cruise_slow = min(v_max[slow], math.sqrt(distance[slow] * a_max[slow]))
        ratio = distance / distance[slow]
        return _profiles(t, start, end, a_max[slow] * ratio, cruise_slow * ratio, np.full_like(distance, duration))
    cruise = _cruise_for(duration, distance, a_max)
    return _profiles(t, start, end, a_max, cruise, np.full_like(distance, duration))


_MOTION_MISTAKES = {
    "fastest_joint": ("{name} gives every joint the fastest joint's time (from the least_duration it "
                      "calls, or its own): in that time a slower joint arrives only beyond its limits (it "
                      "cruises above v_max, or its ramps at a_max cover less than its distance). The "
                      "slowest joint sets the duration T = max_i T_i."),
    "unsynchronised": ("in {name} every joint moves in its own minimum time, so the joints arrive one "
                       "after the other: plan every joint again with the common duration T = max_i T_i."),
    "swapped_limits": "{name} swaps v_max and a_max.",
    "triangular_missed": ("{name} takes the duration T_i = D_i/v_max + v_max/a_max also for a joint that "
                          "never reaches v_max (a negative cruise time; check the trapezoid_time its "
                          "duration comes from): that joint's triangle is faster."),
    "same_shape": ("{name} stretches the slowest joint's profile for every joint (v_i and a_i scaled "
                   "by D_i/D_slow): synchronised, but the task keeps each joint's own acceleration "
                   "a_max,i and lowers its cruise speed."),
}


def _cases() -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    """The moves the check tries: random ones, one with a joint at rest, one with both profile kinds."""
    rng = np.random.default_rng(10)
    cases = []
    for n in (2, 3, 6, 6):
        start = rng.uniform(-2.0, 2.0, n)
        end = start + rng.uniform(-2.0, 2.0, n)
        cases.append((start, end, rng.uniform(0.5, 2.0, n), rng.uniform(1.0, 6.0, n)))
    start = np.array([0.2, -0.4, 1.0])
    cases.append((start, start + [0.9, 0.0, -0.3], np.array([1.2, 1.0, 0.8]), np.array([3.0, 2.0, 5.0])))
    # the slowest joint a triangle (0.2 < 1.5²/2)
    cases.append((np.zeros(2), np.array([0.2, -0.05]), np.array([1.5, 1.5]), np.array([2.0, 4.0])))
    # two more, forwards and backwards: at a triangle the slowest joint's cruise speed solves
    # a quadratic with a zero discriminant, which rounding may make negative (sqrt: NaN)
    cases.append((np.zeros(3), np.array([0.35, -0.1, 0.2]), np.array([1.5, 1.5, 2.0]),
                  np.array([2.5, 4.0, 6.0])))
    cases.append((np.array([0.5, -1.0]), np.array([0.6, -2.1]), np.array([2.0, 1.5]), np.array([3.0, 1.7])))
    return cases


class _MotionCheck(FunctionCheck):
    """Check ``synchronised_motion(t, q_start, q_end, v_max, a_max)`` against the synchronised trapezoids."""

    def judge(self, answer: Callable[..., Any]) -> CheckResult:
        answer = with_reference_steps(answer, {"least_duration": reference_least_duration})
        cases = _cases()
        n = len(cases)
        rng = np.random.default_rng(3)
        for k, (start, end, v_max, a_max) in enumerate(cases):
            duration = max(_trapezoid_time(abs(e - s), v, a) for s, e, v, a in zip(start, end, v_max, a_max))
            t = np.concatenate([[0.0], np.sort(rng.uniform(0.0, duration, 40)), [duration]])
            ref = _motion(t, start, end, v_max, a_max)
            where = (f"(move {k + 1}: q_start = {fmt(start)}, q_end = {fmt(end)}, v_max = {fmt(v_max)}, "
                     f"a_max = {fmt(a_max)})")
            out = self.call(answer, (t.copy(), start.copy(), end.copy(), v_max.copy(), a_max.copy()), where, n)
            got = self._arrays(out, len(t), len(start))
            if isinstance(got, str):
                return self.failure("shape", got, n)
            inner = slice(1, -1)    # accelerations jump at the ends: compared inside
            if self._same(got, ref, inner):
                continue
            explains = partial(self._explains, got, ref, (t, start, end, v_max, a_max))
            diagnosed = self.diagnose(((code, f"{message} {where}") for code, message in _MOTION_MISTAKES.items()),
                                      explains, n)
            if diagnosed is not None:
                return diagnosed
            return self.failure("mismatch", self._describe(t, got, ref, start, end, v_max, a_max, duration)
                                + " " + where, n)
        return self.success(f"{self.name} is correct (checked on {n} moves).", n)

    def _explains(self, got: tuple, ref: tuple, case: tuple, code: str) -> bool:
        """The mistake ``code`` on the move ``case`` = (t, q_start, q_end, v_max, a_max) gives ``got``."""
        inner = slice(1, -1)
        t, start, end, v_max, a_max = case
        wrong = _motion(t, start, end, v_max, a_max, mistake=code)
        return not self._same(wrong, ref, inner) and self._same(got, wrong, inner)

    @staticmethod
    def _same(a, b, inner) -> bool:
        return (np.allclose(a[0], b[0], atol=1e-7) and np.allclose(a[1], b[1], atol=1e-7)
                and np.allclose(a[2][inner], b[2][inner], atol=1e-6))

    def _arrays(self, out: Any, rows: int, n: int) -> tuple[np.ndarray, ...] | str:
        if not isinstance(out, (tuple, list)) or len(out) != 3:
            return (f"{self.name} should return three arrays (positions, velocities, accelerations); "
                    f"got {type(out).__name__}" + (f" of length {len(out)}." if isinstance(out, (tuple, list))
                                                   else "."))
        arrays = []
        for what, value in zip(("positions", "velocities", "accelerations"), out):
            try:
                array = np.asarray(value, dtype=float)
            except (TypeError, ValueError):
                return f"the {what} of {self.name} are not numbers."
            if array.shape != (rows, n):
                return (f"the {what} of {self.name} should have shape (len(t), n) = ({rows}, {n}); "
                        f"got {array.shape}.")
            if not np.all(np.isfinite(array)):
                return (f"the {what} of {self.name} contain NaN or infinite values: a joint that does not move "
                        "(0/0), or the slowest joint at a triangle, where the cruise speed's discriminant "
                        "is zero and rounding can make it negative (a square root of it).")
            arrays.append(array)
        return tuple(arrays)

    def _describe(self, t, got, ref, start, end, v_max, a_max, duration) -> str:
        return self._what_differs(t, got, ref, start, end, v_max, a_max, duration) + self._triangle_note(
            got, ref, start, end, v_max, a_max)

    @staticmethod
    def _triangle_note(got, ref, start, end, v_max, a_max) -> str:
        """A note when the slowest joint, wrong here, never reaches its speed limit."""
        distances = np.abs(end - start)
        times = [_trapezoid_time(d, v, a) for d, v, a in zip(distances, v_max, a_max)]
        slowest = int(np.argmax(times))
        triangle = distances[slowest] * a_max[slowest] < v_max[slowest] ** 2
        wrong = not (np.allclose(got[0][:, slowest], ref[0][:, slowest], atol=1e-7)
                     and np.allclose(got[1][:, slowest], ref[1][:, slowest], atol=1e-7))
        if not (triangle and wrong):
            return ""
        return (f" Joint {slowest + 1}, the slowest, never reaches its speed limit here (a triangle): its "
                "peak speed is √(D a_max), where the quadratic for the cruise speed has a zero "
                "discriminant, which rounding can make negative (its square root is then NaN).")

    def _what_differs(self, t, got, ref, start, end, v_max, a_max, duration) -> str:
        positions, velocities, accelerations = got
        if not np.allclose(positions[0], start, atol=1e-7):
            return f"{self.name} does not start at q_start: at t = 0 the positions are {fmt(positions[0])}."
        if not np.allclose(positions[-1], end, atol=1e-7):
            return (f"{self.name} does not arrive at q_end at T = {duration:.4g} s (the slowest joint's "
                    f"minimum time): the positions there are {fmt(positions[-1])}.")
        if not (np.allclose(velocities[0], 0, atol=1e-7) and np.allclose(velocities[-1], 0, atol=1e-7)):
            return f"{self.name} does not rest at t = 0 and t = T: the velocities there must be zero."
        if np.any(np.abs(velocities) > v_max * (1 + 1e-9) + 1e-9):
            return f"{self.name} exceeds a joint's speed limit v_max."
        if np.any(np.abs(accelerations[1:-1]) > a_max * (1 + 1e-9) + 1e-9):
            return f"{self.name} exceeds a joint's acceleration limit a_max."
        k = int(np.argmax(np.abs(got[0] - ref[0]).max(axis=1) + np.abs(got[1] - ref[1]).max(axis=1)))
        return (f"{self.name} differs from the synchronised trapezoids at t = {t[k]:.4g} s: positions "
                f"{fmt(got[0][k])}, expected {fmt(ref[0][k])}; velocities {fmt(got[1][k])}, expected "
                f"{fmt(ref[1][k])}. Every joint keeps its a_max,i and cruises at the speed that makes it "
                "arrive at T.")


synchronised_motion = exercise(_CHAPTER, "synchronised_motion", _MotionCheck(
    name="synchronised_motion",
    signature="synchronised_motion(t, q_start, q_end, v_max, a_max)",
    doc=("Check synchronised_motion(t, q_start, q_end, v_max, a_max) -> (positions, velocities, "
         "accelerations), each (len(t), n): synchronised minimum-time trapezoids."),
))


# ------------------------------------------------------------------ via points
def _via_velocities(points: np.ndarray, durations: np.ndarray, mistake: str = "") -> np.ndarray:
    """Velocities (m + 1, n) at the via points by the chapter's rule, or a typical mistake of it."""
    if mistake == "durations_reversed":
        durations = durations[::-1]
    steps = np.diff(points, axis=0)
    slopes = steps if mistake == "differences" else steps / durations[:, None]
    velocities = np.zeros_like(points)
    before, after = slopes[:-1], slopes[1:]
    if mistake == "no_sign_rule":
        velocities[1:-1] = 0.5 * (before + after)
    elif mistake == "central_difference":
        velocities[1:-1] = (points[2:] - points[:-2]) / (durations[:-1] + durations[1:])[:, None]
    elif mistake != "stop_at_via":
        velocities[1:-1] = np.where(before * after > 0, 0.5 * (before + after), 0.0)
    if mistake == "ends_moving":
        velocities[0], velocities[-1] = slopes[0], slopes[-1]
    return velocities


def _via_coefficients(points: np.ndarray, durations: np.ndarray, mistake: str = "") -> np.ndarray:
    """Coefficients (m, 4, n) [a0, a1, a2, a3] of q = Σ a_i σ^i, σ = t − t_k in s, or a mistake."""
    velocities = _via_velocities(points, durations, mistake)
    out = np.empty((len(durations), 4, points.shape[1]))
    for k, duration in enumerate(durations):
        step = points[k + 1] - points[k]
        start, end = velocities[k], velocities[k + 1]
        if mistake == "segment_slope":          # each segment's own slope at both of its ends
            start = end = step / duration
        if mistake == "normalised_time":        # coefficients in τ = σ / T_k
            start, end, duration, step = start * duration, end * duration, 1.0, step
        out[k] = [points[k], start, (3 * step / duration - 2 * start - end) / duration,
                  (-2 * step / duration + start + end) / duration**2]
    if mistake == "reversed_order":
        out = out[:, ::-1]
    return out


_VIA_MISTAKES = {
    "segment_slope": ("{name} gives each segment its own slope (q_k+1 − q_k)/T_k at both of its ends: straight "
                      "lines whose velocity jumps at every via point, and the ends are not at rest. Use one "
                      "velocity per via point, the same for the segment that ends there and the one that starts."),
    "no_sign_rule": ("the velocity of {name} at a via point where the joint turns back is the mean of the two "
                     "slopes: by the rule it is 0 where the slopes do not have the same sign (else the joint "
                     "overshoots the via point)."),
    "central_difference": ("the velocity of {name} at via point k is the chord's slope (q_k+1 − q_k−1)/(T_k−1 + "
                           "T_k): the rule takes the mean of the two slopes, ½(v_k + v_k+1), or 0 where their "
                           "signs differ."),
    "stop_at_via": ("{name} stops at every via point (a rest-to-rest cubic per segment): the interior velocities "
                    "follow the rule, ½(v_k + v_k+1) where the two slopes have the same sign."),
    "ends_moving": ("{name} does not start and end at rest: the velocity at the first and the last via point "
                    "must be 0, not the adjacent segment's slope."),
    "differences": ("the slopes of {name} are the position differences q_k − q_k−1 without dividing by the "
                    "durations: v_k = (q_k − q_k−1)/T_k−1 (rad/s)."),
    "durations_reversed": ("{name} uses the durations in reverse order: segment k, from q_k to q_k+1, lasts "
                           "durations[k]."),
    "normalised_time": ("the coefficients of {name} are for the normalised time τ = (t − t_k)/T_k: the task asks "
                        "for them in the time since the segment's start in seconds, σ = t − t_k in [0, T_k] "
                        "(a_k1 = q̇_k, a_k2 and a_k3 divided by T_k and T_k²)."),
    "reversed_order": ("{name} gives the coefficients highest power first (np.polyval's order): row i must be "
                       "a_i, the coefficient of σ^i (a_0 = q_k first)."),
}


def _via_cases() -> list[tuple[np.ndarray, np.ndarray]]:
    """Via points (m + 1, n) and durations (m,): random ones, a turn back and a pause in one joint."""
    rng = np.random.default_rng(12)
    cases = []
    for m, n in ((2, 1), (4, 2), (5, 3), (3, 6)):
        cases.append((rng.uniform(-2.0, 2.0, (m + 1, n)), rng.uniform(0.4, 2.5, m)))
    # joint 1 turns back at via point 2, joint 2 pauses (a zero slope), joint 3 climbs throughout
    points = np.array([[0.0, 0.5, -1.0], [0.8, 0.9, -0.6], [1.1, 0.9, 0.1], [0.4, 1.5, 0.3], [0.2, 1.0, 1.2]])
    cases.append((points, np.array([0.7, 1.6, 1.1, 0.5])))
    return cases


def _polynomial(coefficients: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """Value and derivative (n,) of the cubics with rows a0..a3 (4, n) at σ."""
    a0, a1, a2, a3 = coefficients
    return a0 + sigma * (a1 + sigma * (a2 + sigma * a3)), a1 + sigma * (2 * a2 + 3 * sigma * a3)


def _explains_via(got: np.ndarray, reference: np.ndarray, points: np.ndarray, durations: np.ndarray,
                  code: str) -> bool:
    """The mistake ``code`` gives the coefficients ``got`` (and not the reference's)."""
    wrong = _via_coefficients(points, durations, code)
    return not np.allclose(wrong, reference, atol=1e-8) and np.allclose(got, wrong, atol=1e-8)


class _ViaCheck(FunctionCheck):
    """Check ``via_point_cubics(points, durations)`` against the rule's cubics on cases of its own."""

    def judge(self, answer: Callable[..., Any]) -> CheckResult:
        cases = _via_cases()
        n_cases = len(cases)
        for k, (points, durations) in enumerate(cases):
            rows = ", ".join(fmt(row) for row in points)     # one line: the message quotes it inline
            where = f"(case {k + 1}: points = [{rows}], durations = {fmt(durations)})"
            with np.errstate(all="ignore"):
                raw = self.call(answer, (points.copy(), durations.copy()), where, n_cases)
            got = self.call(np.asarray, (raw, float), where, n_cases)
            m, n = len(durations), points.shape[1]
            if got.shape != (m, 4, n):
                return self.failure("shape", f"{self.name} should return the coefficients of shape (m, 4, n) = "
                                    f"({m}, 4, {n}) for {m + 1} via points of {n} joints; got {got.shape} {where}.",
                                    n_cases)
            if not np.all(np.isfinite(got)):
                return self.failure("nan", f"the coefficients of {self.name} contain NaN or infinite values "
                                    f"{where}.", n_cases)
            reference = _via_coefficients(points, durations)
            if np.allclose(got, reference, atol=1e-8):
                continue
            diagnosed = self.diagnose(((code, f"{message} {where}") for code, message in _VIA_MISTAKES.items()),
                                      partial(_explains_via, got, reference, points, durations), n_cases)
            if diagnosed is not None:
                return diagnosed
            return self.failure("mismatch", f"{self._describe(got, reference, points, durations)} {where}", n_cases)
        return self.success(f"{self.name} is correct (checked on {n_cases} sets of via points, a turn back and a "
                            "pause included).", n_cases)

    def _describe(self, got: np.ndarray, reference: np.ndarray, points: np.ndarray, durations: np.ndarray) -> str:
        """The first property the cubics break: a via point missed, ends moving, a velocity jump, a value."""
        ends = [_polynomial(got[k], 0.0) + _polynomial(got[k], float(T)) for k, T in enumerate(durations)]
        for k, (start, _, end, _) in enumerate(ends):
            if not np.allclose(start, points[k], atol=1e-8):
                return (f"segment {k} of {self.name} does not start at via point {k}: q = {fmt(start)} at σ = 0, "
                        f"expected {fmt(points[k])}.")
            if not np.allclose(end, points[k + 1], atol=1e-8):
                return (f"segment {k} of {self.name} misses via point {k + 1}: q = {fmt(end)} at σ = T_{k}, "
                        f"expected {fmt(points[k + 1])}.")
        if not (np.allclose(ends[0][1], 0.0, atol=1e-8) and np.allclose(ends[-1][3], 0.0, atol=1e-8)):
            return f"{self.name} does not start and end at rest: the velocity at the first and last via point is 0."
        for k in range(1, len(durations)):
            if not np.allclose(ends[k - 1][3], ends[k][1], atol=1e-8):
                return (f"the velocity of {self.name} jumps at via point {k}: {fmt(ends[k - 1][3])} at the end of "
                        f"segment {k - 1}, {fmt(ends[k][1])} at the start of segment {k}. Give both segments the "
                        "same velocity there.")
        expected = reference[:, 1]
        k = int(np.argmax(np.abs(got[:, 1] - expected).max(axis=1) > 1e-8))
        return (f"the velocity of {self.name} at via point {k} is {fmt(got[k, 1])}, expected {fmt(expected[k])} by "
                "the rule: ½(v_k + v_k+1) where the slopes v_k = (q_k − q_k−1)/T_k−1 and v_k+1 have the same "
                "sign, else 0.")


via_point_cubics = exercise(_CHAPTER, "via_point_cubics", _ViaCheck(
    name="via_point_cubics",
    signature="via_point_cubics(points, durations) -> coefficients (m, 4, n)",
    doc=("Check via_point_cubics(points, durations) -> coefficients (m, 4, n): per segment k and joint j the "
         "cubic a0 + a1 σ + a2 σ² + a3 σ³ in σ = t − t_k (s), through the via points with the velocities of "
         "the rule (mean of adjacent slopes, 0 where their signs differ, at rest at both ends)."),
))


# ------------------------------------------------------------------ slerp
def _unit(q: np.ndarray) -> np.ndarray:
    return q / np.linalg.norm(q)


def _slerp(q0: np.ndarray, q1: np.ndarray, s: float, *, flip: bool = True, linear: bool = False,
           angle_factor: float = 1.0) -> np.ndarray:
    """Slerp written out (the sign flip, the angle by atan2, a series near 0) or a typical mistake."""
    if flip and q0 @ q1 < 0:
        q1 = -q1
    if linear:
        return _unit((1 - s) * q0 + s * q1)
    omega = 2.0 * math.atan2(np.linalg.norm(q0 - q1), np.linalg.norm(q0 + q1)) * angle_factor
    if abs(math.sin(omega)) < 1e-9:
        return _unit((1 - s) * q0 + s * q1)
    return (math.sin((1 - s) * omega) * q0 + math.sin(s * omega) * q1) / math.sin(omega)


def _euler_interpolation(q0: np.ndarray, q1: np.ndarray, s: float) -> np.ndarray:
    """The mistake of interpolating roll, pitch and yaw linearly, as a quaternion."""
    from robokin.transforms import (
        quaternion_from_rotation,
        rotation_from_quaternion,
        rotation_from_rpy,
        rpy_from_rotation,
    )

    a = np.asarray(rpy_from_rotation(rotation_from_quaternion(q0)), dtype=float)
    b = np.asarray(rpy_from_rotation(rotation_from_quaternion(q1)), dtype=float)
    return quaternion_from_rotation(rotation_from_rpy(*((1 - s) * a + s * b)))


def _slerp_cases() -> list[tuple[np.ndarray, np.ndarray, float]]:
    """Pairs of unit quaternions and parameters: generic, q0·q1 < 0, equal, nearly equal (1e-10 rad)."""
    rng = np.random.default_rng(7)
    cases = []
    for k in range(12):
        q0, q1 = _unit(rng.normal(size=4)), _unit(rng.normal(size=4))
        if (k % 2 == 0) == (q0 @ q1 > 0):    # every other pair the long way in its raw signs
            q1 = -q1
        cases.append((q0, q1, float(rng.uniform(0.05, 0.95))))
    exact = np.array([0.5, 0.5, -0.5, 0.5])     # q·q = 1 exactly: arccos(1) = 0, sin 0 = 0
    cases.append((exact, exact.copy(), 0.4))
    q0 = _unit(rng.normal(size=4))
    tiny = np.array([math.cos(5e-11), math.sin(5e-11), 0.0, 0.0])     # a turn of 1e-10 rad about x
    w0, v0 = q0[0], q0[1:]
    w1, v1 = tiny[0], tiny[1:]
    near = np.concatenate([[w0 * w1 - v0 @ v1], w0 * v1 + w1 * v0 + np.cross(v0, v1)])
    cases.append((q0, near, 0.7))
    cases.append((q0, -near, 0.3))
    return cases


_SLERP_MISTAKES: list[tuple[str, Callable[..., np.ndarray], str]] = [
    ("long_way", lambda q0, q1, s: _slerp(q0, q1, s, flip=False), (
        "{name} goes the long way round when q0·q1 < 0: q1 and −q1 are the same rotation; flip q1 "
        "when q0·q1 < 0 so that the rotation turns by the smaller angle (≤ π).")),
    ("nlerp", lambda q0, q1, s: _slerp(q0, q1, s, linear=True), (
        "{name} normalises the straight-line interpolation (1 − s) q0 + s q1: the right rotations at the "
        "ends, but not at a constant angular rate in between: on the great circle the angle from q0 "
        "grows in proportion to s, and the weights a(s), b(s) follow from that.")),
    ("lerp", lambda q0, q1, s: (1 - s) * q0 + s * (q1 if q0 @ q1 >= 0 else -q1), (
        "{name} returns (1 − s) q0 + s q1, which is not a unit quaternion: interpolate on the sphere "
        "(slerp).")),
    ("rotation_angle", lambda q0, q1, s: _slerp(q0, q1, s, angle_factor=2.0), (
        "{name} uses the rotation angle θ as Ω: the angle between the quaternions q0 and q1 (as vectors "
        "in 4D) is Ω = θ/2, cos Ω = q0·q1.")),
    ("euler_angles", lambda q0, q1, s: _euler_interpolation(q0, q1, s), (
        "{name} interpolates roll, pitch and yaw one by one: the axis of the rotation then moves "
        "during the motion, and an angle that wraps at ±π turns the long way. Interpolate the "
        "quaternions on the sphere (slerp).")),
    ("reversed", lambda q0, q1, s: _slerp(q1, q0, s), (
        "{name} runs from q1 to q0: at s = 0 it must give q0.")),
]


def _same_rotation(a: np.ndarray, b: np.ndarray, tol: float = 1e-8) -> bool:
    """Two quaternions (4,) of the same rotation: equal, or opposite."""
    return a.shape == b.shape == (4,) and bool(min(np.abs(a - b).max(), np.abs(a + b).max()) < tol)


def _explains_slerp(got: np.ndarray, reference: np.ndarray, case: tuple[np.ndarray, np.ndarray, float],
                    code: str) -> bool:
    """The mistake ``code`` of slerp gives the rotation ``got`` (and not the reference's)."""
    with np.errstate(all="ignore"):
        mistaken = np.asarray(_SLERP_WRONG[code](*case), dtype=float)
    return (bool(np.all(np.isfinite(mistaken))) and not _same_rotation(mistaken, reference)
            and _same_rotation(got, mistaken))


_SLERP_WRONG = {code: wrong for code, wrong, _ in _SLERP_MISTAKES}


class _SlerpCheck(FunctionCheck):
    """Check ``slerp(q0, q1, s)`` on generic, opposite-sign, equal and nearly equal pairs."""

    def judge(self, answer: Callable[..., Any]) -> CheckResult:
        cases = _slerp_cases()
        n = len(cases)
        for k, (q0, q1, s) in enumerate(cases):
            where = f"(at q0 = {fmt(q0)}, q1 = {fmt(q1)}, s = {s:.3g})"
            with np.errstate(all="ignore"):
                raw = self.call(answer, (q0.copy(), q1.copy(), s), where, n)
            got = self.call(np.asarray, (raw, float), where, n).reshape(-1)
            if got.shape != (4,):
                return self.failure("shape", f"{self.name} should return a quaternion (w, x, y, z) of shape (4,); "
                                    f"got {got.size} numbers {where}.", n)
            if not np.all(np.isfinite(got)):
                near = (" for (nearly) equal rotations: sin Ω ≈ 0 there; what do the weights tend to as "
                        "Ω → 0?") if k >= 12 else ""
                return self.failure("nan", f"{self.name} gives NaN or infinite values{near} {where}.", n)
            reference = _slerp(q0, q1, s)
            if _same_rotation(got, reference):
                continue
            diagnosed = self.diagnose(((code, f"{message} {where}") for code, _, message in _SLERP_MISTAKES),
                                      partial(_explains_slerp, got, reference, (q0, q1, s)), n)
            if diagnosed is not None:
                return diagnosed
            if abs(np.linalg.norm(got) - 1.0) > 1e-8:
                return self.failure("not_unit", f"{self.name} returns a quaternion of norm "
                                    f"{np.linalg.norm(got):.6g}, not 1 {where}.", n)
            return self.failure("mismatch", f"{self.name} = {fmt(got)}, expected {fmt(reference)} (or its "
                                f"negative) {where}.", n)
        return self.success(f"{self.name} is correct (checked at {n} pairs of rotations, the nearly equal ones "
                            "included).", n)


slerp = exercise(_CHAPTER, "slerp", _SlerpCheck(
    name="slerp",
    signature="slerp(q0, q1, s) -> (4,)",
    doc=("Check slerp(q0, q1, s) -> unit quaternion (4,): the short way, at a constant rate, also for equal "
         "and nearly equal rotations (a quaternion or its negative accepted)."),
))


# ------------------------------------------------------------------ the straight line
def _line_case(seed: int):
    """A short straight line of the UR10's flange: start configuration, its pose, the end pose."""
    from robokin.models import ur10
    from robokin.transforms import rotation_exp

    rng = np.random.default_rng(seed)
    robot = ur10()
    q0 = np.deg2rad([75.0, -60.0, 60.0, -130.0, -90.0, 45.0]) + rng.uniform(-0.3, 0.3, 6)
    start = robot.fk(q0)
    end = start.copy()
    end[:3, :3] = rotation_exp(rng.uniform(-0.5, 0.5, 3)) @ start[:3, :3]
    end[:3, 3] += rng.uniform(-0.15, 0.15, 3)
    return robot, q0, start, end


def _line_reference(t: float, start: np.ndarray, end: np.ndarray, duration: float, *,
                    mistake: str = "") -> tuple[np.ndarray, np.ndarray]:
    """Pose and twist [v; ω] (base frame) of the slerped straight line, written out, or a mistake."""
    from robokin.transforms import rotation_exp, rotation_log

    law = "linear" if mistake == "linear_law" else "quintic"
    s, ds, _ = (float(v) for v in _law(np.asarray(min(max(t / duration, 0.0), 1.0)), law))
    ds /= duration
    w = rotation_log(start[:3, :3].T @ end[:3, :3])        # in the start frame, |w| <= π
    pose = np.eye(4)
    pose[:3, :3] = start[:3, :3] @ rotation_exp(s * w)
    pose[:3, 3] = start[:3, 3] + s * (end[:3, 3] - start[:3, 3])
    omega = start[:3, :3] @ w * ds
    if mistake == "body_frame":
        omega = w * ds
    elif mistake == "not_scaled":
        omega = start[:3, :3] @ w / duration
    return pose, np.concatenate([(end[:3, 3] - start[:3, 3]) * ds, omega])


_LINE_MISTAKES = {
    "body_frame": ("the angular velocity of {name} is in the start (tool) frame: the twist is in the base "
                   "frame, as the twist [v; ω] of the conventions."),
    "not_scaled": ("the angular velocity of {name} is constant, θ h/T: the orientation follows s(t), so "
                   "ω changes with ṡ(t), zero at both ends."),
    "linear_law": ("{name} uses s = t/T: the line must use the quintic law (rest at both ends)."),
}


def _pose_and_twist(out: Any) -> tuple[np.ndarray, np.ndarray]:
    """The two parts of what line_reference returns, as float arrays (raises as unpacking does)."""
    pose, twist = (np.asarray(x, dtype=float) for x in out)
    return pose, twist


def _explains_line(pose: np.ndarray, twist: np.ndarray, case: tuple[float, np.ndarray, np.ndarray, float],
                   code: str) -> bool:
    """The mistake ``code`` of the line gives ``pose`` and ``twist``."""
    wrong_pose, wrong_twist = _line_reference(*case, mistake=code)
    return np.allclose(pose, wrong_pose, atol=1e-8) and np.allclose(twist, wrong_twist, atol=1e-8)


class _LineCheck(FunctionCheck):
    """Check ``line_reference(t, T_start, T_end, duration)`` on lines of its own."""

    def judge(self, answer: Callable[..., Any]) -> CheckResult:
        answer = with_reference_steps(answer, {"quintic_scaling": reference_quintic_scaling,
                                                "slerp": reference_slerp})
        n = 3
        for seed in range(n):
            _, _, start, end = _line_case(seed)
            duration = 1.5 + seed
            for t in (0.0, 0.23 * duration, 0.61 * duration, duration):
                where = f"(at t = {t:.3g} s of a line of {duration:.3g} s)"
                out = self.call(answer, (t, start.copy(), end.copy(), duration), where, n)
                pose, twist = self.call(_pose_and_twist, (out,), where, n)
                if pose.shape != (4, 4) or twist.shape != (6,):
                    return self.failure("shape", f"{self.name} should return a pose (4, 4) and a twist (6,); got "
                                        f"{pose.shape} and {twist.shape} {where}.", n)
                ref_pose, ref_twist = _line_reference(t, start, end, duration)
                if np.allclose(pose, ref_pose, atol=1e-8) and np.allclose(twist, ref_twist, atol=1e-8):
                    continue
                diagnosed = self.diagnose(((code, f"{message} {where}") for code, message in _LINE_MISTAKES.items()),
                                          partial(_explains_line, pose, twist, (t, start, end, duration)), n)
                if diagnosed is not None:
                    return diagnosed
                part = "pose" if not np.allclose(pose, ref_pose, atol=1e-8) else "twist"
                expected = ref_pose if part == "pose" else ref_twist
                got = pose if part == "pose" else twist
                return self.failure("mismatch", f"the {part} of {self.name} is not correct {where}: expected "
                                    f"{fmt(expected)}, got {fmt(got)}.", n)
        return self.success(f"{self.name} is correct (checked on {n} lines of its own).", n)


line_reference = exercise(_CHAPTER, "line_reference", _LineCheck(
    name="line_reference",
    signature="(t, T_start, T_end, duration) -> (pose, twist)",
    doc=("Check line_reference(t, T_start, T_end, duration) -> (pose (4, 4), twist (6,)): the straight line "
         "with the slerped orientation and the quintic law."),
))


def _track_reference(robot, q0, poses, twists, ts, gain, mistake: str = "") -> np.ndarray:
    """The resolved-rate loop with Euler steps, written out, or one of its typical mistakes."""
    from robokin.transforms import rotation_log

    q = np.array(q0, dtype=float)
    out = []
    for pose, twist in zip(poses, twists):
        if mistake != "recorded_after":
            out.append(q)
        now = robot.fk(q)
        error = np.concatenate([pose[:3, 3] - now[:3, 3], rotation_log(pose[:3, :3] @ now[:3, :3].T)])
        if mistake == "error_sign":
            error = -error
        elif mistake == "orientation_error":
            error[3:] = rotation_log(now[:3, :3] @ pose[:3, :3].T)
        feedforward = 0.0 if mistake == "no_feedforward" else twist
        q = q + ts * np.linalg.solve(robot.jacobian(q), feedforward + gain * error)
        if mistake == "recorded_after":
            out.append(q)
    return np.array(out)


_TRACK_MISTAKES = {
    "no_feedforward": ("{name} leaves out the feed-forward twist ν_k: without it the tool lags behind the "
                       "moving reference. q̇ = J⁻¹(ν_k + K e_k)."),
    "error_sign": ("{name} uses the error with the wrong sign (actual − desired): the loop then pushes the "
                   "tool away from the reference. e = [p_k − p(q); log(R_k R(q)ᵀ)]."),
    "orientation_error": ("the orientation error of {name} is log(R(q) R_kᵀ), the wrong direction: it is "
                          "the rotation vector of R_k R(q)ᵀ (from the tool's orientation to the desired "
                          "one, in the base frame)."),
    "recorded_after": ("{name} records q after the step: row k must be the configuration at sample k "
                       "(row 0 = q0), before the command of that sample is applied."),
}


def _explains_track(got: np.ndarray, case: tuple, code: str) -> bool:
    """The mistake ``code`` of the loop, run on ``case`` = (robot, q0, poses, twists, ts, gain), gives ``got``."""
    robot, q0, poses, twists, ts, gain = case
    wrong = _track_reference(robot, q0, poses, twists, ts, gain, mistake=code)
    return bool(np.all(np.isfinite(wrong))) and np.allclose(got, wrong, atol=1e-8)


class _TrackCheck(FunctionCheck):
    """Check ``track(q0, poses, twists, ts, gain)`` against the resolved-rate loop on lines of its own."""

    def judge(self, answer: Callable[..., Any]) -> CheckResult:
        from robokin.motion import pose_trajectory

        n = 3
        for seed, (ts, gain) in enumerate([(0.01, 20.0), (0.02, 10.0), (0.005, 40.0)]):
            robot, q0, start, end = _line_case(seed + 10)
            times = ts * np.arange(25)
            line = pose_trajectory(times, start, end, 0.2 + 24 * ts)
            poses, twists = line.poses, line.twists
            # start 1 cm and a little turned away from the line, so that the gain matters
            q_start = q0 + np.array([0.01, -0.01, 0.01, 0.02, -0.02, 0.02])
            where = f"(a line of its own, ts = {ts:g} s, gain = {gain:g} 1/s)"
            out = self.call(answer, (q_start.copy(), poses.copy(), twists.copy(), ts, gain), where, n)
            got = self.call(np.asarray, (out, float), where, n)
            if got.shape != (len(times), 6):
                return self.failure("shape", f"{self.name} should return the joint angles at the {len(times)} "
                                    f"samples, shape ({len(times)}, 6); got {got.shape} {where}.", n)
            reference = _track_reference(robot, q_start, poses, twists, ts, gain)
            if np.allclose(got, reference, atol=1e-8):
                continue
            diagnosed = self.diagnose(((code, f"{message} {where}") for code, message in _TRACK_MISTAKES.items()),
                                      partial(_explains_track, got, (robot, q_start, poses, twists, ts, gain)), n)
            if diagnosed is not None:
                return diagnosed
            if not np.allclose(got[0], q_start, atol=1e-12):
                return self.failure("start", f"row 0 of what {self.name} returns must be q0 {where}.", n)
            k = int(np.argmax(np.abs(got - reference).max(axis=1) > 1e-8))
            return self.failure("mismatch", f"{self.name} differs from the resolved-rate loop at sample {k} "
                                f"{where}: expected {fmt(reference[k])}, got {fmt(got[k])}.", n)
        return self.success(f"{self.name} is correct (checked on {n} lines of its own).", n)


track = exercise(_CHAPTER, "track", _TrackCheck(
    name="track",
    signature="track(q0, poses, twists, ts, gain)",
    doc=("Check track(q0, poses, twists, ts, gain) -> joint angles (N, 6): resolved rates with feed-forward "
         "and Euler steps on the UR10."),
))


# ------------------------------------------------------------------ the tests' stand-ins
# The graded tests of the tasks that build on earlier ones pass these to the student's later
# functions in place of the student's own earlier steps (their default arguments), so that a
# mistake in one step costs the points of that step's own test only.
def _reference_scaling(t: Any, T: Any, law: str) -> np.ndarray:
    t, T = as_scalar(t, "t"), check_positive(T, "T", scalar=True)
    with np.errstate(all="ignore"):
        tau = t / T
        s, ds, dds = _law(np.clip(np.asarray(tau), 0.0, 1.0), law)
        inside = 0.0 <= tau <= 1.0   # at rest before and after
        rates = np.array([s, ds / T if inside else 0.0, dds / (T * T) if inside else 0.0], dtype=float)
    return check_result_finite(rates, f"the {law} law's rates", t=t, T=T)


def reference_cubic_scaling(t: float, T: float) -> np.ndarray:
    """robokin's answer to ``cubic_scaling`` of Task 1 (the tests' stand-in).

    Parameters
    ----------
    t : float
        A time (s); outside [0, T] the law is at rest (s = 0 before, 1 after).
    T : float
        The duration (s), positive.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ``[s, ṡ, s̈]`` of the cubic rest-to-rest law at ``t`` (1, 1/s, 1/s²).
    """
    return _reference_scaling(t, T, "cubic")


def reference_quintic_scaling(t: float, T: float) -> np.ndarray:
    """robokin's answer to ``quintic_scaling`` of Task 1 (the tests' stand-in).

    The graded tests of Task 6 pass it to the student's ``line_reference`` in place of the
    student's own.

    Parameters
    ----------
    t : float
        A time (s); outside [0, T] the law is at rest (s = 0 before, 1 after).
    T : float
        The duration (s), positive.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ``[s, ṡ, s̈]`` of the quintic rest-to-rest law at ``t`` (1, 1/s, 1/s²).
    """
    return _reference_scaling(t, T, "quintic")


def reference_trapezoid_time(distance: float, v_max: float, a_max: float) -> float:
    """robokin's answer to ``trapezoid_time`` of Task 2 (the tests' stand-in).

    The graded tests of Task 3 pass it to the student's ``least_duration`` in place of the
    student's own.

    Parameters
    ----------
    distance : float
        The distance (rad), at least 0.
    v_max, a_max : float
        The speed (rad/s) and acceleration (rad/s²) limits, positive.

    Returns
    -------
    float
        The minimum rest-to-rest time (s) of one joint within the two limits.
    """
    return float(_trapezoid_time(check_positive(distance, "distance", allow_zero=True, scalar=True),
                                 check_positive(v_max, "v_max", scalar=True),
                                 check_positive(a_max, "a_max", scalar=True)))


def reference_least_duration(q_start: Any, q_end: Any, v_max: Any, a_max: Any) -> float:
    """robokin's answer to ``least_duration`` of Task 3 (the tests' stand-in).

    The graded tests of ``synchronised_motion`` pass it in place of the student's own.

    Parameters
    ----------
    q_start, q_end : array_like, shape (n,)
        The start and end configurations (rad).
    v_max, a_max : array_like, shape (n,)
        The joints' speed (rad/s) and acceleration (rad/s²) limits, positive.

    Returns
    -------
    float
        The least duration (s) of the synchronised rest-to-rest move of the n joints within
        their limits.
    """
    arrays = {name: as_float_array(value, name) for name, value in
              (("q_start", q_start), ("q_end", q_end), ("v_max", v_max), ("a_max", a_max))}
    shapes = {name: array.shape for name, array in arrays.items()}
    if len(set(shapes.values())) != 1 or len(shapes["q_start"]) != 1:
        raise ShapeError("q_start, q_end, v_max and a_max must be vectors of one shape (n,); got "
                         + ", ".join(f"{name} {shape}" for name, shape in shapes.items()))
    start, end = arrays["q_start"], arrays["q_end"]
    v_limit, a_limit = check_positive(arrays["v_max"], "v_max"), check_positive(arrays["a_max"], "a_max")
    with np.errstate(all="ignore"):
        times = [float(_trapezoid_time(abs(e - s), v, a)) for s, e, v, a in zip(start, end, v_limit, a_limit)]
    return float(check_result_finite(max(times, default=0.0), "the least duration", **arrays))


def reference_slerp(q0: Any, q1: Any, s: float) -> np.ndarray:
    """robokin's answer to ``slerp`` of Task 5 (the tests' stand-in).

    The graded tests of Task 6 pass it to the student's ``line_reference`` in place of the
    student's own.

    Parameters
    ----------
    q0, q1 : array_like, shape (4,)
        Unit quaternions (w, x, y, z) (others are normalised).
    s : float
        The fraction of the way, in [0, 1].

    Returns
    -------
    numpy.ndarray, shape (4,)
        The unit quaternion of the tool's rotation at ``s``, turning at a constant rate about
        a fixed axis by the smaller angle.
    """
    a, b, s = as_vector(q0, 4, "q0"), as_vector(q1, 4, "q1"), as_scalar(s, "s")
    if min(np.abs(a).max(), np.abs(b).max()) == 0.0:
        raise DomainError("q0 and q1 must be quaternions of a rotation, not zero")
    a, b = (_unit(q / np.abs(q).max()) for q in (a, b))   # scaled first: no overflow
    if a @ b < 0.0:
        b = -b   # the same rotation, the short way round
    omega = 2.0 * math.atan2(np.linalg.norm(a - b), np.linalg.norm(a + b))
    with np.errstate(all="ignore"):
        if omega < 1e-9:
            q = (1.0 - s) * a + s * b
            q = q / np.linalg.norm(q)
        else:
            q = (np.sin((1.0 - s) * omega) * a + np.sin(s * omega) * b) / np.sin(omega)
    return check_result_finite(q, "the slerp", s=s)
