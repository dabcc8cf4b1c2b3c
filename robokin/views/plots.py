"""matplotlib drawings: stick figures, planar mechanisms, time series.

All helpers draw into ``ax`` when given, else into a new figure (made with
pyplot, so a notebook shows it once at the end of the cell); none calls
``plt.show()``.  Single-panel helpers return the Axes, :func:`plot_history` the
Figure.  Output is deterministic (no random colours).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from robokin.chains.protocol import DrawableChain
from robokin.errors import DomainError, ShapeError
from robokin.views import optional
from robokin.views.arguments import as_chain, as_numbers
from robokin.views.ellipsoids import ellipsoid_wireframe
from robokin.views.geometry import ellipsoid_box_points, scene_scale
from robokin.views.record import ChainItem, EllipsoidItem, PathItem, PointsItem, SceneRecord, TargetItem

__all__ = ["PLOT_LIMIT", "SINGULAR_COLOR", "plot_chain", "plot_planar", "plot_history", "plot_scene"]

LINK = "#E69F00"
JOINT = "#3B3B3B"
EE = "#D62728"
AXES_RGB = ("#E41A1C", "#2CA02C", "#1F77B4")
#: Largest magnitude plot_history draws (matplotlib's autoscaling overflows near 1e308).
PLOT_LIMIT = 1e100


def _new_axes(projection=None, figsize=(5.5, 4.5)):
    fig = optional.pyplot().figure(figsize=figsize)
    return fig.add_subplot(projection=projection)


def _set_equal_3d(ax, pts):
    pts = np.asarray(pts).reshape(-1, 3)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    c, r = (lo + hi) / 2, max(float((hi - lo).max()) / 2, 1e-3) * 1.1
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")


def _draw_triad(ax, T, size, alpha=1.0):
    for k in range(3):
        a = T[:3, 3]
        b = a + size * T[:3, k]
        ax.plot(*np.c_[a, b], color=AXES_RGB[k], lw=1.5, alpha=alpha)


def _draw_chain(ax, chain, q, alpha=1.0, color=None, frames=False, label=None, triad=True):
    F = np.asarray(chain.frames(np.asarray(q, dtype=float)), dtype=float)
    o = F[:, :3, 3]
    ax.plot(o[:, 0], o[:, 1], o[:, 2], "-", color=color or LINK, lw=3, alpha=alpha, label=label)
    ax.plot(o[1:-1, 0], o[1:-1, 1], o[1:-1, 2], "o", color=JOINT, ms=5, alpha=alpha)
    ax.plot(*o[-1], "o", color=EE, ms=6, alpha=alpha)
    reach = float(np.linalg.norm(np.diff(o, axis=0), axis=1).sum()) or 1.0
    if triad:
        _draw_triad(ax, F[-1], 0.1 * reach, alpha)
    if frames:
        for T in F[:-1]:
            _draw_triad(ax, T, 0.12 * reach, alpha)
    return o


def plot_chain(chain: DrawableChain, q: Any, ax: Any = None, *, frames: bool = False, alpha: float | None = None,
               labels: Sequence[str] | None = None) -> Any:
    """3D stick figure of ``chain`` at one configuration or at each row of a batch.

    Links orange, joints dark dots, end-effector red with a small RGB triad;
    ``frames=True`` adds a triad per frame.  With several configurations the
    first is opaque and the others fade.

    Parameters
    ----------
    chain : SerialChain
        Any object with ``n`` and ``frames(q)``.
    q : array_like, shape (n,) or (N, n)
        Configuration(s) (rad, m).
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D, optional
        A 3D Axes to draw into; default a new figure.
    frames : bool, optional
        A triad at every frame.
    alpha : float, optional
        Opacity of every configuration; default 1 for the first, fading for the others.
    labels : sequence of str, optional
        A legend label per configuration.

    Returns
    -------
    mpl_toolkits.mplot3d.axes3d.Axes3D
        The Axes (equal scales, metres).

    Raises
    ------
    ShapeError
        ``q`` is not (n,) or (N, n) with N >= 1.
    """
    n = int(as_chain(chain).n)
    Q = as_numbers(q, "q", f"a configuration ({n},) or configurations (N, {n})")
    if Q.ndim == 1:
        Q = Q[None]
    if Q.ndim != 2 or Q.shape[1] != n or not len(Q):
        raise ShapeError(f"q must have shape ({n},) or (N, {n}); got shape {np.shape(q)}")
    if ax is None:
        ax = _new_axes("3d")
    pts = []
    for k, row in enumerate(Q):
        a = alpha if alpha is not None else (1.0 if k == 0 else max(0.15, 0.6 - 0.4 * k / max(len(Q) - 1, 1)))
        lab = labels[k] if labels is not None else None
        pts.append(_draw_chain(ax, chain, row, alpha=a, frames=frames, label=lab, triad=(k == 0)))
    _set_equal_3d(ax, np.vstack(pts + [np.zeros((1, 3))]))
    if labels is not None:
        ax.legend(loc="upper left", fontsize=8)
    return ax


def plot_planar(segments: Any = (), points: Any = None, ax: Any = None, *, labels: Sequence[str] | None = None,
                color: str = LINK, point_color: str = JOINT, title: str | None = None,
                annotate: Sequence | None = None) -> Any:
    """Planar drawing of links and points (planar serial or parallel robots).

    Parameters
    ----------
    segments : sequence of array_like of shape (K, 2), or array, shape (M, 2, 2)
        Links: polylines of K >= 2 points (m), e.g. ``((x0, y0), (x1, y1))`` pairs.
    points : array_like, shape (N, 2), optional
        Joints or markers (m).
    ax : matplotlib.axes.Axes, optional
        Axes to draw into; default a new figure.
    labels : sequence of str, optional
        A legend label per segment.
    color : str, optional
        Colour of the links (matplotlib colour).
    point_color : str, optional
        Colour of the points.
    title : str, optional
        Axes title.
    annotate : sequence, optional
        Text labels for the points, in order.

    Returns
    -------
    matplotlib.axes.Axes
        The Axes (equal aspect, metres).

    Raises
    ------
    ShapeError
        A segment is not (K, 2) with K >= 2, or ``points`` not (N, 2).
    TypeError
        ``segments`` is a string, or holds something that is not numbers.
    """
    if isinstance(segments, (str, bytes)):
        raise TypeError(f"segments must be a list of polylines (K, 2); got {type(segments).__name__}")
    if ax is None:
        ax = _new_axes()
    allpts = []
    for k, seg in enumerate(segments):
        s = as_numbers(seg, f"segments[{k}]", "a polyline of shape (K, 2)")
        if s.ndim != 2 or s.shape[1] != 2 or s.shape[0] < 2:
            raise ShapeError(f"segments[{k}] must have shape (K, 2) with K >= 2; got shape {s.shape}")
        ax.plot(s[:, 0], s[:, 1], "-", color=color, lw=3, solid_capstyle="round",
                label=labels[k] if labels is not None else None)
        allpts.append(s)
    if points is not None:
        p = as_numbers(points, "points", "points of shape (N, 2)")
        if p.size % 2:
            raise ShapeError(f"points must have shape (N, 2); got shape {p.shape}")
        p = p.reshape(-1, 2)
        ax.plot(p[:, 0], p[:, 1], "o", color=point_color, ms=6, zorder=3)
        allpts.append(p)
        for txt, xy in zip(annotate or [], p):
            ax.annotate(str(txt), xy, textcoords="offset points", xytext=(5, 5), fontsize=9)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    if title:
        ax.set_title(title)
    if labels is not None:
        ax.legend(fontsize=8)
    return ax


def _get(record, *names):
    if record is None:
        return None
    for name in names:
        value = record.get(name) if isinstance(record, dict) else getattr(record, name, None)
        if value is not None:
            return value
    return None


def _series(ax, t, y, names, ylabel, log=False):
    y = np.asarray(y, dtype=float)
    if y.ndim == 1:
        y = y[:, None]
    for k in range(y.shape[1]):
        lab = names[k] if names is not None and k < len(names) else f"{k + 1}"
        (ax.semilogy if log else ax.plot)(t, y[:, k], label=lab, lw=1.5)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    if y.shape[1] > 1:
        ax.legend(fontsize=8, ncol=min(y.shape[1], 4), loc="best")


#: Colour of the bands that mark near-singular steps.
SINGULAR_COLOR = "#D62728"


def _singular_spans(x, flags):
    """(start, end) x-intervals covering the runs of True in ``flags`` (each step spans to the next)."""
    flags = np.asarray(flags, dtype=bool)
    x = np.asarray(x, dtype=float)
    if not flags.any():
        return []
    step = float(np.median(np.diff(x))) if len(x) > 1 else 1.0
    edges = np.diff(np.r_[0, flags.astype(int), 0])
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    return [(x[a], x[b] + step) for a, b in zip(starts, ends)]


def _history_values(kind, values):
    """One panel's samples as floats; a named error when empty, not numbers or never finite."""
    if isinstance(values, (str, bytes)):
        raise TypeError(f"{kind} must be an array of numbers (one row per sample); got str {values!r}"[:200])
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{kind} must be an array of numbers (one row per sample); got "
                        f"{type(values).__name__}") from None
    if v.ndim == 0 or len(v) == 0:
        raise ShapeError(f"{kind} has no samples (shape {v.shape}): there is nothing to plot")
    if not np.isfinite(v).any():
        raise DomainError(f"{kind} has no finite value ({v.size} NaN or infinite): there is nothing to plot")
    largest = float(np.nanmax(np.abs(np.where(np.isfinite(v), v, 0.0))))
    if largest > PLOT_LIMIT:
        raise DomainError(f"{kind} has values up to {largest:.3g}, more than a plot can scale ({PLOT_LIMIT:g})")
    return v


