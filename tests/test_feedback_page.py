"""What the feedback page says and how it reads, without nbgrader commands or a kernel.

The preprocessors of ``generate_feedback`` and the notes autograde writes
(``tools/grading/robokin_nbgrader/``) on made-up notebooks:

* MyST markup of the task statements (``{exercise}``, ``{admonition}``, ``{cite}``, ``{doc}``)
  becomes Markdown the page renders, for every chapter notebook in ``notebooks/``;
* the page's notes wrap at its width and its tables have a gap between columns;
* *Where to start* and the note under a failing test never blame an answer that
  ``robokin.check`` finds correct, an answer's "own tests" are tests of its task, a value
  computed from robokin's model is not called the student's, and the note on an error in an
  ungraded cell quotes the line that raised (the cell's statement, not a line in the body of a
  function it called), and an answer cell that raised blames a function of the cell only when the
  error passed through its body (else the line that raised);
* a value ``robokin.check`` finds wrong because it is computed from a wrong earlier answer, while
  its own tests pass, says that it follows from that answer;
* the note under a test tagged ``explains-<answer>`` asks about and blames only the answers it
  names (an earlier answer whose cell raised is still the cause).

``tests/test_nbgrader.py`` checks the pages of real graded submissions.
"""

from __future__ import annotations

import html
import os
import re
from pathlib import Path
from typing import Any

import nbformat
import pytest

from conftest import ROOT
from support.nbgrader_course import code_cell
from tools.authoring.nbgrader_metadata import chapter_notebooks

NOTEBOOKS = Path(os.environ.get("ROBOKIN_NBGRADER_NOTEBOOKS", ROOT / "notebooks")).resolve()
CHAPTERS = chapter_notebooks(NOTEBOOKS.parent, NOTEBOOKS.name)
#: MyST that nbconvert's Markdown would show raw: a directive's fence, a role.
RAW_MYST = re.compile(r"(```+|:::+)\{[\w:-]+\}|\{[a-z][\w:-]*\}`")


def _myst(text: str, notebook: str = "03_example") -> str:
    from tools.grading.robokin_nbgrader import MystMarkdown

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell(text)]
    nb, _ = MystMarkdown().preprocess(nb, {"nbgrader": {"notebook": notebook}})
    return nb.cells[0].source


def test_myst_directives_and_roles_become_markdown():
    text = ("## Task 1: a title\n\n```{exercise-start}\n:label: rpr-ik\n```\nWrite `ik(pose)`, see "
            "{cite}`lynch2017` and {cite}`siciliano2009,craig2005`.\n```{exercise-end}\n```\n\n"
            "```{admonition} Common pitfall: the moment arm\n:class: warning\nThe arm is $B_i - P$ "
            "({doc}`the conventions <../book/conventions>`).\n```\n\n```python\n{cite}`not_a_role`\n```")
    out = _myst(text)
    assert not RAW_MYST.search(out.replace("```python\n{cite}`not_a_role`\n```", "")), out
    assert "**Exercise 3.1**" in out and "Write `ik(pose)`" in out and ":label:" not in out, out
    assert "(Lynch and Park, 2017)" in out and "(Siciliano et al., 2009; Craig, 2005)" in out, out
    assert "> **Common pitfall: the moment arm**" in out and "> The arm is $B_i - P$ (the conventions)." in out
    assert ":class:" not in out and "../book" not in out, "the options and the book's links stay"
    assert "```python\n{cite}`not_a_role`\n```" in out, "a code block is not MyST"


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_no_raw_myst_in_a_chapters_feedback(path):
    """Every text cell of the chapter, as the feedback page shows it: no directive or role is left raw,
    and no link points into the book's folder (it does not resolve where the page is read)."""
    from tools.grading.robokin_nbgrader import MystMarkdown

    nb = nbformat.read(path, as_version=4)
    nb, _ = MystMarkdown().preprocess(nb, {"nbgrader": {"notebook": path.stem}})
    for index, cell in enumerate(nb.cells):
        if cell.cell_type != "markdown":
            continue
        outside_code = re.sub(r"^(```+|~~~+)[^{\n]*\n.*?^\1\s*$", "", cell.source, flags=re.S | re.M)
        raw = RAW_MYST.findall(outside_code)
        assert not raw, f"{path.stem} cell {index}: raw MyST in the feedback: {raw[:3]}\n{cell.source[:300]}"
        assert "](../" not in cell.source, f"{path.stem} cell {index}: a link into the book's folder"


def test_feedback_page_wraps_notes_and_spaces_table_columns(tmp_path):
    from nbconvert.exporters import HTMLExporter
    from nbconvert.preprocessors import CSSHTMLHeaderPreprocessor

    from tools.grading.robokin_nbgrader import FeedbackStyle

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("| task | points |\n|---|---|\n| Task 1: foot position | 0 / 2 |")]
    resources: dict = {"config_dir": str(tmp_path), "nbgrader": {"notebook": "01_example", "score": 0, "max_score": 2,
                                                              "late_penalty": 0}}
    import nbgrader

    formgrader = Path(nbgrader.__file__).parent / "server_extensions" / "formgrader"   # as GenerateFeedback sets it
    exporter = HTMLExporter(template_name="feedback", extra_template_basedirs=[str(formgrader / "templates")],
                            extra_template_paths=[str(formgrader / "static/node_modules/bootstrap/dist/css")])
    exporter.register_preprocessor(CSSHTMLHeaderPreprocessor(), enabled=True)   # as nbgrader's pipeline runs them
    exporter.register_preprocessor(FeedbackStyle(), enabled=True)
    page = exporter.from_notebook_node(nb, resources)[0]
    assert "white-space: pre-wrap" in page and "padding: 0.25em 0.9em" in page
    # Bootstrap's pre {word-break: break-all} cut words at the line's end: lines break at spaces
    assert "pre-wrap; word-break: normal" in page


# ---------------------------------------------------------------- what the notes say
def _error(ename, count, line, evalue=""):
    return {"output_type": "error", "ename": ename, "evalue": evalue,
            "traceback": [f"Cell In[{count}], line {line}\n----> {line} whatever", f"{ename}: {evalue}"]}


