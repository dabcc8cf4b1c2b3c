"""The graded courses of the nbgrader suites: building a chapter's course, its submissions, one
``nbgrader autograde`` run per course, and reading the gradebook (tests/test_nbgrader.py says what
the suites check; tests/support/grading_course.py how the runs are shared).

Everything goes through nbgrader's real command-line tools and its sqlite gradebook, in temporary
course directories (one per chapter). ``ROBOKIN_NBGRADER_NOTEBOOKS=<folder>`` grades the notebooks
of another folder instead (e.g. a copy the metadata script was run on).
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
from concurrent.futures import ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

from conftest import ROOT
from support import grading_course, installed
from support import nbgrader_runner
from tools.authoring import nbgrader_metadata, student_edition
from tools.notebook_analysis import free_names

installed.require("nbgrader", "nbgrader is not installed: run `make test` (installs requirements.txt)")
# The graded courses are built in two parts, one xdist group each (tests/support/grading_course.py):
# each test that reads a run is marked with its part (grading_course.reads, chapter_params).

NOTEBOOKS = Path(os.environ.get("ROBOKIN_NBGRADER_NOTEBOOKS", ROOT / "notebooks")).resolve()
CHAPTERS = [p.stem for p in nbgrader_metadata.chapter_notebooks(NOTEBOOKS.parent, NOTEBOOKS.name)]
#: the chapter of the instructors' walk-through: book/for-instructors.md quotes its commands for it.
#: The everyday chapter (tests/support/tiers.py), the cheapest to grade: about 5 CPU-s a
#: submission where chapter 3's cost 16-27 (sympy, scipy, three figures)
WALKTHROUGH_CHAPTER = "07_ur10_closed_form"
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
    (tests/support/nbgrader_runner.py: about 1.1 s of CPU less per command); with
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


def code_cell(source: str, grade_id: str | None = None, solution: bool = False, grade: bool = False,
              task: int | None = None, count: int | None = None, outputs=()):
    """A code cell of a made-up notebook: with a ``grade_id``, nbgrader's metadata (one point,
    locked unless a ``solution``) and robokin's ``task``; its execution ``count`` and ``outputs``."""
    import nbformat

    cell = nbformat.v4.new_code_cell(source, execution_count=count)
    if grade_id:
        cell.metadata["nbgrader"] = {"grade_id": grade_id, "solution": solution, "grade": grade,
                                     "locked": not solution, "points": 1, "schema_version": 3}
        cell.metadata["robokin"] = {"task": task}
    cell.outputs = [nbformat.from_dict(o) for o in outputs]
    return cell


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
    """Raises in an ungraded cell, runs forever in an answer, and lost its first test cell.

    The cell that raises is one of the student's own, added before the last answer: the student's
    kernel stops after the last cell that is graded or holds an answer, so a *Try it yourself*
    cell after it (chapter 7's only one) would not be run.
    """
    nb = copy.deepcopy(correct)
    cells = nb["cells"]
    answers = [c for c in cells if nbg(c).get("solution")]
    tests = [c for c in cells if nbg(c).get("grade")]
    own: dict = {"cell_type": "code", "metadata": {}, "outputs": [], "execution_count": None,
                 "source": 'raise ValueError("my own experiment went wrong")\n'}
    if "id" in answers[-1]:
        own["id"] = "my-own-experiment"
    cells.insert(cells.index(answers[-1]), own)
    what = {"raises": own, "loops": answers[-1], "deleted": nbg(tests[0])["grade_id"]}
    # it sleeps: to the grader the same endless cell as a busy loop, interrupted at the time
    # limit, but the wait costs no CPU. At the top of the cell: the loop runs even where the
    # answer reads a name that an earlier answer, left as given, never defined
    answers[-1]["source"] = "import time\n\nwhile True:  # never ends\n    time.sleep(0.5)\n\n" + src(answers[-1])
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


#: Grades the submissions of the suites graded apart (:attr:`grading_course.Suite.apart`) beside
#: the chapters' shared runs: one thread per job a pytest process grades at a time, kept for
#: the session so that each keeps its nbgrader runner (tests/support/nbgrader_runner.py).
_APART = ThreadPoolExecutor(max_workers=WORKERS, thread_name_prefix="nbgrader-apart")


def copy_course(course: Path, copy: Path, chapter: str) -> None:
    """A course in ``copy`` in which ``chapter`` is assigned as in ``course`` (its gradebook,
    ``source/`` and ``release/``, as tools/grading/grade_submission.py copies a template course),
    with no submission."""
    student_edition.write_course(copy, copy.parent / "exchange")
    shutil.copy2(course / "gradebook.db", copy / "gradebook.db")
    for part in ("source", "release"):
        shutil.copytree(course / part / chapter, copy / part / chapter)


def grade(chapter: str, course: Path, log: list[str], options: list[str], environment: dict) -> None:
    """``nbgrader autograde`` and ``generate_feedback`` of ``chapter`` in ``course``."""
    nbgrader(["autograde", chapter, *options], course, log, **environment)
    nbgrader(["generate_feedback", chapter], course, log)


