"""Choosing how a scene is shown: live MeshCat, static HTML or matplotlib.

Rules (first match wins):

1. the ``mode`` argument (``"live"``, ``"static"``, ``"matplotlib"``);
2. the environment variable ``ROBOKIN_VIEWER`` (same values);
3. automatic: ``"live"`` in an interactive Jupyter kernel started by a Jupyter
   server for a browser session (jupyter_server puts ``JPY_SESSION_NAME`` into
   the kernel's environment; nbclient -- used by jupyter-book and nbval -- does
   not.  A kernel started by nbclient *from inside* a notebook inherits it, so it
   must not also be in the parent process's environment), otherwise ``"static"``.

If the live server cannot start, the static scene is shown with one line saying why.
"""

from __future__ import annotations

import os
import sys

from robokin.views.arguments import as_height

__all__ = ["MODES", "choose_mode", "in_browser_kernel", "show_scene"]

MODES = ("live", "static", "matplotlib")
ENV = "ROBOKIN_VIEWER"
MAX_LIVE = 8
_live_scenes: list = []


def _parent_environ_has(name):
    """True/False if the kernel's launcher (JPY_PARENT_PID) has ``name`` in its environment; None if unknown."""
    pid = os.environ.get("JPY_PARENT_PID")
    if not pid:
        pid = str(os.getppid())
    try:
        with open(f"/proc/{int(pid)}/environ", "rb") as f:
            return any(entry.split(b"=", 1)[0] == name.encode() for entry in f.read().split(b"\0"))
    except (OSError, ValueError):
        pass
    try:
        import psutil
        return name in psutil.Process(int(pid)).environ()
    except Exception:  # noqa: BLE001
        return None


def _in_ipython_kernel():
    ipython = sys.modules.get("IPython")
    if ipython is None:
        return False
    shell = ipython.get_ipython()
    return shell is not None and getattr(shell, "kernel", None) is not None


def in_browser_kernel():
    """True in a Jupyter kernel that a Jupyter server started for a browser session."""
    if "JPY_SESSION_NAME" not in os.environ or not _in_ipython_kernel():
        return False
    return _parent_environ_has("JPY_SESSION_NAME") is not True


def choose_mode(mode=None):
    """The display mode after applying the rules above."""
    for source, value in (("mode", mode), (ENV, os.environ.get(ENV))):
        if value:
            value = str(value).strip().lower()
            if value not in MODES:
                raise ValueError(f"{source} must be one of {MODES}; got {value!r}")
            return value
    return "live" if in_browser_kernel() else "static"


def _display(obj):
    from IPython.display import display
    display(obj)


def _note(text):
    import html
    from IPython.display import HTML
    return HTML(f'<p style="margin:0;font:13px sans-serif;color:#a33">{html.escape(text)}</p>')


def show_scene(scene, mode=None, height=None):
    from IPython.display import HTML

    mode = choose_mode(mode)
    height = scene.options.height if height is None else as_height(height)
    if mode == "matplotlib":
        import matplotlib.pyplot as plt
        ax = scene.plot()
        _display(ax.figure)
        plt.close(ax.figure)
        return
    if mode == "live":
        try:
            viewer = show_live(scene)
        except Exception as exc:  # noqa: BLE001 - never break the notebook: fall back to static
            _display(_note(f"robokin: live MeshCat viewer unavailable ({exc}); showing a static scene."))
            mode = "static"
        else:
            _display(HTML(viewer.iframe_html(height)))
            return
    _display(HTML(scene.to_html(height=height)))


def show_live(scene):
    """Draw ``scene`` in its own live viewer (started if needed); return the viewer."""
    from robokin.views.live import LiveViewer

    viewer = scene._live
    if viewer is None or not viewer.alive:
        viewer = LiveViewer()
        _live_scenes.append(scene)
        while len(_live_scenes) > MAX_LIVE:     # keep the number of server processes bounded
            old = _live_scenes.pop(0)
            if old._live is not None:
                old._live.close()
                old._live = None
    else:
        viewer.delete("/meshcat")
    viewer.send_all(scene.commands())
    scene._live = viewer
    return viewer