def _leg_notebook():
    """Task 1: two answers and their test (which fails); Task 2: a given cell that computes a model value
    and, in another statement, one from the answers; a test of Task 2 that fails."""
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: rotations"),
        code_cell("R_a = rot(1)\nR_b = rot(2)", "task1_answer1", solution=True, task=1, count=1),
        code_cell("assert np.allclose(R_a @ R_b, model(3))", "task1_test1", grade=True, task=1, count=2,
              outputs=[_error("AssertionError", 2, 1)]),
        nbformat.v4.new_markdown_cell("## Task 2: the foot"),
        code_cell("H_model = leg_frames(q)\nH = R_a @ R_b", "cell-given", count=3),
        code_cell("foot = H[:3, 3]", "task2_answer1", solution=True, task=2, count=4),
        code_cell("h = 1e-6\nJ_fd = fd(leg_fk, q_lift)\nassert np.allclose(H_model, foot_model)\n"
              "assert np.allclose(J_fd, foot)", "task2_test1", grade=True, task=2, count=5),
        code_cell("q_lift = [0, 1, 2]", "task2_answer2", solution=True, task=2, count=6),
    ]
    # q_lift answered after the test reads it would be odd: move it before the test
    nb.cells.insert(6, nb.cells.pop(7))
    return nb


def test_a_model_value_is_not_the_students_and_a_correct_answer_is_no_cause():
    from tools.grading.robokin_nbgrader import FailureNotes

    nb = _leg_notebook()
    index = next(i for i, c in enumerate(nb.cells) if c.metadata.get("nbgrader", {}).get("grade_id") == "task2_test1")
    # the test fails at its last line (J_fd against foot)
    failure = nbformat.from_dict(_error("AssertionError", 5, 4))
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    notes = FailureNotes(nb, index, report)
    notes.pairs(failure)
    assert "H_model" not in notes.derived and "H_model" not in notes.yours, "leg_frames(q) is not the student's"
    correct = [{"quantity": "R_a", "status": "correct", "message": "✔ R_a is correct", "typical": False}]
    text = "\n".join(notes.lines(failure, correct))
    assert "because of `R_b` (Task 1)" in text and "`R_a`" not in text.split("because of")[1].split(".")[0], text
    assert "It also reads `J_fd`, computed earlier in this test cell; it uses your answer `q_lift`" in text, text
    assert "`foot` (Task 2) uses your earlier answers `R_a`, `R_b` (Task 1)." in text, text
    assert [c["names"] for c in report["causes"].values()] == [["R_b"]], report["causes"]


def test_own_tests_are_the_tests_of_the_answers_task():
    from tools.grading.robokin_nbgrader import FailureNotes

    nb = _leg_notebook()
    nb.cells.append(nbformat.v4.new_markdown_cell("## Task 3: later"))
    nb.cells.append(code_cell("assert foot[2] < 0", "task3_test1", grade=True, task=3, count=7))
    failed = next(c for c in nb.cells if c.metadata.get("nbgrader", {}).get("grade_id") == "task2_test1")
    failed.outputs = [nbformat.from_dict(_error("AssertionError", 5, 4))]
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    notes = FailureNotes(nb, len(nb.cells) - 1, report)
    text = "\n".join(notes.lines(nbformat.from_dict(_error("AssertionError", 7, 1)), []))
    # foot's own test task2_test1 failed; R_a, R_b (Task 1) are named for task1_test1 only, never task2_test1
    assert "`foot` (Task 2): its own test task2_test1 failed" in text or "own test task1_test1" in text, text
    for line in text.splitlines():
        if "R_a" in line and "own test" in line:
            assert "task2_test1" not in line.split("R_a")[1].split(";")[0], line


def test_report_quotes_the_line_that_raised_and_drops_correct_causes():
    from tools.grading.robokin_nbgrader import AutograderReport

    nb = nbformat.v4.new_notebook()
    ungraded = code_cell("x = 1\ny = 2\nassert y == 3, 'my own experiment'", count=9,
                     outputs=[_error("AssertionError", 9, 3, "my own experiment")])
    test = code_cell("assert R_b is not None", "task1_test1", grade=True, task=1, count=10,
                 outputs=[_error("AssertionError", 10, 1)])
    nb.cells = [nbformat.v4.new_markdown_cell("# Chapter"), ungraded, test]
    resources = {"robokin": {
        "pairs": [(1, "leg.a", "R_a"), (1, "leg.b", "R_b")],
        "verdicts": [{"quantity": "R_a", "status": "correct", "message": "✔ R_a is correct", "typical": False},
                     {"quantity": "R_b", "status": "wrong", "message": "✘ R_b is transposed", "typical": True,
                      "diagnosis": "transpose"}],
        "causes": {"1|own test task1_test1 failed": {"task": 1, "why": "own test task1_test1 failed",
                                                     "names": ["R_a", "R_b"], "tests": ["task2_test1"]}},
        "incidents": []}}
    nb, _ = AutograderReport().preprocess(nb, resources)
    report = nb.cells[0].source
    start = report.split("**Where to start**")[1].split("**Notes")[0]
    assert "`R_b`" in start and "`R_a`" not in start, report
    assert "line 3, `assert y == 3, 'my own experiment'`" in report and "`x = 1`" not in report, report


def test_feedback_page_shows_no_markdown_raw():
    """The report's own Markdown renders (a smoke test of the exporter with the feedback's preprocessors)."""
    from nbconvert.exporters import HTMLExporter

    from tools.grading.robokin_nbgrader import MystMarkdown

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("```{admonition} Learning goals\n:class: tip\n- one\n```")]
    nb, _ = MystMarkdown().preprocess(nb, {})
    page = html.unescape(re.sub(r"<[^>]+>", "", HTMLExporter(template_name="classic").from_notebook_node(nb)[0]))
    assert "{admonition}" not in page and "Learning goals" in page and ":class:" not in page


def test_a_check_that_names_the_answer_otherwise_says_so():
    """A check's message uses its own name of the answer: the note says which of the student's it is."""
    from tools.grading.course import check_names

    from tools.grading.robokin_nbgrader.checks import called_as

    check, own = next(iter(sorted(check_names().items())))
    verdict = {"check": check, "quantity": "found[0]", "status": "wrong", "message": f"✘ {own} is transposed"}
    assert called_as(verdict) == f" (on your `found[0]`, which it calls `{own}`)"
    assert called_as({**verdict, "quantity": own}) == ""
    assert called_as({**verdict, "message": "✘ the value is transposed"}) == ""
    from tools.grading.robokin_nbgrader import AutograderReport

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("# Chapter"),
                code_cell("assert False", "task1_test1", grade=True, task=1, count=1,
                      outputs=[_error("AssertionError", 1, 1)])]
    resources = {"robokin": {"pairs": [(1, check, "found[0]")], "verdicts": [{**verdict, "typical": False}],
                             "incidents": []}}
    report = AutograderReport().preprocess(nb, resources)[0].cells[0].source
    assert f"- Task 1 (on your `found[0]`, which it calls `{own}`): ✘ {own} is transposed" in report, report


