"""The stored notebook outputs do not depend on the machine that computed them.

nbval (in the main run) compares every stored output with a fresh run on *this*
machine. A student's laptop rounds differently: OpenBLAS picks a kernel for its
CPU (``OPENBLAS_CORETYPE``) and splits work over its cores
(``OPENBLAS_NUM_THREADS``), and a last-bit difference grows wherever a
computation is ill-conditioned. These tests re-run the whole notebook suite under
nbval as three other machines, one test each:

1. another OpenBLAS kernel, one thread;
2. a third OpenBLAS kernel, two threads;
3. the default kernel and OpenBLAS's default threads (one per core), with every
   ``numpy.linalg`` result perturbed by a relative 1e-14 (``tests/support/numerical_noise.py``),
   about a hundred times what real machines differ by.

(The suite itself, nbval's run on this machine among it, computes with one thread: conftest.py.)

A notebook passes only if every printed digit survives all three. When one does
not, print less (fewer digits, a bound, a verdict): see ``robokin.formatting``.

Every cell whose output nbval compares runs in each machine's kernel, after every cell
it could read from. On the two machines with another OpenBLAS kernel, the pictures and
scenes that nbval does not compare (tagged ``nbval-ignore-output``), that bind no name a
later cell reads and that check nothing themselves are skipped (``tests/support/picture_cells.py``
has the rule): running them computed their curves again (about a fifth of such a machine's
run) for no output anyone compares. The perturbed machine runs every cell: its noise is one
seeded sequence through the whole notebook, so a cell left out would hand every later cell
other perturbations (another machine, not the same one with fewer cells). The figures that
run are not rendered to a PNG there: nbval does not compare images (``image/png`` is in its
``skip_compare``), so rasterising them checked nothing and cost about 8 of each machine's
50 CPU-s. The main nbval run executes every cell and renders every figure on this machine.

Skip it locally with ``pytest -m "not other_machines"``; after editing one notebook, run it on
that one: ``pytest tests/test_notebooks_other_machines.py --other-machines-notebook
notebooks/NN_name.ipynb``.
"""

from __future__ import annotations

import ctypes
import glob
import json
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT
from support.picture_cells import skipped_cells

pytestmark = pytest.mark.other_machines

#: OpenBLAS kernels that run on any CPU of the architecture, most common first,
#: each with the CPU feature it needs (None: baseline).
KERNELS = {
    "x86_64": [("Haswell", "avx2"), ("Sandybridge", "avx"), ("Prescott", None)],
    "aarch64": [("NEOVERSEN1", "asimd"), ("ARMV8", None), ("CORTEXA53", None)],
}
TIMEOUT = 900  # seconds for one configuration: the notebooks take ~60 s; a hang, not load, reaches it


def default_kernel() -> str | None:
    """Name of the OpenBLAS kernel NumPy's bundled OpenBLAS chose for this CPU, if it says."""
    libs = glob.glob(os.path.join(os.path.dirname(np.__file__) + ".libs", "*openblas*"))
    for path in libs:
        library = ctypes.CDLL(path)
        for symbol in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename", "openblas_get_corename"):
            function = getattr(library, symbol, None)
            if function is not None:
                function.restype = ctypes.c_char_p
                return function().decode()
    return None


def cpu_flags() -> set[str]:
    try:
        text = Path("/proc/cpuinfo").read_text()
    except OSError:
        return set()
    flags = set()
    for line in text.splitlines():
        if line.startswith(("flags", "Features")):
            flags.update(line.split(":", 1)[1].split())
    return flags


def other_kernels(count: int = 2) -> list[str]:
    """``count`` OpenBLAS kernels this CPU can run that differ from the default one."""
    candidates = KERNELS.get(platform.machine())
    if candidates is None:
        pytest.skip(f"no OpenBLAS kernel list for the architecture {platform.machine()!r}")
    default = (default_kernel() or "").lower()
    flags = cpu_flags()
    usable = [name for name, needs in candidates if name.lower() != default and (needs is None or needs in flags)]
    if len(usable) < count:
        pytest.skip(f"fewer than {count} other OpenBLAS kernels usable here (default {default!r})")
    return usable[:count]


#: The module that perturbs ``numpy.linalg`` (loaded by path in each kernel: the kernel's path has no tests/).
NOISE_MODULE = ROOT / "tests" / "support" / "numerical_noise.py"


#: A kernel's start-up file: figures are shown as their text alone, not rendered to an image (the
#: module docstring says why): the inline backend's formats emptied, before any cell draws one.
NO_FIGURE_IMAGES = """\
get_ipython().run_line_magic("config", "InlineBackend.figure_formats = set()")
"""

#: A kernel's start-up file, run after ``NO_FIGURE_IMAGES``: it writes, as one JSON line in REPORT, the
#: OpenBLAS kernel and thread count numpy computes with in this kernel, whether the kernel was forked (its
#: parent is the fork server) and the image formats a figure is still rendered to (none).
KERNEL_REPORT = """\
def _report(path):
    import ctypes, glob, json, os, numpy
    from matplotlib.figure import Figure
    found = {"figure_images": sorted(mime for mime, formatter in get_ipython().display_formatter.formatters.items()
                                     if Figure in formatter.type_printers)}
    for library in glob.glob(os.path.join(os.path.dirname(numpy.__file__) + ".libs", "*openblas*")):
        library = ctypes.CDLL(library)
        for key, symbols in (("core", ("scipy_openblas_get_corename64_", "openblas_get_corename")),
                             ("threads", ("scipy_openblas_get_num_threads64_", "openblas_get_num_threads"))):
            function = next((getattr(library, s) for s in symbols if hasattr(library, s)), None)
            if function is not None and key not in found:
                function.restype = ctypes.c_char_p if key == "core" else ctypes.c_int
                value = function()
                found[key] = value.decode() if key == "core" else value
    with open(f"/proc/{os.getppid()}/cmdline", "rb") as parent:
        found["forked"] = b"fork_server" in parent.read()
    with open(path, "a") as report:
        report.write(json.dumps(found) + "\\n")
_report(REPORT)
del _report
"""


