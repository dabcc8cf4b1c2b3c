#!/usr/bin/env python3
"""Grade one submitted notebook of a chapter, with no course directory to keep.

    .venv/bin/python tools/grading/grade_submission.py 03_three_rpr submission.ipynb --out results/alice
    .venv/bin/python tools/grading/grade_submission.py 03_three_rpr submission.ipynb --out . --memory 4096 \
        --max-processes 256
    .venv/bin/python tools/grading/grade_submission.py 03_three_rpr --assign template    # once, then:
    .venv/bin/python tools/grading/grade_submission.py 03_three_rpr submission.ipynb --out . \
        --template template/course

The course's own pipeline grades it (nbgrader_config.py: the bubblewrap sandbox, the
verdicts decided in a grader kernel of their own, restarts after a lost kernel, the
diagnoses of typical mistakes, the points of each test): the chapter is assigned in a
temporary course, the notebook submitted there as one student's, ``nbgrader autograde``
and ``nbgrader generate_feedback`` run, and the course is thrown away. nbgrader's three
steps run in one process, by its Python API (one start-up of nbgrader instead of three,
about 4 CPU-seconds less per submission), under the caps below. ``--assign FOLDER`` assigns the
chapter once, in a template course ``FOLDER/course``; ``--template FOLDER/course`` then copies it
for the submission (its gradebook, ``source/`` and ``release/``) instead of assigning the chapter
again (the step costs about 0.7 CPU-seconds, the new gradebook's ``alembic heads`` process
included; the log gives each step's CPU time). What is kept, in ``--out``:

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
cases its other marks stay and the grading machine goes on. The student's kernel and
everything it starts may have at most ``--max-processes`` processes and threads (default
:data:`process_cap.DEFAULT_MAX_PROCESSES`): a fork bomb gets ``BlockingIOError`` in its cell,
which loses its points, and whatever it started is killed with the kernel. The cap is a
cgroup's ``pids.max`` where a pids cgroup is writable (root), ``RLIMIT_NPROC`` for an
ordinary user (tools/grading/process_cap.py says why not both); where neither works, grading stops
and says why, and ``--max-processes 0`` grades without the cap, with a warning. The exit
code is 0 when the notebook was graded (whatever its score), 1 when grading itself failed
(the message says why), 2 for bad arguments.
"""

from __future__ import annotations

import argparse
import json
import logging
import resource
import shutil
import subprocess
import sys
import tempfile
import uuid
from pathlib import Path

from tools.grading import process_cap
from tools.grading.process_cap import DEFAULT_MAX_PROCESSES, ProcessCapUnavailable
from tools.grading.sandbox import sandbox_wanted
from tools.grading.course import ROOT, add_source, environment, nbgrader_command, write_course

#: MiB of address space per process: a grader or student kernel with numpy, sympy and
#: matplotlib maps about 1 GiB; 4 GiB leaves room for any exercise and lets a 2-core,
#: 24 GB machine grade two submissions at a time with two kernels each.
DEFAULT_MEMORY_MIB = 4096
#: CPU seconds per process: the longest chapter's kernels use about 20 s; a submission that
#: computes for ten minutes is stopped (each cell also has its own time limit).
DEFAULT_CPU_SECONDS = 600
#: The student's name in the temporary course.
STUDENT = "submission"

logger = logging.getLogger("robokin.grading")


def add_cap_options(parser: argparse.ArgumentParser, max_processes: int = DEFAULT_MAX_PROCESSES,
                    max_processes_help: str = "") -> None:
    """The caps of a submission's grading (:func:`grade`) as options of ``parser``: ``--memory``,
    ``--cpu-seconds`` and ``--max-processes`` (default ``max_processes``, explained by
    ``max_processes_help``, or by a sentence on the default cap when it is empty)."""
    parser.add_argument("--memory", type=int, default=DEFAULT_MEMORY_MIB,
                        help=f"MiB of address space per process (default {DEFAULT_MEMORY_MIB})")
    parser.add_argument("--cpu-seconds", type=int, default=DEFAULT_CPU_SECONDS,
                        help=f"CPU seconds per process (default {DEFAULT_CPU_SECONDS})")
    parser.add_argument("--max-processes", type=int, default=max_processes,
                        help=max_processes_help or "processes and threads of a submission's kernel and its "
                        f"children (default {DEFAULT_MAX_PROCESSES}; 0: no cap, with a warning, where none can be "
                        "made: root in a container with a read-only cgroup, which caps them itself)")