def test_where_to_start_has_one_line_per_answer_with_all_its_tests():
    """Causes recorded by several failing tests (for different reasons) merge by the answer's name."""
    from tools.grading.robokin_nbgrader import AutograderReport

    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("# Chapter")] + [
        code_cell("assert False", grade_id, grade=True, task=task, count=count,
              outputs=[_error("AssertionError", count, 1)])
        for count, (grade_id, task) in enumerate([("task1_test1", 1), ("task4_test1", 4), ("task4_test2", 4)], 1)]
    resources = {"robokin": {"pairs": [], "verdicts": [], "incidents": [], "causes": {
        "1|own test task1_test1 failed": {"task": 1, "why": "own test task1_test1 failed",
                                          "names": ["newton_ik"], "tests": ["task4_test2"]},
        "1|answer cell In [3] raised ValueError": {"task": 1, "why": "answer cell In [3] raised ValueError",
                                                   "names": ["newton_ik", "q_start"],
                                                   "tests": ["task4_test2", "task4_test1"]},
        "1|own tests task4_test1, task1_test1 failed": {"task": 1, "why": "own tests task4_test1, task1_test1 failed",
                                                        "names": ["newton_ik"], "tests": ["task4_test2"]}}}}
    report = AutograderReport().preprocess(nb, resources)[0].cells[0].source
    start = report.split("**Where to start**")[1].strip().splitlines()
    assert len(start) == 2 and sum("`newton_ik`" in line for line in start) == 1, start
    assert start[0] == ("- `newton_ik` (Task 1): its own tests task1_test1, task4_test1 failed and its answer cell "
                        "In [3] raised ValueError; the failing tests task4_test1, task4_test2 depend on it. "
                        "Fix it first."), start


def test_provenance_follows_the_data_flow_of_an_answer_cell():
    """A name uses the answers its defining statements read, transitively: ``closed`` is computed
    from ``ik_closed_form`` only, ``found`` from ``newton_ik`` through the list it appends to."""
    from tools.grading.robokin_nbgrader.failure_notes import trace

    cells = [("answer", "def newton_ik(p, q):\n    return [q]"),
             ("code", "r_goal = [0.2, 0.5, -2.0]"),
             ("answer", "def ik_closed_form(p):\n    return [p]\n\n\nclosed = ik_closed_form(r_goal)\n"
                        "found = []\nfor q_start in [0, 1]:\n    q_end = newton_ik(r_goal, q_start)[-1]\n"
                        "    found.append(q_end)\nfound = sorted(found)"),
             ("code", "closed_sorted = sorted(closed)\nboth = [closed, found]"),
             ("code", "closed_sorted, both")]
    reads = trace(cells)[-1]
    assert reads["closed_sorted"].roots == {"closed", "ik_closed_form"} and not reads["closed_sorted"].answer, reads
    assert reads["both"].roots == {"closed", "ik_closed_form", "found", "newton_ik"}, reads
    assert trace(cells)[3]["found"].answer and "newton_ik" in trace(cells)[3]["found"].roots


def test_a_function_uses_the_functions_its_body_calls_in_its_cell():
    """``my_leg_ik`` calls ``ankle_angles`` of its cell, defined after it: it
    uses it (``hip`` is shadowed there by a local name); a default argument from an earlier cell
    stays a root; ``Q_mine``, a value computed in the cell by calling ``my_leg_ik``, uses it and its
    helpers, and an unused function uses nothing."""
    from tools.grading.robokin_nbgrader.failure_notes import _cell_functions_used, trace

    cells = [("answer", "def ankle_point(T):\n    return T"),
             ("answer", "def my_leg_ik(T, ankle=ankle_point):\n    return [ankle_angles(ankle(T))]\n\n\n"
                        "def ankle_angles(u):\n    hip = 2\n    return u * hip\n\n\n"
                        "def hip(u):\n    return u\n\n\ndef unused(u):\n    return u\n\n\n"
                        "Q_mine = my_leg_ik(1.0)\nk = 8"),
             ("code", "my_leg_ik, Q_mine, ankle_angles, unused, k")]
    reads = trace(cells)[-1]
    assert reads["my_leg_ik"].roots == {"my_leg_ik", "ankle_angles", "ankle_point"}, reads
    assert reads["Q_mine"].roots == {"Q_mine", "my_leg_ik", "ankle_angles", "ankle_point"}, reads
    assert reads["ankle_angles"].roots == {"ankle_angles"}, reads
    assert reads["unused"].roots == {"unused"} and reads["k"].roots == {"k"}, reads
    used = {name: (used, calls) for name, used, calls in _cell_functions_used(cells[1][1])}
    assert used == {"my_leg_ik": (("ankle_angles",), ()), "Q_mine": (("ankle_angles", "my_leg_ik"), ("my_leg_ik",))}


def test_a_helper_reached_through_a_function_body_is_judged_by_its_check():
    """A failing test of ``leg_ik``, whose body calls ``ankle_angles`` and ``hip_angles`` of its
    cell: a helper is named only when ``robokin.check`` finds it wrong (``ankle_angles``); one it
    finds correct, or cannot check (``hip_angles``), leaves the blame on ``leg_ik``."""
    from tools.grading.robokin_nbgrader import FailureNotes

    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: the leg"),
        code_cell("def leg_ik(T):\n    return [hip_angles(a) for a in ankle_angles(T)]\n\n\n"
                  "def ankle_angles(u):\n    return [u]\n\n\ndef hip_angles(R):\n    return R",
                  "task1_answer1", solution=True, task=1),
        code_cell("assert leg_ik(1.0) == [2.0]", "task1_test1", grade=True, task=1, count=2,
                  outputs=[_error("AssertionError", 2, 1)]),
        code_cell("assert len(leg_ik(2.0)) == 2", "task1_test2", grade=True, task=1, count=3,
                  outputs=[_error("AssertionError", 3, 1)]),
    ]
    failure = nbformat.from_dict(_error("AssertionError", 3, 1))
    check = "ar601.ankle_angles"
    for status, blamed in [("wrong", "`ankle_angles` (Task 1): its value is wrong for robokin.check"),
                           ("correct", "`leg_ik` (Task 1): its own test task1_test1 failed"),
                           (None, "`leg_ik` (Task 1): its own test task1_test1 failed")]:
        report: dict[str, Any] = {"pairs": [[1, check, "ankle_angles"]], "explained": {}}
        notes_ = FailureNotes(nb, 3, report)
        assert (check, "ankle_angles") in notes_.pairs(failure)
        verdicts = [] if status is None else [{
            "status": status, "quantity": "ankle_angles", "check": check, "typical": False,
            "diagnosis": "q5 of the wrong sign" if status == "wrong" else "",
            "message": f"{'✘' if status == 'wrong' else '✔'} ankle_angles"}]
        text = "\n".join(notes_.lines(failure, verdicts))
        assert f"This test failed because of {blamed}" in text, (status, text)
        assert "hip_angles`" not in text.split("because of")[1], (status, text)


