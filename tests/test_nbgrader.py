"""Student edition and autograding with nbgrader (book/for-instructors.md, "Assigning chapters").

Everything goes through nbgrader's real command-line tools and its sqlite
gradebook, in temporary course directories (one per chapter, so that chapters
are graded two at a time without sharing a database), with ONE autograde run per
chapter that also grades the submissions of test_grading_trust.py (every chapter)
and test_grading_tamper.py (chapter 3; tests/grading_course.py). The student
edition handed in unchanged (``unanswered``) is also the tamper suite's blank
submission, graded once:

1. ``generate_assignment`` makes the student edition: no line of the instructor's
   solution code is left, the stubs compile, outputs are cleared;
2. the student edition handed in unchanged scores 0 on every test;
3. the instructor's solutions pasted into the student cells score full marks, and
   robokin.check finds every answer it can check correct;
4. a submission with a typical mistake made from the solutions (a transposed
   matrix, a flipped sign, degrees for radians) scores partial marks, and its
   feedback names the mistake;
5. the instructors' walk-through (release, fetch, submit, collect, autograde,
   feedback) runs as written, through nbgrader's local exchange, on a submission
   that raises in an ungraded cell, runs forever in another and lost a test cell.

The tests read the committed chapter notebooks, which must carry the metadata
written by ``tools/nbgrader_metadata.py`` (``test_metadata_is_up_to_date`` says
when they do not). ``ROBOKIN_NBGRADER_NOTEBOOKS=<folder>`` grades the notebooks
of another folder instead (e.g. a copy the script was run on).
"""

from __future__ import annotations

import copy
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import Any

import pytest

from conftest import ROOT
import grading_course
import nbgrader_runner
from tools import nbgrader_metadata, student_edition
from tools.notebook_analysis import free_names, stub_plan

pytest.importorskip("nbgrader", reason="nbgrader is not installed: run `make test` (installs requirements.txt)")
# The graded courses are built in two parts, one xdist group each (tests/grading_course.py):
# each test that reads a run is marked with its part (grading_course.reads, chapter_params).

NOTEBOOKS = Path(os.environ.get("ROBOKIN_NBGRADER_NOTEBOOKS", ROOT / "notebooks")).resolve()
CHAPTERS = [p.stem for p in nbgrader_metadata.chapter_notebooks(NOTEBOOKS.parent, NOTEBOOKS.name)]
WALKTHROUGH_CHAPTER = grading_course.CHAPTER3
HIDDEN_TESTS = re.compile(r"### BEGIN HIDDEN TESTS\n.*?### END HIDDEN TESTS\n?", re.S)
#: autograde runs at a time in one pytest process (three were measured slower in the full suite:
#: 344 s instead of 287 s for the chapter 3 part, the machine's two cores being busy anyway)
WORKERS = 2
#: seconds per cell in the walk-through, for the submission that runs forever; its other
#: submissions (the correct resubmission too) must finish every cell in it: 30 s, as the trust
#: suite's runs, a ceiling load does not reach (chapter 3's imports passed 10 s at load 16)
TIMEOUT_FOR_BAD_SUBMISSION = 30

#: Typical mistakes made from a correct answer: (kind, diagnoses of a check that
#: recognise it, diagnosis codes the feedback may then name). Tried in this order.
MISTAKES = [
    ("transpose", {"transpose", "transform_transposed"}, {"transpose", "transform_transposed"}),
    ("negate", {"sign", "error_sign", "velocity_sign", "negative_branch", "direction"},
     {"sign", "error_sign", "velocity_sign", "negative_branch", "direction"}),
    ("degrees_input", {"degrees"}, {"degrees_input"}),
    ("degrees_output", {"degrees_output"}, {"degrees_output"}),
]

#: The code appended to a correct answer to make it mistaken.
MISTAKE_CODE = '''
def _robokin_mistake(value, kind, angle_args=()):
    import numpy as np

    def change(out):
        if kind == "transpose":
            return out.T
        if kind == "negate":
            return -out
        if kind == "degrees_output":
            return np.rad2deg(out)
        return out

    if callable(value) and not hasattr(value, "shape"):
        def mistaken(*args, **kwargs):
            if kind == "degrees_input":
                args = [np.deg2rad(np.asarray(a, dtype=float)) if i in angle_args else a
                        for i, a in enumerate(args)]
                return value(*args, **kwargs)
            return change(value(*args, **kwargs))
        return mistaken
    return change(value)


{name} = _robokin_mistake({name}, {kind!r}, {angles!r})  # a typical mistake, made by the test
'''


def _env(**extra: str) -> dict[str, str]:
    env = student_edition.environment()
    env.update(PYDEVD_DISABLE_FILE_VALIDATION="1", **extra)
    return env


def nbgrader(args: list[str], cwd: Path, log: list[str], check: bool = True, new_process: bool = False,
             **env: str) -> subprocess.CompletedProcess:
    """Run one nbgrader command line; its output goes to ``log``.

    The command runs in a child forked from a process that imported nbgrader once
    (tests/nbgrader_runner.py: about 1.1 s of CPU less per command); with
    ``new_process``, as a new ``nbgrader`` process, the console script an instructor types.
    """
    started = time.perf_counter()
    if new_process:
        proc = subprocess.run([*student_edition.nbgrader_command(), *args], cwd=cwd, capture_output=True,
                              text=True, env=_env(**env), timeout=900)
    else:
        proc = nbgrader_runner.run(args, cwd, _env(**env), timeout=900)
    log.append(f"$ nbgrader {' '.join(args)}   [{time.perf_counter() - started:.1f} s, exit {proc.returncode}]")
    log.append((proc.stdout + proc.stderr)[-4000:])
    if check and proc.returncode != 0:
        raise RuntimeError("\n".join(log[-2:]))
    return proc


def load(path: Path) -> dict:
    return json.loads(Path(path).read_text(encoding="utf-8"))


def save(nb: dict, path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(nb, indent=1, ensure_ascii=False), encoding="utf-8")


def src(cell: dict) -> str:
    s = cell.get("source", "")
    return "".join(s) if isinstance(s, list) else s


def nbg(cell: dict) -> dict:
    return cell.get("metadata", {}).get("nbgrader", {})


def rk(cell: dict) -> dict:
    return cell.get("metadata", {}).get("robokin", {})


# ---------------------------------------------------------------- submissions
def correct_submission(release: dict, source: dict) -> dict:
    """The student edition with the instructor's solution code in every answer cell."""
    answers = {nbg(c)["grade_id"]: src(c) for c in source["cells"] if nbg(c).get("solution")}
    nb = copy.deepcopy(release)
    for cell in nb["cells"]:
        if nbg(cell).get("grade_id") in answers:
            cell["source"] = answers[nbg(cell)["grade_id"]]
    return nb


