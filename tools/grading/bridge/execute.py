"""``BridgedExecute``: autograde's executor -- the student's kernel in a sandbox, the verdicts in a grader kernel.

nbgrader's ``Execute`` (replaced by it in ``nbgrader_config.py``), with two kernels per submission:

the **student's kernel** runs the submission, in a bubblewrap sandbox (``tools/grading/sandbox.py``);
    a test scores by pass/fail only (its stderr is a note, a result it shows no partial credit); a
    kernel that dies or ignores the interrupt is killed, restarted and brought back to where it was
    (the cells before are run again), so it costs only that cell (after the last test, grading just
    stops there: nothing graded is left to run). It stops after the last cell that is graded or holds
    an answer (nbgrader's ``grade`` or ``solution``): the cells after it (*Going further*, pictures)
    are graded by nobody, so they are not run; the graded notebook shows them without outputs, and
    ``NotRunNote`` (``tools/grading/robokin_nbgrader/not_run_note.py``) says why above the first.
a **grader kernel** beside it (:mod:`grader_kernel`), for every chapter, runs each read-only cell (given
    or test) of the assignment -- its text from nbgrader's gradebook, never from the submission -- in
    order; before it runs, the answers it reads (names declared by answer cells,
    ``metadata.robokin.declare`` of the instructor's source notebook) are imported from the student's
    kernel through the bridge (:mod:`tools.grading.bridge.grader_side`): data copied, functions as
    proxies. A test cell's outputs in the graded notebook are the grader kernel's (the student's own run
    of it is discarded), so ``SaveAutoGrades`` scores what the grader saw. When a test fails,
    ``FailureNotes`` (``tools/grading/robokin_nbgrader/failure_notes.py``) writes the note above the
    traceback; after the last test ``robokin.check`` is asked about every answer it has a check for
    (``checks.registered_pairs``). Those verdicts are computed in the grader kernel too: a verdict never
    comes from the student's kernel. Answer cells that delegate to robokin's own solution are listed for
    review by hand (:mod:`delegation`). Each grader kernel is a new process, forked from a warm process
    that imported ipykernel and ``PRELOAD`` once per autograde run (:mod:`fork_server`;
    ``c.BridgedExecute.fork_server = False``: started anew, as a kernel spec's command, each time).

``BridgeReport`` (after ``AutograderReport``; :mod:`bridge_report`) adds to the report on top of the
graded notebook the answers for review by hand and the answers that could not be handed over as data.

Nothing a submission does in its own kernel (input or AST transformers, IPython
hooks, a patched numpy or robokin.check, forged outputs) reaches the grader
kernel, except what its answers compute when the tests call them.
"""

from __future__ import annotations

import builtins
import json
import os
import re
import secrets
from pathlib import Path
from typing import Any, cast

import nbformat
from jupyter_client.asynchronous import AsyncKernelClient
from jupyter_client.manager import AsyncKernelManager
from jupyter_core.utils import run_sync
from nbclient.exceptions import CellTimeoutError, DeadKernelError
from nbformat.notebooknode import from_dict
from nbgrader import utils
from nbgrader.coursedir import CourseDirectory
from nbgrader.preprocessors import Execute
from traitlets import Bool, Float, Unicode
from traitlets.config.loader import DeferredConfig

from tools.grading.bridge import delegation, fork_server
from tools.grading.bridge.grader_kernel import PRELOAD, GraderKernel
from tools.grading.bridge.grader_side import NOT_CALLED
from tools.grading.bridge.pictures import skip_pictures
from tools.grading.robokin_nbgrader.cells import cell_label, robokin_metadata, task_of
from tools.grading.robokin_nbgrader.checks import VERDICT_MARK, registered_pairs
from tools.grading.robokin_nbgrader.failure_notes import FailureNotes
from tools.grading.robokin_nbgrader.grading_incidents import KERNEL_LOST, NOT_RUN
from tools.grading.robokin_nbgrader.streams import JoinedStreamsClient
from tools.grading.sandbox import KernelAtProcessCap, SandboxedKernelManager, bwrap_executable, sandbox_wanted
from tools.notebook_analysis import defined_names, free_names

#: The repository (hidden from the sandboxed kernel: its notebooks hold the solutions).
REPOSITORY = Path(__file__).resolve().parents[3]
STDERR_NOTE = "[written to stderr; not counted as a failure]"
IMPORT_MARK = "ROBOKIN-BRIDGE-IMPORT "


