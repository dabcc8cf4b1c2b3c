"""Static export: a recorded scene as an HTML snippet that needs no server.

The snippet holds the scene's MeshCat commands (msgpack-packed, base64) and a
short script that loads the MeshCat viewer *once per page* from
``<content root>_static/meshcat/main.min.js`` -- the content root comes from
``<html data-content_root="...">`` (Sphinx >= 7.2), else from Sphinx's older
``documentation_options`` script, else the page's own folder -- then creates a
``MeshCat.Viewer`` in the snippet's div and feeds it every command.  The viewer
script itself is never inlined (it is 850 kB); :mod:`robokin.views.sphinx_extension`
copies it into the built book, :func:`save_page` next to a standalone page.

A scene is made when it comes within 300 px of the viewport and redrawn only there; its
animation plays while it is on screen (a reader sees it from its start, and a long page does
not keep drawing scenes nobody sees).

If the script cannot be loaded (e.g. the snippet is viewed inside JupyterLab),
the div shows a one-line explanation instead.  The output is deterministic:
the div id is a hash of the content, nothing depends on time or randomness.
"""

from __future__ import annotations

import base64
import hashlib
import html
import importlib.util
import json
import os
import re
import shutil
from collections.abc import Sequence
from pathlib import Path

from robokin.views import optional
from robokin.views.record import DEFAULT_HEIGHT

__all__ = ["pack_commands", "refresh_scene_scripts", "scene_html", "save_page", "share_scene_scripts",
           "shared_scene_script", "viewer_files", "VIEWER_PATH"]

VIEWER_PATH = "_static/meshcat/main.min.js"


def viewer_files() -> dict[str, Path]:
    """The MeshCat viewer script and its licence files, as installed with meshcat.

    Returns
    -------
    dict of str to pathlib.Path
        ``{file name: source path}`` of ``main.min.js``, its licence file and
        MeshCat's ``LICENSE`` (those that exist).

    Raises
    ------
    ModuleNotFoundError
        meshcat is not installed.
    """
    spec = importlib.util.find_spec("meshcat")
    if spec is None or not spec.submodule_search_locations:
        raise ModuleNotFoundError("meshcat is not installed: pip install 'robokin[views]'")
    dist = Path(list(spec.submodule_search_locations)[0]) / "viewer" / "dist"
    files = {"main.min.js": dist / "main.min.js",
             "main.min.js.LICENSE.txt": dist / "main.min.js.LICENSE.txt",
             "LICENSE": dist.parent / "LICENSE"}
    return {k: v for k, v in files.items() if v.exists()}


def pack_commands(commands: Sequence[dict]) -> list[str]:
    """Each command msgpack-packed (single-precision floats) and base64-encoded.

    Parameters
    ----------
    commands : sequence of dict
        MeshCat commands (:meth:`robokin.views.Scene.commands`).

    Returns
    -------
    list of str
        One ASCII string per command.
    """
    umsgpack = optional.umsgpack()
    return [base64.b64encode(umsgpack.packb(c, force_float_precision="single")).decode("ascii")
            for c in commands]


