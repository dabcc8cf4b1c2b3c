"""The grading kernel of a submission, inside a bubblewrap sandbox (``nbgrader autograde``).

``BridgedExecute`` (``tools/grading/bridge/execute.py``) starts the kernel that runs a
student's notebook with ``SandboxedKernelManager``, jupyter_client's
``AsyncKernelManager`` whose kernel command is wrapped in ``bwrap``
(Debian/Ubuntu package ``bubblewrap``). The sandbox's file system is built
from nothing (bwrap's root is an empty tmpfs):

- read-only: the system (``/usr``, ``/etc`` and ``/bin``, ``/lib`` ...),
  the Python environment of the grader (the venv and the Python it was made
  from) and the ``robokin`` package folder -- not the repository around it, whose
  notebooks hold the solutions;
- writable: the submission's own folder (nbgrader's ``autograded/<student>/<assignment>``,
  the kernel's working directory), a private tmpfs ``/tmp`` and an empty tmpfs
  ``$HOME``, in which only matplotlib's font list is the grader's, read-only
  (:func:`font_lists`);
- hidden: everything else, among it the course directory (``source/`` with the
  instructor's notebooks, ``release/``, ``submitted/``, other students' folders,
  ``feedback/``, ``gradebook.db``), nbgrader's exchange and the repository. A
  hidden folder that lies inside a readable one, or holds the submission's
  folder, is covered by an empty tmpfs made read-only; so is the sandbox's root.

The kernel has no network (``--unshare-net``: it talks to the grader over ZMQ's
``ipc`` transport, through sockets in a private folder bound into the sandbox),
its own process namespace (``--unshare-pid``: whatever it starts is killed when
the kernel ends), dies with the grader (``--die-with-parent``), has no
controlling terminal (``--new-session``), no capabilities (``--cap-drop ALL``)
and an environment of a few named variables (``--clearenv``: no tokens of the
grader's session). A kernel in a new session does not get the SIGINT that
jupyter_client sends to the process group it started, so an interrupt is an
``interrupt_request`` message (ipykernel then signals itself).

``ROBOKIN_MAX_PROCESSES=N`` (or ``c.SandboxedKernelManager.max_processes = N``) caps the
processes and threads of the kernel and everything it starts at ``N`` (a fork bomb gets
``BlockingIOError`` from ``fork``), by a cgroup's ``pids.max`` or by ``RLIMIT_NPROC``, whichever
works here (``tools/grading/process_cap.py``); when neither does, the kernel does not start and the
error says why. ``tools/grading/grade_submission.py`` sets it. A cell that leaves the kernel at its
cap (a fork bomb's children, which the kernel never reaps, stay counted until it ends) leaves
a kernel that cannot start a thread: ``BridgedExecute`` asks :meth:`SandboxedKernelManager.at_process_cap`
after each cell and restarts such a kernel, as one that died in the cell.

``ROBOKIN_GRADING_SANDBOX=off`` or ``c.BridgedExecute.sandbox = False`` runs the
kernel as nbgrader does, unsandboxed (for an instructor who grades inside a
container of their own).
"""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from collections.abc import Awaitable, Callable
from pathlib import Path

from traitlets import Int, List, Unicode

from tools.grading import process_cap
from tools.kernel_sockets import AsyncPrivateSocketsKernelManager

