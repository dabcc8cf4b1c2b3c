"""``RequireGradingMetadata`` (generate_assignment).

A chapter without nbgrader metadata is an error naming the notebook, not an assignment without
tests.
"""

from __future__ import annotations

from nbgrader import utils
from nbgrader.preprocessors import NbGraderPreprocessor


class RequireGradingMetadata(NbGraderPreprocessor):
    """Refuse a notebook that carries no nbgrader metadata (say which one)."""

    def preprocess(self, nb, resources):
        name = resources.get("nbgrader", {}).get("notebook", "?")
        graded = [c for c in nb.cells if utils.is_grade(c)]
        if not any("nbgrader" in c.metadata for c in nb.cells) or not graded:
            raise RuntimeError(
                f"notebook '{name}' has no nbgrader metadata (no autograder test cells): run "
                "`.venv/bin/python tools/authoring/nbgrader_metadata.py` on the chapter notebooks first"
            )
        return nb, resources
