"""``OfflineMathJaxHTMLExporter`` (generate_feedback).

nbgrader's HTML exporter with MathJax 3 inlined in the page (from the ``django-static-mathjax``
wheel the book uses) instead of loaded from a CDN: the feedback page is read offline, and
``release_feedback`` hands out the HTML file only. The page is nbconvert's, byte for byte, with
that script in place of the CDN's.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

from nbconvert.exporters import HTMLExporter


MATHJAX_CONFIG = """window.MathJax = {
  tex: {inlineMath: [["$", "$"], ["\\\\(", "\\\\)"]], displayMath: [["$$", "$$"], ["\\\\[", "\\\\]"]],
        processEscapes: true, processEnvironments: true, tags: "ams"},
  svg: {fontCache: "global"},
  options: {enableMenu: false}
};"""
#: The CDN script tag of nbconvert's/nbgrader's MathJax 2 macro and its configuration.
CDN_MATHJAX = re.compile(r'<script[^>]*\bsrc="https?://[^"]*mathjax[^"]*"[^>]*>\s*</script>', re.I)
MATHJAX2_CONFIG = re.compile(r'<script type="text/x-mathjax-config">.*?</script>', re.S)


@functools.cache
def mathjax_script() -> str:
    """MathJax 3 (TeX input, SVG output: no font files) from the ``django-static-mathjax`` wheel."""
    try:
        import mathjax  # the wheel the book serves MathJax from (book/_ext/robokin_book.py)
    except ImportError as exc:  # pragma: no cover - install problem
        raise RuntimeError("MathJax is missing: `pip install -r requirements.txt` installs "
                           "django-static-mathjax, the offline MathJax of the book and the feedback") from exc
    path = Path(mathjax.__file__).resolve().parent / "static" / "mathjax" / "es5" / "tex-svg-full.js"
    return path.read_text(encoding="utf-8").replace("</script", "<\\/script")


class OfflineMathJaxHTMLExporter(HTMLExporter):
    """HTML with MathJax inlined: formulas render in a feedback page opened without internet."""

    def from_notebook_node(self, nb, resources=None, **kw):
        """nbconvert's page (its own ``from_notebook_node``) with MathJax inlined."""
        output, resources = super().from_notebook_node(nb, resources, **kw)
        return inline_mathjax(output), resources


def inline_mathjax(html: str) -> str:
    """``html`` with the CDN MathJax (and its MathJax 2 configuration) replaced by MathJax 3 inline."""
    inline = (f"<script>{MATHJAX_CONFIG}</script>\n"
              f"<script id=\"robokin-mathjax\">{mathjax_script()}</script>")
    html = MATHJAX2_CONFIG.sub("", html)
    html, count = CDN_MATHJAX.subn(lambda _: inline, html, count=1)
    html = CDN_MATHJAX.sub("", html)
    if not count:  # a template without the macro: put it at the end of the head
        html = html.replace("</head>", inline + "\n</head>", 1)
    return html