_SCRIPT = r"""(function () {
  var me = document.currentScript, box = me ? me.parentElement : document.getElementById("%(id)s");
  var pane = box.querySelector(".robokin-scene-pane"), msg = box.querySelector(".robokin-scene-msg");
  var holder = box.querySelector(".robokin-scene-data");
  function loadScript(src, check) {  /* a <script> works on file:// pages too, unlike fetch() */
    return new Promise(function (resolve, reject) {
      var s = document.createElement("script"), amd = window.define;
      s.src = src;
      window.define = undefined;  /* UMD bundles must set globals, not register with require.js */
      s.onload = function () {
        window.define = amd;
        var value = check();
        if (value) resolve(value); else reject(new Error(src + " did not define what it should"));
      };
      s.onerror = function () { window.define = amd; reject(new Error("cannot load " + src)); };
      document.head.appendChild(s);
    });
  }
  function stored(src, key) {  /* window.robokinSceneData[key], set by the script src; one request per file */
    var store = window.robokinSceneData || {}, loads = window.robokinSceneLoads = window.robokinSceneLoads || {};
    if (store[key]) return Promise.resolve(store[key]);
    if (!loads[key]) loads[key] = loadScript(src, function () { return (window.robokinSceneData || {})[key]; });
    return loads[key];
  }
  function sceneData() {
    /* inline, or (in the book) in _static/scenes/<key>.js next to the page; there a large
       command shared by several scenes (a robot's mesh) is "@<key>", stored once in its own file */
    var src = holder.getAttribute("data-src");
    if (!src) return Promise.resolve(JSON.parse(holder.textContent));
    var folder = src.slice(0, src.lastIndexOf("/") + 1);
    return stored(src, holder.getAttribute("data-key")).then(function (list) {
      return Promise.all(list.map(function (item) {
        return item.charAt(0) === "@" ? stored(folder + item.slice(1) + ".js", item.slice(1)) : item;
      }));
    });
  }
  var near = false, onScreen = false;  /* the box within 300 px of the viewport; in the viewport */
  function watch(margin, seen, first) {  /* seen(true/false) as the box comes and goes; first() once */
    if (!("IntersectionObserver" in window)) { seen(true); if (first) first(); return; }
    new IntersectionObserver(function (entries) {
      var now = entries[entries.length - 1].isIntersecting;
      seen(now);
      if (now && first) { var run = first; first = null; run(); }
    }, {rootMargin: margin}).observe(box);
  }
  function drawOnlyNear(viewer) {
    /* MeshCat redraws a scene whenever it changed, on screen or not, and plays an animation
       from the moment the scene is made: here a scene far from the viewport is not redrawn
       (it is when it comes near), and an animation waits until its scene is on screen */
    var animate = viewer.animate, loop = function () { viewer.animate(); };
    viewer.animate = function () {
      if (onScreen) return animate.call(viewer);
      requestAnimationFrame(loop);
      if (viewer.animator.playing) viewer.animator.clock.getDelta();  /* the time off screen is not played */
      if (near && viewer.needs_render) viewer.render();
    };
  }
  function viewerSrc() {
    var src = %(src)s;
    if (src) return src;
    var root = document.documentElement.getAttribute("data-content_root");
    if (root === null) {
      var opts = document.getElementById("documentation_options");
      root = opts ? opts.getAttribute("data-url_root") : null;
    }
    return (root || "") + "%(path)s";
  }
  function loadMeshCat() {
    if (window.MeshCat && window.MeshCat.Viewer) return Promise.resolve(window.MeshCat);
    if (!window.robokinMeshCat) {
      window.robokinMeshCat = loadScript(viewerSrc(), function () {
        return window.MeshCat && window.MeshCat.Viewer ? window.MeshCat : null;
      });
    }
    return window.robokinMeshCat;
  }
  function start() { Promise.all([loadMeshCat(), sceneData()]).then(function (loaded) {
    var MeshCat = loaded[0], data = loaded[1];
    msg.remove();
    var viewer = new MeshCat.Viewer(pane), resize = viewer.set_3d_pane_size;
    viewer.set_3d_pane_size = function (w, h) {  /* size to the div, not to the window */
      resize.call(viewer, w === undefined ? pane.clientWidth : w, h === undefined ? pane.clientHeight : h);
    };
    viewer.set_3d_pane_size();
    data.forEach(function (b64) {
      var s = atob(b64), bytes = new Uint8Array(s.length);
      for (var i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);
      viewer.handle_command_bytearray(bytes);
    });
    if (%(animated)s && pane.clientWidth >= 760) {  /* wide enough: show the play / pause / time controls */
      viewer.gui.open();
      if (viewer.gui.__folders.Scene) viewer.gui.__folders.Scene.close();
    }
    drawOnlyNear(viewer);
    box.robokinViewer = viewer;
  }).catch(function (err) {
    msg.textContent = "3D scene not shown: " + err.message +
      " (the MeshCat viewer ships with the built book; in Jupyter use ROBOKIN_VIEWER=live).";
  }); }
  watch("0px", function (now) { onScreen = now; });
  /* a scene starts when it comes near the viewport: pages with many load fast */
  watch("300px", function (now) { near = now; }, start);
})();"""


