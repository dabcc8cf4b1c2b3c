"""Tests for roll-pitch-yaw and ZYZ Euler angles."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from robokin.errors import DomainError, ShapeError
from robokin.transforms import (
    rotation_from_rpy,
    rotation_from_zyz,
    rotx,
    roty,
    rotz,
    rpy_from_rotation,
    zyz_from_rotation,
)

angle = st.floats(-np.pi + 1e-6, np.pi - 1e-6)
regular_pitch = st.floats(-np.pi / 2 + 1e-3, np.pi / 2 - 1e-3)


def test_rpy_definition():
    r, p, y = 0.3, -0.7, 2.1
    np.testing.assert_allclose(rotation_from_rpy(r, p, y), rotz(y) @ roty(p) @ rotx(r), atol=1e-15)
    np.testing.assert_allclose(rotation_from_rpy([r, p, y]), rotation_from_rpy(r, p, y), atol=0)


@pytest.mark.parametrize(
    "rpy, v, expected",
    [
        ((0, 0, np.pi / 2), [1, 0, 0], [0, 1, 0]),  # yaw turns x into y
        ((np.pi / 2, 0, 0), [0, 1, 0], [0, 0, 1]),  # roll turns y into z
        ((0, np.pi / 2, 0), [0, 0, 1], [1, 0, 0]),  # pitch turns z into x
    ],
)
def test_rpy_known_values(rpy, v, expected):
    np.testing.assert_allclose(rotation_from_rpy(*rpy) @ v, expected, atol=1e-15)


@settings(max_examples=200, deadline=None)
@given(angle, regular_pitch, angle)
def test_rpy_round_trip(r, p, y):
    rpy = rpy_from_rotation(rotation_from_rpy(r, p, y))
    np.testing.assert_allclose(rpy, [r, p, y], atol=1e-9)


def test_rpy_batch_equals_loop():
    rng = np.random.default_rng(7)
    rpy = rng.uniform(-1.5, 1.5, (30, 3))
    Rs = rotation_from_rpy(rpy)
    assert Rs.shape == (30, 3, 3)
    np.testing.assert_allclose(Rs, np.stack([rotation_from_rpy(*x) for x in rpy]), atol=1e-15)
    back = rpy_from_rotation(Rs)
    assert back.shape == (30, 3)
    np.testing.assert_allclose(back, rpy, atol=1e-12)
    np.testing.assert_allclose(back, np.stack([rpy_from_rotation(R) for R in Rs]), atol=0)
    # separate arrays broadcast
    assert rotation_from_rpy(rpy[:, 0], 0.1, rpy[:, 2]).shape == (30, 3, 3)


@pytest.mark.parametrize("pitch", [np.pi / 2, -np.pi / 2, np.pi / 2 - 1e-10, -np.pi / 2 + 1e-12])
@pytest.mark.parametrize("roll, yaw", [(0.3, 0.2), (-2.0, 1.0), (0.0, 0.0)])
def test_rpy_gimbal_lock(roll, pitch, yaw):
    R = rotation_from_rpy(roll, pitch, yaw)
    r, p, y = rpy_from_rotation(R)
    assert y == 0.0  # documented convention
    assert p == pytest.approx(np.sign(pitch) * np.pi / 2, abs=1e-8)
    np.testing.assert_allclose(rotation_from_rpy(r, p, y), R, atol=1e-8)


def test_rpy_near_gimbal_lock_reconstructs():
    for eps in [1e-4, 1e-6, 1e-7, 1e-9]:
        R = rotation_from_rpy(0.4, np.pi / 2 - eps, -0.3)
        np.testing.assert_allclose(rotation_from_rpy(rpy_from_rotation(R)), R, atol=1e-7)


def test_rpy_symbolic():
    r, p, y = sp.symbols("roll pitch yaw")
    R = rotation_from_rpy(r, p, y)
    assert isinstance(R, sp.MatrixBase)
    assert sp.simplify(R - rotz(y) * roty(p) * rotx(r)) == sp.zeros(3, 3)
    assert R[2, 0] == -sp.sin(p)
    vals = {r: 0.1, p: -0.4, y: 1.2}
    np.testing.assert_allclose(np.array(R.subs(vals), dtype=float), rotation_from_rpy(0.1, -0.4, 1.2),
                               atol=1e-15)
    # a float zero next to symbols stays exact
    R0 = rotation_from_rpy(r, 0.0, y)
    assert not R0.atoms(sp.Float)
    assert R0[2, 0] == 0
    assert rotation_from_rpy(sp.Matrix([r, p, y])) == R
    angles = rpy_from_rotation(R.subs(vals))
    np.testing.assert_allclose(np.array(angles, dtype=float).ravel(), [0.1, -0.4, 1.2], atol=1e-12)


def test_rpy_errors():
    with pytest.raises(ShapeError, match=r"rpy must have shape \(3,\) or \(N, 3\)"):
        rotation_from_rpy([0.1, 0.2])
    with pytest.raises(TypeError, match="pass either all three of roll, pitch, yaw"):
        rotation_from_rpy(0.1, 0.2)
    with pytest.raises(DomainError, match="pitch must be finite"):
        rotation_from_rpy(0.1, np.nan, 0.3)
    with pytest.raises(DomainError, match="R is not a rotation matrix"):
        rpy_from_rotation(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(ShapeError, match=r"R must have shape \(3, 3\) or \(N, 3, 3\)"):
        rpy_from_rotation(np.eye(4), check=False)


# --- ZYZ ------------------------------------------------------------------------------


def test_zyz_definition():
    f, t, s = 0.3, 1.1, -2.0
    np.testing.assert_allclose(rotation_from_zyz(f, t, s), rotz(f) @ roty(t) @ rotz(s), atol=1e-15)


@settings(max_examples=200, deadline=None)
@given(angle, st.floats(1e-3, np.pi - 1e-3), angle)
def test_zyz_round_trip(f, t, s):
    np.testing.assert_allclose(zyz_from_rotation(rotation_from_zyz(f, t, s)), [f, t, s], atol=1e-9)


@pytest.mark.parametrize("theta", [0.0, np.pi, 1e-12, np.pi - 1e-12])
def test_zyz_singular(theta):
    R = rotation_from_zyz(0.5, theta, -1.2)
    f, t, s = zyz_from_rotation(R)
    assert f == 0.0
    np.testing.assert_allclose(rotation_from_zyz(f, t, s), R, atol=1e-10)


def test_zyz_batch_and_symbolic():
    rng = np.random.default_rng(3)
    a = np.column_stack([rng.uniform(-3, 3, 10), rng.uniform(0.1, 3, 10), rng.uniform(-3, 3, 10)])
    Rs = rotation_from_zyz(a)
    assert Rs.shape == (10, 3, 3)
    np.testing.assert_allclose(zyz_from_rotation(Rs), a, atol=1e-12)
    f, t, s = sp.symbols("phi theta psi")
    R = rotation_from_zyz(f, t, s)
    assert sp.simplify(R - rotz(f) * roty(t) * rotz(s)) == sp.zeros(3, 3)
