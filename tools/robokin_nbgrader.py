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
    nbgrader's ``Execute``, with the kernel in a bubblewrap sandbox
    (``tools/robokin_sandbox.py``); a test scores by pass/fail only (its stderr is
    a note, a result it shows no partial credit); a kernel that dies or ignores
    the interrupt is killed, restarted and brought back to where it was (the cells
    before are run again), so it costs only that cell (after the last test, grading
    just stops there: nothing graded is left to run). When a test cell fails,
    ``FailureNotes`` writes above the traceback the failing statement, the
    student's answers it depends on (traced through the read-only cells), the root
    cause among them, and what ``robokin.check`` (asked in the student's kernel)
    says about those answers; after the last test it asks about every answer it
    has a check for (``registered_pairs``).
``HideHiddenTests`` (generate_feedback)
    The hidden tests of the test cells are not in the feedback page: nbgrader's
    ``ClearHiddenTests`` takes them out, the tracebacks lose their code, and the
    verdict and diagnosis stay.
``OfflineMathJaxHTMLExporter`` (generate_feedback)
    nbgrader's HTML exporter with MathJax 3 inlined in the page (from the
    ``django-static-mathjax`` wheel the book uses) instead of loaded from a CDN:
    the feedback page is read offline, and ``release_feedback`` hands out the
    HTML file only. The page is nbconvert's, byte for byte, made with less CPU
    (code highlighting and markdown memoised per process).
``RobokinCheckCellMetadata`` (every pipeline, replaces ``CheckCellMetadata``)
    nbgrader's check of the cells' nbgrader metadata, with nbgrader's schema
    checked once per process instead of once per cell (the same verdicts).
``AutograderReport`` (autograde, after ``SaveAutoGrades``)
    A markdown cell on top of the graded notebook (and so of the feedback): the
    score per task, what ``robokin.check`` found, and what went wrong outside the
    tests (a cell that raised, a cell that timed out, a test cell that was deleted).
``GradingIncidents`` (autograde, after ``AutograderReport``)
    Adds to the report what happened to the kernel (died, killed), the tests not
    run because of it, and the tests whose code wrote to stderr.

A new gradebook records the revision of nbgrader's gradebook schema: it is read
here in the process (``alembic_head``), not by running ``alembic heads`` as a
program of its own as nbgrader does.

The cell roles come from ``tools/nbgrader_metadata.py`` (``metadata.robokin``).
"""

from __future__ import annotations

import functools
import json
import os
import re
import sys
import textwrap
import traceback
from pathlib import Path

import jsonschema
from jinja2 import pass_context
from jupyter_core.utils import run_sync
from nbclient.exceptions import CellTimeoutError, DeadKernelError
from nbconvert.exporters import HTMLExporter
from nbconvert.filters.highlight import Highlight2HTML
from nbformat.notebooknode import from_dict
from nbgrader import api as nbgrader_api
from nbgrader import utils
from nbgrader.coursedir import CourseDirectory
from nbgrader.dbutil import ALEMBIC_DIR
from nbgrader.nbgraderformat import MetadataValidator, ValidationError
from nbgrader.nbgraderformat.common import BaseMetadataValidator
from nbgrader.api import MissingEntry
from nbgrader.preprocessors import CheckCellMetadata, ClearHiddenTests, Execute, NbGraderPreprocessor, OverwriteCells
from traitlets import Bool, Unicode

sys.path.insert(0, str(Path(__file__).resolve().parent))

from notebook_analysis import (
    Binding,
    _check_aliases,
    defined_names,
    free_names,
    level2_headings,
    mark_solution,
    statement_at,
    statement_span,
)
from notebook_analysis import trace as _cell_trace
from robokin_sandbox import SandboxedKernelManager, bwrap_executable, sandbox_wanted

TYPE_PROBE = "type"  # robokin.check.grading.TYPE_PROBE: what a value is, no verdict
ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")
VERDICT_MARK = "ROBOKIN-VERDICTS"
RESTORED_NOTE = "was missing from the submission"
STDERR_NOTE = "[written to stderr; not counted as a failure]"
#: ename of the error output that zeroes a test the kernel could not run (it had died).
NOT_RUN = "TestNotRun"
#: ename of a cell whose kernel died, or was killed because it ignored the interrupt.
KERNEL_LOST = "KernelLost"


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


def hidden_lines(source: str, begin: str | None = None, end: str | None = None) -> set[int]:
    """The numbers (from 1) of the lines of ``source`` in its hidden tests, delimiters included:
    the lines nbgrader's ``ClearHiddenTests`` removes (its default delimiters unless given)."""
    begin = begin or ClearHiddenTests.begin_test_delimeter.default_value
    end = end or ClearHiddenTests.end_test_delimeter.default_value
    out, inside = set(), False
    for number, line in enumerate(source.split("\n"), 1):
        if begin in line:
            inside = True
        if inside:
            out.add(number)
        if end in line:
            inside = False
    return out


def visible_source(source: str) -> str:
    """``source`` without its hidden tests, as nbgrader's ``ClearHiddenTests`` leaves it for a student."""
    if not hidden_lines(source):
        return source
    cell = from_dict({"cell_type": "code", "metadata": {}, "source": source, "outputs": [], "execution_count": None})
    return ClearHiddenTests(enforce_metadata=False).preprocess_cell(cell, {}, 0)[0].source


# ---------------------------------------------------------------- every pipeline
_NBGRADER_ALEMBIC_VERSION = nbgrader_api.get_alembic_version


def alembic_head() -> str:
    """The revision of nbgrader's gradebook schema, which a new gradebook records: what nbgrader's
    ``get_alembic_version`` reads from ``alembic heads``, run as a program -- a Python process of
    its own, 0.9 s of CPU for every new course -- read here from nbgrader's migration scripts in
    this process (0.08 s). With other than one head, nbgrader's own function answers."""
    from alembic.config import Config
    from alembic.script import ScriptDirectory

    config = Config()
    config.set_main_option("script_location", ALEMBIC_DIR)
    heads = ScriptDirectory.from_config(config).get_heads()
    return heads[0] if len(heads) == 1 else _NBGRADER_ALEMBIC_VERSION()


# a new gradebook (the course's first nbgrader command) asks for it
nbgrader_api.get_alembic_version = alembic_head


class _SchemaCheckedOnce(BaseMetadataValidator):
    """nbgrader's per-cell check of the metadata against its schema, with the schema itself checked
    once per process: ``jsonschema.validate``, which nbgrader calls for every cell, first checks
    nbgrader's own (constant) schema against the JSON meta-schema -- nine tenths of the time
    ``CheckCellMetadata`` takes. A cell's metadata is then validated as ``jsonschema.validate``
    does it (the same best-matching error); a cell without metadata, or of another schema version
    (an error), goes to nbgrader's own code."""

    _validators: dict[int, object] = {}

    def validate_cell(self, cell) -> None:
        meta = cell.metadata.get("nbgrader")
        if meta is None or meta.get("schema_version", 0) != self.schema_version:
            return super().validate_cell(cell)
        validator = self._validators.get(self.schema_version)
        if validator is None:
            cls = jsonschema.validators.validator_for(self.schema)
            cls.check_schema(self.schema)
            validator = self._validators[self.schema_version] = cls(self.schema)
        error = jsonschema.exceptions.best_match(validator.iter_errors(meta))
        if error is not None:
            raise error
        return None


class _MetadataValidator(MetadataValidator, _SchemaCheckedOnce):
    """nbgrader's metadata validator (its checks beyond the schema included), the schema
    checked once per process (:class:`_SchemaCheckedOnce` comes between it and its base)."""