def mistake_candidates(source: dict) -> list[dict]:
    """Typical mistakes robokin.check can recognise, made from the chapter's answers.

    For a test cell, a quantity it explains with a check (``metadata.robokin.explain``)
    whose variable is defined by an answer of the same task and read by the test,
    and a kind of mistake among that check's diagnoses.
    """
    from robokin.check.grading import _resolve

    defined: dict[str, tuple[str, int | None]] = {}  # name -> (grade_id of the answer, task)
    out = []
    for cell in source["cells"]:
        meta = rk(cell)
        if meta.get("role") == "answer":
            from tools.notebook_analysis import defined_names
            for name in defined_names(src(cell)):
                defined[name] = (nbg(cell)["grade_id"], meta.get("task"))
        if meta.get("role") != "test":
            continue
        for check, expr in meta.get("explain", []):
            try:
                checker = _resolve(check)
            except Exception:  # noqa: BLE001
                continue
            codes = {d.code for d in getattr(checker, "diagnoses", [])}
            for name in sorted(free_names(expr)):
                answer = defined.get(name)
                if answer is None or answer[1] != meta.get("task") or name not in meta.get("reads", []):
                    continue
                for kind, needs, names in MISTAKES:
                    if not codes & needs or not recognised(checker, kind, names):
                        continue
                    out.append({"answer": answer[0], "name": name, "kind": kind, "check": check,
                                "expr": expr, "codes": names, "angles": _angle_args(checker),
                                "task": meta.get("task"), "test": nbg(cell)["grade_id"]})
    return out


def _reference_as_answer(checker):
    """The check's reference shaped like a student's answer: a function of the check's
    argument groups (or of its variables one by one), or a value when it has none."""
    import numpy as np

    variables = getattr(checker, "variables", [])
    if not variables:
        return np.asarray(checker.reference(np.zeros(0)), dtype=float)
    groups = getattr(checker, "groups", None) or [(v.label, [i]) for i, v in enumerate(variables)]

    def answer(*args):
        x = np.zeros(len(variables))
        for (_, index), value in zip(groups, args):
            x[index] = np.asarray(value, dtype=float).ravel() if len(index) > 1 else float(value)
        return checker.reference(x)
    return answer


def recognised(checker, kind: str, names: set[str]) -> bool:
    """Whether robokin.check names the mistake ``kind`` made from the correct answer.

    A mistake made by the same code as in a submission (MISTAKE_CODE), applied to the
    check's own reference: a sign diagnosis of a feedback term, for example, is not the
    same as a negated result, and a pose given as one array has no angle argument to
    put in degrees. Unknown (the check cannot be evaluated this way): kept.
    """
    scope: dict = {}
    exec(MISTAKE_CODE.split("\n\n\n{name}")[0], scope)
    angles = _angle_args(checker)
    if kind == "degrees_input" and not angles:
        return False
    try:
        answer = _reference_as_answer(checker)
        if not checker.evaluate(answer).passed:   # the reference cannot be called like an answer
            return True
        result = checker.evaluate(scope["_robokin_mistake"](answer, kind, angles))
    except Exception:  # noqa: BLE001
        return True
    return not result.passed and result.diagnosis in names


def _angle_args(checker) -> tuple[int, ...]:
    """Positions of the arguments that are angles when the check calls the answer."""
    variables = getattr(checker, "variables", [])
    groups = getattr(checker, "groups", [])
    if groups and len(groups) != len(variables):
        return tuple(i for i, (_, idx) in enumerate(groups) if all(variables[j].kind == "angle" for j in idx))
    return tuple(i for i, v in enumerate(variables) if v.kind == "angle")


def mistaken_submission(correct: dict, mistake: dict) -> dict:
    nb = copy.deepcopy(correct)
    for cell in nb["cells"]:
        if nbg(cell).get("grade_id") == mistake["answer"]:
            cell["source"] = src(cell).rstrip() + "\n" + MISTAKE_CODE.format(
                name=mistake["name"], kind=mistake["kind"], angles=mistake["angles"])
    return nb


def bad_submission(correct: dict) -> tuple[dict, dict]:
    """Raises in an ungraded cell, runs forever in an answer, and lost its first test cell."""
    nb = copy.deepcopy(correct)
    cells = nb["cells"]
    tried = [c for c in cells if c["cell_type"] == "code" and "nbgrader" not in c.get("metadata", {})]
    answers = [c for c in cells if nbg(c).get("solution")]
    tests = [c for c in cells if nbg(c).get("grade")]
    what = {"raises": None, "loops": answers[-1], "deleted": nbg(tests[0])["grade_id"]}
    if tried:
        tried[0]["source"] = 'raise ValueError("my own experiment went wrong")\n' + src(tried[0])
        what["raises"] = tried[0]
    # it sleeps: to the grader the same endless cell as a busy loop, interrupted at the time
    # limit, but the wait costs no CPU
    answers[-1]["source"] = src(answers[-1]) + "\nimport time\n\nwhile True:  # never ends\n    time.sleep(0.5)\n"
    cells.remove(tests[0])
    return nb, what


#: The chapter that gets two more submissions for the feedback tests: an answer cell that
#: raises (its names are missing in later tasks: a knock-on failure) and an answer of the
#: wrong type. Chosen from the notebook (tools/notebook_analysis.py), not by name.
FEEDBACK_CHAPTER = "02_ur10_ik" if "02_ur10_ik" in CHAPTERS else (CHAPTERS[0] if CHAPTERS else "")
LIST_ATTRIBUTES = set(dir([]))


def _analysis(source: dict, chapter: str):
    from tools.notebook_analysis import analyse, trace
    info = analyse(NOTEBOOKS / f"{chapter}.ipynb", source)
    kinds = [("answer" if c.role == "answer" else "code" if c.cell_type == "code" else "markdown", c.source)
             for c in info.cells]
    return info, trace(kinds)


def knock_on_candidate(source: dict, chapter: str) -> dict | None:
    """The first test that reads, directly or through given cells, an answer of an earlier task."""
    info, reads = _analysis(source, chapter)
    for test in info.tests():
        todo, seen = [test.index], set()
        while todo:
            cell = todo.pop()
            if cell in seen:
                continue
            seen.add(cell)
            for name, binding in sorted(reads[cell].items()):
                answer = info.cells[binding.cell]
                if binding.answer and answer.task is not None and test.task is not None and answer.task < test.task:
                    return {"name": name, "task": answer.task, "answer": nbg(source["cells"][binding.cell])["grade_id"],
                            "test": nbg(source["cells"][test.index])["grade_id"]}
                if not binding.answer and binding.roots:
                    todo.append(binding.cell)
    return None


def wrong_type_candidate(source: dict, chapter: str) -> dict | None:
    """An answer variable (not a function) whose attribute a test reads: a list has none of it."""
    import ast
    info, reads = _analysis(source, chapter)
    for test in info.tests():
        try:
            tree = ast.parse(test.source)
        except SyntaxError:
            continue
        for node in ast.walk(tree):
            if not (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)):
                continue
            binding = reads[test.index].get(node.value.id)
            if binding is None or not binding.answer or node.attr in LIST_ATTRIBUTES:
                continue
            body = ast.parse(info.cells[binding.cell].source).body
            if any(isinstance(n, (ast.FunctionDef, ast.ClassDef)) and n.name == node.value.id for n in body):
                continue
            return {"name": node.value.id, "answer": nbg(source["cells"][binding.cell])["grade_id"],
                    "test": nbg(source["cells"][test.index])["grade_id"]}
    return None


