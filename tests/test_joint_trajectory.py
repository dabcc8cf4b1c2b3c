"""Tests of robokin.motion.joint_trajectory: synchronised minimum-time point-to-point motions.

References: the closed forms of one joint's minimum time (trapezoid, triangle, polynomials), the
limits checked on a dense time grid, finite differences of the positions, and the claim that
the duration is minimal: a slightly shorter duration violates a limit of the slowest joint.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from robokin.errors import DomainError, ShapeError
from robokin.motion import joint_trajectory, joint_trajectory_duration

START = np.zeros(6)
END = np.deg2rad([90.0, -45.0, 30.0, 0.0, 120.0, -10.0])
V_MAX = np.deg2rad([120.0, 120.0, 180.0, 180.0, 180.0, 180.0])
A_MAX = np.deg2rad([300.0, 300.0, 400.0, 400.0, 400.0, 400.0])
LAWS = ["trapezoidal", "cubic", "quintic"]


def dense(law: str, start=START, end=END, v_max=V_MAX, a_max=A_MAX, samples: int = 20001):
    duration = joint_trajectory_duration(start, end, v_max=v_max, a_max=a_max, law=law)
    t = np.linspace(0.0, duration, samples)
    return t, duration, joint_trajectory(t, start, end, v_max=v_max, a_max=a_max, law=law)


@pytest.mark.parametrize("distance, v_max, a_max, expected", [
    (2.0, 1.0, 2.0, 2.0 / 1.0 + 1.0 / 2.0),       # reaches its speed: D/v + v/a
    (0.5, 1.0, 2.0, 2.0 * math.sqrt(0.5 / 2.0)),   # a triangle: 2 sqrt(D/a)
    (0.5, 1.0, 2.0 - 1e-12, 2.0 * math.sqrt(0.5 / (2.0 - 1e-12))),
    (1.0, 1.0, 1.0, 2.0),                           # the boundary D = v²/a: both formulas give 2
])
def test_one_joint_minimum_time(distance, v_max, a_max, expected):
    assert math.isclose(joint_trajectory_duration([0.0], [distance], v_max=v_max, a_max=a_max), expected,
                        rel_tol=1e-14)


@pytest.mark.parametrize("law, c_v, c_a", [("cubic", 1.5, 6.0), ("quintic", 15 / 8, 10 / math.sqrt(3))])
def test_polynomial_minimum_time(law, c_v, c_a):
    for distance, v_max, a_max in ((2.0, 1.0, 10.0), (2.0, 10.0, 1.0)):
        expected = max(c_v * distance / v_max, math.sqrt(c_a * distance / a_max))
        assert math.isclose(joint_trajectory_duration([0.0], [-distance], v_max=v_max, a_max=a_max, law=law),
                            expected, rel_tol=1e-14)


@pytest.mark.parametrize("law", LAWS)
def test_every_joint_starts_and_arrives_together_at_rest_within_its_limits(law):
    t, duration, motion = dense(law)
    assert np.allclose(motion.positions[0], START, atol=1e-15) and np.allclose(motion.positions[-1], END, atol=1e-12)
    assert np.array_equal(motion.velocities[0], np.zeros(6)) and np.array_equal(motion.velocities[-1], np.zeros(6))
    assert np.all(np.abs(motion.velocities) <= V_MAX * (1 + 1e-12))
    assert np.all(np.abs(motion.accelerations) <= A_MAX * (1 + 1e-12))
    # every moving joint is still moving just before the end: none arrives early
    before_end = joint_trajectory(duration * (1 - 1e-3), START, END, v_max=V_MAX, a_max=A_MAX, law=law)
    moving = END != START
    assert np.all(np.abs(before_end.velocities[moving]) > 0)


@pytest.mark.parametrize("law", LAWS)
def test_velocities_and_accelerations_are_the_derivatives(law):
    t, _, motion = dense(law)
    step = t[1] - t[0]
    speed = np.gradient(motion.positions, step, axis=0)
    # central differences: O(step²) inside, one step wide at the trapezoid's corners
    assert np.allclose(speed[1:-1], motion.velocities[1:-1], atol=1e-3)
    smooth = np.gradient(motion.velocities, step, axis=0)
    if law != "trapezoidal":
        assert np.allclose(smooth[1:-1], motion.accelerations[1:-1], atol=1e-3)


@pytest.mark.parametrize("law", LAWS)
def test_the_duration_is_the_least_the_limits_allow(law):
    """The slowest joint, given 1 % less time with the same law, needs more speed or acceleration."""
    duration = joint_trajectory_duration(START, END, v_max=V_MAX, a_max=A_MAX, law=law)
    own = [joint_trajectory_duration(START[i:i + 1], END[i:i + 1], v_max=V_MAX[i], a_max=A_MAX[i], law=law)
           for i in range(6)]
    assert duration == max(own)
    slowest = int(np.argmax(own))
    distance = abs(END[slowest] - START[slowest])
    shorter = 0.99 * duration
    if law == "trapezoidal":   # the fastest trapezoid within the acceleration limit in that time
        needed = 0.5 * (A_MAX[slowest] * shorter
                        - math.sqrt(max(A_MAX[slowest] ** 2 * shorter**2 - 4 * A_MAX[slowest] * distance, 0.0)))
        too_fast = A_MAX[slowest] * shorter**2 < 4 * distance or needed > V_MAX[slowest]
    else:
        c_v, c_a = {"cubic": (1.5, 6.0), "quintic": (15 / 8, 10 / math.sqrt(3))}[law]
        too_fast = c_v * distance / shorter > V_MAX[slowest] or c_a * distance / shorter**2 > A_MAX[slowest]
    assert too_fast


def test_polynomial_laws_keep_a_straight_line_in_joint_space():
    _, _, motion = dense("quintic", samples=101)
    direction = (END - START) / np.linalg.norm(END - START)
    offsets = motion.positions - START
    assert np.allclose(offsets - np.outer(offsets @ direction, direction), 0, atol=1e-15)


def test_rest_before_and_after_and_a_motion_of_nothing():
    duration = joint_trajectory_duration(START, END, v_max=V_MAX, a_max=A_MAX)
    positions, velocities, accelerations = joint_trajectory([-1.0, duration + 1.0], START, END, v_max=V_MAX,
                                                            a_max=A_MAX)
    assert np.allclose(positions, [START, END], atol=1e-12)
    assert not velocities.any() and not accelerations.any()
    still = joint_trajectory([0.0, 1.0], END, END, v_max=1.0, a_max=1.0)
    assert np.array_equal(still.positions, [END, END]) and not still.velocities.any()
    assert joint_trajectory(0.5, START, END, v_max=1.0, a_max=1.0).positions.shape == (6,)


@pytest.mark.parametrize("call, error, words", [
    (lambda: joint_trajectory(0.0, START, END[:5], v_max=1, a_max=1), ShapeError, "q_end"),
    (lambda: joint_trajectory(0.0, START, END, v_max=[1, 2], a_max=1), ShapeError,
     r"v_max must be a number or have shape \(6,\)"),
    (lambda: joint_trajectory(0.0, START, END, v_max=1, a_max=0.0), DomainError, "a_max"),
    (lambda: joint_trajectory(0.0, START, END, v_max=1, a_max=1, law="linear"), ValueError, "law"),
    (lambda: joint_trajectory(np.zeros((2, 2)), START, END, v_max=1, a_max=1), ShapeError, "t must be"),
])
def test_bad_arguments_are_named(call, error, words):
    with pytest.raises(error, match=words):
        call()