class RobokinCheckCellMetadata(CheckCellMetadata):
    """nbgrader's ``CheckCellMetadata`` (the same verdicts, errors and messages), with the schema
    checked once per process instead of once per cell (:class:`_SchemaCheckedOnce`)."""

    def preprocess(self, nb, resources):
        try:
            _MetadataValidator().validate_nb(nb)
        except ValidationError:
            self.log.error(traceback.format_exc())
            msg = "Notebook failed to validate; the nbgrader metadata may be corrupted."
            self.log.error(msg)
            raise ValidationError(msg)  # noqa: B904 - as nbgrader's CheckCellMetadata raises it
        return nb, resources


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
    """Leave out of the student edition the solution prose that ``ClearSolutions`` emptied.

    A prose cell with text outside its own ``BEGIN SOLUTION``/``END SOLUTION``
    markers keeps that text. The cells are read-only and not graded, so the gradebook
    does not miss them; ``tests/test_student_edition_contracts.py`` predicts the
    student edition with the same rule (``notebook_analysis.student_markdown``).
    """

    def preprocess(self, nb, resources):
        nb.cells = [c for c in nb.cells if not (
            c.cell_type == "markdown" and _robokin(c).get("role") == "prose" and not c.source.strip())]
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


class RobokinExecute(Execute):
    """nbgrader's ``Execute`` in a sandbox, scoring a test by pass/fail, plus robokin.check's verdicts.

    - The kernel runs in bubblewrap (``tools/robokin_sandbox.py``) unless ``sandbox`` is
      False or ``ROBOKIN_GRADING_SANDBOX=off``; without ``bwrap`` grading stops with a
      message naming the package to install.
    - A test cell fails only by an error output: what it writes to stderr (a warning,
      a log message) stays in its output marked as a note, and a result or display it
      shows is kept as a display (nbgrader would read a number as partial credit).
    - A kernel that dies, or ignores the interrupt after the time limit (it is then
      killed), is restarted and the cells before are run again: only that cell is lost.
      If that fails, the cells after it are not run and their tests score 0 with the
      reason. After the last test (nothing graded follows) it is not restarted: the
      cells after it are not run, and no score changes. The report names the
      incident (``resources['robokin']['incidents']``, written by ``GradingIncidents``).
    """

    viewer = Unicode("matplotlib", help="ROBOKIN_VIEWER of the grading kernel (how 3D scenes are shown)"
                     ).tag(config=True)
    sandbox = Bool(True, help="run each submission's kernel in bubblewrap (bwrap); "
                   "ROBOKIN_GRADING_SANDBOX=off|on overrides it").tag(config=True)

    def create_kernel_manager(self):
        if not self._sandboxed:
            return super().create_kernel_manager()
        if not self.kernel_name:
            self.kernel_name = self.nb.metadata.get("kernelspec", {}).get("name") or "python3"
        folder = self.resources.get("metadata", {}).get("path") or os.getcwd()
        course = Path(CourseDirectory(config=self.config).root).resolve()
        exchange = self.config.get("Exchange", {}).get("root", "/srv/nbgrader/exchange")
        hidden = [str(course), str(Path(exchange).resolve()), str(Path(__file__).resolve().parent.parent)]
        self.km = SandboxedKernelManager(kernel_name=self.kernel_name, config=self.config,
                                         writable=str(Path(folder).resolve()), hidden=hidden)
        return self.km

    def _grade_by_pass_fail(self, cell) -> None:
        """A test cell's outputs such that only an error output can lower its score.

        Its stderr (warnings, log messages) becomes one stdout note, where the first stderr
        output was; a result it shows (``execute_result``) becomes a display.
        """
        outputs, stderr, position = [], [], None
        for output in cell.get("outputs", []):
            if output.get("output_type") == "stream" and output.get("name") == "stderr":
                position = len(outputs) if position is None else position
                stderr.append(output.get("text", ""))
                continue
            if output.get("output_type") == "execute_result":
                output["output_type"] = "display_data"
                output.pop("execution_count", None)
            outputs.append(output)
        if stderr:
            outputs.insert(position, from_dict({"output_type": "stream", "name": "stdout",
                                                "text": f"{STDERR_NOTE}\n{''.join(stderr)}"}))
            self._report["incidents"].append({"kind": "stderr", "label": _label(cell)})
        cell.outputs = outputs

    def _kernel_lost(self, cell, index, exc) -> None:
        """The kernel died in ``cell``, or ignored the interrupt at the time limit.

        The kernel is killed and restarted, and the code cells before this one are run
        again (their outputs are kept from the first run), so that the notebook goes on
        and loses only this cell. If that fails too, grading stops here: the cells after
        it are not run (``_not_run``). When nothing graded comes after the cell (no test,
        and robokin.check's verdicts are taken), grading stops there at once: restarting
        the kernel and running the notebook again would change no score.
        """
        hung = isinstance(exc, CellTimeoutError)
        if hung:
            self.log.error("The kernel ignored the interrupt after %s s: killing it", self.timeout)
        cell = self.nb.cells[index]
        why = (f"the cell ran longer than the time limit ({self.timeout} s) and ignored the interrupt: "
               "the kernel was killed" if hung else
               "the kernel died while running this cell (os._exit, a crash, or not enough memory)")
        if utils.is_grade(cell):   # the test scores 0
            output = {"output_type": "error", "ename": KERNEL_LOST, "evalue": why,
                      "traceback": [f"{KERNEL_LOST}: {why}"]}
        else:                      # not an error of the notebook that ran on: said in the report
            output = {"output_type": "stream", "name": "stderr", "text": f"{KERNEL_LOST}: {why}\n"}
        cell.setdefault("outputs", []).append(from_dict(output))
        later = [c for c in self.nb.cells[index + 1:] if c.cell_type == "code" and utils.is_grade(c)]
        incident = {"kind": "hang" if hung else "died", "label": _label(cell), "graded": utils.is_grade(cell),
                    "tests_lost": len(later), "replayed": False,
                    # nothing graded after it (no test, robokin.check's verdicts taken): no restart
                    "nothing_after": not later and index > self._last_code}
        self._report["incidents"].append(incident)
        if not incident["nothing_after"] and not self._replays and self._restart_and_replay(index):
            incident["replayed"], incident["tests_lost"] = True, 0
            self._replays += 1
            return
        try:
            run_sync(self.km.shutdown_kernel)(now=True)
        except Exception as kill_error:  # noqa: BLE001 - it is already gone
            self.log.warning("Stopping the kernel: %s", kill_error)
        self._stopped = incident

    def _restart_and_replay(self, index) -> bool:
        """A fresh kernel in the state before cell ``index``: True if that worked."""
        self.log.warning("Restarting the kernel and running the %d cells before cell %d again", index, index)
        try:
            run_sync(self.km.restart_kernel)(now=True)
            run_sync(self.kc.wait_for_ready)(timeout=self.startup_timeout)
        except Exception as restart_error:  # noqa: BLE001 - then grading stops at this cell
            self.log.error("Restarting the kernel failed: %s", restart_error)
            return False
        for number, original in enumerate(self.nb.cells[:index]):
            if original.cell_type != "code" or not original.source.strip() or any(
                    o.get("ename") == "CellTimeoutError" for o in original.get("outputs", [])):
                continue
            copy = from_dict(json.loads(json.dumps(original)))
            try:
                super().execute_cell(copy, number, store_history=True)
            except (DeadKernelError, CellTimeoutError) as again:
                self.log.error("Running cell %d again, the kernel was lost again: %s", number, again)
                return False
            finally:
                self.nb.cells[number] = original   # nbclient stores the executed copy at its index
        return True

    def _not_run(self, cell):
        if cell.cell_type != "code":
            return cell
        cell.outputs = []
        cell.execution_count = None
        if utils.is_grade(cell):
            why = f"not run: the kernel had stopped in {self._stopped['label']}"
            cell.outputs.append(from_dict({"output_type": "error", "ename": NOT_RUN, "evalue": why,
                                           "traceback": [f"{NOT_RUN}: {why}"]}))
            self._report["incidents"].append({"kind": "not_run", "label": _label(cell)})
        return cell

    async def _async_handle_timeout(self, timeout, cell=None):
        # nbgrader interrupts a cell that runs too long; the kernel then reports a
        # KeyboardInterrupt. Remember the cell, so that its error is named for what it is.
        if cell is not None:
            self._timed_out.add(id(cell))
        return await super()._async_handle_timeout(timeout, cell)

    def preprocess(self, nb, resources=None, km=None):
        self._sandboxed = km is None and sandbox_wanted(self.sandbox)
        if self._sandboxed:
            bwrap_executable()   # stops grading with a message naming the package when it is missing
        self._stopped: dict | None = None
        self._replays = 0
        self._timed_out: set[int] = set()
        self._report = {"explained": {}, "verdicts": None, "pairs": [], "incidents": []}
        pairs = []
        for cell in nb.cells:
            for pair in _robokin(cell).get("explain", []):
                item = (_task_of(cell), pair[0], pair[1])
                if item not in pairs:
                    pairs.append(item)
        pairs += [item for item in registered_pairs(nb) if item not in pairs]
        self._report["pairs"] = pairs
        # robokin.check's verdicts on every task: after the last test (the answers are all
        # there), so that a kernel that dies in a later cell does not take them along
        self._last_code = max((i for i, c in enumerate(nb.cells) if c.cell_type == "code" and utils.is_grade(c)),
                              default=max((i for i, c in enumerate(nb.cells) if c.cell_type == "code"), default=-1))
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
        if self._stopped is not None:
            return self._not_run(cell), self.resources
        try:
            cell, resources = super().preprocess_cell(cell, resources, index)
        except (DeadKernelError, CellTimeoutError) as exc:
            self._kernel_lost(cell, index, exc)
            return self.nb.cells[index], self.resources
        if cell.cell_type == "code" and utils.is_grade(cell):
            self._grade_by_pass_fail(cell)
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
        notes = FailureNotes(self.nb, index, self._report)
        verdicts = self._verdicts(notes.pairs(error), index) or []
        lines = notes.lines(error, verdicts)
        self._report["explained"][cell.metadata["nbgrader"]["grade_id"]] = lines
        note = from_dict({"output_type": "stream", "name": "stdout", "text": "\n".join(lines) + "\n\n"})
        position = cell.outputs.index(error)
        cell.outputs.insert(position, note)


