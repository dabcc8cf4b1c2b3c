"""Grading an instructor can trust (book/for-instructors.md, "What grading guarantees").

Crafted submissions go through the course's own pipeline (the course built as in
tests/test_nbgrader.py, then ``nbgrader autograde``, ``generate_feedback`` and
``export``), each in its chapter's job (tests/support/grading_course.py): the everyday
chapter's in its ONE autograde run, with the submissions of test_nbgrader.py; every other
chapter's by an autograde of its own beside that run:

benign, the everyday chapter (tests/support/tiers.py: chapter 7, the UR10's closed form; the
instructor's solutions, plus ...) -- each keeps full marks:
    ``noisy``   answers that log (``logging.warning``), warn (``RuntimeWarning``),
                print to stderr and use helpers of their own, called by the tests,
                and a post-run hook that shows a number (``0.0``) under every cell,
                which nbgrader would take for partial credit; and ``os._exit(1)`` in a
                cell of the student's own after the first test (the kernel dies);
    ``hang``    answers written another way (tests/support/benign_variants.py: other
                intermediate names, another valid method), and a loop that ignores
                SIGINT in a cell of the student's own after the first test (the kernel
                is killed at the time limit); in both, tests come after that cell: the
                kernel is restarted, the cells before are run again, the tests after it
                keep their points, and the report names the incident. ``hang`` also ends
                its ungraded *Try it yourself* cell, after the last test, with
                ``os._exit(1)``: nothing after the last graded cell is run, so it costs
                nothing and takes no time, and the feedback says why those cells have no
                outputs;
benign, every other chapter (graded apart, beside that chapter's shared run), one submission:
    ``written_talkative``
                answers written another way (tests/support/benign_variants.py: other
                intermediate names, another valid method), made talkative by one function
                (:func:`talkative`): every answer cell logs and prints to stderr once,
                and wraps each function it declares in one that logs, warns, prints to
                stderr and calls a helper of its own on its first calls; a cell that
                never ends at the end of an earlier ungraded cell (the *Try it yourself*
                cell before the last, or, in a chapter with one, a cell of the student's
                own after the first test: interrupted at the time limit, ``OTHER_TIMEOUT``
                s in these runs, and the tests after it show that the notebook went on);
                and its kernel dies (``os._exit``) at the end of the last *Try it
                yourself* cell -- where tests follow (chapters 4, 5 and 10), the kernel is
                restarted and the cells before are run again (the stopped cell
                excepted); elsewhere that cell comes after the last graded one and is not
                run (nothing after the last graded cell is). One submission, not one per
                property: each costs a full execution of the notebook and its grading
                (8-28 CPU-s), and every check of both properties reads it;
sandbox:
    ``escape``  the solutions, and a cell of the student's own (after the first test: the
                student's kernel runs it) that writes outside its folder, reads the
                instructor's source notebook, the repository's notebook and the gradebook
                and prints what it got, and leaves a detached process behind that keeps
                trying to rewrite ``gradebook.db``.

The hangs sleep: waiting for the time limit costs no CPU, and to the grader they are
the same incidents as busy loops. The sandbox needs ``bwrap`` (Debian package
``bubblewrap``): without it the tests skip locally and fail on CI (``CI=true``), which
installs it (``.ci/run``).
"""

from __future__ import annotations

import csv
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from conftest import ROOT
from support.nbgrader_course import (
    CHAPTERS,
    NOTEBOOKS,
    Run,
    load,
    nbg,
    nbgrader,
    rk,
    src,
)
from support import grading_course
from support.benign_variants import (
    CRASH,
    HANG,
    VARIANTS,
    last_try_cell,
    with_earlier_hang,
    with_incident,
    with_own_cell,
    written_another_way,
)
from tools.grading.sandbox import PACKAGE, SWITCH, bwrap_executable, python_folders, sandbox_arguments, sandbox_wanted

# The tests that read a run are marked with its part of the graded courses (one xdist group each):
# grading_course.reads(CHAPTER) for the everyday chapter's, chapter_params for the others.

CHAPTER = grading_course.EVERYDAY_CHAPTER
#: seconds per cell in the everyday chapter's run: the hang is killed after it (+ nbclient's 4 s
#: for the interrupt). Every other submission of that run (the solutions too) must finish each
#: cell in it: chapter 7's slowest cells, the imports and the 100 runs of solve_ik, take 1-2 s on
#: a quiet machine and 5 s at a load average of 15 (chapter 3's imports passed a former 10 s at a
#: load average of 16, and its correct submission then lost points), so the limit is the other
#: chapters' 30 s, a ceiling load does not reach; it costs the hang's wait.
TIMEOUT = 30
OTHER_TIMEOUT = 30    # seconds per cell in the other chapters' runs (their longest cells, with a margin)
TOKEN = "robokin-test-token-4f1c"   # a secret in the grader's environment
ATTACK_DELAY = 1.0    # the escape's detached process tries every ATTACK_DELAY seconds
#: seconds the escape's cell waits for its detached process to start (a Python start: 0.05-0.1 s on
#: a quiet machine, under 2 s at a load average of 15), well within the cell limit TIMEOUT
ESCAPE_WAIT = 15.0


def _require_bwrap() -> None:
    if shutil.which("bwrap") is None:
        message = f"bwrap is not installed (Debian package {PACKAGE})"
        if os.environ.get("CI"):
            pytest.fail(f"{message}: CI must install it (.ci/run) and run these tests")
        pytest.skip(message)


