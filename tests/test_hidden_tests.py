"""Hidden tests never reach a student: not in the student book, not in the feedback page.

A test cell's hidden tests (``### BEGIN HIDDEN TESTS`` ... ``### END HIDDEN TESTS``) run
when a submission is graded and nowhere else. nbgrader's student edition leaves them out
(``tests/test_nbgrader.py``, ``test_student_edition_has_no_solutions``); here, without
nbgrader commands or a kernel:

* the student edition of the book (``book/_ext/robokin_book.py``), its pages and the
  notebooks a reader downloads, for every chapter notebook in ``notebooks/`` and for the
  chapter ``tools/authoring/new_chapter.py`` scaffolds;
* the feedback page's preprocessor (``HideHiddenTests``) on a graded notebook whose hidden
  test failed: the verdict and its message stay, the code goes, from the cell, the
  traceback and the robokin note alike.

``tests/test_nbgrader.py`` checks the feedback pages of real graded submissions.
"""

from __future__ import annotations

import functools
import html
import importlib.util
import json
import os
import re
import sys
from pathlib import Path
from typing import Any

import nbformat
import pytest

from conftest import ROOT
from tools.authoring.nbgrader_metadata import chapter_notebooks


@functools.cache
def robokin_book():
    """The book's Sphinx extension, ``book/_ext/robokin_book.py``, loaded from its file (jupyter-book
    puts ``book/_ext`` on the path when it builds the book, as ``_config.yml`` says; a test does not)."""
    spec = importlib.util.spec_from_file_location("robokin_book", ROOT / "book" / "_ext" / "robokin_book.py")
    assert spec is not None and spec.loader is not None
    module = sys.modules["robokin_book"] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


NOTEBOOKS = Path(os.environ.get("ROBOKIN_NBGRADER_NOTEBOOKS", ROOT / "notebooks")).resolve()
CHAPTERS = chapter_notebooks(NOTEBOOKS.parent, NOTEBOOKS.name)
HIDDEN = re.compile(r"^[^\n]*BEGIN HIDDEN TESTS[^\n]*\n(.*?)^[^\n]*END HIDDEN TESTS[^\n]*$", re.S | re.M)


def _source(cell: dict) -> str:
    source = cell.get("source", "")
    return "".join(source) if isinstance(source, list) else source


def hidden_only_lines(nb: dict) -> set[str]:
    """The lines of ``nb``'s hidden tests (stripped, 4+ characters) that are not also in the code a
    student is given (the code cells other than solutions, outside their hidden tests)."""
    hidden, visible = set(), set()
    for cell in nb["cells"]:
        source = _source(cell)
        for block in HIDDEN.findall(source):
            hidden |= {line.strip() for line in block.splitlines() if len(line.strip()) >= 4}
        if cell.get("cell_type", "code") == "code" and "solution" not in cell.get("metadata", {}).get("tags", []):
            visible |= {line.strip() for line in HIDDEN.sub("", source).splitlines()}
    return hidden - visible


def scaffolded_chapter() -> dict:
    """The notebook ``tools/authoring/new_chapter.py`` writes for a new chapter (the next free number)."""
    from tools.authoring import new_chapter

    numbers = [int(p.name[:2]) for p in CHAPTERS] or [0]
    return new_chapter.notebook(max(numbers) + 1, "example_arm", "An example arm", "an example arm")


def _leaks(student_text: str, hidden: set[str]) -> list[str]:
    """The hidden lines in the student notebook: a whole line of a cell, or (30+ characters) in an output."""
    student = json.loads(student_text)
    lines = {line.strip() for c in student["cells"] for line in _source(c).splitlines()}
    outputs = "\n".join(json.dumps(c.get("outputs", []), ensure_ascii=False) for c in student["cells"])
    leaks = sorted(line for line in hidden if line in lines or (len(line) >= 30 and line in outputs))
    return leaks + (["HIDDEN TESTS"] if any("HIDDEN TESTS" in line for line in lines) else [])


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_student_book_leaves_hidden_tests_out(path):
    student_notebook = robokin_book().student_notebook

    text = path.read_text(encoding="utf-8")
    leaks = _leaks(student_notebook(text), hidden_only_lines(json.loads(text)))
    assert not leaks, f"{path.stem}: hidden tests in the student edition of the book: {leaks[:3]}"


def test_student_book_leaves_a_scaffolded_chapters_hidden_tests_out():
    student_notebook = robokin_book().student_notebook

    nb = scaffolded_chapter()
    hidden = hidden_only_lines(nb)
    assert hidden, "the scaffolded chapter has no hidden tests (tools/authoring/new_chapter.py): nothing is checked"
    leaks = _leaks(student_notebook(json.dumps(nb)), hidden)
    assert not leaks, f"the scaffolded chapter's hidden tests in the student edition of the book: {leaks[:3]}"


