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

import html
import os
import sys
from typing import Any

from robokin.views import live, optional
from robokin.views.arguments import as_height
from robokin.views.plots import plot_scene

__all__ = ["ENV", "MAX_LIVE", "MODES", "choose_mode", "display", "html_output", "in_browser_kernel", "note",
           "show_live", "show_scene"]

#: The display modes.
MODES = ("live", "static", "matplotlib")
#: Environment variable that sets the mode.
ENV = "ROBOKIN_VIEWER"
#: Live servers kept running at once (one per scene shown live; the oldest is stopped).
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
        return name in optional.psutil().Process(int(pid)).environ()
    except Exception:  # noqa: BLE001
        return None


def _in_ipython_kernel():
    ipython = sys.modules.get("IPython")
    if ipython is None:
        return False
    shell = ipython.get_ipython()
    return shell is not None and getattr(shell, "kernel", None) is not None


def in_browser_kernel() -> bool:
    """True in a Jupyter kernel that a Jupyter server started for a browser session.

    Returns
    -------
    bool
        ``JPY_SESSION_NAME`` is set in this kernel, but not in its launcher's
        environment (a kernel started by nbclient from inside a notebook
        inherits it), and IPython runs a kernel.
    """
    if "JPY_SESSION_NAME" not in os.environ or not _in_ipython_kernel():
        return False
    return _parent_environ_has("JPY_SESSION_NAME") is not True


def choose_mode(mode: str | None = None) -> str:
    """The display mode after applying the rules above.

    Parameters
    ----------
    mode : str, optional
        ``"live"``, ``"static"`` or ``"matplotlib"`` (any case); None: the
        environment variable ``ROBOKIN_VIEWER``, else automatic.

    Returns
    -------
    str
        One of :data:`MODES`.

    Raises
    ------
    ValueError
        ``mode`` or ``ROBOKIN_VIEWER`` is not one of :data:`MODES`.
    """
    for source, value in (("mode", mode), (ENV, os.environ.get(ENV))):
        if value:
            value = str(value).strip().lower()
            if value not in MODES:
                raise ValueError(f"{source} must be one of {MODES}; got {value!r}")
            return value
    return "live" if in_browser_kernel() else "static"


def display(obj: Any) -> None:
    """Show ``obj`` as a notebook output (``IPython.display.display``).

    Parameters
    ----------
    obj : object
        Anything IPython displays (HTML, a figure, a widget).
    """
    optional.ipython_display().display(obj)


def html_output(text: str) -> Any:
    """HTML as a notebook output.

    Parameters
    ----------
    text : str
        HTML.

    Returns
    -------
    IPython.display.HTML
    """
    return optional.ipython_display().HTML(text)


def note(text: str) -> Any:
    """A one-line red note (e.g. why a live viewer is not shown) as an HTML output.

    Parameters
    ----------
    text : str
        Plain text (escaped).

    Returns
    -------
    IPython.display.HTML
    """
    return html_output(f'<p style="margin:0;font:13px sans-serif;color:#a33">{html.escape(text)}</p>')


def show_scene(scene: Any, mode: str | None = None, height: int | None = None) -> None:
    """Display ``scene`` live, statically or as a matplotlib figure (:meth:`robokin.views.Scene.show`).

    Parameters
    ----------
    scene : Scene
        The scene.
    mode : str, optional
        As in :func:`choose_mode`.
    height : int, optional
        CSS pixels; default the scene's height.

    Raises
    ------
    ValueError
        A bad ``mode`` or ``height``.
    """
    mode = choose_mode(mode)
    height = scene.options.height if height is None else as_height(height)
    if mode == "matplotlib":
        ax = plot_scene(scene)
        display(ax.figure)
        optional.pyplot().close(ax.figure)
        return
    if mode == "live":
        try:
            viewer = show_live(scene)
        except Exception as exc:  # noqa: BLE001 - never break the notebook: fall back to static
            display(note(f"robokin: live MeshCat viewer unavailable ({exc}); showing a static scene."))
            mode = "static"
        else:
            display(html_output(viewer.iframe_html(height)))
            return
    display(html_output(scene.to_html(height=height)))


def show_live(scene: Any) -> live.LiveViewer:
    """Draw ``scene`` in its own live viewer (started if needed).

    At most :data:`MAX_LIVE` servers run at once: showing a ninth scene live
    stops the server of the oldest one.

    Parameters
    ----------
    scene : Scene
        The scene; its viewer is kept in ``scene.viewer``.

    Returns
    -------
    LiveViewer

    Raises
    ------
    MeshcatUnavailable
        The server cannot start or does not answer.
    """
    viewer = scene.viewer
    if viewer is None or not viewer.alive:
        viewer = live.LiveViewer()
        _live_scenes.append(scene)
        while len(_live_scenes) > MAX_LIVE:     # keep the number of server processes bounded
            old = _live_scenes.pop(0)
            old.detach_viewer()
    else:
        viewer.delete("/meshcat")
    viewer.send_all(scene.commands())
    scene.attach_viewer(viewer)
    return viewer
