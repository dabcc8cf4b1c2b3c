"""tools/notebook_analysis.py: which calls of robokin.check a notebook makes on an answer."""

from __future__ import annotations

import textwrap

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
