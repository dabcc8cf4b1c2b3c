"""Tampering submissions gain no points; delegation is flagged (the grading
bridge decides verdicts outside the student's kernel).

The everyday chapter (tests/support/tiers.py: chapter 7, the UR10's closed form, the cheapest
to grade) is graded through the bridge (``tools/grading/bridge``): its test cells and
robokin.check's verdicts run in a grader kernel, the answers handed over as data and
functions as proxies. Each submission below is one the old pipeline (verdicts in the
student's kernel) scored well with blank or wrong answers; all are graded in one
``nbgrader autograde`` run, in this file's own course of the chapter
(tests/support/grading_course.py, with the chapter's correct submission):

* blank answers with one line in the first answer cell that
  - turns test cells into ``pass`` (an IPython input transformer),
  - drops ``assert`` statements (an AST transformer),
  - makes every cell show a text result first (a ``pre_run_cell`` hook calling the
    display hook: nbgrader reads a test's first result as its score),
  - patches numpy (``np.allclose = lambda *a, **k: True``),
  - forges robokin.check's verdicts (``print_verdicts`` and every check passing),
  - forges outputs (test cells handed in with a full-marks result, tracebacks hidden,
    every cell reported to nbgrader as a success);
* wrong answers (every answer off by 1 %, and one a generator: no plain data), plain and
  with numpy and robokin.check patched;
* answers that call robokin's own closed form (``np.unique(ur10_ik(T).q[:, 0])``, and
  ``all_solutions`` through a helper of its own);
* an ``all_solutions`` that never returns when a test calls it (the call is stopped;
  robokin.check's summary says so, and checks every other answer on its own).

Expected: each tampering submission scores exactly what its untampered answers score
(0 for blank ones), and the report does not say robokin.check finds the answers
correct; delegation is named in the report "for review by hand", its score as
tested; the instructor's solutions score full marks through the bridge.
"""

from __future__ import annotations

import copy
import re

import pytest

from support import grading_course
from support.nbgrader_course import CHAPTERS, NOTEBOOKS, Run, load, nbg, src
from support.tampering import TAMPER, tampered

CHAPTER = grading_course.EVERYDAY_CHAPTER

#: appended to every answer cell of the "wrong" submission: each answer off by 1 %
WRONG_CODE = '''

def _robokin_wrong(value):
    import numpy as np
    import sympy as sp

    if callable(value) and not isinstance(value, type):
        def wrong(*args, **kwargs):
            return _robokin_wrong(value(*args, **kwargs))
        return wrong
    if isinstance(value, np.ndarray) and value.dtype.kind in "fc":
        return value * 1.01 + 0.01
    if isinstance(value, float):
        return value * 1.01 + 0.01
    if isinstance(value, sp.Poly):
        return sp.Poly(value.as_expr() + 1, *value.gens)
    if isinstance(value, sp.Expr) and not isinstance(value, sp.Symbol):
        return value + 1
    return value


for _name in {names!r}:
    globals()[_name] = _robokin_wrong(globals()[_name])  # every answer wrong, made by the test
'''

#: answer cells replaced by calls of robokin's closed form (robokin.models.ur10_ik, which the
#: checks of Tasks 1 and 4 name): grade_id -> (old lines pattern, new code); all_solutions calls
#: it through a helper of its own. The chapter imports robokin's solver only after the tasks, so
#: a delegating student imports it, as these answers do.
IMPORT_CLOSED_FORM = "from robokin.models import ur10_ik\n\n\n"
DELEGATE = {
    "task1_answer1": (r"def shoulder_angles\([^)]*\):\n(    .*\n)+",
                      IMPORT_CLOSED_FORM + "def shoulder_angles(T, wrist_centre=wrist_centre):\n"
                      "    return np.unique(ur10_ik(T).q[:, 0])\n"),
    "task4_answer1": (r"def all_solutions\([^)]*\):\n(    .*\n)+",
                      IMPORT_CLOSED_FORM + "def _closed_form(T):\n    return ur10_ik(T)\n\n\n"
                      "def all_solutions(T, **steps):\n    return _closed_form(T).q\n"),
}


