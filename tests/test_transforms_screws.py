"""Tests of robokin.transforms.screws: SE(3) exp and log, and the adjoint, in Lynch & Park's [ω; v].

Cross-checked against the Modern Robotics library (``modern_robotics``, a test-only dependency)
where its thresholds hold (its ``MatrixExp6`` treats rotations below 1e-6 rad as none, its
``MatrixLog6`` loses the axis near θ = π); the group identities are checked everywhere, and
the ends θ → 0 and θ → π against round trips.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from robokin.errors import DomainError, ShapeError
from robokin.transforms import adjoint, rotation_exp, skew, transform_exp, transform_inverse, transform_log

mr = pytest.importorskip("modern_robotics", reason="modern_robotics (requirements.txt) cross-checks SE(3)")

#: products of a few float matrices: a few ulps of their unit-size entries
TOLERANCE = 1e-12


def twists(count: int, seed: int, largest_angle: float = 3.0) -> np.ndarray:
    """``count`` exponential coordinates [w; u] with |w| in [1e-3, largest_angle] and |u| up to 2 m."""
    rng = np.random.default_rng(seed)
    axes = rng.normal(size=(count, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    angles = rng.uniform(1e-3, largest_angle, count)
    return np.hstack([axes * angles[:, None], rng.uniform(-2, 2, (count, 3))])


def hat(V: np.ndarray) -> np.ndarray:
    """The 4×4 matrix [V] of a twist [ω; v] (Lynch & Park 2017, §3.3.2)."""
    out = np.zeros((4, 4))
    out[:3, :3] = skew(V[:3])
    out[:3, 3] = V[3:]
    return out


@pytest.mark.parametrize("V", list(twists(50, seed=1)))
def test_exp_equals_modern_robotics(V):
    assert np.allclose(transform_exp(V), mr.MatrixExp6(mr.VecTose3(V)), rtol=0, atol=TOLERANCE)


@pytest.mark.parametrize("V", list(twists(50, seed=2, largest_angle=3.0)))
def test_log_equals_modern_robotics_away_from_pi(V):
    T = transform_exp(V)
    assert np.allclose(transform_log(T), mr.se3ToVec(mr.MatrixLog6(T)), rtol=0, atol=1e-10)
    assert np.allclose(transform_log(T), V, rtol=0, atol=TOLERANCE)   # |w| < π: the log returns V itself


@pytest.mark.parametrize("V", list(twists(20, seed=3)))
def test_adjoint_equals_modern_robotics(V):
    T = transform_exp(V)
    assert np.array_equal(adjoint(T), mr.Adjoint(T))


@pytest.mark.parametrize("gap", [1e-2, 1e-5, 1e-8, 1e-12, 0.0])
@pytest.mark.parametrize("axis", [[0, 0, 1], [0.6, 0.8, 0], [1, -1, 1], [-1, 0, 0]])
def test_log_is_exact_near_half_a_turn(axis, gap):
    """Modern Robotics' MatrixLog6 is off by up to 2 at θ = π; this log is exact there."""
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    V = np.r_[axis * (math.pi - gap), 0.3, -0.2, 0.5]
    T = transform_exp(V)
    back = transform_log(T)
    assert np.allclose(transform_exp(back), T, rtol=0, atol=TOLERANCE)
    assert abs(np.linalg.norm(back[:3]) - (math.pi - gap)) < TOLERANCE
    if gap > 0:   # below π the rotation vector is unique
        assert np.allclose(back, V, rtol=0, atol=1e-9)


@pytest.mark.parametrize("angle", [0.0, 1e-12, 1e-8, 1e-5, 9.9e-4, 1.01e-3, 1e-2])
def test_exp_and_log_near_no_rotation(angle):
    """The series below SERIES_ANGLE and the closed forms above it meet; a pure translation is exact."""
    V = np.r_[np.array([0.0, 0.6, 0.8]) * angle, 1.0, -2.0, 0.5]
    T = transform_exp(V)
    W = hat(V)
    series = np.eye(4) + W + W @ W / 2 + W @ W @ W / 6 + W @ W @ W @ W / 24   # terms beyond: < 1e-16
    if angle <= 1e-5:
        assert np.allclose(T, series, rtol=0, atol=TOLERANCE)
    assert np.allclose(transform_log(T), V, rtol=0, atol=TOLERANCE)
    if angle == 0.0:
        assert np.array_equal(T[:3, :3], np.eye(3)) and np.array_equal(T[:3, 3], V[3:])


