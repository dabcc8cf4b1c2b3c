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
