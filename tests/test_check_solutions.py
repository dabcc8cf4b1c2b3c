"""The ready-made checks for 'a solution' and 'the set of solutions' (robokin.check.solutions)."""

from __future__ import annotations

import numpy as np
import pytest

from robokin import check
from robokin.models import ar601_leg, ar601_leg_ik, ur10
from robokin.motion import solve_ik

ARM = ur10()
Q_GOAL = np.array([0.3, -1.2, 1.4, -1.0, -1.57, 0.4])
T_GOAL = ARM.fk(Q_GOAL)


def test_any_configuration_reaching_the_target_passes():
    other = solve_ik(ARM, T_GOAL, q0=np.array([0.3, -2.2, -1.4, -1.0, 1.57, 0.4]))
    assert other.success and not np.allclose(other.q, Q_GOAL, atol=1e-3)   # another posture
    for q in (Q_GOAL, other.q):
        result = check.ik_solution(q, ARM, T_GOAL, quiet=True)
        assert result.passed, result.message
    assert check.ik_solution(Q_GOAL, ARM, T_GOAL[:3, 3], quiet=True).passed       # position only


@pytest.mark.parametrize("answer, code", [
    (np.rad2deg(Q_GOAL), "degrees"),
    (Q_GOAL + 0.1, "misses_target"),
    (Q_GOAL[:5], "shape"),
    (np.full(6, np.nan), "not_finite"),
    ("abc", "shape"),
])
def test_wrong_configurations_are_diagnosed(answer, code, capsys):
    result = check.ik_solution(answer, ARM, T_GOAL)
    assert not result.passed and result.diagnosis == code, result
    assert capsys.readouterr().out.startswith("\u2718")
    with pytest.raises(AssertionError):
        check.ik_solution(answer, ARM, T_GOAL, raise_on_fail=True, quiet=True)


def test_outside_the_limits_is_named():
    q = Q_GOAL.copy()
    q[0] += 2 * np.pi * 2                     # same pose, joint 1 two turns on: beyond ±2π
    result = check.ik_solution(q, ARM, T_GOAL, quiet=True)
    assert result.diagnosis == "limits" and "joint 1" in result.message
    assert check.ik_solution(q, ARM, T_GOAL, limits=False, quiet=True).passed


def test_solution_sets_in_any_order_and_up_to_full_turns():
    leg = ar601_leg()
    q = np.array([0.1, 0.05, -0.3, 0.6, -0.3, -0.05])
    ref = ar601_leg_ik(leg.fk(q)).q
    assert len(ref) == 8
    shuffled = ref[::-1] + 2 * np.pi * np.eye(6)[0]
    assert check.solution_set(shuffled, ref, quiet=True).passed
    cases = {"missing": ref[:7], "duplicate": np.vstack([ref, ref[:1]])[1:], "extra": np.vstack([ref, ref[0] + 0.5]),
             "shape": ref[:, :5], "not_finite": np.full((8, 6), np.nan)}
    cases["duplicate"] = np.vstack([ref[1:], ref[1]])
    for code, answer in cases.items():
        result = check.solution_set(answer, ref, quiet=True)
        assert not result.passed and result.diagnosis == code, (code, result)
    assert not check.solution_set(shuffled, ref, angles=False, quiet=True).passed


# ---------------------------------------------------------------- SolutionSetCheck: a chapter check
def _elbows(d):
    """Both elbow angles q2 of a two-link arm (l1 = l2 = 1 m) whose tool is at distance d (m)."""
    return np.arccos(d**2 / 2 - 1)


ELBOWS = check.SolutionSetCheck(
    name="q2", variables=[check.Variable("d", kind="length", low=0.2, high=1.9)], noun="distances",
    reference=lambda x: np.array([[1.0], [-1.0]]) * _elbows(x[0]))


@pytest.mark.parametrize("answer", [
    lambda d: [[_elbows(d)], [-_elbows(d)]],
    lambda d: [[-_elbows(d)], [_elbows(d)]],                         # another order
    lambda d: [[_elbows(d) + 2 * np.pi], [2 * np.pi - _elbows(d)]],   # other turns
], ids=["in_order", "other_order", "other_turns"])
def test_solution_set_check_accepts_every_order_and_turn(answer):
    result = ELBOWS.evaluate(answer)
    assert result.passed and result.diagnosis is None, result.message


@pytest.mark.parametrize("answer, code", [
    (lambda d: [[_elbows(d)]], "missing"),
    (lambda d: [[_elbows(d)], [_elbows(d)]], "duplicate"),
    (lambda d: [[_elbows(d)], [-_elbows(d)], [0.5]], "extra"),
    (lambda d: np.rad2deg([[_elbows(d)], [-_elbows(d)]]), "degrees"),
    (lambda d: None, "error"),
    (lambda d: 1 / 0, "error"),
    (lambda d: [[np.nan], [0.0]], "not_finite"),
    (lambda d: [[1.0, 2.0]], "shape"),
    (lambda d: [], "missing"),
], ids=["missing", "duplicate", "extra", "degrees", "no_return", "raises", "nan", "shape", "empty"])
def test_solution_set_check_names_the_mistake(answer, code):
    result = ELBOWS.evaluate(answer)
    assert not result.passed and result.diagnosis == code, result.message
    if code in ("missing", "duplicate", "extra"):
        assert "(at d = " in result.message     # where it is wrong


def test_solution_set_check_with_one_row_compares_angles_modulo_two_pi():
    """A reference of one row: an answer function whose angles are right up to full turns."""
    heading = check.SolutionSetCheck(name="heading", variables=[check.Variable("t")],
                                     reference=lambda x: np.array([x[0] / 2]))
    assert heading.evaluate(lambda t: t / 2 + 2 * np.pi).passed
    assert heading.evaluate(lambda t: t / 2 - 4 * np.pi).passed
    assert heading.evaluate(lambda t: t / 2 + np.pi).diagnosis == "extra"


def test_solution_set_check_registers_as_a_chapter_check():
    from robokin.check._registry import _REGISTRY, exercise

    registered = exercise("test_only_chapter", "q2", ELBOWS)
    try:
        assert registered is ELBOWS and isinstance(registered, check.Check)
        assert ELBOWS(lambda d: [[_elbows(d)], [-_elbows(d)]], quiet=True).passed
    finally:
        _REGISTRY.pop("test_only_chapter", None)
