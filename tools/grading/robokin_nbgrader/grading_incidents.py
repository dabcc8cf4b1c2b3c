"""``GradingIncidents`` (autograde, after ``AutograderReport``).

Adds to the report what happened to the kernel (died, killed), the tests not run because of it,
and the tests whose code wrote to stderr.
"""

from __future__ import annotations

from nbformat.notebooknode import from_dict
from nbgrader.preprocessors import NbGraderPreprocessor

from .cells import markdown_line, robokin_metadata

#: ename of the error output that zeroes a test the kernel could not run (it had died).
NOT_RUN = "TestNotRun"
#: ename of a cell whose kernel died, or was killed because it ignored the interrupt.
KERNEL_LOST = "KernelLost"


class GradingIncidents(NbGraderPreprocessor):
    """What happened to the kernel, appended to the report (autograde, after ``AutograderReport``).

    From autograde's executor, ``BridgedExecute`` (``tools/grading/bridge/execute.py``):
    a kernel that died or was killed (and in which cell), the tests that were therefore not run
    (0 points, with the reason), and the tests whose code wrote to stderr (shown as a note, not
    counted as a failure).
    """

    def preprocess(self, nb, resources):
        incidents = resources.get("robokin", {}).get("incidents", [])
        if not incidents:
            return nb, resources
        lines = []
        for item in incidents:
            if item["kind"] in ("died", "hang"):
                what = (item.get("what") or "the kernel died (os._exit, a crash or too much memory)"
                        if item["kind"] == "died" else
                        "it ran longer than the time limit and ignored the interrupt, so the kernel was killed")
                scope = "a test, which scores 0" if item["graded"] else "not graded"
                if item.get("replayed"):
                    after = ("The kernel was restarted and the cells before it were run again, so the "
                             "notebook went on: only this cell's work is lost.")
                elif item.get("nothing_after"):
                    after = ("No test comes after it, so grading stopped there: the cells after it were "
                             "not run, and no points were lost. Everything before it was graded.")
                else:
                    count = item["tests_lost"]
                    lost = ("no test came after it, so no points were lost" if not count else
                            "the test after it was not run and scores 0" if count == 1 else
                            f"the {count} tests after it were not run and score 0")
                    after = f"Grading stopped there; {lost}. Everything that ran before it was graded."
                lines.append(f"- **The kernel stopped** in {markdown_line(item['label'])} ({scope}): {what}. {after}")
        not_run = [item["label"] for item in incidents if item["kind"] == "not_run"]
        if not_run:
            lines.append("- Not run (0 points), because the kernel had stopped: "
                         + "; ".join(markdown_line(label) for label in not_run) + ".")
        noisy = [item["label"] for item in incidents if item["kind"] == "stderr"]
        if noisy:
            lines.append("- Your code wrote to stderr (a warning or a log message) while these tests ran: "
                         + "; ".join(markdown_line(label) for label in noisy)
                         + ". It is shown under the test and is not counted as a failure.")
        section = "\n".join(["", "**What happened while grading**", "", *lines])
        report = next((c for c in nb.cells if c.cell_type == "markdown"
                       and robokin_metadata(c).get("role") == "report"), None)
        if report is None:
            report = from_dict({"cell_type": "markdown", "metadata": {"robokin": {"role": "report"}},
                                "source": "## Autograder report\n"})
            if nb.cells and "id" in nb.cells[0]:
                report["id"] = "robokin-report"
            nb.cells.insert(0, report)
        report.source = report.source.rstrip() + "\n" + section
        return nb, resources
