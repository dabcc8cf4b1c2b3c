"""``PointsHeader`` (generate_assignment).

A read-only cell under the title: points per task and in total.
"""

from __future__ import annotations

from nbformat.notebooknode import from_dict
from nbgrader.preprocessors import NbGraderPreprocessor


class PointsHeader(NbGraderPreprocessor):
    """A read-only cell after the title with the points per task (from the notebook's metadata)."""

    def preprocess(self, nb, resources):
        grading = nb.metadata.get("robokin", {}).get("grading")
        if not grading or any(c.metadata.get("nbgrader", {}).get("grade_id") == "robokin-points" for c in nb.cells):
            return nb, resources
        lines = [
            f"**Grading.** This notebook is graded automatically (nbgrader): "
            f"**{grading['points']} points** (a task's points are the sum of its test cells'). "
            "Write your code where it says `# YOUR CODE HERE` (keep the names that are given); "
            "the read-only cells, the test cells among them, are restored before grading.",
            "",
            "| task | points |",
            "|---|---|",
        ]
        lines += [f"| Task {t['task']}: {t['title']} | {t['points']} |" for t in grading["tasks"]]
        cell = from_dict({
            "cell_type": "markdown", "metadata": {"nbgrader": {
                "grade": False, "grade_id": "robokin-points", "locked": True, "schema_version": 3,
                "solution": False, "task": False}},
            "source": "\n".join(lines),
        })
        if "id" in nb.cells[0]:
            cell["id"] = "robokin-points"
        nb.cells.insert(1, cell)
        return nb, resources
