"""``AutograderReport`` (autograde, after ``SaveAutoGrades``).

A markdown cell on top of the graded notebook (and so of the feedback): the score per task, what
``robokin.check`` found (a value found wrong that follows from a wrong earlier answer, while its own
tests pass, says so: :func:`follows_from`), and what went wrong outside the tests (a cell that
raised, a cell that timed out, a test cell that was deleted).
"""

from __future__ import annotations

import re

from nbformat.notebooknode import from_dict
from nbgrader import utils
from nbgrader.preprocessors import NbGraderPreprocessor

from tools.notebook_analysis import defined_names

from .cells import cell_label, failing_line, markdown_line, task_of
from .checks import called_as
from .failure_notes import cell_kinds, error_outputs, trace


#: What nbgrader writes into a test cell it put back (``OverwriteCells.missing_cell_transform``).
RESTORED_NOTE = "was missing from the submission"


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
                entry = scores.setdefault(task_of(cell), [0.0, 0.0])
                entry[0] += score or 0.0
                entry[1] += maximum
        total = sum(s for s, _ in scores.values())
        maximum = sum(m for _, m in scores.values())

        out = ["## Autograder report", "",
               f"**{_num(total)} of {_num(maximum)} points** from the automatic tests. "
               "A test scores 0 when it raises an error; the note below a failing test quotes the "
               "statement that failed, names your answers it depends on (and the earlier answer that "
               "made it fail, if any) and, where `robokin.check` recognises it, which typical "
               "mistake your answer looks like.", "",
               "| task | points |", "|---|---|"]
        for task in sorted(scores, key=lambda t: (t is None, t or 0)):
            score, top = scores[task]
            label = f"Task {task}: {titles.get(task, '')}".rstrip(": ") if task is not None else "other tests"
            out.append(f"| {label} | {_num(score)} / {_num(top)} |")

        verdicts = report.get("verdicts") or []
        pairs = report.get("pairs") or []
        # the answers found wrong: by a check, or as the cause of a failing test
        wrong = {v["quantity"] for v in verdicts if v["status"] == "wrong"} | set(report.get("wrong") or {})
        wrong |= {name for cause in (report.get("causes") or {}).values() for name in cause["names"]}
        findings = []
        for (task, _, _), v in zip(pairs, verdicts):
            lost = scores.get(task, [1, 1])[0] < scores.get(task, [1, 1])[1]
            if v["status"] == "wrong" or (v["status"] == "missing" and lost):
                tag = f" *(typical mistake: {v['diagnosis']})*" if v["typical"] else ""
                text = v["message"] if v["status"] == "wrong" else f"✘ {v['message']}"
                earlier = follows_from(nb, v["quantity"], wrong) if v["status"] == "wrong" else []
                if earlier:   # its own tests pass: the value is wrong because an earlier answer is
                    named = ", ".join(f"`{name}` (Task {task_of(nb.cells[cell])})" for name, cell in earlier)
                    tag = f" *(follows from your {named}; its own tests pass)*"
                called = called_as(v)
                where = f" {markdown_line(called)}" if called else ""
                findings.append(f"- Task {task}{where}: {markdown_line(text)}{tag}")
        if findings:
            out += ["", "**What `robokin.check` says about your answers**", "", *findings]
        elif verdicts and all(v["status"] == "correct" for v in verdicts):
            out += ["", f"`robokin.check` finds all {len(verdicts)} answers it can check correct."]

        # an answer this page reports correct is nobody's cause
        right = {v["quantity"] for v in verdicts if v["status"] == "correct"}
        right -= {v["quantity"] for v in verdicts if v["status"] in ("wrong", "missing")}
        # one line per answer: the causes of all failing tests merged by the answer's name, its
        # tests in notebook order (a test's note records its causes grouped by the reason)
        order = {cell.metadata.get("nbgrader", {}).get("grade_id"): i for i, cell in enumerate(nb.cells)}
        causes: dict[str, dict] = {}
        for cause in (report.get("causes") or {}).values():
            if cause.get("line"):   # a line of an answer cell that raised, not in an answer's body
                merged = causes.setdefault(cause["line"], {"task": cause["task"], "why": [], "tests": [],
                                                           "line": True})
                merged["why"] += [cause["why"]] if cause["why"] not in merged["why"] else []
                merged["tests"] += [t for t in cause["tests"] if t not in merged["tests"]]
            for name in cause["names"]:
                if name in right:
                    continue
                merged = causes.setdefault(name, {"task": cause["task"], "why": [], "tests": []})
                merged["why"] += [cause["why"]] if cause["why"] not in merged["why"] else []
                merged["tests"] += [t for t in cause["tests"] if t not in merged["tests"]]
        if causes:
            out += ["", "**Where to start**", ""]
            ordered = sorted(causes.items(), key=lambda kv: (kv[1]["task"] is None, kv[1]["task"] or 0, kv[0]))
            for name, cause in ordered[: self.max_notes]:
                of_task = f" (Task {cause['task']})" if cause["task"] is not None else ""
                tests = sorted(cause["tests"], key=lambda t: order.get(t, len(order)))
                if cause.get("line"):   # the label says where: In [5], line 7, `...` (your answer to Task 3)
                    out.append(f"- {name} {' and '.join(markdown_line(w) for w in cause['why'])}; "
                               f"the failing test{'s' if len(tests) > 1 else ''} {', '.join(tests)} "
                               f"depend{'' if len(tests) > 1 else 's'} on that cell. Fix it first.")
                    continue
                # each reason reads after "its": "its own test … failed and its value is wrong"
                why = " and its ".join(markdown_line(w) for w in _merge_own_tests(cause["why"], order))
                out.append(f"- `{name}`{of_task}: its {why}; "
                           f"the failing test{'s' if len(tests) > 1 else ''} {', '.join(tests)} "
                           f"depend{'' if len(tests) > 1 else 's'} on it. Fix it first.")
            if len(ordered) > self.max_notes:
                out.append(f"- … and {len(ordered) - self.max_notes} more answers that tests depend on.")

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
            label = cell_label(cell)
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
                    evalue = markdown_line(str(output.get("evalue", "")))[:120]
                    label = cell_label(cell, failing_line(cell, output))
                    notes.append(f"- {label} (not graded) raised `{output.get('ename')}`"
                                 + (f": {evalue}" if evalue else "") + "; the notebook ran on.")
                break
        # timeouts and deleted tests first, then errors
        return sorted(notes, key=lambda n: 0 if ("time limit" in n or "missing" in n) else 1)


