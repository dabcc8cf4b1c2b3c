"""Student edition and autograding with nbgrader (book/for-instructors.md, "Assigning chapters").

Everything goes through nbgrader's real command-line tools and its sqlite
gradebook, in temporary course directories (one per chapter, so that chapters
are graded two at a time without sharing a database), with ONE autograde run per
chapter that also grades the submissions of test_grading_trust.py (every chapter;
test_grading_tamper.py grades the everyday chapter, chapter 7, in a course of its own:
tests/support/grading_course.py). The student edition handed in unchanged
(``unanswered``) is also the tamper suite's blank submission, graded once per course:

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
written by ``tools/authoring/nbgrader_metadata.py`` (``test_metadata_is_up_to_date`` says
when they do not). ``ROBOKIN_NBGRADER_NOTEBOOKS=<folder>`` grades the notebooks
of another folder instead (e.g. a copy the script was run on).
"""

from __future__ import annotations

import copy
import html
import json
import re
import shutil
import subprocess
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pytest

from conftest import ROOT
from support import grading_course, installed
from support.nbgrader_course import (
    CHAPTERS,
    FEEDBACK_CHAPTER,
    HIDDEN_TESTS,
    NOTEBOOKS,
    WALKTHROUGH_CHAPTER,
    Run,
    code_cell,
    load,
    nbg,
    notes,
    rk,
    save,
    src,
    walkthrough_commands,
)
from tools.notebook_analysis import stub_plan

installed.require("nbgrader", "nbgrader is not installed: run `make test` (installs requirements.txt)")


@pytest.fixture(scope="session")
def graded(request, tmp_path_factory) -> Mapping[str, Run]:
    """Every chapter generated, submitted, autograded and given feedback (tests/support/grading_course.py);
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
    """The committed notebooks carry the metadata tools/authoring/nbgrader_metadata.py writes."""
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "authoring" / "nbgrader_metadata.py"), "--check"],
                          capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == 0, (
        "nbgrader metadata of the chapter notebooks is missing or stale; run "
        "`.venv/bin/python tools/authoring/nbgrader_metadata.py` and commit:\n" + (proc.stdout + proc.stderr)[-3000:]
    )


def test_metadata_script_writes_metadata_only_and_is_idempotent(tmp_path):
    folder = tmp_path / "notebooks"
    folder.mkdir()
    originals = {}
    for chapter in CHAPTERS:
        shutil.copy2(NOTEBOOKS / f"{chapter}.ipynb", folder)
        originals[chapter] = load(folder / f"{chapter}.ipynb")
    paths = [str(p) for p in sorted(folder.glob("*.ipynb"))]
    script = [sys.executable, str(ROOT / "tools" / "authoring" / "nbgrader_metadata.py")]
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
    subprocess.run([sys.executable, str(ROOT / "tools" / "authoring" / "nbgrader_metadata.py"), str(path)], check=True,
                   capture_output=True)
    nb = load(path)
    tests = [(i, rk(c).get("task")) for i, c in enumerate(nb["cells"])
             if "check" in c["metadata"].get("tags", []) and nbg(c).get("grade")]
    # a test of a task that has another one (a task left without a test is an error, exit 2)
    index = next(i for i, task in tests if sum(t == task for _, t in tests) > 1)
    nb["cells"][index]["metadata"]["tags"].remove("check")   # an author untags a check cell
    save(nb, path)
    proc = subprocess.run([sys.executable, str(ROOT / "tools" / "authoring" / "nbgrader_metadata.py"), "--check",
                           str(path)], capture_output=True, text=True)
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
def test_walkthrough_quotes_the_chapter_it_grades():
    """Every nbgrader command book/for-instructors.md quotes names the walk-through's chapter (the
    graded walk-through runs them as quoted; this says which chapter to change in both places)."""
    commands = walkthrough_commands()
    assert {who for who, _ in commands} == {"instructor", "student"}
    for _, line in commands:
        assert WALKTHROUGH_CHAPTER in line.split(), f"{line!r} does not name {WALKTHROUGH_CHAPTER}"


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


#: A cause that is the line an answer cell raised at (tools/grading/robokin_nbgrader/cells.py's
#: cell_label): ``In [4], line 13, `raise NotImplementedError()` (your answer to Task 3), which raised ...``
ANSWER_LINE_RAISED = re.compile(r"In \[\d+\], line \d+, `[^`]*` \(your answer to Task \d+\), which raised \w+")


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
                    part = line.split("This test failed because of")[-1]
                    # a cause may be the line of an answer cell that raised, quoted with its label
                    raised = ANSWER_LINE_RAISED.findall(part) if "because" in line else []
                    part = ANSWER_LINE_RAISED.sub("", part).split(":")[0]
                    named = set(re.findall(r"`([A-Za-z_]\w*)`", part if "because" in line else line))
                    assert (named or raised) and named <= answers, (
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

    from tools.grading.robokin_nbgrader import RestoreMissingCells
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


def _feedback_probe(graded, kind: str, none: str) -> tuple[Run, dict, str]:
    """The feedback chapter's run, its probe submission ``kind`` (``none``: why a chapter has
    none) and the note under the probe's test (``""``: none)."""
    if FEEDBACK_CHAPTER not in graded:
        pytest.skip("no chapter graded here")
    run = _run(graded, FEEDBACK_CHAPTER)
    probe = run.probes.get(kind)
    assert probe, f"{FEEDBACK_CHAPTER}: {none}"
    return run, probe, notes(run.autograded[kind]).get(probe["test"], "")