#: an all_solutions that never returns when a test calls it through the bridge (its own cell's
#: call, Q_goal, returns); no other answer calls it, so the tests of the other tasks call only
#: functions that return
SLOW_ANSWER = '''
def _never_for_the_grader(function):
    import inspect
    import time

    def all_solutions(T, **steps):
        if any("robokin grading bridge" in frame.filename for frame in inspect.stack()):
            time.sleep(10**6)
        return function(T, **steps)
    return all_solutions


all_solutions = _never_for_the_grader(all_solutions)
'''
#: seconds per call of a student's function, in this course: a call through the bridge costs
#: 0.1-0.2 ms (tools/grading/bridge/benchmark.py, quiet machine) plus the answer's own work, a
#: few milliseconds here (all_solutions, the costliest: eight forward kinematics, about 1 ms),
#: so load cannot reach 3 s; the never-returning call waits it out
CALL_TIMEOUT = 3


def slow_submission(correct: dict) -> dict:
    nb = copy.deepcopy(correct)
    for cell in nb["cells"]:
        if nbg(cell).get("grade_id") == "task4_answer1":
            cell["source"] = src(cell).replace("\n\nQ_goal = ", SLOW_ANSWER + "\n\nQ_goal = ", 1)
            assert SLOW_ANSWER in cell["source"]
    return nb


def wrong_submission(correct: dict, source: dict) -> dict:
    declared = {nbg(c)["grade_id"]: c["metadata"]["robokin"].get("declare", []) for c in source["cells"]
                if nbg(c).get("solution") and c["metadata"].get("robokin", {}).get("role") == "answer"}
    nb = copy.deepcopy(correct)
    for cell in nb["cells"]:
        names = declared.get(nbg(cell).get("grade_id"), [])
        if names:
            cell["source"] = src(cell).rstrip() + "\n" + WRONG_CODE.format(names=names)
        if "q5_singular" in names:   # and one answer that is no plain data
            cell["source"] += "\nq5_singular = (angle for angle in q5_singular)\n"
    return nb


def delegating_submission(correct: dict) -> dict:
    nb = copy.deepcopy(correct)
    for cell in nb["cells"]:
        change = DELEGATE.get(nbg(cell).get("grade_id", ""))
        if change:
            new, count = re.subn(change[0], change[1], src(cell) + "\n", count=1)
            assert count == 1, f"{nbg(cell)['grade_id']}: the answer to replace is not there"
            cell["source"] = new
    return nb


def submissions(run: Run, correct: dict, course) -> dict[str, dict]:
    """This file's submissions of the chapter (its solutions are test_nbgrader.py's ``correct``)."""
    wrong = wrong_submission(correct, run.source)
    # the blank submissions are the student edition with one kind of tampering each; the edition
    # handed in unchanged is graded in the chapter's shared run (tests/test_nbgrader.py), not here
    out = {"wrong": wrong, "delegating": delegating_submission(correct), "slow": slow_submission(correct)}
    for kind in TAMPER:
        out[f"blank_{kind}"] = tampered(run.release, kind)
    out["wrong_patched_numpy"] = tampered(wrong, "patched_numpy")
    out["wrong_forged_check"] = tampered(wrong, "forged_check")
    return out


#: graded in a course of the chapter of its own (tests/support/grading_course.py), with the correct
#: submission, and with a short time limit per call of a student's function
SUITE = grading_course.Suite("tamper", submissions,
                             options=[f"--BridgedExecute.call_timeout={CALL_TIMEOUT}"], own_course=True)
# this file's course of the chapter is a part of the graded courses of its own (one xdist group):
# its never-returning call waits the call limit in every test, in parallel with the other parts.
# Each test names the submissions it reads: a session grades only those (make test: one kind of
# tampering, tests/support/tiers.py), besides the correct one every course has.
KEY = SUITE.key(CHAPTER)


def reads(*students: str):
    """The test reads these submissions of this file's course."""
    return grading_course.reads(KEY, students)