# ---------------------------------------------------------------- what a failing test says
def _cell_kinds(nb) -> list[tuple[str, str]]:
    """``(kind, source)`` of every cell for ``notebook_analysis.trace``: the student's answer
    cells are ``"answer"``, other code cells (given, tests, the student's own) ``"code"``."""
    out = []
    for cell in nb.cells:
        if cell.cell_type != "code":
            out.append(("markdown", ""))
        else:
            out.append(("answer" if utils.is_solution(cell) else "code", cell.source))
    return out


def _errors(cell) -> list:
    return [o for o in cell.get("outputs", []) if o.get("output_type") == "error"]


def _identifier_names(expression: str) -> set[str]:
    return free_names(expression) if expression.strip() else set()


@functools.cache
def _check_names() -> dict[str, str]:
    """``nbgrader_metadata.check_names()``, read once per process (robokin.check's registry does not
    change while a command runs; autograde asks for it for every submission): read-only."""
    from nbgrader_metadata import check_names

    return check_names()


def registered_pairs(nb) -> list[tuple[int | None, str, str]]:
    """``(task, check, name)`` for every exercise check registered in ``robokin.check`` whose
    quantity has the name of a variable or function that an answer cell binds, in the
    chapters of checks the notebook uses (imports, or names in its test cells' metadata),
    unless a test cell's metadata already explains with that check."""
    try:
        names = _check_names()
    except Exception:  # noqa: BLE001 - feedback is a bonus; grading goes on
        return []
    chapters, explained = set(), set()
    for cell in nb.cells:
        if cell.cell_type == "code":
            chapters |= {v for v in _check_aliases(cell.source).values() if v != "*"}
            explained |= {p[0] for p in _robokin(cell).get("explain", [])}
    chapters |= {check.split(".")[0] for check in explained}
    bound: dict[str, int | None] = {}
    for cell in nb.cells:
        if cell.cell_type == "code" and utils.is_solution(cell):
            for name in defined_names(cell.source):
                bound[name] = _task_of(cell)
    # a check the chapter already calls on an answer is asked as the chapter calls it (e.g.
    # through a lambda that fixes default arguments), not on the bare name
    return [(bound[name], check, name) for check, name in sorted(names.items())
            if check.split(".")[0] in chapters and name in bound and check not in explained]