def _grade_id(cell) -> str | None:
    return cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")


def last_graded_cell(cells) -> tuple[int, int | None]:
    """Where the student's kernel stops: the index of the last cell that is graded or holds an answer.

    Parameters
    ----------
    cells : list
        The submission's cells (after autograde's sanitizing steps, which restore the
        instructor's nbgrader metadata and put deleted test cells back).

    Returns
    -------
    last : int
        The last cell with nbgrader's ``grade`` or ``solution`` (a manually graded answer
        counts); the last cell when there is none.
    first_not_run : int or None
        The index of the cell after ``last`` when a code cell with code follows it (those
        cells are not run: nothing there is graded), else None.
    """
    last = max((i for i, c in enumerate(cells) if utils.is_grade(c) or utils.is_solution(c)),
               default=len(cells) - 1)
    later = any(c.cell_type == "code" and c.source.strip() for c in cells[last + 1:])
    return last, last + 1 if later else None


#: Settings of ``BridgedExecute`` that are gone, and why an old ``nbgrader_config.py`` may drop them.
RETIRED_SETTINGS = {
    "chapters": "every chapter is graded through the bridge (the verdicts are decided in a grader kernel); "
                "grading in the student's kernel only is no longer offered",
}
#: The executor's former names, whose settings an old ``nbgrader_config.py`` may still hold
#: (``c.RobokinExecute.sandbox``): they still apply, with a warning naming the new setting.
FORMER_NAMES = ("RobokinExecute",)
#: Where an instructor reads about the executor's settings.
SETTINGS_DOC = "book/for-instructors.md, \"Where the verdicts are decided\""