def test_a_function_of_a_module_changes_nothing():
    """``np.sort(x)`` is a value, not a change of ``np``: ``np`` never takes the student's answers."""
    from tools.grading.robokin_nbgrader.failure_notes import trace

    cells = [("code", "import numpy as np"), ("answer", "modes = [3, 1]"),
             ("code", "assert np.allclose(np.sort(modes), [1, 3])\nnp.random.shuffle(modes)"),
             ("code", "np")]
    assert trace(cells)[-1]["np"].roots == frozenset()


def test_a_function_of_a_module_called_as_a_statement_changes_nothing():
    """A bare ``np.sort(modes)`` calls a function of the module ``np``: ``np`` keeps no answer of
    the student's, while ``found.sort()`` on the student's list still passes the list on."""
    from tools.grading.robokin_nbgrader.failure_notes import trace

    cells = [("code", "import numpy as np\nimport numpy.linalg as la"), ("answer", "modes = [3, 1]"),
             ("code", "np.sort(modes)\nla.pop(modes)\nfound = []\nfound.append(modes)\nfound.sort()"),
             ("code", "np, la, found")]
    reads = trace(cells)[-1]
    assert reads["np"].roots == frozenset() and reads["la"].roots == frozenset(), reads
    assert reads["found"].roots == {"modes"}, reads


_MEMOS = ("_imported_modules", "_top_level", "_with_mutations")


def _failure_note(nb) -> tuple[list[str], list[tuple[str, str]], dict]:
    """The note of the leg notebook's failing Task 2 test, its questions to the kernel and the report."""
    from tools.grading.robokin_nbgrader import FailureNotes

    index = next(i for i, c in enumerate(nb.cells) if c.metadata.get("nbgrader", {}).get("grade_id") == "task2_test1")
    failure = nbformat.from_dict(_error("AssertionError", 5, 4))
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    notes = FailureNotes(nb, index, report)
    pairs = notes.pairs(failure)
    return notes.lines(failure, []), pairs, report


def test_the_memoised_parses_give_the_notes_of_the_uncached_ones(monkeypatch):
    """Each cell source is parsed once (memoised by its text alone): the note, its questions to the
    kernel and the report are those of the functions without their memo, cold and warm alike."""
    from tools.grading.robokin_nbgrader import failure_notes

    for memo in _MEMOS:
        getattr(failure_notes, memo).cache_clear()
    cold = _failure_note(_leg_notebook())
    warm = _failure_note(_leg_notebook())
    assert failure_notes._top_level.cache_info().hits > 0 and failure_notes._with_mutations.cache_info().hits > 0
    with monkeypatch.context() as patch:
        for memo in _MEMOS:
            patch.setattr(failure_notes, memo, getattr(failure_notes, memo).__wrapped__)
        uncached = _failure_note(_leg_notebook())
    assert cold == warm == uncached, (cold, warm, uncached)
    assert any("because of `R_a`, `R_b` (Task 1)" in line for line in cold[0]), cold[0]


def test_memoised_mutations_depend_on_the_statement_and_the_modules_only():
    """A statement read once with ``np`` a module and once with ``np`` the student's list: the
    memo, keyed by the statement and the modules, still finds the change in the second notebook;
    a cell read again is split into the same statements, and one that does not parse stays whole."""
    from tools.grading.robokin_nbgrader.failure_notes import _statements, trace

    with_module = [("code", "import numpy as np"), ("answer", "modes = [3, 1]"), ("code", "np.sort(modes)"),
                   ("code", "np")]
    with_list = [("answer", "np = [2, 0]"), ("answer", "modes = [3, 1]"), ("code", "np.sort(modes)"),
                 ("code", "np")]
    for _ in range(2):   # cold, then from the memo
        assert trace(with_module)[-1]["np"].roots == frozenset()
        assert trace(with_list)[-1]["np"].roots == {"np", "modes"}
    appended = [("answer", "q_end = 1.0"), ("code", "found = []\nfound.append(q_end)"), ("code", "found")]
    assert trace(appended)[-1]["found"].roots == trace(appended)[-1]["found"].roots == {"q_end"}
    two = "a = 1\nb = (a,\n     2)"
    assert _statements(two) == _statements(two) == ["a = 1", "b = (a,\n     2)"]
    assert _statements("a = (") == _statements("a = (") == ["a = ("]


def _screw_notebook(screw_axis_fails: bool):
    """Task 2 of chapter 8 in small: an answer cell defines ``screw_axis`` and computes ``S_list``
    by calling it (through a value of its cell); ``screw_axis``'s test fails or passes, ``S_list``'s
    fails; Task 3 reads ``S_list`` and computes ``T0`` by calling its own ``poe_fk``."""
    first = [_error("AssertionError", 2, 1)] if screw_axis_fails else []
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 2: screw axes"),
        code_cell("def screw_axis(omega, point):\n    return omega + point\n\n\n"
                  "rows = [screw_axis(w, p) for w, p in frames]\nS_list = np.array(rows)",
                  "task2_answer1", solution=True, task=2, count=1),
        code_cell("assert np.allclose(screw_axis(w, p), ref(w, p))", "task2_test1", grade=True, task=2,
                  count=2, outputs=first),
        code_cell("assert np.allclose(S_list, S_ref)", "task2_test2", grade=True, task=2, count=3,
                  outputs=[_error("AssertionError", 3, 1)]),
        nbformat.v4.new_markdown_cell("## Task 3: the pose"),
        code_cell("def poe_fk(M, S_list, theta):\n    return M\n\n\nT0 = poe_fk(M, S_list, THETA0)",
                  "task3_answer1", solution=True, task=3, count=4),
        code_cell("assert np.allclose(T0, fk(THETA0))", "task3_test1", grade=True, task=3, count=5,
                  outputs=[_error("AssertionError", 5, 1)]),
    ]
    return nb


