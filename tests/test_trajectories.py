"""Cartesian trajectory generators: shapes, geometry, continuity, derivatives."""

from __future__ import annotations

import numpy as np
import pytest

from robokin.errors import DomainError, ShapeError
from robokin.motion import circle_trajectory, line_trajectory, time_law, via_point_trajectory


def _numeric_derivative(fn, t, h=1e-6):
    return (fn(t + h) - fn(t - h)) / (2 * h)


def test_circle_geometry_and_derivatives():
    c = np.array([0.5, -0.2, 1.0])
    n = np.array([1.0, 1.0, 1.0]) / np.sqrt(3)
    t = np.linspace(0, 4, 41)
    p, v, a = circle_trajectory(t, c, 0.3, normal=n, angular_speed=2.0, phase=0.4)
    assert p.shape == v.shape == a.shape == (41, 3)
    assert np.allclose(np.linalg.norm(p - c, axis=1), 0.3)
    assert np.allclose((p - c) @ n, 0.0)
    assert np.allclose(np.linalg.norm(v, axis=1), 0.6)
    assert np.allclose(a, -4.0 * (p - c))
    num = _numeric_derivative(lambda s: circle_trajectory(s, c, 0.3, normal=n, angular_speed=2.0, phase=0.4)[0], t)
    assert np.allclose(v, num, atol=1e-6)
    # counter-clockwise about the normal
    assert np.all(np.cross(p - c, v) @ n > 0)


def test_circle_with_axes_and_scalar_time():
    p, v, a = circle_trajectory(0.0, [0, 0, 0], 2.0, axes=[[1, 0, 0], [1, 1, 0]], angular_speed=1.0)
    assert p.shape == (3,)
    assert np.allclose(p, [2, 0, 0]) and np.allclose(v, [0, 2, 0])
    with pytest.raises(DomainError, match="axes"):
        circle_trajectory(0.0, [0, 0, 0], 1.0, axes=[[1, 0, 0], [2, 0, 0]])
    with pytest.raises(ValueError, match="normal"):
        circle_trajectory(0.0, [0, 0, 0], 1.0)
    with pytest.raises(DomainError, match="radius"):
        circle_trajectory(0.0, [0, 0, 0], -1.0, normal=[0, 0, 1])
    with pytest.raises(DomainError, match="normal"):
        circle_trajectory(0.0, [0, 0, 0], 1.0, normal=[0, 0, 0])


@pytest.mark.parametrize("law", ["quintic", "cubic", "linear"])
def test_line_with_time_law(law):
    a, b = np.array([0.1, 0.2, 0.3]), np.array([0.5, -0.4, 0.9])
    t = np.linspace(-0.5, 2.5, 301)
    p, v, acc = line_trajectory(t, a, b, 2.0, law=law)
    assert np.allclose(p[0], a) and np.allclose(p[-1], b)
    # on the segment
    s = (p - a) @ (b - a) / np.sum((b - a) ** 2)
    assert np.allclose(a + s[:, None] * (b - a), p)
    assert np.all(np.diff(s) >= -1e-12)
    inner = (t > 0.01) & (t < 1.99)
    num = _numeric_derivative(lambda x: line_trajectory(x, a, b, 2.0, law=law)[0], t[inner])
    assert np.allclose(v[inner], num, atol=1e-6)
    if law == "quintic":
        assert np.allclose(v[[0, -1]], 0) and np.allclose(acc[[0, -1]], 0)
        # peak speed 15/8 * L / T at the middle
        assert np.max(np.linalg.norm(v, axis=1)) == pytest.approx(15 / 8 * np.linalg.norm(b - a) / 2.0, rel=1e-3)


def test_time_law_values():
    s, ds, dds = time_law(np.array([0.0, 0.5, 1.0]))
    assert np.allclose(s, [0, 0.5, 1]) and np.allclose(ds, [0, 1.875, 0]) and np.allclose(dds, 0)
    with pytest.raises(ValueError, match="time_law"):
        time_law(0.5, "septic")


def test_via_points_continuity():
    P = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 1.0]])
    tk = np.array([0.0, 1.0, 2.5, 3.0])
    t = np.linspace(0, 3, 3001)
    p, v, a = via_point_trajectory(t, P, tk)
    for k in range(4):
        assert np.allclose(via_point_trajectory(tk[k], P, tk).positions, P[k])
    # velocity continuous, positions are its integral
    assert np.max(np.abs(np.diff(v, axis=0))) < 0.05
    assert np.allclose(np.cumsum(v[:-1] * np.diff(t)[:, None], axis=0)[-1], P[-1] - P[0], atol=5e-3)
    assert np.allclose(v[[0, -1]], 0.0)
    inner = np.all(np.abs(t[:, None] - tk[None]) > 1e-3, axis=1)
    num = _numeric_derivative(lambda x: via_point_trajectory(x, P, tk)[0], t[inner])
    assert np.allclose(v[inner], num, atol=1e-5)
    # given velocities are met
    V = np.ones((4, 3))
    assert np.allclose(via_point_trajectory(tk[1], P, tk, V).velocities, 1.0)


def test_via_points_bad_input():
    with pytest.raises(DomainError, match="times"):
        via_point_trajectory(0.0, np.zeros((3, 3)), [0.0, 1.0, 1.0])
    with pytest.raises(ShapeError, match="points"):
        via_point_trajectory(0.0, np.zeros((1, 3)), [0.0])
    with pytest.raises(ShapeError, match="times"):
        via_point_trajectory(0.0, np.zeros((3, 3)), [0.0, 1.0])
    with pytest.raises(DomainError, match="t"):
        line_trajectory(np.nan, [0, 0, 0], [1, 0, 0], 1.0)
    with pytest.raises(DomainError, match="duration"):
        line_trajectory(0.0, [0, 0, 0], [1, 0, 0], 0.0)
