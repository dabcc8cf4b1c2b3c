"""How the suite uses both cores: pytest-xdist workers, groups, longest parts first.

``tests/conftest.py`` imports the hooks below (its fixture ``suite_run_id`` reads
``config.robokin_run_id``, the same in every worker of a run). What they do:

* **Two workers by default.** ``pytest`` (and ``make test``) runs on two worker
  processes with ``--dist loadgroup``, as if ``-n 2 --dist loadgroup`` had been
  given. ``-n 0`` (or ``-p no:xdist``) runs everything in one process, ``-n 4``
  on four workers. This is set here, not in ``addopts``: ``-p no:xdist`` would
  reject an ``-n`` in ``addopts``, and ``pytest notebooks/NB.ipynb`` (which does not
  load this conftest, so its cells would not be grouped) runs in one process. A
  pytest started by a test (a scaffolded chapter's suite, the notebooks under other
  BLAS kernels) runs in one process too: the outer run already uses the cores.
* **Markers** ``notebooks``, ``nbgrader``, ``book`` and ``browser`` are added from what a
  test uses (the fast loop, ``make quick``, deselects them), and ``exhaustive`` by the rules
  of ``tests/support/tiers.py`` (``make test`` deselects it, ``make test-all`` keeps it).
* **Groups** (``xdist_group``; one group runs in one worker, in collection order):
  the cells of one notebook under nbval (``nbval:<stem>``: its kernel lives in the
  worker, cell after cell), and the tests of a module with module- or class-scoped
  fixtures (``module:<path>``: the fixture is built once, not once per worker), and the
  tests that mostly wait (``waiting``: :data:`WAITING_TESTS`, one wait at a time). A
  test that already has an ``xdist_group`` mark keeps it.
* **Most CPU first.** A work unit is a group or a single test. Units that cost (or
  are expected to cost) a CPU-second or more run first, the costliest first, so that the
  workers finish together; shorter tests keep their order and follow. The suite is
  CPU-bound (its CPU-seconds are about 1.8 times its wall seconds on two cores), so
  the order is by CPU, not by wall time: by wall, the graded courses (minutes of wall,
  half of it waiting for their time limits) all ran first, four at a time, and the
  cores were a fifth idle; by CPU, the units that compute (mypy, the book builds, the
  other machines) run beside them. A unit's CPU-seconds come from the last run that
  counted them (``ROBOKIN_CPU_REPORT``, tests/support/cpu_accounting.py; pytest's cache,
  ``.pytest_cache``, key ``robokin/unit-cpu-seconds``), else from :data:`ESTIMATES` (a
  fresh clone), else the unit's wall seconds in the last run stand in (key
  ``robokin/unit-durations``).
* **A fresh checkout is collected by one worker first.** Every worker imports every test
  module; without bytecode caches (``__pycache__``: a fresh clone) each one compiles and
  rewrites the asserts of all of them at the same time. There the first worker collects
  alone, the others after it, from the caches it wrote (:func:`pytest_collection`).
"""

from __future__ import annotations

import fcntl
import os
import re
import sys
import uuid
from collections import defaultdict
from pathlib import Path

import pytest

from support import tiers

try:
    from _pytest.nodeid import NodeId, coerce_node_id
except ImportError:  # pytest < 9.2 keeps the node id in item._nodeid
    NodeId = coerce_node_id = None  # type: ignore[assignment,misc]  # the names exist from pytest 9.2 on

