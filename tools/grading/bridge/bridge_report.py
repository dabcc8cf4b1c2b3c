"""``BridgeReport`` (autograde, after ``AutograderReport``): what the bridge adds to the report.

The answers ``BridgedExecute`` (:mod:`tools.grading.bridge.execute`) lists for review by hand
(``resources["robokin"]["review"]``) and the answers it could not hand over as data
(``resources["robokin"]["bridge"]``), appended to the report cell on top of the graded notebook.
"""

from __future__ import annotations

import re

from nbformat.notebooknode import from_dict
from nbgrader.preprocessors import NbGraderPreprocessor

from tools.grading.robokin_nbgrader.cells import robokin_metadata


class BridgeReport(NbGraderPreprocessor):
    """Adds answers for review by hand, and answers that are not plain data, to the report cell."""

    def preprocess(self, nb, resources):
        report = resources.get("robokin", {})
        review = report.get("review") or []
        bridge = report.get("bridge") or {}
        lines = []
        if review:
            lines += ["", "**For review by hand** (the points above stand as tested; the instructor decides)", ""]
            lines += [f"- Task {item['task']}: {item['line']}" for item in review]
        refused = {name: status for name, status in (bridge.get("imports") or {}).items()
                   if status.startswith(("not plain data", "refused"))}
        if refused or bridge.get("problems"):
            lines += ["", "**Answers the grader could not use**", ""]
            for name, status in refused.items():
                what = status.split(": ", 1)[-1]
                lines.append(f"- answer `{name}` is not plain data (a {_plain(what)})"
                             if status.startswith("not plain data") else f"- answer `{name}`: {_plain(what)}")
            lines += [f"- {_plain(p)}" for p in bridge.get("problems", [])]
        if not lines:
            return nb, resources
        for cell in nb.cells:
            if cell.cell_type == "markdown" and robokin_metadata(cell).get("role") == "report":
                cell.source = cell.source.rstrip("\n") + "\n" + "\n".join(lines)
                break
        else:
            nb.cells.insert(0, from_dict({"cell_type": "markdown", "metadata": {"robokin": {"role": "report"}},
                                          "source": "\n".join(lines).strip()}))
        return nb, resources


def _plain(text: str) -> str:
    return re.sub(r"\s+", " ", str(text)).replace("|", "\\|").replace("<", "&lt;")[:300]
