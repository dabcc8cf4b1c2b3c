"""Grader kernels forked from a warm process (tools/grading/bridge/fork_server.py):
a kernel costs a fork, not a Python start.

Each grader kernel of an ``nbgrader autograde`` run is a fresh fork of one
process that imported ipykernel and the grader's modules (``PRELOAD``) once.
These tests start the grader kernels as ``BridgedExecute`` does
(``GraderKernel``, tools/grading/bridge/grader_kernel.py), without a course: two kernels of one server are two
processes that share nothing; a forked kernel is what a new one would be (its
environment, ``sys.path``, modules, signal handlers, matplotlib backend); a cell
past its time limit is interrupted; nothing is left running when the launcher
or the autograde process is killed; and grading without the server
(``c.BridgedExecute.fork_server = False``, or a server that cannot start or
refuses) starts each kernel as a new process. The autograde runs of
``tests/test_nbgrader.py`` and the trust, tamper and mutation suites grade
through the fork server.
"""

from __future__ import annotations

import json
import logging
import os
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from typing import TYPE_CHECKING

import pytest

from support import installed

psutil = pytest.importorskip("psutil")
installed.require("nbgrader", "nbgrader is not installed: run `make test` (installs requirements.txt)")
if not hasattr(os, "fork") or not sys.platform.startswith("linux"):
    pytest.skip("the fork server forks grader kernels on Linux", allow_module_level=True)

from tools.grading.bridge import fork_server  # noqa: E402 - after the skip: it needs fork

if TYPE_CHECKING:
    from tools.grading.bridge.grader_kernel import GraderKernel

# tools.grading.bridge.grader_kernel and .execute import nbgrader (1.3 CPU-s): the tests import
# them when they run, not at collection, which every pytest worker of a run does

pytestmark = pytest.mark.nbgrader
LOG = logging.getLogger("test_grading_fork_server")
CURRENT_TEST = "PYTEST_CURRENT_TEST"
#: Seconds a killed process's kernel and server may take to end.
GRACE = 10.0


def _probe_source() -> str:
    """What a kernel tells about itself, after the grader's imports (as the bridge's set-up cell does them)."""
    from tools.grading.bridge.grader_kernel import PRELOAD

    return "\n".join([
        "import json as _json, os as _os, signal as _signal, sys as _sys, threading as _threading",
        *[f"import {name}" for name in PRELOAD],
        "_figure = matplotlib.pyplot.figure()",
        "print('PROBE ' + _json.dumps({",
        "    'pid': _os.getpid(), 'parent': _os.getppid(), 'env': dict(_os.environ), 'path': _sys.path[1:],",
        "    'argv': [_sys.argv[0], *_sys.argv[3:]], 'cwd_first': _sys.path[0] == _os.getcwd(),",
        "    'backend': matplotlib.get_backend(), 'rc': {k: repr(v) for k, v in matplotlib.rcParams.items()},",
        "    'modules': sorted(_sys.modules), 'fds': len(_os.listdir('/proc/self/fd')),",
        "    'threads': sorted(__import__('re').sub(r'-[0-9]+', '', t.name) for t in _threading.enumerate()),",
        "    'signals': {n: repr(_signal.getsignal(getattr(_signal, n))) for n in",
        "                ('SIGINT', 'SIGTERM', 'SIGCHLD', 'SIGHUP', 'SIGPIPE', 'SIGQUIT')},",
        "    'own_session': _os.getsid(0) == _os.getpid(), 'main': repr(_sys.modules['__main__']),",
        "}))",
    ])


def _alive(pid: int) -> bool:
    try:
        return psutil.Process(pid).status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def _wait_gone(pids, seconds: float = GRACE) -> list[int]:
    """The processes of ``pids`` still running after ``seconds``."""
    deadline = time.monotonic() + seconds
    left = [pid for pid in pids if _alive(pid)]
    while left and time.monotonic() < deadline:
        time.sleep(0.1)
        left = [pid for pid in left if _alive(pid)]
    return left


def _stdout(cell) -> str:
    return "".join(o.get("text", "") for o in cell.outputs if o.get("output_type") == "stream")


def _errors(cell) -> list:
    return [(o.ename, o.evalue) for o in cell.outputs if o.get("output_type") == "error"]


def _probe(kernel: GraderKernel) -> dict:
    cell = kernel.run(_probe_source())
    assert not _errors(cell), _errors(cell)
    line = next(line for line in _stdout(cell).splitlines() if line.startswith("PROBE "))
    return json.loads(line[len("PROBE "):])


@pytest.fixture(scope="module")
def server():
    """A fork server with the grader's modules, as the first grader kernel of an autograde run starts it."""
    from tools.grading.bridge.grader_kernel import PRELOAD

    started = fork_server.ForkServer(PRELOAD)
    yield started
    started.stop()


