"""A recorded 3D scene: chains, ghosts, targets, points, paths, ellipsoids and animations.

A :class:`Scene` only *records* what should be drawn; it imports neither MeshCat
nor matplotlib.  The backends turn the record into pictures:

- :mod:`robokin.views.meshcat_draw` lowers it to MeshCat commands, which are
  sent to a live MeshCat server (:mod:`robokin.views.live`) or packed into a
  static HTML snippet (:mod:`robokin.views.static_html`);
- :mod:`robokin.views.plots` draws it as a matplotlib stick figure.

:meth:`Scene.show` picks the backend (see :mod:`robokin.views` for the rules).
"""

from __future__ import annotations

from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from robokin.chains.protocol import DrawableChain
from robokin.errors import DomainError, ShapeError
from robokin.models.urdf import ROBOT_DESCRIPTIONS
from robokin.models.urdf_meshes import RobotMeshes
from robokin.views import arguments
from robokin.views.arguments import (
    as_color,
    as_configuration,
    as_height,
    as_length,
    as_numbers,
    as_opacity,
    as_points,
    as_pose,
    as_time_step,
    as_times,
    as_trajectory,
    subsample,
)
from robokin.views.display import show_scene
from robokin.views.geometry import chain_layout, scene_scale
from robokin.views.live import LiveViewer
from robokin.views.meshcat_draw import chain_transforms, scene_commands
from robokin.views.meshes import robot_meshes
from robokin.views.plots import plot_scene
from robokin.views.record import (
    DEFAULT_HEIGHT,
    AnimationItem,
    ChainItem,
    EllipsoidItem,
    PathItem,
    PointsItem,
    SceneOptions,
    SceneRecord,
    TargetItem,
)
from robokin.views.static_html import save_page, scene_html

