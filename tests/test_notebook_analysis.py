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


ANSWER_WITH_DEMONSTRATION = '''\
def double(x):
    # twice x
    return 2 * x


total = double(DATA)
# Given: your double at the problem's data
shown = double(3)
print("double(3) =", shown)
'''


def test_the_given_tail_of_an_answer_stays_as_written():
    """From a top-level ``# Given:`` line on, an answer cell's code is a demonstration the student
    edition keeps: no second stub there, and its names are not the student's to declare."""
    from tools.notebook_analysis import analyse, stub_source

    stub = stub_source(ANSWER_WITH_DEMONSTRATION, {"double", "total"})
    assert stub == (
        "def double(x):\n    # YOUR CODE HERE\n    raise NotImplementedError()\n\n\n"
        "total = None\n# YOUR CODE HERE\nraise NotImplementedError()\n"
        "# Given: your double at the problem's data\nshown = double(3)\n"
        'print("double(3) =", shown)'
    )
    cells = [
        {"cell_type": "markdown", "metadata": {}, "source": "## Task 1: Double"},
        _code("DATA = 2"),
        _code(ANSWER_WITH_DEMONSTRATION, "solution"),
        _code("assert double(5) == 10 and total == 4 and shown == 6", "check"),
    ]
    answer = analyse(Path("demo.ipynb"), {"cells": cells}).cells[2]
    assert answer.interface == {"double", "total"}  # `shown` comes with the given tail


def test_without_a_given_line_every_statement_is_the_students():
    from tools.notebook_analysis import stub_source

    code = ANSWER_WITH_DEMONSTRATION.replace("# Given: your", "# your")
    assert stub_source(code, {"double", "total"}).endswith(
        "total = None\n# YOUR CODE HERE\nraise NotImplementedError()")


@pytest.mark.parametrize("code, message", [
    # the tail would overwrite (and show) the student's answer
    (ANSWER_WITH_DEMONSTRATION + "total = 4\n", "assigns total, which the student's answer defines"),
    # the line must start the tail at the top level, not sit inside a statement
    ("def double(x):\n# Given: inside\n    return 2 * x\n", "inside a statement"),
])
def test_a_misplaced_given_tail_is_refused(code, message):
    from tools.notebook_analysis import stub_plan

    with pytest.raises(ValueError, match=message):
        stub_plan(code, {"double", "total"})
