"""nbgrader preprocessors of the robokin course (configured in ``nbgrader_config.py``).

nbgrader does the work -- ``generate_assignment`` clears the solutions and records
the assignment in its gradebook, ``autograde`` runs the submission and scores
its test cells, ``generate_feedback`` writes the HTML -- and these classes plug
into its pipelines:

``RequireGradingMetadata`` (generate_assignment)
    A chapter without nbgrader metadata is an error naming the notebook, not an
    assignment without tests.
``MarkSolutionRegions`` (generate_assignment, before ``ClearSolutions``)
    Puts nbgrader's ``### BEGIN SOLUTION`` / ``### END SOLUTION`` around the parts
    of a solution cell that the student writes, so that ``ClearSolutions`` keeps
    imports, function signatures and docstrings, and the variables later cells
    need (``name = None``); marks the solution prose for removal.
``DropSolutionProse`` (generate_assignment, after ``ClearSolutions``)
    Leaves the emptied solution prose out of the student edition.
``PointsHeader`` (generate_assignment)
    A read-only cell under the title: points per task and in total.
``RestoreMissingCells`` (autograde, replaces ``OverwriteCells``)
    nbgrader's ``OverwriteCells`` with ``add_missing_cells``, where a deleted test
    cell is put back after the nearest cell the submission still has (nbgrader
    0.9.6 fails with a KeyError when that cell is a read-only one).
``RobokinExecute`` (autograde, replaces ``Execute``)
    nbgrader's ``Execute``; when a test cell fails it asks ``robokin.check``, in
    the student's kernel, about the quantities of that task and writes the answer
    above the traceback; at the end it asks about every task.
``AutograderReport`` (autograde, after ``SaveAutoGrades``)
    A markdown cell on top of the graded notebook (and so of the feedback): the
    score per task, what ``robokin.check`` found, and what went wrong outside the
    tests (a cell that raised, a cell that timed out, a test cell that was deleted).

The cell roles come from ``tools/nbgrader_metadata.py`` (``metadata.robokin``).
"""

from __future__ import annotations

import json
import os
import re
import sys
from pathlib import Path

from nbformat.notebooknode import NotebookNode, from_dict
from nbgrader import utils
from nbgrader.preprocessors import Execute, NbGraderPreprocessor, OverwriteCells
from traitlets import Unicode

sys.path.insert(0, str(Path(__file__).resolve().parent))

from notebook_analysis import mark_solution  # noqa: E402

ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")
VERDICT_MARK = "ROBOKIN-VERDICTS"
RESTORED_NOTE = "was missing from the submission"


def _robokin(cell) -> dict:
    return cell.metadata.get("robokin", {}) or {}


def _task_of(cell) -> int | None:
    task = _robokin(cell).get("task")
    if task is None:
        m = re.match(r"task(\d+)_", cell.metadata.get("nbgrader", {}).get("grade_id", ""))
        task = int(m.group(1)) if m else None
    return task


def _first_line(text: str, width: int = 60) -> str:
    for line in text.splitlines():
        line = line.strip()
        if line and not line.startswith("#"):
            return line if len(line) <= width else line[: width - 1] + "…"
    return text.strip().splitlines()[0][:width] if text.strip() else ""


# ---------------------------------------------------------------- generate_assignment
class RequireGradingMetadata(NbGraderPreprocessor):
    """Refuse a notebook that carries no nbgrader metadata (say which one)."""

    def preprocess(self, nb, resources):
        name = resources.get("nbgrader", {}).get("notebook", "?")
        graded = [c for c in nb.cells if utils.is_grade(c)]
        if not any("nbgrader" in c.metadata for c in nb.cells) or not graded:
            raise RuntimeError(
                f"notebook '{name}' has no nbgrader metadata (no autograder test cells): run "
                "`.venv/bin/python tools/nbgrader_metadata.py` on the chapter notebooks first"
            )
        return nb, resources