class BridgedExecute(JoinedStreamsClient, Execute):
    """nbgrader's ``Execute`` with the student's kernel in a sandbox and the tests and verdicts in a grader kernel.

    - The student's kernel runs in bubblewrap (``tools/grading/sandbox.py``) unless
      ``sandbox`` is False or ``ROBOKIN_GRADING_SANDBOX=off``; without ``bwrap`` grading
      stops with a message naming the package to install.
    - Each read-only cell of the assignment and robokin.check's verdicts run in a grader
      kernel, on the answers imported from the student's kernel; a test cell's outputs
      are the grader kernel's.
    - A test cell fails only by an error output: what it writes to stderr (a warning,
      a log message) stays in its output marked as a note, and a result or display it
      shows is kept as a display (nbgrader would read a number as partial credit).
    - A kernel that dies, or ignores the interrupt after the time limit (it is then
      killed), is restarted and the cells before are run again: only that cell is lost.
      If that fails, the cells after it are not run and their tests score 0 with the
      reason. After the last test (nothing graded follows) it is not restarted: the
      cells after it are not run, and no score changes. The report names the
      incident (``resources['robokin']['incidents']``, written by ``GradingIncidents``).
    - The cells after the last one that is graded or holds an answer are not run at all
      (nothing there is graded): their outputs are cleared, and
      ``resources['robokin']['not_run_from']`` is the index of the first of them (None when
      no code follows), where ``NotRunNote`` puts its note.
    """

    viewer = Unicode("matplotlib", help="ROBOKIN_VIEWER of the grading kernel (how 3D scenes are shown)"
                     ).tag(config=True)
    sandbox = Bool(True, help="run each submission's kernel in bubblewrap (bwrap); "
                   "ROBOKIN_GRADING_SANDBOX=off|on overrides it").tag(config=True)
    call_timeout = Float(30.0, help="Seconds for one call of a student's function from a test").tag(config=True)
    fork_server = Bool(True, help="fork each grader kernel from a warm process that imported ipykernel and "
                       "PRELOAD once per autograde run (tools.grading.bridge.fork_server); False: start each as a new "
                       "process").tag(config=True)

    # the notebook being graded, set by preprocess: the student's kernel
    _sandboxed: bool
    _stopped: dict[str, Any] | None   # the incident that stopped grading (the kernel was lost)
    _replays: int
    _timed_out: set[int]
    _report: dict[str, Any]           # resources["robokin"]
    _last_code: int
    _last_graded: int                 # the last cell that is graded or holds an answer: the kernel stops there
    # the notebook being graded, set by preprocess: the bridge's plan and the grader kernel (None
    # between notebooks; the kernel also before it starts)
    _plan: dict | None
    _grader: GraderKernel | None
    _settled_at: int

    def __init__(self, **kw: Any) -> None:
        """Keywords only, as every traitlets configurable: ``config``, ``parent``, and the traits
        (``sandbox=False``). nbgrader's ``Execute`` carries no types; without this signature a type
        checker takes nbclient's ``NotebookClient(nb, ...)`` for it, which nbconvert's
        ``ExecutePreprocessor.__init__(**kw)`` overrides at run time.

        Settings of an older ``nbgrader_config.py`` are not ignored silently: one under a former
        name of this class (:data:`FORMER_NAMES`) still applies, unless the new name sets it too,
        and a warning names the new setting; a retired one (:data:`RETIRED_SETTINGS`) is ignored
        with a warning saying why.
        """
        super().__init__(**kw)
        own = self.config["BridgedExecute"] if "BridgedExecute" in self.config else {}
        for name, why in RETIRED_SETTINGS.items():
            if name in own:
                self._retired(f"c.BridgedExecute.{name}", why)
        traits = self.traits(config=True)
        for former in FORMER_NAMES:
            section = self.config[former] if former in self.config else {}
            for name, value in section.items():
                if name in RETIRED_SETTINGS:
                    self._retired(f"c.{former}.{name}", RETIRED_SETTINGS[name])
                elif name not in traits:
                    self.log.warning("c.%s.%s is no setting of the executor and is ignored. Remove it from "
                                     "nbgrader_config.py (%s).", former, name, SETTINGS_DOC)
                elif name in own:
                    self.log.warning("c.%s.%s is ignored: c.BridgedExecute.%s, also set, is the one that "
                                     "applies. Remove the former from nbgrader_config.py (%s).",
                                     former, name, name, SETTINGS_DOC)
                else:
                    trait = traits[name]
                    setattr(self, name, value.get_value(trait) if isinstance(value, DeferredConfig) else value)
                    self.log.warning("c.%s.%s is now c.BridgedExecute.%s (the executor's one name); it still "
                                     "applies. Rename it in nbgrader_config.py (%s).", former, name, name,
                                     SETTINGS_DOC)

    def _retired(self, setting: str, why: str) -> None:
        self.log.warning("%s is no longer needed and is ignored: %s. Remove it from nbgrader_config.py (%s).",
                         setting, why, SETTINGS_DOC)

    def _async_manager(self) -> AsyncKernelManager:
        """The kernel manager of the notebook being graded. nbclient types it as a ``KernelManager``;
        it is an async one (nbclient's default class, the sandbox's), whose methods are coroutines."""
        return cast(AsyncKernelManager, self.km)

    def create_kernel_manager(self):
        if not self._sandboxed:
            return super().create_kernel_manager()
        if not self.kernel_name:
            self.kernel_name = self.nb.metadata.get("kernelspec", {}).get("name") or "python3"
        folder = self.resources.get("metadata", {}).get("path") or os.getcwd()
        course = Path(CourseDirectory(config=self.config).root).resolve()
        exchange = self.config.get("Exchange", {}).get("root", "/srv/nbgrader/exchange")
        hidden = [str(course), str(Path(exchange).resolve()), str(REPOSITORY)]
        self.km = SandboxedKernelManager(kernel_name=self.kernel_name, config=self.config,
                                         writable=str(Path(folder).resolve()), hidden=hidden)
        return self.km

    def _grade_by_pass_fail(self, cell) -> None:
        """A test cell's outputs such that only an error output can lower its score.

        Its stderr (warnings, log messages) becomes one stdout note, where the first stderr
        output was; a result it shows (``execute_result``) becomes a display.
        """
        outputs: list = []
        stderr: list[str] = []
        position: int | None = None   # where the first stderr output was
        for output in cell.get("outputs", []):
            if output.get("output_type") == "stream" and output.get("name") == "stderr":
                position = len(outputs) if position is None else position
                stderr.append(output.get("text", ""))
                continue
            if output.get("output_type") == "execute_result":
                output["output_type"] = "display_data"
                output.pop("execution_count", None)
            outputs.append(output)
        if position is not None:   # some stderr
            outputs.insert(position, from_dict({"output_type": "stream", "name": "stdout",
                                                "text": f"{STDERR_NOTE}\n{''.join(stderr)}"}))
            self._report["incidents"].append({"kind": "stderr", "label": cell_label(cell)})
        cell.outputs = outputs

    def _kernel_lost(self, cell, index, exc) -> None:
        """The kernel died in ``cell``, ignored the interrupt at the time limit, or was left at its
        cap on processes (``KernelAtProcessCap``: it could not start a thread any more).

        The kernel is killed and restarted, and the code cells before this one are run
        again (their outputs are kept from the first run), so that the notebook goes on
        and loses only this cell. If that fails too, grading stops here: the cells after
        it are not run (``_not_run``). When nothing graded comes after the cell (no test,
        and robokin.check's verdicts are taken), grading stops there at once: restarting
        the kernel and running the notebook again would change no score.
        """
        hung = isinstance(exc, CellTimeoutError)
        capped = isinstance(exc, KernelAtProcessCap)
        if hung:
            self.log.error("The kernel ignored the interrupt after %s s: killing it", self.timeout)
        if capped:
            self.log.error("Cell %d: %s; killing the kernel", index, exc)
        cell = self.nb.cells[index]
        why = (f"the cell ran longer than the time limit ({self.timeout} s) and ignored the interrupt: "
               "the kernel was killed" if hung else f"{exc}: the kernel was killed" if capped else
               "the kernel died while running this cell (os._exit, a crash, or not enough memory)")
        if utils.is_grade(cell):   # the test scores 0
            output = {"output_type": "error", "ename": KERNEL_LOST, "evalue": why,
                      "traceback": [f"{KERNEL_LOST}: {why}"]}
        else:                      # not an error of the notebook that ran on: said in the report
            output = {"output_type": "stream", "name": "stderr", "text": f"{KERNEL_LOST}: {why}\n"}
        cell.setdefault("outputs", []).append(from_dict(output))
        later = [c for c in self.nb.cells[index + 1:] if c.cell_type == "code" and utils.is_grade(c)]
        incident = {"kind": "hang" if hung else "died", "label": cell_label(cell), "graded": utils.is_grade(cell),
                    "tests_lost": len(later), "replayed": False,
                    # nothing graded after it (no test, robokin.check's verdicts taken): no restart
                    "nothing_after": not later and index > self._last_code}
        if capped:   # what the report says instead of "the kernel died"
            incident["what"] = f"{exc}; the kernel was killed"
        self._report["incidents"].append(incident)
        if not incident["nothing_after"] and not self._replays and self._restart_and_replay(index):
            incident["replayed"], incident["tests_lost"] = True, 0
            self._replays += 1
            return
        try:
            run_sync(self._async_manager().shutdown_kernel)(now=True)
        except Exception as kill_error:  # noqa: BLE001 - it is already gone
            self.log.warning("Stopping the kernel: %s", kill_error)
        self._stopped = incident

    def _restart_and_replay(self, index) -> bool:
        """A fresh kernel in the state before cell ``index``: True if that worked."""
        self.log.warning("Restarting the kernel and running the %d cells before cell %d again", index, index)
        try:
            run_sync(self._async_manager().restart_kernel)(now=True)
            run_sync(cast(AsyncKernelClient, self.kc).wait_for_ready)(timeout=self.startup_timeout)  # its client: async
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
        """``cell`` emptied, after grading stopped (``_stopped``); a test scores 0 and says why."""
        if cell.cell_type != "code":
            return cell
        cell.outputs = []
        cell.execution_count = None
        if utils.is_grade(cell):
            where = self._stopped["label"] if self._stopped is not None else "an earlier cell"
            why = f"not run: the kernel had stopped in {where}"
            cell.outputs.append(from_dict({"output_type": "error", "ename": NOT_RUN, "evalue": why,
                                           "traceback": [f"{NOT_RUN}: {why}"]}))
            self._report["incidents"].append({"kind": "not_run", "label": cell_label(cell)})
        return cell

    async def _async_handle_timeout(self, timeout, cell=None):
        # nbgrader interrupts a cell that runs too long; the kernel then reports a
        # KeyboardInterrupt. Remember the cell, so that its error is named for what it is.
        if cell is not None:
            self._timed_out.add(id(cell))
        return await super()._async_handle_timeout(timeout, cell)

    def _bridge(self) -> tuple[dict, GraderKernel]:
        """The plan and the grader kernel, while a notebook is graded through the bridge."""
        if self._plan is None or self._grader is None:
            raise RuntimeError("BridgedExecute: no grader kernel (no notebook is being graded, "
                               "or its grader kernel has not started)")
        return self._plan, self._grader

    # ------------------------------------------------------------ set-up
    def preprocess(self, nb, resources=None, km=None):
        self._grader = None
        self._plan = None
        self._settled_at = -1   # the grader kernel's run count when it last said "not stuck"
        # marks of the grader's own output lines, unknown to the student's code (whose output
        # during a call is shown in the grader kernel, under the test that called it)
        nonce = secrets.token_hex(8)
        self._import_mark = f"{IMPORT_MARK.rstrip()}-{nonce} "
        self._verdict_mark = f"{VERDICT_MARK}-{nonce}"
        resources = resources if resources is not None else {}
        notebook = resources.get("nbgrader", {}).get("notebook")
        plan = self._plan = self._make_plan(nb, resources)
        calls = None
        try:
            nb, resources = self._run_student_kernel(nb, resources, km)
            if self._grader is not None:
                try:
                    status, _ = self._grader.marked(f"print({self._import_mark!r} + __import__('json').dumps("
                                                    "_robokin_bridge.status()))", self._import_mark)
                    calls = (status or {}).get("calls")
                except Exception as exc:  # noqa: BLE001 - a count for the log only
                    self.log.warning("bridge: no call count (%s)", exc)
        finally:
            if self._grader is not None:
                self._grader.stop()
        kinds: dict[str, int] = {}
        for status in plan["imports"].values():
            kinds[status.split(":")[0]] = kinds.get(status.split(":")[0], 0) + 1
        self.log.info("bridge: %s graded in a grader kernel (%d of %d instructor cells run; answers: %s; "
                      "%s calls of the student's functions)",
                      notebook, sum(1 for c in plan["cells"][: plan["done"]] if not c.get("skip")),
                      len(plan["cells"]), kinds, calls)
        reviewed = {item["name"] for item in plan["review"]}
        for name, status in plan["imports"].items():   # an answer that IS a robokin function
            if status.startswith("function of ") and name not in reviewed:
                plan["review"].append({"task": plan["tasks"].get(name), "name": name,
                                       "reference": status[len("function of "):], "how": "runtime",
                                       "through": None})
        report = resources.setdefault("robokin", {})
        report["review"] = [dict(item, line=delegation.describe(item)) for item in plan["review"]]
        report["bridge"] = {"imports": plan["imports"], "problems": plan["problems"],
                            "side_effects": plan["side_effects"]}
        return nb, resources

    def _make_plan(self, nb, resources) -> dict:
        """Instructor cells (from the gradebook), declared names and roles (from the source notebook)."""
        from nbgrader.api import Gradebook

        info = resources.get("nbgrader", {})
        with Gradebook(info["db_url"]) as gb:
            source_nb = gb.find_notebook(info["notebook"], info["assignment"])
            grades = {c.name for c in source_nb.grade_cells}
            solutions = {c.name for c in source_nb.solution_cells}
            cells = [{"grade_id": c.name, "source": c.source, "test": c.name in grades}
                     for c in source_nb.source_cells
                     if c.cell_type == "code" and c.locked and c.name not in solutions]
        source = self._source_metadata(info)
        if source is None:
            source = {_grade_id(c): (robokin_metadata(c), c.metadata.get("tags", [])) for c in nb.cells if _grade_id(c)}
        meta = {key: value[0] for key, value in source.items()}
        skip_pictures(cells, {key: value[1] for key, value in source.items()})
        # the instructor's robokin metadata replaces the submission's (a student can edit metadata)
        for cell in nb.cells:
            if _grade_id(cell) in meta and meta[_grade_id(cell)]:
                cell.metadata["robokin"] = json.loads(json.dumps(meta[_grade_id(cell)]))
        declared: list[str] = []
        for entry in meta.values():
            if entry.get("role") == "answer":
                declared += [n for n in entry.get("declare", []) if n not in declared]
        task_checks: dict = {}   # task -> check -> the expressions it checks
        for entry in meta.values():
            if entry.get("role") == "test":
                for check, expression in entry.get("explain", []):
                    task_checks.setdefault(entry.get("task"), {}).setdefault(check, set()).add(expression)
        answers = [(task_of(c), c.source, meta.get(_grade_id(c), {}).get("declare", []))
                   for c in nb.cells if c.cell_type == "code" and utils.is_solution(c)
                   and meta.get(_grade_id(c), {}).get("role") == "answer"]
        tasks = {name: task for task, _, names in answers for name in names}
        return {"cells": cells, "done": 0, "declared": declared, "review": delegation.find(answers, task_checks),
                "tasks": tasks,
                "imports": {}, "problems": [], "side_effects": {}, "instructor_names": set()}

    def _source_metadata(self, info) -> dict | None:
        try:
            coursedir = CourseDirectory(parent=self)
            path = Path(coursedir.format_path(coursedir.source_directory, ".", info["assignment"])) \
                / f"{info['notebook']}.ipynb"
            source = nbformat.read(path, as_version=4)
        except Exception as exc:  # noqa: BLE001 - then the submission's metadata is used
            self.log.warning("bridge: no source notebook (%s); using the submission's metadata", exc)
            return None
        return {_grade_id(c): (robokin_metadata(c), c.metadata.get("tags", [])) for c in source.cells if _grade_id(c)}

    def _start_grader(self) -> None:
        server = fork_server.shared_server(PRELOAD, self.log) if self.fork_server else None
        self._grader = GraderKernel(self.timeout, self.log, server)
        self._grader.start(self._async_manager().get_connection_info(), self.call_timeout)

    # ------------------------------------------------------------ running
    def execute_cell(self, cell, cell_index, execution_count=None, store_history=True):
        if self._grader is None:
            self._start_grader()   # before any code of the submission runs
        cell = super().execute_cell(cell, cell_index, execution_count, store_history)
        plan, _ = self._bridge()
        grade_id = _grade_id(cell)
        ids = [c["grade_id"] for c in plan["cells"]]
        if grade_id in ids[plan["done"]:]:
            graded = self._run_instructor_cells(ids.index(grade_id) + 1)
            if utils.is_grade(cell) and cell.cell_type == "code":
                student_count = cell.get("execution_count")
                count = graded.get("execution_count")
                outputs = graded.outputs
                if count and student_count:
                    for output in outputs:
                        if output.get("output_type") == "error":
                            # the student's numbering of the cell ("Cell In[n], line k")
                            output["traceback"] = [re.sub(rf"(Cell(?:\x1b\[[0-9;]*m|\s)*In\[){count}\]",
                                                          rf"\g<1>{student_count}]", line)
                                                   for line in output.get("traceback", [])]
                cell.outputs = outputs
        return cell

    def _run_instructor_cells(self, upto: int):
        """Run the instructor's cells not yet run, up to index ``upto`` (exclusive); the last one run."""
        plan, grader = self._bridge()
        last = None
        while plan["done"] < upto:
            item = plan["cells"][plan["done"]]
            plan["done"] += 1
            if item.get("skip"):
                continue
            self._import(free_names(item["source"]), item["grade_id"], extra=item["test"])
            last = grader.run(item["source"])
            plan["instructor_names"].update(defined_names(item["source"]))
            self._unstick()
        return last

    def _import(self, names, where: str, extra: bool = False) -> None:
        self._unstick()   # a call stopped earlier (in a test or in robokin.check) must not block this one
        plan, grader = self._bridge()
        wanted = [n for n in plan["declared"] if n in names]
        # a test that reads a name no answer declares and no instructor cell defines relies on a
        # side effect of the student's code (e.g. an import in a cell of theirs): taken if it can be handed over
        others = sorted(n for n in names if n not in plan["declared"]
                        and n not in plan["instructor_names"] and not hasattr(builtins, n)) if extra else []
        if others:
            self.log.info("bridge: %s reads %s, which no answer declares", where, ", ".join(others))
            plan["side_effects"].setdefault(where, others)
        if not wanted and not others:
            return
        summary, cell = grader.marked(
            f"_robokin_bridge.import_names(globals(), {wanted!r}, {self._import_mark!r}, {tuple(others)!r})",
            self._import_mark)
        if summary is None:
            errors = [f"{o.ename}: {o.evalue}" for o in cell.outputs if o.get("output_type") == "error"]
            plan["problems"].append(f"answers {', '.join(wanted)} could not be imported before {where}: "
                                          + ("; ".join(errors) or "no reply"))
            return
        for name, status in summary.items():
            plan["imports"][name] = status
        self._unstick()

    def _unstick(self) -> None:
        """A call of a student's function timed out: interrupt the student's kernel.

        Asked of the grader kernel only if it has run a cell since it last answered "not
        stuck": a call can time out (and a call session stay open) only while a cell of the
        grader's runs, so a second question with nothing run in between (after one
        instructor cell, before the next one's answers are imported) has the same answer.
        """
        _, grader = self._bridge()
        if grader.runs == self._settled_at:
            return
        status, _ = grader.marked(f"print({self._import_mark!r} + __import__('json').dumps("
                                  "_robokin_bridge.status()))", self._import_mark)
        if status and status.get("stuck"):
            self.log.warning("bridge: a call of the student's function timed out; interrupting its kernel")
            run_sync(self._async_manager().interrupt_kernel)()
            grader.run("_robokin_bridge.unstick()")
        else:
            self._settled_at = grader.runs

    def _verdicts(self, pairs, index):
        """robokin.check's verdicts, computed in the grader kernel on the imported answers.

        A call of the student's function that is stopped at the time limit leaves the
        student's kernel running it until it is interrupted: the checks after it in the
        same run could not call any answer (``grader_side.NOT_CALLED``). Those are run
        again after the interrupt, so that each answer's verdict is its own.
        """
        verdicts = self._verdicts_once(pairs)
        for _ in range(len(pairs)):   # each round checks at least one more answer
            again = [i for i, v in enumerate(verdicts or []) if NOT_CALLED in str(v.get("message", ""))]
            if not again:
                break
            redone = self._verdicts_once([pairs[i] for i in again])
            if redone is None or len(redone) != len(again):
                break
            for i, verdict in zip(again, redone):
                verdicts[i] = verdict
        return verdicts

    def _verdicts_once(self, pairs):
        if not pairs:
            return []
        names = set()
        for _, expression in pairs:
            names |= free_names(str(expression))
        self._import(names, "robokin.check")
        code = (f"__import__('robokin.check.grading', fromlist=['_']).print_verdicts("
                f"globals(), {[list(p) for p in pairs]!r}, {self._verdict_mark!r})")
        try:
            cell = self._bridge()[1].run(code)
            self._unstick()
        except Exception as exc:  # noqa: BLE001 - feedback is a bonus; grading goes on
            self.log.warning("robokin.check verdicts failed: %s", exc)
            return None
        text = "".join(o.get("text", "") for o in cell.outputs if o.get("output_type") == "stream")
        for line in text.splitlines():
            if line.startswith(self._verdict_mark + " "):
                try:
                    return json.loads(line[len(self._verdict_mark):])
                except ValueError:
                    return None
        return None

    def _run_student_kernel(self, nb, resources, km):
        """The notebook run in the student's kernel (``preprocess`` has made the bridge's plan)."""
        self._sandboxed = km is None and sandbox_wanted(self.sandbox)
        if self._sandboxed:
            bwrap_executable()   # stops grading with a message naming the package when it is missing
        self._stopped = None
        self._replays = 0
        self._timed_out = set()
        self._report = {"explained": {}, "verdicts": None, "pairs": [], "incidents": [], "not_run_from": None}
        pairs = []
        for cell in nb.cells:
            for pair in robokin_metadata(cell).get("explain", []):
                item = (task_of(cell), pair[0], pair[1])
                if item not in pairs:
                    pairs.append(item)
        pairs += [item for item in registered_pairs(nb) if item not in pairs]
        self._report["pairs"] = pairs
        # robokin.check's verdicts on every task: after the last test (the answers are all
        # there), so that a kernel that dies in a later cell does not take them along
        self._last_code = max((i for i, c in enumerate(nb.cells) if c.cell_type == "code" and utils.is_grade(c)),
                              default=max((i for i, c in enumerate(nb.cells) if c.cell_type == "code"), default=-1))
        self._last_graded, self._report["not_run_from"] = last_graded_cell(nb.cells)
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

    def preprocess_cell(self, cell, resources, index):
        if self._stopped is not None:
            return self._not_run(cell), self.resources
        if index > self._last_graded:   # nothing graded from here on: not run
            if cell.cell_type == "code":
                cell.outputs, cell.execution_count = [], None
            return cell, self.resources
        try:
            cell, resources = super().preprocess_cell(cell, resources, index)
        except (DeadKernelError, CellTimeoutError) as exc:
            self._kernel_lost(cell, index, exc)
            return self.nb.cells[index], self.resources
        # a fork bomb's children stay counted until the kernel ends: it could not start a thread
        full = self.km.at_process_cap() if isinstance(self.km, SandboxedKernelManager) else ""
        if full:
            self._kernel_lost(cell, index, KernelAtProcessCap(full))
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
