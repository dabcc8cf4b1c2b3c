"""Views: 3D scenes (MeshCat), joint sliders and matplotlib figures.

Quick use::

    from robokin import models, views
    chain = models.ur10()
    views.show(chain, q)                      # one call, works everywhere
    views.show(chain, q, meshes="ur10")       # with the robot's real (URDF) meshes

    scene = views.Scene()                     # or build a scene
    scene.add_chain(chain, q, frames=True)
    scene.add_chain(chain, q, meshes="ur10", name="real")   # its URDF meshes (robokin[robots])
    scene.add_target(T_goal, label="goal")
    scene.add_ghost(chain, q_other)           # translucent copy (other IK solution)
    radii, axes = chain.velocity_ellipsoid(q)
    scene.add_ellipsoid(chain.fk(q)[:3, 3], 0.3 * radii, axes)   # at the tool point, 0.3 m per m/s
    scene.animate("robot", Q, dt=0.05)        # (T, n) joint trajectory, play/pause in the viewer
    scene.show()
    scene.save("robot.html")                  # the view as a standalone page (what show() draws)

    views.joint_sliders(chain)                # one slider per joint (live kernels)
    views.plot_chain(chain, q)                # matplotlib stick figure
    views.plot_history(t=t, q=Q, error=err)   # time series

How ``show()`` chooses the display mode (first match wins):

1. the ``mode`` argument: ``"live"``, ``"static"`` or ``"matplotlib"``;
2. the environment variable ``ROBOKIN_VIEWER`` (same values);
3. automatic: ``"live"`` in an interactive Jupyter kernel started by a Jupyter
   server for a browser session (``JPY_SESSION_NAME`` is set by jupyter_server,
   not by nbclient/jupyter-book/nbval), otherwise ``"static"``.

- **live**: a MeshCat server on 127.0.0.1 (first free port from 7000) shown in an
  iframe -- through ``jupyter-server-proxy`` (``<prefix>proxy/<port>/static/``)
  when that is installed or the kernel runs on JupyterHub/Binder.  Servers stop with
  ``viewer.close()``, on garbage collection and at kernel exit.  If MeshCat cannot
  start, the static scene is shown with one line saying why.
- **static**: the recorded MeshCat commands embedded in HTML; the viewer script is
  loaded from ``<book root>/_static/meshcat/main.min.js`` (shipped once by the
  Sphinx extension :mod:`robokin.views.sphinx_extension`).  Works from ``file://``
  and any static web server, no network; deterministic output.
- **matplotlib**: a stick figure (PDF, text-only outputs).

Layers (each module imports only modules listed before it; ``tests/test_layers.py``
checks the order):

1. :mod:`~robokin.views.optional` (the optional libraries, each imported there
   only, on first use), :mod:`~robokin.views.record` (the scene's items),
   :mod:`~robokin.views.arguments` (argument checks);
2. :mod:`~robokin.views.geometry` (frames, layout, scale, bounds: numpy only),
   :mod:`~robokin.views.ellipsoids` (the curves of velocity and force ellipsoids: numpy only);
3. backends: :mod:`~robokin.views.meshcat_draw` (MeshCat commands),
   :mod:`~robokin.views.static_html`, :mod:`~robokin.views.plots` (matplotlib),
   :mod:`~robokin.views.ellipse_plots` (planar ellipses in matplotlib),
   :mod:`~robokin.views.meshes` (URDF meshes), :mod:`~robokin.views.live` (live server),
   :mod:`~robokin.views.sphinx_extension`;
4. :mod:`~robokin.views.display` (choosing the mode, showing);
5. the facade: :mod:`~robokin.views.scene` (:class:`Scene`, :func:`show`), then
   :mod:`~robokin.views.sliders`.

``import robokin.views`` imports numpy and robokin only: matplotlib, MeshCat,
IPython and ipywidgets are imported when a function needs them, and
``import robokin`` does not import this package.
"""

from __future__ import annotations

from robokin.views.display import choose_mode
from robokin.views.live import LiveViewer
from robokin.views.meshes import robot_meshes
from robokin.views.plots import plot_chain, plot_history, plot_planar, plot_scene
from robokin.views.scene import Scene, show
from robokin.views.sliders import JointSliders, joint_sliders
from robokin.views.static_html import save_page

__all__ = ["Scene", "show", "choose_mode", "joint_sliders", "JointSliders", "LiveViewer",
           "plot_chain", "plot_planar", "plot_history", "plot_scene", "save_page", "robot_meshes"]
