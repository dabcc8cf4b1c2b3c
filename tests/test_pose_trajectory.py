"""Tests of robokin.motion.pose_trajectory: a straight line with slerped orientation.

References: finite differences of the poses (the twists and their rates), the closed form
R₀ e^{[w]s} with w the rotation vector of R₀ᵀR₁, a constant axis of rotation, and the short way
round when the end quaternion is given with the other sign.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from robokin.errors import DomainError, ShapeError
from robokin.motion import pose_trajectory, time_law
from robokin.transforms import rotation_exp, rotation_log, transform

START = transform(rotation_exp([0.1, 0.2, 0.3]), [0.5, 0.1, 0.3])
END = transform(rotation_exp([1.0, -0.5, 2.0]), [0.2, -0.4, 0.6])


def angular_velocity_by_differences(poses: np.ndarray, step: float) -> np.ndarray:
    rates = np.gradient(poses[:, :3, :3], step, axis=0)
    W = rates @ np.swapaxes(poses[:, :3, :3], 1, 2)   # Ṙ Rᵀ = [ω]
    return np.stack([W[:, 2, 1], W[:, 0, 2], W[:, 1, 0]], axis=1)


@pytest.mark.parametrize("law", ["quintic", "cubic", "linear"])
def test_twists_are_the_derivatives_of_the_poses(law):
    t = np.linspace(0.0, 2.0, 4001)
    motion = pose_trajectory(t, START, END, 2.0, law=law)
    step = t[1] - t[0]
    inner = slice(1, -1)
    assert np.allclose(np.gradient(motion.poses[:, :3, 3], step, axis=0)[inner], motion.twists[inner, :3], atol=1e-5)
    assert np.allclose(angular_velocity_by_differences(motion.poses, step)[inner], motion.twists[inner, 3:],
                       atol=1e-5)
    if law != "linear":
        assert np.allclose(np.gradient(motion.twists, step, axis=0)[2:-2], motion.accelerations[2:-2], atol=1e-3)


def test_orientation_is_the_closed_form_about_a_fixed_axis():
    t = np.linspace(0.0, 2.0, 41)
    motion = pose_trajectory(t, START, END, 2.0)
    w = rotation_log(START[:3, :3].T @ END[:3, :3])
    s, _, _ = time_law(t / 2.0)
    for pose, fraction in zip(motion.poses, s):
        assert np.allclose(pose[:3, :3], START[:3, :3] @ rotation_exp(fraction * w), atol=1e-14)
    axes = motion.twists[1:-1, 3:] / np.linalg.norm(motion.twists[1:-1, 3:], axis=1, keepdims=True)
    assert np.allclose(axes, START[:3, :3] @ w / np.linalg.norm(w), atol=1e-14)
    assert np.allclose(motion.poses[-1], END, atol=1e-14) and np.allclose(motion.poses[0], START, atol=1e-15)


def test_the_short_way_round():
    """A turn of 300° about z is done as 60° the other way."""
    end = transform(rotation_exp([0, 0, math.radians(300)]), [0, 0, 0])
    motion = pose_trajectory(np.linspace(0, 1, 11), np.eye(4), end, 1.0, law="linear")
    turned = [rotation_log(pose[:3, :3])[2] for pose in motion.poses]
    assert np.allclose(turned, np.linspace(0, -math.radians(60), 11), atol=1e-14)


def test_rest_outside_the_motion_and_shapes():
    motion = pose_trajectory([-1.0, 3.0], START, END, 2.0)
    assert np.allclose(motion.poses, [START, END], atol=1e-14) and not motion.twists.any()
    one = pose_trajectory(0.7, START, END, 2.0)
    assert one.poses.shape == (4, 4) and one.twists.shape == (6,) and one.accelerations.shape == (6,)


@pytest.mark.parametrize("call, error, words", [
    (lambda: pose_trajectory(0.0, np.eye(3), END, 1.0), ShapeError, "T_start"),
    (lambda: pose_trajectory(0.0, START, np.diag([2.0, 1, 1, 1]), 1.0), DomainError, "T_end"),
    (lambda: pose_trajectory(0.0, START, END, 0.0), DomainError, "duration"),
    (lambda: pose_trajectory(0.0, START, END, 1.0, law="trapezoidal"), ValueError, "law"),
])
def test_bad_arguments_are_named(call, error, words):
    with pytest.raises(error, match=words):
        call()
