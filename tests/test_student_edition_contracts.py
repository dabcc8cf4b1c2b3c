"""The student edition stands on its own: what a test reads, the student is told to define.

Static (no kernel, no nbgrader run): for every chapter notebook,

* every name that a test cell reads from the student's work -- directly, or
  through the given cells it reads -- is bound by an answer cell whose stub in the
  student edition still defines it (a function signature, or ``name = None``), and
  it is documented where the student sees it: the function's docstring, a comment
  in the stub that names it, or a task statement above the answer cell (a markdown
  cell of the same section) that names it in backticks;
* the student edition has no empty markdown cells.

The student edition is computed as ``generate_assignment`` makes it
(``tools/notebook_analysis.py``: ``stub_source`` is ``MarkSolutionRegions`` and
``ClearSolutions``, ``student_markdown`` is ``ClearSolutions`` and ``DropSolutionProse``);
``tests/test_nbgrader.py`` checks that the two agree on the real student edition.

``ROBOKIN_NBGRADER_NOTEBOOKS=<folder>`` checks the notebooks of another folder.
"""

from __future__ import annotations

import ast
import os
import re
from pathlib import Path

import pytest

from conftest import ROOT
from tools.authoring.nbgrader_metadata import chapter_notebooks
from tools.notebook_analysis import (
    Binding,
    Chapter,
    analyse,
    defined_names,
    given_tail_start,
    removed_in_student_edition,
    student_markdown,
    stub_source,
    trace,
)

NOTEBOOKS = Path(os.environ.get("ROBOKIN_NBGRADER_NOTEBOOKS", ROOT / "notebooks")).resolve()
CHAPTERS = chapter_notebooks(NOTEBOOKS.parent, NOTEBOOKS.name)
CODE_SPAN = re.compile(r"(`+)(.+?)\1", re.S)


def _first_line(text: str) -> str:
    line = next((line.strip() for line in text.splitlines() if line.strip()), "")
    return line if len(line) <= 60 else line[:59] + "…"


def _kinds(chapter: Chapter) -> list[tuple[str, str]]:
    return [("answer" if c.role == "answer" else "code" if c.cell_type == "code" else "markdown", c.source)
            for c in chapter.cells]


def answer_names_read(chapter: Chapter, reads: list[dict[str, Binding]], index: int) -> dict[str, int]:
    """Names of answer cells that cell ``index`` reads, directly or through given cells:
    ``{name: index of the answer cell that binds it}``."""
    out: dict[str, int] = {}
    seen: set[int] = set()

    def visit(cell: int) -> None:
        if cell in seen:
            return
        seen.add(cell)
        for name, binding in reads[cell].items():
            if binding.answer:
                out.setdefault(name, binding.cell)
            elif binding.roots:
                visit(binding.cell)

    visit(index)
    return out


def statement_before(chapter: Chapter, answer: int) -> list[tuple[int, str]]:
    """The task statement an answer cell follows: the markdown cells of the student edition
    in the same section (``## Task k``), above the answer cell."""
    section = chapter.cells[answer].section
    return [(c.index, student_markdown(c) or "") for c in chapter.cells[:answer]
            if c.section == section and c.cell_type == "markdown" and not removed_in_student_edition(c)]


def documented(name: str, stub: str, statement: list[tuple[int, str]]) -> bool:
    tree = ast.parse(stub)
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)) and node.name == name:
            if (ast.get_docstring(node) or "").strip():
                return True
    word = re.compile(rf"(?<![\w.]){re.escape(name)}\b")
    for line in stub.splitlines():
        if "#" in line and word.search(line[line.index("#"):]):
            return True
    return any(word.search(span.group(2)) for _, text in statement for span in CODE_SPAN.finditer(text))