def test_student_book_downloads_are_student_notebooks(tmp_path):
    """Sphinx copies each page's source file into ``_sources/`` (the page's download button): in the
    student edition the extension writes the student notebook there instead of the instructor's."""
    from types import SimpleNamespace

    student_notebook, student_sources = robokin_book().student_notebook, robokin_book().student_sources

    path = CHAPTERS[0]
    docname = f"{path.parent.name}/{path.stem}"
    copied = tmp_path / "_sources" / f"{docname}.ipynb"
    copied.parent.mkdir(parents=True)
    copied.write_bytes(path.read_bytes())   # what Sphinx's HTML builder leaves there
    app = SimpleNamespace(config=SimpleNamespace(robokin_edition="student"), outdir=str(tmp_path),
                          builder=SimpleNamespace(format="html"),
                          env=SimpleNamespace(found_docs={docname, "book/intro"},
                                              doc2path=lambda name: str(path if name == docname else
                                                                        ROOT / "book" / "intro.md")))
    student_sources(app, None)
    assert copied.read_text(encoding="utf-8") == student_notebook(path.read_text(encoding="utf-8"))
    instructor = SimpleNamespace(**{**vars(app), "config": SimpleNamespace(robokin_edition="instructor")})
    copied.write_bytes(path.read_bytes())
    student_sources(instructor, None)
    assert copied.read_bytes() == path.read_bytes(), "the instructor edition's download is the notebook itself"


def test_student_book_has_no_launch_buttons():
    """Binder, Colab and a hub open the repository's notebook (the instructor's): the student edition
    has no launch buttons; the instructor edition keeps those of ``_config.yml``."""
    from types import SimpleNamespace

    configure_edition = robokin_book().configure_edition

    buttons = {"binderhub_url": "https://mybinder.org", "colab_url": "https://colab.research.google.com"}
    for edition, expected in (("student", {}), ("instructor", buttons)):
        config = SimpleNamespace(robokin_edition=edition, html_theme_options={"launch_buttons": dict(buttons)})
        configure_edition(None, config)
        assert config.html_theme_options["launch_buttons"] == expected, edition


# ---------------------------------------------------------------- the feedback page
def _graded_notebook():
    """A graded notebook whose test cell failed in its hidden tests, with the note autograde writes."""
    from tools.grading.robokin_nbgrader import FailureNotes

    def cell(source, grade_id, solution=False, task=1, count=None):
        out = nbformat.v4.new_code_cell(source, execution_count=count)
        out.metadata["nbgrader"] = {"grade_id": grade_id, "solution": solution, "grade": not solution,
                                    "locked": not solution, "points": 2, "schema_version": 3}
        out.metadata["robokin"] = {"task": task, "role": "answer" if solution else "test"}
        return out

    test = ("assert answer.shape == (3,)\n"
            "### BEGIN HIDDEN TESTS\n"
            "expected_secret = np.array([0.125, 0.25, 0.375])\n"
            "assert np.allclose(answer, expected_secret), 'not the value of the closed form'\n"
            "### END HIDDEN TESTS\n"
            "print('shape checked')")
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_markdown_cell("## Task 1: the answer"),
                nbformat.v4.new_code_cell("import numpy as np", execution_count=1),
                cell("answer = np.zeros(3)", "task1_answer1", solution=True, count=1),
                cell(test, "task1_test1", count=2)]
    frame = ("\x1b[36mCell\x1b[39m \x1b[32mIn[2]\x1b[39m\x1b[32m, line 4\x1b[39m\n"
             "      2 ### BEGIN HIDDEN TESTS\n      3 expected_secret = np.array([0.125, 0.25, 0.375])\n"
             "----> 4 assert np.allclose(answer, expected_secret), 'not the value of the closed form'\n"
             "      5 ### END HIDDEN TESTS\n")
    error = nbformat.from_dict({"output_type": "error", "ename": "AssertionError",
                                "evalue": "not the value of the closed form",
                                "traceback": ["-" * 75, "AssertionError    Traceback (most recent call last)", frame,
                                              "AssertionError: not the value of the closed form"]})
    report: dict[str, Any] = {"pairs": [], "explained": {}}
    note = "\n".join(FailureNotes(nb, 3, report).lines(error, [])) + "\n"
    nb.cells[3].outputs = [nbformat.v4.new_output("stream", name="stdout", text="shape checked\n"),
                           nbformat.v4.new_output("stream", name="stdout", text=note), error]
    return nb, test


def test_failure_note_never_quotes_a_hidden_test():
    nb, test = _graded_notebook()
    note = nb.cells[3].outputs[1]["text"]
    assert note.startswith("✘ Task 1 (task1_test1) failed in its hidden tests"), note
    assert "expected_secret" not in note and "np.allclose" not in note and "line 4" not in note, note
    assert "AssertionError: not the value of the closed form" in note, note
    assert "It checks your answer `answer` (Task 1)." in note, note