# ---------------------------------------------------------------- the submissions
NOISY = '''

import logging
import sys
import warnings


def _my_distance(x, y):  # a helper of my own
    return np.sqrt(x**2 + y**2)


def shoulder_angles(T, wrist_centre=wrist_centre):  # the same answer, talkative
    logging.warning("shoulder_angles called")
    print("debugging shoulder_angles", file=sys.stderr)
    x, y, _ = wrist_centre(T)
    r = _my_distance(x, y)
    if r < abs(D4):
        return np.zeros(0)
    psi, beta = np.arctan2(y, x), np.arccos(D4 / r)
    if psi < 0:  # the target's wrist centre has psi = -0.42 rad
        warnings.warn("a negative angle", RuntimeWarning)
    return wrap([psi + np.pi / 2 + beta, psi + np.pi / 2 - beta])
'''

HOOKED = '''

def _show_zero(result):  # shows 0.0 as the result of every cell that runs after this one
    get_ipython().displayhook(0.0)


get_ipython().events.register("post_run_cell", _show_zero)
'''

#: a cell that never ends and ignores the interrupt (it sleeps: the wait for the time limit costs no
#: CPU, and to the grader it is the same incident as a busy loop: the kernel is killed at the limit)
HANG_IGNORING_SIGINT = '''import signal
import time

signal.signal(signal.SIGINT, signal.SIG_IGN)
while True:  # my experiment never ends, and ignores the interrupt
    time.sleep(0.5)
'''

ESCAPE = '''import os
import subprocess
import sys

for target in {targets!r}:
    try:
        with open(target, "w") as f:
            f.write("escaped")
        print("WRO" "TE", target)
    except OSError as error:
        print("WRITE" "-BLOCKED", target, type(error).__name__)
print("TOKEN", os.environ.get("JUPYTERHUB_API_TOKEN", "absent"))
for secret in {secrets!r}:
    try:
        with open(secret, "rb") as f:
            print("SECRET" "-READ", f.read()[:3000])
    except OSError as error:
        print("SECRET" "-BLOCKED", type(error).__name__)
ATTACK = """
import os, sqlite3, sys, time
os.setsid()
if os.fork():
    sys.exit(0)
for _ in range(600):
    with open("alive.txt", "w") as f:
        f.write(str(time.time()))
    try:
        db = sqlite3.connect({gradebook!r})
        db.execute("UPDATE grade SET auto_score = 0")
        db.commit()
        db.close()
    except Exception:
        pass
    time.sleep({delay!r})
"""
subprocess.Popen([sys.executable, "-c", ATTACK], stdin=subprocess.DEVNULL,
                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
# the cell ends once the detached process has run (alive.txt written): where the rest of the
# notebook grades in under a second (chapter 7), the kernel could otherwise be gone before a new
# Python has started, and the test would test nothing. At most ESCAPE_WAIT s, within the cell limit.
import time
for _ in range(int({wait!r} / 0.05)):
    if os.path.exists("alive.txt"):
        break
    time.sleep(0.05)
'''


def _with_answer_code(nb: dict, grade_id: str, code: str) -> dict:
    nb = json.loads(json.dumps(nb))
    cell = next(c for c in nb["cells"] if nbg(c).get("grade_id") == grade_id)
    cell["source"] = src(cell).rstrip() + "\n" + code
    return nb


def submissions(correct: dict, course: Path) -> dict[str, dict]:
    gradebook = course / "gradebook.db"
    escape = ESCAPE.format(
        targets=[str(course / "escaped.txt"), str(course / "submitted" / "correct" / "escaped.txt"),
                 str(ROOT / "escaped.txt"), str(Path.home() / "robokin-escaped.txt"), "/tmp/robokin-escaped.txt"],
        secrets=[str(course / "source" / CHAPTER / f"{CHAPTER}.ipynb"), str(NOTEBOOKS / f"{CHAPTER}.ipynb"),
                 str(gradebook)],
        gradebook=str(gradebook), delay=ATTACK_DELAY, wait=ESCAPE_WAIT)
    return {
        "noisy": with_own_cell(_with_answer_code(correct, "task1_answer1", NOISY + HOOKED), CRASH),
        "hang": with_incident(with_own_cell(written_another_way(correct, CHAPTER), HANG_IGNORING_SIGINT), CRASH),
        "escape": with_own_cell(correct, escape),
    }


#: how many calls of each function of a ``noisy`` submission log, warn and write to stderr: in
#: the student's kernel and again in the grader kernel's calls. Every call talking made chapter
#: 5's run grade ~40,000 messages (80 CPU-s, three times its solution's); a flood of output is
#: tested on its own (test_grading_tamper: cells that printed thousands of lines;
#: test_kernel_sockets: 12,000 lines), so here the talk shows that talking costs no marks.
TALKING_CALLS = 20
#: appended to every answer cell of a chapter's ``noisy`` submission (:func:`talkative`)
TALKATIVE = """

import functools
import logging
import sys
import warnings


def _my_identity(value):  # a helper of my own
    return value


def _talkative(function):
    calls = []

    @functools.wraps(function)
    def talking(*args, **kwargs):
        calls.append(None)
        if len(calls) <= {talking_calls}:  # a student's debugging prints of the first calls
            logging.warning("noisy: %s called", function.__name__)
            warnings.warn(f"noisy: {{function.__name__}} warns", RuntimeWarning, stacklevel=2)
            print(f"noisy: debugging {{function.__name__}}", file=sys.stderr)
        return _my_identity(function(*args, **kwargs))

    return talking


{wraps}print("noisy: cell {grade_id} ran", file=sys.stderr)
logging.warning("noisy: cell %s logged", {grade_id!r})
"""


def declared_functions(cell: dict) -> list[str]:
    """The functions an answer cell of the instructor's source declares (``def`` at its top level)."""
    import ast

    declared = set(rk(cell).get("declare", []))
    return [node.name for node in ast.parse(src(cell)).body
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name in declared]