def _joint_units(joint_types: Sequence[str] | None, degrees: bool) -> tuple[str, str]:
    """Units of the joint position and velocity axes."""
    kinds = set(joint_types or [])
    if kinds == {"prismatic"}:
        return "m", "m/s"
    if "prismatic" in kinds:
        return ("deg | m" if degrees else "rad | m"), ("deg/s | m/s" if degrees else "rad/s | m/s")
    return ("deg", "deg/s") if degrees else ("rad", "rad/s")


def _mark_singular(axes: Any, x: np.ndarray, singular: Any, length: int) -> None:
    """A red band on every panel over the samples flagged near a singularity."""
    flags = np.asarray(singular, dtype=bool)
    if flags.shape != (length,):
        raise ShapeError(f"singular must have shape ({length},) (one flag per sample); got shape {flags.shape}")
    spans = _singular_spans(x, flags)
    for ax in axes:
        for i, (a, b) in enumerate(spans):
            ax.axvspan(a, b, color=SINGULAR_COLOR, alpha=0.15, lw=0,
                       label="near a singularity" if (i == 0 and ax is axes[0]) else None)
    if spans:
        axes[0].legend(fontsize=8, loc="best")


def plot_history(record: Any = None, *, t: Any = None, q: Any = None, dq: Any = None, error: Any = None,
                 singular_values: Any = None, dt: float | None = None, joint_names: Sequence[str] | None = None,
                 joint_types: Sequence[str] | None = None, log_error: bool = True, degrees: bool = False,
                 error_label: str = "error", time_label: str | None = None, sigma_min: Any = None,
                 singular: Any = None, singular_threshold: float | None = None) -> Any:
    """Time-series figure of a simulation / IK record: one panel per quantity given.

    Quantities come from keyword arguments or from ``record`` (an object or dict
    with ``t``/``time``, ``q``, ``dq``/``qd``, ``error``/``errors`` and
    ``singular_values``).  ``q``/``dq`` are (T, n) [rad, m]; ``error`` is (T,)
    norms or (T, k) vectors (plotted as their norm); ``singular_values`` (T, m).
    The x axis is time [s] when ``t`` or ``dt`` is known,
    else the iteration number.  Errors use a log scale unless ``log_error=False``.

    Singularities: ``sigma_min`` (T,), the smallest singular value of the
    controller's Jacobian, adds a log-scale panel with ``singular_threshold``
    drawn as a dashed line; ``singular`` (T,) bool marks the flagged steps with a
    red band on every panel. A :class:`~robokin.motion.SimulationLog` passed as
    ``record`` supplies all three (its ``sigma_min``, ``singular`` and
    ``singular_threshold`` fields), so ``plot_history(log)`` shows where a run
    came close to a singular configuration.

    Parameters
    ----------
    record : object or dict, optional
        Source of the quantities not given as keywords (see above).
    t : array_like, shape (T,), optional
        Sample times (s).
    q : array_like, shape (T, n), optional
        Joint positions (rad, m).
    dq : array_like, shape (T, n), optional
        Joint velocities (rad/s, m/s).
    error : array_like, shape (T,) or (T, k), optional
        Error norms, or error vectors (plotted as their norm).
    singular_values : array_like, shape (T, m), optional
        Singular values of the Jacobian.
    dt : float, optional
        Sampling period (s), when ``t`` is not known.
    joint_names : sequence of str, optional
        Legend labels of the joints.
    joint_types : sequence of str, optional
        ``"revolute"``/``"prismatic"`` per joint (units of the axes).
    log_error : bool, optional
        Log scale for the error panel.
    degrees : bool, optional
        Revolute joints in degrees.
    error_label : str, optional
        Name of the error on its axis.
    time_label : str, optional
        Label of the x axis.
    sigma_min : array_like, shape (T,), optional
        Smallest singular value of the controller's Jacobian.
    singular : array_like of bool, shape (T,), optional
        Steps flagged near a singularity.
    singular_threshold : float, optional
        The threshold drawn in the ``sigma_min`` panel.

    Returns
    -------
    matplotlib.figure.Figure
        One panel per quantity, sharing the x axis.

    Raises
    ------
    DomainError
        No quantity given or found, a quantity with no finite value, or values
        beyond :data:`PLOT_LIMIT`.
    ShapeError
        A quantity without samples, or lengths that differ.
    TypeError
        A quantity that is not numbers.
    """
    plt = optional.pyplot()

    q = q if q is not None else _get(record, "q", "qs", "joint_positions")
    dq = dq if dq is not None else _get(record, "dq", "qd", "q_dot", "joint_velocities")
    error = error if error is not None else _get(record, "error", "errors", "error_norm", "err")
    singular_values = singular_values if singular_values is not None else _get(record, "singular_values", "sigma")
    t = t if t is not None else _get(record, "t", "time", "times")
    sigma_min = sigma_min if sigma_min is not None else _get(record, "sigma_min")
    if sigma_min is not None and not np.isfinite(np.asarray(sigma_min, dtype=float)).any():
        sigma_min = None                       # a controller that reports no sigma_min: no panel
    singular = singular if singular is not None else _get(record, "singular")
    if singular_threshold is None:
        singular_threshold = _get(record, "singular_threshold")
    panels = [(k, v) for k, v in (("q", q), ("dq", dq), ("error", error), ("sv", singular_values),
                                  ("sigma_min", sigma_min)) if v is not None]
    if not panels:
        raise DomainError("plot_history needs at least one of q, dq, error, singular_values (none given or "
                          "found in record)")
    panels = [(kind, _history_values(kind, v)) for kind, v in panels]
    length = len(panels[0][1])
    if t is None and dt is not None:
        t = np.arange(length) * float(dt)
    if t is None:
        x, xlabel = np.arange(length), time_label or "iteration"
    else:
        x, xlabel = as_numbers(t, "t", f"sample times of shape ({length},)"), time_label or "time t [s]"
        if x.shape != (length,):
            raise ShapeError(f"t must have shape ({length},) (one time per sample of {panels[0][0]}); got shape "
                             f"{x.shape}")
    qunit, dqunit = _joint_units(joint_types, degrees)

    def conv(v):
        v = np.asarray(v, dtype=float)
        if not degrees:
            return v
        v = v.copy()
        rev = [i for i, jt in enumerate(joint_types or ["revolute"] * v.shape[-1]) if jt == "revolute"]
        if v.ndim == 2:
            v[:, rev] = np.rad2deg(v[:, rev])
        return v

    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(6.5, 2.2 * len(panels) + 0.6), squeeze=False)
    axes = axes[:, 0]
    for ax, (kind, values) in zip(axes, panels):
        v = np.asarray(values, dtype=float)
        if len(v) != length:
            raise ShapeError(f"{kind} has {len(v)} samples but {panels[0][0]} has {length}")
        if kind == "q":
            _series(ax, x, conv(v), joint_names, f"joint position q [{qunit}]")
        elif kind == "dq":
            _series(ax, x, conv(v), joint_names, f"joint velocity q̇ [{dqunit}]")
        elif kind == "error":
            if v.ndim == 2 and v.shape[1] > 1:
                v = np.linalg.norm(v, axis=1)
            _series(ax, x, np.maximum(np.abs(v), 1e-300) if log_error else v, None,
                    f"{error_label} (norm)", log=log_error)
        elif kind == "sigma_min":
            _series(ax, x, np.maximum(v, 1e-300), ["σ_min"], "smallest singular value σ_min of J", log=True)
            if singular_threshold is not None and np.isfinite(singular_threshold) and singular_threshold > 0:
                ax.axhline(singular_threshold, color=SINGULAR_COLOR, ls="--", lw=1,
                           label=f"threshold {singular_threshold:g}")
                ax.legend(fontsize=8, loc="best")
        else:
            _series(ax, x, v, [f"σ{k + 1}" for k in range(v.shape[1] if v.ndim == 2 else 1)],
                    "singular values σ of J", log=False)
    if singular is not None:
        _mark_singular(axes, x, singular, length)
    axes[-1].set_xlabel(xlabel)
    fig.tight_layout()
    return fig