def run_chapter(chapter: str, base: Path, suites=(), key: str | None = None) -> Run:
    """generate_assignment, the submissions, ONE autograde, generate_feedback.

    ``suites`` (tests/support/grading_course.py) add submissions of other test files to
    this chapter's run, with the environment and options their tests need; those of a
    suite graded apart go to a copy of the course, autograded at the same time. With
    ``key`` (a suite's own course, "<chapter>+<suite>"), the course is graded in
    a folder of that name, with the correct submission only besides the suites'
    (the unanswered one, graded in the chapter's shared run, only when a suite
    hands it in among its own).
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
        submissions = {"correct": correct} if key else {"unanswered": run.release, "correct": correct}
        if key is None:   # the chapter's shared run: its typical mistake and probes too
            candidates = mistake_candidates(run.source)
            if candidates:
                run.mistake = candidates[0]
                submissions["mistake"] = mistaken_submission(correct, run.mistake)
            submissions.update(chapter_submissions(chapter, run.source, correct, run))
        run.own = list(submissions)
        environment, options = {}, []
        apart: dict[str, dict] = {}                  # the submissions of the suites graded apart
        apart_environment, apart_options = {}, []
        for suite in suites:
            extra = suite.chosen(key or chapter, suite.submissions(run, correct, course))
            clash = {s for s in extra if s in submissions and extra[s] != submissions[s]}
            assert not clash, f"{suite.name}: students {clash} are taken by another file's submissions"
            suite.students = list(extra)
            submissions.update(extra)
            if suite.apart:
                apart.update(extra)
                apart_environment.update(suite.environment)
                apart_options += suite.options
            else:
                environment.update(suite.environment)
                options += suite.options
        courses = {student: folder / "apart" if student in apart else course for student in submissions}
        if apart:
            copy_course(course, folder / "apart", chapter)
        for student, nb in submissions.items():
            save(nb, courses[student] / "submitted" / student / chapter / f"{chapter}.ipynb")
        for suite in suites:
            if suite.before:
                suite.before(run, course)
        apart_log: list[str] = []
        graded_apart = _APART.submit(grade, chapter, folder / "apart", apart_log, apart_options,
                                     apart_environment) if apart else None
        try:
            nbgrader(["autograde", chapter, *options], course, run.log, **environment)
            for suite in suites:
                if suite.after:
                    suite.after(run, course)
            nbgrader(["generate_feedback", chapter], course, run.log)
        finally:
            if graded_apart is not None:
                wait([graded_apart])
                run.log += apart_log
        if graded_apart is not None:
            graded_apart.result()
            read_gradebook(folder / "apart", chapter, run)
        read_gradebook(course, chapter, run)
        for student, graded_in in courses.items():
            page = graded_in / "feedback" / student / chapter / f"{chapter}.html"
            run.feedback[student] = page.read_text(encoding="utf-8") if page.exists() else ""
            graded_nb = graded_in / "autograded" / student / chapter / f"{chapter}.ipynb"
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
        # JUPYTER_DATA_DIR: the student's nbgrader_cache (submit keeps a copy there, fetch_feedback
        # reads it) in this run's folder, not the home directory of whoever runs the tests
        env = {"EXCHANGE": str(exchange), "ROBOKIN_CELL_TIMEOUT": str(TIMEOUT_FOR_BAD_SUBMISSION),
               "JUPYTER_DATA_DIR": str(base / "walk" / "jupyter_data")}
        submitted, seen_pages, typed = 0, set(), set()
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
                proc = nbgrader([a for a in args if a != "--update"], course, run.log,
                                **env)  # type: ignore[arg-type]  # env holds environment variables, never check or new_process
                run.log.append("plain collect of a resubmission: " + (proc.stdout + proc.stderr)[-2000:])
            # the first command of the instructor and of the student a new `nbgrader` process, the console
            # script as they type it; the others forked from the runner, which calls the same `main()` in
            # the same folder and environment (about 1.1 CPU-s of imports less per command, 15 commands)
            first = who not in typed
            typed.add(who)
            nbgrader(args, home if who == "student" else course, run.log, new_process=first,
                     **env)  # type: ignore[arg-type]  # env holds environment variables, never check or new_process
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
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "authoring" / "student_edition.py"),
                           "--notebooks", str(folder), "--course", str(run.course), chapter],
                          capture_output=True, text=True, env=_env())
    run.log.append(f"make student: exit {proc.returncode}\n{proc.stdout}{proc.stderr}")
    student_edition.add_source(run.course, folder / f"{chapter}.ipynb")
    proc = nbgrader(["generate_assignment", chapter], run.course, run.log, check=False)
    run.log.append(f"nbgrader generate_assignment: exit {proc.returncode}")
    return run


def grade_everything(base: Path, suites=(), chapters=(), own=(), extras=()) -> dict[str, Run]:
    """The ``chapters`` generated, submitted, autograded once and given feedback, each with the
    submissions of the ``suites`` that join it (tests/support/grading_course.py); ``own``: the keys
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
    order = sorted(jobs, key=lambda k: {grading_course.EVERYDAY_CHAPTER: -1 if suites else 5, "01_leg_kinematics": 0,
                                        "05_baxter_circle": 1, "walkthrough": 2}.get(k, 5))

    with ThreadPoolExecutor(max_workers=WORKERS) as pool:
        futures = {k: pool.submit(jobs[k]) for k in order}
        runs = {k: f.result() for k, f in futures.items()}
    summary = ", ".join(f"{k} {r.seconds:.0f} s" for k, r in runs.items())
    print(f"\n[nbgrader] {len(runs)} jobs in {time.perf_counter() - started:.0f} s on {WORKERS} workers "
          f"({grading_course.EVERYDAY_CHAPTER} with {', '.join(s.name for s in suites) or 'no other suite'}): "
          f"{summary}")
    return runs