class FailureNotes:
    """The note under a failing test: what failed, which of the student's answers it
    depends on, which of those is the root cause, and what ``robokin.check`` says.

    * the whole failing statement is quoted (a multi-line ``assert`` too);
    * the names it reads are traced back (``notebook_analysis.trace``) through the
      read-only cells and the earlier statements of the test cell to the answer
      cells: only names bound by an answer cell are called "your answer";
    * among those answers, the ones whose own earlier test failed, whose cell raised,
      or that ``robokin.check`` found wrong are named as the root cause (the first
      in the chain: an answer that is wrong only because it uses another wrong one
      is left out);
    * ``robokin.check`` is asked about those answers only, and a typical mistake is
      named only for a check run on the student's value of those very names;
    * a test that fails with a wrong type (``AttributeError``, ``TypeError``, ...)
      says what the answer is and what was expected (the stub's docstring, the
      task statement, or the check's signature).

    ``report`` is the run's shared record (``resources["robokin"]``): it collects what
    checks found wrong (``"wrong"``) and the root causes (``"causes"``) for the report.
    """

    max_statement_lines = 12
    type_errors = ("AttributeError", "TypeError", "IndexError", "KeyError", "ValueError")

    def __init__(self, nb, index: int, report: dict):
        self.nb = nb
        self.index = index
        self.cell = nb.cells[index]
        self.report = report
        self.grade_id = self.cell.metadata.get("nbgrader", {}).get("grade_id", "?")
        self.task = _task_of(self.cell)
        self._analysed = False

    # -- the static analysis
    def _failing_line(self, error) -> int | None:
        traceback = ANSI.sub("", "\n".join(error.get("traceback", [])))
        count = self.cell.get("execution_count")
        for number, line in re.findall(r"Cell In\[(\d+)\], line (\d+)", traceback):
            if str(number) == str(count) and 0 < int(line) <= len(self.cell.source.splitlines()):
                return int(line)
        return None

    def analyse(self, error) -> None:
        if self._analysed:
            return
        self._analysed = True
        self.line = self._failing_line(error)
        kinds = _cell_kinds(self.nb)[: self.index]
        self.statement = statement_at(self.cell.source, self.line) if self.line else ""
        if self.statement:
            first, _ = statement_span(self.cell.source, self.line)
            own = [("code", s) for s in _statements("\n".join(self.cell.source.splitlines()[: first - 1]))]
            reads = trace(kinds + own + [("code", self.statement)])[-1]
        else:
            reads = trace(kinds + [("code", self.cell.source)])[-1]
        student = {n: b for n, b in reads.items() if b.roots}
        if self.statement and not student:  # the failing line reads nothing of the student's
            reads = trace(kinds + [("code", self.cell.source)])[-1]
            student = {n: b for n, b in reads.items() if b.roots}
        self.yours = {n: b for n, b in student.items() if b.answer and b.cell < self.index}
        self.derived = {n: b for n, b in student.items() if n not in self.yours}
        # the answers the whole test reads itself (a test that fails before it reaches its check of
        # J_lift still checks J_lift: the note gives robokin.check's verdict on it)
        whole = trace(kinds + [("code", visible_source(self.cell.source))])[-1]
        self.checked = {n for n, b in whole.items() if b.answer and b.cell < self.index}
        self.roots = set().union(*(b.roots for b in student.values())) if student else set()
        table = _bindings(kinds)
        self.answer_cell = {n: table[n].cell for n in self.roots if n in table}
        self.root_roots = {n: table[n].roots for n in self.roots if n in table}
        self._kinds = kinds
        self.causes = self._causes(kinds)

    def _causes(self, kinds, correct: frozenset[str] = frozenset()) -> dict[str, str]:
        """``{answer name: why it is suspect}`` for the root causes of this failure (the why
        reads after "its" or "their": ``"own test task2_test1 failed"``). An answer that
        ``robokin.check`` finds correct (``correct``) is never a cause, and its own tests are
        the failing tests of its task that read it."""
        why: dict[str, str] = {}
        all_reads = trace(kinds)
        for name in sorted(self.roots - set(correct)):
            cell = self.answer_cell.get(name)
            if cell is not None and _errors(self.nb.cells[cell]):
                error = _errors(self.nb.cells[cell])[0]
                count = self.nb.cells[cell].get("execution_count")
                where = f" In [{count}]" if count else ""
                why[name] = f"answer cell{where} raised {error.get('ename')}"
                continue
            failed = []
            task = _task_of(self.nb.cells[cell]) if cell is not None else None
            for j in range(cell + 1 if cell is not None else 0, self.index):
                other = self.nb.cells[j]
                if other.cell_type == "code" and utils.is_grade(other) and _errors(other) \
                        and _task_of(other) == task:   # a test of another task is not its own
                    roots = set().union(*(b.roots for b in all_reads[j].values())) if all_reads[j] else set()
                    if name in roots:
                        failed.append(other.metadata["nbgrader"]["grade_id"])
            if failed:
                why[name] = f"own test {failed[0]} failed" if len(failed) == 1 else \
                    f"own tests {', '.join(failed)} failed"
            elif name in self.report.get("wrong", {}):
                why[name] = f"value is wrong for robokin.check ({self.report['wrong'][name]})"
        # the first link of the chain: leave out an answer that uses another suspect one
        return {n: w for n, w in why.items()
                if not any(other != n and other in self.root_roots.get(n, ()) for other in why)}

    # -- the questions to the kernel
    def pairs(self, error) -> list[tuple[str, str]]:
        """``(check, quantity)`` pairs to evaluate in the kernel: the checks of this test and
        the registered checks, on the student's answers it depends on; type probes."""
        self.analyse(error)
        names = self.roots | set(self.yours)
        out: list[tuple[str, str]] = []
        own = [tuple(p) for p in _robokin(self.cell).get("explain", [])]
        candidates = [(check, quantity, names | self.checked) for check, quantity in own]
        candidates += [(check, name, names) for _, check, name in self.report.get("pairs", [])]
        for check, quantity, allowed in candidates:
            used = _identifier_names(quantity)
            if used and used <= allowed | _BUILTIN_NAMES and (check, quantity) not in out:
                out.append((check, quantity))
        if error.get("ename") in self.type_errors:
            for name in sorted(self.yours):
                out.append((TYPE_PROBE, name))
        return out

    # -- the note
    def lines(self, error, verdicts: list[dict]) -> list[str]:
        self.analyse(error)
        out = []
        if error.get("ename") == "CellTimeoutError":
            out.append(f"✘ Task {self.task} ({self.grade_id}) did not finish within the time limit: "
                       "it was stopped.")
        elif self.line and self.line in hidden_lines(self.cell.source):
            # a hidden test: its verdict and diagnosis, never its code (not even the line's number)
            out.append(f"✘ Task {self.task} ({self.grade_id}) failed in its hidden tests "
                       "(tests run when grading, whose code is not shown):")
            message = f"{error.get('ename')}: {error.get('evalue', '')}".strip().rstrip(":")
            out.append(f"  {message}" if error.get("evalue") else f"  ({error.get('ename')})")
        else:
            where = f" at line {self.line}:" if self.line else ""
            out.append(f"✘ Task {self.task} ({self.grade_id}) failed{where}")
            statement = self.statement.splitlines()
            if len(statement) > self.max_statement_lines:
                statement = statement[: self.max_statement_lines] + ["..."]
            out += [f"      {line}" for line in textwrap.dedent("\n".join(statement)).splitlines()]
            message = f"{error.get('ename')}: {error.get('evalue', '')}".strip().rstrip(":")
            out.append(f"  {message}" if error.get("evalue") else f"  ({error.get('ename')})")
        if self.yours:
            out.append(f"  It checks your answer{'s' if len(self.yours) > 1 else ''} "
                       f"{self._named(self.yours)}.")
        derived = {n: b for n, b in self.derived.items() if n not in self._hidden_names()}
        if derived:
            upstream = sorted(set().union(*(b.roots for b in derived.values())))
            given = ", ".join(f"`{n}`" for n in sorted(derived))
            here = [b.cell >= self.index for b in derived.values()]
            where = ("earlier in this test cell" if all(here) else "by read-only cells" if not any(here)
                     else "by read-only cells and earlier in this test cell")
            # what it reads of the student's, not that it is "computed from" them: a finite-difference
            # reference at the student's q is robokin's value there, not the student's
            several = len(derived) > 1
            out.append(f"  It also reads {given}, computed {where}; {'they use' if several else 'it uses'} "
                       f"your answer{'s' if len(upstream) > 1 else ''} {self._named(upstream)}.")
        for name in sorted(self.yours):
            missing = f"name '{name}' is not defined"
            if error.get("ename") == "NameError" and missing in str(error.get("evalue", "")):
                cell = self.yours[name].cell
                out.append(f"  `{name}` was never defined: your answer cell of Task "
                           f"{_task_of(self.nb.cells[cell])} did not finish (see its error above it).")
        correct = frozenset(v["quantity"] for v in verdicts if v.get("status") == "correct")
        if correct & set(self.causes):   # robokin.check finds it right: not the cause
            self.causes = self._causes(self._kinds, correct)
        if self.causes:
            groups: dict[tuple, list[str]] = {}
            for name, why in sorted(self.causes.items()):
                groups.setdefault((self._task_of_name(name), why), []).append(name)
            items = "; ".join(f"{self._named(names)}: {'its' if len(names) == 1 else 'their'} {why}"
                              for (_, why), names in groups.items())
            out.append(f"  This test failed because of {items}. Fix that first: this test may then pass.")
            record = self.report.setdefault("causes", {})
            for (task, why), names in groups.items():
                entry = record.setdefault(f"{task}|{why}", {"task": task, "why": why, "names": [], "tests": []})
                entry["names"] = sorted(set(entry["names"]) | set(names))
                entry["tests"].append(self.grade_id)
        checked = {name for v in verdicts if v.get("status") not in ("info", "skipped")
                   for name in _identifier_names(v["quantity"])}
        infos: dict[str, list[str]] = {}
        for v in verdicts:
            if v.get("status") == "info" and v["quantity"] not in checked:
                infos.setdefault(v.get("got") or v.get("message", ""), []).append(v["quantity"])
        for got, names in infos.items():
            expected = [_expected_from_notebook(self.nb, self.yours[n].cell, n) for n in names if n in self.yours]
            listed = ", ".join(f"`{n}`" for n in names)
            text = f"  Your {listed} {'is' if len(names) == 1 else 'are'} {got}"
            hints = "; ".join(e for e in expected if e)
            out.append(text + (f"; expected: {hints}" if hints else "."))
        names = self.roots | set(self.yours) | self.checked
        wrong = self.report.setdefault("wrong", {})
        for v in verdicts:
            if v.get("status") in ("skipped", "info"):
                continue
            used = _identifier_names(v["quantity"])
            mine = bool(used) and used <= names | _BUILTIN_NAMES
            tag = f"  (typical mistake: {v['diagnosis']})" if v.get("typical") and mine else ""
            text = v["message"] if v["status"] in ("correct", "wrong") else f"✘ {v['message']}"
            out.append(f"  robokin.check{_called(v)}: {text}{tag}")
            if v["status"] in ("wrong", "missing") and v["quantity"].isidentifier():
                wrong.setdefault(v["quantity"], v.get("diagnosis") or v["status"])
        return out

    def _hidden_names(self) -> set[str]:
        """Names bound in this cell's hidden tests only: the note never names them."""
        hidden = hidden_lines(self.cell.source)
        if not hidden:
            return set()
        lines = self.cell.source.split("\n")
        code = "\n".join(line for number, line in enumerate(lines, 1) if number in hidden)
        try:
            return set(defined_names(textwrap.dedent(code))) - set(defined_names(visible_source(self.cell.source)))
        except SyntaxError:
            return set()

    def _task_of_name(self, name: str) -> int | None:
        cell = self.answer_cell.get(name)
        return _task_of(self.nb.cells[cell]) if cell is not None else None

    def _named(self, names) -> str:
        """```a`, `b` (Task 2), `c` (Task 3)``: names with their task, grouped by task."""
        by_task: dict[int | None, list[str]] = {}
        for name in sorted(names):
            task = self._task_of_name(name)
            if task is None and name in self.yours:
                task = _task_of(self.nb.cells[self.yours[name].cell])
            by_task.setdefault(task, []).append(name)
        parts = []
        for task, group in sorted(by_task.items(), key=lambda kv: (kv[0] is None, kv[0] or 0)):
            listed = ", ".join(f"`{n}`" for n in group)
            parts.append(f"{listed} (Task {task})" if task is not None else listed)
        return ", ".join(parts)


