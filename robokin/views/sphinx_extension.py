"""Sphinx extension shipping the MeshCat viewer with the book, once.

Add to the Jupyter Book ``_config.yml``::

    sphinx:
      extra_extensions: [robokin.views.sphinx_extension]

After an HTML build it copies MeshCat's ``main.min.js`` (and its licence files)
into ``<outdir>/_static/meshcat/``, where the static scenes written by
:mod:`robokin.views.static_html` load it from (``<content root>_static/meshcat/``).
"""

from __future__ import annotations

import os

__all__ = ["setup", "copy_viewer"]


def copy_viewer(app, exception):
    if exception is not None or getattr(app.builder, "format", None) != "html":
        return
    from robokin.views.static_html import copy_viewer_files

    copy_viewer_files(os.path.join(app.outdir, "_static", "meshcat"))


def setup(app):
    app.connect("build-finished", copy_viewer)
    return {"version": "0.1", "parallel_read_safe": True, "parallel_write_safe": True}
