"""CPU cost of grading one correct submission of each chapter (prints a table; not a test).

Run:  .venv/bin/python benchmarks/grading_throughput.py [CHAPTER ...] [--timeout 600]

For each chapter (default: every ``notebooks/NN_*.ipynb`` from 01 on), the student edition is
made by ``nbgrader generate_assignment`` and filled with the instructor's answers (as
tests/test_nbgrader.py's ``correct_submission`` does); then ``tools/grading/grade_submission.py`` grades
it as ``make grade`` grades each submission (the sandbox, the grader kernels, the process cap,
the feedback page), in a process of its own, in a copy of a template course in which the chapter
is assigned (``--template``), made before and not counted: ``make grade`` and a Kubernetes shard
make it once per run. ``--no-template`` grades as one ``grade_submission.py`` alone does (the
chapter assigned for the submission, about 0.7 CPU-seconds more). Its CPU time is counted two ways:

* in a cpuacct control group of its own (cgroup v1 ``cpuacct.usage``, or v2 ``cpu.stat``), made
  under this process's group where the control-group file system is writable (root): every
  process the grading starts is counted, whoever waits for it;
* by ``resource.getrusage(RUSAGE_CHILDREN)`` around the run: a process's CPU reaches it only
  when its parent waited for it, all the way up. It misses what the grading's processes do
  not wait for (see the table it prints): plan with the control group's figure.

Submissions per minute per core = 60 / CPU seconds per submission (grading is CPU-bound on a
machine of its own); the cores that grade a 1,000-student chapter in an hour =
1,000 x CPU seconds / 3,600, rounded up. The CPU seconds are also given in millions of
yardsticks (``yardstick.py``, timed in the same run), which cancels the machine's speed.
The script needs the venv of the repository (nbgrader, bubblewrap for the sandbox).
"""

from __future__ import annotations

import argparse
import copy
import json
import math
import os
import resource
import signal
import subprocess
import sys
import tempfile
import time
import uuid
from pathlib import Path

from yardstick import yardstick_seconds

from tools.grading.grade_submission import assign
from tools.authoring.student_edition import generate
from tools.grading.course import ROOT, add_source, write_course

NOTEBOOKS = ROOT / "notebooks"
STUDENTS = 1000


def chapters() -> list[str]:
    """Every exercise chapter: ``notebooks/NN_*.ipynb`` from 01 on."""
    return sorted(path.stem for path in NOTEBOOKS.glob("[0-9][0-9]_*.ipynb") if not path.stem.startswith("00"))


def correct_submission(chapter: str, folder: Path) -> Path:
    """The chapter's student edition with the instructor's code in every answer cell, saved in ``folder``."""
    course = folder / "course"
    write_course(course, folder / "exchange")
    add_source(course, NOTEBOOKS / f"{chapter}.ipynb")
    proc = generate(course, chapter, quiet=True)
    if proc.returncode != 0:
        raise RuntimeError(f"nbgrader generate_assignment {chapter} failed:\n{proc.stdout}{proc.stderr}")

    def grading(cell: dict) -> dict:
        return cell.get("metadata", {}).get("nbgrader", {})

    source = json.loads((NOTEBOOKS / f"{chapter}.ipynb").read_text(encoding="utf-8"))
    release = json.loads((course / "release" / chapter / f"{chapter}.ipynb").read_text(encoding="utf-8"))
    answers = {grading(cell)["grade_id"]: cell["source"] for cell in source["cells"] if grading(cell).get("solution")}
    submission = copy.deepcopy(release)
    for cell in submission["cells"]:
        if grading(cell).get("grade_id") in answers:
            cell["source"] = answers[grading(cell)["grade_id"]]
    path = folder / "submission" / f"{chapter}.ipynb"
    path.parent.mkdir(parents=True)
    path.write_text(json.dumps(submission, indent=1, ensure_ascii=False), encoding="utf-8")
    return path


class CpuGroup:
    """A control group that counts the CPU seconds of every process in it, children included.

    Made under this process's own group (so that a group around this script counts it too),
    in cgroup v1's ``cpuacct`` hierarchy or in cgroup v2; :meth:`make` returns ``None`` where
    neither is writable.
    """

    def __init__(self, path: Path, version: int):
        self.path, self.version = path, version

    @classmethod
    def make(cls) -> CpuGroup | None:
        name = f"robokin-grading-{uuid.uuid4().hex[:8]}"
        for line in Path("/proc/self/cgroup").read_text().splitlines():
            number, controllers, own = line.split(":", 2)
            if "cpuacct" in controllers.split(","):
                base, version = Path("/sys/fs/cgroup") / controllers, 1
            elif number == "0" and (Path("/sys/fs/cgroup") / "cgroup.controllers").is_file():
                base, version = Path("/sys/fs/cgroup"), 2
            else:
                continue
            try:
                path = base / own.lstrip("/") / name
                path.mkdir()
                group = cls(path, version)
                group.seconds()
                return group
            except OSError:
                continue
        return None

    def seconds(self) -> float:
        if self.version == 1:
            return int((self.path / "cpuacct.usage").read_text()) / 1e9
        stat = dict(line.split() for line in (self.path / "cpu.stat").read_text().splitlines())
        return int(stat["usage_usec"]) / 1e6

    def join(self) -> None:
        """Move the calling process into the group (a ``preexec_fn``)."""
        (self.path / "cgroup.procs").write_text(str(os.getpid()))

    def kill_all(self) -> None:
        for pid in (self.path / "cgroup.procs").read_text().split():
            try:
                os.kill(int(pid), signal.SIGKILL)
            except ProcessLookupError:
                pass

    def remove(self) -> None:
        for _ in range(50):   # the last processes of a killed run take a moment to go
            try:
                self.path.rmdir()
                return
            except OSError:
                time.sleep(0.1)


