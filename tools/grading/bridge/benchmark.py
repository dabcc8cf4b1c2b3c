"""What one call of a student's function costs through the grading bridge.

Starts a student's kernel (in the bubblewrap sandbox, as autograde does, and
without it), connects the grader side to it in this process, and times calls of
small functions through the call channel (:mod:`tools.grading.bridge.grader_side`), and
for comparison through one execute request per call (how the bridge called before
the channel). Prints a table (milliseconds per call, median of repeated batches)::

    python tools/grading/bridge/benchmark.py [--calls N] [--no-sandbox]

Timings depend on the machine and its load; nothing in the test suite asserts them.
"""

from __future__ import annotations

import argparse
import queue
import statistics
import tempfile
import time
import uuid

from tools.grading.bridge import grader_side

STUDENT_CODE = """
import numpy as np

def scalar(phi):
    return np.sin(phi) - 0.5

def matrix(q):
    q = np.asarray(q, dtype=float)
    return np.outer(np.cos(q), np.sin(q))
"""

CASES = (("scalar(phi): float -> float", "scalar", lambda: (0.3,)),
         ("matrix(q): 6 floats -> 6x6 array", "matrix", lambda: ([0.1, 0.2, 0.3, 0.4, 0.5, 0.6],)))


def start_kernel(sandbox: bool, folder: str):
    """A student's kernel (in the sandbox, as autograde starts it, or not) with the benchmark's
    functions defined, and a blocking client of it: ``(manager, client)``.

    The client keeps any number of unread iopub messages (as the clients of
    :mod:`kernel_sockets` managers do) and uses no heartbeat; cells are run with
    :func:`run_cell`, which reads their end from the shell channel.
    """
    import zmq
    from jupyter_client.manager import KernelManager

    manager: KernelManager
    if sandbox:
        from jupyter_core.utils import run_sync

        from tools.grading.sandbox import SandboxedKernelManager

        manager = SandboxedKernelManager(kernel_name="python3", writable=folder, hidden=[])
        run_sync(manager.start_kernel)(cwd=folder)
    else:
        manager = KernelManager(kernel_name="python3")
        manager.start_kernel(cwd=folder)
    from jupyter_client import BlockingKernelClient

    context = zmq.Context()
    context.setsockopt(zmq.RCVHWM, 0)   # the default of the client's channels: no receive limit
    client = BlockingKernelClient(context=context)
    client.load_connection_info(manager.get_connection_info())
    # No heartbeat (as the bridge's link): a client without its manager judges the kernel by
    # heartbeats answered within 1 s, and on a busy machine a late answer made wait_for_ready
    # report "Kernel died before replying to kernel_info" of a live kernel. The wait for the
    # kernel_info reply (60 s, never reached by load: ~1 s on a quiet machine) decides alone.
    client.start_channels(hb=False)
    client.wait_for_ready(timeout=60)
    run_cell(client, STUDENT_CODE, timeout=60)
    return manager, client


def run_cell(client, code: str, timeout: float) -> dict:
    """Run ``code`` in the kernel of ``client`` and return its ``execute_reply``.

    The end of the request is read from its reply on the shell channel, never from the
    ``idle`` status on iopub (``execute_interactive`` waits for that): the kernel sends
    iopub through a ZeroMQ PUB socket, which drops messages for a subscriber more than
    1,000 behind (ZeroMQ's default send limit, which ipykernel keeps). After a cell that
    printed thousands of lines on a busy machine the ``idle`` could be among them, and
    the wait then ran into its time limit ("Timeout waiting for output"). A reply on the
    shell channel is never dropped. The cell's output stays unread on iopub.
    """
    msg_id = client.execute(code, store_history=False)
    deadline = time.monotonic() + timeout
    while (remaining := deadline - time.monotonic()) > 0:
        try:
            reply = client.get_shell_msg(timeout=remaining)
        except queue.Empty:
            break
        if reply["parent_header"].get("msg_id") == msg_id:
            return reply
    raise TimeoutError(f"the kernel did not finish the cell within {timeout:g} s: {code[:60]!r}")


def stop_kernel(manager) -> None:
    from jupyter_core.utils import run_sync

    if hasattr(manager, "_async_shutdown_kernel") and type(manager).__name__ != "KernelManager":
        run_sync(manager.shutdown_kernel)(now=True)
    else:
        manager.shutdown_kernel(now=True)


def _per_call(function, arguments, calls: int, batches: int = 5) -> float:
    """Median over ``batches`` of the mean time of one call, in ms."""
    function(*arguments())   # warm up (opens the session)
    times = []
    for _ in range(batches):
        start = time.perf_counter()
        for _ in range(calls):
            function(*arguments())
        times.append((time.perf_counter() - start) / calls * 1e3)
    return statistics.median(times)


def _execute_request_call(link, handle: int, arguments) -> object:
    """One call as one execute request in the student's kernel (the bridge before the channel)."""
    from tools.grading.bridge import codec

    link.release()
    payload = codec.json.dumps(codec.encode([list(arguments), {}], link.callbacks))
    nonce = uuid.uuid4().hex
    code = (f"_m = __import__('sys').modules['_robokin_bridge']; "
            f"_m._reply({nonce!r}, _m._call({handle}, __import__('json').loads({payload!r})))")
    reply = link.request(code, nonce, link.call_timeout)
    return codec.decode(reply["value"])


def measure(sandbox: bool, calls: int) -> list[tuple[str, str, float, float]]:
    folder = tempfile.mkdtemp(prefix="robokin-bench-")
    manager, client = start_kernel(sandbox, folder)
    try:
        grader_side.connect(manager.get_connection_info(), 30.0)
        namespace: dict = {}
        grader_side.import_names(namespace, ["scalar", "matrix"], "imported: ")
        link = grader_side._LINK
        rows = []
        for label, name, arguments in CASES:
            proxy = namespace[name]
            channel = _per_call(proxy, arguments, calls)
            old = _per_call(lambda *a, p=proxy: _execute_request_call(link, p._handle, a), arguments,
                            max(10, calls // 20))
            rows.append(("sandboxed" if sandbox else "plain", label, channel, old))
        return rows
    finally:
        grader_side.disconnect()
        client.stop_channels()
        stop_kernel(manager)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--calls", type=int, default=500, help="calls per batch (default 500)")
    parser.add_argument("--no-sandbox", action="store_true", help="only the kernel without bubblewrap")
    options = parser.parse_args(argv)
    rows = []
    for sandbox in ([False] if options.no_sandbox else [True, False]):
        rows += measure(sandbox, options.calls)
    print(f"{'kernel':<10} {'call':<34} {'channel ms':>10} {'execute ms':>10} {'ratio':>6}")
    for kernel, label, channel, old in rows:
        print(f"{kernel:<10} {label:<34} {channel:>10.3f} {old:>10.2f} {old / channel:>6.0f}")


if __name__ == "__main__":
    main()
