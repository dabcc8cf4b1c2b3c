"""The command jupyter_client runs for a grader kernel forked from the fork server.

Run as ``python -I -S fork_launcher.py SOCKET -- python -m ipykernel_launcher -f FILE``
(:class:`tools.grading.bridge.fork_server.ForkedKernelManager` puts it in front of the
kernel spec's command). It sends the fork server (:mod:`tools.grading.bridge.fork_server`)
the kernel's arguments, its working folder and environment (what jupyter_client
gave this process) and its standard streams; the server forks a kernel from its
warm process. This process stays the kernel jupyter_client knows: it forwards
the signals it gets (the interrupt at a cell's time limit, SIGTERM) to the
kernel, and exits with the kernel's status when the kernel ends (killed by a
signal: by the same signal). If it dies, even by SIGKILL, the server sees its
connection close and kills the kernel.

When the server cannot fork the kernel (it is gone, or it refuses: another
environment), this process says so on stderr and becomes the kernel as
jupyter_client would have started it (``exec`` of the command after ``--``).

Standard library only, no ``site``: it starts in a few milliseconds.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import sys

#: Bytes of one message of the server's (a reply or an exit status).
MAX_REPLY = 4096
#: Signals passed on to the kernel.
FORWARDED = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1, signal.SIGUSR2)


def ask_server(path: str, command: list[str]) -> tuple[socket.socket | None, str]:
    """A connection to the server at ``path`` that forked the kernel, or None and why not."""
    connection = socket.socket(socket.AF_UNIX, socket.SOCK_SEQPACKET)
    try:
        connection.connect(path)
        request = json.dumps({"argv": command[1:], "cwd": os.getcwd(), "env": dict(os.environ)}).encode()
        socket.send_fds(connection, [request], [0, 1, 2])
        reply = json.loads(connection.recv(MAX_REPLY) or b'{"error": "the fork server closed the connection"}')
    except (OSError, ValueError) as exc:
        connection.close()
        return None, f"{type(exc).__name__}: {exc}"
    if "pid" not in reply:
        connection.close()
        return None, str(reply.get("error", reply))
    return connection, ""


def main(argv: list[str]) -> int:
    if len(argv) < 4 or argv[2] != "--":
        sys.stderr.write("usage: fork_launcher.py SOCKET -- KERNEL COMMAND...\n")
        return 2
    command = argv[3:]
    connection, why = ask_server(argv[1], command)
    if connection is None:
        sys.stderr.write(f"[robokin grading] the fork server did not start this grader kernel ({why}): "
                         "starting it as a new process\n")
        sys.stderr.flush()
        os.execv(command[0], command)

    def forward(signum, frame):
        try:
            connection.send(json.dumps({"signal": signum}).encode())
        except OSError as exc:   # the server is gone, and the kernel with it (it killed it)
            sys.stderr.write(f"[robokin grading] signal {signum} not passed on to the grader kernel: {exc}\n")

    for signum in FORWARDED:
        signal.signal(signum, forward)
    while True:
        data = connection.recv(MAX_REPLY)
        if not data:   # the server died, and with it the kernel (its parent-death signal)
            return 1
        message = json.loads(data)
        if "exit" in message:
            break
    status = int(message["exit"])
    if status < 0:   # the kernel was killed by a signal: so is this process
        signal.signal(-status, signal.SIG_DFL)
        os.kill(os.getpid(), -status)
        return 128 - status
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