def chapter_submissions(chapter: str, source: dict, correct: dict, run: Run) -> dict[str, dict]:
    """The knock-on and wrong-type submissions of FEEDBACK_CHAPTER."""
    out: dict[str, dict] = {}
    if chapter != FEEDBACK_CHAPTER:
        return out
    knock, wrong = knock_on_candidate(source, chapter), wrong_type_candidate(source, chapter)
    for student, probe, change in (
        ("knockon", knock, lambda code: 'raise RuntimeError("not finished")  # made by the test\n' + code),
        ("wrongtype", wrong, lambda code: code.rstrip() + f"\n{wrong['name']} = [1, 2, 3]\n" if wrong else code),
    ):
        if probe is None:
            continue
        nb = copy.deepcopy(correct)
        for cell in nb["cells"]:
            if nbg(cell).get("grade_id") == probe["answer"]:
                cell["source"] = change(src(cell))
        run.probes[student] = probe
        out[student] = nb
    return out


def notes(nb: dict) -> dict[str, str]:
    """``{grade_id: the robokin note}`` under the failing tests of a graded notebook."""
    out = {}
    for cell in nb.get("cells", []):
        for output in cell.get("outputs", []):
            text = output.get("text", "")
            text = "".join(text) if isinstance(text, list) else text
            if output.get("output_type") == "stream" and text.startswith("✘ Task"):
                out[nbg(cell).get("grade_id", "?")] = text
    return out


# ---------------------------------------------------------------- running a chapter
@dataclass
class Run:
    chapter: str
    course: Path
    source: dict = field(default_factory=dict)
    release: dict = field(default_factory=dict)
    mistake: dict | None = None
    scores: dict[str, dict[str, float]] = field(default_factory=dict)   # student -> grade_id -> score
    maximum: dict[str, float] = field(default_factory=dict)              # grade_id -> points
    feedback: dict[str, str] = field(default_factory=dict)               # student -> HTML
    autograded: dict[str, dict] = field(default_factory=dict)            # student -> graded notebook
    rounds: list[dict[str, dict[str, float]]] = field(default_factory=list)  # scores after each autograde
    probes: dict[str, dict] = field(default_factory=dict)                # student -> what was changed
    own: list[str] = field(default_factory=list)                         # this file's students
    log: list[str] = field(default_factory=list)
    error: str | None = None
    seconds: float = 0.0

    def total(self, student: str) -> float:
        return sum(self.scores.get(student, {}).values())

    def fail_message(self) -> str:
        return f"{self.chapter}: {self.error}\n" + "\n".join(self.log[-6:])


def read_gradebook(course: Path, chapter: str, run: Run) -> None:
    from nbgrader.api import Gradebook

    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gb:
        for cell in gb.find_notebook(chapter, chapter).grade_cells:
            run.maximum[cell.name] = cell.max_score
        for submission in gb.assignment_submissions(chapter):
            for notebook in submission.notebooks:
                run.scores[submission.student.id] = {g.name: g.score for g in notebook.grades}


def run_chapter(chapter: str, base: Path, suites=(), key: str | None = None) -> Run:
    """generate_assignment, the submissions, ONE autograde, generate_feedback.

    ``suites`` (tests/grading_course.py) add submissions of other test files to
    this chapter's run, with the environment and options their tests need. With
    ``key`` (a suite's own course, "<chapter>+<suite>"), the course is graded in
    a folder of that name, with the unanswered and correct submissions only
    besides the suites'.
    """
    started = time.perf_counter()
    folder = base / (key or chapter)
    course = folder / "course"
    run = Run(chapter, course)
    try:
        student_edition.write_course(course, folder / "exchange")
        student_edition.add_source(course, NOTEBOOKS / f"{chapter}.ipynb")
        nbgrader(["generate_assignment", chapter], course, run.log)
        run.source = load(course / "source" / chapter / f"{chapter}.ipynb")
        run.release = load(course / "release" / chapter / f"{chapter}.ipynb")
        correct = correct_submission(run.release, run.source)
        submissions = {"unanswered": run.release, "correct": correct}
        if key is None:   # the chapter's shared run: its typical mistake and probes too
            candidates = mistake_candidates(run.source)
            if candidates:
                run.mistake = candidates[0]
                submissions["mistake"] = mistaken_submission(correct, run.mistake)
            submissions.update(chapter_submissions(chapter, run.source, correct, run))
        run.own = list(submissions)
        environment, options = {}, []
        for suite in suites:
            extra = suite.chosen(key or chapter, suite.submissions(run, correct, course))
            clash = {s for s in extra if s in submissions and extra[s] != submissions[s]}
            assert not clash, f"{suite.name}: students {clash} are taken by another file's submissions"
            suite.students = list(extra)
            submissions.update(extra)
            environment.update(suite.environment)
            options += suite.options
        for student, nb in submissions.items():
            save(nb, course / "submitted" / student / chapter / f"{chapter}.ipynb")
        for suite in suites:
            if suite.before:
                suite.before(run, course)
        nbgrader(["autograde", chapter, *options], course, run.log, **environment)
        for suite in suites:
            if suite.after:
                suite.after(run, course)
        nbgrader(["generate_feedback", chapter], course, run.log)
        read_gradebook(course, chapter, run)
        for student in submissions:
            page = course / "feedback" / student / chapter / f"{chapter}.html"
            run.feedback[student] = page.read_text(encoding="utf-8") if page.exists() else ""
            graded_nb = course / "autograded" / student / chapter / f"{chapter}.ipynb"
            run.autograded[student] = load(graded_nb) if graded_nb.exists() else {}
        for suite in suites:
            if suite.finally_:
                suite.finally_(run, course, folder)
    except Exception as exc:  # noqa: BLE001 - reported by the tests that need it
        run.error = f"{type(exc).__name__}: {exc}"
    run.seconds = time.perf_counter() - started
    return run


# ---------------------------------------------------------------- the walk-through
def walkthrough_commands() -> list[tuple[str, str]]:
    """``[(who, command), ...]`` from the walk-through block of book/for-instructors.md."""
    text = (ROOT / "book" / "for-instructors.md").read_text(encoding="utf-8")
    m = re.search(r"<!-- walkthrough:start -->\s*```bash\n(.*?)```\s*<!-- walkthrough:end -->", text, re.S)
    assert m, "book/for-instructors.md has no walk-through block (<!-- walkthrough:start --> ... end)"
    who, out = "instructor", []
    for line in m.group(1).splitlines():
        line = line.strip()
        if line.startswith("#"):
            who = "student" if line.lower().startswith("# student") else "instructor"
        elif line.startswith("nbgrader "):
            out.append((who, line.split("  #")[0].strip()))
    return out