def kinds(names, students):
    """``names`` as parameters, each marked with the submissions ``students(name)`` it reads."""
    return [pytest.param(name, marks=grading_course.job_marks(KEY, students(name))) for name in names]


@pytest.fixture(scope="session")
def graded(request, tmp_path_factory) -> Run:
    """The chapter: every submission below (and the solutions) autograded in this file's course
    (one autograde run); ``feedback`` is the report on top of each graded notebook."""
    run = grading_course.graded_courses(request, tmp_path_factory)[SUITE.key(CHAPTER)]
    if run.error:
        pytest.fail(run.fail_message())
    students = ["correct", *SUITE.students]
    reports = {s: "".join(src(run.autograded[s]["cells"][0])) if run.autograded.get(s) else "" for s in students}
    print(f"\n[tamper] {len(students)} submissions of {CHAPTER}, graded in this file's course in {run.seconds:.0f} s")
    return grading_course.view(run, students, feedback=reports)


def _scores(run: Run, student: str) -> dict[str, float]:
    scores = run.scores.get(student)
    assert scores is not None and set(scores) == set(run.maximum), f"{student} was not graded"
    return scores


@pytest.mark.parametrize("kind", kinds(TAMPER, lambda kind: (f"blank_{kind}",)))
def test_tampering_a_blank_submission_gains_nothing(graded, kind):
    scores = _scores(graded, f"blank_{kind}")
    earned = {k: v for k, v in scores.items() if v}
    assert not earned, f"{kind}: a blank submission earns {earned}"
    report = graded.feedback[f"blank_{kind}"]
    assert "**0 of" in report and "finds all" not in report, report[:2000]


@pytest.mark.parametrize("kind", kinds(["patched_numpy", "forged_check"], lambda kind: ("wrong", f"wrong_{kind}")))
def test_tampering_wrong_answers_gains_nothing(graded, kind):
    baseline = _scores(graded, "wrong")
    scores = _scores(graded, f"wrong_{kind}")
    gained = {k: (baseline[k], v) for k, v in scores.items() if v > baseline[k]}
    assert not gained, f"{kind}: wrong answers gain points in {gained}"
    assert sum(baseline.values()) < sum(graded.maximum.values()), "the wrong answers score full marks"
    assert "finds all" not in graded.feedback[f"wrong_{kind}"]


@reads("wrong", "wrong_forged_check")
def test_blank_and_wrong_reports_name_the_answers(graded):
    report = graded.feedback["wrong_forged_check"]
    assert "What `robokin.check` says about your answers" in report, report[:2000]
    assert "answer `q5_singular` is not plain data (a generator)" in graded.feedback["wrong"], graded.feedback["wrong"]


@reads()
def test_solutions_score_full_marks_through_the_bridge(graded):
    scores = _scores(graded, "correct")
    assert scores == graded.maximum
    report = graded.feedback["correct"]
    assert "finds all" in report and "review by hand" not in report and "could not use" not in report, report


@reads("delegating")
def test_delegation_is_flagged_for_review(graded):
    report = graded.feedback["delegating"]
    assert "review by hand: `shoulder_angles` calls robokin's `robokin.models.ur10_ik`" in report, report
    assert ("review by hand: `all_solutions` calls robokin's `robokin.models.ur10_ik` (through `_closed_form`)"
            in report), report
    # the score stands as tested: robokin's own closed form passes the tests
    assert _scores(graded, "delegating") == graded.maximum


@reads("blank_forged_outputs", "blank_display_hook")
def test_graded_test_outputs_come_from_the_grader_kernel(graded):
    """The forged full-marks results handed in and the display hook's text are gone from the test cells."""
    for student in ("blank_forged_outputs", "blank_display_hook"):
        nb = load(graded.course / "autograded" / student / CHAPTER / f"{CHAPTER}.ipynb")
        for cell in nb["cells"]:
            if nbg(cell).get("grade") and cell["cell_type"] == "code":
                kinds = [o["output_type"] for o in cell["outputs"]]
                assert "execute_result" not in kinds and "error" in kinds, (student, nbg(cell)["grade_id"], kinds)
        # the note above a failing test names its line, numbered as in the student's run (a blank
        # submission's: the tampering is in an answer cell, the note the grader kernel's)
        note = next("".join(o["text"]) for c in nb["cells"] if nbg(c).get("grade_id") == "task1_test1"
                    for o in c["outputs"] if o["output_type"] == "stream")
        assert "failed at line" in note, (student, note)


