"""``DropSolutionProse`` (generate_assignment, after ``ClearSolutions``).

Leaves the emptied solution prose out of the student edition.
"""

from __future__ import annotations

from nbgrader.preprocessors import NbGraderPreprocessor

from .cells import robokin_metadata


class DropSolutionProse(NbGraderPreprocessor):
    """Leave out of the student edition the solution prose that ``ClearSolutions`` emptied.

    A prose cell with text outside its own ``BEGIN SOLUTION``/``END SOLUTION``
    markers keeps that text. The cells are read-only and not graded, so the gradebook
    does not miss them; ``tests/test_student_edition_contracts.py`` predicts the
    student edition with the same rule (``notebook_analysis.student_markdown``).
    """

    def preprocess(self, nb, resources):
        nb.cells = [c for c in nb.cells if not (
            c.cell_type == "markdown" and robokin_metadata(c).get("role") == "prose" and not c.source.strip())]
        return nb, resources
