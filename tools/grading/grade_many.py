#!/usr/bin/env python3
"""Grade every submission of a chapter in a folder, several at a time (``make grade``).

    make grade CH=03_three_rpr SUBMISSIONS=~/term/03 [JOBS=2] [MAX_PROCESSES=0]
    .venv/bin/python tools/grading/grade_many.py 03_three_rpr ~/term/03 --jobs 2 --max-processes 256

The folder holds one folder per student, ``<folder>/<student>/<chapter>.ipynb``; each is
graded on its own by :mod:`grade_submission` (its own temporary course, its own memory, CPU
and process caps: ``--memory``, ``--cpu-seconds`` and ``--max-processes``, passed on as they
are) into ``<folder>/<student>/results.json`` and ``feedback.html``, ``--jobs`` at a
time (default: the number of cores). The chapter is assigned once per run, in a template
course (:func:`grade_submission.assign`) that each submission's course is a copy of: its
gradebook, ``source/`` and ``release/``, the state ``nbgrader generate_assignment`` would
give it, without the CPU of assigning the chapter again for every submission. A line per
submission reports its score or why it could not be graded; the exit code is 1 when any could
not be, 0 otherwise. Grading one at a time gives the same scores: each submission is graded in
a course of its own, and the template, which every course is copied from, no grading changes.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path

from tools.grading.grade_submission import add_cap_options, assign, grade
from tools.grading.process_cap import DEFAULT_MAX_PROCESSES


def submissions(folder: Path, chapter: str) -> list[Path]:
    """The notebooks ``<folder>/<student>/<chapter>.ipynb``, by student."""
    return sorted(path for path in folder.glob(f"*/{chapter}.ipynb") if path.is_file())


def grade_one(chapter: str, notebook: Path, memory_mib: int, cpu_seconds: int,
              max_processes: int = DEFAULT_MAX_PROCESSES, template: Path | None = None) -> tuple[Path, str, bool]:
    """Grade ``notebook`` into its folder: ``(notebook, its score or why it was not graded, graded)``.

    ``template``: the chapter's course made by :func:`grade_submission.assign`, copied for the
    submission (``None``: the chapter is assigned for it)."""
    try:
        results = grade(chapter, notebook, notebook.parent, memory_mib, cpu_seconds, max_processes=max_processes,
                        template=template)
    except (FileNotFoundError, RuntimeError) as error:
        return notebook, f"not graded: {str(error).splitlines()[0]}", False
    maximum = sum(test["max_score"] for test in results["tests"])
    return notebook, f"{results['score']:g} / {maximum:g}", True


def add_batch_options(parser: argparse.ArgumentParser) -> None:
    """The options of a batch (``make grade``, a shard): ``--jobs`` and the caps of each submission."""
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="submissions graded at a time")
    add_cap_options(parser)


def batch_options_error(args: argparse.Namespace) -> str:
    """What is wrong with the options of :func:`add_batch_options` (``""``: nothing)."""
    if args.jobs < 1:
        return f"--jobs must be at least 1; got {args.jobs}"
    if args.max_processes < 0:
        return f"--max-processes must be 0 (no cap) or a positive number of processes; got {args.max_processes}"
    return ""


def grade_batch(chapter: str, notebooks: list[Path], args: argparse.Namespace,
                report: Callable[[int, Path, str, bool], None], in_order: bool = False) -> int | None:
    """Grade ``notebooks``, ``args.jobs`` at a time, each in a copy of one template course.

    The chapter is assigned once (:func:`grade_submission.assign`), then each notebook is graded
    by :func:`grade_one` with the caps of :func:`add_batch_options`. ``report(done, notebook,
    verdict, graded)`` is called for each, in the order they finish (``in_order``: the order of
    ``notebooks``), ``done`` counting from 1. Returns how many could not be graded, or ``None``
    (the error printed) when the chapter could not be assigned.
    """
    failed = 0
    with tempfile.TemporaryDirectory(prefix="robokin-template-") as folder, \
            ThreadPoolExecutor(max_workers=args.jobs) as pool:
        try:
            template = assign(chapter, Path(folder))
        except (FileNotFoundError, RuntimeError) as error:
            print(f"ERROR: cannot assign {chapter}: {error}", file=sys.stderr)
            return None
        futures = [pool.submit(grade_one, chapter, path.resolve(), args.memory, args.cpu_seconds,
                               args.max_processes, template) for path in notebooks]
        for done, future in enumerate(futures if in_order else as_completed(futures), 1):
            notebook, verdict, ok = future.result()
            failed += not ok
            report(done, notebook, verdict, ok)
    return failed


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("chapter", help="the chapter, e.g. 03_three_rpr")
    parser.add_argument("folder", type=Path, help="folder of <student>/<chapter>.ipynb")
    add_batch_options(parser)
    args = parser.parse_args(argv)
    found = submissions(args.folder, args.chapter)
    if not found:
        print(f"ERROR: no {args.folder}/<student>/{args.chapter}.ipynb", file=sys.stderr)
        return 2
    if error := batch_options_error(args):
        print(f"ERROR: {error}", file=sys.stderr)
        return 2
    started = time.monotonic()

    def report(done: int, notebook: Path, verdict: str, graded: bool) -> None:
        print(f"[{done}/{len(found)}, {time.monotonic() - started:.0f} s] {notebook.parent.name}: {verdict}",
              flush=True)

    failed = grade_batch(args.chapter, found, args, report)
    if failed is None:
        return 1
    minutes = (time.monotonic() - started) / 60
    print(f"{len(found)} submissions in {minutes:.1f} min with {args.jobs} jobs "
          f"({len(found) / max(minutes, 1e-9) / args.jobs:.1f} per minute per job); {failed} not graded")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