@pytest.fixture
def kernels(server):
    """``kernels(n, timeout=30, server=server)``: n grader kernels started, stopped after the test."""
    from tools.grading.bridge.grader_kernel import GraderKernel

    made: list[GraderKernel] = []

    def make(count: int = 1, timeout: int = 30, source=server) -> list[GraderKernel]:
        # pytest's PYTEST_CURRENT_TEST names the test: the server's is the one of the test that started it
        current = os.environ.get(CURRENT_TEST, "")
        os.environ[CURRENT_TEST] = server.environment.get(CURRENT_TEST, current)
        try:
            for _ in range(count):
                kernel = GraderKernel(timeout, LOG, source)
                made.append(kernel)
                kernel.start_kernel()
        finally:
            os.environ[CURRENT_TEST] = current
        return made[-count:]

    yield make
    for kernel in made:
        kernel.stop()


def test_server_has_imported_the_modules_and_runs_no_thread_of_its_own(server):
    assert server.alive()
    process = psutil.Process(server.info["pid"])
    assert process.ppid() == os.getpid()
    assert oct(os.stat(server.folder).st_mode & 0o777) == "0o700"
    # the only threads besides the main one are OpenBLAS's (one pool per library loaded:
    # numpy's and scipy's), stopped by OpenBLAS's own fork handler
    assert server.info["threads"] <= 1 + 2 * (os.cpu_count() or 1)


def test_two_kernels_are_two_processes_that_share_nothing(server, kernels):
    first, second = kernels(2)
    pids = []
    for kernel in (first, second):
        cell = kernel.run("import os\nprint(os.getpid(), os.getppid())")
        pid, parent = map(int, _stdout(cell).split())
        pids.append(pid)
        assert parent == server.info["pid"], "forked by the server"
        launcher = kernel.client.km.provisioner.process
        assert launcher.pid != pid and psutil.Process(launcher.pid).ppid() == os.getpid()
    assert pids[0] != pids[1] and server.info["pid"] not in pids
    first.run("secret = 42\nimport numpy\nnumpy.seterr(all='raise')")
    cell = second.run("import numpy\nprint('secret' in globals(), numpy.geterr()['divide'])")
    assert _stdout(cell).split() == ["False", "warn"]
    # BLAS after the fork (OpenBLAS's threads were stopped by its fork handler): right products
    cell = first.run(textwrap.dedent("""\
        import numpy as np
        rng = np.random.default_rng(0)
        a, b = rng.standard_normal((2, 400, 400))
        print(np.allclose(a @ b, np.einsum('ij,jk->ik', a, b)))"""))
    assert _stdout(cell).split() == ["True"]
    # numpy.random is seeded afresh in each kernel, as in a new process
    draws = [_stdout(k.run("import numpy\nprint(numpy.random.randint(2**62))")) for k in (first, second)]
    assert draws[0] != draws[1]


def test_a_forked_kernel_is_what_a_new_one_is(kernels):
    """Environment, sys.path, argv, modules, signals, matplotlib: the same as a kernel started anew
    (the path ``c.BridgedExecute.fork_server = False`` takes)."""
    forked, = kernels(1)
    new, = kernels(1, source=None)
    assert new.client.km.provisioner.process.args[1:3] == ["-c", fork_server.UNLIMITED_IOPUB_KERNEL]
    seen = {"forked": _probe(forked), "new": _probe(new)}
    assert seen["new"]["parent"] == os.getpid()
    for key in ("env", "path", "argv", "cwd_first", "backend", "rc", "modules", "fds", "threads", "signals",
                "own_session", "main"):
        assert seen["forked"][key] == seen["new"][key], key
    assert seen["forked"]["backend"] == "module://matplotlib_inline.backend_inline"
    assert seen["forked"]["own_session"]
    # a stream a module kept when imported (sympy: `from sys import stdout`) shows under the cell
    for kernel in (forked, new):
        cell = kernel.run("import sympy.strategies.core\nsympy.strategies.core.stdout.write('kept stream\\n')")
        assert _stdout(cell) == "kept stream\n"


def test_a_cell_past_its_time_limit_is_interrupted(kernels):
    kernel, = kernels(1, timeout=2)
    started = time.monotonic()
    cell = kernel.run("import time\ntime.sleep(60)")
    assert time.monotonic() - started < 30
    assert [name for name, _ in _errors(cell)] == ["CellTimeoutError"]
    assert _stdout(kernel.run("print('still here')")).strip() == "still here"


def test_killing_the_launcher_kills_its_kernel(server, kernels):
    kernel, other = kernels(2)
    pid = int(_stdout(kernel.run("import os\nprint(os.getpid())")))
    launcher = kernel.client.km.provisioner.process
    os.kill(launcher.pid, signal.SIGKILL)
    launcher.wait(timeout=GRACE)
    assert _wait_gone([pid]) == []
    assert server.alive()
    assert _stdout(other.run("print(6 * 7)")).strip() == "42", "the other kernel goes on"