def talkative(correct: dict, source: dict) -> dict:
    """``correct`` with every answer cell made talkative (:data:`TALKATIVE`)."""
    nb = json.loads(json.dumps(correct))
    functions = {nbg(c)["grade_id"]: declared_functions(c) for c in source["cells"] if nbg(c).get("solution")}
    for cell in nb["cells"]:
        grade_id = nbg(cell).get("grade_id")
        if grade_id in functions:
            wraps = "".join(f"{name} = _talkative({name})\n" for name in functions[grade_id])
            cell["source"] = src(cell).rstrip() + "\n" + TALKATIVE.format(wraps=wraps, grade_id=grade_id,
                                                                             talking_calls=TALKING_CALLS)
    return nb


def _outside_targets(course: Path) -> list[Path]:
    # another student's folder: "correct", which every run of the chapter grades
    return [course / "escaped.txt", course / "submitted" / "correct" / "escaped.txt", ROOT / "escaped.txt",
            Path.home() / "robokin-escaped.txt", Path("/tmp/robokin-escaped.txt")]


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _before(run: Run, course: Path) -> None:
    for target in _outside_targets(course):   # left by an earlier run that escaped
        target.unlink(missing_ok=True)
    # without bwrap on PATH autograde refuses to grade, naming the package
    no_bwrap = nbgrader(["autograde", CHAPTER, "--student", "correct"], course, run.log, check=False,
                        PATH=str(Path(sys.executable).parent))
    run.refused = (no_bwrap.returncode, no_bwrap.stdout + no_bwrap.stderr)  # type: ignore[attr-defined]  # the job's hooks keep their findings on the Run


def _after(run: Run, course: Path) -> None:
    run.gradebook_digest = _digest(course / "gradebook.db")  # type: ignore[attr-defined]  # the job's hooks keep their findings on the Run
    alive = course / "autograded" / "escape" / CHAPTER / "alive.txt"
    run.alive_before = alive.read_text() if alive.exists() else None  # type: ignore[attr-defined]  # the job's hooks keep their findings on the Run
    time.sleep(3 * ATTACK_DELAY)   # a process left behind would rewrite the gradebook by now
    run.alive_after = alive.read_text() if alive.exists() else None  # type: ignore[attr-defined]  # the job's hooks keep their findings on the Run
    run.gradebook_after = _digest(course / "gradebook.db")  # type: ignore[attr-defined]  # the job's hooks keep their findings on the Run


def _export(run: Run, course: Path, base: Path) -> None:
    nbgrader(["export", "--to", str(base / "grades.csv")], course, run.log)
    with open(base / "grades.csv", newline="") as f:
        exported = {row["student_id"]: float(row["raw_score"]) for row in csv.DictReader(f)
                    if row["assignment"] == CHAPTER}
    run.exported = exported  # type: ignore[attr-defined]  # the job's hooks keep their findings on the Run


#: this file's submissions, graded in the everyday chapter's one autograde run (tests/support/grading_course.py),
#: with a time limit of TIMEOUT s per cell and a secret in the grader's environment
SUITE = grading_course.Suite(
    "trust", lambda run, correct, course: submissions(correct, course),
    environment={"ROBOKIN_CELL_TIMEOUT": str(TIMEOUT), "JUPYTERHUB_API_TOKEN": TOKEN},
    before=_before, after=_after, finally_=_export)


#: every other chapter's one benign submission: correct answers written another way, talkative,
#: a hang in an earlier ungraded cell and a crash in the last (the module's docstring)
BENIGN = "written_talkative"


def benign_submissions(run: Run, correct: dict) -> dict[str, dict]:
    """Every other chapter's benign submission: written another way and talkative, hanging, then crashing.

    The answers of :data:`VARIANTS` are re-computed first, then every answer cell is made
    talkative, so that the talkative wrappers wrap the functions written another way. It is
    graded apart (:data:`NOISY_SUITE`): its wait for the time limit overlaps the chapter's
    shared run."""
    merged = talkative(written_another_way(correct, run.chapter), run.source)
    return {BENIGN: with_incident(with_earlier_hang(merged, HANG), CRASH)}


#: the benign submission of every other chapter, graded in that chapter's job by an autograde
#: of its own, beside the shared run (grading_course.Suite.apart), with a time limit of
#: OTHER_TIMEOUT s per cell (the hang waits that long)
NOISY_SUITE = grading_course.Suite(
    "trust-benign", lambda run, correct, course: benign_submissions(run, correct),
    environment={"ROBOKIN_CELL_TIMEOUT": str(OTHER_TIMEOUT)},
    joins=lambda chapter: chapter != CHAPTER, apart=True)
SUITES = (SUITE, NOISY_SUITE)


@pytest.fixture(scope="session")
def trusted(request, tmp_path_factory) -> Run:
    """The everyday chapter, three crafted submissions, graded in its one autograde run, feedback and export."""
    _require_bwrap()
    run = grading_course.graded_courses(request, tmp_path_factory)[CHAPTER]
    if run.error:
        pytest.fail(run.fail_message())
    print(f"\n[grading trust] {len(SUITE.students)} submissions of {CHAPTER}, graded with the others "
          f"of the chapter in {run.seconds:.0f} s")
    return grading_course.view(run, SUITE.students)


def _report(page: str) -> str:
    """The text of the Autograder report at the top of a feedback page (tags removed)."""
    text = re.sub(r"<[^>]+>", " ", page.split("Autograder report", 1)[-1])
    return re.sub(r"\s+", " ", text.replace("&#39;", "'").replace("&quot;", '"'))


