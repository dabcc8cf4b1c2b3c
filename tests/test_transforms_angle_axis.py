"""Tests for rotation_exp / rotation_log and the angle-axis helpers."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from robokin.errors import DomainError, ShapeError
from robokin.transforms import (
    angle_axis_from_rotation,
    rotation_exp,
    rotation_from_angle_axis,
    rotation_log,
    rotx,
    roty,
    rotz,
    skew,
)


def unit_vectors(rng, n):
    v = rng.standard_normal((n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def is_rotation(R, atol=1e-13):
    np.testing.assert_allclose(R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape),
                               atol=atol)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=atol)


unit_axis = st.tuples(*[st.floats(-1, 1)] * 3).map(np.array).filter(
    lambda v: np.linalg.norm(v) > 1e-3).map(lambda v: v / np.linalg.norm(v))


@pytest.mark.parametrize("fn, axis", [(rotx, [1, 0, 0]), (roty, [0, 1, 0]), (rotz, [0, 0, 1])])
@pytest.mark.parametrize("theta", [0.0, 0.4, -1.3, np.pi])
def test_exp_matches_elementary(fn, axis, theta):
    np.testing.assert_allclose(rotation_exp(theta * np.array(axis, float)), fn(theta), atol=1e-15)
    np.testing.assert_allclose(rotation_from_angle_axis(axis, theta), fn(theta), atol=1e-15)


def test_exp_matches_matrix_exponential_series():
    rng = np.random.default_rng(11)
    for w in rng.standard_normal((5, 3)):
        K = skew(w)
        E, term = np.eye(3), np.eye(3)
        for k in range(1, 40):
            term = term @ K / k
            E = E + term
        np.testing.assert_allclose(rotation_exp(w), E, atol=1e-13)


@pytest.mark.parametrize("theta", [0.0, 1e-300, 1e-12, 1e-8, 1e-5, 9.99e-4, 1e-3, 1.01e-3, 0.1])
def test_exp_small_angles(theta):
    h = np.array([0.2, -0.6, 0.3])
    h /= np.linalg.norm(h)
    R = rotation_exp(theta * h)
    is_rotation(R, atol=1e-15)
    # first-order behaviour R ≈ I + [w]x
    np.testing.assert_allclose(R, np.eye(3) + skew(theta * h), atol=max(theta**2, 1e-300))
    np.testing.assert_allclose(rotation_log(R), theta * h, atol=1e-16, rtol=1e-12)


@pytest.mark.parametrize(
    "theta", [np.pi / 2, 2.5, 2.7, np.pi - 1e-3, np.pi - 1e-6, np.pi - 1e-9, np.pi - 1e-12, np.pi]
)
def test_log_near_pi(theta):
    rng = np.random.default_rng(5)
    for h in unit_vectors(rng, 20):
        R = rotation_from_angle_axis(h, theta)
        w = rotation_log(R)
        assert np.linalg.norm(w) == pytest.approx(theta, abs=1e-12)
        np.testing.assert_allclose(rotation_exp(w), R, atol=1e-14)
        if theta < np.pi - 1e-7:  # away from pi the sign of the axis is determined
            np.testing.assert_allclose(w, theta * h, atol=1e-7)


def test_log_exactly_pi_about_coordinate_axes():
    for i, R in enumerate([np.diag([1.0, -1, -1]), np.diag([-1.0, 1, -1]), np.diag([-1.0, -1, 1])]):
        w = rotation_log(R)
        expected = np.zeros(3)
        expected[i] = np.pi
        np.testing.assert_array_equal(w, expected)  # documented: positive component


@settings(max_examples=300, deadline=None)
@given(unit_axis, st.floats(0.0, np.pi))
def test_exp_log_round_trip(h, theta):
    R = rotation_exp(theta * h)
    is_rotation(R)
    w = rotation_log(R)
    assert 0.0 <= np.linalg.norm(w) <= np.pi + 1e-15
    np.testing.assert_allclose(rotation_exp(w), R, atol=1e-13)
    if theta < np.pi - 1e-6:
        np.testing.assert_allclose(w, theta * h, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(st.tuples(*[st.floats(-20, 20)] * 3).map(np.array))
def test_log_wraps_large_rotation_vectors(w):
    R = rotation_exp(w)
    is_rotation(R, atol=1e-12)
    np.testing.assert_allclose(rotation_exp(rotation_log(R)), R, atol=1e-12)


def test_exp_log_batch_equals_loop():
    rng = np.random.default_rng(9)
    thetas = np.concatenate([[0.0, 1e-9, 1e-4, np.pi, np.pi - 1e-9], rng.uniform(0, np.pi, 20)])
    ws = unit_vectors(rng, len(thetas)) * thetas[:, None]
    Rs = rotation_exp(ws)
    assert Rs.shape == (len(ws), 3, 3)
    np.testing.assert_allclose(Rs, np.stack([rotation_exp(w) for w in ws]), atol=1e-15)
    logs = rotation_log(Rs)
    assert logs.shape == ws.shape
    np.testing.assert_allclose(logs, np.stack([rotation_log(R) for R in Rs]), atol=1e-15)
    np.testing.assert_allclose(rotation_exp(logs), Rs, atol=1e-14)


def test_log_validates():
    with pytest.raises(DomainError, match="R is not a rotation matrix"):
        rotation_log(np.diag([1.0, 1.0, -1.0]))
    rotation_log(np.diag([1.0, 1.0, -1.0]), check=False)  # garbage in, no error
    with pytest.raises(ShapeError, match=r"R must have shape \(3, 3\) or \(N, 3, 3\)"):
        rotation_log(np.eye(4))
    with pytest.raises(ShapeError, match=r"w must have shape \(3,\) or \(N, 3\); got shape \(4,\)"):
        rotation_exp([0, 0, 0, 1])
    with pytest.raises(DomainError, match="w must be finite"):
        rotation_exp([0, np.nan, 0])


# --- angle-axis ---------------------------------------------------------------------


def test_angle_axis_normalises_and_round_trips():
    R = rotation_from_angle_axis([0, 0, 5.0], 0.3)
    np.testing.assert_allclose(R, rotz(0.3), atol=1e-15)
    rng = np.random.default_rng(2)
    for h in unit_vectors(rng, 20):
        theta = rng.uniform(1e-6, np.pi - 1e-6)
        axis, angle = angle_axis_from_rotation(rotation_from_angle_axis(3 * h, theta))
        assert isinstance(angle, float)
        assert angle == pytest.approx(theta, abs=1e-12)
        np.testing.assert_allclose(axis, h, atol=1e-8)
    # a negative angle comes back as the opposite axis and a positive angle
    axis, angle = angle_axis_from_rotation(rotation_from_angle_axis([0, 1, 0], -0.5))
    np.testing.assert_allclose(axis, [0, -1, 0], atol=1e-15)
    assert angle == pytest.approx(0.5)


def test_angle_axis_identity_has_documented_axis():
    axis, angle = angle_axis_from_rotation(np.eye(3))
    np.testing.assert_array_equal(axis, [1.0, 0.0, 0.0])
    assert angle == 0.0


def test_angle_axis_batch():
    rng = np.random.default_rng(4)
    axes = unit_vectors(rng, 8)
    angles = rng.uniform(0, np.pi, 8)
    Rs = rotation_from_angle_axis(axes, angles)
    assert Rs.shape == (8, 3, 3)
    np.testing.assert_allclose(Rs, np.stack([rotation_from_angle_axis(a, t) for a, t in zip(axes, angles)]),
                               atol=1e-15)
    np.testing.assert_allclose(rotation_from_angle_axis([0, 0, 1], angles), rotz(angles), atol=1e-15)
    out_axes, out_angles = angle_axis_from_rotation(np.concatenate([Rs, np.eye(3)[None]]))
    assert out_axes.shape == (9, 3) and out_angles.shape == (9,)
    np.testing.assert_allclose(out_angles[:8], angles, atol=1e-12)
    np.testing.assert_array_equal(out_axes[8], [1, 0, 0])


def test_angle_axis_errors():
    with pytest.raises(DomainError, match="axis must be non-zero; got norm 0"):
        rotation_from_angle_axis([0, 0, 0], 1.0)
    with pytest.raises(DomainError, match=r"axis must be non-zero; got norm 0 at index 1"):
        rotation_from_angle_axis([[1, 0, 0], [0, 0, 0]], 1.0)
    with pytest.raises(ShapeError, match=r"axis must have shape \(3,\) or \(N, 3\)"):
        rotation_from_angle_axis([0, 1], 1.0)
    with pytest.raises(DomainError, match="angle must be finite"):
        rotation_from_angle_axis([0, 0, 1], np.inf)
    with pytest.raises(ShapeError, match="axis and angle have incompatible batch sizes"):
        rotation_from_angle_axis(np.eye(3), [0.1, 0.2])


def test_angle_axis_symbolic():
    t = sp.Symbol("theta")
    assert rotation_from_angle_axis([0, 0, 1], t) == rotz(t)
    assert rotation_from_angle_axis([1.0, 0.0, 0.0], t) == rotx(t)  # floats 1.0 become exact
    R = rotation_from_angle_axis([1, 1, 0], t)
    assert not R.atoms(sp.Float)
    np.testing.assert_allclose(np.array(R.subs(t, 0.8), dtype=float),
                               rotation_from_angle_axis([1, 1, 0], 0.8), atol=1e-15)
    with pytest.raises(DomainError, match="axis must be non-zero"):
        rotation_from_angle_axis([0, 0, 0], t)
    x, y, z = sp.symbols("x y z", real=True)
    Rw = rotation_exp([x, y, z])
    vals = {x: 0.1, y: -0.3, z: 0.5}
    np.testing.assert_allclose(np.array(Rw.subs(vals), dtype=float), rotation_exp([0.1, -0.3, 0.5]),
                               atol=1e-15)
    with pytest.raises(TypeError, match="rotation_log needs a numeric R"):
        rotation_log(rotz(t))