def test_exp_is_rotation_exp_and_translation_for_a_pure_rotation_about_the_origin():
    V = np.r_[0.3, -1.1, 0.4, 0.0, 0.0, 0.0]
    T = transform_exp(V)
    assert np.allclose(T[:3, :3], rotation_exp(V[:3]), rtol=0, atol=TOLERANCE)
    assert np.array_equal(T[:3, 3], np.zeros(3))


def test_exp_of_a_screw_about_an_axis_through_a_point():
    """Lynch & Park's screw: a rotation by θ about the axis ω through q moves q nowhere."""
    omega, point, theta = np.array([0.0, 0.0, 1.0]), np.array([1.0, 2.0, 0.0]), 0.7
    S = np.r_[omega, -np.cross(omega, point)]
    T = transform_exp(S * theta)
    assert np.allclose(T @ np.r_[point, 1.0], np.r_[point, 1.0], rtol=0, atol=TOLERANCE)
    assert np.allclose(T[:3, :3], rotation_exp(omega * theta), rtol=0, atol=TOLERANCE)


@pytest.mark.parametrize("V", list(twists(10, seed=4)))
def test_derivative_of_the_exponential_at_zero_is_the_twist(V):
    """d/dt e^{[V]t} at t = 0 is [V] (central differences, error O(h²))."""
    h = 1e-5
    derivative = (transform_exp(V * h) - transform_exp(-V * h)) / (2 * h)
    assert np.allclose(derivative, hat(V), rtol=0, atol=1e-8)


@pytest.mark.parametrize("V", list(twists(10, seed=5)))
def test_group_identities(V):
    T = transform_exp(V)
    other = transform_exp(twists(1, seed=6)[0])
    assert np.allclose(transform_exp(-V), transform_inverse(T), rtol=0, atol=TOLERANCE)
    assert np.allclose(adjoint(T @ other), adjoint(T) @ adjoint(other), rtol=0, atol=TOLERANCE)
    assert np.allclose(adjoint(transform_inverse(T)), np.linalg.inv(adjoint(T)), rtol=0, atol=1e-11)
    # a twist moved by the adjoint is the same motion seen from another frame: T e^{[V']} T⁻¹
    moved = twists(1, seed=7)[0]
    assert np.allclose(transform_exp(adjoint(T) @ moved), T @ transform_exp(moved) @ transform_inverse(T),
                       rtol=0, atol=1e-11)


def test_batches_equal_single_calls():
    V = twists(7, seed=8)
    T = transform_exp(V)
    assert T.shape == (7, 4, 4) and transform_log(T).shape == (7, 6) and adjoint(T).shape == (7, 6, 6)
    for k in range(7):
        assert np.array_equal(T[k], transform_exp(V[k]))
        assert np.allclose(transform_log(T)[k], transform_log(T[k]), rtol=0, atol=1e-15)
        assert np.array_equal(adjoint(T)[k], adjoint(T[k]))
    assert transform_exp(np.zeros((0, 6))).shape == (0, 4, 4)


def test_symbolic_exponential_equals_the_numbers():
    theta, d = sp.symbols("theta d", positive=True)
    T = transform_exp(sp.Matrix([0, 0, theta, d, 0, 0]))
    numbers = {theta: 0.8, d: 0.25}
    assert np.allclose(np.array(T.subs(numbers), dtype=float), transform_exp([0, 0, 0.8, 0.25, 0, 0]),
                       rtol=0, atol=TOLERANCE)


@pytest.mark.parametrize("bad, error, words", [
    (np.zeros(5), ShapeError, "V must have shape (6,) or (N, 6); got shape (5,)"),
    (np.zeros((2, 3)), ShapeError, "V must have shape"),
    ([0, 0, np.nan, 0, 0, 0], DomainError, "V"),
])
def test_exp_names_a_bad_argument(bad, error, words):
    with pytest.raises(error, match=words.replace("(", r"\(").replace(")", r"\)")):
        transform_exp(bad)


def test_log_and_adjoint_name_a_bad_transform():
    with pytest.raises(ShapeError, match="T"):
        transform_log(np.eye(3))
    with pytest.raises(DomainError, match="T"):
        adjoint(np.diag([2.0, 1.0, 1.0, 1.0]))