def _full_marks(run: Run, student: str, what: str = "") -> None:
    """``student`` scored every point; ``what`` (the property tested) starts the failure messages."""
    who = f"{what}: {student}" if what else student
    scores = run.scores.get(student)
    assert scores is not None and set(scores) == set(run.maximum), f"{who}: not graded"
    lost = {k: v for k, v in scores.items() if v != run.maximum[k]}
    assert not lost, f"{who}: a correct notebook loses points in {lost}\n{_report(run.feedback[student])[:3000]}"
    total, top = sum(scores.values()), sum(run.maximum.values())
    assert f"{total:g} of {top:g} points" in _report(run.feedback[student]), f"{who}: the feedback's total differs"


# ---------------------------------------------------------------- benign submissions
@grading_course.reads(CHAPTER, ("noisy",))
def test_logging_warnings_and_stderr_keep_full_marks(trusted):
    _full_marks(trusted, "noisy")
    page = trusted.feedback["noisy"]
    assert "shoulder_angles called" in page and "debugging shoulder_angles" in page and "RuntimeWarning" in page, (
        "what the answer logged is not shown")
    assert "not counted as a failure" in _report(page)


@grading_course.reads(CHAPTER, ("noisy",))
def test_a_number_shown_by_a_hook_sets_no_score(trusted):
    """nbgrader reads a test's first result as partial credit: the hook shows 0.0 under every cell."""
    _full_marks(trusted, "noisy")
    nb = load(trusted.course / "autograded" / "noisy" / CHAPTER / f"{CHAPTER}.ipynb")

    def shown(cell) -> bool:
        return any(src({"source": o.get("data", {}).get("text/plain", "")}) == "0.0" for o in cell.get("outputs", []))

    assert any(shown(c) for c in nb["cells"] if not nbg(c).get("grade")), (
        "the hook showed no number under the student's cells (the test tests nothing)")
    # the tests ran in the grader kernel (book/for-instructors.md, "Where the verdicts are
    # decided"): what the student's hook showed there is not under them
    assert not any(shown(c) for c in nb["cells"] if nbg(c).get("grade"))


#: report sections that name something as wrong (tools/grading/robokin_nbgrader/, tools/grading/bridge)
WRONG = ("What `robokin.check` says", "Where to start", "Notes on running your notebook",
         "For review by hand", "Answers the grader could not use", "Not run")


#: the incident of the benign submission's earlier ungraded cell: its one note in the report
STOPPED_NOTE = "ran longer than the time limit and was stopped"


def _only_the_stopped_cell_noted(what: str, report: str) -> None:
    """The report's "Notes on running your notebook" name the cell stopped at the time limit, once,
    and nothing else (no ungraded cell that raised, no missing test)."""
    assert "Notes on running your notebook" in report, f"{what}: the stopped cell is not noted:\n{report[:3000]}"
    notes = report.split("Notes on running your notebook", 1)[1].split("What happened while grading", 1)[0]
    assert notes.count(STOPPED_NOTE) == 1, f"{what}: the stopped cell is not noted once:\n{notes[:3000]}"
    assert "(not graded) raised" not in notes and "missing from your submission" not in notes, (
        f"{what}: the report of correct work notes more than the stopped cell:\n{notes[:3000]}")


def _benign_run(request, tmp_path_factory, chapter: str) -> Run:
    """``chapter``'s run, its benign submission (:data:`BENIGN`) only."""
    _require_bwrap()
    run = grading_course.graded_courses(request, tmp_path_factory)[chapter]
    if run.error:
        pytest.fail(run.fail_message())
    return grading_course.view(run, NOISY_SUITE.students)


@pytest.mark.parametrize("chapter", grading_course.chapter_params((c for c in CHAPTERS if c != CHAPTER),
                                                                  lambda chapter: (BENIGN,)))
def test_talkative_solutions_keep_full_marks(request, tmp_path_factory, chapter):
    """Every chapter's solutions, logging, warning and printing to stderr in every answer and in
    the first calls of every function (TALKING_CALLS); the benign submission, also written another
    way (test_correct_answers_written_another_way_keep_full_marks reads it for that)."""
    what = f"{chapter}: talkative"
    run = _benign_run(request, tmp_path_factory, chapter)
    _full_marks(run, BENIGN, what)
    page = run.feedback[BENIGN]
    report = _report(page)
    top = run.source["metadata"]["robokin"]["grading"]["points"]
    assert sum(run.maximum.values()) == top and f"{top:g} of {top:g} points" in report, f"{what}: not {top} points"
    # the submission's one note is its earlier cell stopped at the time limit (the other test's property)
    named = [w for w in WRONG if w.replace("`", "") in report.replace("`", "")
             and w != "Notes on running your notebook"]
    assert not named, f"{what}: the report of correct work names {named}:\n{report[:3000]}"
    _only_the_stopped_cell_noted(what, report)
    assert "noisy: cell" in page, f"{what}: the answer cells' stderr is not shown (the test tests nothing)"
    if any(declared_functions(c) for c in run.source["cells"] if nbg(c).get("solution")):
        assert "noisy: debugging" in page or "noisy: debugging" in json.dumps(run.autograded[BENIGN]), (
            f"{what}: no talkative function was called (the test tests nothing)")
    # ... and its kernel dies in its last ungraded cell (benign_variants.CRASH), where a test follows
    # it; elsewhere that cell, after the last graded one, is not run
    if _tests_after_the_last_try_cell(run.source):
        _kernel_died_and_was_restarted(report)
    else:
        _not_run_after_the_last_graded_cell(run, BENIGN, report)


def _tests_after_the_last_try_cell(source: dict) -> bool:
    """Whether a test cell comes after the chapter's last ungraded (Try it yourself) cell."""
    cells = [c for c in source["cells"] if c["cell_type"] == "code"]
    last = cells.index(last_try_cell(source))
    return any(nbg(c).get("grade") for c in cells[last + 1:])


def _kernel_died_and_was_restarted(report: str) -> None:
    """The kernel died in an ungraded cell that tests follow: restarted, the notebook went on (its tests ran)."""
    assert "The kernel stopped" in report and "the kernel died" in report and "os._exit" in report, report[:3000]
    assert "The kernel was restarted and the cells before it were run again" in report, report[:3000]


