"""Which of an assignment's read-only cells the grader kernel runs: :func:`skip_pictures`.

Its own module (standard library and ``tools.notebook_analysis`` only), so that a tool or test
can apply the grader's rule without importing nbgrader; ``execute.BridgedExecute`` applies it to
each submission's plan.
"""

from __future__ import annotations

from tools.notebook_analysis import defined_names, free_names


def skip_pictures(cells: list[dict], tags: dict[str, list[str]]) -> None:
    """Mark the given cells the grader need not run (``item["skip"] = True``).

    Parameters
    ----------
    cells : list of dict
        The notebook's read-only code cells in order, each ``{"grade_id", "source", "test"}``
        (``test``: a graded test cell).
    tags : dict
        The instructor's tags of each cell, by grade id.

    Notes
    -----
    Skipped: the cells after the last test (nothing is graded there), and pictures and 3D
    scenes (tagged ``nbval-ignore-output``, book/conventions) that define nothing a later
    cell *the grader runs* reads. The pictures are judged from the last one back, so a
    picture whose names only later skipped pictures read is skipped too (a drawing helper
    read by the next figure alone).
    """
    tests = [i for i, item in enumerate(cells) if item["test"]]
    for item in cells[tests[-1] + 1:] if tests else []:
        item["skip"] = True
    read_later: set[str] = set()   # the free names of the cells after `index` that run
    for item in reversed(cells):
        if not item["test"] and "nbval-ignore-output" in tags.get(item["grade_id"], []):
            item["skip"] = item.get("skip", False) or not set(defined_names(item["source"])) & read_later
        if not item.get("skip", False):
            read_later |= set(free_names(item["source"]))
