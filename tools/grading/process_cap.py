"""A cap on the number of processes a graded submission's kernel can create (a fork bomb).

``RLIMIT_NPROC`` alone does not do it: the kernel counts it per real user (every process
of that user, the grader's own included) and ignores it for root (the initial user
namespace's uid 0) and for a process with ``CAP_SYS_RESOURCE`` or ``CAP_SYS_ADMIN``
(Linux, ``kernel/fork.c``, ``copy_process``): a grader that runs as root -- CI, a container,
Gradescope -- would not be capped at all. So the cap is made the first of these ways that
works on the machine (:func:`plan`):

``cgroup``
    the kernel's command starts in a control group of its own whose ``pids.max`` is the cap
    (cgroup v1's ``pids`` hierarchy, or cgroup v2 where the ``pids`` controller is delegated
    to the children of the grader's group): it counts the kernel's processes and threads,
    and nothing else, whoever runs the grader. Needs a writable cgroup (root on a machine or
    VM, a systemd-delegated group); the group is removed when the kernel ends, after killing
    whatever is left in it.
``rlimit``
    ``RLIMIT_NPROC`` on the kernel's command, set inside the sandbox. For an ordinary user
    bwrap makes a user namespace, in which Linux counts the processes of the namespace's
    user apart (the namespace's count is checked against the limit, the user's count on the
    machine against the limit bwrap had when it made the namespace): the limit is the cap,
    and the grader's own processes take nothing from it. Where the kernel shares the
    grader's user namespace, the limit is the number of processes (threads included) the
    grader's user has now plus the cap (other work of that user started meanwhile takes
    from it).

When neither works (root, or a process with those capabilities, and no writable ``pids``
cgroup: a container, where ``/sys/fs/cgroup`` is read-only), :func:`plan` raises
:class:`ProcessCapUnavailable` naming the cause and what to do; nothing falls back silently.
``ROBOKIN_PROCESS_CAP=cgroup|rlimit`` asks for one way only (an error if it does not work).

The cap counts tasks, as both mechanisms do: a thread is one, so it must leave room for the
kernel's own (15 processes and threads for a sandboxed kernel that imported numpy, sympy,
matplotlib and robokin, bwrap's two included).

Both count a child that has ended until its parent reaps it (a zombie), and a kernel reaps
none of the processes a cell forks: a fork bomb's children, ended or not, keep the kernel at
its cap after the cell, and the kernel then cannot start a thread of its own (pyzmq's garbage
collector, started on the first message over 64 kB: its output is lost half-sent and the
grader reads a message with an invalid signature). Only the kernel's end ends them, so the
grader asks after each cell (:meth:`ProcessCap.full`) and restarts a kernel left at its cap
(``tools/grading/bridge/execute.py``), as it does a kernel that died.
"""

from __future__ import annotations

import itertools
import os
import signal
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

#: Processes and threads a student's kernel may have at once: a sandboxed kernel that imported
#: numpy, sympy, matplotlib and robokin has 15 (bwrap's two included), and no exercise starts
#: processes of its own.
DEFAULT_MAX_PROCESSES = 256
#: The cap on the processes of one sandboxed kernel (``tools/grading/sandbox.py``); unset or
#: 0: no cap (what ``nbgrader autograde`` in a course does unless configured).
VARIABLE = "ROBOKIN_MAX_PROCESSES"
#: ``cgroup`` or ``rlimit``: make the cap that way only (default: the first that works).
METHOD_VARIABLE = "ROBOKIN_PROCESS_CAP"
#: A name shared by the control groups of one grading (``grade_submission.py`` sets it, and
#: removes what is left of them at the end).
TAG_VARIABLE = "ROBOKIN_PROCESS_CAP_TAG"
METHODS = ("cgroup", "rlimit")
#: Free places under the cap a kernel needs after a cell: the threads it may start on its own
#: (pyzmq's garbage collector, a thread pool of numpy's or matplotlib's); with fewer, the cell
#: left it at its cap and it is restarted.
HEADROOM = 8
PREFIX = "robokin-kernel-"