def test_delegation_finder_on_code():
    from tools.grading.bridge import delegation

    checks: dict[int | None, set[str]] = {1: {"ur10_closed_form.wrist_centre", "ur10_closed_form.shoulder_angles"},
                                          4: {"ur10_closed_form.all_solutions"}}
    answers = [
        (4, "all_solutions = ur10_ik\nQ_goal = all_solutions(T_goal)\n", ["all_solutions", "Q_goal"]),
        (1, "def helper(T):\n    return getattr(models, 'ur10_ik')(T)\n\n"
            "def shoulder_angles(T):\n    return np.unique(helper(T).q[:, 0])\n", ["shoulder_angles"]),
    ]
    found = {item["name"]: item for item in delegation.find(answers, checks)}
    assert set(found) == {"all_solutions", "shoulder_angles"}
    assert delegation.describe(found["all_solutions"]) == (
        "review by hand: `all_solutions` returns robokin's `robokin.models.ur10_ik` (it is bound to it)")
    assert found["shoulder_angles"]["through"] == "helper"
    solutions = [(1, "def shoulder_angles(T):\n    x, y, _ = wrist_centre(T)\n    return np.arctan2(y, x)\n",
                  ["shoulder_angles"])]
    assert delegation.find(solutions, checks) == []


@reads("slow")
def test_a_call_that_never_returns_is_stopped(graded):
    """The test calling it fails after the time limit per call; the student's kernel is
    interrupted, and the tests after it are graded as usual."""
    scores = _scores(graded, "slow")
    full = _scores(graded, "correct")
    assert scores["task4_test1"] == 0 and full["task4_test1"] > 0 and full["task5_test1"] > 0, (scores, full)
    # the tests before it, and task 5's after it, keep their points
    assert {k: v for k, v in scores.items() if k != "task4_test1"} == \
        {k: v for k, v in full.items() if k != "task4_test1"}, scores
    nb = load(graded.course / "autograded" / "slow" / CHAPTER / f"{CHAPTER}.ipynb")
    errors = [o for c in nb["cells"] if nbg(c).get("grade_id") == "task4_test1"
              for o in c["outputs"] if o["output_type"] == "error"]
    assert errors and f"took longer than {CALL_TIMEOUT} s" in errors[0]["evalue"], errors
    # robokin.check's summary: all_solutions's call was stopped at the limit; every other answer is
    # checked on its own (after the interrupt), none is reported as not called or as failing for
    # all_solutions's call
    report = graded.feedback["slow"]
    summary = report.split("What `robokin.check` says about your answers", 1)[-1].split("**Where to start**")[0]
    assert f"Calling all_solutions raised AnswerError: the call took longer than {CALL_TIMEOUT} s and was stopped" \
        in summary, report
    assert "still busy" not in report and "not called" not in report, report
    assert "all_solutions(T)" in summary, summary
    others = ("wrist_centre", "shoulder_angles", "wrist_angles", "arm_angles", "coinciding_branches")
    assert not [name for name in others if name in summary], summary


def _answers_and_checks(nb: dict) -> tuple[list, dict]:
    """What the bridge hands to ``delegation.find`` for a chapter (as ``BridgedExecute._make_plan``)."""
    meta = [c.get("metadata", {}).get("robokin", {}) for c in nb["cells"]]
    checks: dict = {}
    for entry in meta:
        if entry.get("role") == "test":
            for check, expression in entry.get("explain", []):
                checks.setdefault(entry.get("task"), {}).setdefault(check, set()).add(expression)
    answers = [(entry.get("task"), src(cell), entry.get("declare", [])) for cell, entry in zip(nb["cells"], meta)
               if entry.get("role") == "answer"]
    return answers, checks


