"""Tests of the chapter-10 exercise checks (robokin.check.trajectories).

The correct answers are written here independently of the check module: the timing laws
from their closed forms, the trapezoid's time from the peak speed min(v_max, √(D a_max)),
the synchronised motion by integrating its piecewise-constant acceleration numerically, and
the via-point cubics from each segment's 4 × 4 linear system, slerp as q0 (q0* q1)^s through
the axis and angle of the relative rotation. The check's own references are compared with
robokin's ``time_law``, ``joint_trajectory``, ``via_point_trajectory`` and ``quaternion_slerp``.
"""

from __future__ import annotations

import importlib
import math
import re
from functools import partial

import numpy as np
import pytest

from robokin.motion import joint_trajectory, joint_trajectory_duration, time_law, via_point_trajectory
from robokin.transforms import quaternion_slerp

chk = importlib.import_module("robokin.check.trajectories")


# ---------------------------------------------------------------- answers written by hand
def cubic_by_hand(t, T):
    tau = t / T
    return np.array([3 * tau**2 - 2 * tau**3, 6 * tau * (1 - tau) / T, (6 - 12 * tau) / T**2])


def quintic_by_hand(t, T):
    tau = t / T
    return np.array([tau**3 * (10 - 15 * tau + 6 * tau**2), 30 * tau**2 * (1 - tau) ** 2 / T,
                     60 * tau * (1 - tau) * (1 - 2 * tau) / T**2])


def trapezoid_by_hand(distance, v_max, a_max):
    if distance == 0:
        return 0.0
    peak = min(v_max, math.sqrt(distance * a_max))
    return distance / peak + peak / a_max


def motion_by_integration(t, q_start, q_end, v_max, a_max):
    """Each joint's acceleration a_i on [0, t_a], 0, −a_i on [T − t_a, T], integrated exactly."""
    q_start, q_end = np.asarray(q_start, float), np.asarray(q_end, float)
    T = max(trapezoid_by_hand(abs(b - a), v, acc) for a, b, v, acc in zip(q_start, q_end, v_max, a_max))
    out_q, out_v, out_a = [], [], []
    for a, b, acc in zip(q_start, q_end, a_max):
        D, sign = abs(b - a), np.sign(b - a)
        # t_a from D = a t_a (T − t_a): the smaller root
        t_a = 0.5 * (T - math.sqrt(max(T * T - 4 * D / acc, 0.0)))
        knots = np.array([0.0, t_a, T - t_a, T])
        accel = np.array([acc, 0.0, -acc])
        v_knot = np.concatenate([[0.0], np.cumsum(accel * np.diff(knots))])
        q_knot = np.concatenate([[0.0], np.cumsum(v_knot[:-1] * np.diff(knots)
                                                  + 0.5 * accel * np.diff(knots) ** 2)])
        k = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, 2)
        dt = t - knots[k]
        out_q.append(a + sign * (q_knot[k] + v_knot[k] * dt + 0.5 * accel[k] * dt**2))
        out_v.append(sign * (v_knot[k] + accel[k] * dt))
        out_a.append(sign * accel[k])
    return np.column_stack(out_q), np.column_stack(out_v), np.column_stack(out_a)


def _multiply(p, q):
    return np.concatenate([[p[0] * q[0] - p[1:] @ q[1:]], p[0] * q[1:] + q[0] * p[1:] + np.cross(p[1:], q[1:])])


def slerp_by_power(q0, q1, s):
    q0, q1 = np.asarray(q0, float), np.asarray(q1, float)
    rel = _multiply(q0 * [1, -1, -1, -1], q1)
    if rel[0] < 0:
        rel = -rel
    half = math.atan2(np.linalg.norm(rel[1:]), rel[0])
    if half == 0.0:
        return q0.copy()
    axis = rel[1:] / np.linalg.norm(rel[1:])
    return _multiply(q0, np.concatenate([[math.cos(s * half)], math.sin(s * half) * axis]))


# ---------------------------------------------------------------- references
@pytest.mark.parametrize("law", ["cubic", "quintic"])
def test_timing_references_are_robokin_time_law(law):
    tau = np.linspace(0.0, 1.0, 11)
    mine = chk._law(tau, law)
    for a, b in zip(mine, time_law(tau, law)):
        assert np.allclose(a, b, atol=1e-12)