def test_a_value_computed_by_a_function_of_its_cell_leads_to_that_function():
    """``S_list``, computed in its answer cell by calling the cell's ``screw_axis``: its failing
    test names ``screw_axis`` (whose own test failed) as the cause, and the note says so; a test
    of ``T0`` (computed by ``poe_fk`` from ``S_list``) starts from ``screw_axis`` too, and says that
    ``T0`` uses those earlier answers."""
    from tools.grading.robokin_nbgrader import FailureNotes
    from tools.grading.robokin_nbgrader.failure_notes import trace

    nb = _screw_notebook(screw_axis_fails=True)
    kinds = [("answer" if c.metadata.get("nbgrader", {}).get("solution") else "code", c.source)
             if c.cell_type == "code" else ("markdown", "") for c in nb.cells]
    assert trace(kinds)[3]["S_list"].roots == {"S_list", "screw_axis"}
    assert trace(kinds)[6]["T0"].roots == {"T0", "S_list", "screw_axis", "poe_fk"}
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    failure = nbformat.from_dict(_error("AssertionError", 3, 1))
    notes_ = FailureNotes(nb, 3, report)
    notes_.pairs(failure)
    text = "\n".join(notes_.lines(failure, []))
    assert "This test failed because of `screw_axis` (Task 2): its own test task2_test1 failed." in text, text
    assert ("`S_list` (Task 2) is computed in its answer cell from your `rows`; it uses your function "
            "`screw_axis`.") in text, text
    failure = nbformat.from_dict(_error("AssertionError", 5, 1))
    text = "\n".join(FailureNotes(nb, 6, report).lines(failure, []))
    assert "This test failed because of `screw_axis` (Task 2): its own test task2_test1 failed." in text, text
    # the answers of earlier cells it uses are named where the note says what T0 is computed from:
    # the cause line's screw_axis is not a name out of nowhere
    assert ("`T0` (Task 3) is computed in its answer cell by your function `poe_fk` and uses your earlier "
            "answers `S_list`, `screw_axis` (Task 2).") in text, text


def _tool_notebook():
    """Task 1 of chapter 4 in small: an answer cell builds ``T_ET`` from its values ``TOOL_YPR``,
    ``TOOL_OFFSET`` by its function ``transform_from_ypr``, then ``tool_arm`` from ``T_ET`` and
    ``T_BT0, T_BE0`` from ``tool_arm`` and the model; tests of ``T_ET`` and ``T_BT0`` fail."""
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: the tool frame"),
        code_cell("TOOL_YPR = np.array([0.0, 0.0, np.pi / 10])\nTOOL_OFFSET = np.array([0.002, 0.0, 0.0])\n\n\n"
                  "def transform_from_ypr(ypr, position):\n    return homogeneous(rotz(ypr[0]), position)\n\n\n"
                  "T_ET = transform_from_ypr(TOOL_YPR, TOOL_OFFSET)\ntool_arm = chain_with_tool(arm, T_ET)\n"
                  "T_BT0, T_BE0 = tool_arm.fk(Q0), arm.fk(Q0)\nmine = []\nmine.append(T_BE0)",
                  "task1_answer1", solution=True, task=1, count=1),
        code_cell("assert np.allclose(T_ET[:3, 3], OFFSET)", "task1_test1", grade=True, task=1, count=2,
                  outputs=[_error("AssertionError", 2, 1)]),
        code_cell("assert np.allclose(T_BT0, T_BE0 @ T_ET)\nassert np.allclose(mine, 0)", "task1_test2",
                  grade=True, task=1, count=3, outputs=[_error("AssertionError", 3, 2)]),
    ]
    return nb


def test_a_value_computed_from_values_of_its_cell_names_them():
    """``T_ET``, computed in its answer cell from the cell's ``TOOL_YPR`` and ``TOOL_OFFSET`` by its
    function: the note names the two values it was computed from, then the function; ``T_BT0``
    names ``tool_arm``, the value it read (not ``T_BE0``, the other element of its assignment, nor the
    values ``tool_arm`` was computed from); a list changed in place reads what the change reads."""
    from tools.grading.robokin_nbgrader import FailureNotes
    from tools.grading.robokin_nbgrader.failure_notes import _cell_values_read

    nb = _tool_notebook()
    read = dict(_cell_values_read(nb.cells[1].source, frozenset({"np"})))
    assert read == {"T_ET": ("TOOL_YPR", "TOOL_OFFSET"), "tool_arm": ("T_ET",), "T_BT0": ("tool_arm",),
                    "mine": ("T_BE0",)}, read
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    failure = nbformat.from_dict(_error("AssertionError", 2, 1))
    text = "\n".join(FailureNotes(nb, 2, report).lines(failure, []))
    assert ("`T_ET` (Task 1) is computed in its answer cell from your `TOOL_YPR`, `TOOL_OFFSET`; it uses "
            "your function `transform_from_ypr`.") in text, text
    failure = nbformat.from_dict(_error("AssertionError", 3, 1))
    text = "\n".join(FailureNotes(nb, 3, report).lines(failure, []))
    assert ("`T_BT0` (Task 1) is computed in its answer cell from your `tool_arm`; it uses your function "
            "`transform_from_ypr`.") in text, text
    assert "`T_BE0` (Task 1) is computed" not in text, text   # read from the model alone
    failure = nbformat.from_dict(_error("AssertionError", 3, 2))
    text = "\n".join(FailureNotes(nb, 3, report).lines(failure, []))
    assert "`mine` (Task 1) is computed in its answer cell from your `T_BE0`." in text, text


def test_a_correct_function_does_not_take_the_blame_of_the_value_it_computes():
    """``screw_axis`` passes its test (or ``robokin.check`` finds it correct): ``S_list``'s failing test
    names ``S_list`` (its call is wrong), never ``screw_axis``; a function a test reaches only
    through a value it computed is no suspect by that test (``x = f(x)``, ``f`` unchecked)."""
    from tools.grading.robokin_nbgrader import FailureNotes

    failure = nbformat.from_dict(_error("AssertionError", 3, 1))
    for verdicts in ([], [{"quantity": "screw_axis", "status": "correct", "typical": False,
                           "check": "poe.screw_axis", "message": "✔ screw_axis is correct"}]):
        nb = _screw_notebook(screw_axis_fails=False)
        report: dict[str, Any] = {"pairs": [[2, "poe.screw_axis", "screw_axis"]], "explained": {}}
        report["wrong"] = {"S_list": "cross_sign"}
        notes_ = FailureNotes(nb, 3, report)
        asked = notes_.pairs(failure)
        assert ("poe.screw_axis", "screw_axis") in asked, asked
        text = "\n".join(notes_.lines(failure, verdicts))
        cause = text.split("because of")[1].split(". Fix")[0]
        assert "`S_list` (Task 2): its value is wrong for robokin.check" in cause, text
        assert "screw_axis" not in cause, text
        # the cause is the answer this test checks: nothing to fix "first"
        assert "(cross_sign). Fix it: this test may then pass." in text, text
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: R"),
        code_cell("R = np.eye(3)\n\n\ndef change(value):\n    return value.T\n\n\nR = change(R)",
                  "task1_answer1", solution=True, task=1, count=1),
        code_cell("assert np.allclose(R, R_ref)", "task1_test1", grade=True, task=1, count=2,
                  outputs=[_error("AssertionError", 2, 1)]),
        code_cell("assert np.allclose(R @ R_ref, I)", "task1_test2", grade=True, task=1, count=3,
                  outputs=[_error("AssertionError", 3, 1)]),
    ]
    text = "\n".join(FailureNotes(nb, 3, {"pairs": [], "explained": {}}).lines(
        nbformat.from_dict(_error("AssertionError", 3, 1)), []))
    assert "This test failed because of `R` (Task 1): its own test task1_test1 failed." in text, text


