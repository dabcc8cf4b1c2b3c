"""Sphinx extension shipping the MeshCat viewer with the book, once, and the scenes' data beside the pages.

Add to the Jupyter Book ``_config.yml``::

    sphinx:
      extra_extensions: [robokin.views.sphinx_extension]

After an HTML build it

* copies MeshCat's ``main.min.js`` (and its licence files) into
  ``<outdir>/_static/meshcat/``, where the static scenes written by
  :mod:`robokin.views.static_html` load it from (``<content root>_static/meshcat/``);
* gives every static scene the script of this version of robokin (the notebooks store
  the snippets written when they were executed), as one file, ``<outdir>/_static/robokin-scene.js``,
  that each scene links instead of carrying its own copy (about 6 kB a scene);
* moves the data of every static scene out of its page into
  ``<outdir>/_static/scenes/<key>.js`` (``key`` = hash of the data, so a scene shown on
  two pages is stored once) and leaves ``data-src``/``data-key`` attributes in the page:
  a page's own HTML stays small, and a scene's data is loaded only when the scene
  comes near the viewport. A command of ``SHARED_COMMAND_SIZE`` characters or more
  (a robot's mesh) is stored in a file of its own, keyed by its hash, so every scene
  and page that shows the robot shares it. ``<script>`` files rather than JSON, because
  browsers refuse ``fetch()`` on pages opened from ``file://``.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from pathlib import Path
from typing import Any

from robokin.views.static_html import copy_viewer_files, share_scene_scripts, shared_scene_script

__all__ = ["setup", "copy_viewer", "externalize_scene_data"]

#: The scenes' shared script, under ``<outdir>/_static/``.
SCENE_SCRIPT = "robokin-scene.js"

#: Commands at least this long (base64 characters) are stored in a file of their own.
SHARED_COMMAND_SIZE = 4_000

_DATA = re.compile(r'<script type="application/json" class="robokin-scene-data">(\[.*?\])</script>', re.S)


def copy_viewer(app: Any, exception: Exception | None) -> None:
    """After an HTML build: copy MeshCat's viewer into ``_static/meshcat/`` and move the scenes' data out.

    Parameters
    ----------
    app : sphinx.application.Sphinx
        The Sphinx application.
    exception : Exception or None
        The build's exception (then nothing is done).
    """
    if exception is not None or getattr(app.builder, "format", None) != "html":
        return
    copy_viewer_files(os.path.join(app.outdir, "_static", "meshcat"))
    externalize_scene_data(Path(app.outdir))


def externalize_scene_data(outdir: Path) -> int:
    """Move inline scene data of every page under ``outdir`` to ``_static/scenes/``.

    Each scene also gets the script of the robokin that builds the book: a notebook stores
    its scenes as they were when it was executed. The script is written once, to
    ``_static/robokin-scene.js`` (:func:`~robokin.views.static_html.shared_scene_script`),
    and each scene links it (:func:`~robokin.views.static_html.share_scene_scripts`).
    Idempotent: a page already rewritten has no inline data or scripts left.

    Parameters
    ----------
    outdir : pathlib.Path
        The HTML output folder of a build.

    Returns
    -------
    int
        The number of scenes moved.
    """
    scenes = outdir / "_static" / "scenes"
    script = outdir / "_static" / SCENE_SCRIPT
    moved = 0
    for page in outdir.rglob("*.html"):
        if "_static" in page.relative_to(outdir).parts:
            continue
        text = page.read_text(encoding="utf-8")
        if "robokin-scene-data" not in text:
            continue
        prefix = os.path.relpath(scenes, page.parent).replace(os.sep, "/")

        def move(match: re.Match, prefix: str = prefix) -> str:
            nonlocal moved
            commands = json.loads(match.group(1))
            # a large command (a robot's mesh) gets a file of its own, shared by every scene that has it
            listed = [f"@{_store(scenes, c)}" if len(c) >= SHARED_COMMAND_SIZE else c for c in commands]
            key = _store(scenes, listed)
            moved += 1
            return (f'<script type="application/json" class="robokin-scene-data" data-key="{key}" '
                    f'data-src="{prefix}/{key}.js">[]</script>')

        if not script.exists() or script.read_text(encoding="utf-8") != shared_scene_script():
            script.parent.mkdir(parents=True, exist_ok=True)   # this robokin's, not an older build's
            script.write_text(shared_scene_script(), encoding="utf-8")
        src = os.path.relpath(script, page.parent).replace(os.sep, "/")
        new, _ = share_scene_scripts(_DATA.sub(move, text), src)
        if new != text:
            page.write_text(new, encoding="utf-8")
    return moved


def _store(folder: Path, value) -> str:
    """Write ``value`` (JSON) as ``folder/<key>.js`` registering it under ``key``; return the key."""
    data = json.dumps(value, separators=(",", ":"))
    key = hashlib.sha1(data.encode()).hexdigest()[:16]
    target = folder / f"{key}.js"
    if not target.exists():
        folder.mkdir(parents=True, exist_ok=True)
        target.write_text(f'(window.robokinSceneData = window.robokinSceneData || {{}})["{key}"] = {data};\n',
                          encoding="utf-8")
    return key


def setup(app: Any) -> dict:
    """Register the extension with Sphinx (``build-finished`` hook).

    Parameters
    ----------
    app : sphinx.application.Sphinx

    Returns
    -------
    dict
        Extension metadata (parallel-safe).
    """
    app.connect("build-finished", copy_viewer)
    return {"version": "0.1", "parallel_read_safe": True, "parallel_write_safe": True}