_BUILTIN_NAMES = set(dir(__import__("builtins")))


def _called(verdict: dict) -> str:
    """`` (on your `found[0]`, which it calls `q_goal`)`` when the check names the answer otherwise
    than the notebook does (its message uses its own name), else ``""``."""
    try:
        own = _check_names().get(verdict.get("check", ""))
    except Exception:  # noqa: BLE001 - feedback is a bonus
        return ""
    quantity = verdict.get("quantity", "")
    if not own or not quantity or own == quantity or not re.search(rf"(?<![\w.]){re.escape(own)}\b",
                                                                    verdict.get("message", "")):
        return ""
    return f" (on your `{quantity}`, which it calls `{own}`)"


def trace(cells: list[tuple[str, str]]) -> list[dict[str, Binding]]:
    """``notebook_analysis.trace`` with each read-only cell read statement by statement.

    A read-only cell that computes ``H_model = leg.frames(q)`` and, in another statement,
    ``H = R_B1 @ R_12`` gives ``H_model`` no answer of the student's: only the statements that
    read an answer pass it on. Answer cells stay whole (all they bind is the student's). The
    result is ``trace``'s, for the cells as given (a binding's ``cell`` is the index in ``cells``).
    """
    expanded: list[tuple[str, str]] = []
    owner: list[int] = []
    for index, (kind, code) in enumerate(cells):
        parts = _statements(code) if kind == "code" else [code]
        for part in parts or [""]:
            expanded.append((kind, part))
            owner.append(index)
    reads = _cell_trace(expanded)
    out: list[dict[str, Binding]] = [{} for _ in cells]
    for position, found in enumerate(reads):
        index = owner[position]
        for name, binding in found.items():
            cell = owner[binding.cell]
            if cell < index and name not in out[index]:   # a name bound earlier in the cell is its own
                out[index][name] = Binding(cell, binding.answer, binding.roots)
    return out


def _statements(code: str) -> list[str]:
    """The top-level statements of ``code`` (the lines before the failing one), as sources."""
    import ast

    try:
        tree = ast.parse(code)
    except SyntaxError:
        return [code]
    lines = code.splitlines()
    return ["\n".join(lines[s.lineno - 1: s.end_lineno]) for s in tree.body]


def _bindings(kinds: list[tuple[str, str]]):
    """The last binding of every name after ``kinds`` (``notebook_analysis.Binding``)."""
    marker = "_robokin_every_name_"
    names = set()
    for kind, code in kinds:
        if kind in ("answer", "code"):
            names |= set(defined_names(code))
    probe = ", ".join(sorted(names)) or "None"
    return trace(kinds + [("code", f"{marker} = ({probe},)")])[-1]