def _flange_notebook(failing_line: int):
    """Task 1: a function, a constant, a table and a value computed from them; its first test reads
    the function and the constant at line 1 and the value at line 2 and fails at ``failing_line``;
    its second test checks the table through the function and fails."""
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: the tables"),
        code_cell("def fk(table, q, d=0.1):\n    return chain(table, q) + d\n\n\nD = 0.2\n"
                  "table = [1, 2, 3]\ngap = abs(fk(table, q, D) - model(q))",
                  "task1_answer1", solution=True, task=1, count=1),
        code_cell("assert np.isclose(fk(printed, q, D), shifted(q))\nassert gap < 5e-4", "task1_test1",
                  grade=True, task=1, count=2, outputs=[_error("AssertionError", 2, failing_line)]),
        code_cell("check_fk(lambda q: fk(table, q, D), raise_on_fail=True)", "task1_test2", grade=True,
                  task=1, count=3, outputs=[_error("AssertionError", 3, 1)]),
    ]
    return nb


def test_an_answer_is_a_cause_only_if_the_statement_that_failed_read_it():
    """An earlier test that reads ``fk`` and ``D`` in a statement that passes and fails at its check
    of ``gap`` is no own failed test of ``fk`` or ``D``: the later test that reads them names no
    cause (its own message names the mistake). When that test failed at the statement that reads
    them, they are the cause."""
    from tools.grading.robokin_nbgrader import FailureNotes

    failure = nbformat.from_dict(_error("AssertionError", 3, 1))
    text = "\n".join(FailureNotes(_flange_notebook(2), 3, {"pairs": [], "explained": {}}).lines(failure, []))
    assert "It checks your answers `D`, `fk`, `table` (Task 1)." in text, text
    assert "because of" not in text, text
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    text = "\n".join(FailureNotes(_flange_notebook(1), 3, report).lines(failure, []))
    assert "This test failed because of `D`, `fk` (Task 1): their own test task1_test1 failed." in text, text
    assert sorted(name for entry in report["causes"].values() for name in entry["names"]) == ["D", "fk"]


def test_an_answer_one_check_finds_wrong_is_a_cause_though_another_finds_it_correct():
    """Two checks of ``leg_ik``: one finds a solution branch missing, the other (every returned
    solution reproduces its pose) finds it correct; the wrong verdict names ``leg_ik`` as the cause."""
    from tools.grading.robokin_nbgrader import FailureNotes

    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: the leg"),
        code_cell("def leg_ik(T):\n    return [T]", "task1_answer1", solution=True, task=1, count=1),
        code_cell("assert len(leg_ik(1.0)) == 8", "task1_test1", grade=True, task=1, count=2,
                  outputs=[_error("AssertionError", 2, 1)]),
    ]
    failure = nbformat.from_dict(_error("AssertionError", 2, 1))
    report: dict[str, Any] = {"pairs": [[1, "ar601.leg_ik", "leg_ik"], [1, "leg.ik", "leg_ik"]], "explained": {}}
    notes_ = FailureNotes(nb, 2, report)
    assert notes_.pairs(failure) == [("ar601.leg_ik", "leg_ik"), ("leg.ik", "leg_ik")]
    verdicts = [{"quantity": "leg_ik", "check": "ar601.leg_ik", "status": "wrong", "typical": True,
                 "diagnosis": "knee_branch_missing", "message": "✘ leg_ik returns only q4 ≥ 0"},
                {"quantity": "leg_ik", "check": "leg.ik", "status": "correct", "typical": False,
                 "message": "✔ ik(T) is correct"}]
    text = "\n".join(notes_.lines(failure, verdicts))
    assert ("This test failed because of `leg_ik` (Task 1): its value is wrong for robokin.check "
            "(knee_branch_missing).") in text, text


def test_where_to_start_lists_only_the_tests_that_depend_on_each_answer():
    """``screw_axis`` and ``S_list`` are each found wrong by robokin.check (the same reason) under their
    own tests: Where to start lists task2_test1 for ``screw_axis`` only, task2_test2 for ``S_list`` only."""
    from tools.grading.robokin_nbgrader import AutograderReport, FailureNotes

    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 2: screw axes"),
        code_cell("def screw_axis(omega, point):\n    return omega + point", "task2_answer1", solution=True,
                  task=2, count=1),
        code_cell("S_list = np.array([omega + point for omega, point in frames])", "task2_answer2",
                  solution=True, task=2, count=2),
        code_cell("assert np.allclose(screw_axis(w, p), ref(w, p))", "task2_test1", grade=True, task=2,
                  count=3, outputs=[_error("AssertionError", 3, 1)]),
        code_cell("assert np.allclose(S_list, S_ref)", "task2_test2", grade=True, task=2, count=4,
                  outputs=[_error("AssertionError", 4, 1)]),
    ]
    report: dict[str, Any] = {"pairs": [[2, "poe.screw_axis", "screw_axis"], [2, "poe.screw_list", "S_list"]],
                              "explained": {}, "incidents": []}
    verdicts = []
    for index, name in [(3, "screw_axis"), (4, "S_list")]:
        failure = nbformat.from_dict(_error("AssertionError", index, 1))
        verdict = {"quantity": name, "check": f"poe.{name}", "status": "wrong", "typical": True,
                   "diagnosis": "cross_sign", "message": f"✘ {name} has the wrong sign"}
        notes_ = FailureNotes(nb, index, report)
        notes_.pairs(failure)
        notes_.lines(failure, [verdict])
        verdicts.append(verdict)
    report["verdicts"] = verdicts
    page = AutograderReport().preprocess(nb, {"robokin": report})[0].cells[0].source
    start = page.split("**Where to start**")[1].strip().splitlines()
    assert start == [
        "- `S_list` (Task 2): its value is wrong for robokin.check (cross_sign); the failing test task2_test2 "
        "depends on it. Fix it first.",
        "- `screw_axis` (Task 2): its value is wrong for robokin.check (cross_sign); the failing test "
        "task2_test1 depends on it. Fix it first."], start