#: chapters whose graded tasks all ask for robokin's own tools (nothing to flag there)
NO_DELEGATION: dict[str, str] = {}


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_delegation_is_flagged_in_every_chapter(chapter):
    """For every check with robokin references that a chapter's tests explain, an answer
    bound to robokin's solution is flagged; the instructor's solutions are not."""
    from tools.grading.bridge import delegation

    answers, checks = _answers_and_checks(load(NOTEBOOKS / f"{chapter}.ipynb"))
    assert delegation.find(answers, checks) == [], f"{chapter}: the solutions are flagged"
    tried = 0
    for task, by_check in checks.items():
        for check, expressions in by_check.items():
            references = delegation.REFERENCES.get(check)
            names = set().union(*(delegation._names(e) or set() for e in expressions))
            target = next(((i, n) for i, (t, _, declared) in enumerate(answers) if t == task
                           for n in declared if n in names), None)
            if not references or target is None:
                continue
            index, name = target
            attr, how = next(iter(references.items()))
            changed = list(answers)
            code = changed[index][1] + f"\n\n{name} = robokin_object.{attr}\n"
            changed[index] = (task, code, changed[index][2])
            found = [item for item in delegation.find(changed, checks) if item["name"] == name]
            assert found and found[0]["reference"] == how, (chapter, check, name, found)
            tried += 1
    # answers named in delegation.ANSWERS (tasks whose tests explain no check)
    for index, (task, code, declared) in enumerate(answers):
        for name in set(declared) & set(delegation.ANSWERS):
            for attr, how in delegation.ANSWERS[name].items():
                changed = list(answers)
                changed[index] = (task, code + f"\n\n{name} = robokin_object.{attr}\n", declared)
                found = [item for item in delegation.find(changed, checks) if item["name"] == name]
                assert found and found[0]["reference"] == how, (chapter, name, attr, found)
                tried += 1
    if chapter in NO_DELEGATION:
        assert tried == 0, f"{chapter}: NO_DELEGATION is out of date"
    else:
        assert tried, f"{chapter}: no graded task has robokin references (delegation.REFERENCES)"


def test_delegation_answer_names_belong_to_one_chapter():
    """Each name of ``delegation.ANSWERS`` is declared by the answers of exactly one chapter
    (it is looked at wherever it is declared), and a call through a helper is flagged too."""
    from conftest import ROOT
    from tools.authoring.nbgrader_metadata import chapter_notebooks
    from tools.grading.bridge import delegation

    # the names are those of every chapter: the repository's notebooks, not the graded folder
    # (``make test-chapter`` grades one chapter alone)
    declaring = {name: [path.stem for path in chapter_notebooks(ROOT, "notebooks")
                        if name in {n for _, _, names in _answers_and_checks(load(path))[0] for n in names}]
                 for name in delegation.ANSWERS}
    assert all(len(chapters) == 1 for chapters in declaring.values()), declaring
    answers = [(3, "def transport(J, R, p):\n    return tool_jacobian(J, R, p)\n\n"
                   "def my_tool_jacobian(q):\n    return transport(arm.jacobian(q), R, p)\n", ["my_tool_jacobian"])]
    (item,) = delegation.find(answers, {})
    assert item["through"] == "transport" and item["reference"] == "robokin.motion.tool_jacobian"
    written = [(3, "def my_tool_jacobian(q):\n    return rigid(q) @ arm.jacobian(q)\n", ["my_tool_jacobian"])]
    assert delegation.find(written, {}) == []
    # the arm with the tool has the tool's Jacobian: its method, or the arm's for a point of E,
    # is flagged; the arm with the tool used for a position is not
    for body, reference in [("tool_arm.jacobian(q)", "tool_arm.jacobian"),
                            ("getattr(tool_arm, 'jacobian')(q)", "tool_arm.jacobian"),
                            ("arm.jacobian(q, point=TOOL_OFFSET)", "SerialChain.jacobian(q, point=...)")]:
        (item,) = delegation.find([(3, f"def my_tool_jacobian(q):\n    return {body}\n", ["my_tool_jacobian"])], {})
        assert item["reference"] == reference, body
    by_position = "def my_tool_jacobian(q):\n    r = tool_arm.fk(q)[:3, 3] - arm.fk(q)[:3, 3]\n" \
                  "    return rigid(r) @ arm.jacobian(q)\n"
    assert delegation.find([(3, by_position, ["my_tool_jacobian"])], {}) == []