#: Workers when ``-n`` is not given. Measured on the 2-core machine the timings in
#: the README come from; ``-n auto`` uses one per core.
DEFAULT_WORKERS = 2
#: Set in the environment of a run; a pytest started by one of its tests sees it.
NESTED = "ROBOKIN_TESTS_RUNNING"
#: pytest's cache: each unit's wall seconds in the last run, and its CPU-seconds in the last run
#: that counted them (``ROBOKIN_CPU_REPORT``)
CACHE_KEY = "robokin/unit-durations"
CPU_CACHE_KEY = "robokin/unit-cpu-seconds"
#: Units cheaper than this (CPU-seconds) keep their collection order, after the long ones.
LONG = 1.0
#: Expected CPU-seconds of the long units, for a run that has not counted them (a fresh clone,
#: as CI's); a unit is a group name or a test's node id. First matching pattern wins. Measured
#: in fresh clones' ``make test-all`` (tests/support/cpu_accounting.py, every child process
#: counted): the medians of three runs of eb79d83 (2026-11-29, one quiet, two with a core kept
#: busy; benchmarks/README.md, "The grading mutations' kernels forked, and the suite's order by
#: CPU"). ``make test`` runs fewer submissions in the everyday chapter's course (about 21 CPU-s,
#: not 97): it still comes first.
ESTIMATES = [
    (r"test_notebooks_other_machines\.py", 33.0),   # each of the three machines
    # the scaffolded chapters' own suite in one process: about 200 s of wall for 52 CPU-s (its graded
    # runs wait for their hangs' time limits), so it starts early, beside the work of others
    (r"^module:tests/test_new_chapter\.py$", 52.0),
    (r"test_book\.py::test_book_builds", 26.0),   # each edition, every page read (--all)
    (r"^module:tests/test_grading_mutations\.py$", 45.0),   # the ten chapters, one forked kernel each
    (r"^module:tests/test_grading_fork_server\.py$", 6.0),
    (r"test_live_jupyter\.py", 17.0),
    (r"test_untrusted_urdf\.py::test_deep_child_first_chain", 5.0),
    (r"^module:tests/test_meshes_stored\.py$", 5.0),
    (r"test_meshes_stored\.py::test_stored_meshes_equal_a_computation_with_another", 4.0),
    (r"^nbval:05_", 12.0),
    (r"^nbval:0[12]_", 7.0),
    (r"^nbval:", 3.0),
    (r"test_reexecution\.py", 5.0),
    (r"test_lint\.py::test_mypy", 37.0),   # no .mypy_cache in a fresh clone: robokin, tools and the tests
    (r"test_kernel_sockets\.py::test_a_cell_that_logs_twelve_thousand_lines", 11.0),
    (r"test_book\.py::test_page_in_browser\[\w+-notebooks/", 5.0),   # a chapter's page: its scenes
    (r"test_book\.py::test_page_in_browser", 1.2),
    (r"test_views_(browser|mesh)\.py", 1.0),
]
#: The xdist groups of the graded courses: "nbgrader:<job>", one per job (tests/support/grading_course.py).
NBGRADER_GROUPS = r"^nbgrader($|[:_-])"
#: Expected CPU-seconds of each job's group, measured as :data:`ESTIMATES`: a chapter's run (its
#: submissions and the trust suite's) 32-45, chapter 2's 88 and chapter 5's 56 (their notebooks cost
#: most per execution), the walk-through 17 (and 75 s of wall: its endless cell's 30 s time limit);
#: the everyday chapter's (chapter 7) with the other engines' re-gradings
#: (tests/test_grading_engines.py) 97 and the tamper suite's own course 50.
NBGRADER_ESTIMATES = [
    (rf"^nbgrader:{tiers.EVERYDAY_CHAPTER}\+tamper$", 50.0),
    (rf"^nbgrader:{tiers.EVERYDAY_CHAPTER}$", 97.0),
    (r"^nbgrader:walkthrough$", 17.0),
    (r"^nbgrader:02_ur10_ik$", 88.0),
    (r"^nbgrader:05_baxter_circle$", 56.0),
    (r"^nbgrader:unmarked$", 1.0),   # a chapter without metadata: no autograde
    (NBGRADER_GROUPS, 40.0),
]
ESTIMATES += NBGRADER_ESTIMATES

#: Tests that mostly wait (a time limit reached on purpose, a process slow to start, a call that
#: never returns): 10-14 s of wall for 0.1-1.0 CPU-s each. Each test on its own, two of them ran
#: at the same time on two of the three workers (the two of test_nbgrader_runner.py, neighbours in
#: collection order, in fresh clones and warm checkouts alike) and left a core idle for 10 s. In one
#: group they wait one after the other on one worker, beside the long computations (about 3
#: CPU-s and 40 s of wall: among the long units, never in the last minutes of a run).
WAITING_TESTS = (
    r"^tests/test_nbgrader_runner\.py::test_a_runner_slow_to_start_takes_none_of_the_commands_time_limit$",
    r"^tests/test_nbgrader_runner\.py::test_a_command_past_its_time_limit_is_killed_and_the_next_one_runs$",
    r"^tests/test_grading_tamper\.py::test_call_channel_calls_calls_back_and_stops_a_call_that_never_returns$",
)
WAITING_GROUP = "waiting"
ESTIMATES.insert(0, (rf"^{WAITING_GROUP}$", 3.0))


def is_nbgrader_group(name: str) -> bool:
    """Whether an xdist group holds nbgrader courses (the group "nbgrader" or a part of it)."""
    return re.match(NBGRADER_GROUPS, name) is not None