def run_walkthrough(base: Path) -> Run:
    chapter = WALKTHROUGH_CHAPTER
    started = time.perf_counter()
    course, exchange, home = base / "walk" / "course", base / "walk" / "exchange", base / "walk" / "student"
    run = Run(chapter, course)
    try:
        home.mkdir(parents=True)
        student_edition.write_course(course, exchange)
        student_edition.add_source(course, NOTEBOOKS / f"{chapter}.ipynb")
        nbgrader(["generate_assignment", chapter], course, run.log)   # what `make student` runs
        run.source = load(course / "source" / chapter / f"{chapter}.ipynb")
        env = {"EXCHANGE": str(exchange), "ROBOKIN_CELL_TIMEOUT": str(TIMEOUT_FOR_BAD_SUBMISSION)}
        submitted, seen_pages = 0, set()
        for who, line in walkthrough_commands():
            args = shlex.split(os.path.expandvars(line.replace("$EXCHANGE", str(exchange))))[1:]
            if args[0] == "submit":   # the student works on the fetched notebook: badly, then right
                fetched = home / chapter / f"{chapter}.ipynb"
                if submitted == 0:
                    release = load(fetched)
                    nb, what = bad_submission(correct_submission(release, run.source))
                    run.mistake = {"deleted": what["deleted"]}
                    # and leaves an answer after the deleted test as it was given (it loses points)
                    ids = [nbg(c).get("grade_id") for c in release["cells"]]
                    after = [c for c in release["cells"][ids.index(what["deleted"]) + 1:]
                             if nbg(c).get("solution")][:-1]
                    for cell in nb["cells"]:
                        if after and nbg(cell).get("grade_id") == nbg(after[0])["grade_id"]:
                            cell["source"] = src(after[0])
                else:
                    nb = correct_submission(load(fetched), run.source)
                save(nb, fetched)
                submitted += 1
            if args[0] == "collect" and "--update" in args:   # what collect does without it
                proc = nbgrader([a for a in args if a != "--update"], course, run.log, new_process=True,
                                **env)  # type: ignore[arg-type]  # env holds environment variables, never check or new_process
                run.log.append("plain collect of a resubmission: " + (proc.stdout + proc.stderr)[-2000:])
            # each command a new `nbgrader` process, as the instructor and the student type them
            nbgrader(args, home if who == "student" else course, run.log, new_process=True, **env)  # type: ignore[arg-type]  # env holds environment variables, never check or new_process
            if args[0] == "autograde":
                snapshot = Run(chapter, course)
                read_gradebook(course, chapter, snapshot)
                run.rounds.append(snapshot.scores)
            if args[0] == "fetch_feedback":
                for page in sorted((home / chapter / "feedback").rglob("*.html")):
                    if page not in seen_pages:
                        seen_pages.add(page)
                        key = "student" if "student" not in run.feedback else "resubmission"
                        run.feedback[key] = page.read_text(encoding="utf-8")
        read_gradebook(course, chapter, run)
    except Exception as exc:  # noqa: BLE001
        run.error = str(exc)
    run.seconds = time.perf_counter() - started
    return run


def run_unmarked(base: Path) -> Run:
    """A chapter without nbgrader metadata, given to make student and to nbgrader."""
    chapter = CHAPTERS[-1]
    run = Run("no-metadata", base / "bare" / "course")
    folder = base / "bare" / "notebooks"
    folder.mkdir(parents=True)
    nb = load(NOTEBOOKS / f"{chapter}.ipynb")
    for cell in nb["cells"]:
        cell.get("metadata", {}).pop("nbgrader", None)
    save(nb, folder / f"{chapter}.ipynb")
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "student_edition.py"), "--notebooks", str(folder),
                           "--course", str(run.course), chapter], capture_output=True, text=True, env=_env())
    run.log.append(f"make student: exit {proc.returncode}\n{proc.stdout}{proc.stderr}")
    student_edition.add_source(run.course, folder / f"{chapter}.ipynb")
    proc = nbgrader(["generate_assignment", chapter], run.course, run.log, check=False)
    run.log.append(f"nbgrader generate_assignment: exit {proc.returncode}")
    return run


def grade_everything(base: Path, suites=(), chapters=(), own=(), extras=()) -> dict[str, Run]:
    """The ``chapters`` generated, submitted, autograded once and given feedback, each with the
    submissions of the ``suites`` that join it (tests/grading_course.py); ``own``: the keys
    "<chapter>+<suite>" of the suites graded in a course of their own; ``extras``: "walkthrough"
    and "unmarked", the walk-through and the chapter without metadata."""
    started = time.perf_counter()
    shared = [s for s in suites if not s.own_course]
    jobs = {chapter: partial(run_chapter, chapter, base, [s for s in shared if s.joins(chapter)])
            for chapter in chapters}
    for key in own:
        chapter, name = key.split(grading_course.OWN, 1)
        jobs[key] = partial(run_chapter, chapter, base, [s for s in suites if s.name == name], key)
    extra_jobs = {"walkthrough": run_walkthrough, "unmarked": run_unmarked}
    for key in extras:
        jobs[key] = partial(extra_jobs[key], base)
    # the slow chapters first, so that the workers finish together
    order = sorted(jobs, key=lambda k: {grading_course.CHAPTER3: -1 if suites else 5, "01_leg_kinematics": 0,
                                        "05_baxter_circle": 1, "walkthrough": 2}.get(k, 5))

    with ThreadPoolExecutor(max_workers=WORKERS) as pool:
        futures = {k: pool.submit(jobs[k]) for k in order}
        runs = {k: f.result() for k, f in futures.items()}
    summary = ", ".join(f"{k} {r.seconds:.0f} s" for k, r in runs.items())
    print(f"\n[nbgrader] {len(runs)} jobs in {time.perf_counter() - started:.0f} s on {WORKERS} workers "
          f"(chapter 3 with {', '.join(s.name for s in suites) or 'no other suite'}): {summary}")
    return runs


@pytest.fixture(scope="session")
def graded(request, tmp_path_factory) -> Mapping[str, Run]:
    """Every chapter generated, submitted, autograded and given feedback (tests/grading_course.py);
    each chapter's run as this file sees it: its own submissions only."""
    return _OwnView(grading_course.graded_courses(request, tmp_path_factory))


class _OwnView(Mapping):
    """Each run of ``courses`` as this file sees it (read, and so graded, when first asked for)."""

    def __init__(self, courses) -> None:
        self.courses = courses

    def __getitem__(self, key: str) -> Run:
        run = self.courses[key]
        return grading_course.view(run, run.own) if getattr(run, "own", None) else run

    def __iter__(self):
        return iter(self.courses)

    def __len__(self) -> int:
        return len(self.courses)


def _run(graded, chapter) -> Run:
    run = graded[chapter]
    if run.error:
        pytest.fail(run.fail_message())
    return run


# ---------------------------------------------------------------- metadata
def test_metadata_is_up_to_date():
    """The committed notebooks carry the metadata tools/nbgrader_metadata.py writes."""
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "nbgrader_metadata.py"), "--check"],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, (
        "nbgrader metadata of the chapter notebooks is missing or stale; run "
        "`.venv/bin/python tools/nbgrader_metadata.py` and commit:\n" + (proc.stdout + proc.stderr)[-3000:]
    )