def _script(div_id: str, viewer_src: str | None, animated: bool) -> str:
    """The script of a scene's snippet (``_SCRIPT`` filled in)."""
    return _SCRIPT % {"id": div_id, "src": json.dumps(viewer_src) if viewer_src else "null",
                      "path": VIEWER_PATH, "animated": "true" if animated else "false"}


#: The script of a snippet written by any version of :func:`scene_html`: its div id, viewer
#: source and animated flag are read back from it.
_ANY_SCRIPT = re.compile(
    r'<script>\(function \(\) \{\n  var me = document\.currentScript, box = me \? me\.parentElement : '
    r'document\.getElementById\("(?P<id>robokin-scene-[0-9a-f]+)"\);\n.*?'
    r'\n    var src = (?P<src>null|"[^"\\]*");\n.*?'
    r'\n    if \((?P<animated>true|false) && pane\.clientWidth >= 760\).*?'
    r'\n\}\)\(\);</script>', re.S)


def refresh_scene_scripts(page: str) -> tuple[str, int]:
    """Give every scene snippet in an HTML page the script of this version of robokin.

    A notebook stores the snippets of its scenes as they were when it was executed; the
    book shows those stored outputs. The snippet's data (its commands, its id) stays as it is.

    Parameters
    ----------
    page : str
        The HTML text of a page.

    Returns
    -------
    tuple of (str, int)
        The page with every scene's script replaced by the current one, and the number of
        scripts that changed.
    """
    changed = 0

    def current(match: re.Match) -> str:
        nonlocal changed
        new = (f"<script>{_script(match['id'], json.loads(match['src']), match['animated'] == 'true')}"
               f"</script>")
        changed += new != match.group(0)
        return new

    return _ANY_SCRIPT.sub(current, page), changed


def shared_scene_script() -> str:
    """Every scene's script as one file, which reads a scene's parameters from its own tag.

    The book links it from each scene (:func:`share_scene_scripts`) instead of repeating the
    script in every scene (about 6 kB each): ``<script src="..." data-animated="true">``,
    optionally ``data-viewer="<url of main.min.js>"``. A classic script runs where it stands,
    so ``document.currentScript`` is the tag and its parent the scene's div.

    Returns
    -------
    str
        The script's text (JavaScript).
    """
    return (_SCRIPT
            .replace('box = me ? me.parentElement : document.getElementById("%(id)s")', "box = me.parentElement")
            .replace("var src = %(src)s;", 'var src = me.getAttribute("data-viewer");')
            .replace("if (%(animated)s &&", 'if (me.getAttribute("data-animated") === "true" &&')
            % {"path": VIEWER_PATH})


def share_scene_scripts(page: str, src: str) -> tuple[str, int]:
    """Replace every scene's inline script in an HTML page by a link to :func:`shared_scene_script`.

    Parameters
    ----------
    page : str
        The HTML text of a page.
    src : str
        URL of the shared script, relative to the page.

    Returns
    -------
    tuple of (str, int)
        The page, and the number of scripts replaced. A page without inline scene scripts
        comes back unchanged.
    """
    replaced = 0

    def linked(match: re.Match) -> str:
        nonlocal replaced
        replaced += 1
        viewer = json.loads(match["src"])
        attributes = f' data-viewer="{html.escape(viewer)}"' if viewer else ""
        return f'<script src="{html.escape(src)}" data-animated="{match["animated"]}"{attributes}></script>'

    return _ANY_SCRIPT.sub(linked, page), replaced


_MESSAGE = ("3D scene: loading the MeshCat viewer&hellip; (if this line stays, JavaScript is off or "
            "<code>_static/meshcat/main.min.js</code> is not next to this page)")


