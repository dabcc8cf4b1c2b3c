r"""Points to draw the velocity and force ellipsoids with (numpy only).

An ellipsoid is given as robokin returns it (:func:`robokin.chains.ellipsoids.velocity_ellipsoid`,
:func:`~robokin.chains.ellipsoids.force_ellipsoid`): its semi-axes ``radii`` and its unit axes as the
columns of ``axes``. Its surface is :math:`\mathbf{c} + \mathbf{A}\,\mathrm{diag}(\mathbf{r})\,\mathbf{s}`
for the unit vectors :math:`\mathbf{s}`. :func:`ellipse_points` gives the closed curve of a planar
one (plot it with matplotlib's ``ax.plot(*points.T)``); :func:`ellipsoid_wireframe` the curves of a
spatial one, for :meth:`robokin.views.Scene.add_path` or a 3D axes::

    radii, axes = chain.velocity_ellipsoid(q)
    for k, curve in enumerate(ellipsoid_wireframe(radii, axes, chain.fk(q)[:3, 3], scale=0.2)):
        scene.add_path(curve, name=f"velocity_ellipsoid_{k}", color=0x1F77B4)

A force ellipsoid at a singularity has an infinite semi-axis, which no drawing shows: pass
``limit`` to draw such an axis (and any longer than ``limit``) at that length, in the drawing's
units (after ``scale``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.validation import as_float_array

__all__ = ["ellipse_points", "ellipsoid_wireframe"]


def _checked(radii: Any, axes: Any, centre: Any, scale: float, limit: float | None,
             dimension: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    try:   # radii may hold inf (a force ellipsoid at a singularity): not as_float_array
        r = np.array(radii, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"radii must be numbers; got {type(radii).__name__}") from None
    A = np.asarray(as_float_array(axes, "axes"), dtype=float)
    c = np.asarray(as_float_array(centre, "centre"), dtype=float)
    if r.shape != (dimension,) or A.shape != (dimension, dimension) or c.shape != (dimension,):
        raise ShapeError(f"radii, axes and centre must have the shapes ({dimension},), ({dimension}, "
                         f"{dimension}) and ({dimension},); got {r.shape}, {A.shape} and {c.shape}")
    if np.isnan(r).any() or (r < 0).any():
        raise DomainError(f"radii must be non-negative (inf allowed with limit); got {r}")
    if not np.allclose(A.T @ A, np.eye(dimension), atol=1e-6):
        raise DomainError("axes must hold orthonormal unit axes as its columns; got axes with "
                          f"axesᵀ axes = {np.round(A.T @ A, 6).tolist()}")
    if not np.isfinite(scale) or scale <= 0:
        raise DomainError(f"scale must be a positive number; got {scale}")
    lengths = scale * r
    if limit is not None:
        if not np.isfinite(limit) or limit <= 0:
            raise DomainError(f"limit must be a positive number or None; got {limit}")
        lengths = np.minimum(lengths, limit)
    elif np.isinf(lengths).any():
        raise DomainError(f"radii has an infinite semi-axis ({r}), as a force ellipsoid at a singularity: "
                          "pass limit=<the length to draw it with>")
    return lengths, A, c


def ellipse_points(radii: Any, axes: Any, centre: Any = (0.0, 0.0), *, scale: float = 1.0,
                   limit: float | None = None, samples: int = 73) -> np.ndarray:
    r"""The closed curve of a planar ellipse, :math:`\mathbf{c} + \mathbf{A}\,\mathrm{diag}(s\mathbf{r})
    (\cos t, \sin t)^\mathsf{T}`.

    Parameters
    ----------
    radii : array_like, shape (2,)
        Semi-axes (≥ 0; ``inf`` only with ``limit``), in any unit (m/s, N, ...).
    axes : array_like, shape (2, 2)
        Orthonormal unit axes as columns, in the order of ``radii``.
    centre : array_like, shape (2,)
        Where the ellipse is drawn (m), e.g. the tool position.
    scale : float
        Drawing length per unit of ``radii`` (m per m/s, m per N, ...), > 0.
    limit : float, optional
        The longest drawn semi-axis (m): longer ones, and infinite ones, are drawn at ``limit``.
    samples : int
        Number of points, ≥ 3 (the first one repeated at the end).

    Returns
    -------
    numpy.ndarray, shape (samples, 2)
        Points of the curve, the first and the last equal.

    Raises
    ------
    ShapeError, DomainError
        Arguments of other shapes, negative or NaN radii, axes that are not orthonormal, an infinite
        radius without ``limit``, a scale or limit that is not positive, fewer than 3 samples.
    """
    lengths, A, c = _checked(radii, axes, centre, scale, limit, 2)
    if int(samples) != samples or samples < 3:
        raise DomainError(f"samples must be an integer ≥ 3; got {samples}")
    t = np.linspace(0.0, 2.0 * np.pi, int(samples))
    circle = np.stack([np.cos(t), np.sin(t)])
    points = c[:, None] + A @ (lengths[:, None] * circle)
    points[:, -1] = points[:, 0]
    return points.T


def ellipsoid_wireframe(radii: Any, axes: Any, centre: Any = (0.0, 0.0, 0.0), *, scale: float = 1.0,
                        limit: float | None = None, samples: int = 49) -> list[np.ndarray]:
    r"""Three closed curves of a spatial ellipsoid: its principal ellipses.

    Curve :math:`k` lies in the plane of the two axes other than axis :math:`k` (through the
    centre); together they show the ellipsoid's three semi-axes and its orientation.

    Parameters
    ----------
    radii : array_like, shape (3,)
        Semi-axes (≥ 0; ``inf`` only with ``limit``).
    axes : array_like, shape (3, 3)
        Orthonormal unit axes as columns, in the order of ``radii``.
    centre : array_like, shape (3,)
        Where the ellipsoid is drawn (m).
    scale, limit, samples
        As for :func:`ellipse_points`.

    Returns
    -------
    list of numpy.ndarray, each of shape (samples, 3)
        The ellipses in the planes of the axes (2, 3), (1, 3) and (1, 2), each closed.

    Raises
    ------
    ShapeError, DomainError
        As :func:`ellipse_points`.
    """
    lengths, A, c = _checked(radii, axes, centre, scale, limit, 3)
    if int(samples) != samples or samples < 3:
        raise DomainError(f"samples must be an integer ≥ 3; got {samples}")
    t = np.linspace(0.0, 2.0 * np.pi, int(samples))
    curves = []
    for first, second in ((1, 2), (0, 2), (0, 1)):
        curve = (c[:, None] + A[:, [first]] * lengths[first] * np.cos(t)
                 + A[:, [second]] * lengths[second] * np.sin(t))
        curve[:, -1] = curve[:, 0]
        curves.append(curve.T)
    return curves
