"""nbval's kernels forked from a warm process: a notebook's kernel costs a fork, not a Python start.

Every notebook nbval checks gets a new kernel: a Python start, ipykernel's imports
(about 1.7 CPU-s) and the notebook's imports (numpy, scipy.optimize, sympy,
matplotlib, robokin: about 1.8 CPU-s), twelve times per run and again in each of
the three other numerical environments (``tests/test_notebooks_other_machines.py``).
Here the kernels are forked from the grading runtime's fork server
(``tools/grading/bridge/fork_server.py``: its docstring says what a forked kernel
has -- environment, ``sys.argv``, ``sys.path``, streams, a freshly seeded
``numpy.random``, the matplotlib backend -- and how nothing outlives its parent):
one server per pytest process and environment (at most :data:`MAX_SERVERS`), started
by the first kernel, stopped at the end of the session (``stop_server``, called by the root
``conftest.py``).

:class:`ForkedNbvalKernelManager` is the synchronous manager nbval starts (the root
``conftest.py`` points ``nbval.kernel.KernelManager`` at it);
:class:`ForkedAsyncKernelManager` is the same for nbclient (the grading mutations,
``tests/test_grading_mutations.py``, whose kernels see ``ROBOKIN_VIEWER=static``: a
server of their own). Their sockets are private files (``tools.kernel_sockets``). A
kernel that cannot be forked (no server, the server died, another environment, a
command that is not this Python's ipykernel, or the server's refusal) starts as a new
process, and says so: a :class:`KernelNotForked` warning (in pytest's warnings summary)
and a line in the log.

One variable differs from kernel to kernel: pytest's ``PYTEST_CURRENT_TEST``
(the name of the running test). ipykernel reads only whether it is set (then it
leaves the file descriptors 1 and 2 alone); no module the server imports reads
it. A forked kernel gets the value the server was started with, so that its
environment is the server's to the letter, as the server requires.
"""

from __future__ import annotations

import logging
import os
import warnings
from pathlib import Path

from jupyter_core.utils import run_sync

from tools.grading.bridge import fork_server
from tools.kernel_sockets import AsyncPrivateSocketsKernelManager, PrivateSocketsKernelManager, PrivateSocketsMixin

#: What the notebooks import (their first cells), imported once by the server.
PRELOAD = ("numpy", "scipy.optimize", "sympy", "matplotlib.pyplot", "robokin", "robokin.formatting",
           "robokin.transforms", "robokin.motion", "robokin.chains", "robokin.check", "robokin.models")
#: The variable pytest sets to the running test's name (its value changes from test to test).
CURRENT_TEST = "PYTEST_CURRENT_TEST"
#: The kernel's stderr (nbval discards it): read at shutdown for the launcher's note that it fell back.
STDERR_FILE = "kernel-stderr.log"
#: How the fork launcher starts the line it writes when the server did not fork the kernel.
LAUNCHER_FALLBACK = "[robokin grading] the fork server did not start"

#: Fork servers kept at once in one process: nbval's and the grading mutations'. A server
#: holds the preloaded modules (about 150 MB); one more environment stops the oldest.
MAX_SERVERS = 2

log = logging.getLogger(__name__)
#: "servers": {environment (sorted items, CURRENT_TEST left out): ForkServer}, oldest first;
#: "failed": why a server could not start (then none is tried again in this process)
_STATE: dict = {}


class KernelNotForked(UserWarning):
    """A notebook's kernel started as a new process instead of a fork (slower, same outputs)."""


def _not_forked(why: str) -> None:
    message = f"notebook kernel: started as a new process, not forked ({why})"
    log.warning(message)
    warnings.warn(message, KernelNotForked, stacklevel=3)


def _comparable(environment: dict) -> dict:
    return {name: value for name, value in environment.items() if name != CURRENT_TEST}


def _key(environment: dict) -> tuple:
    return tuple(sorted(_comparable(environment).items()))