__all__ = ["Scene", "show"]

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
        label = str(getattr(chain, "name", "")).lower()
        meshes = next((k for k in ROBOT_DESCRIPTIONS if label == k or label.startswith(k + "_")), None)
        if meshes is None:
            raise DomainError(
                f"style='mesh' needs meshes= for the chain {getattr(chain, 'name', '')!r}: a robot name "
                f"({', '.join(sorted(ROBOT_DESCRIPTIONS))}), the path of its URDF file, or "
                f"robokin.views.robot_meshes(urdf, chain)")
    if isinstance(meshes, str) or hasattr(meshes, "__fspath__"):
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
class Scene(SceneRecord):
    """A backend-independent record of a 3D scene.

    Build it with the ``add_*`` methods and :meth:`animate`, then call
    :meth:`show` (live MeshCat, static HTML or matplotlib, chosen automatically),
    :meth:`to_html` (static HTML), :meth:`commands` (the MeshCat command list) or
    :meth:`plot` (matplotlib).

    Parameters
    ----------
    height : int, optional
        Height in CSS pixels, in [100, 4000].
    grid : bool, optional
        Draw the floor grid: a square of 40 × 40 cells, 2.5 times the scene's half
        diagonal wide, under the scene's centre at the height of its lowest point
        (z = 0 for a robot standing on the floor).

    Attributes
    ----------
    items : list
        The recorded items (:class:`~robokin.views.record.ChainItem`, ...), in order.
    animations : list of AnimationItem
        The recorded animations.
    options : SceneOptions
        Height, grid, play and loop.

    Examples
    --------
    >>> scene = Scene()
    >>> scene.add_chain(chain, q)              # doctest: +SKIP
    'robot'
    >>> scene.add_target(T_goal)               # doctest: +SKIP
    >>> scene.animate(chain, result.history, dt=0.05)   # doctest: +SKIP
    >>> scene.show()                           # doctest: +SKIP
    """

    def __init__(self, *, height: int = DEFAULT_HEIGHT, grid: bool = True) -> None:
        super().__init__(SceneOptions(height=as_height(height), grid=bool(grid)))
        self._live: LiveViewer | None = None          # once shown live

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

    # ---- adding things
    def add_chain(self, chain: DrawableChain, q: Any = None, *, name: str | None = None, color: Any = None,
                  opacity: float = 1.0, frames: bool = False, labels: bool = True, style: str | None = None,
                  meshes: str | PathLike | RobotMeshes | None = None) -> str:
        """Draw ``chain`` at configuration ``q``.

        ``style`` is ``"stick"`` (the default: cylinders between the frame
        origins) or ``"mesh"``: the robot's visual meshes from its URDF, moved by
        the chain's frames. ``meshes`` says which: a robot name (``"ur10"``,
        ``"baxter"``, ``"panda"``), the path of a URDF file, or the result of
        :func:`robokin.views.robot_meshes`; given alone it implies
        ``style="mesh"``; left out with ``style="mesh"``, the chain's name
        picks the robot (``models.ur10()``, ``models.panda()``,
        ``models.baxter_left()``). Needs ``pip install 'robokin[robots]'``.
        ``views.show(models.ur10(), q, meshes="ur10")`` is the short form.

        Parameters
        ----------
        chain : SerialChain
            The chain (any object with ``n``, ``frames(q)``, ``joint_axes``,
            ``joint_types`` and ``limits``).
        q : array_like, shape (n,), optional
            Configuration (rad for revolute, m for prismatic joints); default
            zeros, moved into the joint limits.
        name : str, optional
            Item name, unique in the scene, without ``/``; default ``"robot"``
            (then ``"robot_2"``, ...).
        color : int, optional
            One colour ``0xRRGGBB`` for every part; default the link, joint and
            end-effector colours.
        opacity : float, optional
            In (0, 1]; below 1 the chain is translucent.
        frames : bool, optional
            Add a triad at every joint frame.
        labels : bool, optional
            Label those triads with the frame names.
        style : {"stick", "mesh"}, optional
            See above.
        meshes : str, os.PathLike or RobotMeshes, optional
            See above.

        Returns
        -------
        str
            The item's name.

        Raises
        ------
        ShapeError
            ``q`` does not have n entries.
        DomainError
            All links of the chain have zero length, its reach is beyond
            :data:`~robokin.views.arguments.MAX_COORDINATE`, ``name`` is taken or
            invalid, ``opacity`` is outside (0, 1], or ``style``/``meshes`` do not
            fit the chain.
        TypeError
            ``name`` is not a str, ``color`` not an int, or ``meshes`` of another type.
        """
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

    def add_ghost(self, chain: DrawableChain, q: Any, *, name: str | None = None, color: Any = 0xB0C4DE,
                  opacity: float = 0.3, style: str | None = None,
                  meshes: str | PathLike | RobotMeshes | None = None) -> str:
        """A translucent copy of ``chain`` at ``q`` (e.g. another IK solution).

        Parameters
        ----------
        chain : SerialChain
            The chain.
        q : array_like, shape (n,)
            Configuration (rad, m).
        name : str, optional
            Item name; default ``"ghost"`` (then ``"ghost_2"``, ...).
        color : int, optional
            Colour ``0xRRGGBB`` of every part (default light steel blue).
        opacity : float, optional
            In (0, 1].
        style, meshes : optional
            As in :meth:`add_chain`.

        Returns
        -------
        str
            The item's name.

        Raises
        ------
        ShapeError, DomainError, TypeError
            As :meth:`add_chain`.
        """
        name = self.add_chain(chain, q, name=self._name(name, "ghost"), color=color, opacity=opacity,
                              style=style, meshes=meshes)
        self.chain_item(name).ghost = True
        return name

    def add_target(self, T: Any, *, name: str | None = None, size: float | None = None,
                   label: str | None = None) -> str:
        """A target frame: a triad at the pose ``T``.

        Parameters
        ----------
        T : array_like, shape (4, 4) or (3,)
            A rigid transform (rotation part a rotation matrix, bottom row
            ``[0, 0, 0, 1]``; position in m), or a position (m) with the base
            frame's orientation.
        name : str, optional
            Item name; default ``"target"`` (then ``"target_2"``, ...).
        size : float, optional
            The triad's length (m); default 0.18 times the scene's scale.
        label : str, optional
            Text shown next to the triad.

        Returns
        -------
        str
            The item's name.

        Raises
        ------
        ShapeError
            ``T`` has another shape.
        DomainError
            ``T`` is not a rigid transform, holds NaN/inf, ``size`` is not
            positive, or ``name`` is taken.
        TypeError
            ``label`` is not a str.
        """
        if size is not None:
            size = as_length(size, "size")
        if label is not None and not isinstance(label, str):
            raise TypeError(f"label must be a str or None; got {type(label).__name__}")
        item = TargetItem(self._name(name, "target"), as_pose(T), size, label)
        self.items.append(item)
        return item.name

    def add_points(self, points: Any, *, name: str | None = None, radius: float | None = None,
                   color: Any = 0xFFD92F) -> str:
        """Spheres at the rows of ``points``.

        More than 500 points are drawn as one point cloud (a square of side
        2 ``radius`` facing the camera at each point), which a page stores in 12
        bytes per point.
        At most :data:`~robokin.views.arguments.MAX_POINTS` (100 000) points are
        kept: more are subsampled evenly, with a :class:`~robokin.errors.ViewWarning`.

        Parameters
        ----------
        points : array_like, shape (N, 3) or (N, 2)
            Positions (m), N >= 1; rows of two get z = 0.
        name : str, optional
            Item name; default ``"points"``.
        radius : float, optional
            Sphere radius (m); default 0.02 times the scene's scale.
        color : int, optional
            ``0xRRGGBB`` (default yellow).

        Returns
        -------
        str
            The item's name.

        Raises
        ------
        ShapeError
            ``points`` is not (N, 3) or (N, 2) with N >= 1.
        DomainError
            NaN/inf or coordinates beyond :data:`~robokin.views.arguments.MAX_COORDINATE`,
            a radius that is not positive, a colour outside [0, 0xFFFFFF] or a taken name.
        TypeError
            ``color`` is not an int.
        """
        if radius is not None:
            radius = as_length(radius, "radius")
        item = PointsItem(self._name(name, "points"), as_points(points, "points"), radius, as_color(color))
        self.items.append(item)
        return item.name

    def add_path(self, points: Any, *, name: str | None = None, color: Any = 0xFFFFFF) -> str:
        """A polyline through the rows of ``points``.

        At most :data:`~robokin.views.arguments.MAX_PATH_POINTS` (100 000) points
        are kept: more are subsampled evenly (ends kept), with a
        :class:`~robokin.errors.ViewWarning`.

        Parameters
        ----------
        points : array_like, shape (N, 3) or (N, 2)
            Vertices in order (m), N >= 2; rows of two get z = 0.
        name : str, optional
            Item name; default ``"path"``.
        color : int, optional
            ``0xRRGGBB`` (default white).

        Returns
        -------
        str
            The item's name.

        Raises
        ------
        ShapeError
            ``points`` is not (N, 3) or (N, 2) with N >= 2.
        DomainError
            NaN/inf or coordinates beyond :data:`~robokin.views.arguments.MAX_COORDINATE`,
            a colour outside [0, 0xFFFFFF] or a taken name.
        TypeError
            ``color`` is not an int.
        """
        pts = as_points(points, "points", minimum=2, cap=arguments.MAX_PATH_POINTS)
        item = PathItem(self._name(name, "path"), pts, as_color(color))
        self.items.append(item)
        return item.name

    def add_ellipsoid(self, center: Any, radii: Any, axes: Any, *, name: str | None = None,
                      color: Any = 0x1F77B4, opacity: float = 0.4) -> str:
        r"""A solid ellipsoid: the points :math:`\mathbf{c} + \mathbf{A}\,\mathrm{diag}(\mathbf{r})\,\mathbf{s}`,
        :math:`\|\mathbf{s}\| \le 1`.

        ``radii`` and ``axes`` are what :meth:`~robokin.chains.SerialChain.velocity_ellipsoid`
        and :meth:`~robokin.chains.SerialChain.force_ellipsoid` return, times the drawing's
        scale (m per m/s, m per N, ...), so that a velocity ellipsoid is drawn at the tool with::

            radii, axes = chain.velocity_ellipsoid(q)
            scene.add_ellipsoid(chain.fk(q)[:3, 3], 0.2 * radii, axes)   # 0.2 m per m/s

        MeshCat draws its unit sphere moved by the transform
        :math:`\mathbf{A}\,\mathrm{diag}(\mathbf{r})` and the centre
        (:func:`~robokin.views.meshcat_draw.ellipsoid_transform`); a zero semi-axis (a velocity
        ellipsoid at a singularity) is drawn as a flat disc, 10⁻³ times the longest semi-axis
        thick. An infinite semi-axis (a force ellipsoid at a singularity: any force along it is
        held with no torque) cannot be drawn and raises :class:`~robokin.errors.DomainError`;
        clip it first, e.g. ``np.minimum(radii, 0.5)``, and say so in the figure's text.

        Parameters
        ----------
        center : array_like, shape (3,)
            The centre in the base frame (m), e.g. the tool position ``chain.fk(q)[:3, 3]``.
        radii : array_like, shape (3,)
            The semi-axes (m), finite and ≥ 0, at least one positive; in the order of the
            columns of ``axes`` (robokin's ellipsoids give them descending).
        axes : array_like, shape (3, 3)
            Orthonormal unit axes as the columns, in the base frame (a reflection,
            ``det = -1``, is accepted: it draws the same ellipsoid).
        name : str, optional
            Item name; default ``"ellipsoid"`` (then ``"ellipsoid_2"``, ...).
        color : int, optional
            ``0xRRGGBB`` (default blue).
        opacity : float, optional
            In (0, 1]; the default 0.4 shows the robot through it.

        Returns
        -------
        str
            The item's name.

        Raises
        ------
        ShapeError
            ``center``, ``radii`` or ``axes`` of another shape.
        DomainError
            NaN, a negative or infinite radius, radii all zero, axes that are not orthonormal
            (:math:`\mathbf{A}^\mathsf{T}\mathbf{A} \ne \mathbf{I}` within 10⁻⁶), an ellipsoid
            reaching beyond :data:`~robokin.views.arguments.MAX_COORDINATE`, an opacity outside
            (0, 1], a colour outside [0, 0xFFFFFF] or a taken name.
        TypeError
            Arguments that are not numbers, or ``color`` not an int.
        """
        c = as_numbers(center, "center", "a position of shape (3,)")
        if c.shape != (3,):
            raise ShapeError(f"center must have shape (3,) (a position in m); got shape {c.shape}")
        r = _as_radii(radii)
        A = as_numbers(axes, "axes", "unit axes as the columns of a (3, 3) array")
        if A.shape != (3, 3):
            raise ShapeError(f"axes must have shape (3, 3) (unit axes as columns); got shape {A.shape}")
        defect = float(np.abs(A.T @ A - np.eye(3)).max())
        if defect > 1e-6:
            raise DomainError(f"axes must hold orthonormal unit axes as its columns (axesᵀ axes = I within 1e-06); "
                              f"got axesᵀ axes - I with max |entry| {defect:.3g}")
        reach = np.abs(c) + np.linalg.norm(A * r, axis=1)
        if reach.max() > arguments.MAX_COORDINATE:
            raise DomainError(f"center and radii: the ellipsoid reaches {reach.max():.3g} m from the origin, more "
                              f"than a scene draws ({arguments.MAX_COORDINATE:g} m)")
        item = EllipsoidItem(self._name(name, "ellipsoid"), c.copy(), r, A.copy(), as_color(color),
                             as_opacity(opacity))
        self.items.append(item)
        return item.name

    def animate(self, chain: DrawableChain | str, trajectory: Any, dt: float = 0.05, *, times: Any = None,
                trace: bool = True, name: str | None = None, trace_color: Any = 0xFFFF66, play: bool = True,
                loop: bool = False) -> str:
        """Animate a chain along ``trajectory``, one row every ``dt`` seconds.

        ``chain`` is either a chain (added to the scene at ``trajectory[0]`` unless
        a chain item called ``name`` exists) or the name of a chain item already in
        the scene.  ``times`` (T,) overrides ``dt`` for non-uniform samples.  With
        ``trace=True`` the end-effector path is drawn as a line.  The viewer shows
        play / pause / reset and a time slider under *Animations* in its controls.
        At most :data:`~robokin.views.arguments.MAX_ANIMATION_STEPS` (20 000)
        steps are kept: a longer trajectory is subsampled in time (first and last
        step kept, their times kept), with a :class:`~robokin.errors.ViewWarning`.

        Parameters
        ----------
        chain : SerialChain or str
            A chain, or the name of a chain item of the scene.
        trajectory : array_like, shape (T, n)
            One configuration per step (rad, m).
        dt : float, optional
            Time between steps (s), positive.
        times : array_like, shape (T,), optional
            Time of each step (s), strictly increasing (shifted to start at 0);
            overrides ``dt``.
        trace : bool, optional
            Draw the end-effector's path.
        name : str, optional
            The chain item to animate (or to create).
        trace_color : int, optional
            Colour ``0xRRGGBB`` of the trace.
        play : bool, optional
            Start playing when the scene opens.
        loop : bool, optional
            Repeat the animation.

        Returns
        -------
        str
            The animated chain item's name.

        Raises
        ------
        ShapeError
            ``trajectory`` is not (T, n) or ``times`` not (T,).
        DomainError
            No chain item ``chain``, the item is already animated, ``dt`` is not
            positive, ``times`` do not increase, or the animation lasts more than
            :data:`~robokin.views.arguments.MAX_DURATION`.
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
                item = self.chain_item(self.add_chain(chain, Q[0], name=name))
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
    def set_configuration(self, name: str, q: Any) -> None:
        """Move chain item ``name`` to ``q``; pushes only transforms to a live viewer.

        Parameters
        ----------
        name : str
            A chain item's name.
        q : array_like, shape (n,)
            Configuration (rad, m).

        Raises
        ------
        KeyError
            No chain item ``name``.
        ShapeError
            ``q`` does not have n entries.
        """
        item = self.chain_item(name)
        item.q = as_configuration(item.chain, q)
        if self._live is not None:
            self._live.send_transforms(chain_transforms(item.name, item.chain, item.q))

    # ---- outputs
    def scale(self) -> float:
        """A characteristic length of the scene (the largest reach).

        Returns
        -------
        float
            In metres (see :func:`~robokin.views.geometry.scene_scale`).
        """
        return scene_scale(self)

    def commands(self) -> list[dict]:
        """The MeshCat commands that draw the scene.

        Returns
        -------
        list of dict
            As sent to the viewer (:func:`~robokin.views.meshcat_draw.scene_commands`).
        """
        return scene_commands(self)

    def to_html(self, *, height: int | None = None, viewer_src: str | None = None) -> str:
        """Static HTML (no server, no network) that renders the scene interactively.

        The MeshCat viewer script is *not* inlined: it is loaded from
        ``<content root>_static/meshcat/main.min.js`` (put there by
        :mod:`robokin.views.sphinx_extension`), or from ``viewer_src`` if given.

        Parameters
        ----------
        height : int, optional
            CSS pixels; default the scene's height.
        viewer_src : str, optional
            URL of MeshCat's ``main.min.js``.

        Returns
        -------
        str
            The HTML snippet (:func:`~robokin.views.static_html.scene_html`).
        """
        return scene_html(self.commands(), height=self.options.height if height is None else as_height(height),
                          animated=bool(self.animations), viewer_src=viewer_src)

    def _repr_html_(self):
        return self.to_html()

    def save(self, path: str | PathLike, *, copy_viewer: bool = True) -> Path:
        """Write a standalone HTML page (plus ``_static/meshcat/main.min.js`` next to it).

        Parameters
        ----------
        path : str or os.PathLike
            The page's file.
        copy_viewer : bool, optional
            Copy MeshCat's viewer script next to the page.

        Returns
        -------
        pathlib.Path
            ``path`` (see :func:`robokin.views.save_page`).
        """
        return save_page(path, [self], copy_viewer=copy_viewer)

    def plot(self, ax: Any = None, **kwargs: Any) -> Any:
        """Matplotlib stick figure of the scene (first configuration of animations).

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            A 3D Axes to draw into; default a new figure.
        **kwargs
            Passed to :func:`robokin.views.plot_scene` (``frames``).

        Returns
        -------
        matplotlib.axes.Axes
        """
        return plot_scene(self, ax=ax, **kwargs)

    def show(self, mode: str | None = None, *, height: int | None = None) -> None:
        """Display the scene live, statically or as a matplotlib figure.

        See :mod:`robokin.views` for how the mode is chosen.  Returns None (so that
        notebook outputs stay deterministic); in live mode the viewer is kept in
        ``scene.viewer``.

        Parameters
        ----------
        mode : {"live", "static", "matplotlib"}, optional
            Default: ``ROBOKIN_VIEWER``, else automatic.
        height : int, optional
            CSS pixels; default the scene's height.

        Raises
        ------
        ValueError
            An unknown ``mode``, or a ``height`` outside [100, 4000] (DomainError).
        TypeError
            ``height`` is not an int.
        """
        show_scene(self, mode=mode, height=height)

    @property
    def viewer(self) -> LiveViewer | None:
        """The live viewer this scene was last shown in (None if never shown live)."""
        return self._live

    def attach_viewer(self, viewer: LiveViewer) -> None:
        """Record ``viewer`` as the live viewer showing this scene (:func:`~robokin.views.display.show_live`).

        Parameters
        ----------
        viewer : LiveViewer
            A running viewer that holds this scene's commands.
        """
        self._live = viewer

    def detach_viewer(self) -> None:
        """Stop this scene's live viewer, if any (its later :meth:`show` starts a new one)."""
        if self._live is not None:
            self._live.close()
            self._live = None

    def __repr__(self) -> str:
        kinds = ", ".join(f"{type(it).__name__[:-4].lower()} {it.name!r}" for it in self.items)
        return f"<robokin.views.Scene: {kinds or 'empty'}; {len(self.animations)} animation(s)>"


