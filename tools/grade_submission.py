#!/usr/bin/env python3
"""Grade one submitted notebook of a chapter, with no course directory to keep.

    .venv/bin/python tools/grade_submission.py 03_three_rpr submission.ipynb --out results/alice
    .venv/bin/python tools/grade_submission.py 03_three_rpr submission.ipynb --out . --memory 4096

The course's own pipeline grades it (nbgrader_config.py: the bubblewrap sandbox, the
verdicts decided in a grader kernel of their own, restarts after a lost kernel, the
diagnoses of typical mistakes, the points of each test): the chapter is assigned in a
temporary course, the notebook submitted there as one student's, ``nbgrader autograde``
and ``nbgrader generate_feedback`` run, and the course is thrown away. What is kept, in
``--out``:

``results.json``
    Gradescope's autograder format: ``score``, and ``tests``, one per graded test cell,
    with ``name``, ``score``, ``max_score`` and ``output`` (the test's verdict: its error
    and diagnosis, never its source, so hidden tests stay hidden).
``feedback.html``
    The feedback page nbgrader writes for the student.

Every process of the grading (nbgrader, the grader kernel, the student's kernel in the
sandbox) runs with a cap on its memory (``--memory``, MiB of address space per process,
default :data:`DEFAULT_MEMORY_MIB`) and on its CPU time (``--cpu-seconds``, default
:data:`DEFAULT_CPU_SECONDS`): a submission that allocates beyond the cap gets a
``MemoryError`` in that cell, one that computes beyond it loses its kernel, and in both
cases its other marks stay and the grading machine goes on. The exit code is 0 when the
notebook was graded (whatever its score), 1 when grading itself failed (the message says
why), 2 for bad arguments.
"""

from __future__ import annotations

import argparse
import json
import resource
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from student_edition import ROOT, add_source, environment, nbgrader_command, write_course

#: MiB of address space per process: a grader or student kernel with numpy, sympy and
#: matplotlib maps about 1 GiB; 4 GiB leaves room for any exercise and lets a 2-core,
#: 24 GB machine grade two submissions at a time with two kernels each.
DEFAULT_MEMORY_MIB = 4096
#: CPU seconds per process: the longest chapter's kernels use about 20 s; a submission that
#: computes for ten minutes is stopped (each cell also has its own time limit).
DEFAULT_CPU_SECONDS = 600
#: The student's name in the temporary course.
STUDENT = "submission"


def limits(memory_mib: int, cpu_seconds: int):
    """A ``preexec_fn`` that caps the address space and CPU time of a process and its children."""
    def apply() -> None:
        memory = memory_mib * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu_seconds, cpu_seconds + 5))
    return apply


def run_nbgrader(args: list[str], course: Path, log: list[str], preexec=None) -> subprocess.CompletedProcess:
    proc = subprocess.run([*nbgrader_command(), *args], cwd=course, capture_output=True, text=True,
                          env=environment(), preexec_fn=preexec, check=False)
    log.append(f"$ nbgrader {' '.join(args)}   [exit {proc.returncode}]\n{proc.stdout}{proc.stderr}")
    return proc


def test_outputs(autograded: dict) -> dict[str, str]:
    """``{grade id: what the test printed and its verdict}`` of the graded test cells.

    Only outputs: a stream's text, an error's name and message (no traceback, which quotes the
    cell's source, and a hidden test's source must not reach the student).
    """
    out = {}
    for cell in autograded.get("cells", []):
        grading = cell.get("metadata", {}).get("nbgrader", {})
        if not grading.get("grade") or grading.get("solution"):
            continue
        parts = []
        for output in cell.get("outputs", []):
            if output.get("output_type") == "stream":
                parts.append("".join(output.get("text", "")))
            elif output.get("output_type") == "error":
                parts.append(f"{output.get('ename', 'Error')}: {output.get('evalue', '')}")
            elif "text/plain" in output.get("data", {}):
                parts.append("".join(output["data"]["text/plain"]))
        out[grading["grade_id"]] = "\n".join(part.rstrip("\n") for part in parts)
    return out


