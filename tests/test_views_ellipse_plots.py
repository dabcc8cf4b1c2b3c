"""Tests of robokin.views.ellipse_plots: the drawn curve is the ellipse, its semi-axes end on it."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from robokin.errors import DomainError, ShapeError
from robokin.views.ellipse_plots import plot_ellipse


def rotation(angle):
    return np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])


def on_ellipse(lengths, axes, centre, points):
    """sum_i (a_i . (x - c) / l_i)^2 for the rows x of points: 1 on the drawn curve."""
    return np.sum(((np.asarray(points) - centre) @ axes / np.asarray(lengths)) ** 2, axis=1)


@pytest.fixture(autouse=True)
def _close():
    yield
    plt.close("all")


@pytest.mark.parametrize(("radii", "angle", "centre", "scale"), [
    ([2.0, 0.5], 0.3, [1.0, -1.0], 1.0),
    ([0.8, 0.8], -1.2, [0.0, 0.0], 0.4),
    ([5.0, 1.0], 2.0, [0.5, 0.25], 0.1),
])
def test_the_curve_lies_on_the_scaled_ellipse(radii, angle, centre, scale):
    ax = plot_ellipse(radii, rotation(angle), centre, scale=scale, samples=37)
    (line,) = ax.get_lines()
    points = np.column_stack(line.get_data())
    assert points.shape == (37, 2) and np.allclose(points[0], points[-1])
    assert np.allclose(on_ellipse(scale * np.array(radii), rotation(angle), centre, points), 1.0)
    assert ax.get_aspect() == 1.0


def test_semi_axes_end_on_the_curve_and_an_infinite_one_is_limited():
    fig, ax = plt.subplots()
    axes = rotation(0.7)
    assert plot_ellipse([np.inf, 0.5], axes, [1.0, 2.0], ax, scale=0.5, limit=1.5,
                        semi_axes=True, label="force") is ax
    curve, first, second = ax.get_lines()
    assert curve.get_label() == "force"
    for line, length, axis in ((first, 1.5, axes[:, 0]), (second, 0.25, axes[:, 1])):
        start, end = np.column_stack(line.get_data())
        assert np.allclose(start, [1.0, 2.0]) and np.allclose(end, start + length * axis)
        assert np.isclose(on_ellipse([1.5, 0.25], axes, [1.0, 2.0], [end])[0], 1.0)


@pytest.mark.parametrize(("arguments", "error"), [
    (([1.0, -0.5], np.eye(2)), DomainError),
    (([1.0, 0.5], 2 * np.eye(2)), DomainError),
    (([1.0, 0.5, 0.2], np.eye(3)), ShapeError),
    (([np.inf, 0.5], np.eye(2)), DomainError),
])
def test_bad_ellipses_are_refused_before_drawing(arguments, error):
    with pytest.raises(error):
        plot_ellipse(*arguments)
    assert plt.get_fignums() == []
