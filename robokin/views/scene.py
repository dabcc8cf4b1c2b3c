"""A recorded 3D scene: chains, ghosts, targets, points, paths and animations.

A :class:`Scene` only *records* what should be drawn; it imports neither MeshCat
nor matplotlib.  The backends turn the record into pictures:

- :mod:`robokin.views.meshcat_draw` lowers it to MeshCat commands, which are
  sent to a live MeshCat server (:mod:`robokin.views.live`) or packed into a
  static HTML snippet (:mod:`robokin.views.static_html`);
- :mod:`robokin.views.plots` draws it as a matplotlib stick figure.

:meth:`Scene.show` picks the backend (see :mod:`robokin.views` for the rules).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.views import arguments
from robokin.views.arguments import (
    MAX_PATH_POINTS,
    as_color,
    as_configuration,
    as_height,
    as_length,
    as_opacity,
    as_points,
    as_pose,
    as_time_step,
    as_times,
    as_trajectory,
    subsample,
)

__all__ = ["Scene", "show"]

DEFAULT_HEIGHT = 420


# --------------------------------------------------------------------------- items
@dataclass
class ChainItem:
    name: str
    chain: Any
    q: np.ndarray
    color: int | None = None
    opacity: float = 1.0
    frames: bool = False
    labels: bool = True
    ghost: bool = False
    meshes: Any = None          # robokin.models.urdf_meshes.RobotMeshes when drawn with meshes


@dataclass
class TargetItem:
    name: str
    T: np.ndarray
    size: float | None = None
    label: str | None = None


@dataclass
class PointsItem:
    name: str
    points: np.ndarray
    radius: float | None = None
    color: int = 0xFFD92F


@dataclass
class PathItem:
    name: str
    points: np.ndarray
    color: int = 0xFFFFFF


@dataclass
class AnimationItem:
    chain_name: str
    trajectory: np.ndarray
    times: np.ndarray
    trace: bool = True
    trace_color: int = 0xFFFF66


@dataclass
class _Options:
    height: int = DEFAULT_HEIGHT
    play: bool = True
    loop: bool = False
    grid: bool = True
    extra: dict = field(default_factory=dict)


STYLES = ("stick", "mesh")


def _resolve_meshes(chain, style, meshes):
    """The RobotMeshes to draw ``chain`` with (None: stick figure)."""
    if style is None:
        style = "stick" if meshes is None else "mesh"
    if style not in STYLES:
        raise DomainError(f"style must be one of {STYLES}; got {style!r}")
    if style == "stick":
        if meshes is not None:
            raise DomainError("meshes were given with style='stick'; use style='mesh' (or leave style out)")
        return None
    if meshes is None:
        from robokin.models.urdf import ROBOT_DESCRIPTIONS

        label = str(getattr(chain, "name", "")).lower()
        meshes = next((k for k in ROBOT_DESCRIPTIONS if label == k or label.startswith(k + "_")), None)
        if meshes is None:
            raise DomainError(
                f"style='mesh' needs meshes= for the chain {getattr(chain, 'name', '')!r}: a robot name "
                f"({', '.join(sorted(ROBOT_DESCRIPTIONS))}), the path of its URDF file, or "
                f"robokin.views.robot_meshes(urdf, chain)")
    if isinstance(meshes, str) or hasattr(meshes, "__fspath__"):
        from robokin.views.meshes import robot_meshes
        return robot_meshes(meshes, chain)
    frames = getattr(meshes, "frames", None)
    if frames is None or not hasattr(meshes, "unreadable"):
        raise TypeError(f"meshes must be a robot name, a URDF path or the result of robokin.views.robot_meshes; "
                        f"got {type(meshes).__name__}")
    if len(frames) != int(chain.n) + 2:
        raise ShapeError(f"meshes must have one entry per frame of the chain ({int(chain.n) + 2}); got "
                         f"{len(frames)}")
    return meshes


# --------------------------------------------------------------------------- scene
class Scene:
    """A backend-independent record of a 3D scene.

    Build it with the ``add_*`` methods and :meth:`animate`, then call
    :meth:`show` (live MeshCat, static HTML or matplotlib, chosen automatically),
    :meth:`to_html` (static HTML), :meth:`commands` (the MeshCat command list) or
    :meth:`plot` (matplotlib).

    >>> scene = Scene()
    >>> scene.add_chain(chain, q)              # doctest: +SKIP
    'robot'
    >>> scene.add_target(T_goal)               # doctest: +SKIP
    >>> scene.animate(chain, result.history, dt=0.05)   # doctest: +SKIP
    >>> scene.show()                           # doctest: +SKIP
    """

    def __init__(self, *, height: int = DEFAULT_HEIGHT, grid: bool = True):
        self.items: list = []
        self.animations: list[AnimationItem] = []
        self.options = _Options(height=as_height(height), grid=bool(grid))
        self._live = None          # robokin.views.live.LiveViewer, once shown live

    # ---- naming
    def _name(self, name, stem):
        taken = {it.name for it in self.items}
        if name is None:
            k = 1
            name = stem
            while name in taken:
                k += 1
                name = f"{stem}_{k}"
            return name
        if not isinstance(name, str):
            raise TypeError(f"name must be a str (or None for a default); got {type(name).__name__} {name!r}")
        if not name or "/" in name:
            raise DomainError(f"name must be a non-empty string without '/'; got {name!r}")
        if name in taken:
            raise DomainError(f"name {name!r} is already used in this scene")
        return name

    def item(self, name):
        """The recorded item called ``name`` (KeyError if there is none)."""
        for it in self.items:
            if it.name == name:
                return it
        raise KeyError(f"no item named {name!r} in this scene; names: {[it.name for it in self.items]}")

    # ---- adding things
    def add_chain(self, chain, q=None, *, name=None, color=None, opacity=1.0, frames=False, labels=True,
                  style=None, meshes=None):
        """Draw ``chain`` at configuration ``q`` (default: mid-limits / zeros).

        ``frames=True`` adds a triad at every joint frame (with text labels when
        ``labels`` is true).  Returns the item name (default ``"robot"``).
        Raises ValueError if all links of the chain have zero length.

        ``style`` is ``"stick"`` (the default: cylinders between the frame
        origins) or ``"mesh"``: the robot's visual meshes from its URDF, moved by
        the chain's frames. ``meshes`` says which: a robot name (``"ur10"``,
        ``"baxter"``, ``"panda"``), the path of a URDF file, or the result of
        :func:`robokin.views.robot_meshes`; given alone it implies
        ``style="mesh"``; left out with ``style="mesh"``, the chain's name
        picks the robot (``models.ur10()``, ``models.panda()``,
        ``models.baxter_left()``). Needs ``pip install 'robokin[robots]'``.
        ``views.show(models.ur10(), q, meshes="ur10")`` is the short form.
        """
        from robokin.views.meshcat_draw import chain_layout  # numpy only

        q = as_configuration(chain, q)
        layout = chain_layout(chain, q)  # validates (zero-length chain -> DomainError)
        if not layout["reach"] <= arguments.MAX_COORDINATE:
            raise DomainError(f"chain: its reach of {layout['reach']:.3g} m is more than a scene draws "
                              f"({arguments.MAX_COORDINATE:g} m)")
        opacity = as_opacity(opacity)
        color = None if color is None else as_color(color)
        item_name = self._name(name, "robot")
        resolved = _resolve_meshes(chain, style, meshes)
        item = ChainItem(item_name, chain, q, color, opacity, bool(frames), bool(labels), meshes=resolved)
        self.items.append(item)
        return item.name

    def add_ghost(self, chain, q, *, name=None, color=0xB0C4DE, opacity=0.3, style=None, meshes=None):
        """A translucent copy of ``chain`` at ``q`` (e.g. another IK solution); ``style``/``meshes``
        as in :meth:`add_chain`."""
        name = self.add_chain(chain, q, name=self._name(name, "ghost"), color=color, opacity=opacity,
                              style=style, meshes=meshes)
        self.items[-1].ghost = True
        return name

    def add_target(self, T, *, name=None, size=None, label=None):
        """A target frame: a triad at the pose ``T``.

        ``T`` is a rigid transform (4, 4) (rotation part a rotation matrix, bottom
        row [0, 0, 0, 1]; DomainError otherwise) or a (3,) position; ``size`` the
        triad's length in metres (default: from the scene's scale).
        """
        if size is not None:
            size = as_length(size, "size")
        if label is not None and not isinstance(label, str):
            raise TypeError(f"label must be a str or None; got {type(label).__name__}")
        item = TargetItem(self._name(name, "target"), as_pose(T), size, label)
        self.items.append(item)
        return item.name

    def add_points(self, points, *, name=None, radius=None, color=0xFFD92F):
        """Spheres at the rows of ``points`` (N, 3), N >= 1, in metres (``radius`` in metres).

        More than 500 points are drawn as one point cloud (a square of side
        2 ``radius`` facing the camera at each point), which a page stores in 12
        bytes per point.
        At most :data:`~robokin.views.arguments.MAX_POINTS` (100 000) points are
        kept: more are subsampled evenly, with a :class:`~robokin.errors.ViewWarning`.
        """
        if radius is not None:
            radius = as_length(radius, "radius")
        item = PointsItem(self._name(name, "points"), as_points(points, "points"), radius, as_color(color))
        self.items.append(item)
        return item.name

    def add_path(self, points, *, name=None, color=0xFFFFFF):
        """A polyline through the rows of ``points`` (N, 3), N >= 2, in metres.

        At most :data:`~robokin.views.arguments.MAX_PATH_POINTS` (100 000) points
        are kept: more are subsampled evenly (ends kept), with a
        :class:`~robokin.errors.ViewWarning`.
        """
        pts = as_points(points, "points", minimum=2, cap=arguments.MAX_PATH_POINTS)
        item = PathItem(self._name(name, "path"), pts, as_color(color))
        self.items.append(item)
        return item.name

    def animate(self, chain, trajectory, dt=0.05, *, times=None, trace=True, name=None,
                trace_color=0xFFFF66, play=True, loop=False):
        """Animate a chain along ``trajectory`` (T, n), one row every ``dt`` seconds.

        ``chain`` is either a chain (added to the scene at ``trajectory[0]`` unless
        a chain item called ``name`` exists) or the name of a chain item already in
        the scene.  ``times`` (T,) overrides ``dt`` for non-uniform samples.  With
        ``trace=True`` the end-effector path is drawn as a line.  The viewer shows
        play / pause / reset and a time slider under *Animations* in its controls.
        At most :data:`~robokin.views.arguments.MAX_ANIMATION_STEPS` (20 000)
        steps are kept: a longer trajectory is subsampled in time (first and last
        step kept, their times kept), with a :class:`~robokin.errors.ViewWarning`.
        """
        if isinstance(chain, str):
            items = [it for it in self.items if isinstance(it, ChainItem) and it.name == chain]
            if not items:
                raise DomainError(f"chain: no chain item named {chain!r} in this scene; chain items: "
                                  f"{[it.name for it in self.items if isinstance(it, ChainItem)]}")
            item = items[0]
        else:
            existing = [it for it in self.items if isinstance(it, ChainItem) and
                        (it.name == name or (name is None and it.chain is chain and not it.ghost))]
            Q = as_trajectory(chain, trajectory)
            if existing:
                item = existing[0]
            else:
                self.add_chain(chain, Q[0], name=name)
                item = self.items[-1]
        Q = as_trajectory(item.chain, trajectory)
        if times is None:
            t = np.arange(Q.shape[0]) * as_time_step(dt)
        else:
            t = as_times(times, Q.shape[0])
        if t[-1] > arguments.MAX_DURATION:
            raise DomainError(f"{'dt' if times is None else 'times'}: the animation would last {t[-1]:.3g} s, "
                              f"more than a scene plays ({arguments.MAX_DURATION:g} s)")
        if len(t) > arguments.MAX_ANIMATION_STEPS:
            keep = subsample(np.arange(len(t)), arguments.MAX_ANIMATION_STEPS, "trajectory", "steps")
            Q, t = Q[keep], t[keep]
        trace_color = as_color(trace_color, "trace_color")
        if any(a.chain_name == item.name for a in self.animations):
            raise DomainError(f"chain item {item.name!r} is already animated")
        item.q = Q[0].copy()
        self.animations.append(AnimationItem(item.name, Q, t, bool(trace), trace_color))
        self.options.play = bool(play)
        self.options.loop = bool(loop)
        return item.name

    # ---- updating (live)
    def set_configuration(self, name, q):
        """Move chain item ``name`` to ``q``; pushes only transforms to a live viewer."""
        item = self.item(name)
        item.q = as_configuration(item.chain, q)
        if self._live is not None:
            from robokin.views.meshcat_draw import chain_transforms
            self._live.send_transforms(chain_transforms(item.name, item.chain, item.q))

    # ---- outputs
    def scale(self) -> float:
        """A characteristic length of the scene in metres (the largest reach)."""
        from robokin.views.meshcat_draw import scene_scale
        return scene_scale(self)

    def commands(self) -> list[dict]:
        """The MeshCat commands (dicts, as sent to the viewer) that draw the scene."""
        from robokin.views.meshcat_draw import scene_commands
        return scene_commands(self)

    def to_html(self, *, height=None, viewer_src=None) -> str:
        """Static HTML (no server, no network) that renders the scene interactively.

        The MeshCat viewer script is *not* inlined: it is loaded from
        ``<content root>_static/meshcat/main.min.js`` (put there by
        :mod:`robokin.views.sphinx_extension`), or from ``viewer_src`` if given.
        """
        from robokin.views.static_html import scene_html
        return scene_html(self.commands(), height=self.options.height if height is None else as_height(height),
                          animated=bool(self.animations), viewer_src=viewer_src)

    def _repr_html_(self):
        return self.to_html()

    def save(self, path, *, copy_viewer=True):
        """Write a standalone HTML page (plus ``_static/meshcat/main.min.js`` next to it)."""
        from robokin.views.static_html import save_page
        return save_page(path, [self], copy_viewer=copy_viewer)

    def plot(self, ax=None, **kwargs):
        """Matplotlib stick figure of the scene (first configuration of animations)."""
        from robokin.views.plots import plot_scene
        return plot_scene(self, ax=ax, **kwargs)

    def show(self, mode=None, *, height=None):
        """Display the scene: ``mode`` is ``"live"``, ``"static"``, ``"matplotlib"`` or None (automatic).

        See :mod:`robokin.views` for how the mode is chosen.  Returns None (so that
        notebook outputs stay deterministic); in live mode the viewer is kept in
        ``scene.viewer``.
        """
        from robokin.views.display import show_scene
        show_scene(self, mode=mode, height=height)

    @property
    def viewer(self):
        """The live viewer this scene was last shown in (None if never shown live)."""
        return self._live

    def __repr__(self):
        kinds = ", ".join(f"{type(it).__name__[:-4].lower()} {it.name!r}" for it in self.items)
        return f"<robokin.views.Scene: {kinds or 'empty'}; {len(self.animations)} animation(s)>"


def show(chain=None, q=None, *, targets=(), points=None, path=None, ghosts=(), trajectory=None,
         dt=0.05, frames=False, mode=None, height=None, style=None, meshes=None):
    """Show a chain (and friends) in one call; returns None.

    ``targets`` are 4x4 poses, ``ghosts`` configurations drawn translucent,
    ``trajectory`` a (T, n) joint trajectory animated every ``dt`` seconds.
    ``style``/``meshes`` draw the chain with its real meshes, e.g.
    ``show(models.ur10(), q, meshes="ur10")`` (see :meth:`Scene.add_chain`;
    ghosts stay stick figures).
    Equivalent to building a :class:`Scene` and calling :meth:`Scene.show`.
    """
    if trajectory is not None:
        if chain is None:
            raise DomainError("trajectory needs a chain: show(chain, trajectory=...)")
        trajectory = as_trajectory(chain, trajectory)
    scene = Scene(height=DEFAULT_HEIGHT if height is None else height)
    if chain is not None:
        scene.add_chain(chain, q if q is not None or trajectory is None else trajectory[0],
                        frames=frames, style=style, meshes=meshes)
        for k, g in enumerate(_as_list(ghosts, "ghosts")):
            scene.add_ghost(chain, as_configuration(chain, g, f"ghosts[{k}]"))
    elif q is not None or ghosts:
        raise DomainError("q and ghosts need a chain: show(chain, q, ghosts=...)")
    for k, T in enumerate(_as_list(targets, "targets", stacked=3)):
        scene.add_target(as_pose(T, f"targets[{k}]"))
    if points is not None:
        scene.add_points(points)
    if path is not None:
        scene.add_path(path)
    if trajectory is not None:
        scene.animate("robot", trajectory, dt=dt)
    scene.show(mode=mode, height=height)


def _as_list(items, name, stacked=2):
    """``items`` as a list of entries: a sequence, or an array whose first axis lists them
    (an array of ``stacked - 1`` dimensions is one entry)."""
    if isinstance(items, (str, bytes, dict)) or items is None:
        raise TypeError(f"{name} must be a sequence; got {type(items).__name__} {items!r}"[:200])
    if isinstance(items, np.ndarray):
        return [items] if items.ndim < stacked else list(items)
    return list(items)