#: The command put in front of the kernel's: it enters the cgroup (writes its pid to
#: ``cgroup.procs``; before bwrap) or sets ``RLIMIT_NPROC`` (``alone:shared:namespace``, in
#: the sandbox: ``alone`` in a user namespace other than the grader's, ``shared`` in it), then
#: becomes the kernel's command (exec).
ENTER = ("import os, resource, sys\n"
         "how, value, command = sys.argv[1], sys.argv[2], sys.argv[4:]\n"
         "if how == 'cgroup':\n"
         "    with open(value, 'w') as procs:\n"
         "        procs.write(str(os.getpid()))\n"
         "else:\n"
         "    alone, shared, namespace = value.split(':')\n"
         "    own = os.stat('/proc/self/ns/user').st_ino != int(namespace)\n"
         "    limit = int(alone if own else shared)\n"
         "    resource.setrlimit(resource.RLIMIT_NPROC, (limit, limit))\n"
         "os.execvp(command[0], command)\n")

_NUMBERS = itertools.count()


class ProcessCapUnavailable(RuntimeError):
    """No way to cap a kernel's processes works on this machine (the message says why)."""


@dataclass
class ProcessCap:
    """A cap made for one kernel: its commands before the sandbox's (``outer``) and in it, before the
    kernel's (``inner``); :meth:`release` when the kernel has ended."""

    method: str
    limit: int
    outer: list[str] = field(default_factory=list)
    inner: list[str] = field(default_factory=list)
    cgroup: Path | None = None
    #: what a log line says about it
    description: str = ""

    def tasks(self, root: int) -> int:
        """The processes and threads the cap counts now: the cgroup's ``pids.current``, or those of
        the process ``root`` (bwrap, which the kernel manager started) and its descendants."""
        if self.cgroup is not None:
            try:
                return int((self.cgroup / "pids.current").read_text())
            except (OSError, ValueError):
                pass   # removed meanwhile: count the tree
        return tasks_of_tree(root)

    def full(self, root: int) -> str:
        """Why the kernel whose first process is ``root`` is at its cap ('' when it is not): fewer
        than :data:`HEADROOM` tasks are left to it."""
        used = self.tasks(root)
        if self.limit - used >= HEADROOM:
            return ""
        return (f"the cell left the kernel at its cap on processes ({used} processes and threads of "
                f"{self.limit}: the processes a cell starts, running or ended, count until the kernel reaps "
                "them), where it cannot start a thread of its own")

    def release(self) -> int:
        """Kill what is left in the cgroup and remove it; the number of processes killed."""
        if self.cgroup is None:
            return 0
        killed = remove_cgroup(self.cgroup)
        self.cgroup = None
        return killed


def requested() -> int:
    """The cap asked for by ``ROBOKIN_MAX_PROCESSES`` (0: none)."""
    value = os.environ.get(VARIABLE, "").strip()
    if not value:
        return 0
    try:
        limit = int(value)
    except ValueError:
        raise ValueError(f"{VARIABLE} must be a whole number of processes (0: no cap), not {value!r}") from None
    if limit < 0:
        raise ValueError(f"{VARIABLE} must be 0 (no cap) or positive, not {limit}")
    return limit


def exempt_from_rlimit() -> str:
    """Why ``RLIMIT_NPROC`` would not hold for this process's children ('' when it would)."""
    if os.getuid() == 0 and _root_of_initial_namespace():
        return "the grader runs as root (uid 0 of the initial user namespace), for which Linux ignores RLIMIT_NPROC"
    capabilities = _effective_capabilities()
    held = [name for bit, name in ((24, "CAP_SYS_RESOURCE"), (21, "CAP_SYS_ADMIN")) if capabilities >> bit & 1]
    if held:
        return f"the grader holds {' and '.join(held)}, with which Linux ignores RLIMIT_NPROC"
    return ""


def _root_of_initial_namespace() -> bool:
    """Whether uid 0 here is uid 0 of the machine (not root mapped from a user in a user namespace)."""
    try:
        first = Path("/proc/self/uid_map").read_text().split()
    except OSError:
        return True
    return len(first) >= 3 and first[0] == "0" and first[1] == "0"


