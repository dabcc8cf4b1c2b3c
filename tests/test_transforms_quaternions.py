"""Tests for the quaternion functions (scalar first, w >= 0)."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from robokin.errors import DomainError, ShapeError
from robokin.transforms import (
    quaternion_conjugate,
    quaternion_from_rotation,
    quaternion_multiply,
    quaternion_slerp,
    rotation_exp,
    rotation_from_angle_axis,
    rotation_log,
    rotation_from_quaternion,
    rotx,
    roty,
    rotz,
)


def random_quaternions(rng, n):
    q = rng.standard_normal((n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


quaternion = st.tuples(*[st.floats(-1, 1)] * 4).map(np.array).filter(
    lambda q: np.linalg.norm(q) > 1e-2)


@pytest.mark.parametrize(
    "R, q",
    [
        (np.eye(3), [1, 0, 0, 0]),
        (rotx(np.pi / 2), [np.cos(np.pi / 4), np.sin(np.pi / 4), 0, 0]),
        (roty(np.pi / 2), [np.cos(np.pi / 4), 0, np.sin(np.pi / 4), 0]),
        (rotz(np.pi / 2), [np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)]),
        (rotz(-np.pi / 2), [np.cos(np.pi / 4), 0, 0, -np.sin(np.pi / 4)]),
        (np.diag([1.0, -1, -1]), [0, 1, 0, 0]),
        (np.diag([-1.0, 1, -1]), [0, 0, 1, 0]),
        (np.diag([-1.0, -1, 1]), [0, 0, 0, 1]),
    ],
)
def test_known_values(R, q):
    np.testing.assert_allclose(quaternion_from_rotation(R), q, atol=1e-15)
    np.testing.assert_allclose(rotation_from_quaternion(q), R, atol=1e-15)


def test_half_angle_form():
    h = np.array([1.0, 2.0, -2.0]) / 3.0
    for theta in [0.0, 0.3, 2.0, np.pi - 1e-9]:
        q = quaternion_from_rotation(rotation_from_angle_axis(h, theta))
        np.testing.assert_allclose(q, np.r_[np.cos(theta / 2), np.sin(theta / 2) * h], atol=1e-14)


@settings(max_examples=300, deadline=None)
@given(quaternion)
def test_round_trip_and_sign(q):
    qn = q / np.linalg.norm(q)
    R = rotation_from_quaternion(q)  # un-normalised input is fine
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-13)
    assert np.linalg.det(R) == pytest.approx(1.0)
    q2 = quaternion_from_rotation(R)
    assert q2[0] >= 0.0
    assert np.linalg.norm(q2) == pytest.approx(1.0)
    s = 1.0 if qn[0] >= 0 else -1.0
    if abs(qn[0]) > 1e-6:
        np.testing.assert_allclose(q2, s * qn, atol=1e-12)
    np.testing.assert_allclose(rotation_from_quaternion(q2), R, atol=1e-13)


def test_w_zero_sign_convention():
    # exact half turn about (-1, 1, 0)/sqrt(2): R = 2 h h^T - I
    R = np.array([[0.0, -1, 0], [-1, 0, 0], [0, 0, -1]])
    q = quaternion_from_rotation(R)
    assert q[0] == 0.0
    np.testing.assert_allclose(q, [0, np.sqrt(0.5), -np.sqrt(0.5), 0], atol=1e-15)
    # batched too, and independent of the sign of the input quaternion
    qs = quaternion_from_rotation(rotation_from_quaternion([[0, -1, 1, 0], [0, 0, -1, 0]]))
    np.testing.assert_allclose(qs, [[0, np.sqrt(0.5), -np.sqrt(0.5), 0], [0, 0, 1, 0]], atol=1e-15)


def test_multiply_composes_rotations():
    rng = np.random.default_rng(12)
    p, q = random_quaternions(rng, 2)
    np.testing.assert_allclose(
        rotation_from_quaternion(quaternion_multiply(p, q)),
        rotation_from_quaternion(p) @ rotation_from_quaternion(q),
        atol=1e-14,
    )
    np.testing.assert_allclose(quaternion_multiply(p, quaternion_conjugate(p)), [1, 0, 0, 0], atol=1e-15)
    np.testing.assert_allclose(quaternion_multiply([1, 0, 0, 0], q), q)
    # i * j = k
    np.testing.assert_array_equal(quaternion_multiply([0, 1, 0, 0], [0, 0, 1, 0]), [0, 0, 0, 1])


def test_batch_equals_loop():
    rng = np.random.default_rng(13)
    qs = random_quaternions(rng, 25)
    Rs = rotation_from_quaternion(qs)
    assert Rs.shape == (25, 3, 3)
    np.testing.assert_allclose(Rs, np.stack([rotation_from_quaternion(q) for q in qs]), atol=1e-15)
    back = quaternion_from_rotation(Rs)
    assert back.shape == (25, 4)
    np.testing.assert_allclose(back, np.stack([quaternion_from_rotation(R) for R in Rs]), atol=1e-15)
    np.testing.assert_allclose(back, qs * np.sign(qs[:, :1]), atol=1e-13)
    prod = quaternion_multiply(qs, qs[0])
    np.testing.assert_allclose(prod, np.stack([quaternion_multiply(q, qs[0]) for q in qs]), atol=1e-15)
    assert quaternion_conjugate(qs).shape == (25, 4)


def test_errors():
    with pytest.raises(DomainError, match="q must be a non-zero quaternion; got norm 0"):
        rotation_from_quaternion([0, 0, 0, 0])
    with pytest.raises(ShapeError, match=r"q must have shape \(4,\) or \(N, 4\); got shape \(3,\)"):
        rotation_from_quaternion([1, 0, 0])
    with pytest.raises(DomainError, match="q must be finite"):
        rotation_from_quaternion([np.nan, 0, 0, 1])
    with pytest.raises(DomainError, match="R is not a rotation matrix"):
        quaternion_from_rotation(-np.eye(3))
    with pytest.raises(ShapeError, match="p and q have incompatible batch sizes"):
        quaternion_multiply(np.ones((3, 4)), np.ones((2, 4)))
    with pytest.raises(ShapeError, match=r"p must have shape \(4,\) or \(N, 4\)"):
        quaternion_multiply([1, 0, 0], [1, 0, 0, 0])


def test_symbolic():
    w, x, y, z = sp.symbols("w x y z", real=True)
    R = rotation_from_quaternion([w, x, y, z])
    assert isinstance(R, sp.MatrixBase) and not R.atoms(sp.Float)
    q = np.array([0.5, -0.1, 0.7, 0.2])
    q /= np.linalg.norm(q)
    vals = dict(zip((w, x, y, z), q))
    np.testing.assert_allclose(np.array(R.subs(vals), dtype=float), rotation_from_quaternion(q), atol=1e-15)
    t = sp.Symbol("theta")
    Rz = rotation_from_quaternion([sp.cos(t / 2), 0, 0, sp.sin(t / 2)])
    assert sp.simplify(Rz - rotz(t)) == sp.zeros(3, 3)
    prod = quaternion_multiply([w, x, y, z], quaternion_conjugate([w, x, y, z]))
    assert sp.expand(prod) == sp.Matrix([w**2 + x**2 + y**2 + z**2, 0, 0, 0])


# ------------------------------------------------------------------ slerp
@given(quaternion, quaternion)
@settings(max_examples=60, deadline=None)
def test_slerp_turns_about_a_fixed_axis_at_a_constant_rate_the_short_way(p, q):
    """R(s) = R₀ exp(s w) with w = log(R₀ᵀR₁), |w| ≤ π (Shoemake 1985): the short way round,
    whichever sign q₁ is given with."""
    R0, R1 = rotation_from_quaternion(p), rotation_from_quaternion(q)
    w = rotation_log(R0.T @ R1)
    if np.linalg.norm(w) > np.pi - 1e-6:   # half a turn: both ways are as short
        return
    s = np.linspace(0.0, 1.0, 7)
    for sign in (1.0, -1.0):
        path = quaternion_slerp(p, sign * q, s)
        assert np.allclose(np.linalg.norm(path, axis=1), 1.0, atol=1e-15)
        for fraction, step in zip(s, path):
            assert np.allclose(rotation_from_quaternion(step), R0 @ rotation_exp(fraction * w), atol=1e-12)


def test_slerp_ends_and_nearly_equal_rotations():
    p = quaternion_from_rotation(rotation_exp([0.3, -0.2, 0.5]))
    q = quaternion_from_rotation(rotation_exp([0.3, -0.2, 0.5 + 1e-9]))
    assert np.allclose(quaternion_slerp(p, q, 0.0), p, atol=1e-15)
    assert np.allclose(quaternion_slerp(p, -q, 1.0), q, atol=1e-15)   # the end rotation, on p's side
    middle = quaternion_slerp(p, q, 0.5)
    assert np.allclose(rotation_from_quaternion(middle), rotation_exp([0.3, -0.2, 0.5 + 0.5e-9]), atol=1e-15)
    assert quaternion_slerp(p, q, [0.1, 0.2]).shape == (2, 4)


@pytest.mark.parametrize("q0, q1, s, error, words", [
    ([1, 0, 0], [1, 0, 0, 0], 0.5, ShapeError, "q0"),
    ([1, 0, 0, 0], [0, 0, 0, 0], 0.5, DomainError, "q1"),
    ([1, 0, 0, 0], [0, 1, 0, 0], [[0.5]], ShapeError, "s must be"),
    ([1, 0, 0, 0], [0, 1, 0, 0], np.nan, DomainError, "s"),
])
def test_slerp_names_a_bad_argument(q0, q1, s, error, words):
    with pytest.raises(error, match=words):
        quaternion_slerp(q0, q1, s)