#: An "autograde process": a fork server (few modules: its life is tested here, not its imports),
#: started from the main thread or another one (``sys.argv[1]``: without the parent-death signal
#: then), and a grader kernel forked from it; prints the pids, the server's folder and the kernel's
#: socket folder (jupyter_client's manager's, which the killed process leaves: the test removes
#: it), then waits to be killed.
AUTOGRADE = """
import json, sys, tempfile, threading, time
import psutil
from jupyter_core.utils import run_sync
from tools.grading.bridge import fork_server
started = []
if sys.argv[1] == "main thread":
    started.append(fork_server.ForkServer(("numpy",)))
else:
    thread = threading.Thread(target=lambda: started.append(fork_server.ForkServer(("numpy",))))
    thread.start()
    thread.join()
server, = started
manager = fork_server.ForkedKernelManager(kernel_name="python3", fork_server=server)
run_sync(manager.start_kernel)(cwd=tempfile.mkdtemp())
client = manager.client()
client.start_channels()
run_sync(client.wait_for_ready)(timeout=60)
kernels = [p.pid for p in psutil.Process(server.process.pid).children()]
print(json.dumps({"server": server.process.pid, "launcher": manager.provisioner.pid, "kernels": kernels,
                  "folder": server.folder, "kernel_folder": str(manager.socket_folder)}), flush=True)
time.sleep(300)
"""


@pytest.mark.parametrize("started_in", ["main thread", "another thread"])
def test_killing_the_autograde_process_leaves_no_process_or_folder_behind(started_in):
    """SIGKILL of the autograde process: the server ends (by the parent-death signal or its pipe),
    kills its kernels and removes its socket's folder (the autograde process cannot)."""
    autograde = subprocess.Popen([sys.executable, "-c", AUTOGRADE, started_in],
                                 stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    pids: dict = {}
    try:
        assert autograde.stdout is not None  # piped
        pids = json.loads(autograde.stdout.readline())
        assert len(pids["kernels"]) == 1 and all(_alive(pid) for pid in (pids["server"], *pids["kernels"]))
        assert os.listdir(pids["folder"]) == ["server"]
        autograde.kill()
        autograde.wait(timeout=GRACE)
        left = _wait_gone([pids["server"], pids["launcher"], *pids["kernels"]])
        assert left == [], [psutil.Process(pid).cmdline()[:4] for pid in left if _alive(pid)]
        assert not os.path.exists(pids["folder"]), os.listdir(pids["folder"])
    finally:
        if autograde.poll() is None:
            autograde.kill()
            autograde.wait()
        if pids:
            shutil.rmtree(pids["kernel_folder"], ignore_errors=True)


def test_a_refused_kernel_starts_anew_and_says_so(kernels, monkeypatch, capfd):
    """Another environment than the server's: the launcher starts the kernel as a new process."""
    monkeypatch.setenv("ROBOKIN_FORK_SERVER_TEST", "another environment")
    kernel, = kernels(1)
    monkeypatch.delenv("ROBOKIN_FORK_SERVER_TEST")
    cell = kernel.run("import os\nprint(os.getpid(), os.environ['ROBOKIN_FORK_SERVER_TEST'])")
    pid, value = _stdout(cell).split(maxsplit=1)
    assert int(pid) == kernel.client.km.provisioner.process.pid, "the launcher became the kernel"
    assert value.strip() == "another environment"
    assert "the fork server did not start this grader kernel" in capfd.readouterr().err


def test_fork_server_false_starts_each_grader_kernel_anew(monkeypatch):
    """``c.BridgedExecute.fork_server = False``: no server; True: this process's shared server."""
    from tools.grading.bridge.execute import BridgedExecute

    made = []

    class Recorder:
        def __init__(self, timeout, log, server=None):
            made.append(server)

        def start(self, connection, call_timeout):
            pass

    class StudentKernel:
        def get_connection_info(self):
            return {}

    monkeypatch.setattr("tools.grading.bridge.execute.GraderKernel", Recorder)
    sentinel = object()
    monkeypatch.setattr(fork_server, "shared_server", lambda preload, logger: sentinel)
    for wanted in (False, True):
        # mypy takes nbclient's __init__(nb); nbgrader's Execute (untyped) puts nbconvert's __init__(**kw) first
        execute = BridgedExecute(fork_server=wanted)
        execute.km = StudentKernel()  # type: ignore[assignment]  # a stand-in kernel manager
        execute._start_grader()
    assert made == [None, sentinel]


def test_a_server_that_cannot_start_is_a_warning_and_kernels_start_anew(monkeypatch, caplog):
    from tools.grading.bridge.grader_kernel import PRELOAD

    def broken(preload):
        raise fork_server.ForkServerError("no fork here")

    monkeypatch.setattr(fork_server, "ForkServer", broken)
    monkeypatch.setattr(fork_server, "_SHARED", {})
    with caplog.at_level(logging.WARNING):
        assert fork_server.shared_server(PRELOAD, LOG) is None
        assert fork_server.shared_server(PRELOAD, LOG) is None
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warnings) == 1 and "no fork server (no fork here)" in warnings[0]