def children_seconds() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def grade(chapter: str, notebook: Path, timeout: float, template: Path | None = None) -> dict:
    """Grade ``notebook`` with tools/grading/grade_submission.py (in a copy of ``template``, a course made by
    ``grade_submission.assign``, where one is given): its score and what it cost."""
    group = CpuGroup.make()
    out = notebook.parent / "out"
    copied = ["--template", str(template)] if template else []
    before, started = children_seconds(), time.perf_counter()
    process = subprocess.Popen([sys.executable, str(ROOT / "tools" / "grading" / "grade_submission.py"), chapter,
                                str(notebook), "--out", str(out), *copied], cwd=ROOT, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, start_new_session=True,
                               preexec_fn=group.join if group else None)
    try:
        log, _ = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        if group:
            group.kill_all()
        log, _ = process.communicate()
        log += f"\n(killed after {timeout:g} s)"
    wall = time.perf_counter() - started
    rusage = children_seconds() - before
    counted = group.seconds() if group else float("nan")
    if group:
        group.remove()
    results = out / "results.json"
    if process.returncode != 0 or not results.is_file():
        raise RuntimeError(f"grading {chapter} failed (exit {process.returncode}):\n{log[-3000:]}")
    tests = json.loads(results.read_text(encoding="utf-8"))["tests"]
    return {"score": sum(test["score"] for test in tests), "max": sum(test["max_score"] for test in tests),
            "cgroup": counted, "rusage": rusage, "wall": wall}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("chapters", nargs="*", help="chapters, e.g. 03_three_rpr (default: every exercise chapter)")
    parser.add_argument("--timeout", type=float, default=600, help="seconds one grading may take (default 600)")
    parser.add_argument("--no-template", action="store_true",
                        help="assign the chapter for the submission, as grade_submission.py alone does")
    args = parser.parse_args(argv)
    chosen = args.chapters or chapters()
    unknown = [chapter for chapter in chosen if not (NOTEBOOKS / f"{chapter}.ipynb").is_file()]
    if unknown:
        print(f"ERROR: no notebook for chapters {unknown}; expected names like {chapters()[0]}", file=sys.stderr)
        return 2
    yardsticks = [yardstick_seconds()]
    rows = {}
    for chapter in chosen:
        with tempfile.TemporaryDirectory(prefix="robokin-throughput-") as folder:
            notebook = correct_submission(chapter, Path(folder))
            template = None if args.no_template else assign(chapter, Path(folder) / "template")
            rows[chapter] = grade(chapter, notebook, args.timeout, template)
        print(f"{chapter}: graded", flush=True)
    yardsticks.append(yardstick_seconds())
    yard = min(yardsticks)
    load = os.getloadavg()
    print(f"{os.cpu_count()} CPUs, load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; "
          f"yardstick {yard * 1e6:.1f} us; CPU counted "
          f"{'in a control group and' if any(r['cgroup'] == r['cgroup'] for r in rows.values()) else 'only'} "
          f"by getrusage(RUSAGE_CHILDREN); {'no template' if args.no_template else 'a copy of a template course'}")
    header = (f"{'chapter':28s} {'score':>9s} {'CPU-s':>7s} {'rusage':>7s} {'wall s':>7s} "
              f"{'per min/core':>12s} {'cores, 1000/h':>13s} {'Myardsticks':>11s}")
    print(header)
    print("-" * len(header))
    for chapter, row in rows.items():
        cpu = row["cgroup"] if row["cgroup"] == row["cgroup"] else row["rusage"]
        print(f"{chapter:28s} {row['score']:4g}/{row['max']:<4g} {row['cgroup']:7.1f} {row['rusage']:7.1f} "
              f"{row['wall']:7.1f} {60 / cpu:12.2f} {math.ceil(STUDENTS * cpu / 3600):13d} {cpu / yard / 1e6:11.2f}")
    return 0 if all(row["score"] == row["max"] for row in rows.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