PACKAGE = "bubblewrap"
SWITCH = "ROBOKIN_GRADING_SANDBOX"
#: Environment variables the sandboxed kernel gets from the grader (the rest are cleared).
KEPT_ENVIRONMENT = ("PATH", "LANG", "LANGUAGE", "LC_ALL", "LC_CTYPE", "LC_NUMERIC", "TZ", "PYTHONPATH",
                    "PYTHONHASHSEED", "PYTHONDONTWRITEBYTECODE", "MPLBACKEND", "OMP_NUM_THREADS",
                    "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "PYDEVD_DISABLE_FILE_VALIDATION")
KEPT_PREFIXES = ("ROBOKIN_",)
SYSTEM = ("/usr", "/etc")
SYSTEM_LINKS = ("/bin", "/sbin", "/lib", "/lib32", "/lib64", "/libx32")


class SandboxUnavailable(RuntimeError):
    """bwrap is not installed (or cannot make a sandbox on this machine)."""


class KernelAtProcessCap(RuntimeError):
    """A cell left the kernel at its cap on processes (the message says how many): it is restarted."""


def sandbox_wanted(configured: bool) -> bool:
    """Whether to sandbox: the configured value, unless ROBOKIN_GRADING_SANDBOX says off/on."""
    value = os.environ.get(SWITCH, "").strip().lower()
    if value in ("off", "0", "false", "no"):
        return False
    if value in ("on", "1", "true", "yes"):
        return True
    if value:
        raise ValueError(f"{SWITCH} must be 'on' or 'off', not {value!r}")
    return configured


_WORKS: dict[str, bool] = {}


def bwrap_executable() -> str:
    """Path of a ``bwrap`` that can make a sandbox here; SandboxUnavailable (saying what to do) if none."""
    path = shutil.which("bwrap")
    if path is None:
        raise SandboxUnavailable(
            "robokin grades every submission in a sandbox (bubblewrap), but `bwrap` is not "
            f"installed: install the Debian/Ubuntu package '{PACKAGE}' (`sudo apt-get install {PACKAGE}`; "
            f"Fedora: `dnf install {PACKAGE}`), or, if you already grade inside a container of your "
            f"own, turn the sandbox off with `export {SWITCH}=off` or `c.BridgedExecute.sandbox = False` "
            "in nbgrader_config.py (book/for-instructors.md, 'What grading guarantees')."
        )
    if path not in _WORKS:   # once per process: can bwrap make a sandbox on this machine?
        probe = subprocess.run([path, "--unshare-all", "--die-with-parent", "--ro-bind", "/", "/", "true"],
                               capture_output=True, text=True, timeout=30)
        if probe.returncode != 0:
            raise SandboxUnavailable(
                f"robokin grades every submission in a sandbox, but `{path}` cannot make one on this "
                f"machine: {(probe.stderr or probe.stdout).strip() or f'exit {probe.returncode}'}. bwrap "
                "needs unprivileged user namespaces (or a setuid bwrap). If this machine is a container "
                f"that grades nothing else, turn the sandbox off: `export {SWITCH}=off` or "
                "`c.BridgedExecute.sandbox = False` (book/for-instructors.md, 'What grading guarantees')."
            )
        _WORKS[path] = True
    return path


def package_folders(names=("robokin",)) -> list[Path]:
    """Folders of the packages the kernel imports from outside the Python environment."""
    out = []
    for name in names:
        spec = importlib.util.find_spec(name)
        for folder in (spec.submodule_search_locations or []) if spec else []:
            out.append(Path(folder).resolve())
    return out


def python_folders() -> list[Path]:
    """The grader's Python: the venv, the installation it was made from, the interpreter's real path."""
    folders = {Path(sys.prefix), Path(sys.base_prefix), Path(sys.exec_prefix), Path(sys.base_exec_prefix),
               Path(os.path.realpath(sys.executable)).parent.parent}
    return sorted({f.resolve() for f in folders} | folders)


def _inside(path: Path, folder: Path) -> bool:
    return path == folder or folder in path.parents


def kernel_environment(home: str) -> dict[str, str]:
    """The variables the sandboxed kernel gets (everything else of the grader's environment is dropped)."""
    env = {k: v for k, v in os.environ.items()
           if k in KEPT_ENVIRONMENT or k.startswith(KEPT_PREFIXES)}
    # JPY_PARENT_PID=1: ipykernel watches no parent (bwrap --die-with-parent does) and
    # prints no note about Ctrl-C to the grader's terminal
    env.update(HOME=home, TMPDIR="/tmp", PYTHONNOUSERSITE="1", JPY_PARENT_PID="1")
    env.setdefault("PATH", "/usr/local/bin:/usr/bin:/bin")
    return env


def font_lists(home: str, readable: set[Path], read_only: set[Path]) -> list[tuple[Path, Path]]:
    """The grader's matplotlib font lists a kernel can use: ``[(grader's list, where the kernel reads it)]``.

    The first ``import matplotlib.font_manager`` in a home without matplotlib's cache looks for
    every font of the system and writes what it found, ``fontlist-v<version>.json``, in its cache
    folder; later imports read it (0.13 against 0.01 CPU-s on the 2-core machine). The kernel's
    home is an empty tmpfs, so every kernel of every submission looked for the fonts again. The
    grader's own lists are bound read-only where the kernel's matplotlib reads them, from the
    folder where the grader's keeps them (``$MPLCONFIGDIR``, else ``$XDG_CACHE_HOME/matplotlib``,
    else ``~/.cache/matplotlib``) into ``home/.cache/matplotlib`` (the kernel has neither
    variable: :func:`kernel_environment`); the kernel reads the one of its version.

    A list is used only when every font it names is in a folder the sandbox reads (``readable``:
    the system's and the readable ones; a name relative to matplotlib's data folder is in the
    Python environment), so that the kernel never picks a font it cannot open. None without
    a home of the kernel's own (``home`` "" or "/"), when the kernel's cache folder would lie
    in one of the ``read_only`` folders (matplotlib wants it writable), or when the grader has
    no list yet: the kernel's matplotlib then makes its own, in the kernel's home, as before.
    """
    if home in ("", "/"):
        return []
    if os.environ.get("MPLCONFIGDIR"):
        cache = Path(os.environ["MPLCONFIGDIR"])
    else:
        cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "matplotlib"
    destination = Path(home) / ".cache" / "matplotlib"
    if any(_inside(destination, folder) for folder in read_only):
        return []
    out = []
    for source in sorted(cache.glob("fontlist-v*.json")):
        try:
            found = json.loads(source.read_text(encoding="utf-8"))
            names = [Path(font["fname"]) for kind in ("ttflist", "afmlist") for font in found[kind]]
        except (OSError, ValueError, KeyError, TypeError):
            continue   # not a list this code can read: the kernel makes its own
        if all(not name.is_absolute() or any(_inside(name, folder) for folder in readable) for name in names):
            out.append((source.resolve(), destination / source.name))
    return out


def sandbox_arguments(*, writable: Path, runtime: Path, hidden: list[Path], readable: list[Path],
                      home: str, bwrap: str) -> list[str]:
    """The ``bwrap ... --`` prefix of the kernel command (paths absolute)."""
    args = [bwrap, "--unshare-all", "--die-with-parent", "--new-session", "--cap-drop", "ALL",
            "--proc", "/proc", "--dev", "/dev", "--tmpfs", "/tmp"]
    if home not in ("", "/", "/tmp"):
        args += ["--tmpfs", home]
    for link in SYSTEM_LINKS:
        if os.path.islink(link):
            args += ["--symlink", os.readlink(link), link]
        elif os.path.isdir(link):
            args += ["--ro-bind", link, link]
    bound = {Path(p) for p in SYSTEM if os.path.isdir(p)} | {p for p in readable if p.exists()}
    # A hidden folder inside a readable one (a course under /opt, say), or around the
    # submission's folder, gets an empty tmpfs, made read-only once the submission's
    # folder is bound in it. Mounts are made parents first, so that a readable folder
    # inside a hidden one is bound again.
    covered = {p for p in hidden if any(_inside(p, b) and p != b for b in bound) or _inside(writable, p)}
    mounts = [(p, "--ro-bind") for p in bound]
    mounts += [(p, "--tmpfs") for p in covered]
    mounts += [(writable, "--bind"), (runtime, "--bind")]
    for folder, kind in sorted(mounts, key=lambda m: (len(m[0].parts), m[1] != "--tmpfs", str(m[0]))):
        args += [kind, str(folder)] if kind == "--tmpfs" else [kind, str(folder), str(folder)]
    for source, destination in font_lists(home, readable=bound, read_only=bound | covered):
        args += ["--ro-bind", str(source), str(destination)]
    for folder in sorted(covered, key=lambda p: len(p.parts)):
        args += ["--remount-ro", str(folder)]
    # the sandbox's own root (the folders made to hold the mounts) read-only too
    args += ["--remount-ro", "/", "--chdir", str(writable), "--clearenv"]
    for key, value in sorted(kernel_environment(home).items()):
        args += ["--setenv", key, value]
    return args + ["--"]


class SandboxedKernelManager(AsyncPrivateSocketsKernelManager):
    """An ``AsyncKernelManager`` whose kernel runs in bwrap and talks over ipc sockets.

    The sockets and the connection file are in a private folder
    (:class:`tools.kernel_sockets.AsyncPrivateSocketsKernelManager`), bound into the sandbox.
    """

    writable = Unicode(help="the only folder the kernel can write (and read, of the course)").tag(config=True)
    hidden = List(Unicode(), help="folders the kernel must not see (course, exchange, repository)"
                  ).tag(config=True)
    readable = List(Unicode(), help="extra read-only folders (besides the system and Python)").tag(config=True)
    max_processes = Int(0, help="processes and threads the kernel may have, its children's included "
                        f"(0: no cap); {process_cap.VARIABLE} overrides it").tag(config=True)
    _process_cap: process_cap.ProcessCap | None = None

    async def _async_pre_start_kernel(self, **kw):
        if not self.writable:
            raise ValueError("SandboxedKernelManager.writable: the submission folder is not set")
        self._bwrap = bwrap_executable()
        kw["cwd"] = self.writable
        return await super()._async_pre_start_kernel(**kw)   # makes the private socket folder

    pre_start_kernel = _async_pre_start_kernel

    def format_kernel_cmd(self, extra_arguments=None):
        cmd = super().format_kernel_cmd(extra_arguments)
        home = os.environ.get("HOME", "/home/grader") or "/home/grader"
        readable = [*python_folders(), *package_folders(), *(Path(p) for p in self.readable)]
        if self.socket_folder is None:   # _async_pre_start_kernel makes it where ipc sockets exist
            raise RuntimeError("SandboxedKernelManager: the kernel has no private socket folder to bind "
                               "(the sandbox needs ipc sockets, a POSIX system)")
        prefix = sandbox_arguments(writable=Path(self.writable).resolve(), runtime=self.socket_folder,
                                   hidden=[Path(p).resolve() for p in self.hidden], readable=readable,
                                   home=home, bwrap=self._bwrap)
        limit = process_cap.requested() if os.environ.get(process_cap.VARIABLE, "").strip() else self.max_processes
        if limit:
            self._release_process_cap()   # a restart: the last kernel's
            self._process_cap = process_cap.plan(limit, make=True)
            self.log.info("The kernel's processes are capped: %s", self._process_cap.description)
            prefix = self._process_cap.outer + prefix + self._process_cap.inner
        return prefix + cmd

    def at_process_cap(self) -> str:
        """Why the kernel is at its cap on processes, so that it cannot start a thread ('' when it is
        not, or has no cap); asked after each cell."""
        pid = getattr(self.provisioner, "pid", None) if self.has_kernel else None
        if self._process_cap is None or not pid:
            return ""
        return self._process_cap.full(pid)

    def _release_process_cap(self) -> None:
        if self._process_cap is not None:
            killed = self._process_cap.release()
            if killed:
                self.log.warning("%d processes of the kernel were left; killed", killed)
            self._process_cap = None

    async def _async_cleanup_resources(self, restart: bool = False) -> None:
        await super()._async_cleanup_resources(restart=restart)
        self._release_process_cap()

    cleanup_resources = _async_cleanup_resources

    async def _async_interrupt_kernel(self) -> None:
        # The kernel is in a session of its own (bwrap --new-session): a signal to the
        # process group jupyter_client started reaches bwrap, not the kernel. Ask the kernel.
        if not self.has_kernel:
            raise RuntimeError("Cannot interrupt kernel. No kernel is running!")
        msg = self.session.msg("interrupt_request", content={})
        self._connect_control_socket()
        self.session.send(self._control_socket, msg)

    # a coroutine in the async manager where KernelManager has a plain method, as jupyter_client's
    # AsyncKernelManager declares it (with the same ignore)
    interrupt_kernel: Callable[..., Awaitable[None]] = _async_interrupt_kernel  # type: ignore[assignment]
