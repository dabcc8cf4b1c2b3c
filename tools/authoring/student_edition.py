#!/usr/bin/env python3
"""Make the nbgrader course and the student edition of every chapter (``make student``).

    .venv/bin/python tools/authoring/student_edition.py                 # all chapters -> _build/nbgrader/course
    .venv/bin/python tools/authoring/student_edition.py 02_ur10_ik      # one chapter
    .venv/bin/python tools/authoring/student_edition.py --course ~/robokin-course --exchange /srv/nbgrader/exchange

For each chapter notebook (``notebooks/NN_*.ipynb`` without the tour) it copies
the notebook, the single source with its nbgrader metadata, to
``<course>/source/<chapter>/<chapter>.ipynb`` and runs nbgrader's own
``nbgrader generate_assignment <chapter>``. The student edition is then
``<course>/release/<chapter>/<chapter>.ipynb`` and the assignment is in the
course's gradebook (``<course>/gradebook.db``).

The course directory gets an ``nbgrader_config.py`` (``tools/grading/course.py``) that loads the repository's
(so the robokin pipeline is used from any directory) and sets the course root
and nbgrader's exchange directory.

A chapter without nbgrader metadata, or with metadata older than the notebook,
is reported by name and the command exits non-zero (after doing the others).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

from tools.authoring.nbgrader_metadata import chapter_notebooks, differences
from tools.grading.course import ROOT, add_source, check_names, environment, nbgrader_command, write_course
from tools.notebook_analysis import analyse, load_notebook

DEFAULT_COURSE = ROOT / "_build" / "nbgrader" / "course"


def metadata_problems(path: Path) -> list[str]:
    """Why a chapter cannot be assigned as it is (empty when it can)."""
    nb = load_notebook(path)
    if not any("nbgrader" in c.get("metadata", {}) for c in nb["cells"]):
        return ["no nbgrader metadata"]
    chapter = analyse(path, nb, check_names=check_names())
    if chapter.problems:
        return chapter.problems
    stale = differences(nb, chapter)
    return [f"nbgrader metadata is stale ({len(stale)} cells, first: {stale[0]})"] if stale else []


def generate(course: Path, chapter: str, quiet: bool = False) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*nbgrader_command(), "generate_assignment", chapter, "--force", "--log-level=WARN"],
        cwd=course, capture_output=quiet, text=True, env=environment(),
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("chapters", nargs="*", help="chapter names, e.g. 02_ur10_ik (default: all)")
    parser.add_argument("--course", type=Path, default=DEFAULT_COURSE, help="course directory")
    parser.add_argument("--exchange", type=Path, default=None,
                        help="nbgrader exchange directory (default: next to the course, 'exchange')")
    parser.add_argument("--notebooks", type=Path, default=ROOT / "notebooks",
                        help="folder of the chapter notebooks (default: notebooks/)")
    parser.add_argument("--allow-stale", action="store_true",
                        help="assign chapters whose metadata is older than the notebook (not recommended)")
    args = parser.parse_args(argv)

    available = {p.stem: p for p in chapter_notebooks(args.notebooks.resolve().parent, args.notebooks.name)}
    wanted = args.chapters or sorted(available)
    unknown = [name for name in wanted if name not in available]
    if unknown:
        print(f"ERROR: no chapter notebook {', '.join(unknown)} (chapters: {', '.join(sorted(available))})")
        return 2
    course = args.course.resolve()
    exchange = (args.exchange or course.parent / "exchange").resolve()
    write_course(course, exchange)

    failed: dict[str, str] = {}
    for name in wanted:
        problems = metadata_problems(available[name])
        if problems and not (args.allow_stale and problems[0].startswith("nbgrader metadata is stale")):
            failed[name] = "; ".join(problems)
            continue
        add_source(course, available[name])
        proc = generate(course, name, quiet=True)
        if proc.returncode != 0:
            log = (proc.stdout + proc.stderr).strip().splitlines()
            failed[name] = "nbgrader generate_assignment failed: " + " | ".join(log[-3:])
            continue
        print(f"student edition: {course / 'release' / name / (name + '.ipynb')}")
    if failed:
        print()
        for name, why in failed.items():
            print(f"ERROR [student]: chapter {name} was not assigned: {why}")
        print("Fix: run `.venv/bin/python tools/authoring/nbgrader_metadata.py` (it writes the nbgrader metadata "
              "into the chapter notebooks), then `make student` again.")
        return 1
    print(f"\nThe student edition is in {course / 'release'}; the course (nbgrader) is {course}.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