def test_metadata_script_writes_metadata_only_and_is_idempotent(tmp_path):
    folder = tmp_path / "notebooks"
    folder.mkdir()
    originals = {}
    for chapter in CHAPTERS:
        shutil.copy2(NOTEBOOKS / f"{chapter}.ipynb", folder)
        originals[chapter] = load(folder / f"{chapter}.ipynb")
    paths = [str(p) for p in sorted(folder.glob("*.ipynb"))]
    script = [sys.executable, str(ROOT / "tools" / "nbgrader_metadata.py")]
    first = subprocess.run(script + paths, capture_output=True, text=True)
    assert first.returncode == 0, first.stdout + first.stderr
    texts = {p: Path(p).read_text() for p in paths}
    second = subprocess.run(script + paths, capture_output=True, text=True)
    assert second.returncode == 0 and "wrote" not in second.stdout, second.stdout
    assert texts == {p: Path(p).read_text() for p in paths}, "a second run changed a notebook"
    check = subprocess.run(script + ["--check"] + paths, capture_output=True, text=True)
    assert check.returncode == 0, check.stdout
    keep = ("cell_type", "source", "outputs", "execution_count", "id")
    for chapter, original in originals.items():
        new = load(folder / f"{chapter}.ipynb")
        assert [{k: c.get(k) for k in keep} for c in new["cells"]] == \
            [{k: c.get(k) for k in keep} for c in original["cells"]], f"{chapter}: a source or output changed"
        grading = new["metadata"]["robokin"]["grading"]
        tests = [c for c in new["cells"] if nbg(c).get("grade")]
        assert grading["points"] == sum(nbg(c)["points"] for c in tests) > 0
        assert {t["task"] for t in grading["tasks"]} == {rk(c)["task"] for c in tests}, (
            f"{chapter}: a task without an autograder test")


def test_check_mode_names_the_stale_cell(tmp_path):
    chapter = CHAPTERS[0]
    nb = load(NOTEBOOKS / f"{chapter}.ipynb")
    path = tmp_path / f"{chapter}.ipynb"
    save(nb, path)
    subprocess.run([sys.executable, str(ROOT / "tools" / "nbgrader_metadata.py"), str(path)], check=True,
                   capture_output=True)
    nb = load(path)
    tests = [(i, rk(c).get("task")) for i, c in enumerate(nb["cells"])
             if "check" in c["metadata"].get("tags", []) and nbg(c).get("grade")]
    # a test of a task that has another one (a task left without a test is an error, exit 2)
    index = next(i for i, task in tests if sum(t == task for _, t in tests) > 1)
    nb["cells"][index]["metadata"]["tags"].remove("check")   # an author untags a check cell
    save(nb, path)
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "nbgrader_metadata.py"), "--check", str(path)],
                          capture_output=True, text=True)
    assert proc.returncode == 1
    assert f"{path}: cell {index} " in proc.stdout and "nbgrader metadata stale" in proc.stdout


# ---------------------------------------------------------------- 1. the student edition
def solution_lines(source: dict) -> list[str]:
    """Lines of the instructor's solution code that the student edition must not contain:
    every line of an answer cell except the ones a stub keeps (imports, signatures, docstrings)
    and the ones that also stand in a cell the student is given (a check cell may repeat a
    loop header such as ``for lam in LAMBDAS:`` of the answer it tests)."""
    given = {line.strip() for cell in source["cells"] if not nbg(cell).get("solution")
             and rk(cell).get("role") != "prose" for line in src(cell).splitlines()}
    out = []
    for cell in source["cells"]:
        if not nbg(cell).get("solution"):
            continue
        code = src(cell)
        plan = stub_plan(code, set(rk(cell).get("declare", [])))
        kept = set(plan.kept) if plan else set()
        for number, line in enumerate(code.splitlines(), 1):
            text = line.strip()
            if number in kept or text in given or len(text) < 4 or text.startswith(("#", ")", "]", "}")):
                continue
            out.append(text)
    return out


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_student_edition_has_no_solutions(graded, chapter):
    run = _run(graded, chapter)
    release = run.release
    student_code = {line.strip() for c in release["cells"] for line in src(c).splitlines()}
    leaked = [line for line in solution_lines(run.source) if line in student_code]
    assert not leaked, f"{chapter}: solution lines in the student edition: {leaked[:5]}"
    prose = [src(c).strip() for c in run.source["cells"] if rk(c).get("role") == "prose"]
    left = [p[:60] for p in prose if p and any(p in src(c) for c in release["cells"])]
    assert not left, f"{chapter}: solution prose in the student edition: {left[:3]}"
    for index, cell in enumerate(release["cells"]):
        if cell["cell_type"] == "code":
            assert not cell.get("outputs"), f"{chapter} cell {index}: outputs not cleared"
            compile(src(cell), f"{chapter} cell {index}", "exec")          # the stubs are valid Python
    stubs = [c for c in release["cells"] if nbg(c).get("solution")]
    assert stubs and all("# YOUR CODE HERE" in src(c) for c in stubs)
    # the problem, the tests and the Try-it-yourself cells are all there
    # hidden tests (### BEGIN/END HIDDEN TESTS) are left out of the student edition
    kept = [HIDDEN_TESTS.sub("", src(c)).rstrip("\n") for c in run.source["cells"]
            if not nbg(c).get("solution") and rk(c).get("role") != "prose"]
    assert kept == [src(c).rstrip("\n") for c in release["cells"] if not nbg(c).get("solution")
                    and rk(c).get("role") != "prose" and nbg(c).get("grade_id") != "robokin-points"]
    points = run.source["metadata"]["robokin"]["grading"]["points"]
    header = next(src(c) for c in release["cells"] if nbg(c).get("grade_id") == "robokin-points")
    assert f"**{points} points**" in header


@grading_course.reads("02_ur10_ik")
def test_functions_keep_their_signatures(graded):
    run = _run(graded, "02_ur10_ik") if "02_ur10_ik" in graded else pytest.skip("chapter 2 is not there")
    stub = next(src(c) for c in run.release["cells"] if "def weighted_pinv" in src(c))
    assert stub.splitlines()[:3] == ["def weighted_pinv(J, W):", "    # YOUR CODE HERE",
                                     "    raise NotImplementedError()"]