def _merge_own_tests(reasons: list[str], order: dict) -> list[str]:
    """The reasons of one answer with its "own test(s) … failed" merged into one, tests in notebook order."""
    own: list[str] = []
    others = []
    for reason in reasons:
        found = re.fullmatch(r"own tests? (.+) failed", reason)
        if found:
            own += [t for t in found.group(1).split(", ") if t not in own]
        else:
            others.append(reason)
    own.sort(key=lambda t: order.get(t, len(order)))
    merged = [f"own test{'s' if len(own) > 1 else ''} {', '.join(own)} failed"] if own else []
    return merged + others


def follows_from(nb, name: str, wrong: set[str]) -> list[tuple[str, int]]:
    """``[(answer, its cell)]``: the answers of earlier answer cells among ``wrong`` that the
    student's answer ``name`` is computed from (traced through the statements of its answer cell),
    when the tests of its task that read ``name`` all passed (one at least); else ``[]``.

    Such a value is wrong because of them: the tests of its task, which grade it against the
    student's own earlier answers, find its own step right. The report says so next to
    ``robokin.check``'s ✘, instead of a typical mistake of its own."""
    if not name.isidentifier():
        return []
    kinds = cell_kinds(nb)
    home = _answer_cell(kinds, len(kinds), name)
    if home is None:
        return []
    # the answer cell read as plain code: its name then has the answers of earlier cells as roots
    binding = trace(kinds[:home] + [("code", kinds[home][1]), ("code", name)])[-1].get(name)
    roots = sorted(binding.roots - {name}) if binding is not None else []
    earlier = [(root, cell) for root, cell in ((r, _answer_cell(kinds, home, r)) for r in roots)
               if root in wrong and cell is not None]
    if not earlier:
        return []
    task = task_of(nb.cells[home])
    reads = trace(kinds)
    tests = [cell for index, cell in enumerate(nb.cells)
             if index > home and cell.cell_type == "code" and utils.is_grade(cell) and task_of(cell) == task
             and any(name in b.roots for b in reads[index].values())]
    # no test of it, or one that failed: it may be wrong on its own
    return earlier if tests and not any(error_outputs(cell) for cell in tests) else []


def _answer_cell(kinds: list[tuple[str, str]], before: int, name: str) -> int | None:
    """The index of the last answer cell before ``before`` that binds ``name``, if any."""
    found = None
    for index, (kind, code) in enumerate(kinds[:before]):
        try:
            if kind == "answer" and name in defined_names(code):
                found = index
        except SyntaxError:
            continue
    return found


def _num(x: float) -> str:
    return f"{x:g}"