def test_delegation_follows_a_robot_under_another_name():
    """An alias of the robot (``robot = tool_arm``, in the cell, in a function, as an attribute,
    through a chain or a walrus) is flagged as the direct call ``tool_arm.jacobian(q)`` is; an
    alias of the bare arm, whose Jacobian is the answer's legitimate start, is not."""
    from tools.grading.bridge import delegation

    use = "\n\ndef my_tool_jacobian(q):\n    return {}\n"
    aliased = [
        "robot = tool_arm" + use.format("robot.jacobian(q)"),
        "robot = tool_arm" + use.format("getattr(robot, 'jacobian')(q)"),
        "first = tool_arm\nrobot = first" + use.format("robot.jacobian(q)"),
        "robot = tool_arm\njac = robot.jacobian" + use.format("jac(q)"),
        "def my_tool_jacobian(q):\n    robot = tool_arm\n    return robot.jacobian(q)\n",
        "def my_tool_jacobian(q):\n    return (robot := tool_arm).jacobian(q)\n",
        "class Arm:\n    def __init__(self):\n        self.robot = tool_arm\n\n"
        "    def jacobian(self, q):\n        return self.robot.jacobian(q)\n" + use.format("Arm().jacobian(q)"),
    ]
    for code in aliased:
        found = delegation.find([(3, code, ["my_tool_jacobian"])], {})
        assert [item["reference"] for item in found] == ["tool_arm.jacobian"], code
    # the alias in another answer cell than the call
    cells = [(1, "robot = tool_arm\n", ["tool_arm"]),
             (3, "def my_tool_jacobian(q):\n    return robot.jacobian(q)\n", ["my_tool_jacobian"])]
    assert [item["name"] for item in delegation.find(cells, {})] == ["my_tool_jacobian"]
    written = ("robot = arm" + use.format("rigid(robot.fk(q)[:3, :3] @ TOOL_OFFSET) @ robot.jacobian(q)"))
    assert delegation.find([(3, written, ["my_tool_jacobian"])], {}) == []
    # a function's keyword counts as a method's: robokin's RPY error is not a wrapped difference
    library = "def rpy_difference(R, R_goal):\n    return pose_error(T(R), T(R_goal), representation='rpy')[3:]\n"
    (item,) = delegation.find([(5, library, ["rpy_difference"])], {})
    assert item["reference"] == "robokin.motion.pose_error(..., representation=...)"
    wrapped = "def rpy_difference(R, R_goal):\n    return wrap(rpy_from_rotation(R_goal) - rpy_from_rotation(R))\n"
    assert delegation.find([(5, wrapped, ["rpy_difference"])], {}) == []


def test_answers_are_handed_over_after_cells_that_printed_thousands_of_lines(tmp_path):
    """The grader's link learns that its request ended from the shell channel, not from iopub:
    iopub carries every output of the student's cells, which the link does not read between
    two tests, and ZeroMQ drops new messages for a reader some 2,000 behind -- the ``idle`` of
    the link's own request among them (a talkative submission then lost its answers)."""
    import shutil
    import time

    from tools.grading.bridge import benchmark, grader_side

    manager, client = benchmark.start_kernel(shutil.which("bwrap") is not None, str(tmp_path))
    # Time limits: the call limit, 60 s, is what a wait for a status that never comes would
    # last; the import below takes ~0.05 s on a quiet machine and under 1 s with both cores
    # busy, so it must end in less than half the call limit. The cell (3,000 lines, ~0.3 s
    # quiet) is given 120 s, a ceiling load does not reach; its end is read from the shell
    # channel (benchmark.run_cell), because iopub drops messages after thousands of lines.
    try:
        grader_side.connect(manager.get_connection_info(), 60.0)
        for round_ in range(2):   # the first import installs the bridge, the second reuses it
            benchmark.run_cell(
                client, f"import sys\nanswer = {round_} + 0.5\nfor i in range(3000):\n"
                "    print('a talkative line', i, file=sys.stderr, flush=True)\n", timeout=120)
            namespace: dict = {}
            started = time.monotonic()
            grader_side.import_names(namespace, ["answer", "scalar"], "imported: ")
            assert namespace.get("answer") == round_ + 0.5, namespace
            assert namespace["scalar"](0.0) == -0.5
            assert time.monotonic() - started < 30.0   # not a wait for a status that never comes
            assert not grader_side.status()["stuck"]
    finally:
        grader_side.disconnect()
        client.stop_channels()
        benchmark.stop_kernel(manager)