def scene_html(commands: Sequence[dict], *, height: int = DEFAULT_HEIGHT, animated: bool = False,
               viewer_src: str | None = None) -> str:
    """The HTML snippet of a scene given its MeshCat commands.

    Parameters
    ----------
    commands : sequence of dict
        MeshCat commands (:meth:`robokin.views.Scene.commands`).
    height : int, optional
        Height of the scene in CSS pixels.
    animated : bool, optional
        The scene has an animation: open the viewer's controls (play, pause, time)
        when the scene is wide enough.
    viewer_src : str, optional
        URL of MeshCat's ``main.min.js``; default ``<content root>_static/meshcat/main.min.js``.

    Returns
    -------
    str
        A ``<div>`` with the packed commands and the script that shows them;
        deterministic (its id is a hash of the content).
    """
    packed = pack_commands(commands)
    payload = json.dumps(packed, separators=(",", ":"))
    digest = hashlib.sha1(f"{height}|{viewer_src}|{payload}".encode()).hexdigest()[:12]
    div_id = f"robokin-scene-{digest}"
    script = _script(div_id, viewer_src, animated)
    return (
        f'<div class="robokin-scene" id="{div_id}" style="position:relative;width:100%;'
        f'height:{int(height)}px;overflow:hidden;border:1px solid #ccc;background:#e8eef5">'
        f'<div class="robokin-scene-pane" style="position:absolute;left:0;top:0;width:100%;height:100%">'
        f'<p class="robokin-scene-msg" style="margin:0;padding:0.5em;font:13px sans-serif;color:#333">'
        f'{_MESSAGE}</p></div>'
        f'<script type="application/json" class="robokin-scene-data">{payload}'
        f'</script>\n<script>{script}</script></div>'
    )


def save_page(path: str | os.PathLike, scenes: Sequence, *, copy_viewer: bool = True,
              title: str = "robokin scene") -> Path:
    """Write a standalone HTML page showing ``scenes``; copy the viewer into ``_static/meshcat/``.

    Parameters
    ----------
    path : str or os.PathLike
        The page's file (its folder is created if needed).
    scenes : list or tuple
        :class:`~robokin.views.Scene` objects, or HTML strings put in the page as they are.
    copy_viewer : bool, optional
        Copy MeshCat's viewer script next to the page (``_static/meshcat/``).
    title : str, optional
        The page's title.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    TypeError
        ``scenes`` is not a list/tuple of scenes or strings, or ``path`` is not a file name.
    """
    if isinstance(scenes, (str, bytes)) or not isinstance(scenes, (list, tuple)):
        raise TypeError(f"scenes must be a list of robokin.views.Scene; got {type(scenes).__name__}")
    for k, s in enumerate(scenes):
        if not (hasattr(s, "to_html") or isinstance(s, str)):
            raise TypeError(f"scenes[{k}] must be a robokin.views.Scene (or an HTML string); got "
                            f"{type(s).__name__}")
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file name (str or os.PathLike); got {type(path).__name__}")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    body = "\n".join(s.to_html() if hasattr(s, "to_html") else str(s) for s in scenes)
    path.write_text(
        f'<!DOCTYPE html>\n<html data-content_root="./"><head><meta charset="utf-8">'
        f"<title>{html.escape(title)}</title></head>\n<body>\n{body}\n</body></html>\n", encoding="utf-8")
    if copy_viewer:
        copy_viewer_files(path.parent / "_static" / "meshcat")
    return path


def copy_viewer_files(dest: str | os.PathLike) -> list[Path]:
    """Copy the MeshCat viewer script and licences into folder ``dest``.

    Parameters
    ----------
    dest : str or os.PathLike
        Target folder (created if needed); files of the right size are not copied again.

    Returns
    -------
    list of pathlib.Path
        The copied files.
    """
    os.makedirs(dest, exist_ok=True)
    out = []
    for name, src in viewer_files().items():
        target = Path(dest) / name
        if not target.exists() or target.stat().st_size != src.stat().st_size:
            shutil.copyfile(src, target)
        out.append(target)
    return out
