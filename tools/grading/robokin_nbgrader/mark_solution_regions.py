"""``MarkSolutionRegions`` (generate_assignment, before ``ClearSolutions``).

Puts nbgrader's ``### BEGIN SOLUTION`` / ``### END SOLUTION`` around the parts of a solution cell
that the student writes, so that ``ClearSolutions`` keeps imports, function signatures and
docstrings, and the variables later cells need (``name = None``); marks the solution prose for
removal.
"""

from __future__ import annotations

from nbgrader import utils
from nbgrader.preprocessors import NbGraderPreprocessor
from tools.notebook_analysis import mark_solution
from traitlets import Unicode

from .cells import robokin_metadata


class MarkSolutionRegions(NbGraderPreprocessor):
    """Mark what ``ClearSolutions`` replaces: solution code bodies and solution prose."""

    begin = Unicode("### BEGIN SOLUTION").tag(config=True)
    end = Unicode("### END SOLUTION").tag(config=True)

    def preprocess_cell(self, cell, resources, index):
        role = robokin_metadata(cell).get("role")
        if cell.cell_type == "code" and utils.is_solution(cell) and "BEGIN SOLUTION" not in cell.source:
            declare = robokin_metadata(cell).get("declare")
            cell.source = mark_solution(cell.source, set(declare) if declare is not None else None,
                                        self.begin, self.end)
        elif cell.cell_type == "markdown" and role == "prose" and "BEGIN SOLUTION" not in cell.source:
            cell.source = f"{self.begin}\n{cell.source}\n{self.end}"
        return cell, resources
