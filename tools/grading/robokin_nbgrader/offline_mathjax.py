"""``OfflineMathJaxHTMLExporter`` (generate_feedback).

nbgrader's HTML exporter with MathJax 3 inlined in the page (from the ``django-static-mathjax``
wheel the book uses) instead of loaded from a CDN: the feedback page is read offline, and
``release_feedback`` hands out the HTML file only. The page is nbconvert's document, with that
script in place of the CDN's; only the last step of nbconvert's ``HTMLExporter`` is done
another way (:func:`accessible_page`).
"""

from __future__ import annotations

import functools
import html as html_text
import re
from html.parser import HTMLParser
from pathlib import Path

from nbconvert.exporters import HTMLExporter, TemplateExporter
from nbconvert.filters.highlight import Highlight2HTML
from nbconvert.filters.widgetsdatatypefilter import WidgetsDataTypeFilter


MATHJAX_CONFIG = """window.MathJax = {
  tex: {inlineMath: [["$", "$"], ["\\\\(", "\\\\)"]], displayMath: [["$$", "$$"], ["\\\\[", "\\\\]"]],
        processEscapes: true, processEnvironments: true, tags: "ams"},
  svg: {fontCache: "global"},
  options: {enableMenu: false}
};"""
#: The CDN script tag of nbconvert's/nbgrader's MathJax 2 macro and its configuration.
CDN_MATHJAX = re.compile(r'<script[^>]*\bsrc="https?://[^"]*mathjax[^"]*"[^>]*>\s*</script>', re.I)
MATHJAX2_CONFIG = re.compile(r'<script type="text/x-mathjax-config">.*?</script>', re.S)
#: nbconvert's alternative text for an image that has none.
NO_DESCRIPTION = "No description has been provided for this image"
#: Elements without content or end tag: never open (BeautifulSoup's list for html.parser).
VOID_ELEMENTS = frozenset({"area", "base", "br", "col", "embed", "hr", "img", "input", "keygen", "link",
                           "menuitem", "meta", "param", "source", "track", "wbr", "basefont", "bgsound",
                           "command", "frame", "image", "isindex", "nextid", "spacer"})
#: Classes of the ``div`` elements nbconvert makes focusable inside a ``.jp-Notebook`` element.
FOCUSABLE = frozenset({"jp-Cell-inputWrapper", "jp-OutputArea-output"})


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
        """nbconvert's page with MathJax inlined.

        The steps of ``HTMLExporter.from_notebook_node`` (nbconvert 7: its two filters, then the
        template), but its last one, a BeautifulSoup pass that parses the whole page and writes
        it out again to add alternative texts and ``tabindex``, is :func:`accessible_page`: the
        same attributes on the same elements, for a tenth of the CPU (a chapter's page exports
        in 0.2-0.9 CPU-s less, a third to a half of the export). The document is nbconvert's
        (tests/test_nbgrader.py compares the two in nbconvert's classic and lab templates).
        """
        language = nb.metadata.get("language_info", {})
        lexer = language.get("pygments_lexer", language.get("name", None))
        highlight_code = self.filters.get("highlight_code", Highlight2HTML(pygments_lexer=lexer, parent=self))
        resources = self._init_resources(resources)
        data_types = WidgetsDataTypeFilter(notebook_metadata=self._nb_metadata, parent=self, resources=resources)
        self.register_filter("highlight_code", highlight_code)
        self.register_filter("filter_data_type", data_types)
        page, resources = TemplateExporter.from_notebook_node(self, nb, resources, **kw)
        page, missing = accessible_page(page)
        if missing:
            self.log.warning("Alternative text is missing on %s image(s).", missing)
        return inline_mathjax(page), resources


class _StartTags(HTMLParser):
    """The start tags :func:`accessible_page` rewrites, found with the tokenizer BeautifulSoup's
    ``html.parser`` uses, and the elements open at each (to tell what is inside ``.jp-Notebook``)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=False)
        #: (line, column, tag, start tag's text, its new attributes), in the page's order
        self.changes: list[tuple[int, int, str, str, list[tuple[str, str | None]]]] = []
        self.missing = 0
        self._open: list[tuple[str, bool]] = []   # (tag, is it a .jp-Notebook)
        self._notebooks = 0

    def handle_starttag(self, tag, attrs):
        classes = set(" ".join(value or "" for name, value in attrs if name == "class").split())
        changed = None
        if tag == "img" and not any(name == "alt" for name, _ in attrs):
            changed = [*attrs, ("alt", NO_DESCRIPTION)]
            self.missing += 1
        elif tag == "div" and self._notebooks and classes & FOCUSABLE:
            changed = [(name, "0" if name == "tabindex" else value) for name, value in attrs]
            if not any(name == "tabindex" for name, _ in attrs):
                changed.append(("tabindex", "0"))
        if changed is not None:
            line, column = self.getpos()
            self.changes.append((line, column, tag, self.get_starttag_text() or "", changed))
        if tag not in VOID_ELEMENTS:
            notebook = "jp-Notebook" in classes
            self._open.append((tag, notebook))
            self._notebooks += notebook

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        self.handle_endtag(tag)

    def handle_endtag(self, tag):
        for depth in range(len(self._open) - 1, -1, -1):   # closes every element opened after it
            if self._open[depth][0] == tag:
                self._notebooks -= sum(notebook for _, notebook in self._open[depth:])
                del self._open[depth:]
                return


def accessible_page(page: str) -> tuple[str, int]:
    """``page`` with what nbconvert's ``HTMLExporter`` adds for assistive technology, and the number
    of images that had no alternative text.

    Every ``img`` without an ``alt`` attribute gets nbconvert's ``alt="No description has been
    provided for this image"``, and every ``div.jp-Cell-inputWrapper`` and
    ``div.jp-OutputArea-output`` inside a ``.jp-Notebook`` element ``tabindex="0"`` (the
    JupyterLab templates; the classic ones and nbgrader's feedback have no such element). Only
    those start tags are written again; every other byte of ``page`` is kept.
    """
    tags = _StartTags()
    tags.feed(page)
    tags.close()
    if not tags.changes:
        return page, 0
    starts = [0, *(match.end() for match in re.finditer("\n", page))]
    out, done = [], 0
    for line, column, tag, text, attrs in tags.changes:
        at = starts[line - 1] + column
        if not text or not page.startswith(text, at):   # pragma: no cover - html.parser's positions
            raise RuntimeError(f"accessible_page: the start tag {text[:60]!r} is not at line {line}, column {column}")
        closing = "/>" if text.endswith("/>") else ">"
        attributes = "".join(f" {name}" if value is None else f' {name}="{html_text.escape(value)}"'
                             for name, value in attrs)
        out += [page[done:at], f"<{tag}{attributes}{closing}"]
        done = at + len(text)
    out.append(page[done:])
    return "".join(out), tags.missing


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
