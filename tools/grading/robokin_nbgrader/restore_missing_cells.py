"""``RestoreMissingCells`` (autograde, replaces ``OverwriteCells``).

nbgrader's ``OverwriteCells`` with ``add_missing_cells``, where a deleted test cell is put back
after the nearest cell the submission still has (nbgrader 0.9.6 fails with a KeyError when that
cell is a read-only one).
"""

from __future__ import annotations

from nbformat.notebooknode import from_dict
from nbgrader.api import MissingEntry
from nbgrader.preprocessors import ClearHiddenTests, OverwriteCells


class RestoreMissingCells(OverwriteCells):
    """``OverwriteCells`` that puts a deleted test cell back after the nearest cell still there, and
    knows that a test cell with hidden tests was released without them.

    The gradebook holds each read-only cell as the instructor wrote it, hidden tests included, and
    its checksum; the student was given the cell without them. nbgrader compares the two, finds them
    different for every test cell with hidden tests (a warning "Attribute 'checksum' ... has
    changed!" in every run) and puts the gradebook's source back. Here a cell that is exactly what
    was released (the gradebook's source without its hidden tests) gets its hidden tests back
    before nbgrader compares: no change to report. A cell changed in any other way is reported and
    restored by nbgrader as before.
    """

    def preprocess_cell(self, cell, resources, cell_index):
        grade_id = cell.metadata.get("nbgrader", {}).get("grade_id")
        if grade_id is not None and cell.cell_type == "code":
            try:
                source_cell = self.gradebook.find_source_cell(grade_id, self.notebook_id, self.assignment_id)
            except MissingEntry:
                source_cell = None
            if source_cell is not None and source_cell.locked and cell.source != source_cell.source:
                released = ClearHiddenTests(config=self.config, enforce_metadata=False).preprocess_cell(
                    from_dict({"cell_type": "code", "metadata": {}, "source": source_cell.source,
                               "outputs": [], "execution_count": None}), resources, cell_index)[0].source
                if released != source_cell.source and cell.source == released:
                    cell.source = source_cell.source
        return super().preprocess_cell(cell, resources, cell_index)

    def add_missing_grade_cells(self, nb, resources):
        source_nb = self.gradebook.find_notebook(self.notebook_id, self.assignment_id)
        order = [cell.name for cell in source_nb.source_cells]
        solutions = {cell.name for cell in source_nb.solution_cells}
        present = {c.metadata.get("nbgrader", {}).get("grade_id") for c in nb.cells} - {None}
        for grade_cell in source_nb.grade_cells:
            if grade_cell.name in present:
                continue
            self.log.warning("Missing grade cell %s: adding it back to the notebook", grade_cell.name)
            source_cell = source_nb.source_cells[order.index(grade_cell.name)]
            new = self.missing_cell_transform(source_cell, grade_cell.max_score,
                                              is_solution=grade_cell.name in solutions)
            position = 0
            for earlier in reversed(order[: order.index(grade_cell.name)]):
                hits = [i for i, c in enumerate(nb.cells)
                        if c.metadata.get("nbgrader", {}).get("grade_id") == earlier]
                if hits:
                    position = hits[0] + 1
                    break
            nb.cells.insert(position, new)
            present.add(grade_cell.name)
        return nb, resources
