"""Grader kernels forked from a warm process: the imports paid once per ``nbgrader autograde``.

A grader kernel (:class:`tools.grading.bridge.grader_kernel.GraderKernel`, which autograde's
executor ``BridgedExecute`` starts beside each submission's kernel) is a new Python process
that starts ipykernel and imports ``PRELOAD`` (numpy, scipy, sympy, matplotlib, robokin, ...)
before it runs the instructor's cells: about 1.5 s of CPU, the same for every submission.
With ``c.BridgedExecute.fork_server = True`` (the default), the first grader kernel an
``nbgrader autograde`` process needs starts a **fork server** (:class:`ForkServer`): a process that imports
ipykernel's modules and those modules, and nothing else -- no student's data, no
connection, no kernel application, no thread of its own. Every grader kernel is
then a fresh ``fork()`` of it that starts the ipykernel application with its own
connection file, working folder and environment. Each submission still gets a
new process: nothing passes from one submission's grading to the next but the
modules imported before any grading.

How jupyter_client sees it: :class:`ForkedKernelManager` runs, instead of the
kernel spec's ``python -m ipykernel_launcher -f FILE``, the launcher
``python -I -S fork_launcher.py SOCKET -- python -m ipykernel_launcher -f FILE``
(:mod:`tools.grading.bridge.fork_launcher`, the standard library only). The launcher
hands the server, over a Unix socket in a private folder (0700), the command's
arguments, its working folder, its environment (the one jupyter_client gives a
kernel) and its standard streams; it forwards SIGINT (the interrupt at a cell's
time limit), SIGTERM and the like to the kernel, and exits with the kernel's
status. So jupyter_client signals, interrupts, polls and kills the launcher as
it would the kernel.

Nothing is left behind:

- the kernel dies with its launcher: when the launcher's connection closes (it
  exited, or was killed, even by SIGKILL), the server kills the kernel's process
  group;
- the server dies with the autograde process: it reads a pipe from it (closed
  when the autograde process ends, however it ends) and, when started from the
  main thread, also has the parent-death signal (``PR_SET_PDEATHSIG``, SIGTERM); it
  then kills the kernels it forked and removes its socket and the socket's folder
  (which the autograde process removes too when it stops the server itself);
- a kernel dies with the server (``PR_SET_PDEATHSIG``), and its launcher then
  exits.

What a forked kernel has is what a new one would have: the environment
jupyter_client gives it (the server refuses a request whose environment is not
the one it imported the modules with, and the launcher then starts the kernel as
a new process, saying so on stderr), ``sys.argv``, ``sys.path`` and ``__main__``
of ``python -m ipykernel_launcher`` in its folder, its own session and process
group, the default signal handlers, a freshly seeded ``numpy.random`` (``random``
reseeds itself after a fork), ipykernel's streams wherever a module kept
``sys.stdout`` or ``sys.stderr`` when imported (:class:`_CurrentStream`), and the
matplotlib backend a new kernel picks (the
server imports matplotlib with the ``MPLBACKEND`` that ipykernel sets before any
user code: the kernel's own, or the inline backend).

Fork safety: the server has no Python thread but its main one when it forks
(checked when it starts: :func:`serve` refuses to serve otherwise); the native
threads OpenBLAS may start are handled by OpenBLAS's own fork handler, as in
``multiprocessing``'s ``fork``. ipykernel's ZMQ context and threads are created in
the child, by the kernel application.

Where ``fork()``, ``AF_UNIX`` sockets or the server's start fail, or with
``c.BridgedExecute.fork_server = False``, each grader kernel starts as a new
process, as before (with a warning in the log when the server could not start).
"""

from __future__ import annotations

import atexit
import ctypes
import importlib
import json
import logging
import os
import runpy
import selectors
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path
from typing import cast

from tools.kernel_sockets import UNLIMITED_IOPUB_KERNEL, AsyncPrivateSocketsKernelManager
from traitlets import Any