def _jacobian_notebook(jacobian_test_fails: bool):
    """Task 2: the foot position (its test fails); Task 3: a Jacobian computed from it, and its test."""
    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("# Chapter"),
        nbformat.v4.new_markdown_cell("## Task 2: the foot"),
        code_cell("H = H_1 * H_2\nr_foot = H[:3, 3]", "task2_answer1", solution=True, task=2, count=1),
        code_cell("assert r_foot == model", "task2_test1", grade=True, task=2, count=2,
                  outputs=[_error("AssertionError", 2, 1)]),
        nbformat.v4.new_markdown_cell("## Task 3: the Jacobian"),
        code_cell("J_sym = r_foot.jacobian(q_sym)\nJ_lift = J_sym.subs(at_lift)\nv_up = [0, 0, 1]",
                  "task3_answer1", solution=True, task=3, count=3),
        code_cell("assert J_sym == r_foot.jacobian(q_sym) and J_lift == J_sym.subs(at_lift)", "task3_test1",
                  grade=True, task=3, count=4,
                  outputs=[_error("AssertionError", 4, 1)] if jacobian_test_fails else []),
    ]
    wrong = [("r_foot", 2, "leg.foot"), ("J_sym", 3, "leg.jacobian"), ("J_lift", 3, "leg.jacobian_at"),
             ("v_up", 3, "leg.up")]
    resources = {"robokin": {
        "pairs": [(task, check, name) for name, task, check in wrong],
        "verdicts": [{"quantity": name, "check": check, "status": "wrong", "typical": True,
                      "diagnosis": "transpose", "message": f"✘ {name} is not correct"}
                     for name, _, check in wrong],
        "causes": {"2|own test task2_test1 failed": {"task": 2, "why": "own test task2_test1 failed",
                                                     "names": ["r_foot"], "tests": ["task2_test1"]}},
        "incidents": []}}
    return _findings(nb, resources)


def _findings(nb, resources) -> list[str]:
    """The lines of the report's *What robokin.check says about your answers*."""
    from tools.grading.robokin_nbgrader import AutograderReport

    report = AutograderReport().preprocess(nb, resources)[0].cells[0].source
    return report.split("**What `robokin.check` says about your answers**")[1].split("**")[0].strip().splitlines()


def test_a_value_computed_from_a_wrong_earlier_answer_follows_from_it():
    """``J_sym`` and ``J_lift`` are computed from the wrong ``r_foot`` of Task 2 and Task 3's test of
    them passes: their ✘ says they follow from ``r_foot``, with no typical mistake of their own;
    ``v_up``, which uses nothing of Task 2, and ``r_foot`` itself keep their own verdicts."""
    findings = _jacobian_notebook(jacobian_test_fails=False)
    follows = " *(follows from your `r_foot` (Task 2); its own tests pass)*"
    assert findings == [
        "- Task 2: ✘ r_foot is not correct *(typical mistake: transpose)*",
        "- Task 3: ✘ J_sym is not correct" + follows,
        "- Task 3: ✘ J_lift is not correct" + follows,
        "- Task 3: ✘ v_up is not correct *(typical mistake: transpose)*",
    ], findings


def test_a_value_whose_own_test_fails_does_not_follow_from_an_earlier_answer():
    """Task 3's test of ``J_sym`` and ``J_lift`` fails: they may be wrong on their own, and the page
    says nothing more."""
    findings = _jacobian_notebook(jacobian_test_fails=True)
    assert not any("follows from" in line for line in findings), findings
    assert "- Task 3: ✘ J_sym is not correct *(typical mistake: transpose)*" in findings, findings


def test_an_error_in_a_function_of_the_cell_quotes_the_statement_that_called_it():
    """The traceback's first frame in the cell is the statement that ran: the call, not the function's
    ``def`` (whose body raised)."""
    from tools.grading.robokin_nbgrader.cells import cell_label, failing_line

    cell = code_cell("def velocity(v):\n    return solve(J, v)\n\n\ndq = velocity(v_cmd)", "task3_answer1",
                     solution=True, task=3, count=7)
    error = {"output_type": "error", "ename": "LinAlgError", "evalue": "Singular matrix",
             "traceback": ["Cell In[7], line 5\n----> 5 dq = velocity(v_cmd)",
                           "Cell In[7], line 2, in velocity(v)\n----> 2     return solve(J, v)",
                           "LinAlgError: Singular matrix"]}
    assert failing_line(cell, error) == 5
    assert cell_label(cell, failing_line(cell, error)) == "In [7], line 5, `dq = velocity(v_cmd)`"


def _raising_answer_page(raised_in_function: bool) -> tuple[str, str]:
    """Task 3: an answer cell that defines ``A_unnormalised`` and raises ``DomainError`` at line 5, inside
    ``A_unnormalised`` (called there) or inside robokin's ``condition_number``; its test fails.
    The note under the test and the report's *Where to start*."""
    from tools.grading.robokin_nbgrader import AutograderReport, FailureNotes

    call = "A_unnormalised(P_grid)" if raised_in_function else "robot.condition_number(P_grid)"
    frames = [f"Cell In[5], line 5\n----> 5 cond_grid = {call}"]
    if raised_in_function:
        frames.append("Cell In[5], line 2, in A_unnormalised(poses)\n----> 2     return robot.jacobian(poses)")
    frames += ["File ~/robokin/parallel.py:120, in ThreeRPR.condition_number(self, poses)\n"
               "--> 120     raise DomainError('a leg of length 0')",
               "DomainError: a leg of length 0"]
    error = {"output_type": "error", "ename": "DomainError", "evalue": "a leg of length 0", "traceback": frames}
    answer = code_cell("def A_unnormalised(poses):\n    return robot.jacobian(poses)\n\n\n"
                       f"cond_grid = {call}", "task3_answer1", solution=True, task=3, count=5, outputs=[error])
    answer.metadata["robokin"]["role"] = "answer"
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("## Task 3: singularities"), answer,
                code_cell("assert np.allclose(A_unnormalised(pose_t), A_ref)", "task3_test1", grade=True, task=3,
                          count=6, outputs=[_error("AssertionError", 6, 1)])]
    report: dict[str, Any] = {"pairs": [], "explained": {}, "incidents": []}
    failure = nbformat.from_dict(_error("AssertionError", 6, 1))
    notes_ = FailureNotes(nb, 2, report)
    notes_.pairs(failure)
    note = "\n".join(notes_.lines(failure, []))
    page = AutograderReport().preprocess(nb, {"robokin": report})[0].cells[0].source
    return note, page.split("**Where to start**")[1].split("**Notes")[0].strip()


def test_an_answer_cell_that_raised_blames_the_function_only_when_its_body_raised():
    """The error passed through ``A_unnormalised``'s body: it is the cause. The error came from robokin's
    ``condition_number`` called on another line: that line is the cause, ``A_unnormalised`` is not."""
    note, start = _raising_answer_page(raised_in_function=True)
    assert "because of `A_unnormalised` (Task 3): its answer cell In [5] raised DomainError." in note, note
    assert start == ("- `A_unnormalised` (Task 3): its answer cell In [5] raised DomainError; the failing test "
                     "task3_test1 depends on it. Fix it first."), start

    note, start = _raising_answer_page(raised_in_function=False)
    line = "In [5], line 5, `cond_grid = robot.condition_number(P_grid)` (your answer to Task 3)"
    assert f"because of {line}, which raised DomainError." in note, note
    assert start == (f"- {line} raised DomainError; the failing test task3_test1 depends on that cell. "
                     "Fix it first."), start
    assert "A_unnormalised" not in note.split("because of")[1] and "A_unnormalised" not in start, (note, start)