def startup_dir(tmp_path: Path, noise: bool) -> Path:
    """An IPYTHONDIR whose start-up files turn off the figures' images, report each kernel's OpenBLAS
    (``kernels.jsonl`` in ``tmp_path``) and, if ``noise``, install the linear-algebra noise (in that order)."""
    startup = tmp_path / "ipython" / "profile_default" / "startup"
    startup.mkdir(parents=True)
    (startup / "00-no-figure-images.py").write_text(NO_FIGURE_IMAGES)
    (startup / "01-kernel-report.py").write_text(
        KERNEL_REPORT.replace("REPORT", repr(str(tmp_path / "kernels.jsonl"))))
    if noise:
        (startup / "02-numerical-noise.py").write_text(
            "import importlib.util as _util\n"
            f"_spec = _util.spec_from_file_location('numerical_noise', {str(NOISE_MODULE)!r})\n"
            "numerical_noise = _util.module_from_spec(_spec)\n_spec.loader.exec_module(numerical_noise)\n"
            "numerical_noise.install()\ndel _util, _spec\n"
        )
    return startup.parent.parent


#: The three other machines, each its own test (a work unit of its own under xdist: the three
#: run at once only when workers are free, instead of three processes on one worker).
MACHINES = ("another OpenBLAS kernel, 1 thread", "a third OpenBLAS kernel, 2 threads",
            "numpy.linalg results perturbed by 1e-14")


def machine_environment(machine: str, tmp_path: Path) -> dict[str, str]:
    """The variables that make this machine compute as ``machine`` (one of ``MACHINES``)."""
    ipython = {"IPYTHONDIR": str(startup_dir(tmp_path, noise=machine == MACHINES[2]))}
    if machine == MACHINES[2]:   # OpenBLAS's default, a thread per core (the suite's is one: conftest.py)
        return {"OPENBLAS_NUM_THREADS": str(len(os.sched_getaffinity(0))), **ipython}
    first, second = other_kernels()
    if machine == MACHINES[0]:
        return {"OPENBLAS_CORETYPE": first, "OPENBLAS_NUM_THREADS": "1", **ipython}
    return {"OPENBLAS_CORETYPE": second, "OPENBLAS_NUM_THREADS": "2", **ipython}


@pytest.mark.parametrize("machine", MACHINES)
def test_notebook_outputs_hold_on_other_machines(tmp_path, machine, request):
    extra = machine_environment(machine, tmp_path)
    chosen = request.config.getoption("--other-machines-notebook")   # after editing one notebook
    notebooks = sorted(ROOT / path for path in chosen) or sorted((ROOT / "notebooks").glob("*.ipynb"))
    command = [sys.executable, "-m", "pytest", *map(str, notebooks), "-q", "-p", "no:cacheprovider",
               "--color=no"]
    skips_pictures = machine != MACHINES[2]   # the noise's sequence must stay the whole notebook's
    if skips_pictures:
        command += ["-p", "tests.support.picture_cells"]
    env = {**os.environ, **extra, "PYDEVD_DISABLE_FILE_VALIDATION": "1"}
    started = time.perf_counter()
    with open(tmp_path / "run.log", "w+") as log:
        process = subprocess.Popen(command, cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT)
        code: int | str
        try:
            code = process.wait(timeout=TIMEOUT)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
            code = "timeout"
        log.seek(0)
        output = log.read()
    described = ", ".join(f"{k}={v}" for k, v in extra.items() if k != "IPYTHONDIR") or machine
    summary = [line for line in output.splitlines() if line.startswith(("FAILED", "ERROR"))]
    assert code == 0, (
        f"stored notebook outputs change on another machine ({described}: exit {code}); print only the "
        "digits the computation supports (robokin.formatting) or a bound:\n"
        + "\n".join(summary) + "\n" + output[-4000:])
    kernels = [json.loads(line) for line in (tmp_path / "kernels.jsonl").read_text().splitlines()]
    assert kernels, "no kernel ran the start-up file that reports its OpenBLAS"
    assert all(k["figure_images"] == [] for k in kernels), kernels   # every cell ran; no figure rasterised
    # the settings reached every kernel, forked from a warm server or not
    if "OPENBLAS_CORETYPE" in extra:
        assert {k.get("core", "").lower() for k in kernels} == {extra["OPENBLAS_CORETYPE"].lower()}, kernels
    assert {k.get("threads") for k in kernels} == {int(extra["OPENBLAS_NUM_THREADS"])}, kernels
    # the pictures the plugin skips, and nothing else: every other cell ran
    pictures = sum(len(skipped_cells(json.loads(path.read_text())["cells"]))
                   for path in notebooks) if skips_pictures else 0
    last_line = output.strip().splitlines()[-1]
    skipped = re.search(r"(\d+) skipped", last_line)
    assert (int(skipped.group(1)) if skipped else 0) == pictures, last_line
    forked = sum(k["forked"] for k in kernels)
    print(f"[other machines] {described}: {last_line} "
          f"({time.perf_counter() - started:.0f} s; {len(kernels)} kernels, {forked} forked)")