@grading_course.reads(FEEDBACK_CHAPTER)
def test_knock_on_failure_names_the_root_cause(graded):
    """An answer cell that raises on its first line: a later task's test that needs its names says so,
    and names that line (not the answer, whose code did not raise) as the root cause."""
    run, probe, note = _feedback_probe(graded, "knockon", "no test of a later task reads an answer of an earlier one")
    assert note, f"{FEEDBACK_CHAPTER}: {probe['test']} does not fail without {probe['name']} (Task {probe['task']})"
    cause = re.search(r"This test failed because of (.*?)\. Fix that first", note)
    line = (f', line 1, `raise RuntimeError("not finished")` (your answer to Task {probe["task"]}), '
            "which raised RuntimeError")
    assert cause and line in cause.group(1) and f"`{probe['name']}`" not in cause.group(1), (
        f"{FEEDBACK_CHAPTER} {probe['test']}: the note does not name the line of {probe['name']}'s answer cell "
        f"(Task {probe['task']}) that raised as the root cause:\n{note}")
    page = run.feedback["knockon"]
    start = html.unescape(page.split("Where to start", 1)[-1])
    assert "Where to start" in page and 'raise RuntimeError("not finished")' in start, start[:2000]


@grading_course.reads(FEEDBACK_CHAPTER)
def test_wrong_type_says_what_came_and_what_was_expected(graded):
    _, probe, note = _feedback_probe(graded, "wrongtype", "no test reads an attribute of an answer variable")
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
    """The feedback exporter's page is nbconvert's HTMLExporter page, the same document (parsed,
    element by element, attribute by attribute), with MathJax inlined (twice: an exporter makes a
    second page as its first; "lab" has the JupyterLab cells that get ``tabindex``). Only the
    start tags that gain an attribute are written again: every other byte is the template's."""
    import nbformat
    from bs4 import BeautifulSoup
    from nbconvert.exporters import HTMLExporter
    from tools.grading.robokin_nbgrader import OfflineMathJaxHTMLExporter, inline_mathjax

    pixel = ("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg==")
    nb = nbformat.v4.new_notebook(metadata={"language_info": {"name": "python", "pygments_lexer": "ipython3"}})
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: a formula $T_{BA} = T_{AB}^{-1}$ and `code` <b>bold</b> &amp;"),
        # images with and without alternative text, as raw HTML in Markdown (an upper-case tag, one
        # closed by "/>", an empty alt, one with a ">" in an attribute) and from Markdown's syntax
        nbformat.v4.new_markdown_cell(f'<IMG SRC="data:image/png;base64,{pixel}"> <img src="data:image/png;base64,'
                                      f'{pixel}" title="a > b"/> <img alt="" src="x.png"> ![a pixel](x.png) '
                                      '<div class="jp-Cell-inputWrapper">not in a notebook cell</div>'),
        nbformat.v4.new_code_cell("import numpy as np\n\ndef f(q):\n    return np.sin(q) @ q  # <img src=x>\n",
                                  outputs=[nbformat.v4.new_output("display_data", {"image/png": pixel}),
                                           nbformat.v4.new_output("display_data", {"text/html": (
                                               '<div class="jp-OutputArea-output" tabindex="-1"><img src="y.png">'
                                               "</div><script>let t = '<img src=z>';</script>")}),
                                           nbformat.v4.new_output("stream", name="stdout", text="<x> & 'y'\n"),
                                           nbformat.v4.new_output("error", ename="ValueError", evalue="bad",
                                                                  traceback=["\x1b[31mValueError\x1b[0m: bad"])]),
        nbformat.v4.new_code_cell("%%bash\necho hi", metadata={"magics_language": "bash"}),
    ]
    for _ in range(2):
        ours = OfflineMathJaxHTMLExporter(template_name=template).from_notebook_node(copy.deepcopy(nb))[0]
        plain = HTMLExporter(template_name=template).from_notebook_node(copy.deepcopy(nb))[0]
        assert BeautifulSoup(ours, "html.parser") == BeautifulSoup(inline_mathjax(plain), "html.parser")
    soup = BeautifulSoup(plain, "html.parser")
    assert ("tabindex=\"0\"" in plain) == (template == "lab") and 'alt="No description' in plain
    described = soup.select('img[alt="No description has been provided for this image"]')
    assert len(soup.select("img")) == 6 and len(described) == 4
    assert "<script>let t = '<img src=z>';</script>" in ours   # a script's text is no tag


