"""The kernels of the suite talk over sockets in a private folder, not TCP ports (tools/kernel_sockets.py).

Two processes that start kernels at the same moment can be handed the same free TCP
port by jupyter_client, and one kernel then dies before its first cell (a CI run of
the other-machines test lost the tour's kernel to it). These tests check that the
managers the suite uses put a kernel's connection file and sockets in a folder of
its own (so no two kernels can ask for one address), keep it across a restart and
remove it at shutdown, and that nbval builds its kernels with that manager.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
from pathlib import Path

import nbval.kernel
import pytest

from conftest import ROOT
from tools import kernel_sockets
from tools.kernel_sockets import AsyncPrivateSocketsKernelManager, PrivateSocketsKernelManager, PrivateSocketsMixin

pytestmark = [pytest.mark.notebooks,
              pytest.mark.skipif(not kernel_sockets.AVAILABLE, reason="ipc sockets are POSIX only")]


def assert_private_sockets(manager) -> Path:
    folder = manager.socket_folder
    assert folder is not None and folder.is_dir()
    assert folder.stat().st_mode & 0o077 == 0, "the socket folder is open to other users"
    assert manager.transport == "ipc"
    assert Path(manager.connection_file).parent == folder
    assert Path(manager.ip).parent == folder
    sockets = sorted(p.name for p in folder.iterdir() if p.is_socket())
    assert sockets == [f"socket-{i}" for i in range(1, 6)], sockets
    return folder


def test_a_kernel_has_its_sockets_in_its_own_folder_kept_across_a_restart(tmp_path, tmp_path_factory):
    manager = PrivateSocketsKernelManager(kernel_name="python3")
    log = tmp_path_factory.mktemp("kernel-log") / "stderr.txt"
    stderr = open(log, "w", encoding="utf-8")  # the restart below writes to it too
    manager.start_kernel(cwd=str(tmp_path), stderr=stderr)
    client = manager.client()
    client.start_channels()
    try:
        client.wait_for_ready(timeout=60)
        folder = assert_private_sockets(manager)
        assert client.execute_interactive("x = 6 * 7", timeout=60)["content"]["status"] == "ok"
        manager.restart_kernel(now=True)
        client.wait_for_ready(timeout=60)
        assert assert_private_sockets(manager) == folder
        reply = client.execute_interactive("assert 'x' not in globals()", timeout=60)
        assert reply["content"]["status"] == "ok", "the restarted kernel is not a new one"
    finally:
        client.stop_channels()
        manager.shutdown_kernel(now=True)
        stderr.close()
    assert not folder.exists(), "the socket folder outlives the kernel"
    assert manager.socket_folder is None
    assert list(tmp_path.iterdir()) == [], "sockets were made in the kernel's working folder"
    # what `make execute` and every notebook run print: nothing (no warning on the kernel's
    # options, none on TCP without encryption)
    assert "WARNING" not in log.read_text(encoding="utf-8"), log.read_text(encoding="utf-8")


def test_the_async_manager_too():
    async def run():
        manager = AsyncPrivateSocketsKernelManager(kernel_name="python3")
        await manager.start_kernel()
        client = manager.client()
        client.start_channels()
        try:
            await client.wait_for_ready(timeout=60)
            folder = assert_private_sockets(manager)
        finally:
            client.stop_channels()
            await manager.shutdown_kernel(now=True)
        assert not folder.exists()

    # in a thread of its own: an earlier test of this worker may have left an event loop running here
    with concurrent.futures.ThreadPoolExecutor(1) as pool:
        pool.submit(asyncio.run, run()).result(timeout=120)


def test_nbval_starts_its_kernels_with_private_sockets():
    """The repository's conftest.py points nbval's manager at one with private sockets (the suite's
    manager of forked kernels, tests/support/forked_kernels.py, has tools.kernel_sockets'
    PrivateSocketsMixin, as PrivateSocketsKernelManager has)."""
    assert issubclass(nbval.kernel.KernelManager, PrivateSocketsMixin)
    kernel = nbval.kernel.RunningKernel(nbval.kernel.CURRENT_ENV_KERNEL_NAME, cwd=str(ROOT / "notebooks"))
    try:
        assert_private_sockets(kernel.km)
    finally:
        kernel.stop()


def test_a_cell_that_logs_twelve_thousand_lines_is_read_whole_and_ends():
    """A kernel and client made by these managers keep every iopub message the kernel sends: a cell that
    logs 12,000 lines (one message each) reaches nbclient whole, and its ``idle`` status too
    (with ZeroMQ's default limit of 1,000 unread messages some 1,000 lines were lost on a quiet
    machine, and under load the cell ended in "Timeout waiting for IOPub output")."""
    import nbformat
    import zmq
    from nbclient import NotebookClient

    manager = PrivateSocketsKernelManager(kernel_name="python3")
    client = manager.client()
    assert client.context.getsockopt(zmq.RCVHWM) == 0
    nb = nbformat.v4.new_notebook()
    talkative = "import logging\nfor i in range(12000):\n    logging.warning('line %d', i)\n"
    hwm = "import zmq\nprint(get_ipython().kernel.iopub_thread.socket.getsockopt(zmq.SNDHWM))"
    nb.cells = [nbformat.v4.new_code_cell(talkative), nbformat.v4.new_code_cell("print('the next cell')"),
                nbformat.v4.new_code_cell(hwm)]
    # Time limits: the whole test (kernel start, the cell, its 12,000 messages read) takes 5-10 s
    # on the 2-core machine with other jobs running, so 120 s per cell is a ceiling load does not
    # reach. After the cell's reply nbclient waits iopub_timeout for the rest of its output; the
    # messages still queued then (each parsed and its signature checked) took longer than
    # nbclient's default of 4 s on a busy machine ("Timeout waiting for IOPub output"), so that
    # wait gets the same ceiling: it ends as soon as the idle status arrives.
    executor = NotebookClient(nb, timeout=120, iopub_timeout=120, kernel_name="python3",
                              raise_on_iopub_timeout=True, kernel_manager_class=AsyncPrivateSocketsKernelManager)
    concurrent.futures.ThreadPoolExecutor(1).submit(executor.execute).result()   # a loop of its own
    lines = "".join(output.get("text", "") for output in nb.cells[0].outputs).splitlines()
    assert lines == [f"WARNING:root:line {i}" for i in range(12000)]
    assert nb.cells[1].outputs[0]["text"] == "the next cell\n"
    assert nb.cells[2].outputs[0]["text"] == "0\n"   # the kernel's iopub socket keeps every message too