def test_a_test_tagged_explains_names_only_the_answers_it_grades():
    from tools.grading.robokin_nbgrader import FailureNotes

    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 1: a step"),
        code_cell("def step(x):\n    return 2 * x", "task1_answer1", solution=True, task=1, count=1),
        nbformat.v4.new_markdown_cell("## Task 2: built on it"),
        code_cell("def later(x, f=step):\n    return f(x) + 1", "task2_answer1", solution=True, task=2,
                  count=2),
        code_cell("y = later(1, f=lambda x: 3 * x)\nassert y == 4", "task2_test1", grade=True, task=2,
                  count=3),
    ]
    failure = nbformat.from_dict(_error("AssertionError", 3, 2))
    pairs = [(1, "chapter.step", "step"), (2, "chapter.later", "later")]

    def note(tags):
        nb.cells[-1].metadata["tags"] = tags
        notes = FailureNotes(nb, len(nb.cells) - 1, {"pairs": pairs, "explained": {}})
        return notes.pairs(failure), "\n".join(notes.lines(failure, []))

    asked, text = note(["check"])   # untagged: step, used through later's default, is named
    assert ("chapter.step", "step") in asked and "`step`" in text, text
    asked, text = note(["check", "explains-later"])   # the test passes a step of its own
    assert asked == [("chapter.later", "later")] and "`step`" not in text, (asked, text)
    assert "`later` (Task 2)" in text, text
    # ... but an earlier answer whose cell raised is still the cause
    nb.cells[1].outputs = [nbformat.from_dict(_error("NameError", 1, 1))]
    _, text = note(["check", "explains-later"])
    assert "because of In [1], line 1, `def step(x): return 2 * x`, which raised NameError" in text, text


def _sweep_notebook():
    """Chapter 6 in small: Task 3's knee, whose test fails; Task 5's answer cell defines
    ``sole_sweep`` and raises when it calls it on the student's own inverse kinematics; Task 5's
    test (tagged ``explains-sole_sweep``) calls ``sole_sweep`` on an inverse kinematics of its own."""
    nb = nbformat.v4.new_notebook()
    test = code_cell("counts, sigmas = sole_sweep(heights_test, leg_ik=ik_test)\n"
                     "assert np.allclose(sigmas, expected)", "task5_test1", grade=True, task=5, count=4,
                     outputs=[_error("AssertionError", 4, 2)])
    test.metadata["tags"] = ["check", "explains-sole_sweep"]
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 3: the knee"),
        code_cell("def knee_angle(d):\n    return d", "task3_answer1", solution=True, task=3, count=1),
        code_cell("assert knee_angle(0.5) == 1.0", "task3_test1", grade=True, task=3, count=2,
                  outputs=[_error("AssertionError", 2, 1)]),
        nbformat.v4.new_markdown_cell("## Task 5: the sweep"),
        code_cell("def sole_sweep(heights, leg_ik=knee_angle):\n    return heights, heights\n\n\n"
                  "n_solutions, sigma_min = sole_sweep(heights)", "task5_answer1", solution=True, task=5,
                  count=3, outputs=[_error("DomainError", 3, 5)]),
        test,
    ]
    return nb


def test_a_raising_answer_cell_may_be_the_whole_cause_only_if_the_answer_is_right_for_its_check():
    """The answer cell of ``sole_sweep`` raised, and the test of ``sole_sweep`` failed on its own
    inputs: the note says fixing the cell may make the test pass only while ``robokin.check`` finds
    no answer the test grades wrong; when it finds ``sole_sweep`` wrong, both must be fixed."""
    from tools.grading.robokin_nbgrader import FailureNotes

    failure = nbformat.from_dict(_error("AssertionError", 4, 2))
    wrong = [{"quantity": "sole_sweep", "status": "wrong", "check": "ar601.sole_sweep", "typical": True,
              "diagnosis": "sigma_last_row", "message": "✘ sole_sweep takes sigma_min at the last row"}]
    for verdicts, advice in [([], "Fix that first: this test may then pass."),
                             (wrong, "Fix that first, and your `sole_sweep` (Task 5) too: robokin.check "
                                     "finds it wrong (below), so this test fails until both are fixed.")]:
        nb = _sweep_notebook()
        report: dict[str, Any] = {"pairs": [], "explained": {}}
        notes_ = FailureNotes(nb, 5, report)
        notes_.pairs(failure)
        text = "\n".join(notes_.lines(failure, verdicts))
        cause = next(line for line in text.splitlines() if "This test failed because of" in line)
        assert "`n_solutions, sigma_min = sole_sweep(heights)`, which raised DomainError" in cause, text
        assert cause.endswith(advice), text
        assert "knee_angle" not in cause, text


def test_an_answer_wrong_through_the_cause_needs_only_the_cause_fixed():
    """``my_ik`` uses the student's ``knee_angle``, whose own test failed: robokin.check finding
    ``my_ik`` wrong does not make the note ask for both (fixing the knee may fix it)."""
    from tools.grading.robokin_nbgrader import FailureNotes

    nb = nbformat.v4.new_notebook()
    nb.cells = [
        nbformat.v4.new_markdown_cell("## Task 3: the knee"),
        code_cell("def knee_angle(d):\n    return d", "task3_answer1", solution=True, task=3, count=1),
        code_cell("assert knee_angle(0.5) == 1.0", "task3_test1", grade=True, task=3, count=2,
                  outputs=[_error("AssertionError", 2, 1)]),
        nbformat.v4.new_markdown_cell("## Task 4: the leg"),
        code_cell("def my_ik(T, knee=knee_angle):\n    return knee(T)", "task4_answer1", solution=True,
                  task=4, count=3),
        code_cell("assert my_ik(1.0) == 2.0", "task4_test1", grade=True, task=4, count=4,
                  outputs=[_error("AssertionError", 4, 1)]),
    ]
    failure = nbformat.from_dict(_error("AssertionError", 4, 1))
    wrong = [{"quantity": "my_ik", "status": "wrong", "check": "ar601.ik_solver", "typical": False,
              "diagnosis": "", "message": "✘ my_ik misses the target"}]
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    notes_ = FailureNotes(nb, 5, report)
    notes_.pairs(failure)
    text = "\n".join(notes_.lines(failure, wrong))
    cause = next(line for line in text.splitlines() if "This test failed because of" in line)
    assert "`knee_angle` (Task 3): its own test task3_test1 failed" in cause, text
    assert cause.endswith("Fix that first: this test may then pass."), text
