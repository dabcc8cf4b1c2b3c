"""What each test costs in CPU-seconds, its children's included: ``ROBOKIN_CPU_REPORT=FILE make test-all``.

``/usr/bin/time`` and ``resource.getrusage(RUSAGE_CHILDREN)`` count a child's CPU
only when its parent waited for it: the kernels jupyter_client starts in bubblewrap,
the grader kernels the fork server forks and the nbgrader commands the runner forks
are waited for by processes that are killed, not waited for, at the end of a run, so
those counts miss about two thirds of a grading run's work (an autograde of chapter
5's solution: 9.2 CPU-s by ``time``, 27 CPU-s in fact). A control group counts every
process in it, however it ends.

With ``ROBOKIN_CPU_REPORT`` set to a file name, each pytest process (the controller
without xdist, else every worker) moves itself into a ``cpuacct`` control group of
its own (cgroup v1 ``cpuacct.usage`` or v2 ``cpu.stat``; the processes it starts
inherit it) and reads the group's counter around each test's set-up, call and
teardown. The controller adds the phases up per work unit (tests/support/parallel_plan.py),
per test file and per chapter, prints the largest in the terminal summary and writes
them all to the file as JSON, with a timeline (when each unit ran, on which worker: the
idle stretches of a run show there). Where no control group can be made (no permission),
the summary says so and nothing else changes. The tests run as they would without it.
"""

from __future__ import annotations

import json
import os
import re
from collections import defaultdict
from pathlib import Path

import pytest

VARIABLE = "ROBOKIN_CPU_REPORT"
#: set by the run's controller (its pid): the processes started below it know they are counted
COUNTING = "ROBOKIN_CPU_COUNTING"
PROPERTY = "cpu_seconds"
V1_ROOT = Path("/sys/fs/cgroup/cpuacct")
V2_ROOT = Path("/sys/fs/cgroup")
CHAPTER = re.compile(r"\d\d_[a-z0-9_]+")


class Counter:
    """The CPU-seconds used so far by the processes of a control group made for this process."""

    def __init__(self, name: str) -> None:
        self.path: Path | None = None
        self.version = 0
        for version, root, counter in ((1, V1_ROOT, "cpuacct.usage"), (2, V2_ROOT, "cpu.stat")):
            if not (root / counter).exists() and not (version == 2 and (root / "cgroup.controllers").exists()):
                continue
            group = root / name
            try:
                group.mkdir(exist_ok=True)
                (group / "cgroup.procs").write_text(str(os.getpid()))
            except OSError:
                continue
            self.path, self.version = group, version
            return

    @property
    def available(self) -> bool:
        return self.path is not None

    def seconds(self) -> float:
        """CPU-seconds (user + system) of every process that was or is in the group."""
        assert self.path is not None
        if self.version == 1:
            return int((self.path / "cpuacct.usage").read_text()) / 1e9
        for line in (self.path / "cpu.stat").read_text().splitlines():
            key, value = line.split()
            if key == "usage_usec":
                return int(value) / 1e6
        raise RuntimeError(f"{self.path}/cpu.stat has no usage_usec")


def wanted() -> str | None:
    return os.environ.get(VARIABLE) or None


def pytest_configure(config) -> None:
    """Set up the counting in this process (a plugin of conftest.py's ``pytest_plugins``)."""
    if wanted() is None:
        return
    if not hasattr(config, "workerinput"):   # the groups of earlier runs, empty now
        for root in (V1_ROOT, V2_ROOT):
            for group in root.glob("robokin-*"):
                try:
                    group.rmdir()
                except OSError:
                    pass
    worker = getattr(config, "workerinput", {}).get("workerid", "main")
    counting = os.environ.get(COUNTING)
    if counting and not (worker != "main" and os.getppid() == int(counting)):
        # a pytest run started by a test (the other machines, the scaffolded chapters): it stays in
        # the group of the worker that started it, whose test it is part of
        return
    os.environ[COUNTING] = str(os.getpid()) if worker == "main" else counting or ""
    counter = Counter(f"robokin-{os.getpid()}-{worker}")
    config.robokin_cpu_counter = counter if counter.available else None
    if not hasattr(config, "workerinput"):
        config.pluginmanager.register(Report(config, counted=counter.available), "robokin-cpu-report")


@pytest.hookimpl(hookwrapper=True)
def _measured(item):
    counter = getattr(item.config, "robokin_cpu_counter", None)
    if counter is None:
        yield
        return
    before = counter.seconds()
    yield
    item.stash.setdefault(SPENT, []).append(counter.seconds() - before)