class MarkSolutionRegions(NbGraderPreprocessor):
    """Mark what ``ClearSolutions`` replaces: solution code bodies and solution prose."""

    begin = Unicode("### BEGIN SOLUTION").tag(config=True)
    end = Unicode("### END SOLUTION").tag(config=True)

    def preprocess_cell(self, cell, resources, index):
        role = _robokin(cell).get("role")
        if cell.cell_type == "code" and utils.is_solution(cell) and "BEGIN SOLUTION" not in cell.source:
            declare = _robokin(cell).get("declare")
            cell.source = mark_solution(cell.source, set(declare) if declare is not None else None,
                                        self.begin, self.end)
        elif cell.cell_type == "markdown" and role == "prose" and "BEGIN SOLUTION" not in cell.source:
            cell.source = f"{self.begin}\n{cell.source}\n{self.end}"
        return cell, resources


class DropSolutionProse(NbGraderPreprocessor):
    """Leave solution prose out of the student edition (after ``ClearSolutions`` it is an empty cell).

    The cells are read-only and not graded, so the gradebook does not miss them;
    ``tests/test_student_edition_contracts.py`` predicts the student edition with
    the same rule (``notebook_analysis.removed_in_student_edition``).
    """

    def preprocess(self, nb, resources):
        nb.cells = [c for c in nb.cells if not (c.cell_type == "markdown" and _robokin(c).get("role") == "prose")]
        return nb, resources


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


# ---------------------------------------------------------------- autograde
class RestoreMissingCells(OverwriteCells):
    """``OverwriteCells`` that puts a deleted test cell back after the nearest cell still there."""

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