def test_accessible_page_rewrites_only_the_start_tags_it_changes():
    """accessible_page keeps every byte but the start tags that gain an attribute: an image
    without alternative text, a focusable cell inside a ``.jp-Notebook`` (its ``tabindex`` set to
    0); not an image that has one, a cell outside a notebook, or a tag in a script's text."""
    from tools.grading.robokin_nbgrader.offline_mathjax import NO_DESCRIPTION, accessible_page

    kept = ('<p class="x">a &amp; b<br></p>\n<img alt="" src="a.png"><div class="jp-Cell-inputWrapper">'
            "</div><script>let t = '<img src=z>';</script>\n")
    assert accessible_page(kept) == (kept, 0)
    page = (kept + '<main class="jp-Notebook">\n  <IMG SRC="b.png" title="a &gt; b"/>\n'
            '  <div class="jp-OutputArea-output x" tabindex="-1" id=o>out</div>\n</main>')
    changed, missing = accessible_page(page)
    assert missing == 1
    assert changed == (kept + '<main class="jp-Notebook">\n'
                       f'  <img src="b.png" title="a &gt; b" alt="{NO_DESCRIPTION}"/>\n'
                       '  <div class="jp-OutputArea-output x" tabindex="0" id="o">out</div>\n</main>')


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

    from tools.grading.robokin_nbgrader import FailureNotes

    def error(ename, count, line):
        return {"output_type": "error", "ename": ename, "evalue": "", "traceback": [
            f"Cell In[{count}], line {line}"]}

    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: f"),
        code_cell("def f(x):\n    return x + 1", "task1_answer1", solution=True, task=1),
        code_cell("assert f(1) == 2", "task1_test1", grade=True, task=1, count=2,
                  outputs=[error("AssertionError", 2, 1)]),
        nbformat.v4.new_markdown_cell("## Task 2: g"),
        code_cell("J0 = 2.0\nscale = f(J0)", "cell-given"),
        code_cell("g = scale * 3", "task2_answer1", solution=True, task=2),
        code_cell("limit = 9.0\nassert abs(\n    g - limit\n) < 1e-9", "task2_test1", grade=True, task=2, count=5),
    ]
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
