"""The record of a 3D scene: what is drawn, as plain data (numpy only).

The bottom layer of :mod:`robokin.views`: the items a
:class:`~robokin.views.Scene` collects, its options, and
:class:`SceneRecord`, the part of a scene the backends read
(:mod:`robokin.views.geometry`, :mod:`robokin.views.meshcat_draw`,
:mod:`robokin.views.plots`). Nothing here draws.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robokin.chains.protocol import DrawableChain

__all__ = ["DEFAULT_HEIGHT", "AnimationItem", "ChainItem", "EllipsoidItem", "Item", "PathItem", "PointsItem",
           "SceneOptions", "SceneRecord", "TargetItem"]

#: Height (CSS pixels) of a scene shown in a page.
DEFAULT_HEIGHT = 420


@dataclass
class ChainItem:
    """A chain drawn at one configuration.

    Attributes
    ----------
    name : str
        Item name, unique in its scene (the MeshCat path ``/meshcat/<name>``).
    chain : SerialChain
        The chain (any object with ``n``, ``frames(q)``, ``joint_axes``, ``joint_types``, ``limits``).
    q : numpy.ndarray, shape (n,)
        Its configuration (rad for revolute, m for prismatic joints).
    color : int or None
        ``0xRRGGBB`` for every part, or None for the default colours.
    opacity : float
        In (0, 1]; below 1 the chain is translucent.
    frames : bool
        Draw a triad at every joint frame.
    labels : bool
        Label the triads with the frame names.
    ghost : bool
        Drawn by :meth:`~robokin.views.Scene.add_ghost` (never animated by default).
    meshes : RobotMeshes or None
        Visual meshes (:func:`robokin.views.robot_meshes`) drawn instead of the stick figure.
    """

    name: str
    chain: DrawableChain
    q: np.ndarray
    color: int | None = None
    opacity: float = 1.0
    frames: bool = False
    labels: bool = True
    ghost: bool = False
    meshes: Any = None          # robokin.models.urdf_meshes.RobotMeshes when drawn with meshes


@dataclass
class TargetItem:
    """A target frame: a triad at a pose.

    Attributes
    ----------
    name : str
        Item name, unique in its scene.
    T : numpy.ndarray, shape (4, 4)
        The pose of the target in the base frame (m).
    size : float or None
        Triad length (m); None: from the scene's scale.
    label : str or None
        Text shown next to the triad.
    """

    name: str
    T: np.ndarray
    size: float | None = None
    label: str | None = None


@dataclass
class PointsItem:
    """Points drawn as spheres (or, above 500 points, as one point cloud).

    Attributes
    ----------
    name : str
        Item name, unique in its scene.
    points : numpy.ndarray, shape (N, 3)
        Positions (m).
    radius : float or None
        Sphere radius (m); None: from the scene's scale.
    color : int
        ``0xRRGGBB``.
    """

    name: str
    points: np.ndarray
    radius: float | None = None
    color: int = 0xFFD92F


@dataclass
class PathItem:
    """A polyline.

    Attributes
    ----------
    name : str
        Item name, unique in its scene.
    points : numpy.ndarray, shape (N, 3)
        Its vertices in order (m), N >= 2.
    color : int
        ``0xRRGGBB``.
    """

    name: str
    points: np.ndarray
    color: int = 0xFFFFFF


@dataclass
class EllipsoidItem:
    r"""A solid ellipsoid: the unit sphere moved by :math:`\mathbf{A}\,\mathrm{diag}(\mathbf{r})` and ``center``.

    Attributes
    ----------
    name : str
        Item name, unique in its scene.
    center : numpy.ndarray, shape (3,)
        Its centre in the base frame (m).
    radii : numpy.ndarray, shape (3,)
        Its semi-axes (m), finite, ≥ 0, at least one positive.
    axes : numpy.ndarray, shape (3, 3)
        Orthonormal unit axes as columns, in the order of ``radii`` (base frame).
    color : int
        ``0xRRGGBB``.
    opacity : float
        In (0, 1]; below 1 the ellipsoid is translucent.
    """

    name: str
    center: np.ndarray
    radii: np.ndarray
    axes: np.ndarray
    color: int = 0x1F77B4
    opacity: float = 0.4


@dataclass
class AnimationItem:
    """A joint trajectory played by a chain item.

    Attributes
    ----------
    chain_name : str
        Name of the animated :class:`ChainItem`.
    trajectory : numpy.ndarray, shape (T, n)
        One configuration per step (rad, m).
    times : numpy.ndarray, shape (T,)
        Time of each step (s), increasing from 0.
    trace : bool
        Draw the end-effector's path as a line.
    trace_color : int
        ``0xRRGGBB`` of that line.
    """

    chain_name: str
    trajectory: np.ndarray
    times: np.ndarray
    trace: bool = True
    trace_color: int = 0xFFFF66


#: Any item of a scene.
Item = ChainItem | TargetItem | PointsItem | PathItem | EllipsoidItem


@dataclass
class SceneOptions:
    """How a scene is shown.

    Attributes
    ----------
    height : int
        Height in CSS pixels.
    play : bool
        Start the animation when the scene opens.
    loop : bool
        Repeat the animation.
    grid : bool
        Draw the floor grid.
    extra : dict
        Reserved for backends.
    """

    height: int = DEFAULT_HEIGHT
    play: bool = True
    loop: bool = False
    grid: bool = True
    extra: dict = field(default_factory=dict)


class SceneRecord:
    """What a scene draws: its items, animations and options (no drawing, no checks).

    :class:`robokin.views.Scene` is a ``SceneRecord`` with the methods that add
    checked items and show the result; the backends read only this part.

    Parameters
    ----------
    options : SceneOptions, optional
        Default: ``SceneOptions()``.
    """

    def __init__(self, options: SceneOptions | None = None) -> None:
        self.items: list[Item] = []
        self.animations: list[AnimationItem] = []
        self.options = SceneOptions() if options is None else options

    def item(self, name: str) -> Item:
        """The recorded item called ``name``.

        Parameters
        ----------
        name : str
            An item name (as returned by the ``add_*`` methods).

        Returns
        -------
        ChainItem, TargetItem, PointsItem, PathItem or EllipsoidItem

        Raises
        ------
        KeyError
            There is no item of that name; the message lists the names.
        """
        for it in self.items:
            if it.name == name:
                return it
        raise KeyError(f"no item named {name!r} in this scene; names: {[it.name for it in self.items]}")

    def chain_item(self, name: str) -> ChainItem:
        """The recorded chain item called ``name``.

        Parameters
        ----------
        name : str
            The name of a chain item (as returned by ``add_chain`` or ``add_ghost``).

        Returns
        -------
        ChainItem

        Raises
        ------
        KeyError
            There is no chain item of that name; the message lists the chain items' names.
        """
        for it in self.items:
            if it.name == name and isinstance(it, ChainItem):
                return it
        raise KeyError(f"no chain item named {name!r} in this scene; chain items: "
                       f"{[it.name for it in self.items if isinstance(it, ChainItem)]}")
