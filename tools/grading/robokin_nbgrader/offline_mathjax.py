"""``OfflineMathJaxHTMLExporter`` (generate_feedback).

nbgrader's HTML exporter with MathJax 3 inlined in the page (from the ``django-static-mathjax``
wheel the book uses) instead of loaded from a CDN: the feedback page is read offline, and
``release_feedback`` hands out the HTML file only. The page is nbconvert's, byte for byte, made
with less CPU (code highlighting and markdown memoised per process).
"""

from __future__ import annotations

import functools
import json
import re
from pathlib import Path

from jinja2 import pass_context
from nbconvert.exporters import HTMLExporter
from nbconvert.filters.highlight import Highlight2HTML


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


class MemoisedHighlight(Highlight2HTML):
    """nbconvert's code highlighting (pygments), memoised per process: ``generate_feedback`` renders
    the same given and test cells for every student, and highlighting is a sixth of its time."""

    _pages: dict[tuple, str] = {}

    def __call__(self, source, language=None, metadata=None):
        key = (source, language or self.pygments_lexer, (metadata or {}).get("magics_language"),
               json.dumps(self.extra_formatter_options, sort_keys=True, default=repr))
        if key not in self._pages:
            self._pages[key] = super().__call__(source, language, metadata)
        return self._pages[key]


class OfflineMathJaxHTMLExporter(HTMLExporter):
    """HTML with MathJax inlined: formulas render in a feedback page opened without internet."""

    _markdown: dict[tuple, str] = {}

    @pass_context
    def markdown2html(self, context, source):
        """nbconvert's markdown filter, memoised per process: the text cells are the same on every
        student's page (the key is all the filter reads: the text, the cell's attachments, the
        notebook's folder and the exporter's options)."""
        key = (source, json.dumps(context.get("cell", {}).get("attachments", {}), sort_keys=True),
               context.get("resources", {}).get("metadata", {}).get("path", ""), self.embed_images,
               self.anchor_link_text, self.exclude_anchor_links,
               json.dumps(self.lexer_options, sort_keys=True, default=repr))
        if key not in self._markdown:
            self._markdown[key] = super().markdown2html(context, source)
        return self._markdown[key]

    def from_notebook_node(self, nb, resources=None, **kw):
        """nbconvert's page (its own ``from_notebook_node``) with MathJax inlined; its code
        highlighting memoised (:class:`MemoisedHighlight`): ``HTMLExporter`` highlights with the
        ``highlight_code`` filter configured in ``filters`` when there is one."""
        langinfo = nb.metadata.get("language_info", {})
        lexer = langinfo.get("pygments_lexer", langinfo.get("name", None)) or "ipython3"
        current = self.filters.get("highlight_code")
        if current is None or (isinstance(current, MemoisedHighlight) and current.pygments_lexer != lexer):
            # a new filters dict rebuilds the exporter's template environment: once per lexer
            self.filters = {**self.filters, "highlight_code": MemoisedHighlight(pygments_lexer=lexer, parent=self)}
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