def test_peak_factors_are_the_laws_maxima():
    tau = np.linspace(0.0, 1.0, 200001)
    for row, law in zip(chk._PEAKS, ("cubic", "quintic")):
        _, ds, dds = time_law(tau, law)
        assert np.isclose(row[0], ds.max(), rtol=1e-9) and np.isclose(row[1], np.abs(dds).max(), rtol=1e-8)


def test_trapezoid_and_motion_references_are_robokins():
    rng = np.random.default_rng(2)
    for D, v, a in rng.uniform([0.01, 0.2, 0.3], [4.0, 3.0, 8.0], (50, 3)):
        assert np.isclose(chk._trapezoid_time(D, v, a), joint_trajectory_duration([0.0], [D], v_max=v, a_max=a))
    for start, end, v_max, a_max in chk._cases():
        T = joint_trajectory_duration(start, end, v_max=v_max, a_max=a_max)
        t = np.linspace(0.0, T, 37)[1:-1]
        mine = chk._motion(t, start, end, v_max, a_max)
        theirs = joint_trajectory(t, start, end, v_max=v_max, a_max=a_max)
        for x, y in zip(mine, theirs):
            assert np.allclose(x, y, atol=1e-12)


def test_slerp_reference_is_robokins_up_to_sign():
    for q0, q1, s in chk._slerp_cases():
        mine, theirs = chk._slerp(q0, q1, s), quaternion_slerp(q0, q1, s)
        assert min(np.abs(mine - theirs).max(), np.abs(mine + theirs).max()) < 1e-12


def test_least_duration_reference_is_robokins():
    for x in chk.least_duration.sample_points():
        start, end, v_max, a_max = chk._move(x)
        expected = joint_trajectory_duration(start, end, v_max=v_max, a_max=a_max)
        assert np.isclose(float(chk.least_duration.reference(x)), expected, rtol=1e-12)
    assert all(start[2] == end[2] for start, end, _, _ in map(chk._move, chk.least_duration.sample_points()))


def test_cases_cover_both_profiles_and_a_joint_at_rest():
    X = chk.trapezoid_time.sample_points()
    triangle = X[:, 0] < X[:, 1] ** 2 / X[:, 2]
    assert 3 <= triangle.sum() <= 17
    cases = chk._cases()
    assert any(np.any(start == end) for start, end, _, _ in cases)
    slowest_triangle = [np.max([chk._trapezoid_time(abs(e - s), v, a) for s, e, v, a in zip(*c)]) for c in cases]
    assert len(slowest_triangle) == len(cases)


# ---------------------------------------------------------------- correct answers
def test_correct_answers_pass(capsys):
    for check, answer in ((chk.cubic_scaling, cubic_by_hand), (chk.quintic_scaling, quintic_by_hand),
                          (chk.trapezoid_time, trapezoid_by_hand), (chk.synchronised_motion, motion_by_integration),
                          (chk.slerp, slerp_by_power)):
        result = check(answer, quiet=True)
        assert result.passed and result.diagnosis is None, result.message
    assert chk.peak_factors(np.array([[1.5, 6.0], [1.875, 10 / math.sqrt(3)]]), quiet=True).passed
    chk.least_duration(least_duration_by_hand)
    assert capsys.readouterr().out == "✔ least_duration is correct (checked at 20 random moves).\n"


def test_slerp_accepts_the_negative_quaternion():
    assert chk.slerp(lambda q0, q1, s: -slerp_by_power(q0, q1, s), quiet=True).passed


# ---------------------------------------------------------------- diagnosed mistakes
WRONG_SCALING = {
    "tau_derivatives": lambda t, T: cubic_by_hand(t, T) * [1, T, T * T],
    "other_law": quintic_by_hand,
    "no_rest": lambda t, T: np.array([t / T, 1 / T, 0.0]),
}