# ---------------------------------------------------------------- 2.-4. grading
@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_unanswered_scores_zero(graded, chapter):
    run = _run(graded, chapter)
    scores = run.scores.get("unanswered")
    assert scores is not None and set(scores) == set(run.maximum), f"{chapter}: not graded"
    earned = {k: v for k, v in scores.items() if v}
    assert not earned, f"{chapter}: the unanswered notebook earns points in {earned}"
    assert "Autograder report" in run.feedback["unanswered"]


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_correct_answers_score_full_marks(graded, chapter):
    run = _run(graded, chapter)
    scores = run.scores["correct"]
    missing = {k: v for k, v in scores.items() if v != run.maximum[k]}
    assert not missing, f"{chapter}: the instructor's solutions lose points in {missing}"
    page = run.feedback["correct"]
    assert "robokin.check</code> finds all" in page or "robokin.check` finds all" in page or "finds all" in page, (
        f"{chapter}: robokin.check does not accept every answer of the instructor's solution")
    assert "Notes on running your notebook" not in page, f"{chapter}: the correct notebook has errors"


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_correct_answers_print_no_failure_marks(graded, chapter):
    """A test of a correct answer prints no ✘ (a check run on a made-up wrong input inside a test
    prints one, and the student reads it as points lost): the demonstration belongs elsewhere."""
    run = _run(graded, chapter)
    marked = []
    for cell in run.autograded["correct"].get("cells", []):
        if nbg(cell).get("grade"):
            for output in cell.get("outputs", []):
                text = output.get("text", "")
                text = "".join(text) if isinstance(text, list) else text
                if "✘" in text:
                    marked.append(f"{nbg(cell)['grade_id']}: {text.strip()[:120]}")
    assert not marked, f"{chapter}: tests of the correct answers print ✘: {marked[:3]}"


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_typical_mistake_scores_partial_marks_and_is_named(graded, chapter):
    run = _run(graded, chapter)
    mistake = run.mistake
    assert mistake, f"{chapter}: no answer that robokin.check explains can be turned into a typical mistake"
    total, top = run.total("mistake"), sum(run.maximum.values())
    assert 0 < total < top, f"{chapter}: {mistake['kind']} of {mistake['name']} scores {total} of {top}"
    assert run.scores["mistake"][mistake["test"]] == 0, f"{chapter}: the test of {mistake['name']} still passes"
    page = run.feedback["mistake"]
    named = re.findall(r"typical mistake: (\w+)", page)
    assert set(named) & mistake["codes"], (
        f"{chapter}: the feedback on {mistake['kind']} of {mistake['name']} names {set(named) or 'no mistake'}")


# ---------------------------------------------------------------- 5. the walk-through and bad input
@grading_course.reads("walkthrough")
def test_walkthrough_with_a_bad_submission(graded):
    run = _run(graded, "walkthrough")
    assert run.rounds, "the walk-through has no autograde"
    scores = run.rounds[0].get(next(iter(run.rounds[0]), ""), {})   # the first submission
    assert scores and set(scores) == set(run.maximum), "the submission was not graded"
    page = run.feedback.get("student", "")
    assert "Autograder report" in page, "the student did not get the feedback"
    assert "ran longer than the time limit" in page, "the endless loop is not reported"
    assert "my own experiment went wrong" in page and "(not graded) raised" in page
    assert run.mistake is not None, "the run made no mistake to restore"
    assert f"id:{run.mistake['deleted']}" in page and "was missing from your submission" in page
    assert scores[run.mistake["deleted"]] == run.maximum[run.mistake["deleted"]], "the restored test did not run"


@grading_course.reads("unmarked")
def test_chapter_without_metadata_is_reported_by_name(graded):
    run = graded["unmarked"]
    log = "\n".join(run.log)
    chapter = CHAPTERS[-1]
    assert f"chapter {chapter} was not assigned: no nbgrader metadata" in log
    assert "nbgrader generate_assignment: exit 0" not in log
    assert f"notebook '{chapter}' has no nbgrader metadata" in log


@grading_course.reads("walkthrough")
def test_walkthrough_resubmission_is_graded_as_the_new_version(graded):
    """A second submission, collected with --update, is the one graded and fed back
    (a plain collect keeps the old one: book/for-instructors.md says so)."""
    run = _run(graded, "walkthrough")
    assert len(run.rounds) == 2, f"expected two rounds of autograde in the walk-through, got {len(run.rounds)}"
    first, second = (r.get(next(iter(r), ""), {}) for r in run.rounds)
    top = sum(run.maximum.values())
    assert sum(first.values()) < top, "the first submission (its first answer left as given) should lose points"
    assert second == run.maximum, f"the resubmission (the instructor's solutions) is graded {second}"
    assert run.scores.get(next(iter(run.scores), ""), {}) == run.maximum
    plain = next(entry for entry in run.log if entry.startswith("plain collect of a resubmission"))
    assert "use --update" in plain, "nbgrader collect without --update no longer refuses a resubmission: " + plain
    page = run.feedback.get("resubmission", "")
    assert "Autograder report" in page and "ran longer than the time limit" not in page, (
        "the student did not get the feedback on the new version")


# ---------------------------------------------------------------- 6. what the feedback says
def _answer_names(source: dict) -> set[str]:
    from tools.notebook_analysis import defined_names
    return {n for c in source["cells"] if nbg(c).get("solution") for n in defined_names(src(c))}


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_feedback_calls_only_answers_your_answers_and_quotes_whole_statements(graded, chapter):
    """Names from read-only and test cells are never "your answers"; a root cause is an
    answer; the failing statement is quoted whole (a multi-line assert too)."""
    import ast
    import textwrap

    run = _run(graded, chapter)
    answers = _answer_names(run.source)
    checked = 0
    for student, nb in run.autograded.items():
        for grade_id, note in notes(nb).items():
            checked += 1
            where = f"{chapter}, submission {student!r}, test {grade_id}"
            for line in note.splitlines():
                if line.strip().startswith(("It checks your answer", "This test failed because of")):
                    part = line.split("This test failed because of")[-1].split(":")[0]
                    named = set(re.findall(r"`([A-Za-z_]\w*)`", part if "because" in line else line))
                    assert named and named <= answers, (
                        f"{where}: {line.strip()!r} calls {sorted(named - answers)} the student's answers, "
                        f"but no answer cell defines them")
            quoted = re.search(r"failed at line \d+:\n((?:      .*\n)+)", note)
            if quoted and not quoted.group(1).rstrip().endswith("..."):
                code = textwrap.dedent(quoted.group(1))
                try:
                    ast.parse(code)
                except SyntaxError:
                    pytest.fail(f"{where}: the failing statement is not quoted whole:\n{code}")
    assert checked, f"{chapter}: no failing test with a note in any submission"


def hidden_test_lines(source: dict) -> set[str]:
    """The lines of the hidden tests of ``source`` (stripped, 4+ characters) that are not also in the
    code the student edition shows (read-only code cells outside their hidden tests)."""
    hidden, shown = set(), set()
    for cell in source["cells"]:
        for block in HIDDEN_TESTS.findall(src(cell)):
            hidden |= {line.strip() for line in block.splitlines()[1:-1] if len(line.strip()) >= 4}
        if cell["cell_type"] == "code" and not nbg(cell).get("solution"):
            shown |= {line.strip() for line in HIDDEN_TESTS.sub("", src(cell)).splitlines()}
    return hidden - shown


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_feedback_never_shows_hidden_tests(graded, chapter):
    """No line of a hidden test is in any feedback page (a student reads it before handing in
    again); a comment says where they were, and a failing test's verdict stays."""
    import html

    run = _run(graded, chapter)
    hidden = hidden_test_lines(run.source)
    has_hidden = any(HIDDEN_TESTS.search(src(c)) for c in run.source["cells"])
    for student, page in run.feedback.items():
        if not page:
            continue
        text = html.unescape(re.sub(r"<[^>]+>", "", page))
        lines = {line.strip() for line in text.splitlines()}
        leaked = sorted(hidden & lines)
        assert not leaked, f"{chapter}: the feedback page of {student!r} shows hidden tests: {leaked[:3]}"
        assert "HIDDEN TESTS" not in text, f"{chapter}: the feedback page of {student!r} shows the delimiters"
        assert not has_hidden or "hidden tests, run when grading" in text, (
            f"{chapter}: the feedback page of {student!r} does not say where the hidden tests were")
    for student, nb in run.autograded.items():
        for grade_id, note in notes(nb).items():
            quoted = "\n".join(line.strip() for line in note.splitlines())
            leaked = [line for line in hidden if line in quoted.splitlines()]
            assert not leaked, f"{chapter} {student} {grade_id}: the robokin note quotes hidden tests: {leaked}"


