"""Static export: a recorded scene as an HTML snippet that needs no server.

The snippet holds the scene's MeshCat commands (msgpack-packed, base64) and a
short script that loads the MeshCat viewer *once per page* from
``<content root>_static/meshcat/main.min.js`` -- the content root comes from
``<html data-content_root="...">`` (Sphinx >= 7.2), else from Sphinx's older
``documentation_options`` script, else the page's own folder -- then creates a
``MeshCat.Viewer`` in the snippet's div and feeds it every command.  The viewer
script itself is never inlined (it is 850 kB); :mod:`robokin.views.sphinx_extension`
copies it into the built book, :func:`save_page` next to a standalone page.

If the script cannot be loaded (e.g. the snippet is viewed inside JupyterLab),
the div shows a one-line explanation instead.  The output is deterministic:
the div id is a hash of the content, nothing depends on time or randomness.
"""

from __future__ import annotations

import base64
import hashlib
import html
import json
import os
import shutil
from pathlib import Path

__all__ = ["pack_commands", "scene_html", "save_page", "viewer_files", "VIEWER_PATH"]

VIEWER_PATH = "_static/meshcat/main.min.js"


def viewer_files():
    """``{name: source path}`` of the MeshCat viewer script and its licence files."""
    import importlib.util

    spec = importlib.util.find_spec("meshcat")
    if spec is None or not spec.submodule_search_locations:
        raise ModuleNotFoundError("meshcat is not installed: pip install 'robokin[views]'")
    dist = Path(list(spec.submodule_search_locations)[0]) / "viewer" / "dist"
    files = {"main.min.js": dist / "main.min.js",
             "main.min.js.LICENSE.txt": dist / "main.min.js.LICENSE.txt",
             "LICENSE": dist.parent / "LICENSE"}
    return {k: v for k, v in files.items() if v.exists()}


def pack_commands(commands):
    """Each command msgpack-packed (single-precision floats) and base64-encoded."""
    import umsgpack

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
  function whenNear(run) {  /* start a scene when it comes near the viewport: pages with many load fast */
    if (!("IntersectionObserver" in window)) return run();
    var seen = new IntersectionObserver(function (entries) {
      if (entries.some(function (e) { return e.isIntersecting; })) { seen.disconnect(); run(); }
    }, {rootMargin: "300px"});
    seen.observe(box);
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
  whenNear(function () { Promise.all([loadMeshCat(), sceneData()]).then(function (loaded) {
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
    box.robokinViewer = viewer;
  }).catch(function (err) {
    msg.textContent = "3D scene not shown: " + err.message +
      " (the MeshCat viewer ships with the built book; in Jupyter use ROBOKIN_VIEWER=live).";
  }); });
})();"""

_MESSAGE = ("3D scene: loading the MeshCat viewer&hellip; (if this line stays, JavaScript is off or "
            "<code>_static/meshcat/main.min.js</code> is not next to this page)")


def scene_html(commands, *, height=420, animated=False, viewer_src=None):
    """The HTML snippet of a scene given its MeshCat ``commands`` (list of dicts)."""
    packed = pack_commands(commands)
    payload = json.dumps(packed, separators=(",", ":"))
    digest = hashlib.sha1(f"{height}|{viewer_src}|{payload}".encode()).hexdigest()[:12]
    div_id = f"robokin-scene-{digest}"
    script = _SCRIPT % {"id": div_id, "src": json.dumps(viewer_src) if viewer_src else "null",
                        "path": VIEWER_PATH, "animated": "true" if animated else "false"}
    return (
        f'<div class="robokin-scene" id="{div_id}" style="position:relative;width:100%;'
        f'height:{int(height)}px;overflow:hidden;border:1px solid #ccc;background:#e8eef5">'
        f'<div class="robokin-scene-pane" style="position:absolute;left:0;top:0;width:100%;height:100%">'
        f'<p class="robokin-scene-msg" style="margin:0;padding:0.5em;font:13px sans-serif;color:#333">'
        f'{_MESSAGE}</p></div>'
        f'<script type="application/json" class="robokin-scene-data">{payload}'
        f'</script>\n<script>{script}</script></div>'
    )


def save_page(path, scenes, *, copy_viewer=True, title="robokin scene"):
    """Write a standalone HTML page showing ``scenes``; copy the viewer into ``_static/meshcat/``.

    ``scenes`` is a list of :class:`~robokin.views.Scene` (or HTML strings put in
    the page as they are); ``path`` the page's file. Returns the path.
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


def copy_viewer_files(dest):
    """Copy the MeshCat viewer script and licences into folder ``dest``; return the paths."""
    os.makedirs(dest, exist_ok=True)
    out = []
    for name, src in viewer_files().items():
        target = Path(dest) / name
        if not target.exists() or target.stat().st_size != src.stat().st_size:
            shutil.copyfile(src, target)
        out.append(target)
    return out