def _not_run_after_the_last_graded_cell(run: Run, student: str, report: str) -> None:
    """``student``'s cells after the last graded one (its crash among them) were not run: no incident,
    no output, and one note above them in the feedback page, where their code is shown."""
    from tools.grading.robokin_nbgrader.not_run_note import NOTE, TITLE

    assert "the kernel died" not in report and "No test comes after it" not in report, (
        f"{student}: a cell after the last graded one ran:\n{report[:3000]}")
    cells = run.autograded[student]["cells"]
    last = max(i for i, c in enumerate(cells) if nbg(c).get("grade") or nbg(c).get("solution"))
    after = [c for c in cells[last + 1:] if c["cell_type"] == "code"]
    crashing = [c for c in after if CRASH.strip() in src(c)]
    assert crashing, f"{student}: the crash is not after the last graded cell (the test tests nothing)"
    assert all(not c.get("outputs") and c.get("execution_count") is None for c in after), (
        f"{student}: a cell after the last graded one has outputs")
    assert src(cells[last + 1]) == NOTE and [src(c) for c in cells].count(NOTE) == 1, (
        f"{student}: no note, or not one, above the cells not run")
    page = run.feedback[student]
    assert page.count(TITLE) == 1 and "my experiment killed the kernel" in page, (
        f"{student}: the feedback does not show the cells not run under one note")


@pytest.mark.parametrize("chapter", grading_course.chapter_params(
    CHAPTERS, lambda chapter: ("hang",) if chapter == CHAPTER else (BENIGN,)))
def test_correct_answers_written_another_way_keep_full_marks(request, tmp_path_factory, chapter):
    """Every chapter's solutions with answers computed by another valid method, other
    intermediate names (tests/support/benign_variants.py), and a hang in an ungraded cell: the
    everyday chapter's in a cell of the student's own (killed: it ignores the interrupt; restarted),
    every other chapter's in an earlier one (interrupted; the benign submission, also talkative: see
    the module's docstring)."""
    what = f"{chapter}: written another way"
    _require_bwrap()
    run = grading_course.graded_courses(request, tmp_path_factory)[chapter]
    if run.error:
        pytest.fail(run.fail_message())
    student = "hang" if chapter == CHAPTER else BENIGN
    run = grading_course.view(run, [student])
    _full_marks(run, student, what)
    report = _report(run.feedback[student])
    named = [w for w in WRONG if w.replace("`", "") in report.replace("`", "")
             and w != "Notes on running your notebook"]
    assert not named, f"{what}: the report of correct work names {named}:\n{report[:3000]}"
    graded = json.dumps(run.autograded[student])
    for variant, code in VARIANTS[chapter].values():
        assert code.strip().splitlines()[0] in graded, f"{what}: the variant ({variant}) is not in the notebook"
    if chapter == CHAPTER:   # ignores the interrupt: killed at the time limit
        assert "ignored the interrupt" in report and "killed" in report, f"{what}: {report[:3000]}"
    else:                    # interrupted at the time limit, the notebook runs on (tests follow: full marks)
        assert STOPPED_NOTE in report, f"{what}: {report[:3000]}"
        _only_the_stopped_cell_noted(what, report)


@grading_course.reads(CHAPTER, ("noisy",))
def test_kernel_that_dies_in_an_ungraded_cell(trusted):
    _full_marks(trusted, "noisy")
    _kernel_died_and_was_restarted(_report(trusted.feedback["noisy"]))


@grading_course.reads(CHAPTER, ("hang",))
def test_kernel_that_ignores_the_interrupt_is_killed(trusted):
    _full_marks(trusted, "hang")
    report = _report(trusted.feedback["hang"])
    assert "The kernel stopped" in report and "ignored the interrupt" in report and "killed" in report
    assert "The kernel was restarted and the cells before it were run again" in report


@grading_course.reads(CHAPTER, ("hang",))
def test_a_crash_after_the_last_graded_cell_is_not_run(trusted):
    """os._exit at the end of the last ungraded cell, after every graded one: not run (no second
    incident, no output), full marks, and the feedback shows those cells under one note."""
    _full_marks(trusted, "hang")
    report = _report(trusted.feedback["hang"])
    assert report.count("The kernel stopped") == 1, report[:3000]   # the hang's, before the last test
    _not_run_after_the_last_graded_cell(trusted, "hang", report)


def test_tests_after_a_lost_kernel_score_zero_and_say_why():
    """The cells after the one the kernel stopped in are not run: their tests score 0, with the reason."""
    from nbformat.v4 import new_code_cell, new_notebook
    from nbgrader import utils
    from tools.grading.bridge.execute import BridgedExecute
    from tools.grading.robokin_nbgrader import NOT_RUN, GradingIncidents

    # mypy takes nbclient's __init__(nb); nbgrader's Execute (untyped) puts nbconvert's __init__(**kw) first
    execute = BridgedExecute()
    execute._report = {"incidents": []}
    execute._stopped = {"kind": "died", "label": "In [7] `os._exit(1)`", "graded": False, "tests_lost": 1,
                        "replayed": False}   # restarting the kernel failed
    execute._report["incidents"].append(execute._stopped)
    test = new_code_cell("assert Q_goal is not None", metadata={"nbgrader": {
        "grade": True, "solution": False, "points": 2, "grade_id": "task4_test1", "schema_version": 3},
        "robokin": {"role": "test", "task": 4}})
    test = execute._not_run(test)
    assert utils.determine_grade(test, None) == (0, 2.0)
    assert test.outputs[0]["ename"] == NOT_RUN and "In [7]" in test.outputs[0]["evalue"]
    nb, _ = GradingIncidents().preprocess(new_notebook(cells=[test]),
                                          {"robokin": {"incidents": execute._report["incidents"]}})
    report = nb.cells[0].source
    assert "The kernel stopped** in In [7] `os._exit(1)` (not graded): the kernel died" in report
    assert "the test after it was not run and scores 0" in report
    assert "Not run (0 points), because the kernel had stopped: a cell `assert Q_goal is not None` " \
        "(a test of Task 4)" in report