def _expected_from_notebook(nb, cell_index: int, name: str) -> str:
    """What the notebook says ``name`` is: the docstring of the function, or the sentence of
    the task statement above its answer cell that names it in backticks."""
    import ast

    cell = nb.cells[cell_index]
    try:
        tree = ast.parse(cell.source)
    except SyntaxError:
        tree = None
    for node in tree.body if tree else []:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name == name:
            doc = ast.get_docstring(node) or ""
            returns = re.search(r"Returns\n-+\n(.*?)(\n\s*\n|\Z)", doc, re.S)
            text = returns.group(1) if returns else doc.split("\n\n")[0]
            args = ", ".join(a.arg for a in node.args.args)
            text = " ".join(text.split())
            return f"{name}({args})" + (f" returning {text}" if returns else f": {text}" if text else "")
    mention = re.compile(rf"(?<![\w.]){re.escape(name)}\b")
    for line in cell.source.splitlines():
        if "#" in line and mention.search(line[line.index("#"):]) and "YOUR CODE HERE" not in line:
            comment = " ".join(line[line.index("#") + 1:].split())
            return f"the notebook says: “{comment[:240]}”"
    word = re.compile(rf"`[^`]*(?<![\w.]){re.escape(name)}\b[^`]*`")
    for other in reversed(nb.cells[:cell_index]):
        if other.cell_type != "markdown":
            continue
        text = " ".join(other.source.split())
        for sentence in re.split(r"(?<=[.!?])\s+", text):
            if word.search(sentence):
                return f"the task says: “{sentence[:240]}”"
        if level2_headings(other.source):
            break
    return ""


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
        findings = []
        for (task, _, _), v in zip(pairs, verdicts):
            lost = scores.get(task, [1, 1])[0] < scores.get(task, [1, 1])[1]
            if v["status"] == "wrong" or (v["status"] == "missing" and lost):
                tag = f" *(typical mistake: {v['diagnosis']})*" if v["typical"] else ""
                text = v["message"] if v["status"] == "wrong" else f"✘ {v['message']}"
                called = _called(v)
                findings.append(f"- Task {task}{' ' + _md(called) if called else ''}: {_md(text)}{tag}")
        if findings:
            out += ["", "**What `robokin.check` says about your answers**", "", *findings]
        elif verdicts and all(v["status"] == "correct" for v in verdicts):
            out += ["", f"`robokin.check` finds all {len(verdicts)} answers it can check correct."]

        # an answer this page reports correct is nobody's cause
        right = {v["quantity"] for v in verdicts if v["status"] == "correct"}
        right -= {v["quantity"] for v in verdicts if v["status"] in ("wrong", "missing")}
        causes = {}
        for key, cause in (report.get("causes") or {}).items():
            names = [n for n in cause["names"] if n not in right]
            if names:
                causes[key] = {**cause, "names": names}
        if causes:
            out += ["", "**Where to start**", ""]
            ordered = sorted(causes.items(), key=lambda kv: (kv[1]["task"] is None, kv[1]["task"] or 0))
            for _, cause in ordered[: self.max_notes]:
                task = f" (Task {cause['task']})" if cause["task"] is not None else ""
                tests = list(dict.fromkeys(cause["tests"]))
                several = len(cause["names"]) > 1
                names = ", ".join(f"`{n}`" for n in cause["names"])
                out.append(f"- {names}{task}: {'their' if several else 'its'} {_md(cause['why'])}; "
                           f"the failing test{'s' if len(tests) > 1 else ''} {', '.join(tests)} "
                           f"depend{'' if len(tests) > 1 else 's'} on {'them' if several else 'it'}. "
                           f"Fix {'them' if several else 'it'} first.")
            if len(ordered) > self.max_notes:
                out.append(f"- … and {len(ordered) - self.max_notes} more groups of answers that tests depend on.")

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
                    label = _label(cell, _failing_line(cell, output))
                    notes.append(f"- {label} (not graded) raised `{output.get('ename')}`"
                                 + (f": {evalue}" if evalue else "") + "; the notebook ran on.")
                break
        # timeouts and deleted tests first, then errors
        return sorted(notes, key=lambda n: 0 if ("time limit" in n or "missing" in n) else 1)


