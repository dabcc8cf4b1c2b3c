"""Tests of the chapter-6 exercise checks (robokin.check.ar601).

The correct answers are written independently of the model: the foot pose as
a product of hand-written sympy matrices, the knee angle from the law of
cosines, a numerical IK as a solver.
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
import sympy as sp

from robokin.models.ar601 import ar601_leg
from robokin.models.ar601_ik import ar601_leg_ik
from robokin.motion import solve_ik

ck = importlib.import_module("robokin.check.ar601")

q = sp.symbols("q1:7", real=True)
L1, L2, L3 = sp.symbols("L1 L2 L3", positive=True)


def Rx(t):
    return sp.Matrix([[1, 0, 0, 0], [0, sp.cos(t), -sp.sin(t), 0], [0, sp.sin(t), sp.cos(t), 0], [0, 0, 0, 1]])


def Ry(t):
    return sp.Matrix([[sp.cos(t), 0, sp.sin(t), 0], [0, 1, 0, 0], [-sp.sin(t), 0, sp.cos(t), 0], [0, 0, 0, 1]])


def Rz(t):
    return sp.Matrix([[sp.cos(t), -sp.sin(t), 0, 0], [sp.sin(t), sp.cos(t), 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def Tz(d):
    M = sp.eye(4)
    M[2, 3] = d
    return M


def foot(l1=L1, l2=L2, l3=L3, hip=None, ankle=None):
    hip = hip or [Rz(q[0]), Ry(q[1]), Rx(q[2])]
    ankle = ankle or [Ry(q[4]), Rx(q[5])]
    return sp.Mul(*hip, Tz(-l1), Rx(q[3]), Tz(-l2), *ankle, Tz(-l3), evaluate=False).doit()


def test_constants():
    assert ck.LENGTHS == (0.3, 0.3, 0.1)
    assert np.allclose(ck.T_GOAL[:3, 3], ck.P_GOAL) and np.allclose(ck.T_GOAL[3], [0, 0, 0, 1])
    res = ar601_leg_ik(ck.T_GOAL)
    assert res.success and len(res) == 8 and res.within_limits.sum() == 2


# ---------------------------------------------------------------- foot transform
def test_foot_transform_correct_forms():
    for answer in (foot(), foot(0.3, 0.3, 0.1), lambda qq: ar601_leg().fk(qq)):
        r = ck.foot_transform(answer, quiet=True)
        assert r.passed, r.message


@pytest.mark.parametrize("answer, code", [
    (foot(-L1, -L2, -L3), "positive_lengths"),
    (foot(l3=0), "missing_sole"),
    (foot(hip=[Rx(q[2]), Ry(q[1]), Rz(q[0])]), "hip_order"),
    (foot(ankle=[Rx(q[5]), Ry(q[4])]), "ankle_order"),
    (None, "inverse"),
])
def test_foot_transform_mistakes(answer, code):
    if answer is None:           # the inverse transform, [[Rᵀ, −Rᵀ p], [0, 1]]
        M = foot()
        answer = sp.eye(4)
        answer[:3, :3] = M[:3, :3].T
        answer[:3, 3] = -M[:3, :3].T * M[:3, 3]
    r = ck.foot_transform(answer, quiet=True)
    assert not r.passed and r.diagnosis.startswith(code), (r.diagnosis, r.message)


def test_foot_transform_knee_in_wrong_place():
    wrong = sp.Mul(Rz(q[0]), Ry(q[1]), Rx(q[2]), Tz(-L1), Tz(-L2), Rx(q[3]), Ry(q[4]), Rx(q[5]),
                   Tz(-L3), evaluate=False).doit()
    r = ck.foot_transform(wrong, quiet=True)
    assert r.diagnosis == "knee_position"


# ---------------------------------------------------------------- knee angle
def knee(d, l1, l2):
    return math.acos((d * d - l1 * l1 - l2 * l2) / (2 * l1 * l2))


def test_knee_angle_correct(capsys):
    r = ck.knee_angle(knee)
    assert r.passed and r.samples == 20
    assert capsys.readouterr().out.startswith("✔ knee_angle(d, l1, l2) is correct")
    # independent value: d = sqrt(L1^2 + L2^2) is a right angle at the knee
    assert math.isclose(knee(math.hypot(0.3, 0.3), 0.3, 0.3), math.pi / 2)


@pytest.mark.parametrize("answer, code", [
    (lambda d, l1, l2: math.acos((l1 * l1 + l2 * l2 - d * d) / (2 * l1 * l2)), "interior_angle"),
    (lambda d, l1, l2: math.degrees(knee(d, l1, l2)), "degrees"),
    (lambda d, l1, l2: -knee(d, l1, l2), "negative_branch"),
])
def test_knee_angle_mistakes(answer, code):
    r = ck.knee_angle(answer, quiet=True)
    assert not r.passed and r.diagnosis.startswith(code), (r.diagnosis, r.message)


# ---------------------------------------------------------------- IK
def numerical(T):
    return solve_ik(ar601_leg(), T, q0=np.full(6, 0.1)).q


def test_ik_solution_accepts_any_solution():
    res = ar601_leg_ik(ck.T_GOAL)
    for row in res.q:
        assert ck.ik_solution(row, quiet=True).passed
    r = ck.ik_solution(res.q, quiet=True)
    assert r.passed and "8 solutions" in r.message
    assert ck.ik_solution(numerical(ck.T_GOAL), quiet=True).passed


def test_ik_solution_diagnoses():
    q_ok = ar601_leg_ik(ck.T_GOAL).q[0]
    assert ck.ik_solution(np.rad2deg(q_ok), quiet=True).diagnosis == "degrees_output"
    position_only = solve_ik(ar601_leg(), ck.P_GOAL, q0=np.zeros(6)).q
    r = ck.ik_solution(position_only, quiet=True)
    assert r.diagnosis == "position_only" and "right place" in r.message
    assert ck.ik_solution(np.zeros(6), quiet=True).diagnosis == "mismatch"
    assert ck.ik_solution(np.zeros(5), quiet=True).diagnosis == "shape"
    assert ck.ik_solution("q", quiet=True).diagnosis == "error"
    with pytest.raises(AssertionError):
        ck.ik_solution(np.zeros(6), quiet=True, raise_on_fail=True)


def test_ik_solver():
    r = ck.ik_solver(lambda T: ar601_leg_ik(T).q, quiet=True)
    assert r.passed and "8 solutions per pose" in r.message
    r = ck.ik_solver(lambda T: ar601_leg_ik(T).q[0], quiet=True)
    assert r.passed and "up to 8" in r.message
    r = ck.ik_solver(lambda T: solve_ik(ar601_leg(), T[:3, 3], q0=np.zeros(6)).q, quiet=True)
    assert r.diagnosis == "position_only"
    assert ck.ik_solver(lambda T: 1 / 0, quiet=True).diagnosis == "error"
    assert ck.ik_solver(lambda T: np.zeros((0, 6)), quiet=True).diagnosis == "no_solution"


def test_ik_solver_wrong_ankle_point():
    def base_z_ankle(T):          # ankle backed off along the base z axis: right only for a level sole
        T2 = T.copy()
        T2[:3, 3] = T[:3, 3] + 0.1 * np.array([0.0, 0.0, 1.0]) - 0.1 * T[:3, 2]
        return ar601_leg_ik(T2).q
    r = ck.ik_solver(base_z_ankle, quiet=True)
    assert r.diagnosis in ("orientation_only", "no_solution"), r.message
    assert ck.ik_solver(np.zeros(6), quiet=True).diagnosis == "constant"
