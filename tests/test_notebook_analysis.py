"""tools/notebook_analysis.py: which calls of robokin.check a notebook makes on an answer."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest

from tools.notebook_analysis import check_calls

ALIASES = {"check": "*"}


@pytest.mark.parametrize("code, expected", [
    ("check.leg.rotation_B1(R_B1)", [("leg.rotation_B1", "R_B1")]),
    # inside a block (a cell wrapped in ``with your_answers(...):``), judged by its own line
    ("with your_answers('Task 1'):\n    check.leg.rotation_B1(R_B1)\n    assert not failed",
     [("leg.rotation_B1", "R_B1")]),
    ("for k in range(2):\n    check.leg.rotation_B1(R[k])", [("leg.rotation_B1", "R[k]")]),
    # a deliberately wrong answer is left out, at the top level or in a block
    ("check.leg.rotation_B1(R_B1.T)  # deliberately wrong", []),
    ("with your_answers('Task 1'):\n    # deliberately wrong: transposed\n    check.leg.rotation_B1(R_B1.T)", []),
    ("with your_answers('Task 1'):\n    assert 'transpose' in check.leg.rotation_B1(R_B1.T).diagnosis", []),
    ("with your_answers('Task 1'):\n    assert not check.leg.rotation_B1(R_B1.T)", []),
    ("check.leg.rotation_B1(lambda q: R(q).T)", []),
    ("check.leg.rotation_B1(lambda q: R(q))", [("leg.rotation_B1", "lambda q: R(q)")]),
])
def test_check_calls_on_answers(code, expected):
    assert check_calls(textwrap.dedent(code), ALIASES) == expected


def test_check_calls_follow_aliases_and_the_full_path():
    code = "import robokin.check.leg as check_leg\ncheck_leg.rotation_B1(R)\nrobokin.check.leg.jacobian(J)"
    assert check_calls(code, {"check_leg": "leg"}) == [("leg.rotation_B1", "R"), ("leg.jacobian", "J")]


def test_unparsable_code_has_no_calls():
    assert check_calls("check.leg.rotation_B1(", ALIASES) == []


def _code(text: str, *tags: str) -> dict:
    return {"cell_type": "code", "metadata": {"tags": list(tags)}, "source": text, "outputs": []}


def test_a_test_tagged_explains_names_only_the_answers_it_grades():
    """Without the tag a test is explained by the checks of every answer of its task so far; with
    ``explains-<answer>`` by those of the answers it names only."""
    from tools.notebook_analysis import analyse

    cells = [
        {"cell_type": "markdown", "metadata": {}, "source": "## Task 1: Two steps"},
        _code("from robokin.check import demo as check_demo"),
        _code("def first(x):\n    return x\n\n\ndef second(x, step=first):\n    return step(x)", "solution"),
        _code("assert second(1.0) == 1.0", "check"),
        _code("assert second(2.0, step=abs) == 2.0", "check", "explains-second"),
        {"cell_type": "markdown", "metadata": {}, "source": "## Try it yourself"},
        _code("check_demo.first(first)\ncheck_demo.second(second)"),
    ]
    chapter = analyse(Path("demo.ipynb"), {"cells": cells})
    plain, tagged = chapter.tests(1)
    assert plain.explain == [("demo.first", "first"), ("demo.second", "second")]
    assert tagged.explain == [("demo.second", "second")]