def plot_scene(scene: SceneRecord, ax: Any = None, *, frames: bool | None = None) -> Any:
    """matplotlib version of a :class:`~robokin.views.Scene` (3D stick figures).

    Chains at their configuration (the first step of an animation), targets as
    triads, points as dots, paths and animation traces as lines, ellipsoids as their
    three principal ellipses.

    Parameters
    ----------
    scene : Scene
        The scene to draw.
    ax : matplotlib.axes.Axes, optional
        A 3D Axes to draw into; default a new figure.
    frames : bool, optional
        Draw a triad at every joint frame; default: as each chain item says.

    Returns
    -------
    matplotlib.axes.Axes
        The 3D Axes (equal scales, metres).

    Raises
    ------
    TypeError
        ``scene`` is not a :class:`~robokin.views.Scene`.
    """
    if not isinstance(scene, SceneRecord):
        raise TypeError(f"scene must be a robokin.views.Scene; got {type(scene).__name__}")
    if ax is None:
        ax = _new_axes("3d")
    pts = [np.zeros((1, 3))]
    L = scene_scale(scene)
    for it in scene.items:
        if isinstance(it, ChainItem):
            a = 1.0 if it.opacity == 1.0 else max(it.opacity, 0.25)
            color = None if it.color is None else f"#{it.color:06x}"
            pts.append(_draw_chain(ax, it.chain, it.q, alpha=a, color=color,
                                   frames=it.frames if frames is None else frames))
        elif isinstance(it, TargetItem):
            _draw_triad(ax, it.T, it.size or 0.18 * L)
            ax.plot(*it.T[:3, 3], "o", color="#FF00FF", ms=5)
            if it.label:
                ax.text(*it.T[:3, 3], f" {it.label}", fontsize=8)
            pts.append(it.T[None, :3, 3])
        elif isinstance(it, PointsItem):
            ax.plot(it.points[:, 0], it.points[:, 1], it.points[:, 2], "o", color=f"#{it.color:06x}",
                    markeredgecolor="k", ms=5)
            pts.append(it.points)
        elif isinstance(it, PathItem):
            ax.plot(it.points[:, 0], it.points[:, 1], it.points[:, 2], "-", color="0.3", lw=1.2)
            pts.append(it.points)
        elif isinstance(it, EllipsoidItem):
            for curve in ellipsoid_wireframe(it.radii, it.axes, it.center):
                ax.plot(curve[:, 0], curve[:, 1], curve[:, 2], "-", color=f"#{it.color:06x}", lw=1.2)
            pts.append(ellipsoid_box_points(it))
    for anim in scene.animations:
        item = scene.chain_item(anim.chain_name)
        if anim.trace:
            F = np.asarray([item.chain.frames(q)[-1] for q in anim.trajectory])
            ax.plot(F[:, 0, 3], F[:, 1, 3], F[:, 2, 3], "--", color="0.4", lw=1)
            pts.append(F[:, :3, 3])
    _set_equal_3d(ax, np.vstack(pts))
    return ax