SPENT = pytest.StashKey[list]()
pytest_runtest_setup = _measured
pytest_runtest_call = _measured
pytest_runtest_teardown = _measured


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    spent = item.stash.get(SPENT, [])
    if spent:
        outcome.get_result().user_properties.append((PROPERTY, spent.pop()))


def unit_of_report(config, nodeid: str) -> str:
    """The work unit of a report's test (its xdist group, else the test)."""
    known = getattr(config, "robokin_units", {})
    if nodeid in known:
        return known[nodeid]
    if nodeid.rfind("@") > nodeid.rfind("]"):
        return nodeid.rsplit("@", 1)[1]
    return nodeid


def pytest_sessionfinish(session):
    """(in a worker) hand the controller this process's whole count, collection included."""
    counter = getattr(session.config, "robokin_cpu_counter", None)
    if counter is not None and hasattr(session.config, "workeroutput"):
        session.config.workeroutput["robokin_cpu"] = [str(counter.path), counter.seconds()]


class Report:
    """In the controller: the CPU-seconds of the run's reports, added up and shown."""

    def __init__(self, config, counted: bool) -> None:
        self.config = config
        self.counted = counted
        self.by_test: dict[str, float] = defaultdict(float)
        self.by_unit: dict[str, float] = defaultdict(float)
        self.workers: dict[str, float] = {}   # a worker's control group: its CPU-s, collection included
        #: per unit: [worker, first start, last stop] (seconds since the epoch): when each unit ran, where
        self.spans: dict[str, list] = {}

    def pytest_runtest_logreport(self, report):
        for key, value in report.user_properties:
            if key == PROPERTY:
                nodeid = report.nodeid.split("@", 1)[0]
                self.by_test[nodeid] += value
                unit = unit_of_report(self.config, report.nodeid)
                self.by_unit[unit] += value
                if report.start:
                    worker = getattr(getattr(report, "node", None), "gateway", None)
                    span = self.spans.setdefault(unit, [getattr(worker, "id", "main"), report.start, report.stop])
                    span[1], span[2] = min(span[1], report.start), max(span[2], report.stop)

    @pytest.hookimpl(optionalhook=True)
    def pytest_testnodedown(self, node, error):
        path, seconds = getattr(node, "workeroutput", {}).get("robokin_cpu", (None, 0.0))
        if path:
            self.workers[path] = seconds

    def pytest_unconfigure(self, config):
        for path in [*self.workers, str(getattr(self.config, "robokin_cpu_counter", None) and
                                        self.config.robokin_cpu_counter.path or "")]:
            if path:
                try:
                    Path(path).rmdir()   # empty once its processes have ended (not this one's own)
                except OSError:
                    pass

    def summary(self) -> dict:
        by_file: dict[str, float] = defaultdict(float)
        by_chapter: dict[str, float] = defaultdict(float)
        for nodeid, value in self.by_test.items():
            by_file[nodeid.split("::", 1)[0]] += value
            found = CHAPTER.search(nodeid)
            by_chapter[found.group(0) if found else "(no chapter)"] += value
        ordered = lambda d: dict(sorted(((k, round(v, 1)) for k, v in d.items()), key=lambda kv: -kv[1]))  # noqa: E731
        first = min((span[1] for span in self.spans.values()), default=0.0)
        timeline = {unit: [worker, round(start - first, 1), round(stop - first, 1)]
                    for unit, (worker, start, stop) in sorted(self.spans.items(), key=lambda kv: kv[1][1])}
        return {"total": round(sum(self.by_test.values()), 1), "timeline": timeline,
                "workers_total": round(sum(self.workers.values()), 1), "by_unit": ordered(self.by_unit),
                "by_file": ordered(by_file), "by_chapter": ordered(by_chapter), "by_test": ordered(self.by_test)}

    def pytest_terminal_summary(self, terminalreporter):
        write = terminalreporter.write_line
        terminalreporter.section("CPU-seconds (children included)")
        if not self.counted:
            write(f"{VARIABLE}: no control group could be made here (needs a writable cpuacct or cgroup v2 "
                  "hierarchy); nothing was counted")
            return
        summary = self.summary()
        Path(wanted() or "cpu-report.json").write_text(json.dumps(summary, indent=1) + "\n", encoding="utf-8")
        write(f"tests {summary['total']:.0f} CPU-s (the workers' processes, collection included: "
              f"{summary['workers_total']:.0f}); the whole table in {wanted()}")
        for title in ("by_file", "by_unit"):
            write(f"-- {title.replace('_', ' ')} (largest 15)")
            for name, value in list(summary[title].items())[:15]:
                write(f"{value:8.1f}  {name}")