def _xdist_active(config) -> bool:
    return config.pluginmanager.hasplugin("xdist")


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config):
    """``-n 2 --dist loadgroup --no-loadscope-reorder`` unless the command line says otherwise."""
    if hasattr(config, "workerinput"):
        # a worker parses the command line again, without what was set here: the
        # controller passes its --dist on (pytest_configure_node below)
        config.option.loadgroup = config.workerinput.get("robokin_dist") == "loadgroup"
        return
    if not _xdist_active(config) or os.environ.get(NESTED):
        return
    option = config.option
    if option.usepdb or option.collectonly:
        return
    if option.numprocesses is None and not option.tx:
        option.numprocesses = DEFAULT_WORKERS
    if option.dist == "no":
        option.dist = "loadgroup"
    option.loadscopereorder = False   # our order: longest first (below)


def _bytecode_cached(root: Path) -> bool:
    """Whether pytest has cached a rewritten test module in ``root/tests`` (False in a fresh clone)."""
    return any((root / "tests" / "__pycache__").glob("test_*-pytest-*.pyc"))


@pytest.hookimpl(hookwrapper=True)
def pytest_collection(session):
    """(in an xdist worker) in a checkout without bytecode caches, collect after the first worker.

    The worker that takes the lock first decides for all: where its caches are missing, it
    collects while it holds the lock and writes them (compiled and assert-rewritten modules);
    the others wait for it, then collect at once from those caches (in a fresh clone 9.8 CPU-s
    for the first and 5.2 for each other, instead of 9.8 each: benchmarks/README.md, "The
    suite's start, end and book builds"). Where the caches exist, nobody waits for a
    collection; where they cannot be written (``PYTHONDONTWRITEBYTECODE``), nothing is locked.
    """
    config = session.config
    cache = getattr(config, "cache", None)
    if not hasattr(config, "workerinput") or cache is None or sys.dont_write_bytecode:
        yield
        return
    folder = cache.mkdir("robokin")
    decided = folder / "collection-decided-by-run"
    with open(folder / "collection.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            first = not (decided.is_file() and decided.read_text() == config.robokin_run_id)
            if not first or _bytecode_cached(config.rootpath):
                decided.write_text(config.robokin_run_id)
                fcntl.flock(lock, fcntl.LOCK_UN)   # collect beside the others
                yield
                return
            yield
            decided.write_text(config.robokin_run_id)
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


@pytest.hookimpl(optionalhook=True)
def pytest_configure_node(node):
    """(pytest-xdist, in the controller) tell a new worker how tests are distributed."""
    node.workerinput["robokin_dist"] = node.config.option.dist


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    """(pytest-xdist, in the controller) keep the processes a worker's tests left running;
    ``pytest_sessionfinish`` in conftest.py reports them and fails the run."""
    survivors = getattr(node, "workeroutput", {}).get("robokin_survivors", [])
    node.config.robokin_worker_survivors = [*getattr(node.config, "robokin_worker_survivors", []),
                                            *(f"{survivor} (in {node.gateway.id})" for survivor in survivors)]


def pytest_configure(config):
    if hasattr(config, "workerinput"):
        config.robokin_run_id = config.workerinput["testrunuid"]
        return
    config.robokin_run_id = uuid.uuid4().hex
    os.environ[NESTED] = config.robokin_run_id
    config.pluginmanager.register(DurationRecorder(config), "robokin-duration-recorder")


def _group_names(item) -> list[str]:
    names = set()
    for mark in item.iter_markers("xdist_group"):
        names.add(str(mark.args[0] if mark.args else mark.kwargs.get("name", "default")))
    return sorted(names)


def _is_nbval_cell(item) -> bool:
    return type(item).__module__.split(".")[0] == "nbval"


def _has_module_fixture(item) -> bool:
    info = getattr(item, "_fixtureinfo", None)
    if info is None:
        return False
    return any(defs and defs[-1].scope in ("module", "class", "package")
               for defs in info.name2fixturedefs.values())


#: Test modules that execute notebooks (``notebooks``) or run nbgrader (``nbgrader``).
NOTEBOOK_MODULES = ("test_grading_mutations.py", "test_reexecution.py", "test_new_chapter.py")
NBGRADER_MODULES = ("test_nbgrader.py", "test_grading_trust.py", "test_grading_tamper.py")


def _assign_markers(item) -> None:
    """The markers ``make quick`` deselects, from what a test uses (see CONTRIBUTING.md)."""
    names = set(getattr(item, "fixturenames", ()))
    if _is_nbval_cell(item) or item.path.name in NOTEBOOK_MODULES:
        item.add_marker(pytest.mark.notebooks)
    if item.path.name in NBGRADER_MODULES or any(is_nbgrader_group(name) for name in _group_names(item)):
        item.add_marker(pytest.mark.nbgrader)
    if names & {"built_book", "built_student_book", "edition_book"}:
        item.add_marker(pytest.mark.book)
    if "browser" in names:
        item.add_marker(pytest.mark.browser)
    tiers.mark(item)


def _assign_groups(items) -> None:
    for item in items:
        _assign_markers(item)
        if _group_names(item):
            continue
        if _is_nbval_cell(item):
            item.add_marker(pytest.mark.xdist_group(f"nbval:{item.path.stem}"))
        elif any(re.search(pattern, item.nodeid) for pattern in WAITING_TESTS):
            item.add_marker(pytest.mark.xdist_group(WAITING_GROUP))
        elif _has_module_fixture(item):
            module = item.nodeid.split("::", 1)[0]
            item.add_marker(pytest.mark.xdist_group(f"module:{module}"))


def unit_of(item) -> str:
    """The work unit of a test: its group (as xdist names it), or its node id."""
    names = _group_names(item)
    return "_".join(names) if names else item.nodeid


def estimates(units) -> dict[str, float]:
    """Expected CPU-seconds of each unit of ``units`` (0: unknown, presumably short)."""
    units = list(units)
    out = {}
    for unit in units:
        for pattern, seconds in ESTIMATES:
            if re.search(pattern, unit):
                out[unit] = seconds
                break
        else:
            out[unit] = 0.0
    return out


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(session, config, items):
    """Group what must share a worker, then put the long units first, the costliest first."""
    _assign_groups(items)
    cache = getattr(config, "cache", None)
    counted = cache.get(CPU_CACHE_KEY, {}) if cache is not None else {}
    recorded = cache.get(CACHE_KEY, {}) if cache is not None else {}
    units: dict[str, list] = {}
    for item in items:
        units.setdefault(unit_of(item), []).append(item)
    config.robokin_units = {item.nodeid: unit for unit, members in units.items() for item in members}

    expected = estimates(units)

    def cost(unit: str) -> float:
        """CPU-seconds: counted in an earlier run, else estimated, else the last run's wall seconds."""
        if unit in counted:
            return float(counted[unit])
        if expected[unit] or unit not in recorded:
            return expected[unit]
        return float(recorded[unit])

    long_units = sorted((u for u in units if cost(u) >= LONG), key=cost, reverse=True)
    short_units = [u for u in units if cost(u) < LONG]
    items[:] = [item for unit in long_units + short_units for item in units[unit]]
    if getattr(config.option, "loadgroup", False):
        for item in items:
            if _group_names(item):
                _name_group_in_node_id(item, unit_of(item))


def _name_group_in_node_id(item, group: str) -> None:
    """``<node id>@<group>``: how an xdist worker tells the controller a test's group.

    pytest-xdist 3.8 does this itself by setting ``item._nodeid``, which pytest 9.2
    no longer reads (the node id is ``item._id``, a ``NodeId``): without this, every
    test of a group would be scheduled on its own and a notebook's cells would be
    spread over both workers.
    """
    nodeid = f"{item.nodeid}@{group}"
    if isinstance(getattr(item, "_id", None), NodeId):
        item._id = coerce_node_id(nodeid)
    else:
        item._nodeid = nodeid
    assert item.nodeid == nodeid, f"could not add the xdist group to the node id of {item.nodeid}"


class DurationRecorder:
    """Adds up the wall seconds of each work unit in this run, and its CPU-seconds where the run
    counts them (tests/support/cpu_accounting.py); stores them in pytest's cache."""

    def __init__(self, config):
        from support import cpu_accounting   # the plugin conftest.py names, imported by pytest by now

        self.config = config
        self.cpu_property = cpu_accounting.PROPERTY
        self.seconds: dict[str, float] = defaultdict(float)
        self.cpu_seconds: dict[str, float] = defaultdict(float)

    def _unit(self, nodeid: str) -> str:
        known = getattr(self.config, "robokin_units", {})
        if nodeid in known:                       # one process: collected here
            return known[nodeid]
        if nodeid.rfind("@") > nodeid.rfind("]"):  # from an xdist worker: node id @ group
            return nodeid.rsplit("@", 1)[1]
        return nodeid

    def pytest_runtest_logreport(self, report):
        unit = self._unit(report.nodeid)
        self.seconds[unit] += report.duration
        for key, value in report.user_properties:
            if key == self.cpu_property:
                self.cpu_seconds[unit] += value

    def pytest_sessionfinish(self, session):
        if getattr(self.config, "cache", None) is None:
            return
        for key, values in ((CACHE_KEY, self.seconds), (CPU_CACHE_KEY, self.cpu_seconds)):
            if values:
                stored = self.config.cache.get(key, {})
                stored.update({unit: round(value, 2) for unit, value in values.items()})
                self.config.cache.set(key, stored)