def _effective_capabilities() -> int:
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("CapEff:"):
                return int(line.split()[1], 16)
    except (OSError, ValueError):
        pass
    return 0


def tasks_of_user(uid: int) -> int:
    """Processes and threads whose real user is ``uid`` (what ``RLIMIT_NPROC`` counts), from /proc."""
    count = 0
    for entry in os.scandir("/proc"):
        if not entry.name.isdigit():
            continue
        try:
            status = Path(entry.path, "status").read_text()
        except OSError:   # ended meanwhile
            continue
        fields = dict(line.split(":", 1) for line in status.splitlines() if ":" in line)
        if int(fields.get("Uid", "-1 0").split()[0]) == uid:
            count += int(fields.get("Threads", "1").strip() or 1)
    return count


def tasks_of_tree(root: int) -> int:
    """Processes and threads of ``root`` and its descendants, children that ended and are not
    reaped (zombies) included, from /proc (``task/*/children``); 0 when ``root`` has ended."""
    count, stack, seen = 0, [root], set()
    while stack:
        pid = stack.pop()
        if pid in seen:
            continue
        seen.add(pid)
        try:
            threads = os.listdir(f"/proc/{pid}/task")
        except OSError:   # ended meanwhile
            continue
        count += len(threads) or 1
        for thread in threads:
            try:
                stack += [int(child) for child in Path(f"/proc/{pid}/task/{thread}/children").read_text().split()]
            except (OSError, ValueError):
                continue
    return count


def _cgroup_mounts() -> list[tuple[str, Path]]:
    """``[(kind, mount point)]`` of the pids hierarchies: ``("v1", ...)`` and ``("v2", ...)``."""
    found: list[tuple[str, Path]] = []
    try:
        lines = Path("/proc/self/mountinfo").read_text().splitlines()
    except OSError:
        return found
    for line in lines:
        before, _, after = line.partition(" - ")
        parts, rest = before.split(), after.split()
        if len(parts) < 5 or len(rest) < 3:
            continue
        point, kind, options = Path(parts[4].replace("\\040", " ")), rest[0], rest[2].split(",")
        if kind == "cgroup" and "pids" in options:
            found.append(("v1", point))
        elif kind == "cgroup2":
            found.append(("v2", point))
    return sorted(found, key=lambda item: item[0])   # v1's pids hierarchy first (hybrid machines)


def _own_cgroup(kind: str) -> str:
    for line in Path("/proc/self/cgroup").read_text().splitlines():
        number, controllers, path = line.split(":", 2)
        if (kind == "v1" and "pids" in controllers.split(",")) or (kind == "v2" and number == "0"):
            return path
    return ""


def cgroup_parent() -> tuple[Path | None, str]:
    """The cgroup under which a kernel's cgroup can be made, or ``(None, why not)``."""
    reasons = []
    for kind, mount in _cgroup_mounts():
        try:
            own = _own_cgroup(kind)
        except OSError as error:
            reasons.append(f"/proc/self/cgroup: {error.strerror}")
            continue
        parent = mount / own.lstrip("/")
        if kind == "v2":
            try:
                delegated = (parent / "cgroup.subtree_control").read_text().split()
            except OSError as error:
                reasons.append(f"{parent}: {error.strerror}")
                continue
            if "pids" not in delegated:
                reasons.append(f"cgroup v2 {parent}: the pids controller is not enabled for its children "
                               "(cgroup.subtree_control)")
                continue
        if not os.access(parent, os.W_OK) or _read_only(parent):
            reasons.append(f"{parent} is not writable")
            continue
        return parent, ""
    return None, "; ".join(reasons) or "no pids cgroup is mounted (/proc/self/mountinfo)"


def _read_only(path: Path) -> bool:
    try:
        return bool(os.statvfs(path).f_flag & os.ST_RDONLY)
    except OSError:
        return True


def make_cgroup(parent: Path, limit: int, tag: str) -> Path:
    """A new cgroup under ``parent`` with ``pids.max = limit``."""
    group = parent / f"{PREFIX}{tag}-{os.getpid()}-{next(_NUMBERS)}"
    group.mkdir()
    try:
        (group / "pids.max").write_text(str(limit))
    except OSError:
        group.rmdir()
        raise
    return group