class RobokinExecute(Execute):
    """nbgrader's ``Execute``, plus robokin.check's verdicts on a failing task."""

    viewer = Unicode("matplotlib", help="ROBOKIN_VIEWER of the grading kernel (how 3D scenes are shown)"
                     ).tag(config=True)

    async def _async_handle_timeout(self, timeout, cell=None):
        # nbgrader interrupts a cell that runs too long; the kernel then reports a
        # KeyboardInterrupt. Remember the cell, so that its error is named for what it is.
        if cell is not None:
            self._timed_out.add(id(cell))
        return await super()._async_handle_timeout(timeout, cell)

    def preprocess(self, nb, resources=None, km=None):
        self._timed_out: set[int] = set()
        self._report = {"explained": {}, "verdicts": None, "pairs": []}
        pairs = []
        for cell in nb.cells:
            for pair in _robokin(cell).get("explain", []):
                item = (_task_of(cell), pair[0], pair[1])
                if item not in pairs:
                    pairs.append(item)
        self._report["pairs"] = pairs
        self._last_code = max((i for i, c in enumerate(nb.cells) if c.cell_type == "code"), default=-1)
        previous = os.environ.get("ROBOKIN_VIEWER")
        os.environ["ROBOKIN_VIEWER"] = self.viewer  # inherited by the kernel started below
        try:
            nb, resources = super().preprocess(nb, resources, km=km)
        finally:
            if previous is None:
                os.environ.pop("ROBOKIN_VIEWER", None)
            else:
                os.environ["ROBOKIN_VIEWER"] = previous
        resources = resources if resources is not None else {}
        resources["robokin"] = self._report
        return nb, resources

    def _verdicts(self, pairs, index) -> list[dict] | None:
        """Run robokin.check on ``pairs`` in the student's kernel; None if that failed."""
        if not pairs:
            return []
        code = (f"__import__('robokin.check.grading', fromlist=['_']).print_verdicts("
                f"globals(), {[list(p) for p in pairs]!r}, {VERDICT_MARK!r})")
        probe = from_dict({"cell_type": "code", "metadata": {}, "source": code, "outputs": [],
                           "execution_count": None})
        original = self.nb.cells[index]
        try:
            super().execute_cell(probe, index, store_history=False)
        except Exception as exc:  # noqa: BLE001 - feedback is a bonus; grading goes on
            self.log.warning("robokin.check verdicts failed: %s", exc)
            return None
        finally:
            self.nb.cells[index] = original  # nbclient stores the executed cell at its index
        text = "".join(o.get("text", "") for o in probe.outputs if o.get("output_type") == "stream")
        for line in text.splitlines():
            if line.startswith(VERDICT_MARK):
                try:
                    return json.loads(line[len(VERDICT_MARK):])
                except ValueError:
                    return None
        return None

    def preprocess_cell(self, cell, resources, index):
        cell, resources = super().preprocess_cell(cell, resources, index)
        if id(cell) in self._timed_out or id(self.nb.cells[index]) in self._timed_out:
            for output in cell.get("outputs", []):
                if output.get("output_type") == "error" and output.get("ename") == "KeyboardInterrupt":
                    output["ename"] = "CellTimeoutError"
                    output["evalue"] = f"the cell ran longer than the time limit ({self.timeout} s) and was stopped"
        if cell.cell_type == "code" and utils.is_grade(cell):
            errors = [o for o in cell.outputs if o.output_type == "error"]
            if errors:
                self._explain(cell, errors[-1], index)
        if index == self._last_code:
            self._report["verdicts"] = self._verdicts([p[1:] for p in self._report["pairs"]], index)
        return cell, resources

    def _explain(self, cell, error, index) -> None:
        meta = _robokin(cell)
        task = _task_of(cell)
        grade_id = cell.metadata["nbgrader"]["grade_id"]
        lines = []
        where = ""
        traceback = ANSI.sub("", "\n".join(error.get("traceback", [])))
        hits = re.findall(r"Cell In\[(\d+)\], line (\d+)", traceback)
        source_lines = cell.source.splitlines()
        failing = ""
        for count, line in hits:
            if str(count) == str(cell.get("execution_count")) and 0 < int(line) <= len(source_lines):
                failing = source_lines[int(line) - 1].strip()
                where = f" at line {line}: `{failing}`"
                break
        if error.ename == "CellTimeoutError":
            lines.append(f"✘ Task {task} ({grade_id}) did not finish within the time limit: it was stopped.")
        else:
            message = f"{error.ename}: {error.evalue}".strip().rstrip(":")
            lines.append(f"✘ Task {task} ({grade_id}) failed{where}")
            lines.append(f"  {message}" if error.evalue else f"  ({error.ename})")
        reads = meta.get("reads", [])
        named = [n for n in reads if re.search(rf"\b{re.escape(n)}\b", failing)] or reads
        if named:
            lines.append("  It tests " + ", ".join(named) + f" from your answer{'s' if len(named) > 1 else ''}.")
        verdicts = self._verdicts([tuple(p) for p in meta.get("explain", [])], index) or []
        for v in verdicts:
            if v["status"] == "skipped":
                continue
            tag = f"  (typical mistake: {v['diagnosis']})" if v["typical"] else ""
            text = v["message"] if v["status"] in ("correct", "wrong") else f"✘ {v['message']}"
            lines.append(f"  robokin.check: {text}{tag}")
        self._report["explained"][grade_id] = lines
        note = from_dict({"output_type": "stream", "name": "stdout", "text": "\n".join(lines) + "\n\n"})
        position = cell.outputs.index(error)
        cell.outputs.insert(position, note)