def show(chain: DrawableChain | None = None, q: Any = None, *, targets: Sequence | np.ndarray = (), points: Any = None,
         path: Any = None, ghosts: Sequence | np.ndarray = (), trajectory: Any = None, dt: float = 0.05,
         frames: bool = False, mode: str | None = None, height: int | None = None, style: str | None = None,
         meshes: str | PathLike | RobotMeshes | None = None) -> None:
    """Show a chain (and friends) in one call; returns None.

    ``style``/``meshes`` draw the chain with its real meshes, e.g.
    ``show(models.ur10(), q, meshes="ur10")`` (see :meth:`Scene.add_chain`;
    ghosts stay stick figures).
    Equivalent to building a :class:`Scene` and calling :meth:`Scene.show`.

    Parameters
    ----------
    chain : SerialChain, optional
        The chain to draw (item ``"robot"``).
    q : array_like, shape (n,), optional
        Its configuration (rad, m); default the trajectory's first row, else zeros
        moved into the joint limits.
    targets : sequence of array_like of shape (4, 4) or (3,), or array, shape (K, 4, 4)
        Target poses (m).
    points : array_like, shape (N, 3), optional
        Points drawn as spheres (m).
    path : array_like, shape (N, 3), optional
        A polyline (m).
    ghosts : sequence of array_like of shape (n,), or array, shape (K, n)
        Configurations drawn translucent (rad, m).
    trajectory : array_like, shape (T, n), optional
        A joint trajectory, animated every ``dt`` seconds.
    dt : float, optional
        Time between trajectory rows (s).
    frames : bool, optional
        A triad at every joint frame.
    mode : {"live", "static", "matplotlib"}, optional
        As in :meth:`Scene.show`.
    height : int, optional
        CSS pixels.
    style, meshes : optional
        As in :meth:`Scene.add_chain`.

    Raises
    ------
    ShapeError, DomainError, TypeError
        As the :class:`Scene` methods; ``q``, ``ghosts`` or ``trajectory``
        without a chain is a DomainError.

    See Also
    --------
    Scene.save : the same view saved to a file.

    Notes
    -----
    **To save the view to a file**, build the scene ``show`` builds and save it:
    :meth:`Scene.save` writes a standalone HTML page that any browser opens, offline
    (``Scene.plot`` gives a matplotlib figure for a PNG or PDF)::

        scene = views.Scene()
        scene.add_chain(chain, q, meshes="ur10")    # what show(chain, q, meshes="ur10") draws
        scene.save("ur10.html")                     # + _static/meshcat/main.min.js next to it
        scene.plot().figure.savefig("ur10.png")     # a stick figure
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


def _as_radii(radii: Any) -> np.ndarray:
    """The semi-axes of an ellipsoid, (3,), finite, ≥ 0, one positive (an infinite one named as such)."""
    if isinstance(radii, (str, bytes, dict, set)) or radii is None:
        raise TypeError(f"radii must be three semi-axes (m); got {type(radii).__name__} {radii!r}"[:200])
    try:   # not as_numbers: an infinite radius gets its own message
        r = np.array(radii, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"radii must be three semi-axes (m), numbers; got {type(radii).__name__} "
                        f"{radii!r}"[:200]) from None
    if r.shape != (3,):
        raise ShapeError(f"radii must have shape (3,) (three semi-axes in m); got shape {r.shape}")
    if np.isnan(r).any() or (r < 0).any():
        raise DomainError(f"radii must be non-negative numbers (m); got {r.tolist()}")
    if np.isinf(r).any():
        raise DomainError(f"radii has an infinite semi-axis ({r.tolist()}), as a force ellipsoid has at a "
                          "singularity, which no scene can draw: clip it first, e.g. np.minimum(radii, 0.5)")
    if not (r > 0).any():
        raise DomainError(f"radii must have at least one positive semi-axis; got {r.tolist()}")
    return r


def _as_list(items, name, stacked=2):
    """``items`` as a list of entries: a sequence, or an array whose first axis lists them
    (an array of ``stacked - 1`` dimensions is one entry)."""
    if isinstance(items, (str, bytes, dict)) or items is None:
        raise TypeError(f"{name} must be a sequence; got {type(items).__name__} {items!r}"[:200])
    if isinstance(items, np.ndarray):
        return [items] if items.ndim < stacked else list(items)
    return list(items)
