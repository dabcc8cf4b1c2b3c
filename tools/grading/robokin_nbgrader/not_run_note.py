"""``NotRunNote`` (autograde, right after the executor).

Above the first cell that grading did not run (nothing after it is graded), one note saying so.
"""

from __future__ import annotations

from nbformat.notebooknode import from_dict
from nbgrader.preprocessors import NbGraderPreprocessor

#: The note's first words, which name it (the report's "Not run (0 points)" names a loss: not these).
TITLE = "Nothing from here on is graded"
#: The note above the first cell the grader did not run.
NOTE = (f"> **{TITLE}**, so the grader did not run the cells below: they are shown without outputs. "
        "To see what they show, run them in your own copy of the notebook.")
#: The note's role in ``metadata.robokin`` (and its cell id, where the notebook's cells have ids).
ROLE = "not-run-note"


class NotRunNote(NbGraderPreprocessor):
    """One note above the first cell autograde's executor did not run, because nothing after it is graded.

    ``BridgedExecute`` (``tools/grading/bridge/execute.py``) stops the student's kernel after the
    last cell that is graded or holds an answer and gives the index of the first cell after it in
    ``resources['robokin']['not_run_from']`` (None when no code follows). This preprocessor runs
    right after the executor, before any other inserts a cell, so that the index still holds.
    The note is prose, not an output: nothing went wrong there.
    """

    def preprocess(self, nb, resources):
        index = resources.get("robokin", {}).get("not_run_from")
        if index is None or not 0 < index <= len(nb.cells):
            return nb, resources
        note = from_dict({"cell_type": "markdown", "metadata": {"robokin": {"role": ROLE}}, "source": NOTE})
        if "id" in nb.cells[0]:
            note["id"] = f"robokin-{ROLE}"
        nb.cells.insert(index, note)
        return nb, resources