class AutograderReport(NbGraderPreprocessor):
    """A markdown cell on top of the graded notebook: score per task, diagnoses, incidents."""

    max_notes = 12

    def preprocess(self, nb, resources):
        report = resources.get("robokin", {})
        grading = nb.metadata.get("robokin", {}).get("grading", {})
        titles = {t["task"]: t["title"] for t in grading.get("tasks", [])}
        scores: dict[int | None, list[float]] = {}
        for cell in nb.cells:
            if utils.is_grade(cell):
                score, maximum = utils.determine_grade(cell, self.log)
                entry = scores.setdefault(_task_of(cell), [0.0, 0.0])
                entry[0] += score or 0.0
                entry[1] += maximum
        total = sum(s for s, _ in scores.values())
        maximum = sum(m for _, m in scores.values())

        out = ["## Autograder report", "",
               f"**{_num(total)} of {_num(maximum)} points** from the automatic tests. "
               "A test scores 0 when it raises an error; the message below the failing test "
               "says which quantity it checks and, where `robokin.check` recognises it, which typical "
               "mistake your answer looks like.", "",
               "| task | points |", "|---|---|"]
        for task in sorted(scores, key=lambda t: (t is None, t or 0)):
            score, top = scores[task]
            label = f"Task {task}: {titles.get(task, '')}".rstrip(": ") if task is not None else "other tests"
            out.append(f"| {label} | {_num(score)} / {_num(top)} |")

        verdicts = report.get("verdicts") or []
        pairs = report.get("pairs") or []
        findings = []
        for (task, _, _), v in zip(pairs, verdicts):
            if v["status"] == "wrong" or (v["status"] == "missing" and scores.get(task, [1, 1])[0] < scores.get(task, [1, 1])[1]):
                tag = f" *(typical mistake: {v['diagnosis']})*" if v["typical"] else ""
                text = v["message"] if v["status"] == "wrong" else f"✘ {v['message']}"
                findings.append(f"- Task {task}: {_md(text)}{tag}")
        if findings:
            out += ["", "**What `robokin.check` says about your answers**", "", *findings]
        elif verdicts and all(v["status"] == "correct" for v in verdicts):
            out += ["", f"`robokin.check` finds all {len(verdicts)} answers it can check correct."]

        notes = self._incidents(nb)
        if notes:
            shown = notes[: self.max_notes]
            more = len(notes) - len(shown)
            out += ["", "**Notes on running your notebook**", "", *shown]
            if more > 0:
                out.append(f"- … and {more} more cells that raised an error.")
        cell = from_dict({"cell_type": "markdown", "metadata": {"robokin": {"role": "report"}},
                          "source": "\n".join(out)})
        if nb.cells and "id" in nb.cells[0]:
            cell["id"] = "robokin-report"
        nb.cells.insert(0, cell)
        return nb, resources

    def _incidents(self, nb) -> list[str]:
        notes = []
        for cell in nb.cells:
            if cell.cell_type != "code":
                continue
            label = _label(cell)
            if RESTORED_NOTE in cell.source:
                notes.append(f"- The test cell {label} was missing from your submission: it was put back "
                             "and run (do not delete test cells).")
            for output in cell.get("outputs", []):
                if output.get("output_type") != "error":
                    continue
                if output.get("ename") == "CellTimeoutError":
                    notes.append(f"- {label} ran longer than the time limit and was stopped; the cells after it "
                                 "ran as usual (look for an endless loop).")
                elif not utils.is_grade(cell):
                    evalue = _md(str(output.get("evalue", "")))[:120]
                    notes.append(f"- {label} (not graded) raised `{output.get('ename')}`"
                                 + (f": {evalue}" if evalue else "") + "; the notebook ran on.")
                break
        # timeouts and deleted tests first, then errors
        return sorted(notes, key=lambda n: 0 if ("time limit" in n or "missing" in n) else 1)


def _label(cell) -> str:
    count = cell.get("execution_count")
    where = f"In [{count}]" if count else "a cell"
    role = _robokin(cell).get("role")
    task = _task_of(cell)
    kind = {"answer": f"your answer to Task {task}", "test": f"a test of Task {task}"}.get(role)
    first = _first_line(cell.source)
    text = f"{where} `{first}`" if first else where
    return f"{text} ({kind})" if kind else text


def _num(x: float) -> str:
    return f"{x:g}"


def _md(text: str) -> str:
    """One line of plain text made safe inside a markdown list item."""
    return " ".join(text.split()).replace("|", "\\|").replace("<", "&lt;")