def contract_problems(path: Path) -> list[str]:
    chapter = analyse(path)
    reads = trace(_kinds(chapter))
    problems: list[str] = []
    reported: set[tuple[str, int]] = set()
    for test in chapter.tests():
        for name, answer_index in sorted(answer_names_read(chapter, reads, test.index).items()):
            if (name, answer_index) in reported:
                continue
            reported.add((name, answer_index))
            answer = chapter.cells[answer_index]
            declare = {n for n in answer.defines if n in answer.interface}
            stub = stub_source(answer.source, declare)
            where = (f"{chapter.name}: the test cell {test.index} (Task {test.task}, "
                     f"`{_first_line(test.source)}`) reads `{name}` from the answer cell {answer_index} "
                     f"(Task {answer.task})")
            if name not in defined_names(stub):
                problems.append(
                    f"{where}, but the student edition's stub of that cell does not define `{name}` "
                    f"(stub: {stub!r}). Make `{name}` a module-level name of the answer cell "
                    "(a function or an assignment) in valid Python, so that the stub keeps it.")
                continue
            statement = statement_before(chapter, answer_index)
            if not documented(name, stub, statement):
                cells = ", ".join(str(i) for i, _ in statement) or "none"
                kind = "function" if any(
                    isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.name == name
                    for n in ast.parse(stub).body) else "variable"
                fix = (f"give `def {name}` a docstring (what it takes and returns, with shapes and units)"
                       if kind == "function" else
                       f"name `{name}` in backticks in the task statement above the answer cell "
                       f"(markdown cells {cells}), saying what it holds (type, shape, units), or add a "
                       f"comment that names it on a line the stub keeps (e.g. an import line or a signature)")
                problems.append(f"{where}, but the student edition does not say what `{name}` is: {fix}.")
    for cell in chapter.cells:
        if (cell.cell_type == "markdown" and not removed_in_student_edition(cell)
                and not (student_markdown(cell) or "").strip()):
            problems.append(f"{chapter.name}: markdown cell {cell.index} (section {cell.section!r}) is empty "
                            "in the student edition: delete it or give it text.")
    return problems


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_student_edition_keeps_and_documents_what_the_tests_read(path):
    problems = contract_problems(path)
    assert not problems, f"{len(problems)} problem(s):\n" + "\n".join(f"- {p}" for p in problems)


def test_contract_finds_an_undocumented_name(tmp_path):
    """The check itself: a variable read by a test and named nowhere is reported, with the fix."""
    def md(text):
        return {"cell_type": "markdown", "metadata": {}, "source": text}

    def code(text, *tags):
        return {"cell_type": "code", "metadata": {"tags": list(tags)}, "source": text,
                "outputs": [], "execution_count": None}

    import json
    nb = {"cells": [md("# Chapter"), md("## Task 1: Sum\nCompute the sum `total` of `DATA`."),
                    code("DATA = [1, 2]"),
                    code("def double(x):\n    return 2 * x\n\ntotal = sum(DATA)\nhidden = double(total)",
                         "solution"),
                    code("tripled = 3 * hidden"),
                    code("assert total == 3 and tripled == 18", "check"),
                    md("")],
          "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    path = tmp_path / "01_demo.ipynb"
    path.write_text(json.dumps(nb))
    problems = contract_problems(path)
    text = "\n".join(problems)
    assert "reads `hidden` from the answer cell 3 (Task 1)" in text, text
    assert "name `hidden` in backticks" in text
    assert "`total`" not in text.replace("reads `hidden`", "")   # `total` is named in the statement
    assert "markdown cell 6" in text and "is empty" in text


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_given_tails_are_kept_and_ask_nothing(path):
    """An answer cell's given tail (from its ``# Given:`` line, book/authoring.md) is in the student
    edition as written, after the last stub, and assigns none of the student's names."""
    for cell in analyse(path).answers():
        start = given_tail_start(cell.source)
        if start is None:
            continue
        declare = {n for n in cell.defines if n in cell.interface}
        stub = stub_source(cell.source, declare)  # ValueError: the tail assigns a declared name
        tail = "\n".join(cell.source.splitlines()[start - 1:])
        assert stub.endswith(tail), f"{path.stem} cell {cell.index}: the given tail is not kept"
        assert "NotImplementedError" not in tail, f"{path.stem} cell {cell.index}: a stub in the tail"
