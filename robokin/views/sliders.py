"""Joint sliders (ipywidgets) driving a live MeshCat scene.

One slider per joint, within the joint limits (degrees for revolute joints,
metres for prismatic ones).  Each move recomputes the frames and sends only
``set_transform`` commands (no geometry), and updates a readout of the
end-effector pose (position in metres, roll-pitch-yaw in degrees, ZYX
convention).  Needs a live viewer; elsewhere the chain is shown as the display
mode shows a scene (statically in the book and under nbval, as a matplotlib figure
in ``"matplotlib"`` mode) under one line explaining that the sliders need a
running kernel.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.chains.protocol import Chain
from robokin.transforms import rpy_from_rotation
from robokin.views import optional
from robokin.views.arguments import as_configuration
from robokin.views.display import choose_mode, display, note, show_live, show_scene
from robokin.views.geometry import chain_layout
from robokin.views.live import LiveViewer
from robokin.views.meshcat_draw import chain_transforms
from robokin.views.record import DEFAULT_HEIGHT
from robokin.views.scene import Scene

__all__ = ["JointSliders", "joint_sliders", "pose_readout"]


def pose_readout(T: np.ndarray) -> str:
    """One line describing a pose: position (m) and roll-pitch-yaw (deg, ZYX).

    Parameters
    ----------
    T : array_like, shape (4, 4)
        The end-effector's pose in the base frame (m).

    Returns
    -------
    str
        ``'end-effector: p = (x, y, z) m, rpy = (r, p, y) deg'`` (3 and 1 decimals).
    """
    T = np.asarray(T, dtype=float)
    rpy = np.rad2deg(np.asarray(rpy_from_rotation(T[:3, :3], check=False), dtype=float))
    x, y, z = T[:3, 3]
    return (f"end-effector: p = ({x:+.3f}, {y:+.3f}, {z:+.3f}) m, "
            f"rpy = ({rpy[0]:+.1f}, {rpy[1]:+.1f}, {rpy[2]:+.1f}) deg")


def _slider_range(chain):
    lim = np.asarray(chain.limits, dtype=float).reshape(int(chain.n), 2)
    out = []
    for (lo, hi), kind in zip(lim, chain.joint_types):
        if kind == "revolute":
            lo = -np.pi if not np.isfinite(lo) else lo
            hi = np.pi if not np.isfinite(hi) else hi
            out.append((np.rad2deg(lo), np.rad2deg(hi), 0.5))
        else:
            lo = -1.0 if not np.isfinite(lo) else lo
            hi = 1.0 if not np.isfinite(hi) else hi
            out.append((lo, hi, max((hi - lo) / 200, 1e-4)))
    return out


class JointSliders:
    """Sliders + scene + readout for ``chain``; ``.widget`` is the ipywidgets box.

    ``update(q)`` moves the robot (radians/metres) -- this is what every slider
    move calls.  ``q`` is the current configuration.

    Parameters
    ----------
    chain : SerialChain
        The chain.
    q : array_like, shape (n,), optional
        Initial configuration (rad, m); default zeros, moved into the joint limits.
    scene : Scene, optional
        A scene holding the chain as item ``name``; default a new scene with the chain alone.
    name : str, optional
        The chain item's name.
    height : int, optional
        Height of the viewer in CSS pixels.
    viewer : LiveViewer, optional
        A running viewer to draw in; default one started by :meth:`build`.
    """

    def __init__(self, chain: Chain, q: Any = None, *, scene: Scene | None = None, name: str = "robot",
                 height: int = DEFAULT_HEIGHT, viewer: LiveViewer | None = None) -> None:
        self.chain = chain
        self.q = as_configuration(chain, q)
        if scene is None:
            scene = Scene(height=height)
            scene.add_chain(chain, self.q, name=name)
        self.scene = scene
        self.name = name
        self._viewer = viewer
        self._revolute = np.array([t == "revolute" for t in chain.joint_types])
        self.widget = None
        self.readout = None
        self.sliders: list[Any] = []  # ipywidgets.FloatSlider, one per joint

    def _to_slider(self, q):
        return np.where(self._revolute, np.rad2deg(q), q)

    def _from_slider(self, v):
        return np.where(self._revolute, np.deg2rad(v), v)

    def build(self) -> Any:
        """Start the live viewer (if needed) and create the widgets.

        Returns
        -------
        ipywidgets.VBox
            The viewer, one slider per joint and the pose readout.

        Raises
        ------
        MeshcatUnavailable
            The live viewer cannot start.
        """
        w = optional.ipywidgets()
        if self._viewer is None:
            self._viewer = show_live(self.scene)
        values = self._to_slider(self.q)
        self.sliders = []
        for k, ((lo, hi, step), jname, kind) in enumerate(zip(_slider_range(self.chain), self.chain.joint_names,
                                                               self.chain.joint_types)):
            unit = "deg" if kind == "revolute" else "m"
            s = w.FloatSlider(value=float(np.clip(values[k], lo, hi)), min=float(lo), max=float(hi),
                              step=float(step), description=f"{jname} [{unit}]", continuous_update=True,
                              readout_format=".1f" if kind == "revolute" else ".3f",
                              style={"description_width": "8em"}, layout=w.Layout(width="32em"))
            s.observe(self._on_change, names="value")
            self.sliders.append(s)
        self.readout = w.HTML(value=f"<code>{pose_readout(self.chain.fk(self.q))}</code>")
        frame = w.HTML(value=self._viewer.iframe_html(self.scene.options.height))
        self.widget = w.VBox([frame, *self.sliders, self.readout])
        return self.widget

    def _on_change(self, _change):
        self.update(self._from_slider(np.array([s.value for s in self.sliders])))

    def update(self, q: np.ndarray) -> str:
        """Move the robot to ``q``: frames, then ``set_transform`` commands only, then the readout.

        Parameters
        ----------
        q : array_like, shape (n,)
            Configuration (rad, m).

        Returns
        -------
        str
            The new readout (:func:`pose_readout` of the end-effector).
        """
        self.q = np.asarray(q, dtype=float)
        item = self.scene.chain_item(self.name)
        item.q = self.q
        transforms = chain_transforms(self.name, self.chain, self.q, self._layout())
        if self._viewer is not None:
            self._viewer.send_transforms(transforms)
        text = pose_readout(transforms[int(self.chain.n) + 1][1])
        if self.readout is not None:
            self.readout.value = f"<code>{text}</code>"
        return text

    def _layout(self):
        if getattr(self, "_cached_layout", None) is None:
            self._cached_layout = chain_layout(self.chain, self.q)
        return self._cached_layout

    def _ipython_display_(self):
        # already displayed by joint_sliders(); showing it again re-displays the widgets only
        if self.widget is not None:
            display(self.widget)

    def __repr__(self):
        return f"<JointSliders: {int(self.chain.n)} joints>"

    def close(self) -> None:
        """Stop the live viewer of these sliders."""
        if self._viewer is not None:
            self._viewer.close()


def joint_sliders(chain: Chain, q: Any = None, *, mode: str | None = None,
                  height: int = DEFAULT_HEIGHT) -> JointSliders:
    """Show ``chain`` with one slider per joint (live mode).

    Outside live mode the chain is shown at ``q`` as :func:`show_scene` shows a
    scene in that mode (a static MeshCat scene, or a matplotlib figure in
    ``"matplotlib"`` mode) under a one-line note, and the returned object has no
    widget.

    Parameters
    ----------
    chain : SerialChain
        The chain.
    q : array_like, shape (n,), optional
        Initial configuration (rad, m).
    mode : str, optional
        As in :func:`robokin.views.choose_mode`.
    height : int, optional
        Height of the viewer in CSS pixels.

    Returns
    -------
    JointSliders

    Raises
    ------
    ShapeError
        ``q`` has the wrong length.
    """

    js = JointSliders(chain, q, height=height)
    chosen = choose_mode(mode)
    if chosen == "live":
        try:
            box = js.build()
        except Exception as exc:  # noqa: BLE001 - keep the notebook running
            display(note(f"robokin: joint sliders need a live MeshCat viewer ({exc}); showing a static scene."))
            chosen = "static"
        else:
            display(box)
            return js
    else:
        display(note("robokin: joint sliders need a running Jupyter kernel (live mode); "
                      "showing the chain at its initial configuration."))
    show_scene(js.scene, mode=chosen, height=height)
    return js