def read_scores(course: Path, chapter: str) -> list[dict]:
    """The graded tests of the submission, in the notebook's order: name, score, max_score."""
    from nbgrader.api import Gradebook

    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gradebook:
        notebook = gradebook.find_submission_notebook(chapter, chapter, STUDENT)
        scores = {grade.name: grade.score for grade in notebook.grades}
        cells = gradebook.find_notebook(chapter, chapter).grade_cells
        return [{"name": cell.name, "score": float(scores.get(cell.name) or 0.0), "max_score": float(cell.max_score)}
                for cell in cells]


def grade(chapter: str, notebook: Path, out: Path, memory_mib: int = DEFAULT_MEMORY_MIB,
          cpu_seconds: int = DEFAULT_CPU_SECONDS, notebooks: Path = ROOT / "notebooks") -> dict:
    """Grade ``notebook`` as a submission of ``chapter``; write ``results.json`` and ``feedback.html``
    into ``out`` and return the results. Raises ``RuntimeError`` when grading itself fails."""
    source = notebooks / f"{chapter}.ipynb"
    if not source.is_file():
        raise FileNotFoundError(f"no chapter {chapter!r}: {source} does not exist")
    out.mkdir(parents=True, exist_ok=True)
    log: list[str] = []
    with tempfile.TemporaryDirectory(prefix="robokin-grade-") as folder:
        course = Path(folder) / "course"
        write_course(course, Path(folder) / "exchange")
        add_source(course, source)
        if run_nbgrader(["generate_assignment", chapter, "--force"], course, log).returncode != 0:
            raise RuntimeError("nbgrader generate_assignment failed:\n" + log[-1])
        submitted = course / "submitted" / STUDENT / chapter
        submitted.mkdir(parents=True)
        shutil.copy2(notebook, submitted / f"{chapter}.ipynb")
        autograde = run_nbgrader(["autograde", chapter, "--student", STUDENT, "--force"], course, log,
                                 preexec=limits(memory_mib, cpu_seconds))
        autograded = course / "autograded" / STUDENT / chapter / f"{chapter}.ipynb"
        if autograde.returncode != 0 or not autograded.is_file():
            raise RuntimeError("nbgrader autograde failed:\n" + log[-1][-4000:])
        run_nbgrader(["generate_feedback", chapter, "--student", STUDENT, "--force"], course, log)
        outputs = test_outputs(json.loads(autograded.read_text(encoding="utf-8")))
        tests = [{**row, "output": outputs.get(row["name"], "")} for row in read_scores(course, chapter)]
        page = course / "feedback" / STUDENT / chapter / f"{chapter}.html"
        if page.is_file():
            shutil.copy2(page, out / "feedback.html")
    results = {"score": sum(test["score"] for test in tests), "tests": tests,
               "output": f"{chapter}: {sum(t['score'] for t in tests):g} of {sum(t['max_score'] for t in tests):g} "
                         "points; feedback.html explains each test."}
    (out / "results.json").write_text(json.dumps(results, indent=2) + "\n", encoding="utf-8")
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("chapter", help="the chapter, e.g. 03_three_rpr")
    parser.add_argument("notebook", type=Path, help="the submitted notebook (.ipynb)")
    parser.add_argument("--out", type=Path, required=True, help="folder for results.json and feedback.html")
    parser.add_argument("--memory", type=int, default=DEFAULT_MEMORY_MIB,
                        help=f"MiB of address space per process (default {DEFAULT_MEMORY_MIB})")
    parser.add_argument("--cpu-seconds", type=int, default=DEFAULT_CPU_SECONDS,
                        help=f"CPU seconds per process (default {DEFAULT_CPU_SECONDS})")
    args = parser.parse_args(argv)
    if not args.notebook.is_file():
        print(f"ERROR: no notebook {args.notebook}", file=sys.stderr)
        return 2
    try:
        results = grade(args.chapter, args.notebook.resolve(), args.out.resolve(), args.memory, args.cpu_seconds)
    except (FileNotFoundError, RuntimeError) as error:
        print(f"ERROR: {error}", file=sys.stderr)
        return 1
    print(results["output"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