# ---------------------------------------------------------------- the sandbox
@grading_course.reads(CHAPTER, ("escape",))
def test_without_bwrap_autograde_refuses_and_names_the_package(trusted):
    code, output = trusted.refused
    assert code != 0
    assert f"install the Debian/Ubuntu package '{PACKAGE}'" in output and SWITCH in output


@grading_course.reads(CHAPTER, ("escape",))
def test_nothing_is_written_outside_the_submission_folder(trusted):
    for target in _outside_targets(trusted.course):
        assert not target.exists(), f"the submission wrote {target}"
    page = trusted.feedback["escape"]
    # the course and the repository read-only; /tmp and $HOME private, empty and thrown away. A
    # repository or course that itself lies under /tmp (a CI clone) is, inside the sandbox, in that
    # private /tmp: a write there may succeed and is thrown away (nothing exists outside: above).
    private = [Path(tempfile.gettempdir()).resolve(), Path.home().resolve()]
    for target in _outside_targets(trusted.course)[:3]:
        if any(p in target.resolve().parents for p in private) and f"WRITE-BLOCKED {target}" not in page:
            continue
        assert f"WRITE-BLOCKED {target}" in page, f"{target}: the write was not refused"


@grading_course.reads(CHAPTER, ("escape",))
def test_the_graders_environment_is_not_passed_on(trusted):
    page = trusted.feedback["escape"]
    assert "TOKEN absent" in page and TOKEN not in page


@grading_course.reads(CHAPTER, ("escape",))
def test_the_instructors_files_are_not_readable(trusted):
    page = trusted.feedback["escape"]
    assert "SECRET-READ" not in page and page.count("SECRET-BLOCKED") == 3
    # the last line of text of each solution-prose cell (not its ``` / :class: marker lines)
    prose = [lines[-1][:50] for c in trusted.source["cells"] if rk(c).get("role") == "prose"
             for lines in [[line for line in src(c).splitlines()
                            if line.strip() and not line.lstrip().startswith(("```", ":class:", "<!--"))]]
             if lines]
    for student, feedback in trusted.feedback.items():
        assert "solution-start" not in feedback, f"{student}: the instructor's source is in the feedback"
        assert not [p for p in prose if p in feedback], f"{student}: solution prose in the feedback"
    _full_marks(trusted, "escape")


@grading_course.reads(CHAPTER, ("escape",))
def test_a_process_left_behind_dies_with_the_kernel(trusted):
    assert trusted.alive_before is not None, "the detached process never ran (the test tests nothing)"
    assert trusted.alive_after == trusted.alive_before, "a process started by the submission outlived grading"
    assert trusted.gradebook_after == trusted.gradebook_digest, "gradebook.db changed after autograde"
    top = sum(trusted.maximum.values())
    for student, scores in trusted.scores.items():
        assert trusted.exported[student] == sum(scores.values()) == top, (
            f"{student}: export {trusted.exported[student]} vs gradebook {sum(scores.values())}")


# ---------------------------------------------------------------- the switch and the layout
def test_the_switch(monkeypatch):
    monkeypatch.delenv(SWITCH, raising=False)
    assert sandbox_wanted(True) and not sandbox_wanted(False)
    monkeypatch.setenv(SWITCH, "off")
    assert not sandbox_wanted(True)
    monkeypatch.setenv(SWITCH, "on")
    assert sandbox_wanted(False)
    monkeypatch.setenv(SWITCH, "maybe")
    with pytest.raises(ValueError, match=SWITCH):
        sandbox_wanted(True)


def test_the_switch_off_runs_nbgraders_own_kernel(monkeypatch):
    from jupyter_client.manager import AsyncKernelManager
    from nbformat.v4 import new_notebook
    from tools.grading.bridge.execute import BridgedExecute
    from tools.grading.sandbox import SandboxedKernelManager

    from traitlets.config import Config

    def manager(**config):
        # mypy takes nbclient's __init__(nb); nbgrader's Execute (untyped) puts nbconvert's __init__(**kw) first
        execute = BridgedExecute(config=Config({"BridgedExecute": config}))
        execute.nb, execute.resources = new_notebook(), {"metadata": {"path": str(ROOT)}}
        execute._sandboxed = sandbox_wanted(execute.sandbox)
        return type(execute.create_kernel_manager())

    for value, expected in (("off", AsyncKernelManager), ("on", SandboxedKernelManager)):
        monkeypatch.setenv(SWITCH, value)
        assert manager() is expected
    monkeypatch.delenv(SWITCH)
    assert manager() is SandboxedKernelManager               # the default
    assert manager(sandbox=False) is AsyncKernelManager      # c.BridgedExecute.sandbox = False


def test_a_bwrap_that_cannot_make_a_sandbox_stops_grading(tmp_path, monkeypatch):
    from tools.grading import sandbox

    fake = tmp_path / "bwrap"
    fake.write_text("#!/bin/sh\necho 'bwrap: No permissions to create new namespace' >&2\nexit 1\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(sandbox.SandboxUnavailable, match="No permissions to create new namespace.*"
                       + SWITCH):
        sandbox.bwrap_executable()