class GradingIncidents(NbGraderPreprocessor):
    """What happened to the kernel, appended to the report (autograde, after ``AutograderReport``).

    From ``RobokinExecute``: a kernel that died or was killed (and in which cell), the
    tests that were therefore not run (0 points, with the reason), and the tests whose
    code wrote to stderr (shown as a note, not counted as a failure).
    """

    def preprocess(self, nb, resources):
        incidents = resources.get("robokin", {}).get("incidents", [])
        if not incidents:
            return nb, resources
        lines = []
        for item in incidents:
            if item["kind"] in ("died", "hang"):
                what = ("the kernel died (os._exit, a crash or too much memory)" if item["kind"] == "died" else
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
                lines.append(f"- **The kernel stopped** in {_md(item['label'])} ({scope}): {what}. {after}")
        not_run = [item["label"] for item in incidents if item["kind"] == "not_run"]
        if not_run:
            lines.append("- Not run (0 points), because the kernel had stopped: "
                         + "; ".join(_md(label) for label in not_run) + ".")
        noisy = [item["label"] for item in incidents if item["kind"] == "stderr"]
        if noisy:
            lines.append("- Your code wrote to stderr (a warning or a log message) while these tests ran: "
                         + "; ".join(_md(label) for label in noisy)
                         + ". It is shown under the test and is not counted as a failure.")
        section = "\n".join(["", "**What happened while grading**", "", *lines])
        report = next((c for c in nb.cells if c.cell_type == "markdown"
                       and _robokin(c).get("role") == "report"), None)
        if report is None:
            report = from_dict({"cell_type": "markdown", "metadata": {"robokin": {"role": "report"}},
                                "source": "## Autograder report\n"})
            if nb.cells and "id" in nb.cells[0]:
                report["id"] = "robokin-report"
            nb.cells.insert(0, report)
        report.source = report.source.rstrip() + "\n" + section
        return nb, resources


def _failing_line(cell, error) -> int | None:
    """The line (from 1) of ``cell`` at which its error output ``error`` was raised, if its traceback says."""
    text = ANSI.sub("", "\n".join(error.get("traceback", [])))
    count = cell.get("execution_count")
    found = [int(line) for number, line in re.findall(r"Cell In\[(\d+)\], line (\d+)", text)
             if str(number) == str(count)]
    return found[-1] if found and 0 < found[-1] <= len(cell.source.splitlines()) else None


def _label(cell, line: int | None = None) -> str:
    """``In [5] `first line` (your answer to Task 2)``; with ``line``, that line is quoted (where the
    cell raised) instead of the first -- never a line of its hidden tests."""
    count = cell.get("execution_count")
    where = f"In [{count}]" if count else "a cell"
    role = _robokin(cell).get("role")
    task = _task_of(cell)
    kind = {"answer": f"your answer to Task {task}", "test": f"a test of Task {task}"}.get(role)
    if line is not None and line not in hidden_lines(cell.source):
        statement = " ".join(part.split("#")[0].strip() for part in statement_at(cell.source, line).splitlines())
        statement = re.sub(r"([(\[{]) ", r"\1", re.sub(r" ([)\]}])", r"\1", " ".join(statement.split())))
        first = statement if len(statement) <= 60 else statement[:59] + "…"
        where += f", line {line},"
    else:
        first = _first_line(visible_source(cell.source))
    text = f"{where} `{first}`" if first else where
    return f"{text} ({kind})" if kind else text


def _num(x: float) -> str:
    return f"{x:g}"


def _md(text: str) -> str:
    """One line of plain text made safe inside a markdown list item."""
    return " ".join(text.split()).replace("|", "\\|").replace("<", "&lt;")


# ---------------------------------------------------------------- generate_feedback
#: A traceback's frame in a cell: "Cell In[12], line 5" (ANSI colours removed).
CELL_FRAME = re.compile(r"Cell In\[(\d+)\], line (\d+)")
#: A line of code quoted in a traceback's frame: "----> 5 code" or "      6 code".
QUOTED_LINE = re.compile(r"\s*(?:-*>)?\s*\d+ ?(.*)$")
FAILED_AT = re.compile(r"^(✘ Task .*? failed at line )(\d+)(:)", re.M)


class HideHiddenTests(ClearHiddenTests):
    """generate_feedback: a test cell's hidden tests are not in the feedback page.

    The graded notebook holds every test cell as the instructor wrote it (autograde restores the
    hidden tests the student edition lacks), and the feedback page is made from it; a student who
    reads the page before handing in again (``collect --update``) would read them. nbgrader's
    ``ClearHiddenTests`` (the preprocessor of ``generate_assignment``, with its delimiters) takes
    them out of the cell, and a comment says where they were; what the cell printed stays (the
    verdict), and its error output keeps the error and its message (the diagnosis) while the
    traceback's frames in the hidden lines lose their code. Line numbers (the traceback's, the
    robokin note's "failed at line N") are those of the cell as the student sees it.
    """

    enforce_metadata = Bool(False, help="complain about hidden tests outside a test cell").tag(config=True)
    marker = Unicode("# … hidden tests, run when grading (their code is not shown) …",
                     help="the comment in place of each block of hidden tests").tag(config=True)

    def preprocess_cell(self, cell, resources, index):
        if cell.cell_type != "code" or self.begin_test_delimeter not in cell.source:
            return cell, resources
        original = cell.source
        hidden = hidden_lines(original, self.begin_test_delimeter, self.end_test_delimeter)
        cell, resources = super().preprocess_cell(cell, resources, index)   # nbgrader's own checks
        lines, renumber = [], {}
        for number, line in enumerate(original.split("\n"), 1):
            if number not in hidden:
                lines.append(line)
                renumber[number] = len(lines)
            elif number - 1 not in hidden:
                lines.append(self.marker)
        assert [line for line in lines if line != self.marker] == cell.source.split("\n"), "ClearHiddenTests changed"
        cell.source = "\n".join(lines)
        # the hidden lines a traceback could quote (not those that are also visible, nor a lone ")")
        hidden_text = {line.strip() for number, line in enumerate(original.split("\n"), 1)
                       if number in hidden and len(line.strip()) >= 4} - {line.strip() for line in lines}
        for output in cell.get("outputs", []):
            if output.get("output_type") == "stream" and "failed at line" in output.get("text", ""):
                output["text"] = FAILED_AT.sub(lambda m: m.group(1) + str(renumber.get(int(m.group(2)), "?"))
                                               + m.group(3), output["text"])
            elif output.get("output_type") == "error":
                output["traceback"] = [self._frame(entry, cell.get("execution_count"), lines, renumber, hidden_text)
                                       for entry in output.get("traceback", [])]
        return cell, resources

    @staticmethod
    def _frame(entry: str, count, lines: list[str], renumber: dict[int, int], hidden_text: set[str]) -> str:
        """A traceback entry without the cell's hidden lines: a frame in this cell shows its line only
        if it is visible; any other entry that quotes a hidden line is replaced by a sentence."""
        plain = ANSI.sub("", entry)
        frame = CELL_FRAME.match(plain)
        quoted = {m.group(1).strip() for m in map(QUOTED_LINE.match, plain.splitlines()[1:]) if m}
        if frame and (str(frame.group(1)) == str(count) or quoted & hidden_text):
            line = renumber.get(int(frame.group(2)))
            if line is None:
                return f"Cell In[{frame.group(1)}], in the hidden tests (their code is not shown)"
            return f"Cell In[{frame.group(1)}], line {line}\n----> {line} {lines[line - 1]}"
        if quoted & hidden_text or any(text in plain for text in hidden_text if len(text) >= 12):
            return "(a frame in the hidden tests: its code is not shown)"
        return entry


class FeedbackStyle(NbGraderPreprocessor):
    """generate_feedback: the page's own stylesheet, after nbconvert's (``CSSHTMLHeaderPreprocessor``,
    whose ``resources["inlining"]["css"]`` the feedback template inlines).

    The notes under a failing test and the tracebacks wrap at the page's width instead of
    scrolling sideways (at 1280 px a note's long lines were cut off), and the report's tables have
    a gap between their columns.
    """

    css = Unicode("""
div.output_area pre, div.output_subarea pre, div.output_text pre, .jp-OutputArea-output pre {
  white-space: pre-wrap; overflow-wrap: anywhere; }
div.output_subarea, div.output_area { overflow-x: visible; max-width: 100%; }
div.text_cell_render table th, div.text_cell_render table td, .rendered_html table th,
.rendered_html table td { padding: 0.25em 0.9em; }
""", help="CSS added to the feedback page").tag(config=True)

    def preprocess(self, nb, resources):
        inlining = resources.setdefault("inlining", {})
        inlining["css"] = [*inlining.get("css", []), self.css]
        return nb, resources


# ---------------------------------------------------------------- MyST, as Markdown
#: The opening fence of a MyST directive: ```{name} argument, or :::{name} argument.
DIRECTIVE_OPEN = re.compile(r"^(?P<indent>\s*)(?P<fence>`{3,}|:{3,})\{(?P<name>[\w:-]+)\}\s*(?P<argument>.*?)\s*$")
#: The opening fence of a plain code block: ``` or ~~~ (with a language, not a directive).
CODE_OPEN = re.compile(r"^\s*(?P<fence>`{3,}|~{3,})(?!\{)")
#: A MyST role: {cite}`key1,key2`, {doc}`text <target>`.
ROLE = re.compile(r"(?<![\w\\])\{(?P<name>[a-z][\w:-]*)\}(?P<ticks>`+)(?P<body>.+?)(?P=ticks)", re.S)
ADMONITIONS = {"note", "tip", "hint", "important", "warning", "caution", "attention", "danger", "error",
               "seealso"}


@functools.cache
def _bibliography(path: str) -> dict[str, tuple[str, str]]:
    """``{key: (authors, year)}`` of the BibTeX file at ``path`` ("Lynch and Park", "2017")."""
    try:
        from pybtex.database import parse_file

        data = parse_file(path)
    except Exception:  # noqa: BLE001 - without the bibliography a citation shows its key
        return {}
    out = {}
    for key, entry in data.entries.items():
        people = entry.persons.get("author") or entry.persons.get("editor") or []
        names = [" ".join(person.last_names).replace("{", "").replace("}", "") for person in people]
        authors = (names[0] if len(names) == 1 else " and ".join(names) if len(names) == 2
                   else f"{names[0]} et al." if names else key)
        out[key] = (authors, entry.fields.get("year", "n.d."))
    return out


class MystMarkdown(NbGraderPreprocessor):
    """generate_feedback: MyST markup in the text cells becomes plain Markdown, which the page renders.

    The task statements are written for the book (MyST: ``{exercise}``, ``{admonition}``,
    ``{cite}``, ``{doc}``); nbconvert's Markdown shows that markup raw. Here a directive becomes
    what it means in Markdown (an exercise a bold "Exercise c.k" with its text, an admonition a
    quotation under its bold title, the fences of ``{exercise-start}``/``{exercise-end}`` and
    the options go), a citation becomes "(Author, year)" from ``book/references.bib``, and a
    cross-reference its text (a link to a page of the book would not resolve where the page is
    read). Code blocks are left as they are.
    """

    bibliography = Unicode(str(Path(__file__).resolve().parent.parent / "book" / "references.bib"),
                           help="the BibTeX file the {cite} roles name").tag(config=True)

    def preprocess(self, nb, resources):
        name = str(resources.get("nbgrader", {}).get("notebook", "") or "")
        head = name.split("_", 1)[0]
        self._chapter = f"{int(head)}." if head.isdigit() else ""
        self._exercises = 0
        return super().preprocess(nb, resources)

    def preprocess_cell(self, cell, resources, index):
        if cell.cell_type == "markdown" and "{" in cell.source:
            cell.source = self.convert(cell.source)
        return cell, resources

    def convert(self, text: str) -> str:
        """``text`` with its MyST directives and roles as Markdown."""
        if not hasattr(self, "_exercises"):
            self._chapter, self._exercises = "", 0
        return "\n".join(self._blocks(text.split("\n")))

    def _blocks(self, lines: list[str]) -> list[str]:
        out: list[str] = []
        k = 0
        while k < len(lines):
            line = lines[k]
            code = CODE_OPEN.match(line)
            directive = DIRECTIVE_OPEN.match(line)
            if code and not directive:
                end = self._closing(lines, k + 1, code.group("fence"))
                out += lines[k: end + 1]
                k = end + 1
                continue
            if not directive:
                out.append(self._roles(line))
                k += 1
                continue
            end = self._closing(lines, k + 1, directive.group("fence"))
            body = lines[k + 1: end]
            options = {}
            while body and re.match(r"^\s*:[\w-]+:", body[0]):
                option = body.pop(0).strip()[1:]
                options[option.split(":", 1)[0]] = option.split(":", 1)[1].strip()
            out += self._directive(directive.group("name"), self._roles(directive.group("argument")),
                                   options, self._blocks(body), directive.group("indent"))
            k = end + 1
        return out

    @staticmethod
    def _closing(lines: list[str], start: int, fence: str) -> int:
        """The index of the line that closes ``fence`` (the last line if none does)."""
        depth = 0
        for k in range(start, len(lines)):
            stripped = lines[k].strip()
            if DIRECTIVE_OPEN.match(lines[k]) and DIRECTIVE_OPEN.match(lines[k]).group("fence") == fence:
                depth += 1
            elif stripped and set(stripped) == {fence[0]} and len(stripped) >= len(fence):
                if depth == 0:
                    return k
                depth -= 1
        return len(lines)

    def _directive(self, name: str, argument: str, options: dict, body: list[str], indent: str) -> list[str]:
        kind = name.split(":")[-1]
        if kind in ("exercise", "exercise-start"):
            self._exercises += 1
            title = f"**Exercise {self._chapter}{self._exercises}**" + (f" ({argument})" if argument else "")
            return [indent + title, "", *body] if body else [indent + title, ""]
        if kind in ("exercise-end", "solution-start", "solution-end", "margin", "only"):
            return body
        if kind == "admonition" or kind in ADMONITIONS:
            title = argument if kind == "admonition" else (kind.capitalize() + (f": {argument}" if argument else ""))
            quoted = [f"{indent}> **{title}**" if title else f"{indent}>", f"{indent}>"]
            quoted += [f"{indent}> {line[len(indent):] if line.startswith(indent) else line}".rstrip() for line in body]
            return [*quoted, ""]
        if kind == "math":
            return [indent + "$$", *body, indent + "$$"]
        if kind in ("figure", "image"):
            return [f"{indent}![{' '.join(body).strip()}]({argument})"]
        if kind in ("code-block", "code", "code-cell"):
            return [indent + "```" + argument, *body, indent + "```"]
        head = [f"{indent}**{argument}**", ""] if argument else []
        return [*head, *body]

    def _roles(self, line: str) -> str:
        return ROLE.sub(self._role, line) if "{" in line else line

    def _role(self, match) -> str:
        name, body = match.group("name"), match.group("body").strip()
        if name.startswith("cite"):
            references = _bibliography(self.bibliography)
            cited = [references.get(key.strip(), (key.strip(), "")) for key in body.split(",") if key.strip()]
            if name in ("cite:t", "cite:ts"):
                return "; ".join(f"{authors} ({year})" if year else authors for authors, year in cited)
            return "(" + "; ".join(f"{authors}, {year}" if year else authors for authors, year in cited) + ")"
        if name == "math":
            return f"${body}$"
        if name == "eq":
            return f"({body})"
        explicit = re.match(r"^(?P<text>.*?)\s*<(?P<target>[^<>]+)>$", body, re.S)
        if explicit and explicit.group("text"):
            return explicit.group("text")
        if name in ("doc", "ref", "numref", "term", "download", "any"):
            return body.rsplit("/", 1)[-1].replace("-", " ").replace("_", " ")
        return body


MATHJAX_CONFIG = """window.MathJax = {
  tex: {inlineMath: [["$", "$"], ["\\\\(", "\\\\)"]], displayMath: [["$$", "$$"], ["\\\\[", "\\\\]"]],
        processEscapes: true, processEnvironments: true, tags: "ams"},
  svg: {fontCache: "global"},
  options: {enableMenu: false}
};"""
#: The CDN script tag of nbconvert's/nbgrader's MathJax 2 macro and its configuration.
CDN_MATHJAX = re.compile(r'<script[^>]*\bsrc="https?://[^"]*mathjax[^"]*"[^>]*>\s*</script>', re.I)
MATHJAX2_CONFIG = re.compile(r'<script type="text/x-mathjax-config">.*?</script>', re.S)


@functools.cache
def mathjax_script() -> str:
    """MathJax 3 (TeX input, SVG output: no font files) from the ``django-static-mathjax`` wheel."""
    try:
        import mathjax  # the wheel the book serves MathJax from (book/_ext/robokin_book.py)
    except ImportError as exc:  # pragma: no cover - install problem
        raise RuntimeError("MathJax is missing: `pip install -r requirements.txt` installs "
                           "django-static-mathjax, the offline MathJax of the book and the feedback") from exc
    path = Path(mathjax.__file__).resolve().parent / "static" / "mathjax" / "es5" / "tex-svg-full.js"
    return path.read_text(encoding="utf-8").replace("</script", "<\\/script")


class MemoisedHighlight(Highlight2HTML):
    """nbconvert's code highlighting (pygments), memoised per process: ``generate_feedback`` renders
    the same given and test cells for every student, and highlighting is a sixth of its time."""

    _pages: dict[tuple, str] = {}

    def __call__(self, source, language=None, metadata=None):
        key = (source, language or self.pygments_lexer, (metadata or {}).get("magics_language"),
               json.dumps(self.extra_formatter_options, sort_keys=True, default=repr))
        if key not in self._pages:
            self._pages[key] = super().__call__(source, language, metadata)
        return self._pages[key]


class OfflineMathJaxHTMLExporter(HTMLExporter):
    """HTML with MathJax inlined: formulas render in a feedback page opened without internet."""

    _markdown: dict[tuple, str] = {}

    @pass_context
    def markdown2html(self, context, source):
        """nbconvert's markdown filter, memoised per process: the text cells are the same on every
        student's page (the key is all the filter reads: the text, the cell's attachments, the
        notebook's folder and the exporter's options)."""
        key = (source, json.dumps(context.get("cell", {}).get("attachments", {}), sort_keys=True),
               context.get("resources", {}).get("metadata", {}).get("path", ""), self.embed_images,
               self.anchor_link_text, self.exclude_anchor_links,
               json.dumps(self.lexer_options, sort_keys=True, default=repr))
        if key not in self._markdown:
            self._markdown[key] = super().markdown2html(context, source)
        return self._markdown[key]

    def from_notebook_node(self, nb, resources=None, **kw):
        """nbconvert's page (its own ``from_notebook_node``) with MathJax inlined; its code
        highlighting memoised (:class:`MemoisedHighlight`): ``HTMLExporter`` highlights with the
        ``highlight_code`` filter configured in ``filters`` when there is one."""
        langinfo = nb.metadata.get("language_info", {})
        lexer = langinfo.get("pygments_lexer", langinfo.get("name", None)) or "ipython3"
        current = self.filters.get("highlight_code")
        if current is None or (isinstance(current, MemoisedHighlight) and current.pygments_lexer != lexer):
            # a new filters dict rebuilds the exporter's template environment: once per lexer
            self.filters = {**self.filters, "highlight_code": MemoisedHighlight(pygments_lexer=lexer, parent=self)}
        output, resources = super().from_notebook_node(nb, resources, **kw)
        return inline_mathjax(output), resources


def inline_mathjax(html: str) -> str:
    """``html`` with the CDN MathJax (and its MathJax 2 configuration) replaced by MathJax 3 inline."""
    inline = (f"<script>{MATHJAX_CONFIG}</script>\n"
              f"<script id=\"robokin-mathjax\">{mathjax_script()}</script>")
    html = MATHJAX2_CONFIG.sub("", html)
    html, count = CDN_MATHJAX.subn(lambda _: inline, html, count=1)
    html = CDN_MATHJAX.sub("", html)
    if not count:  # a template without the macro: put it at the end of the head
        html = html.replace("</head>", inline + "\n</head>", 1)
    return html