def remove_cgroup(group: Path, timeout: float = 10.0) -> int:
    """Kill every process in ``group``, wait for them to go, remove it; the number killed."""
    killed: set[int] = set()
    deadline = time.monotonic() + timeout
    while True:
        try:
            pids = [int(p) for p in (group / "cgroup.procs").read_text().split()]
        except FileNotFoundError:
            return len(killed)
        for pid in pids:
            try:
                os.kill(pid, signal.SIGKILL)
                killed.add(pid)
            except ProcessLookupError:
                pass
        if not pids:
            try:
                group.rmdir()
                return len(killed)
            except OSError:
                if time.monotonic() > deadline:
                    raise
        elif time.monotonic() > deadline:
            raise ProcessCapUnavailable(f"the processes of {group} did not end after SIGKILL: {pids[:10]}")
        time.sleep(0.05)


def remove_leftovers(tag: str) -> int:
    """Remove the cgroups of the grading ``tag`` still there (their kernel's cleanup did not run);
    the number of processes killed in them."""
    killed = 0
    parent, _ = cgroup_parent()
    if parent is not None:
        for group in parent.glob(f"{PREFIX}{tag}-*"):
            killed += remove_cgroup(group)
    return killed


def _wanted_methods() -> tuple[str, ...]:
    value = os.environ.get(METHOD_VARIABLE, "").strip().lower()
    if not value or value == "auto":
        return METHODS
    if value not in METHODS:
        raise ValueError(f"{METHOD_VARIABLE} must be one of auto, {', '.join(METHODS)}; not {value!r}")
    return (value,)


def plan(limit: int, *, make: bool = False, tag: str = "") -> ProcessCap:
    """How a kernel's processes are capped at ``limit`` here; with ``make``, the cgroup is made.

    Raises :class:`ProcessCapUnavailable`, naming the cause of each way that does not work
    and what to do, when none does.
    """
    if limit <= 0:
        raise ValueError(f"limit must be a positive number of processes, not {limit}")
    tag = tag or os.environ.get(TAG_VARIABLE, "") or "x"
    causes = []
    enter = [sys.executable, "-S", "-c", ENTER]
    for method in _wanted_methods():
        if method == "cgroup":
            parent, why = cgroup_parent()
            if parent is None:
                causes.append(f"no writable pids cgroup ({why})")
                continue
            if not make:
                return ProcessCap("cgroup", limit, description=f"a cgroup under {parent} with pids.max = {limit}")
            try:
                group = make_cgroup(parent, limit, tag)
            except OSError as error:
                causes.append(f"cannot make a cgroup under {parent} ({error.strerror})")
                continue
            return ProcessCap("cgroup", limit, outer=[*enter, "cgroup", str(group / "cgroup.procs"), "--"],
                              cgroup=group, description=f"cgroup {group}, pids.max = {limit}")
        exempt = exempt_from_rlimit()
        if exempt:
            causes.append(f"RLIMIT_NPROC would not hold: {exempt}")
            continue
        shared = tasks_of_user(os.getuid()) + limit
        namespace = os.stat("/proc/self/ns/user").st_ino
        return ProcessCap("rlimit", limit, inner=[*enter, "rlimit", f"{limit}:{shared}:{namespace}", "--"],
                          description=f"RLIMIT_NPROC = {limit} in the sandbox's user namespace ({shared}, the "
                          f"processes and threads of uid {os.getuid()} now plus {limit}, if it has none)")
    raise ProcessCapUnavailable(
        f"cannot cap the processes of a submission's kernel at {limit}: {'; '.join(causes)}. Do one of: "
        "run the grader as an unprivileged user (then RLIMIT_NPROC holds); give it a writable pids cgroup "
        "(root on a machine or VM, a systemd unit with Delegate=yes); or grade in a container with a "
        "process limit of its own (docker run --pids-limit, Kubernetes podPidsLimit) and turn this cap "
        f"off there ({VARIABLE}=0, grade_submission.py --max-processes 0), which is then logged")