#: The kernel commands (after the Python) a fork can stand for: ipykernel's launcher, and the same
#: with no limit on the iopub socket (what kernel_sockets' managers start).
KERNEL_COMMANDS = (["-m", "ipykernel_launcher"], ["-c", UNLIMITED_IOPUB_KERNEL])
LAUNCHER = Path(__file__).resolve().with_name("fork_launcher.py")
#: Bytes of one request of a launcher's (its environment is most of it).
MAX_REQUEST = 1 << 20
#: Seconds the server may take to import its modules (more on a loaded machine).
START_TIMEOUT = 180.0
#: Seconds a launcher may take to send its request once connected.
REQUEST_TIMEOUT = 10.0
#: What ipykernel sets ``MPLBACKEND`` to, when it is not set, before any user code runs
#: (``IPKernelApp.init_gui_pylab``); matplotlib reads it when it is imported.
INLINE_BACKEND = "module://matplotlib_inline.backend_inline"
PR_SET_PDEATHSIG = 1
#: The signals whose dispositions a forked kernel gets back: a new process's, inherited as the server's.
KERNEL_SIGNALS = (signal.SIGCHLD, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT, signal.SIGINT)
#: The server's own modules (and their submodules): a forked kernel drops them, a new one never had them.
SERVER_MODULES = ("tools",)
_BOOT = "import sys; _path = list(sys.path); from tools.grading.bridge import fork_server; fork_server.serve(_path)"

log = logging.getLogger(__name__)


class ForkServerError(RuntimeError):
    """The fork server could not be started."""


# ---------------------------------------------------------------- the autograde process's side
class ForkServer:
    """A warm process that forks grader kernels; its socket's folder is private (0700).

    Parameters
    ----------
    preload : sequence of str
        Modules the server imports (besides ipykernel's), in this order.

    Raises
    ------
    ForkServerError
        The platform has no ``fork``/``AF_UNIX``, or the server did not start (an
        import failed, or it did not report within ``START_TIMEOUT`` seconds).
    """

    def __init__(self, preload) -> None:
        if not hasattr(os, "fork") or not hasattr(socket, "AF_UNIX") or not hasattr(socket, "send_fds"):
            raise ForkServerError("this platform has no fork() or no Unix sockets")
        self.preload = tuple(preload)
        self.environment = kernel_environment()
        self.folder = tempfile.mkdtemp(prefix="robokin-forks-")   # mode 0700
        self.socket_path = str(Path(self.folder) / "server")
        in_main_thread = threading.current_thread() is threading.main_thread()
        command = [sys.executable, "-c", _BOOT, self.socket_path,
                   json.dumps(self.preload), str(os.getpid()) if in_main_thread else "0"]
        try:
            self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                            env=self.environment, cwd=self.folder)
        except OSError as exc:
            shutil.rmtree(self.folder, ignore_errors=True)
            raise ForkServerError(f"the fork server did not start: {exc}") from exc
        try:
            self.info = self._ready()
        except BaseException:
            self.stop()
            raise

    def _ready(self) -> dict:
        """The server's report once it listens (pid, threads), read from its stdout."""
        stdout = self.process.stdout
        if stdout is None:   # never: the server is started with stdout=PIPE
            raise ForkServerError("the fork server has no stdout to report on")
        deadline = time.monotonic() + START_TIMEOUT
        selector = selectors.DefaultSelector()
        selector.register(stdout, selectors.EVENT_READ)
        try:
            while not selector.select(timeout=1.0):
                if self.process.poll() is not None or time.monotonic() > deadline:
                    raise ForkServerError("the fork server ended before it was ready (see its error above)"
                                          if self.process.poll() is not None else
                                          f"the fork server was not ready after {START_TIMEOUT:.0f} s")
        finally:
            selector.close()
        line = stdout.readline()
        try:
            info = json.loads(line)
        except ValueError:
            info = {}
        if "error" in info or "pid" not in info:
            raise ForkServerError(f"the fork server did not start: {info.get('error') or line[:300]!r}")
        return info

    def alive(self) -> bool:
        return self.process.poll() is None

    def serves(self, environment) -> bool:
        """Whether a kernel with ``environment`` can be forked here."""
        return _differences(self.environment, environment) == []

    def launch_command(self, command: list[str]) -> list[str] | None:
        """The launcher's command for the kernel ``command``; None for a command it cannot fork.

        Only an ipykernel (``python -m ipykernel_launcher ...``, or kernel_sockets' same kernel with
        no iopub limit, :data:`KERNEL_COMMANDS`) with this Python is forked.
        """
        if len(command) < 3 or command[1:3] not in KERNEL_COMMANDS \
                or os.path.realpath(command[0]) != os.path.realpath(sys.executable):
            return None
        return [sys.executable, "-I", "-S", str(LAUNCHER), self.socket_path, "--", *command]

    def stop(self) -> None:
        """End the server (it kills the kernels it forked that still run) and remove its folder."""
        if self.process.poll() is None:
            try:
                if self.process.stdin is not None:   # always (stdin=PIPE)
                    self.process.stdin.close()   # the server's signal to end
                self.process.wait(timeout=5)
            except (OSError, subprocess.TimeoutExpired):
                self.process.kill()
                self.process.wait()
        for stream in (self.process.stdin, self.process.stdout):
            if stream is not None and not stream.closed:
                stream.close()
        shutil.rmtree(self.folder, ignore_errors=True)