@pytest.mark.browser
@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_feedback_page_reads_at_laptop_width(graded, chapter, browser, tmp_path):
    """The feedback on a mistaken submission at 1280 px in Chromium: no note or traceback scrolls
    sideways, the tables have a gap between their columns, no MyST markup is shown raw."""
    run = _run(graded, chapter)
    page = tmp_path / "feedback.html"
    page.write_text(run.feedback.get("mistake") or run.feedback["correct"], encoding="utf-8")
    tab = browser.new_page(viewport={"width": 1280, "height": 900})
    try:
        tab.goto(page.as_uri())
        scrolling = tab.evaluate("""() => Array.from(document.querySelectorAll('pre'))
            .filter(e => e.scrollWidth > e.clientWidth + 1).map(e => e.textContent.slice(0, 80))""")
        gaps = tab.evaluate("""() => Array.from(document.querySelectorAll('.text_cell_render td'))
            .map(e => parseFloat(getComputedStyle(e).paddingLeft) + parseFloat(getComputedStyle(e).paddingRight))""")
        text = tab.evaluate("() => document.body.innerText")
    finally:
        tab.close()
    assert not scrolling, f"{chapter}: text that scrolls sideways at 1280 px: {scrolling[:3]}"
    assert gaps and min(gaps) >= 8, f"{chapter}: table cells without a gap between columns: {gaps[:4]}"
    raw = re.findall(r"(?:```+|:::+)\{[\w:-]+\}|\{(?:cite|doc|ref|numref|eq|admonition)\}", text)
    assert not raw, f"{chapter}: MyST markup shown raw in the feedback: {raw[:3]}"


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_released_test_cells_are_not_reported_as_changed(graded, chapter):
    """A test cell handed in as it was released (without its hidden tests) is not "changed": autograde's
    RestoreMissingCells puts its hidden tests back without nbgrader's checksum warning, and a cell
    that was changed is still reported and restored."""
    import logging

    from tools.robokin_nbgrader import RestoreMissingCells
    import nbformat

    run = _run(graded, chapter)
    warnings: list[str] = []

    class Collect(logging.Handler):
        def emit(self, record):
            warnings.append(record.getMessage())

    def overwrite(nb: dict) -> nbformat.NotebookNode:
        processor = RestoreMissingCells(add_missing_cells=True)
        processor.log.addHandler(Collect())
        processor.log.setLevel(logging.WARNING)
        resources = {"nbgrader": {"notebook": chapter, "assignment": chapter,
                                  "db_url": f"sqlite:///{run.course / 'gradebook.db'}"}}
        return processor.preprocess(nbformat.reads(json.dumps(nb), as_version=4), resources)[0]

    graded_nb = overwrite(run.release)
    assert not warnings, f"{chapter}: the released notebook handed in as it is: {warnings[:3]}"
    sources = {nbg(c).get("grade_id"): src(c) for c in run.source["cells"] if nbg(c).get("grade")}
    restored = {nbg(c).get("grade_id"): src(c) for c in graded_nb.cells if nbg(c).get("grade")}
    assert restored == sources, f"{chapter}: the test cells are not graded as the instructor wrote them"
    tampered = copy.deepcopy(run.release)
    test = next(c for c in tampered["cells"] if nbg(c).get("grade"))
    test["source"] = "pass  # the student emptied the test\n"
    restored = {nbg(c).get("grade_id"): src(c) for c in overwrite(tampered).cells if nbg(c).get("grade")}
    assert any("checksum" in w and nbg(test)["grade_id"] in w for w in warnings), (
        f"{chapter}: a changed test cell is not reported: {warnings}")
    assert restored == sources, f"{chapter}: a changed test cell is not restored"


@grading_course.reads(FEEDBACK_CHAPTER)
def test_knock_on_failure_names_the_root_cause(graded):
    """An answer cell that raises: a later task's test that needs its names says so."""
    if FEEDBACK_CHAPTER not in graded:
        pytest.skip("no chapter graded here")
    run = _run(graded, FEEDBACK_CHAPTER)
    probe = run.probes.get("knockon")
    assert probe, f"{FEEDBACK_CHAPTER}: no test of a later task reads an answer of an earlier one"
    note = notes(run.autograded["knockon"]).get(probe["test"])
    assert note, f"{FEEDBACK_CHAPTER}: {probe['test']} does not fail without {probe['name']} (Task {probe['task']})"
    cause = re.search(r"This test failed because of (.*?)\. Fix that first", note)
    assert cause and f"`{probe['name']}`" in cause.group(1) and f"(Task {probe['task']}): " in cause.group(1) \
        and "raised RuntimeError" in cause.group(1), (
        f"{FEEDBACK_CHAPTER} {probe['test']}: the note does not name {probe['name']} (Task {probe['task']}), "
        f"whose answer cell raised, as the root cause:\n{note}")
    page = run.feedback["knockon"]
    assert "Where to start" in page and f"<code>{probe['name']}</code>" in page


@grading_course.reads(FEEDBACK_CHAPTER)
def test_wrong_type_says_what_came_and_what_was_expected(graded):
    if FEEDBACK_CHAPTER not in graded:
        pytest.skip("no chapter graded here")
    run = _run(graded, FEEDBACK_CHAPTER)
    probe = run.probes.get("wrongtype")
    assert probe, f"{FEEDBACK_CHAPTER}: no test reads an attribute of an answer variable"
    note = notes(run.autograded["wrongtype"]).get(probe["test"], "")
    name = probe["name"]
    # in the note's own words, or in robokin.check's when a check describes the answer
    said = re.search(rf"Your `{name}` is a list of 3 items; expected: .+"
                     rf"|{name} is a list of 3 items; expected .+", note)
    assert f"{name}` is a list of 3 items" in note or f"{name} is a list of 3 items" in note, (
        f"{FEEDBACK_CHAPTER}: the note does not say what {name} is:\n{note}")
    assert said, (
        f"{FEEDBACK_CHAPTER}: the note does not say what {name} should be (document `{name}` in the task "
        f"statement, in backticks, or in the stub):\n{note}")


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_feedback_renders_formulas_offline(graded, chapter):
    run = _run(graded, chapter)
    page = run.feedback["correct"]
    remote = [url for url in re.findall(r"<script[^>]*\bsrc=[\"']([^\"']+)", page, re.I)
              if "mathjax" in url.lower() or url.startswith(("http:", "https:", "//"))]
    assert not remote, f"{chapter}: the feedback page loads scripts from the network: {remote}"
    assert 'id="robokin-mathjax"' in page and "MathJax" in page, f"{chapter}: no inline MathJax in the feedback"
    assert "text/x-mathjax-config" not in page, f"{chapter}: MathJax 2 configuration left in the feedback"


