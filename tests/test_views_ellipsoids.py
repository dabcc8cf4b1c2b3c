"""Tests of robokin.views.ellipsoids: the curves lie on the ellipse (ellipsoid) they draw."""

from __future__ import annotations

import numpy as np
import pytest

from robokin import models
from robokin.errors import DomainError, ShapeError
from robokin.views.ellipsoids import ellipse_points, ellipsoid_wireframe


def quadratic_form(radii, axes, centre, points):
    """sum_i (a_i . (x - c) / r_i)^2 for the rows x of points: 1 on the surface."""
    return np.sum(((np.asarray(points) - centre) @ np.asarray(axes) / np.asarray(radii)) ** 2, axis=1)


def rotation(angle):
    return np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])


@pytest.mark.parametrize(("radii", "angle", "centre"), [
    ([2.0, 0.5], 0.3, [1.0, -1.0]),
    ([1.0, 1.0], -1.2, [0.0, 0.0]),
    ([0.3, 0.1], 2.0, [0.5, 0.25]),
])
def test_ellipse_points_lie_on_the_ellipse(radii, angle, centre):
    points = ellipse_points(radii, rotation(angle), centre, samples=41)
    assert points.shape == (41, 2) and np.allclose(points[0], points[-1])
    assert np.allclose(quadratic_form(radii, rotation(angle), centre, points), 1.0)
    # the ends of the first axis are the farthest points from the centre
    distances = np.linalg.norm(points - centre, axis=1)
    assert np.isclose(distances.max(), max(radii), rtol=1e-2)


def test_scale_and_limit():
    points = ellipse_points([2.0, 0.5], np.eye(2), scale=0.5)
    assert np.allclose(np.abs(points).max(axis=0), [1.0, 0.25])
    points = ellipse_points([np.inf, 0.5], np.eye(2), limit=0.8)
    assert np.allclose(np.abs(points).max(axis=0), [0.8, 0.5])


def test_the_velocity_ellipsoid_of_the_ur10():
    ur10 = models.ur10()
    q = np.array([0.3, -1.2, 1.0, -0.6, 1.1, 0.4])
    radii, axes = ur10.velocity_ellipsoid(q)
    centre = ur10.fk(q)[:3, 3]
    curves = ellipsoid_wireframe(radii, axes, centre, scale=0.5, samples=37)
    assert len(curves) == 3 and all(c.shape == (37, 3) for c in curves)
    for k, curve in enumerate(curves):
        assert np.allclose(quadratic_form(0.5 * radii, axes, centre, curve), 1.0)
        assert np.allclose((curve - centre) @ axes[:, k], 0.0, atol=1e-12)  # its plane
    # a point of the velocity ellipsoid is a velocity J q_dot with |q_dot| = 1 (scale 1)
    J = ur10.position_jacobian(q)
    ends = np.linalg.pinv(J) @ (axes * radii)
    assert np.allclose(np.linalg.norm(ends, axis=0), 1.0)


def test_infinite_force_axis_needs_a_limit():
    arm = models.planar_two_link()
    radii, axes = arm.force_ellipsoid([0.3, 1.0])   # a planar arm: inf along z
    assert np.isinf(radii[0])
    with pytest.raises(DomainError, match="limit"):
        ellipsoid_wireframe(radii, axes)
    curves = ellipsoid_wireframe(radii, axes, limit=2.0)
    assert np.isclose(np.abs(curves[2] @ axes[:, 0]).max(), 2.0)


@pytest.mark.parametrize(("call", "error", "words"), [
    (lambda: ellipse_points([1.0], np.eye(2)), ShapeError, "shapes"),
    (lambda: ellipse_points([1.0, 1.0], np.eye(3)), ShapeError, "shapes"),
    (lambda: ellipse_points([1.0, -1.0], np.eye(2)), DomainError, "non-negative"),
    (lambda: ellipse_points([1.0, np.nan], np.eye(2)), DomainError, "non-negative"),
    (lambda: ellipse_points([1.0, 1.0], 2 * np.eye(2)), DomainError, "orthonormal"),
    (lambda: ellipse_points([1.0, 1.0], np.eye(2), scale=0.0), DomainError, "scale"),
    (lambda: ellipse_points([1.0, 1.0], np.eye(2), limit=-1.0), DomainError, "limit"),
    (lambda: ellipse_points([1.0, 1.0], np.eye(2), samples=2), DomainError, "samples"),
    (lambda: ellipse_points("ab", np.eye(2)), TypeError, "radii"),
    (lambda: ellipsoid_wireframe([1.0, 1.0, 1.0], np.eye(3), centre=[0.0, 0.0]), ShapeError, "shapes"),
])
def test_bad_input_is_named(call, error, words):
    with pytest.raises(error, match=words):
        call()