def test_hidden_folder_inside_a_readable_one_is_covered(tmp_path):
    shared = tmp_path / "shared"           # a folder the sandbox reads (as /usr or the venv) ...
    course = shared / "course"             # ... that holds the course (hidden) ...
    venv = course / "venv"                 # ... that holds a folder the sandbox reads again
    submission = course / "autograded" / "s" / "a"
    for folder in (venv, submission):
        folder.mkdir(parents=True)
    args = sandbox_arguments(writable=submission, runtime=tmp_path / "run", hidden=[course, Path("/srv/exchange")],
                             readable=[shared, venv], home="/home/grader", bwrap="bwrap")
    text = " ".join(args)
    assert text.index("--tmpfs /home/grader") < text.index(f"--ro-bind {shared} {shared}") < text.index(
        f"--tmpfs {course}") < text.index(f"--ro-bind {venv} {venv}") < text.index(
        f"--bind {submission} {submission}") < text.index(f"--remount-ro {course}") < text.index("--remount-ro / ")
    assert "/srv" not in text, "a folder outside the readable ones is not in the sandbox at all"
    for flag in ("--unshare-all", "--die-with-parent", "--new-session", "--clearenv", "--cap-drop"):
        assert flag in args


def _font_list(folder: Path, fonts: list[str], version: str = "v3.11.0") -> Path:
    """A matplotlib font list naming ``fonts``, in ``folder`` (the grader's cache folder)."""
    folder.mkdir(parents=True, exist_ok=True)
    entries = [{"fname": name, "name": Path(name).stem, "__class__": "FontEntry"} for name in fonts]
    path = folder / f"fontlist-{version}.json"
    path.write_text(json.dumps({"_version": version, "ttflist": entries, "afmlist": [], "__class__": "FontManager"}))
    return path


def test_the_graders_font_list_is_bound_where_the_kernels_matplotlib_reads_it(tmp_path, monkeypatch):
    """The grader's font list, read-only in the kernel's home, if the kernel can open every font it names."""
    submission = tmp_path / "course" / "autograded" / "s" / "a"
    submission.mkdir(parents=True)
    monkeypatch.setenv("MPLCONFIGDIR", str(tmp_path / "mpl"))
    listed = _font_list(tmp_path / "mpl", ["fonts/ttf/DejaVuSans.ttf", "/usr/share/fonts/truetype/x.ttf"])
    elsewhere = _font_list(tmp_path / "mpl", ["/home/grader/.fonts/mine.ttf"], version="v3.10.0")

    def arguments(home: str) -> str:
        return " ".join(sandbox_arguments(writable=submission, runtime=tmp_path / "run", hidden=[tmp_path / "course"],
                                          readable=[], home=home, bwrap="bwrap"))

    text = arguments("/home/grader")
    bind = f"--ro-bind {listed} /home/grader/.cache/matplotlib/{listed.name}"
    assert text.index("--tmpfs /home/grader") < text.index(bind) < text.index("--remount-ro / ")
    assert elsewhere.name not in text, "a list naming a font the kernel cannot open is not bound"
    assert listed.name not in arguments("/"), "no home of the kernel's own: no list"
    monkeypatch.setenv("MPLCONFIGDIR", str(tmp_path / "none"))
    assert "fontlist" not in arguments("/home/grader"), "the grader has no list: the kernel makes its own"


def test_a_sandboxed_kernels_matplotlib_reads_the_graders_font_list(tmp_path, monkeypatch):
    """In a real sandbox, matplotlib reads the bound list (it does not look for the fonts again) and
    finds the fonts the grader's found; its cache folder is writable, as matplotlib wants it."""
    _require_bwrap()
    monkeypatch.setenv("MPLCONFIGDIR", str(tmp_path / "mpl"))
    report = ("import logging, os, sys\nlogging.basicConfig(level=logging.DEBUG, stream=sys.stdout)\n"
              "import matplotlib\nimport matplotlib.font_manager as fm\n"
              "cache = matplotlib.get_cachedir()\n"
              "print('fonts', len(fm.fontManager.ttflist), 'writable', os.access(cache, os.W_OK))\n")
    graders = subprocess.run([sys.executable, "-c", report], capture_output=True, text=True, timeout=120)
    assert graders.returncode == 0 and list((tmp_path / "mpl").glob("fontlist-v*.json")), graders.stderr
    submission, runtime = tmp_path / "submission", tmp_path / "run"
    submission.mkdir()
    runtime.mkdir()
    prefix = sandbox_arguments(writable=submission, runtime=runtime, hidden=[], readable=python_folders(),
                               home="/home/grader", bwrap=bwrap_executable())
    kernels = subprocess.run([*prefix, sys.executable, "-c", report], capture_output=True, text=True, timeout=120)
    assert kernels.returncode == 0, kernels.stderr
    assert "Using fontManager instance from /home/grader/.cache/matplotlib/fontlist-v" in kernels.stdout, kernels.stdout
    assert "generated new fontManager" not in kernels.stdout
    assert kernels.stdout.splitlines()[-1] == graders.stdout.splitlines()[-1]   # "fonts N writable True"
    assert kernels.stdout.splitlines()[-1].endswith("writable True")


class _FakeKernelManager:
    """What ``BridgedExecute._kernel_lost`` asks of the kernel manager; ``restart`` is what a restart does."""

    def __init__(self, restart):
        self.stopped, self.restarts, self._restart = False, 0, restart

    async def restart_kernel(self, now=False):
        self.restarts += 1
        self._restart()

    async def shutdown_kernel(self, now=False):
        self.stopped = now


def _graded_test_cell():
    from nbformat.v4 import new_code_cell

    return new_code_cell("assert x == 1", metadata={"nbgrader": {
        "grade": True, "solution": False, "points": 1, "grade_id": "task1_test1", "schema_version": 3}})