def test_feedback_page_keeps_the_verdict_and_not_the_code():
    from nbconvert.exporters import HTMLExporter

    from tools.grading.robokin_nbgrader import HideHiddenTests

    nb, test = _graded_notebook()
    hidden = hidden_only_lines({"cells": [{"source": test}]})
    nb, _ = HideHiddenTests().preprocess(nb, {})
    cell = nb.cells[3]
    assert "HIDDEN" not in cell.source and "expected_secret" not in cell.source, cell.source
    assert cell.source.splitlines()[0] == "assert answer.shape == (3,)" and "print('shape checked')" in cell.source
    assert "hidden tests" in cell.source, "no comment says where the hidden tests were"
    page = html.unescape(re.sub(r"<[^>]+>", "", HTMLExporter().from_notebook_node(nb)[0]))
    leaked = [line for line in hidden if line in page]
    assert not leaked, f"the feedback page shows hidden tests: {leaked}"
    # the verdict and the diagnosis stay
    assert "failed in its hidden tests" in page and "AssertionError: not the value of the closed form" in page
    assert "in the hidden tests (their code is not shown)" in page and "shape checked" in page


def test_feedback_renumbers_a_visible_failure():
    """A visible assert after the hidden block fails: the note's and the traceback's line numbers are
    those of the cell the student reads, and they quote the visible line only."""
    from tools.grading.robokin_nbgrader import HideHiddenTests

    source = ("x = 1\n### BEGIN HIDDEN TESTS\nsecret_value = 42\nassert secret_value == 42\n"
              "### END HIDDEN TESTS\nassert x == 2, 'x is not 2'")
    cell = nbformat.v4.new_code_cell(source, execution_count=7)
    cell.metadata["nbgrader"] = {"grade_id": "task1_test1", "grade": True, "solution": False, "locked": True,
                                 "points": 1, "schema_version": 3}
    frame = ("Cell In[7], line 6\n      4 assert secret_value == 42\n      5 ### END HIDDEN TESTS\n"
             "----> 6 assert x == 2, 'x is not 2'\n")
    cell.outputs = [
        nbformat.v4.new_output("stream", name="stdout", text="✘ Task 1 (task1_test1) failed at line 6:\n"
                                                             "      assert x == 2, 'x is not 2'\n"),
        nbformat.from_dict({"output_type": "error", "ename": "AssertionError", "evalue": "x is not 2",
                            "traceback": [frame, "AssertionError: x is not 2"]})]
    nb = nbformat.v4.new_notebook()
    nb.cells = [cell]
    nb, _ = HideHiddenTests().preprocess(nb, {})
    lines = nb.cells[0].source.splitlines()
    assert lines[2] == "assert x == 2, 'x is not 2'" and "secret_value" not in nb.cells[0].source, lines
    assert nb.cells[0].outputs[0]["text"].startswith("✘ Task 1 (task1_test1) failed at line 3:")
    assert nb.cells[0].outputs[1]["traceback"][0] == "Cell In[7], line 3\n----> 3 assert x == 2, 'x is not 2'"


# ---------------------------------------------------------------- the built student book
@pytest.mark.book
def test_built_student_book_has_no_hidden_tests(built_student_book):
    """The pages and the notebooks a reader downloads (``_sources/``) of the built student edition."""
    for path in sorted((ROOT / "notebooks").glob("*.ipynb")):
        nb = json.loads(path.read_text(encoding="utf-8"))
        hidden = hidden_only_lines(nb)
        given = [line for cell in nb["cells"] if "solution" not in cell.get("metadata", {}).get("tags", [])
                 for line in HIDDEN.sub("", _source(cell)).splitlines()]
        page = html.unescape(re.sub(r"<[^>]+>", "", (built_student_book / "notebooks" / f"{path.stem}.html")
                                    .read_text(encoding="utf-8")))
        # a whole line of the page (a code line shown), or a long hidden line anywhere that is no part
        # of a line the student is given: a short one such as ``r_BF`` or ``).positions,`` also
        # stands in the prose and the given code
        page_lines = {line.strip() for line in page.splitlines()}
        leaked = sorted(line for line in hidden if line in page_lines or (
            len(line) >= 30 and line in page and not any(line in given_line for given_line in given)))
        assert not leaked, f"{path.stem}: hidden tests in the student book's page: {leaked[:3]}"
        raw = (built_student_book / "notebooks" / f"{path.stem}.html").read_text(encoding="utf-8")
        assert "colab.research.google.com/github" not in raw and "mybinder.org/v2" not in raw, (
            f"{path.stem}: a launch button of the student book opens the instructor's notebook")
        for download in (built_student_book / "_sources" / "notebooks").glob(f"{path.stem}.ipynb*"):
            text = download.read_text(encoding="utf-8")
            leaked = _leaks(text, hidden)
            solutions = [c for c in json.loads(text)["cells"] if "solution" in c.get("metadata", {}).get("tags", [])]
            assert not leaked and not solutions, (
                f"{download.name}: the student book's download holds hidden tests {leaked[:2]} "
                f"or {len(solutions)} solution cells")
