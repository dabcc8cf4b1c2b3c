"""Kernels whose sockets are files in a private folder (ZMQ's ``ipc`` transport), not TCP ports.

jupyter_client gives a new kernel its five TCP ports by binding port 0 and closing
the socket again; the kernel binds those ports about a second later, once Python
and ipykernel are imported. A process that starts a kernel in that second can be
handed the same free port, and one of the two kernels then dies before it answers
("Address already in use", seen by its client as "Kernel died before replying to
kernel_info"; jupyter/jupyter_client#154, jupyter/nbconvert#1066). ``make test``
starts kernels in several processes at once (two pytest workers, three nbval runs
for other machines, the grader's kernels), so the race is a matter of time: one
kernel in about 80 died of it when ten started together on the 2-core machine.

With the ``ipc`` transport each socket is a file named after a folder made for
this kernel alone (``tempfile.mkdtemp``), so no two kernels can ask for the same
address, and no other user of the machine can connect (the folder is ``0700``).
The folder is kept across restarts (the connection file stays valid) and removed
when the kernel is shut down. Windows has no ``ipc`` sockets: there the managers
below are jupyter_client's own (TCP).

A client made by these managers (``manager.client()``, as nbclient, nbval and the
autograder make theirs) keeps any number of unread messages on its iopub channel.
ZeroMQ's default high-water mark is 1,000 messages at each end: a cell that logs
thousands of lines (one message per flushed line) outruns a client that is slower
than the kernel, and ZeroMQ then drops new messages for that client -- lines of
output and, at the end, the cell's ``idle`` status, which nbclient waits for and
reports as "Timeout waiting for IOPub output" (the autograder took a correct but
talkative notebook for a hang). With no limit on the client's side, its ZeroMQ
thread takes the messages off the kernel's queue as fast as they come, whatever
the Python code reading them does. The kernel's end is lifted too: an ipykernel started by
these managers runs with no limit on its iopub socket (:data:`UNLIMITED_IOPUB_KERNEL`), since a
client's ZeroMQ thread that the machine's load keeps from running for a moment falls 1,000
messages behind a talkative cell (330 lines of 12,000 were lost that way with three test
workers on two cores).

Used for the kernels nbval starts (``conftest.py`` at the repository's root), the
grader's kernels (``tools.grading.bridge``) and the sandboxed student kernel
(``tools.grading.sandbox``, which binds the folder into the sandbox).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import zmq
from jupyter_client.manager import AsyncKernelManager, KernelManager
from jupyter_core.utils import run_sync

#: Whether this system has ZMQ ``ipc`` sockets (Unix domain sockets).
AVAILABLE = os.name == "posix"

#: What ``python -m ipykernel_launcher`` does (the working folder first on the path, then
#: ipykernel's app), with no high-water mark on the kernel's sockets: its iopub socket keeps
#: every message for a client that is behind instead of dropping new ones. Run as ``python -c``.
UNLIMITED_IOPUB_KERNEL = """\
import os
import runpy  # noqa: F401  python -m imports it: the kernel's modules are those of -m's kernel
import sys

sys.path[0] = os.getcwd()  # as python -m puts it (python -c puts "")
import zmq
from ipykernel.kernelapp import IPKernelApp


class UnlimitedIOPubKernelApp(IPKernelApp):
    def init_iopub(self, context):
        context.setsockopt(zmq.SNDHWM, 0)  # the default of the sockets made from here on
        super().init_iopub(context)


UnlimitedIOPubKernelApp.launch_instance()
"""


def with_unlimited_iopub(command: list[str]) -> list[str]:
    """``command`` with ``-m ipykernel_launcher`` replaced by ``-c`` :data:`UNLIMITED_IOPUB_KERNEL`
    (the command of a kernelspec; another kernel's command is returned as it is)."""
    for index in range(len(command) - 1):
        if command[index:index + 2] == ["-m", "ipykernel_launcher"]:
            return [*command[:index], "-c", UNLIMITED_IOPUB_KERNEL, *command[index + 2:]]
    return list(command)


def new_socket_folder() -> Path:
    """A new private folder (mode 0700) for one kernel's connection file and sockets.

    Under ``/tmp`` when it exists: a Unix socket's path has at most 107 bytes
    (103 on macOS), and ``$TMPDIR`` can be long.
    """
    return Path(tempfile.mkdtemp(prefix="robokin-kernel-", dir="/tmp" if os.path.isdir("/tmp") else None))


if TYPE_CHECKING:
    # the class the mixin is mixed into, for mypy: its methods call that class's through super()
    _KernelManagerHost = KernelManager
else:
    _KernelManagerHost = object


class PrivateSocketsMixin(_KernelManagerHost):
    """For a jupyter_client kernel manager: the kernel's sockets are ipc files in a private folder.

    ``socket_folder`` is the folder (None before the first start and after
    shutdown); it holds ``kernel.json`` (the connection file) and the sockets
    ``socket-1`` ... ``socket-5``.
    """

    socket_folder: Path | None = None

    async def _async_pre_start_kernel(self, **kw):
        if AVAILABLE and self.socket_folder is None:   # kept across restarts
            self.socket_folder = new_socket_folder()
            self.transport = "ipc"
            self.connection_file = str(self.socket_folder / "kernel.json")
            self.ip = str(self.socket_folder / "socket")
        return await super()._async_pre_start_kernel(**kw)

    def format_kernel_cmd(self, extra_arguments=None):
        """The kernelspec's command, an ipykernel's with no limit on its iopub socket (see the module)."""
        return with_unlimited_iopub(super().format_kernel_cmd(extra_arguments))

    def client(self, **kwargs):
        """A client of the kernel that keeps any number of unread iopub messages (see the module)."""
        client = super().client(**kwargs)
        client.context.setsockopt(zmq.RCVHWM, 0)   # the client's own context: its channels' default
        return client

    async def _async_cleanup_resources(self, restart: bool = False) -> None:
        await super()._async_cleanup_resources(restart=restart)
        if not restart and self.socket_folder is not None:
            shutil.rmtree(self.socket_folder, ignore_errors=True)
            self.socket_folder = None


class PrivateSocketsKernelManager(PrivateSocketsMixin, KernelManager):
    """jupyter_client's ``KernelManager`` with the kernel's sockets in a private folder."""

    pre_start_kernel = run_sync(PrivateSocketsMixin._async_pre_start_kernel)
    cleanup_resources = run_sync(PrivateSocketsMixin._async_cleanup_resources)


class AsyncPrivateSocketsKernelManager(PrivateSocketsMixin, AsyncKernelManager):
    """jupyter_client's ``AsyncKernelManager`` with the kernel's sockets in a private folder."""

    pre_start_kernel = PrivateSocketsMixin._async_pre_start_kernel
    cleanup_resources = PrivateSocketsMixin._async_cleanup_resources
