"""``GraderKernel``: a kernel of the grader's, in which a chapter's tests and verdicts run.

``BridgedExecute`` (:mod:`tools.grading.bridge.execute`) starts one beside each submission's
kernel. It runs instructor cells only (given and test cells, their text from nbgrader's
gradebook); its set-up imports :data:`PRELOAD` and connects the bridge
(:mod:`tools.grading.bridge.grader_side`) to the student's kernel, whose answers it then
imports as data, functions as proxies. It is forked from a warm process
(:class:`tools.grading.bridge.fork_server.ForkServer`) or started as a new process; either
way its sockets are files in a private folder (:mod:`tools.kernel_sockets`) and its
connection file is removed once it runs, so that code in the student's kernel (the same
user) cannot connect to it.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from typing import cast

import nbformat
from jupyter_client.connect import KernelConnectionInfo

from tools.grading.bridge import fork_server
from tools.grading.robokin_nbgrader.streams import JoinedStreamsClient
from tools.kernel_sockets import AsyncPrivateSocketsKernelManager

#: Modules the grader kernel imports before any student code runs.
PRELOAD = ("numpy", "scipy", "scipy.optimize", "scipy.linalg", "sympy", "matplotlib", "matplotlib.pyplot",
           "robokin", "robokin.check", "robokin.check.grading", "robokin.parallel", "robokin.models",
           "robokin.chains", "robokin.transforms", "robokin.motion", "robokin.formatting")
#: ``gc.freeze()`` at the end of the grader kernel's set-up: the ~150,000 objects of ``PRELOAD``
#: and the kernel (which live until the kernel ends) are left out of every later collection. The
#: tests allocate a lot (answers decoded, robokin.check's samples, thousands of calls), and each
#: older-generation collection walked all of them -- and, in a kernel forked from the fork
#: server, wrote to every page they sit on, copying it. CPU in the grader kernel's collections
#: (``gc.callbacks``) for a correct submission: chapter 3 0.27 -> 0.07 s (126 collections),
#: chapter 2 0.17 -> 0.01 s. What the tests print and score does not change; a cycle of garbage
#: made before the set-up ended is freed with the kernel instead of by a collection.
FREEZE_AFTER_SETUP = True


class GraderKernel:
    """A kernel of the grader's, in a private empty folder; runs instructor cells only.

    With a ``server`` (:class:`fork_server.ForkServer`) the kernel is forked from it,
    otherwise started as a new process. Either way its sockets are files in a
    private folder (``kernel_sockets``), not TCP ports.
    """

    def __init__(self, timeout: int | None, log, server: fork_server.ForkServer | None = None) -> None:
        self.folder = tempfile.mkdtemp(prefix="robokin-grader-")
        self.nb = nbformat.v4.new_notebook()
        self.server = server
        manager = fork_server.ForkedKernelManager if server is not None else AsyncPrivateSocketsKernelManager
        self.client = JoinedStreamsClient(self.nb, timeout=timeout, interrupt_on_timeout=True, allow_errors=True,
                                     kernel_name="python3", record_timing=False, log=log,
                                     resources={"metadata": {"path": self.folder}}, kernel_manager_class=manager)
        self.started = False
        #: cells run so far (``run`` and ``marked``): tells whether anything ran since a given moment
        self.runs = 0

    def start_kernel(self) -> None:
        """Start the kernel (forked, or a new process) and its client; remove its connection file."""
        client = self.client
        client.km = client.create_kernel_manager()
        if self.server is not None:   # then the client's kernel_manager_class is ForkedKernelManager
            cast(fork_server.ForkedKernelManager, client.km).fork_server = self.server
        client.start_new_kernel(cwd=self.folder)
        client.start_new_kernel_client()
        self.started = True
        # The key of this kernel is in its connection file: remove the file, so that
        # code running in the student's kernel (same user) cannot connect to it.
        try:
            os.remove(client.km.connection_file)
        except OSError:
            pass

    def start(self, student_connection: KernelConnectionInfo, call_timeout: float) -> None:
        self.start_kernel()
        info = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in student_connection.items()
                if k in ("transport", "ip", "shell_port", "iopub_port", "stdin_port", "control_port",
                         "hb_port", "key", "signature_scheme")}
        setup = "\n".join([
            "import sys as _sys",
            "_sys.path[:] = [p for p in _sys.path if p not in ('', '.')]",
            *[f"import {m}" for m in PRELOAD],
            "from tools.grading.bridge import grader_side as _robokin_bridge",
            f"_robokin_bridge.connect({info!r}, {float(call_timeout)!r})",
            # the modules and the kernel made so far live as long as the kernel: out of the
            # cycle collector's sight (:data:`FREEZE_AFTER_SETUP`)
            *(["import gc as _gc", "_gc.freeze()", "del _gc"] if FREEZE_AFTER_SETUP else []),
            "del _sys",
        ])
        cell = self.run(setup)
        errors = [o for o in cell.outputs if o.output_type == "error"]
        if errors:
            raise RuntimeError(f"the grader kernel could not start the bridge: {errors[0].ename}: "
                               f"{errors[0].evalue}")

    def run(self, source: str):
        self.runs += 1
        cell = nbformat.v4.new_code_cell(source)
        self.nb.cells.append(cell)
        cell = self.client.execute_cell(cell, len(self.nb.cells) - 1, store_history=True)
        for output in cell.outputs:   # nbclient interrupted a cell that ran too long
            if output.get("output_type") == "error" and output.get("ename") == "KeyboardInterrupt":
                output["ename"] = "CellTimeoutError"
                output["evalue"] = (f"the test ran longer than the time limit ({self.client.timeout} s) "
                                    "and was stopped")
        return cell

    def marked(self, source: str, mark: str):
        """Run ``source``; the JSON of its last stdout line that starts with ``mark``."""
        cell = self.run(source)
        text = "".join(o.get("text", "") for o in cell.outputs if o.get("output_type") == "stream")
        found = None
        for line in text.splitlines():
            if line.startswith(mark):
                found = json.loads(line[len(mark):])
        return found, cell

    def stop(self) -> None:
        if self.started:
            try:
                self.client._cleanup_kernel()
            except Exception:  # noqa: BLE001 - shutting down; nothing left to grade
                pass
        shutil.rmtree(self.folder, ignore_errors=True)
