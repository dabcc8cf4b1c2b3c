r"""matplotlib drawing of planar velocity and force ellipses.

A planar ellipse is given as robokin returns it (the first two rows and columns of
:func:`robokin.chains.ellipsoids.velocity_ellipsoid` for a planar arm, or a student's
``(radii, axes)``): its semi-axes ``radii`` and its unit axes as the columns of ``axes``. Its
curve is :math:`\mathbf{c} + \mathbf{A}\,\mathrm{diag}(s\mathbf{r})(\cos t, \sin t)^\mathsf{T}`
(:func:`robokin.views.ellipsoids.ellipse_points`)::

    radii, axes = velocity_ellipse(J)                 # (2,), (2, 2)
    ax = plot_ellipse(radii, axes, tool_position, scale=0.4, color="#1F77B4")

The drawing is in the units of ``centre`` (m): ``scale`` converts the ellipse's own unit
(m/s per rad/s, N per N·m) to them. matplotlib is imported only when a drawing is made.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.views import optional
from robokin.views.ellipsoids import ellipse_points

__all__ = ["plot_ellipse"]


def plot_ellipse(radii: Any, axes: Any, centre: Any = (0.0, 0.0), ax: Any = None, *, scale: float = 1.0,
                 limit: float | None = None, semi_axes: bool = False, color: Any = "#1F77B4",
                 label: str | None = None, linewidth: float = 1.5, samples: int = 73) -> Any:
    r"""Draw a planar ellipse, and optionally its principal semi-axes, into a matplotlib Axes.

    Parameters
    ----------
    radii : array_like, shape (2,)
        Semi-axes (≥ 0; ``inf`` only with ``limit``), in the ellipse's unit (m/s, N, ...).
    axes : array_like, shape (2, 2)
        Orthonormal unit axes as columns, in the order of ``radii``.
    centre : array_like, shape (2,)
        Where the ellipse is drawn (m), e.g. the tool position.
    ax : matplotlib.axes.Axes, optional
        The Axes to draw into; a new figure's when left out.
    scale : float
        Drawing length per unit of ``radii`` (m per m/s, m per N, ...), > 0.
    limit : float, optional
        The longest drawn semi-axis (m): longer and infinite ones are drawn at ``limit``.
    semi_axes : bool
        Also draw each semi-axis as a segment from the centre, :math:`\mathbf{c} + s\,r_i\mathbf{a}_i`.
    color, label, linewidth
        matplotlib line properties (the label goes to the curve only).
    samples : int
        Points on the curve, ≥ 3.

    Returns
    -------
    matplotlib.axes.Axes
        The Axes drawn into, its aspect set equal (an ellipse drawn round is round).

    Raises
    ------
    ShapeError, DomainError
        As :func:`robokin.views.ellipsoids.ellipse_points`: arguments of other shapes, negative or
        NaN radii, axes that are not orthonormal, an infinite radius without ``limit``, a scale or
        limit that is not positive, fewer than 3 samples.
    """
    points = ellipse_points(radii, axes, centre, scale=scale, limit=limit, samples=samples)
    if ax is None:
        ax = optional.pyplot().figure(figsize=(4.5, 4.0)).add_subplot()
    ax.plot(points[:, 0], points[:, 1], color=color, lw=linewidth, label=label)
    if semi_axes:
        r = np.array(radii, dtype=float)
        lengths = scale * r if limit is None else np.minimum(scale * r, limit)
        c = np.asarray(centre, dtype=float)
        for length, axis in zip(lengths, np.asarray(axes, dtype=float).T):
            end = c + length * axis
            ax.plot([c[0], end[0]], [c[1], end[1]], color=color, lw=0.8 * linewidth)
    ax.set_aspect("equal")
    return ax
