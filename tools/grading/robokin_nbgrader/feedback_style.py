"""``FeedbackStyle`` (generate_feedback): the page's own stylesheet."""

from __future__ import annotations

from nbgrader.preprocessors import NbGraderPreprocessor
from traitlets import Unicode


class FeedbackStyle(NbGraderPreprocessor):
    """generate_feedback: the page's own stylesheet, after nbconvert's (``CSSHTMLHeaderPreprocessor``,
    whose ``resources["inlining"]["css"]`` the feedback template inlines).

    The notes under a failing test and the tracebacks wrap at the page's width instead of
    scrolling sideways (at 1280 px a note's long lines were cut off), at spaces (Bootstrap's
    ``word-break: break-all`` on ``pre`` cut words, "may then pas|s"; a token longer than the line
    still breaks), and the report's tables have a gap between their columns.
    """

    css = Unicode("""
div.output_area pre, div.output_subarea pre, div.output_text pre, .jp-OutputArea-output pre {
  white-space: pre-wrap; word-break: normal; overflow-wrap: anywhere; }
div.output_subarea, div.output_area { overflow-x: visible; max-width: 100%; }
div.text_cell_render table th, div.text_cell_render table td, .rendered_html table th,
.rendered_html table td { padding: 0.25em 0.9em; }
""", help="CSS added to the feedback page").tag(config=True)

    def preprocess(self, nb, resources):
        inlining = resources.setdefault("inlining", {})
        inlining["css"] = [*inlining.get("css", []), self.css]
        return nb, resources