def _execute(cells, manager, replays=0, **state):
    """A BridgedExecute on ``cells`` with ``manager``, as autograde sets it up before the cells run."""
    from nbformat.v4 import new_notebook
    from tools.grading.bridge.execute import BridgedExecute

    # mypy takes nbclient's __init__(nb); nbgrader's Execute (untyped) puts nbconvert's __init__(**kw) first
    execute = BridgedExecute()
    execute.nb, execute.km = new_notebook(cells=cells), manager
    execute._report, execute._replays, execute._stopped = {"incidents": []}, replays, None
    for name, value in state.items():
        setattr(execute, name, value)
    return execute


def _refuse(message):
    def restart():
        raise RuntimeError(message)
    return restart


def test_when_the_kernel_cannot_be_restarted_grading_stops_there():
    """_kernel_lost: restart fails -> the kernel is stopped and the cells after it are not run."""
    from nbclient.exceptions import DeadKernelError
    from nbformat.v4 import new_code_cell
    from tools.grading.robokin_nbgrader import NOT_RUN

    crash, test = new_code_cell("import os\nos._exit(1)"), _graded_test_cell()
    manager = _FakeKernelManager(_refuse("no more kernels"))
    execute = _execute([crash, test], manager)
    execute._kernel_lost(crash, 0, DeadKernelError("Kernel died"))
    assert manager.stopped and execute._stopped["tests_lost"] == 1 and not execute._stopped["replayed"]
    execute.preprocess_cell(test, {}, 1)
    assert test.outputs[0]["ename"] == NOT_RUN
    # a second lost kernel in the same notebook: no second restart, grading stops there
    manager = _FakeKernelManager(_refuse("a second restart must not happen"))
    execute = _execute([crash, test], manager, replays=1)
    execute._kernel_lost(crash, 0, DeadKernelError("Kernel died"))
    assert execute._stopped is not None and not execute._stopped["replayed"] and manager.restarts == 0


def test_after_the_last_test_a_lost_kernel_is_not_restarted():
    """_kernel_lost after the last test (the kernel runs on to an answer that no test follows): no
    restart, no replay; the report says nothing graded was lost."""
    from nbclient.exceptions import DeadKernelError
    from nbformat.v4 import new_code_cell, new_notebook
    from tools.grading.robokin_nbgrader import GradingIncidents

    test = _graded_test_cell()
    crash = new_code_cell("import os\nos._exit(1)")
    after = new_code_cell("print('an answer no test reads')", metadata={"nbgrader": {
        "grade": False, "solution": True, "grade_id": "task2_answer1", "schema_version": 3}})
    manager = _FakeKernelManager(_refuse("the kernel must not be restarted: nothing graded comes after the cell"))
    execute = _execute([test, crash, after], manager, _last_code=0, _last_graded=2)
    execute._kernel_lost(crash, 1, DeadKernelError("Kernel died"))
    incident = execute._stopped
    assert manager.stopped and manager.restarts == 0
    assert incident["nothing_after"] and not incident["replayed"] and not incident["tests_lost"]
    assert execute.preprocess_cell(after, {}, 2)[0].outputs == []   # not run
    nb, _ = GradingIncidents().preprocess(new_notebook(cells=[]), {"robokin": {"incidents": [incident]}})
    assert "No test comes after it, so grading stopped there: the cells after it were not run, and no " \
        "points were lost" in nb.cells[0].source


def test_cells_after_the_last_graded_cell_are_not_run():
    """The student's kernel stops after the last cell that is graded or holds an answer (a manually
    graded one counts): a crash, a hang or any code after it is not run, costs nothing and takes no
    time; the graded notebook shows those cells without outputs, under one note saying why."""
    from nbformat.v4 import new_code_cell, new_markdown_cell, new_notebook, new_output
    from tools.grading.bridge.execute import last_graded_cell
    from tools.grading.robokin_nbgrader import NotRunNote
    from tools.grading.robokin_nbgrader.not_run_note import NOTE

    manual = new_markdown_cell("My reasoning.", metadata={"nbgrader": {
        "grade": True, "solution": True, "points": 1, "grade_id": "task2_answer2", "schema_version": 3}})
    heading = new_markdown_cell("## Going further")
    crash = new_code_cell("import os\nos._exit(1)", outputs=[new_output("stream", name="stdout", text="mine\n")],
                          execution_count=9)
    picture = new_code_cell("while True:\n    pass")
    cells = [_graded_test_cell(), manual, heading, crash, picture]
    assert last_graded_cell(cells) == (1, 2)
    assert last_graded_cell(cells[:3]) == (1, None)   # no code after it: nothing is left out
    assert last_graded_cell([new_code_cell("x = 1")]) == (0, None)   # no grading metadata: all of it runs

    # a kernel that ran a cell would fail: the fake manager has no kernel and no client
    execute = _execute(cells, _FakeKernelManager(_refuse("no kernel")), _last_graded=1)
    for index in (2, 3, 4):
        cell, _ = execute.preprocess_cell(cells[index], {}, index)
        assert cell is cells[index]
    assert crash.outputs == [] and crash.execution_count is None and not execute._report["incidents"]

    nb, _ = NotRunNote().preprocess(new_notebook(cells=list(cells)), {"robokin": {"not_run_from": 2}})
    notes = [c for c in nb.cells if c.source == NOTE]
    assert len(notes) == 1 and nb.cells.index(notes[0]) == 2 and nb.cells[3] is heading
    assert "error" not in NOTE.lower() and "graded" in NOTE
    # what the student can do, true on every grading path (a submission may come without outputs)
    assert "run them in your own copy" in NOTE and "keeps" not in NOTE
    assert not [words for words in WRONG if words in NOTE], "the note reads as a report of something wrong"
    nb, _ = NotRunNote().preprocess(new_notebook(cells=list(cells)), {"robokin": {"not_run_from": None}})
    assert len(nb.cells) == len(cells)