def server() -> fork_server.ForkServer | None:
    """This process's fork server for its environment (started on first use); None if it cannot start."""
    servers: dict = _STATE.setdefault("servers", {})
    key = _key(fork_server.kernel_environment())
    running = servers.get(key)
    if running is not None and running.alive():
        return running
    if running is not None:
        log.info("forked kernels: a new fork server (the last one died)")
        servers.pop(key).stop()
    if "failed" in _STATE:
        return None
    while len(servers) >= MAX_SERVERS:
        log.info("forked kernels: fork server of another environment stopped (at most %d)", MAX_SERVERS)
        servers.pop(next(iter(servers))).stop()
    try:
        started = fork_server.ForkServer(PRELOAD)
    except fork_server.ForkServerError as exc:
        _STATE["failed"] = str(exc)
        _not_forked(f"no fork server: {exc}")
        return None
    servers[key] = started
    log.info("forked kernels: fork server %d ready", started.info["pid"])
    return started


def stop_server() -> None:
    """Stop this process's fork servers, if any run (each kills the kernels it forked that still run)."""
    servers: dict = _STATE.setdefault("servers", {})
    while servers:
        servers.pop(next(iter(servers))).stop()


class ForkedKernelMixin(PrivateSocketsMixin):
    """For a jupyter_client kernel manager: private sockets, the kernel forked when it can be."""

    _forked_from: fork_server.ForkServer | None = None
    _stderr = None

    async def _async_pre_start_kernel(self, **kw):
        self._forked_from = None
        source = server()
        if source is not None:
            environment = dict(kw.get("env") or os.environ)
            if CURRENT_TEST in source.environment and CURRENT_TEST in environment:
                environment[CURRENT_TEST] = source.environment[CURRENT_TEST]
            if source.serves(dict(environment, JPY_PARENT_PID=str(os.getpid()))):
                kw["env"] = environment
                self._forked_from = source
            else:
                _not_forked("its environment is not the fork server's")
        command, kw = await super()._async_pre_start_kernel(**kw)
        if self._forked_from is not None and self.socket_folder is not None:
            self._close_stderr()
            self._stderr = kw["stderr"] = open(self.socket_folder / STDERR_FILE, "wb")
        return command, kw

    def format_kernel_cmd(self, extra_arguments=None):
        command = super().format_kernel_cmd(extra_arguments)
        if self._forked_from is None:
            return command
        launcher = self._forked_from.launch_command(command)
        if launcher is None:
            self._forked_from = None
            _not_forked(f"the command {command[:3]} is not ipykernel with this Python")
            return command
        return launcher

    async def _async_cleanup_resources(self, restart: bool = False) -> None:
        self._close_stderr()
        if not restart and self.socket_folder is not None:
            _report_fallback(self.socket_folder / STDERR_FILE)
        await super()._async_cleanup_resources(restart=restart)

    def _close_stderr(self) -> None:
        if self._stderr is not None:
            self._stderr.close()
            self._stderr = None


class ForkedNbvalKernelManager(ForkedKernelMixin, PrivateSocketsKernelManager):
    """jupyter_client's synchronous ``KernelManager``, private sockets, the kernel forked when it can be."""

    pre_start_kernel = run_sync(ForkedKernelMixin._async_pre_start_kernel)
    cleanup_resources = run_sync(ForkedKernelMixin._async_cleanup_resources)


class ForkedAsyncKernelManager(ForkedKernelMixin, AsyncPrivateSocketsKernelManager):
    """jupyter_client's ``AsyncKernelManager`` (nbclient's), private sockets, the kernel forked when it can be."""

    pre_start_kernel = ForkedKernelMixin._async_pre_start_kernel
    cleanup_resources = ForkedKernelMixin._async_cleanup_resources


def _report_fallback(stderr_file: Path) -> None:
    """Warn if the launcher wrote that the server did not fork the kernel (then it started anew)."""
    try:
        text = stderr_file.read_text(errors="replace")
    except OSError:
        return
    for line in text.splitlines():
        if line.startswith(LAUNCHER_FALLBACK):
            _not_forked(line)
