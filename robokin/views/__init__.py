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
    scene.animate("robot", Q, dt=0.05)        # (T, n) joint trajectory, play/pause in the viewer
    scene.show()

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

This package imports matplotlib, MeshCat, IPython and ipywidgets only when a
function needs them; ``import robokin`` never imports it.
"""

from __future__ import annotations

from robokin.views.scene import Scene, show

__all__ = ["Scene", "show", "choose_mode", "joint_sliders", "JointSliders", "LiveViewer",
           "plot_chain", "plot_planar", "plot_history", "plot_scene", "save_page", "robot_meshes"]

_LAZY = {
    "choose_mode": "robokin.views.display",
    "joint_sliders": "robokin.views.sliders",
    "JointSliders": "robokin.views.sliders",
    "LiveViewer": "robokin.views.live",
    "plot_chain": "robokin.views.plots",
    "plot_planar": "robokin.views.plots",
    "plot_history": "robokin.views.plots",
    "plot_scene": "robokin.views.plots",
    "save_page": "robokin.views.static_html",
    "robot_meshes": "robokin.views.meshes",
}


def __getattr__(name):
    if name in _LAZY:
        import importlib
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'robokin.views' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + list(_LAZY))