@pytest.mark.parametrize("code", list(WRONG_SCALING))
def test_scaling_mistakes_are_diagnosed(code):
    result = chk.cubic_scaling(WRONG_SCALING[code], quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


WRONG_TRAPEZOID = {
    "triangular_missed": lambda D, v, a: D / v + v / a,
    "swapped_limits": lambda D, v, a: trapezoid_by_hand(D, a, v),
    "threshold": lambda D, v, a: D / v + v / a if D >= v * v / (2 * a) else 2 * math.sqrt(D / a),
    "ramps_added": lambda D, v, a: D / v + 2 * v / a if D >= v * v / a else 2 * math.sqrt(D / a),
    "triangle_time": lambda D, v, a: D / v + v / a if D >= v * v / a else math.sqrt(D / a),
}


@pytest.mark.parametrize("code", list(WRONG_TRAPEZOID))
def test_trapezoid_mistakes_are_diagnosed(code):
    result = chk.trapezoid_time(WRONG_TRAPEZOID[code], quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_trapezoid_unknown_mistake_names_a_move():
    result = chk.trapezoid_time(lambda D, v, a: 1.1 * trapezoid_by_hand(D, v, a), quiet=True)
    assert result.diagnosis == "mismatch" and "distance =" in result.message and "expected" in result.message


@pytest.mark.parametrize("code", list(chk._MOTION_MISTAKES))
def test_motion_mistakes_are_diagnosed(code):
    def wrong(t, q_start, q_end, v_max, a_max):
        return chk._motion(np.asarray(t), np.asarray(q_start), np.asarray(q_end), np.asarray(v_max),
                           np.asarray(a_max), mistake=code)

    result = chk.synchronised_motion(wrong, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


@pytest.mark.parametrize("answer, phrase", [
    (lambda *args: 3, "three arrays"),
    (lambda t, *args: (np.zeros(3), np.zeros(3), np.zeros(3)), "shape"),
    (lambda *args: 1 / 0, "ZeroDivisionError"),
    ("not a function", "Python function"),
])
def test_motion_bad_answers_are_explained(answer, phrase):
    result = chk.synchronised_motion(answer, quiet=True)
    assert not result.passed and phrase in result.message


def test_motion_late_arrival_is_described():
    def slow(t, q_start, q_end, v_max, a_max):
        q, v, a = motion_by_integration(np.asarray(t) * 0.9, q_start, q_end, v_max, a_max)
        return q, v, a

    result = chk.synchronised_motion(slow, quiet=True)
    assert result.diagnosis == "mismatch" and "does not arrive at q_end" in result.message


def test_motion_with_an_unguarded_root_is_named_at_a_triangle():
    # the cruise speed as the root (a T - sqrt((a T)^2 - 4 a D)) / 2: right wherever the
    # discriminant stays >= 0, NaN where the slowest joint is a triangle and it rounds below 0
    def unguarded(t, q_start, q_end, v_max, a_max):
        t, q_start, q_end = (np.asarray(x, dtype=float) for x in (t, q_start, q_end))
        distances = np.abs(q_end - q_start)
        T = max(trapezoid_by_hand(d, v, a) for d, v, a in zip(distances, v_max, a_max))
        with np.errstate(invalid="ignore"):
            speeds = (a_max * T - np.sqrt((a_max * T) ** 2 - 4 * a_max * distances)) / 2
            scale = np.where(distances > 0, speeds / np.where(distances > 0, distances, 1.0), 0.0)
        reference = motion_by_integration(t, q_start, q_end, v_max, a_max)
        broken = ~np.isfinite(scale)
        return tuple(np.where(broken, np.nan, x) for x in reference)

    assert chk.synchronised_motion(
        lambda t, *args: motion_by_integration(np.asarray(t), *args), quiet=True).passed
    result = chk.synchronised_motion(unguarded, quiet=True)
    assert not result.passed
    assert "triangle" in result.message and ("NaN" in result.message or "square root" in result.message)


@pytest.mark.parametrize("code", [code for code, _, _ in chk._SLERP_MISTAKES])
def test_slerp_mistakes_are_diagnosed(code):
    wrong = dict((c, f) for c, f, _ in chk._SLERP_MISTAKES)[code]
    result = chk.slerp(wrong, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_slerp_nan_for_equal_rotations():
    def arccos_slerp(q0, q1, s):
        q1 = q1 if q0 @ q1 >= 0 else -q1
        omega = np.arccos(np.clip(q0 @ q1, -1, 1))
        return (np.sin((1 - s) * omega) * q0 + np.sin(s * omega) * q1) / np.sin(omega)

    result = chk.slerp(arccos_slerp, quiet=True)
    assert result.diagnosis == "nan" and "nearly" in result.message


PEAKS = np.array([[1.5, 6.0], [1.875, 10 / math.sqrt(3)]])


def peaks_with(row, column, value):
    wrong = PEAKS.copy()
    wrong[row, column] = value
    return wrong


@pytest.mark.parametrize("answer, code, words", [
    (PEAKS[:, ::-1], "columns_swapped", "columns swapped"),
    (PEAKS[::-1], "rows_swapped", "rows swapped"),
    # the quintic's acceleration at τ = 1/2, where the speed peaks: 60 τ(1 − τ)(1 − 2τ) = 0
    (peaks_with(1, 1, 0.0), "quintic_acceleration", "τ = 1/2"),
    # the cubic's acceleration at τ = 1/2: 6 − 12τ = 0
    (peaks_with(0, 1, 0.0), "acceleration_at_middle", "the ends"),
    # the signed acceleration where each law brakes: −6 at τ = 1; −10/√3 at τ = 1/2 + √3/6
    (peaks_with(0, 1, -6.0), "acceleration_sign", "brakes (τ = 1)"),
    (peaks_with(1, 1, -10 / math.sqrt(3)), "acceleration_sign", "largest size"),
    # the quintic's acceleration at τ = 1/4: 60 · (1/4)(3/4)(1/2)
    (peaks_with(1, 1, 5.625), "acceleration_at_quarter", "τ = 1/4"),
    # the velocity factor of the other law, in either row
    (peaks_with(0, 0, 1.875), "speed_other_law", "quintic law's speed factor"),
    (peaks_with(1, 0, 1.5), "speed_other_law", "cubic law's speed factor"),
    (peaks_with(0, 1, 10 / math.sqrt(3)), "acceleration_other_law", "quintic law's acceleration"),
    # the mean speed D/T in both rows: both entries named
    (np.array([[1.0, 6.0], [1.0, 10 / math.sqrt(3)]]), "mean_speed", "(2, 1)"),
    # the peaks of the student's own laws at T = 2 s: ṡ = c_v/T, s̈ = c_a/T²
    (PEAKS * [1 / 2, 1 / 4], "scaled", "T = 2 s"),
    # ... and of a move of D = 3 in T = 0.5 s
    (PEAKS * [3 / 0.5, 3 / 0.25], "scaled", "D = 3 in T = 0.5 s"),
])
def test_peak_factor_mistakes_are_diagnosed(answer, code, words):
    result = chk.peak_factors(answer, quiet=True)
    assert result.diagnosis == code and words in result.message


@pytest.mark.parametrize("answer, where", [
    (np.array([[1.0, 2.0], [3.0, 4.0]]), "the cubic's c_v (entry (1, 1)), the cubic's c_a (entry (1, 2)), "
     "the quintic's c_v (entry (2, 1)), the quintic's c_a (entry (2, 2)) differ"),   # no entry right
    (peaks_with(0, 0, 1.6), "the cubic's c_v (entry (1, 1)) differs"),   # one wrong, no typical value
    # one entry explained, the other not
    (np.array([[1.0, 6.0], [1.7, 10 / math.sqrt(3)]]), "(entry (1, 1)), the quintic's c_v (entry (2, 1)) differ"),
])
def test_peak_factors_without_a_typical_mistake_say_where(answer, where):
    """They name the factors that differ, not the values they should have (the answer)."""
    result = chk.peak_factors(answer, quiet=True)
    assert result.diagnosis == "mismatch" and where in result.message, result.message
    assert "should be" not in result.message and "1.875" not in result.message
    assert result.message.endswith(chk.peak_factors.hint)


def test_peak_factors_of_other_forms():
    assert chk.peak_factors(PEAKS.tolist(), quiet=True).passed
    assert chk.peak_factors(PEAKS * (1 + 1e-8), quiet=True).passed
    assert chk.peak_factors(PEAKS[0], quiet=True).diagnosis == "shape"


def least_duration_by_hand(q_start, q_end, v_max, a_max, pick=max, swapped=False):
    """The slowest joint's trapezoid time (``pick=max``); other ``pick`` and ``swapped``: mistakes."""
    if swapped:
        v_max, a_max = a_max, v_max
    return pick(trapezoid_by_hand(abs(e - s), v, a) for s, e, v, a in zip(q_start, q_end, v_max, a_max))


def test_least_duration_mistakes_are_diagnosed():
    def fastest_moving(times):
        return min(t for t in times if t > 0)

    for answer, code in [
        (partial(least_duration_by_hand, pick=fastest_moving), "fastest_joint"),
        (partial(least_duration_by_hand, pick=min), "fastest_joint"),
        (partial(least_duration_by_hand, pick=sum), "sum"),
        (partial(least_duration_by_hand, swapped=True), "swapped_limits"),
        (lambda *move: 1.0, "mismatch"),
    ]:
        assert chk.least_duration(answer, quiet=True).diagnosis == code


def test_least_duration_of_zero_says_what_it_is():
    """A function that returns 0 is the shortest time when a joint is at rest (every move of the
    check has one): the message says it is 0 for every move, not only that it picks the shortest."""
    message = chk.least_duration(lambda *move, trapezoid_time=None: 0.0, quiet=True).message
    assert "is 0 for every move here" in message and "slowest joint sets the duration" in message, message


def test_scaling_messages_name_the_rates_and_the_call():
    """A wrong law's message names s, ṡ, s̈ (not bracketed indices a student reads as Python's) and
    the time t and duration T it was called with (not the normalised τ it never sees)."""
    def only_s(t, T):
        tau = t / T
        return np.array([3 * tau**2 - 2 * tau**3, 0.0, 0.0])

    message = chk.cubic_scaling(only_s, quiet=True).message
    assert "ṡ (entry 1), s̈ (entry 2) differ" in message, message
    assert re.search(r"at t = [-\d.]+ s, T = [\d.]+ s: ṡ \(entry 1\) should be", message), message
    assert "tau =" not in message and "[2]" not in message, message


@pytest.mark.parametrize("check_name", ["cubic_scaling", "quintic_scaling", "trapezoid_time",
                                        "synchronised_motion", "slerp", "peak_factors", "least_duration"])
@pytest.mark.parametrize("answer", [None, "text", 3.0, np.zeros((2, 2)), lambda *args: None])
def test_any_answer_gets_a_result(check_name, answer):
    result = getattr(chk, check_name)(answer, quiet=True)
    assert isinstance(result.message, str) and result.message


# ---------------------------------------------------------------- the straight line and the loop
def line_by_exponential(t, T_start, T_end, duration):
    """R0 exp([w] s) and the twist [ṡ (p1 − p0); ṡ R0 w], with the quintic written here."""
    from robokin.transforms import rotation_exp, rotation_log

    s, sd, _ = quintic_by_hand(t, duration)
    w = rotation_log(T_start[:3, :3].T @ T_end[:3, :3])
    pose = np.eye(4)
    pose[:3, :3] = T_start[:3, :3] @ rotation_exp(s * w)
    pose[:3, 3] = T_start[:3, 3] + s * (T_end[:3, 3] - T_start[:3, 3])
    return pose, np.concatenate([sd * (T_end[:3, 3] - T_start[:3, 3]), sd * T_start[:3, :3] @ w])


def test_line_reference_is_pose_trajectory():
    from robokin.motion import pose_trajectory

    _, _, start, end = chk._line_case(4)
    for t in (0.0, 0.4, 1.1, 2.0):
        pose, twist = chk._line_reference(t, start, end, 2.0)
        theirs = pose_trajectory(t, start, end, 2.0, law="quintic")
        assert np.allclose(pose, theirs.poses, atol=1e-12) and np.allclose(twist, theirs.twists, atol=1e-12)


def test_line_reference_twist_is_the_derivative_of_the_pose():
    from robokin.transforms import rotation_log

    _, _, start, end = chk._line_case(5)
    h = 1e-6
    for t in (0.3, 0.8, 1.7):
        _, twist = chk._line_reference(t, start, end, 2.0)
        before, _ = chk._line_reference(t - h, start, end, 2.0)
        after, _ = chk._line_reference(t + h, start, end, 2.0)
        assert np.allclose((after[:3, 3] - before[:3, 3]) / (2 * h), twist[:3], atol=1e-7)
        assert np.allclose(rotation_log(after[:3, :3] @ before[:3, :3].T) / (2 * h), twist[3:], atol=1e-7)


def track_by_pinv(q0, poses, twists, ts, gain):
    from robokin.models import ur10
    from robokin.transforms import rotation_log

    robot, rows = ur10(), [np.array(q0, dtype=float)]
    for pose, twist in zip(poses[:-1], twists[:-1]):
        now = robot.fk(rows[-1])
        error = np.concatenate([pose[:3, 3] - now[:3, 3], rotation_log(pose[:3, :3] @ now[:3, :3].T)])
        rows.append(rows[-1] + ts * np.linalg.pinv(robot.jacobian(rows[-1])) @ (twist + gain * error))
    return np.array(rows)


def test_line_and_track_correct_answers_pass():
    assert chk.line_reference(line_by_exponential, quiet=True).passed
    assert chk.track(track_by_pinv, quiet=True).passed


@pytest.mark.parametrize("code", list(chk._LINE_MISTAKES))
def test_line_mistakes_are_diagnosed(code):
    result = chk.line_reference(lambda t, a, b, d: chk._line_reference(t, a, b, d, mistake=code), quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


@pytest.mark.parametrize("code", list(chk._TRACK_MISTAKES))
def test_track_mistakes_are_diagnosed(code):
    from robokin.models import ur10

    robot = ur10()
    result = chk.track(lambda *args: chk._track_reference(robot, *args, mistake=code), quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_track_wrong_shape_and_start_are_explained():
    assert chk.track(lambda q0, poses, *rest: np.zeros((3, 6)), quiet=True).diagnosis == "shape"
    result = chk.track(lambda q0, poses, *rest: np.tile(np.asarray(q0) + 1, (len(poses), 1)), quiet=True)
    assert result.diagnosis == "start"


@pytest.mark.parametrize("answer", [None, "text", 3.0, lambda *args: None])
def test_line_and_track_any_answer_gets_a_result(answer):
    for check in (chk.line_reference, chk.track):
        result = check(answer, quiet=True)
        assert not result.passed and result.message


# ---------------------------------------------------------------- via points
def via_by_linear_system(points, durations):
    """Each segment's cubic from the 4 × 4 system of its end conditions, the rule's velocities in a loop."""
    points, durations = np.asarray(points, float), np.asarray(durations, float)
    m, n = len(durations), points.shape[1]
    velocities = np.zeros((m + 1, n))
    for k in range(1, m):
        for j in range(n):
            before = (points[k, j] - points[k - 1, j]) / durations[k - 1]
            after = (points[k + 1, j] - points[k, j]) / durations[k]
            velocities[k, j] = 0.5 * (before + after) if before * after > 0 else 0.0
    out = np.empty((m, 4, n))
    for k, T in enumerate(durations):
        system = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [1, T, T * T, T**3], [0, 1, 2 * T, 3 * T * T]])
        out[k] = np.linalg.solve(system, np.stack([points[k], velocities[k], points[k + 1], velocities[k + 1]]))
    return out


def _evaluate(coefficients, durations, t):
    """Positions and velocities (N, n) of the piecewise cubics at the times t (N,)."""
    knots = np.concatenate([[0.0], np.cumsum(durations)])
    k = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, len(durations) - 1)
    sigma = (t - knots[k])[:, None]
    a = coefficients[k]
    return (a[:, 0] + sigma * (a[:, 1] + sigma * (a[:, 2] + sigma * a[:, 3])),
            a[:, 1] + sigma * (2 * a[:, 2] + 3 * sigma * a[:, 3]))


@pytest.mark.parametrize("case", range(len(chk._via_cases())))
def test_via_reference_is_robokins_via_point_trajectory(case):
    points, durations = chk._via_cases()[case]
    coefficients = chk._via_coefficients(points, durations)
    assert np.allclose(coefficients, via_by_linear_system(points, durations), atol=1e-12)
    t = np.linspace(0.0, durations.sum(), 97)
    knots = np.concatenate([[0.0], np.cumsum(durations)])
    positions, velocities = _evaluate(coefficients, durations, t)
    padded = np.zeros((len(points), 3 * ((points.shape[1] + 2) // 3)))   # robokin's takes 3 columns
    padded[:, :points.shape[1]] = points
    for first in range(0, padded.shape[1], 3):
        theirs = via_point_trajectory(t, padded[:, first:first + 3], knots)
        n = min(3, points.shape[1] - first)
        assert np.allclose(positions[:, first:first + n], theirs.positions[:, :n])
        assert np.allclose(velocities[:, first:first + n], theirs.velocities[:, :n])


def test_via_cases_have_a_turn_back_and_a_pause():
    points, durations = chk._via_cases()[-1]
    slopes = np.diff(points, axis=0) / durations[:, None]
    products = slopes[:-1] * slopes[1:]
    assert np.any(products < 0) and np.any(products == 0) and np.any(products > 0)


def test_via_correct_answer_passes():
    result = chk.via_point_cubics(via_by_linear_system, quiet=True)
    assert result.passed and result.diagnosis is None, result.message


@pytest.mark.parametrize("code", list(chk._VIA_MISTAKES))
def test_via_mistakes_are_diagnosed(code):
    def wrong(points, durations):
        return chk._via_coefficients(np.asarray(points, float), np.asarray(durations, float), code)

    result = chk.via_point_cubics(wrong, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def _cubics(points, durations, starts, ends):
    """Cubics (m, 4, n) through the via points with the velocities starts[k], ends[k] of segment k."""
    out = np.empty((len(durations), 4, points.shape[1]))
    for k, T in enumerate(durations):
        step = points[k + 1] - points[k]
        out[k] = [points[k], starts[k], (3 * step / T - 2 * starts[k] - ends[k]) / T,
                  (-2 * step / T + starts[k] + ends[k]) / T**2]
    return out


def _with_velocities(change_start, change_end):
    def answer(points, durations):
        points, durations = np.asarray(points, float), np.asarray(durations, float)
        v = chk._via_velocities(points, durations)
        return _cubics(points, durations, change_start(v[:-1].copy()), change_end(v[1:].copy()))
    return answer


def _bump(rows, amount):
    def change(v):
        v[rows] += amount
        return v
    return change


@pytest.mark.parametrize("answer, phrase", [
    (lambda p, d: via_by_linear_system(p, d) + np.array([0.0, 0.0, 0.0, 0.01])[:, None], "misses via point 1"),
    (lambda p, d: via_by_linear_system(p, d) + np.array([0.01, 0.0, 0.0, 0.0])[:, None],
     "does not start at via point 0"),
    (_with_velocities(_bump(1, 0.1), lambda v: v), "jumps at via point 1"),
    (_with_velocities(_bump(0, 0.1), lambda v: v), "does not start and end at rest"),
    (_with_velocities(_bump(slice(1, None), 0.1), _bump(slice(None, -1), 0.1)), "at via point 1 is"),
    (lambda p, d: via_by_linear_system(p, d)[:, :3], "shape"),
    (lambda p, d: 1 / 0, "ZeroDivisionError"),
    ("not a function", "Python function"),
])
def test_via_bad_answers_are_explained(answer, phrase):
    result = chk.via_point_cubics(answer, quiet=True)
    assert not result.passed and phrase in result.message, result.message
    # the case's via points are quoted on one line, row by row
    if "(case " in result.message:
        assert "\n" not in result.message and "points = [[" in result.message, result.message


@pytest.mark.parametrize("answer", [None, "text", 3.0, np.zeros((2, 2)), lambda *args: None,
                                    lambda p, d: np.full((len(d), 4, np.shape(p)[1]), np.nan)])
def test_via_any_answer_gets_a_result(answer):
    result = chk.via_point_cubics(answer, quiet=True)
    assert not result.passed and isinstance(result.message, str) and result.message


# ---------------------------------------------------------------- the refusals of FunctionCheck
@pytest.mark.parametrize("check_name", ["synchronised_motion", "via_point_cubics", "slerp", "line_reference",
                                        "track"])
def test_function_checks_refuse_and_report_as_every_chapter(check_name):
    from robokin.check._core import FunctionCheck

    check = getattr(chk, check_name)
    assert isinstance(check, FunctionCheck) and check.name == check_name and (check.__doc__ or "").startswith("Check ")
    none = check(None, quiet=True)
    assert (none.diagnosis, none.message) == ("error", f"✘ {check_name} is None: did you forget to define it?")
    text = check("text", quiet=True)
    assert (text.diagnosis, text.message) == (
        "constant", f"✘ {check_name} should be a Python function {check.signature}; got str.")
    raised = check(lambda *args: 1 / 0, quiet=True)
    assert raised.diagnosis == "error" and raised.message.startswith(f"✘ calling {check_name} (")
    assert raised.message.endswith(") raised ZeroDivisionError: division by zero"), raised.message


# ---------------------------------------------------------------- the tests' stand-ins
def test_references_pass_their_checks():
    assert chk.cubic_scaling(chk.reference_cubic_scaling, quiet=True).passed
    assert chk.quintic_scaling(chk.reference_quintic_scaling, quiet=True).passed
    assert chk.trapezoid_time(chk.reference_trapezoid_time, quiet=True).passed
    assert chk.least_duration(chk.reference_least_duration, quiet=True).passed
    assert chk.slerp(chk.reference_slerp, quiet=True).passed


def test_references_agree_with_robokin_and_the_hand_written_answers():
    rng = np.random.default_rng(5)
    for _ in range(20):
        t, T = rng.uniform(0.0, 1.0) * 2.5, 2.5
        assert np.allclose(chk.reference_cubic_scaling(t, T), cubic_by_hand(t, T), atol=1e-12)
        assert np.allclose(chk.reference_quintic_scaling(t, T), quintic_by_hand(t, T), atol=1e-12)
        D, v, a = rng.uniform([0.0, 0.2, 0.3], [3.0, 2.5, 6.0])
        assert math.isclose(chk.reference_trapezoid_time(D, v, a), trapezoid_by_hand(D, v, a), rel_tol=1e-12)
        start, step = rng.uniform(-2.0, 2.0, (2, 5))
        v_max, a_max = rng.uniform(0.2, 2.5, 5), rng.uniform(0.3, 6.0, 5)
        assert math.isclose(chk.reference_least_duration(start, start + step, v_max, a_max),
                            joint_trajectory_duration(start, start + step, v_max=v_max, a_max=a_max), rel_tol=1e-12)
        q0, q1 = (q / np.linalg.norm(q) for q in rng.normal(size=(2, 4)))
        s = rng.uniform()
        mine, theirs = chk.reference_slerp(q0, q1, s), quaternion_slerp(q0, q1, s)
        assert np.allclose(mine, theirs, atol=1e-12) or np.allclose(mine, -theirs, atol=1e-12)
    # at rest outside [0, T]; no joint moving: no time; equal rotations: no NaN
    assert np.allclose(chk.reference_quintic_scaling(3.0, 2.0), [1.0, 0.0, 0.0])
    assert np.allclose(chk.reference_cubic_scaling(-1.0, 2.0), [0.0, 0.0, 0.0])
    assert chk.reference_least_duration(np.ones(3), np.ones(3), np.ones(3), np.ones(3)) == 0.0
    q = np.array([0.5, 0.5, -0.5, 0.5])
    assert np.allclose(chk.reference_slerp(q, q, 0.3), q)


@pytest.mark.parametrize("call", [
    lambda: chk.reference_quintic_scaling(0.5, 0.0),
    lambda: chk.reference_trapezoid_time(-0.1, 1.0, 1.0),
    lambda: chk.reference_trapezoid_time(0.1, 1.0, 0.0),
    lambda: chk.reference_least_duration([0.0, 1.0], [1.0], [1.0, 1.0], [1.0, 1.0]),
    lambda: chk.reference_least_duration([0.0], [1.0], [-1.0], [1.0]),
    lambda: chk.reference_slerp(np.zeros(4), [1.0, 0.0, 0.0, 0.0], 0.5),
    lambda: chk.reference_slerp([1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], 0.5),
])
def test_references_refuse_bad_input(call):
    with pytest.raises((TypeError, ValueError)):
        call()


def test_references_are_flagged_as_answers_to_their_own_tasks():
    for task, reference in [("cubic_scaling", "reference_cubic_scaling"),
                            ("quintic_scaling", "reference_quintic_scaling"),
                            ("trapezoid_time", "reference_trapezoid_time"),
                            ("least_duration", "reference_least_duration"), ("slerp", "reference_slerp")]:
        assert reference in chk.DELEGATION[task] and reference in chk.__all__


def test_a_later_step_is_judged_with_robokin_steps_in_place_of_the_students():
    def wrong_trapezoid(distance, v_max, a_max):
        return distance / v_max + v_max / a_max  # the triangle missed

    def least_duration(q_start, q_end, v_max, a_max, trapezoid_time=wrong_trapezoid):
        return max(trapezoid_time(abs(e - s), v, a) for s, e, v, a in zip(q_start, q_end, v_max, a_max))

    def wrong_duration(q_start, q_end, v_max, a_max):
        return 0.9 * least_duration_by_hand(q_start, q_end, v_max, a_max)

    def synchronised_motion(t, q_start, q_end, v_max, a_max, least_duration=wrong_duration):
        assert math.isclose(least_duration(q_start, q_end, v_max, a_max),
                            least_duration_by_hand(q_start, q_end, v_max, a_max), rel_tol=1e-12)
        return motion_by_integration(t, q_start, q_end, v_max, a_max)

    def wrong_law(t, T):
        return quintic_by_hand(t, T) * [1.0, T, T * T]  # rates per unit of tau

    def line_reference(t, T_start, T_end, duration, quintic_scaling=wrong_law, slerp=None):
        assert np.allclose(quintic_scaling(0.3 * duration, duration), quintic_by_hand(0.3 * duration, duration))
        assert slerp is chk.reference_slerp
        return line_by_exponential(t, T_start, T_end, duration)

    assert chk.least_duration(least_duration, quiet=True).passed
    assert chk.synchronised_motion(synchronised_motion, quiet=True).passed
    assert chk.line_reference(line_reference, quiet=True).passed
    # a function without the argument is judged as it is: the wrong step shows
    assert not chk.least_duration(lambda *move: least_duration(*move), quiet=True).passed