def limits(memory_mib: int, cpu_seconds: int):
    """A ``preexec_fn`` that caps the address space and CPU time of a process and its children."""
    def apply() -> None:
        memory = memory_mib * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu_seconds, cpu_seconds + 5))
    return apply


def run_nbgrader(args: list[str], course: Path, log: list[str], preexec=None,
                 env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    proc = subprocess.run([*nbgrader_command(), *args], cwd=course, capture_output=True, text=True,
                          env={**environment(), **(env or {})}, preexec_fn=preexec, check=False)
    log.append(f"$ nbgrader {' '.join(args)}   [exit {proc.returncode}]\n{proc.stdout}{proc.stderr}")
    return proc


#: nbgrader's steps of one submission's grading, in their order.
STEPS = ("generate_assignment", "autograde", "generate_feedback")
#: What the process that runs the steps prints before each step's log.
STEP_MARK = "$ nbgrader "
#: The process that runs nbgrader's steps in a course folder: ``run_steps`` below.
#: The file, in the course folder, into which :func:`run_steps` writes the scores of the submission
#: after ``autograde`` (a JSON list, as :func:`read_scores` returns it).
SCORES_FILE = "robokin-scores.json"
STEPS_SCRIPT = ("import sys\nfrom tools.grading.grade_submission import run_steps\n"
                "sys.exit(run_steps(sys.argv[1], sys.argv[2], sys.argv[3:]))")


def cpu_seconds_so_far() -> float:
    """CPU seconds of this process and of the children it waited for."""
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def run_steps(chapter: str, student: str, steps: list[str]) -> int:
    """Run nbgrader's ``steps`` on the course in the working folder, in this process; print their logs.

    nbgrader's Python API (``NbGraderAPI``, with the configuration the command line loads from the
    same folder) runs each step as ``nbgrader <step> <chapter> [--student <student>] --force``
    does: one Python start-up and one import of nbgrader for all of them, not one per step
    (about 2 CPU-seconds each). The steps stop at the first that fails; the exit code is the
    number of steps that did not succeed (0: all did). After ``autograde``, the submission's
    scores (:func:`read_scores`) are written to :data:`SCORES_FILE` in the working folder: read
    here, where nbgrader is imported, they cost the process that grades nothing (importing nbgrader
    to read them took about 1 CPU-second of each submission).
    """
    unknown = [step for step in steps if step not in STEPS]
    if unknown:
        raise ValueError(f"steps must be among {STEPS}; got {unknown}")
    from nbgrader.apps import NbGraderAPI
    from nbgrader.apps.baseapp import NbGrader

    loader = NbGrader()   # the configuration files the command line reads, the course's last
    loader.load_config_file()
    api = NbGraderAPI(config=loader.config)
    for done, step in enumerate(steps):
        before = cpu_seconds_so_far()
        if step == "generate_assignment":
            result = api.generate_assignment(chapter, force=True)
        elif step == "autograde":
            result = api.autograde(chapter, student, force=True)
        else:
            result = api.generate_feedback(chapter, student, force=True)
        print(f"{STEP_MARK}{step} {chapter}   [{'ok' if result['success'] else 'failed'}, "
              f"{cpu_seconds_so_far() - before:.1f} CPU-s with the processes it waited for]\n"
              f"{result.get('log', '')}{result.get('error', '')}", flush=True)
        if not result["success"]:
            return len(steps) - done
        if step == "autograde":   # nbgrader is imported here: the caller need not import it to read them
            Path(SCORES_FILE).write_text(json.dumps(read_scores(Path.cwd(), chapter, student)), encoding="utf-8")
    return 0


def run_steps_process(chapter: str, steps: list[str], course: Path, log: list[str], preexec=None,
                      env: dict[str, str] | None = None) -> dict[str, str]:
    """Run nbgrader's ``steps`` for :data:`STUDENT` in one process of their own (:func:`run_steps`),
    in ``course``; append its output to ``log`` and return ``{step: its log}`` of the steps it ran.
    A step that failed has ``[failed,`` in its log's first line; the steps after it did not run."""
    proc = subprocess.run([sys.executable, "-c", STEPS_SCRIPT, chapter, STUDENT, *steps], cwd=course,
                          capture_output=True, text=True, env={**environment(), **(env or {})},
                          preexec_fn=preexec, check=False)
    log.append(f"$ nbgrader {' + '.join(steps)} (one process)   [exit {proc.returncode}]\n{proc.stdout}{proc.stderr}")
    logs = {}
    for part in proc.stdout.split(STEP_MARK)[1:]:
        logs[part.split(" ", 1)[0]] = STEP_MARK + part
    if proc.returncode != 0 and proc.stderr:   # a crash, not a step that failed: it goes with the last step
        last = next((step for step in reversed(steps) if step in logs), steps[0])
        logs[last] = logs.get(last, "") + proc.stderr
    return logs


def assign(chapter: str, folder: Path, notebooks: Path = ROOT / "notebooks") -> Path:
    """A course in ``folder`` in which ``chapter`` is assigned (``nbgrader generate_assignment``:
    ``gradebook.db``, ``source/``, ``release/``); :func:`grade` copies it for each submission
    (``template``) instead of assigning the chapter again. Raises ``RuntimeError`` when nbgrader fails."""
    source = notebooks / f"{chapter}.ipynb"
    if not source.is_file():
        raise FileNotFoundError(f"no chapter {chapter!r}: {source} does not exist")
    course = folder / "course"
    write_course(course, folder / "exchange")
    add_source(course, source)
    log: list[str] = []
    logs = run_steps_process(chapter, ["generate_assignment"], course, log)
    if "[ok," not in logs.get("generate_assignment", "").split("\n", 1)[0]:
        raise RuntimeError("nbgrader generate_assignment failed:\n" + log[-1][-4000:])
    return course


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


def read_scores(course: Path, chapter: str, student: str = STUDENT) -> list[dict]:
    """The graded tests of ``student``'s submission, in the notebook's order: name, score, max_score."""
    from nbgrader.api import Gradebook

    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gradebook:
        notebook = gradebook.find_submission_notebook(chapter, chapter, student)
        scores = {grade.name: grade.score for grade in notebook.grades}
        cells = gradebook.find_notebook(chapter, chapter).grade_cells
        return [{"name": cell.name, "score": float(scores.get(cell.name) or 0.0), "max_score": float(cell.max_score)}
                for cell in cells]


def process_cap_environment(max_processes: int) -> dict[str, str]:
    """The variables that cap the student's kernel's processes at ``max_processes`` (0: no cap).

    Raises ``RuntimeError`` (from :class:`process_cap.ProcessCapUnavailable`) naming the cause
    when no cap can be made here; with no cap, or no sandbox to put it on, logs a warning
    saying so.
    """
    if max_processes < 0:
        raise ValueError(f"max_processes must be 0 (no cap) or a positive number of processes, not {max_processes}")
    if max_processes == 0:
        logger.warning("the processes of the submission's kernel are not capped (max_processes=0): a fork bomb is "
                       "stopped only by the machine's own limits (a container's pids limit)")
        return {process_cap.VARIABLE: "0"}
    if not sandbox_wanted(True):
        logger.warning("the processes of the submission's kernel are not capped: ROBOKIN_GRADING_SANDBOX=off runs "
                       "the kernel outside the sandbox, where the cap is made; grade in a container with a pids "
                       "limit of its own (docker run --pids-limit, Kubernetes podPidsLimit)")
        return {}
    try:
        process_cap.plan(max_processes)
    except ProcessCapUnavailable as error:
        raise RuntimeError(str(error)) from None
    return {process_cap.VARIABLE: str(max_processes), process_cap.TAG_VARIABLE: uuid.uuid4().hex[:12]}


def grade(chapter: str, notebook: Path, out: Path, memory_mib: int = DEFAULT_MEMORY_MIB,
          cpu_seconds: int = DEFAULT_CPU_SECONDS, notebooks: Path = ROOT / "notebooks",
          max_processes: int = DEFAULT_MAX_PROCESSES, template: Path | None = None) -> dict:
    """Grade ``notebook`` as a submission of ``chapter``; write ``results.json`` and ``feedback.html``
    into ``out`` and return the results. Raises ``RuntimeError`` when grading itself fails (or no
    cap on the kernel's processes can be made: ``max_processes=0`` grades without one).

    The submission is graded in a course of its own. ``template``, a course made by :func:`assign`
    for ``chapter`` (``make grade`` makes one per run), is copied into it (its gradebook, ``source/``
    and ``release/``); without it, the chapter is assigned there. nbgrader's steps run by its Python
    API in one process (:func:`run_steps`), under the memory and CPU caps.
    """
    source = notebooks / f"{chapter}.ipynb"
    if not source.is_file():
        raise FileNotFoundError(f"no chapter {chapter!r}: {source} does not exist")
    if template is not None:
        missing = [part for part in ("gradebook.db", f"source/{chapter}", f"release/{chapter}")
                   if not (template / part).exists()]
        if missing:
            raise FileNotFoundError(f"template must be a course in which {chapter} is assigned (made by "
                                    f"assign or --assign); {template} has no {', '.join(missing)}")
    capped = process_cap_environment(max_processes)
    out.mkdir(parents=True, exist_ok=True)
    log: list[str] = []
    with tempfile.TemporaryDirectory(prefix="robokin-grade-") as folder:
        course = Path(folder) / "course"
        write_course(course, Path(folder) / "exchange")
        if template is None:
            add_source(course, source)
            steps = list(STEPS)
        else:
            shutil.copy2(template / "gradebook.db", course / "gradebook.db")
            for part in ("source", "release"):
                shutil.copytree(template / part / chapter, course / part / chapter)
            steps = [step for step in STEPS if step != "generate_assignment"]
        submitted = course / "submitted" / STUDENT / chapter
        submitted.mkdir(parents=True)
        shutil.copy2(notebook, submitted / f"{chapter}.ipynb")
        try:
            logs = run_steps_process(chapter, steps, course, log, preexec=limits(memory_mib, cpu_seconds),
                                     env=capped)
        finally:   # a kernel's cgroup that its cleanup did not remove (nbgrader killed, say)
            tag = capped.get(process_cap.TAG_VARIABLE)
            killed = process_cap.remove_leftovers(tag) if tag else 0
            if killed:
                logger.warning("%d processes of the submission's kernel were left after grading; killed", killed)
        if "generate_assignment" in steps and "[ok," not in logs.get("generate_assignment", "").split("\n", 1)[0]:
            raise RuntimeError("nbgrader generate_assignment failed:\n" + log[-1][-4000:])
        autograded = course / "autograded" / STUDENT / chapter / f"{chapter}.ipynb"
        if "[ok," not in logs.get("autograde", "").split("\n", 1)[0] or not autograded.is_file():
            raise RuntimeError("nbgrader autograde failed:\n" + log[-1][-4000:])
        outputs = test_outputs(json.loads(autograded.read_text(encoding="utf-8")))
        scores = course / SCORES_FILE
        rows = json.loads(scores.read_text(encoding="utf-8")) if scores.is_file() else read_scores(course, chapter)
        tests = [{**row, "output": outputs.get(row["name"], "")} for row in rows]
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
    parser.add_argument("notebook", type=Path, nargs="?", help="the submitted notebook (.ipynb)")
    parser.add_argument("--out", type=Path, help="folder for results.json and feedback.html")
    parser.add_argument("--template", type=Path, default=None,
                        help="a course in which the chapter is assigned (FOLDER/course of --assign), copied "
                             "for the submission instead of assigning the chapter again")
    parser.add_argument("--assign", type=Path, default=None, metavar="FOLDER",
                        help="only assign the chapter, in a template course FOLDER/course, and exit")
    add_cap_options(parser)
    args = parser.parse_args(argv)
    logging.basicConfig(format="%(levelname)s [robokin grading] %(message)s")
    if args.max_processes < 0:
        parser.error(f"--max-processes must be 0 (no cap) or positive, not {args.max_processes}")
    if args.assign is not None:
        if args.notebook is not None or args.template is not None:
            parser.error("--assign takes no notebook and no --template: it makes the template")
        try:
            print(f"{args.chapter} assigned in {assign(args.chapter, args.assign.resolve())}")
        except (FileNotFoundError, RuntimeError) as error:
            print(f"ERROR: {error}", file=sys.stderr)
            return 1
        return 0
    if args.notebook is None or args.out is None:
        parser.error("a notebook and --out are needed (or --assign FOLDER)")
    if not args.notebook.is_file():
        print(f"ERROR: no notebook {args.notebook}", file=sys.stderr)
        return 2
    try:
        results = grade(args.chapter, args.notebook.resolve(), args.out.resolve(), args.memory, args.cpu_seconds,
                        max_processes=args.max_processes,
                        template=args.template.resolve() if args.template else None)
    except (FileNotFoundError, RuntimeError) as error:
        print(f"ERROR: {error}", file=sys.stderr)
        return 1
    print(results["output"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