@pytest.mark.parametrize("template", ["classic", "lab"])
def test_feedback_exporter_writes_nbconvert_page(template):
    """The feedback exporter's page is nbconvert's HTMLExporter page, byte for byte, with MathJax
    inlined: its memoised highlighting and markdown change nothing (twice, so that the second page
    is made from the memo; "lab" has the JupyterLab cells)."""
    import nbformat
    from nbconvert.exporters import HTMLExporter
    from tools.robokin_nbgrader import OfflineMathJaxHTMLExporter, inline_mathjax

    pixel = ("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==")
    nb = nbformat.v4.new_notebook(metadata={"language_info": {"name": "python", "pygments_lexer": "ipython3"}})
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: a formula $T_{BA} = T_{AB}^{-1}$ and `code` <b>bold</b> &amp;"),
        nbformat.v4.new_code_cell("import numpy as np\n\ndef f(q):\n    return np.sin(q) @ q  # a comment\n",
                                  outputs=[nbformat.v4.new_output("display_data", {"image/png": pixel}),
                                           nbformat.v4.new_output("stream", name="stdout", text="<x> & 'y'\n"),
                                           nbformat.v4.new_output("error", ename="ValueError", evalue="bad",
                                                                  traceback=["\x1b[31mValueError\x1b[0m: bad"])]),
        nbformat.v4.new_code_cell("%%bash\necho hi", metadata={"magics_language": "bash"}),
    ]
    for _ in range(2):
        ours = OfflineMathJaxHTMLExporter(template_name=template).from_notebook_node(copy.deepcopy(nb))[0]
        plain = HTMLExporter(template_name=template).from_notebook_node(copy.deepcopy(nb))[0]
        assert ours == inline_mathjax(plain)
    assert ("tabindex=\"0\"" in plain) == (template == "lab") and 'alt="No description' in plain


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_points_per_test_in_header_and_report(graded, chapter):
    """A test cell tagged points-N is worth N: in the gradebook, the student edition's header
    and the report's table."""
    run = _run(graded, chapter)
    per_task: dict[int, float] = {}
    for cell in run.source["cells"]:
        if nbg(cell).get("grade"):
            per_task[rk(cell)["task"]] = per_task.get(rk(cell)["task"], 0) + nbg(cell)["points"]
            assert run.maximum[nbg(cell)["grade_id"]] == nbg(cell)["points"], f"{chapter}: gradebook points"
    header = next(src(c) for c in run.release["cells"] if nbg(c).get("grade_id") == "robokin-points")
    report = src(run.autograded["correct"]["cells"][0])
    for task, points in per_task.items():
        assert re.search(rf"\| Task {task}: [^|]*\| {points:g} \|", header), (
            f"{chapter}: the student edition's header does not give Task {task} {points:g} points:\n{header}")
        assert re.search(rf"\| Task {task}: [^|]*\| {points:g} / {points:g} \|", report), (
            f"{chapter}: the report does not give Task {task} {points:g} of {points:g} points:\n{report}")


@pytest.mark.parametrize("chapter", grading_course.chapter_params(CHAPTERS))
def test_student_edition_is_what_the_contract_test_predicts(graded, chapter):
    """tests/test_student_edition_contracts.py computes the student edition statically: the
    stubs and the cells left out must be what generate_assignment makes."""
    from tools.notebook_analysis import stub_source

    run = _run(graded, chapter)
    stubs = {nbg(c)["grade_id"]: stub_source(src(c), set(rk(c).get("declare", [])))
             for c in run.source["cells"] if nbg(c).get("solution")}
    for cell in run.release["cells"]:
        grade_id = nbg(cell).get("grade_id")
        if grade_id in stubs:
            assert src(cell) == stubs[grade_id], f"{chapter} {grade_id}: the stub differs from stub_source"
    empty = [i for i, c in enumerate(run.release["cells"]) if c["cell_type"] == "markdown" and not src(c).strip()]
    assert not empty, f"{chapter}: empty markdown cells in the student edition: {empty}"
    from tools.notebook_analysis import analyse, student_markdown
    predicted = {}
    for info, cell in zip(analyse(NOTEBOOKS / f"{chapter}.ipynb", run.source).cells, run.source["cells"]):
        if info.cell_type == "markdown":
            predicted[nbg(cell).get("grade_id")] = student_markdown(info)
    released = {nbg(c).get("grade_id"): src(c) for c in run.release["cells"] if c["cell_type"] == "markdown"}
    for grade_id, text in predicted.items():
        assert released.get(grade_id) == text, (
            f"{chapter} {grade_id}: the student edition's text differs from student_markdown:\n"
            f"{released.get(grade_id)!r}\n{text!r}")


def test_failure_notes_trace_the_root_cause_without_a_kernel():
    """FailureNotes on a made-up graded notebook: a given value is not "your answer", the
    earlier answer whose own test failed is the root cause, and the whole assert is quoted."""
    import nbformat

    from tools.robokin_nbgrader import FailureNotes

    def code(source, grade_id=None, solution=False, grade=False, task=None, outputs=()):
        cell = nbformat.v4.new_code_cell(source)
        if grade_id:
            cell.metadata["nbgrader"] = {"grade_id": grade_id, "solution": solution, "grade": grade,
                                         "locked": not solution, "points": 1, "schema_version": 3}
            cell.metadata["robokin"] = {"task": task}
        cell.outputs = [nbformat.from_dict(o) for o in outputs]
        return cell

    def error(ename, count, line):
        return {"output_type": "error", "ename": ename, "evalue": "", "traceback": [
            f"Cell In[{count}], line {line}"]}

    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: f"),
        code("def f(x):\n    return x + 1", "task1_answer1", solution=True, task=1),
        code("assert f(1) == 2", "task1_test1", grade=True, task=1, outputs=[error("AssertionError", 2, 1)]),
        nbformat.v4.new_markdown_cell("## Task 2: g"),
        code("J0 = 2.0\nscale = f(J0)", "cell-given"),
        code("g = scale * 3", "task2_answer1", solution=True, task=2),
        code("limit = 9.0\nassert abs(\n    g - limit\n) < 1e-9", "task2_test1", grade=True, task=2),
    ]
    nb.cells[2].execution_count = 2
    nb.cells[6].execution_count = 5
    failure = nbformat.from_dict(error("AssertionError", 5, 2))
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    notes_ = FailureNotes(nb, 6, report)
    assert notes_.pairs(failure) == []
    text = "\n".join(notes_.lines(failure, []))
    assert "      assert abs(\n          g - limit\n      ) < 1e-9" in text, text
    assert "It checks your answer `g` (Task 2)." in text, text
    assert "`limit`" not in text and "`J0`" not in text, text      # not the student's
    assert "This test failed because of `f` (Task 1): its own test task1_test1 failed." in text, text
    assert [(c["names"], c["tests"]) for c in report["causes"].values()] == [(["f"], ["task2_test1"])]