class ForkedKernelManager(AsyncPrivateSocketsKernelManager):
    """A kernel manager whose kernel is forked by ``fork_server`` (a :class:`ForkServer`).

    Only the command changes: jupyter_client launches the fork launcher instead of
    the kernel, and manages it as it would the kernel. Its sockets are files in a
    private folder (``kernel_sockets``: no TCP port another process can be handed too).
    """

    fork_server = Any(None, allow_none=True, help="the ForkServer that forks the kernel (None: a new process)")

    def format_kernel_cmd(self, extra_arguments=None):
        command = super().format_kernel_cmd(extra_arguments)
        if self.fork_server is None:
            return command
        launcher = self.fork_server.launch_command(command)
        if launcher is None:
            self.log.warning("grader kernel: the kernel command %s is not ipykernel with this Python; "
                             "started as a new process", command)
            return command
        return launcher


_SHARED: dict = {}   # "server": the ForkServer of this process, "failed": why it could not start


def shared_server(preload, logger=log) -> ForkServer | None:
    """This process's fork server for ``preload`` (started on first use); None if it cannot start.

    A server is started again when the one running died or was started with
    another environment or other modules. When it cannot start, the warning goes
    to ``logger`` once, and None is returned from then on (each grader kernel then
    starts as a new process).
    """
    server = _SHARED.get("server")
    if server is not None and server.alive() and server.preload == tuple(preload) \
            and server.serves(kernel_environment()):
        return server
    if server is not None:
        logger.info("grader kernels: a new fork server (%s)", "the last one died" if not server.alive()
                    else "another environment or other modules")
        server.stop()
        _SHARED.pop("server")
    if "failed" in _SHARED:
        return None
    try:
        server = ForkServer(preload)
    except ForkServerError as exc:
        _SHARED["failed"] = str(exc)
        logger.warning("grader kernels: no fork server (%s); each grader kernel starts as a new process "
                       "(c.BridgedExecute.fork_server = False says this is meant)", exc)
        return None
    if not _SHARED.get("exit_handler"):
        atexit.register(stop_shared_server)
        _SHARED["exit_handler"] = True
    _SHARED["server"] = server
    logger.info("grader kernels: fork server %d ready (%s thread(s))", server.info["pid"], server.info["threads"])
    return server


def stop_shared_server() -> None:
    """Stop this process's fork server, if it runs."""
    server = _SHARED.pop("server", None)
    if server is not None:
        server.stop()


def kernel_environment() -> dict[str, str]:
    """The environment jupyter_client gives a kernel that this process starts (its kernel spec has none).

    ``JPY_PARENT_PID`` is this process's pid (``jupyter_client.launcher``): the
    server imports the modules with it too, since ipykernel reads it when imported.
    """
    return dict(os.environ, JPY_PARENT_PID=str(os.getpid()))