def test_call_channel_calls_calls_back_and_stops_a_call_that_never_returns(tmp_path):
    """The bridge's call channel with a student's kernel in the sandbox (as autograde starts it):
    a call returns data, a function of the test is called back, a call that never returns is
    stopped after the time limit per call, and after the interrupt the next call works."""
    import shutil

    import numpy as np
    from jupyter_core.utils import run_sync

    from tools.grading.bridge import benchmark, grader_side

    sandboxed = shutil.which("bwrap") is not None
    manager, client = benchmark.start_kernel(sandboxed, str(tmp_path))
    try:
        benchmark.run_cell(client, "import time\n\ndef slow(x):\n    time.sleep(10**6)\n\n"
                           "def twice(f, x):\n    return 2 * f(x)\n", timeout=60)
        # The call limit: 10 s, the time the call that never returns is given; every other call
        # takes milliseconds (under 0.1 s with both cores busy), far below it.
        grader_side.connect(manager.get_connection_info(), 10.0)
        namespace: dict = {}
        grader_side.import_names(namespace, ["scalar", "matrix", "slow", "twice"], "imported: ")
        assert namespace["scalar"](0.3) == np.sin(0.3) - 0.5
        assert np.array_equal(namespace["matrix"]([0.0, 1.0]), np.outer(np.cos([0.0, 1.0]), np.sin([0.0, 1.0])))
        assert namespace["twice"](lambda x: x + 1, 2) == 6   # the test's function, called back
        with pytest.raises(grader_side.AnswerError, match="took longer than 10 s"):
            namespace["slow"](1)
        assert grader_side.status(release=False)["stuck"]
        interrupt = manager.interrupt_kernel
        run_sync(interrupt)() if sandboxed else interrupt()
        grader_side.unstick()
        assert namespace["scalar"](0.0) == -0.5
        assert grader_side.status()["calls"] == 5 and not grader_side.status()["stuck"]
        reply = benchmark.run_cell(client, "x = 1", timeout=30)   # the student's kernel is free again
        assert reply["content"]["status"] == "ok"
    finally:
        grader_side.disconnect()
        client.stop_channels()
        benchmark.stop_kernel(manager)


def test_delegation_flags_the_legs_own_fk_for_the_whole_transform():
    """Chapter 1's ``H_BF = leg.fk(q_sym)`` (also under another name of ``leg``) hands back the
    model the tests compare with; the product of the student's own transforms is not flagged."""
    from tools.grading.bridge import delegation

    checks: dict[int | None, dict[str, set[str]]] = {2: {"leg.transform_BF": {"H_BF"}, "leg.foot_position": {"r_BF"}}}
    for code in ("H_BF = leg.fk(q_sym)\nr_BF = H_BF[:3, 3]\n",
                 "model = leg\nH_BF = model.fk(q_sym)\nr_BF = H_BF[:3, 3]\n"):
        found = delegation.find([(2, code, ["H_BF", "r_BF"])], checks)
        assert [(item["name"], item["reference"]) for item in found] == [("H_BF", "leg.fk (SerialChain.fk)")], found
    own = "H_BF = sp.simplify(H_B1 * H_12 * H_23 * H_3F)\nr_BF = H_BF[:3, 3]\nassert leg.fk(q0) is not None\n"
    assert delegation.find([(2, own, ["H_BF", "r_BF"])], checks) == []
