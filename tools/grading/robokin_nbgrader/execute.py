"""``RobokinExecute``: the student's kernel of autograde (``BridgedExecute`` adds the grader kernel).

nbgrader's ``Execute``, with the kernel in a bubblewrap sandbox (``tools/grading/sandbox.py``);
a test scores by pass/fail only (its stderr is a note, a result it shows no partial credit); a
kernel that dies or ignores the interrupt is killed, restarted and brought back to where it was
(the cells before are run again), so it costs only that cell (after the last test, grading just
stops there: nothing graded is left to run). When a test cell fails, ``FailureNotes``
(``failure_notes.py``) writes the note above the traceback; after the last test it asks
``robokin.check`` about every answer it has a check for (``checks.registered_pairs``). The
verdicts come from the grader kernel of ``BridgedExecute`` (``_verdicts``), never from the
student's kernel.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, cast

from jupyter_client.asynchronous import AsyncKernelClient
from jupyter_client.manager import AsyncKernelManager
from jupyter_core.utils import run_sync
from nbclient.exceptions import CellTimeoutError, DeadKernelError
from nbformat.notebooknode import from_dict
from nbgrader import utils
from nbgrader.coursedir import CourseDirectory
from nbgrader.preprocessors import Execute
from tools.grading.sandbox import KernelAtProcessCap, SandboxedKernelManager, bwrap_executable, sandbox_wanted
from traitlets import Bool, Unicode

from .cells import cell_label, robokin_metadata, task_of
from .checks import registered_pairs
from .failure_notes import FailureNotes
from .streams import JoinedStreamsClient


#: The repository (hidden from the sandboxed kernel: its notebooks hold the solutions).
REPOSITORY = Path(__file__).resolve().parents[3]
STDERR_NOTE = "[written to stderr; not counted as a failure]"
#: ename of the error output that zeroes a test the kernel could not run (it had died).
NOT_RUN = "TestNotRun"
#: ename of a cell whose kernel died, or was killed because it ignored the interrupt.
KERNEL_LOST = "KernelLost"


class RobokinExecute(JoinedStreamsClient, Execute):
    """nbgrader's ``Execute`` in a sandbox, scoring a test by pass/fail, plus robokin.check's verdicts.

    - The kernel runs in bubblewrap (``tools/grading/sandbox.py``) unless ``sandbox`` is
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

    # the notebook being graded, set by preprocess
    _sandboxed: bool
    _stopped: dict[str, Any] | None   # the incident that stopped grading (the kernel was lost)
    _replays: int
    _timed_out: set[int]
    _report: dict[str, Any]           # resources["robokin"]
    _last_code: int

    def __init__(self, **kw: Any) -> None:
        """Keywords only, as every traitlets configurable: ``config``, ``parent``, and the traits
        (``sandbox=False``). nbgrader's ``Execute`` carries no types; without this signature a type
        checker takes nbclient's ``NotebookClient(nb, ...)`` for it, which nbconvert's
        ``ExecutePreprocessor.__init__(**kw)`` overrides at run time."""
        super().__init__(**kw)

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

    def preprocess(self, nb, resources=None, km=None):
        self._sandboxed = km is None and sandbox_wanted(self.sandbox)
        if self._sandboxed:
            bwrap_executable()   # stops grading with a message naming the package when it is missing
        self._stopped = None
        self._replays = 0
        self._timed_out = set()
        self._report = {"explained": {}, "verdicts": None, "pairs": [], "incidents": []}
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
        """robokin.check's verdicts on ``pairs`` (``[(check, expression), ...]``), asked after the test
        cell ``index``; None if they could not be had.

        Never asked of the student's kernel, which a submission can tamper with: ``BridgedExecute``
        (``tools/grading/bridge/preprocessors.py``), the executor of the pipeline, decides them in its
        grader kernel.
        """
        raise NotImplementedError("robokin.check's verdicts are decided in a grader kernel: BridgedExecute")

    def preprocess_cell(self, cell, resources, index):
        if self._stopped is not None:
            return self._not_run(cell), self.resources
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