def _differences(expected, actual) -> list[str]:
    """Names of the variables whose values differ between two environments."""
    return sorted(name for name in set(expected) | set(actual) if expected.get(name) != actual.get(name))


# ---------------------------------------------------------------- the server process
def _set_parent_death_signal(parent: int, signum: int) -> bool:
    """Send ``signum`` to this process when its parent ``parent`` ends (Linux); False if the parent is gone already."""
    if sys.platform.startswith("linux"):
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_PDEATHSIG, signum, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_SET_PDEATHSIG) failed")
    return os.getppid() == parent


def _thread_count() -> int:
    """Threads of this process, native ones included (Linux's /proc; Python's count elsewhere)."""
    try:
        return len(os.listdir("/proc/self/task"))
    except OSError:
        return threading.active_count()


def serve(path_at_start: list[str]) -> None:
    """The fork server's life (``python -c`` started by :class:`ForkServer`; arguments in ``sys.argv``).

    ``path_at_start`` is ``sys.path`` as Python set it up, before the server imported
    anything: a kernel gets it back, its first entry being its working folder as with
    ``python -m``.
    """
    socket_path, preload, parent = sys.argv[1], json.loads(sys.argv[2]), int(sys.argv[3])
    signals_at_start = {signum: signal.getsignal(signum) for signum in KERNEL_SIGNALS}
    # the parent's death (SIGTERM): until the server serves, it removes the folder and exits
    signal.signal(signal.SIGTERM, lambda signum, frame: _remove_socket_and_exit(socket_path, exit_code=0))
    if parent and not _set_parent_death_signal(parent, signal.SIGTERM):
        _remove_socket_and_exit(socket_path, exit_code=1)
    environment = dict(os.environ)
    try:
        if not os.environ.get("MPLBACKEND"):   # as ipykernel sets it before any user code
            os.environ["MPLBACKEND"] = INLINE_BACKEND
        sys.stdout, sys.stderr = _CurrentStream("stdout"), _CurrentStream("stderr")
        try:
            for name in ("ipykernel.kernelapp", *preload):
                importlib.import_module(name)
        finally:
            sys.stdout, sys.stderr = sys.__stdout__, sys.__stderr__
        os.environ.clear()
        os.environ.update(environment)
        if threading.active_count() != 1:
            raise RuntimeError(f"threads were started by the imports: {[t.name for t in threading.enumerate()]}")
        listener = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
        listener.bind(socket_path)
        listener.listen(64)
    except Exception as exc:  # noqa: BLE001 - reported to the autograde process, which then starts kernels anew
        traceback.print_exc()
        print(json.dumps({"error": f"{type(exc).__name__}: {exc}"}), flush=True)
        _remove_socket_and_exit(socket_path, exit_code=1)
    print(json.dumps({"pid": os.getpid(), "threads": _thread_count()}), flush=True)
    _Server(listener, socket_path, environment, path_at_start, signals_at_start).run()


def _remove_socket_and_exit(socket_path: str, exit_code: int) -> None:
    """Remove the server's socket and its folder (empty then; left if not), and end with ``exit_code``."""
    for remove, path in ((os.unlink, socket_path), (os.rmdir, os.path.dirname(socket_path))):
        try:
            remove(path)
        except OSError:
            pass   # never made, removed already by the autograde process, or not empty: left as it is
    os._exit(exit_code)


class _CurrentStream:
    """``sys.stdout`` or ``sys.stderr`` while the server imports the modules.

    A module that keeps the stream it finds when imported (sympy's ``from sys import
    stdout``) would keep, in a new kernel, ipykernel's stream, which shows what it
    writes under the cell. Kept in the server, this stand-in writes in a forked
    kernel where the kernel's ``sys.stdout``/``sys.stderr`` write (ipykernel's
    streams); in the server, to its stderr (its stdout is for its report).
    """

    def __init__(self, name: str) -> None:
        self._name = name

    def __getattr__(self, attribute):
        stream = getattr(sys, self._name)
        return getattr(sys.__stderr__ if stream is self else stream, attribute)


class _Server:
    """The server's loop: requests of launchers, their signals and ends, the kernels' ends."""

    def __init__(self, listener: socket.socket, socket_path: str, environment: dict, path_at_start: list[str],
                 signals_at_start: dict) -> None:
        self.listener = listener
        self.socket_path = socket_path
        self.pid = os.getpid()
        self.environment = environment
        self.path_at_start = path_at_start
        self.selector = selectors.DefaultSelector()
        self.kernels: dict[socket.socket, int] = {}   # launcher's connection -> kernel's pid
        self.alive: set[int] = set()                 # kernels not reaped yet
        self.wake_read, self.wake_write = os.pipe()
        for fd in (self.wake_read, self.wake_write):
            os.set_blocking(fd, False)
        #: what a new process started by the grader would have: its dispositions, inherited as ours
        self.signals_at_start = signals_at_start
        signal.signal(signal.SIGCHLD, lambda signum, frame: None)
        signal.signal(signal.SIGTERM, self._on_terminate)   # the autograde process died (or a kill)
        signal.set_wakeup_fd(self.wake_write)
        signal.signal(signal.SIGINT, signal.SIG_IGN)   # a Ctrl-C of the autograde's terminal: its business
        self.selector.register(listener, selectors.EVENT_READ, "listener")
        self.selector.register(sys.stdin.fileno(), selectors.EVENT_READ, "parent")
        self.selector.register(self.wake_read, selectors.EVENT_READ, "children")

    def run(self) -> None:
        while True:
            for key, _ in self.selector.select():
                if key.data == "listener":
                    self._accept()
                elif key.data == "parent":
                    if not os.read(sys.stdin.fileno(), 4096):   # the autograde process ended or stops us
                        self._end()
                elif key.data == "children":
                    try:
                        os.read(self.wake_read, 4096)
                    except BlockingIOError:
                        pass   # woken by another event: the children are reaped below anyway
                    self._reap()
                else:   # "launcher": a launcher's connection (registered by _accept)
                    self._from_launcher(cast(socket.socket, key.fileobj))

    def _on_terminate(self, signum, frame) -> None:
        if os.getpid() != self.pid:   # a forked kernel before it restored its dispositions: as SIG_DFL
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        self._end()

    def _end(self) -> None:
        for pid in list(self.alive):
            _kill_group(pid, signal.SIGKILL)
        _remove_socket_and_exit(self.socket_path, exit_code=0)

    def _accept(self) -> None:
        connection, _ = self.listener.accept()
        fds: list[int] = []
        try:
            connection.settimeout(REQUEST_TIMEOUT)
            message, fds, flags, _ = socket.recv_fds(connection, MAX_REQUEST, 3)
            request = json.loads(message)
            problem = self._refusal(request, fds, flags)
            if problem:
                connection.send(json.dumps({"error": problem}).encode())
                connection.close()
                return
            sys.stdout.flush()
            sys.stderr.flush()
            server = os.getpid()
            pid = os.fork()
            if pid == 0:
                self._become_kernel(request, fds, connection, server)   # never returns
            self.alive.add(pid)
            self.kernels[connection] = pid
            connection.send(json.dumps({"pid": pid}).encode())
            self.selector.register(connection, selectors.EVENT_READ, "launcher")
        except (OSError, ValueError) as exc:   # this launcher gets no kernel (it then starts one anew)
            print(f"[robokin grading] fork server: a request failed: {type(exc).__name__}: {exc}",
                  file=sys.stderr, flush=True)
            if connection not in self.kernels:
                connection.close()
        finally:
            for fd in fds:
                os.close(fd)

    def _refusal(self, request, fds, flags) -> str:
        """Why the request cannot be served ("" if it can)."""
        if flags & (socket.MSG_TRUNC | socket.MSG_CTRUNC) or len(fds) != 3:
            return "the request was cut short"
        if not isinstance(request, dict) or not isinstance(request.get("env"), dict) \
                or not isinstance(request.get("cwd"), str) or not isinstance(request.get("argv"), list):
            return "the request is not {argv, cwd, env}"
        if request["argv"][:2] not in KERNEL_COMMANDS:
            return f"not an ipykernel command: {request['argv'][:2]}"
        differences = _differences(self.environment, request["env"])
        if differences:
            return f"the kernel's environment is not the server's ({', '.join(differences[:8])} differ)"
        return ""

    def _from_launcher(self, connection: socket.socket) -> None:
        pid = self.kernels.get(connection)
        try:
            data = connection.recv(MAX_REQUEST)
        except OSError:
            data = b""
        if not data:   # the launcher ended (or was killed): so does its kernel
            if pid in self.alive:
                _kill_group(pid, signal.SIGKILL)
            self._forget(connection)
            return
        try:
            signum = int(json.loads(data)["signal"])
        except (ValueError, KeyError, TypeError):
            return
        if pid in self.alive:
            _kill_group(pid, signum)

    def _forget(self, connection: socket.socket) -> None:
        self.kernels.pop(connection, None)
        self.selector.unregister(connection)
        connection.close()

    def _reap(self) -> None:
        while self.alive:
            try:
                pid, status = os.waitpid(-1, os.WNOHANG)
            except ChildProcessError:
                return
            if pid == 0:
                return
            self.alive.discard(pid)
            for connection, kernel in list(self.kernels.items()):
                if kernel == pid:
                    try:
                        connection.send(json.dumps({"exit": os.waitstatus_to_exitcode(status)}).encode())
                    except OSError:
                        pass   # the launcher is gone already: nobody is waiting for the status
                    self._forget(connection)

    # ------------------------------------------------------------ in the forked child
    def _become_kernel(self, request: dict, fds: list[int], connection: socket.socket, server: int) -> None:
        """Turn this forked child of ``server`` into the kernel ``python -m ipykernel_launcher`` would start."""
        code = 1
        try:
            os.setsid()
            if not _set_parent_death_signal(server, signal.SIGKILL):
                os._exit(1)
            signal.set_wakeup_fd(-1)
            for signum, handler in self.signals_at_start.items():   # e.g. SIGQUIT ignored by a shell's &
                signal.signal(signum, handler)
            self.selector.close()
            for item in (self.listener, connection, *self.kernels):
                item.close()
            for fd in (self.wake_read, self.wake_write):
                os.close(fd)
            for target, fd in enumerate(fds):
                os.dup2(fd, target)
            for fd in fds:
                if fd > 2:
                    os.close(fd)
            os.chdir(request["cwd"])
            os.environ.clear()
            os.environ.update(request["env"])
            sys.path[:] = [os.getcwd(), *self.path_at_start[1:]]
            for name in [n for n in sys.modules if n.partition(".")[0] in SERVER_MODULES]:
                del sys.modules[name]
            if "numpy.random" in sys.modules:   # a new kernel's numpy.random is seeded afresh
                sys.modules["numpy.random"].seed()
            if request["argv"][0] == "-c":   # python -c UNLIMITED_IOPUB_KERNEL -f FILE
                sys.argv = ["-c", *request["argv"][2:]]
                exec(compile(request["argv"][1], "<kernel>", "exec"), {"__name__": "__main__"})
            else:
                sys.argv = ["ipykernel_launcher", *request["argv"][2:]]
                runpy.run_module("ipykernel_launcher", run_name="__main__", alter_sys=True)
            code = 0
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
            if exc.code is not None and not isinstance(exc.code, int):
                print(exc.code, file=sys.stderr)
        except BaseException:  # noqa: BLE001 - the kernel's crash, reported on its stderr
            traceback.print_exc()
            code = 1
        finally:
            try:
                atexit._run_exitfuncs()
                sys.stdout.flush()
                sys.stderr.flush()
            finally:
                os._exit(code)


def _kill_group(pid: int, signum: int) -> None:
    """Send ``signum`` to the kernel ``pid``'s process group (the kernel alone if that fails)."""
    try:
        os.killpg(pid, signum)
    except OSError:
        try:
            os.kill(pid, signum)
        except OSError:
            pass   # it ended meanwhile: it is reaped by the loop
