"""Tests of the chapter-6 exercise checks (robokin.check.ar601).

The correct answers are written independently of the model: the foot pose as
a product of hand-written sympy matrices, the knee angle from the law of
cosines, a numerical IK as a solver.
"""

from __future__ import annotations

import importlib
import math
import re

import numpy as np
import pytest
import sympy as sp

from robokin.models.ar601 import ar601_leg
from robokin.models.ar601_ik import ar601_leg_ik
from robokin.motion import solve_ik
from robokin.transforms import transform

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


def test_ik_solution_names_the_answer_as_the_notebook_does():
    """The messages call the answer ``Q_mine``, the notebook's name, or the name given."""
    q_ok = ar601_leg_ik(ck.T_GOAL).q
    assert ck.ik_solution(q_ok, quiet=True).message.startswith("✔ Q_mine is correct")
    for answer in (np.zeros(6), np.zeros(5), np.rad2deg(q_ok[0])):
        message = ck.ik_solution(answer, quiet=True).message
        assert "Q_mine" in message and not re.search(r"\bq\b", message), message
    other = ck.ik_solution(np.zeros(6), name="position_only", quiet=True).message
    assert "position_only does not reach" in other and "Q_mine" not in other, other


def test_ik_solver():
    r = ck.ik_solver(lambda T: ar601_leg_ik(T).q, quiet=True)
    assert r.passed and "8 solutions per pose" in r.message
    r = ck.ik_solver(lambda T: ar601_leg_ik(T).q[0], quiet=True)
    assert r.passed and "may have more" in r.message and "8" not in r.message.split("per pose")[1]
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
    assert r.diagnosis in ("ankle_point_base_z", "no_solution"), r.message
    assert ck.ik_solver(np.zeros(6), quiet=True).diagnosis == "constant"


def _leg_ik(T, ankle, knee):
    """The chapter's construction with a pluggable ankle point and knee (non-negative branch)."""
    l1, l2, _ = ck.LENGTHS
    R, a = T[:3, :3], ankle(T)
    d = np.linalg.norm(a)
    if not abs(ck.LENGTHS[0] - ck.LENGTHS[1]) <= d <= ck.LENGTHS[0] + ck.LENGTHS[1]:
        return np.zeros((0, 6))
    q4 = knee(d)
    u = R.T @ a
    rho, phi = np.hypot(u[1], u[2]), np.arctan2(u[2], u[1])
    c6 = -l1 * np.sin(q4) / rho
    if abs(c6) > 1:
        return np.zeros((0, 6))
    q6 = np.arccos(c6) - phi
    w = Rx_num(q6) @ u
    k = l1 * np.cos(q4) + l2
    q5 = np.arctan2(w[0] / k, -w[2] / k)
    from robokin.transforms import rotation_from_rpy, rpy_from_rotation  # noqa: F401

    R_H = R @ (Rx_num(q4) @ Ry_num(q5) @ Rx_num(q6)).T
    roll, pitch, yaw = rpy_from_rotation(R_H)
    return np.array([yaw, pitch, roll, q4, q5, q6])


def Rx_num(t):
    c, s = math.cos(t), math.sin(t)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def Ry_num(t):
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def foot_ankle(T):
    return T[:3, 3] + ck.LENGTHS[2] * T[:3, 2]


def knee_ok(d):
    l1, l2, _ = ck.LENGTHS
    return math.acos((d * d - l1 * l1 - l2 * l2) / (2 * l1 * l2))


def test_ik_solver_construction_is_right():
    # the helper above is a correct solver: the diagnoses below come from the mistakes alone
    r = ck.ik_solver(lambda T: _leg_ik(T, foot_ankle, knee_ok), quiet=True)
    assert r.passed, r.message


def test_ik_solver_blames_the_knee_only_when_the_ankle_point_is_right():
    # interior angle: the ankle point is right, the knee is wrong; the orientation stays exact
    def interior(d):
        return math.pi - knee_ok(d)

    r = ck.ik_solver(lambda T: _leg_ik(T, foot_ankle, interior), quiet=True)
    assert r.diagnosis == "hip_ankle_distance", r.message
    assert "a = p + L3 R e_z, along" not in r.message and "knee" in r.message


@pytest.mark.parametrize("ankle, code", [
    (lambda T: T[:3, 3] + np.array([0.0, 0.0, ck.LENGTHS[2]]), "ankle_point_base_z"),
    (lambda T: T[:3, 3] - ck.LENGTHS[2] * T[:3, 2], "ankle_point_sign"),
    (lambda T: T[:3, 3].copy(), "ankle_point_missing"),
])
def test_ik_solver_names_the_wrong_ankle_point(ankle, code):
    r = ck.ik_solver(lambda T: _leg_ik(T, ankle, knee_ok), quiet=True)
    assert r.diagnosis in (code, "no_solution"), r.message
    if r.diagnosis == code:
        assert "ankle point" in r.message


def test_ik_solver_wrong_ankle_angles_at_the_right_distance():
    # q6 from the other arccos branch but q5 kept from the first: right |a|, wrong ankle
    def bad(T):
        q = _leg_ik(T, foot_ankle, knee_ok)
        if len(q) == 0:
            return q
        q = q.copy()
        q[5] += 0.3
        R = T[:3, :3]
        # re-solve the hip so that the orientation is exact again
        from robokin.transforms import rpy_from_rotation

        R_H = R @ (Rx_num(q[3]) @ Ry_num(q[4]) @ Rx_num(q[5])).T
        roll, pitch, yaw = rpy_from_rotation(R_H)
        q[:3] = [yaw, pitch, roll]
        return q

    r = ck.ik_solver(bad, quiet=True)
    assert r.diagnosis == "ankle_angles", r.message


# ---------------------------------------------------------------- every solution: leg_ik
def _all_solutions(T):
    """Every solution of a foot pose, written independently of the check: robokin's
    closed form, whose rows the forward kinematics verifies."""
    return ar601_leg_ik(T).q


def test_leg_ik_reference_is_robokins_closed_form():
    leg = ar601_leg()
    for q0 in leg.random_configurations(30, seed=7):
        T = leg.fk(q0)
        rows = ck._closed_form(T)
        assert rows.shape == (8, 6) and np.allclose(leg.fk(rows), T, atol=1e-10)
        assert ck._same_rows(rows, _all_solutions(T))


def test_leg_ik_accepts_every_order_and_full_turns(capsys):
    assert ck.leg_ik(_all_solutions).passed
    assert "all 8 solutions" in capsys.readouterr().out
    assert ck.leg_ik(lambda T: _all_solutions(T)[::-1] + 2 * np.pi, quiet=True).passed
    assert ck.leg_ik(lambda T: list(map(list, _all_solutions(T))), quiet=True).passed


def _hip_angles_xyz(T):
    """The typical mistake, written out: hip angles (a, b, c) of Rx(a) Ry(b) Rz(c) = R_H."""
    from robokin.transforms import rotx, roty

    out = []
    for q in _all_solutions(T):
        R_H = T[:3, :3] @ (rotx(q[3]) @ roty(q[4]) @ rotx(q[5])).T
        for sign in (1.0, -1.0):
            c2 = sign * math.hypot(R_H[1, 2], R_H[2, 2])
            a = math.atan2(-R_H[1, 2] / c2, R_H[2, 2] / c2)
            b = math.atan2(R_H[0, 2], c2)
            c = math.atan2(-R_H[0, 1] / c2, R_H[0, 0] / c2)
            out.append([c, b, a, *q[3:]])
    unique: list[list[float]] = []
    for row in out:
        if not any(np.allclose(ck._wrap(np.subtract(row, u)), 0, atol=1e-9) for u in unique):
            unique.append(row)
    return np.array(unique)


@pytest.mark.parametrize("answer, code", [
    (lambda T: _all_solutions(T)[_all_solutions(T)[:, 3] > 0], "knee_branch_missing"),
    (lambda T: _all_solutions(T)[np.cos(_all_solutions(T)[:, 1]) > 0], "hip_branch_missing"),
    (lambda T: np.rad2deg(_all_solutions(T)), "degrees_output"),
    (lambda T: np.r_[_all_solutions(T), _all_solutions(T)[:1]], "duplicate"),
    (lambda T: _all_solutions(T)[:7], "missing"),
    (_hip_angles_xyz, "hip_order"),
    (lambda T: ck._closed_form(T, "hip_atan2_swapped"), "hip_atan2_swapped"),
    (lambda T: ck._closed_form(T, "ankle_atan2_swapped"), "ankle_atan2_swapped"),
    (lambda T: ck._closed_form(T, "ankle_branch_missing"), "ankle_branch_missing"),
    (lambda T: ck._closed_form(T, "hip_product_side"), "hip_product_side"),
])
def test_leg_ik_names_the_mistake(answer, code):
    result = ck.leg_ik(answer, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message
    assert "my_leg_ik" in result.message


def test_leg_ik_hip_atan2_swapped_written_out():
    def swapped(T):
        rows = _all_solutions(T).copy()
        rows[:, 0] = np.pi / 2 - rows[:, 0]  # atan2(x, y) = pi/2 - atan2(y, x)
        rows[:, 2] = np.pi / 2 - rows[:, 2]
        return rows

    result = ck.leg_ik(swapped, quiet=True)
    assert result.diagnosis == "hip_atan2_swapped", result.message


@pytest.mark.parametrize("answer, code", [
    (None, "error"), (3.0, "constant"), (lambda T: 1 / 0, "error"),
    (lambda T: np.zeros((8, 5)), "shape"), (lambda T: np.full((8, 6), np.nan), "not_finite"),
    (lambda T: np.zeros((0, 6)), "missing"),
])
def test_leg_ik_bad_answers(answer, code):
    result = ck.leg_ik(answer, quiet=True)
    assert not result.passed and result.diagnosis == code


def test_leg_ik_raises_on_fail():
    with pytest.raises(AssertionError, match="knee"):
        ck.leg_ik(lambda T: _all_solutions(T)[_all_solutions(T)[:, 3] > 0], raise_on_fail=True)


# ---------------------------------------------------------------- unreachable_reason
def _reason_by_robokin(T):
    res = ar601_leg_ik(T, within_limits=True)
    return None if res.success else res.reason


def test_unreachable_reason_targets_cover_every_reason_and_agree_with_robokin():
    targets = ck._reason_targets(0)
    assert {reason for _, reason in targets} == {None, "too_far", "ankle_range", "joint_limits"}
    for T, reason in targets:
        assert _reason_by_robokin(T) == reason


def test_unreachable_reason_correct(capsys):
    assert ck.unreachable_reason(_reason_by_robokin).passed
    assert "16 targets" in capsys.readouterr().out


@pytest.mark.parametrize("answer, code", [
    (lambda T: "too_far" if _reason_by_robokin(T) == "ankle_range" else _reason_by_robokin(T),
     "ankle_range_as_too_far"),
    (lambda T: None if _reason_by_robokin(T) == "joint_limits" else _reason_by_robokin(T),
     "joint_limits_as_reachable"),
    (lambda T: "far" if _reason_by_robokin(T) == "too_far" else _reason_by_robokin(T),
     "unknown_reason"),
    (lambda T: 0, "type"), (None, "error"), ("too_far", "constant"),
    (lambda T: [][1], "error"),
])
def test_unreachable_reason_mistakes(answer, code):
    result = ck.unreachable_reason(answer, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


# ---------------------------------------------------------------- the steps: ankle point, ankle angles
def _ankle_frames_origin(T):
    """The ankle point read off the model: the ankle frames' origin at a solution of T."""
    leg = ar601_leg()
    return leg.frames(ar601_leg_ik(T).q[0])[5][:3, 3]


def test_ankle_point_correct_and_its_reference_is_the_model():
    leg = ar601_leg()
    for x in leg.random_configurations(5, seed=3):
        T = leg.fk(x)
        assert np.allclose(ck._ankle_point_of(T), _ankle_frames_origin(T), atol=1e-12)
    assert ck.ankle_point(foot_ankle, quiet=True).passed


@pytest.mark.parametrize("answer, code", [
    (lambda T: T[:3, 3] + np.array([0.0, 0.0, ck.LENGTHS[2]]), "ankle_point_base_z"),
    (lambda T: T[:3, 3] - ck.LENGTHS[2] * T[:3, 2], "ankle_point_sign"),
    (lambda T: T[:3, 3].copy(), "ankle_point_missing"),
    (lambda T: T[:3, 3] + ck.LENGTHS[2] * T[2, :3], "ankle_point_row"),
    (lambda T: T[:3, 3] + 0.2 * T[:3, 2], "mismatch"),
    (lambda T: T[:3, :3], "shape"),
    (None, "error"),
])
def test_ankle_point_mistakes(answer, code):
    assert ck.ankle_point(answer, quiet=True).diagnosis == code


def _ankle_pairs_numeric(u, q4):
    """Every (q5, q6) with Ry(q5) Rx(q6) u = v(q4), by a scan of q6 and root polishing:
    independent of the check's closed form."""
    l1, l2, _ = ck.LENGTHS
    v = np.array([0.0, -l1 * math.sin(q4), -(l1 * math.cos(q4) + l2)])

    def y_residual(q6):
        return (Rx_num(q6) @ u)[1] - v[1]

    grid = np.linspace(-math.pi, math.pi, 2001)
    values = np.array([y_residual(g) for g in grid])
    pairs = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if fa == 0.0 or fa * fb < 0.0:
            for _ in range(60):  # bisection
                m = 0.5 * (a + b)
                if y_residual(a) * y_residual(m) <= 0.0:
                    b = m
                else:
                    a = m
            q6 = 0.5 * (a + b)
            w = Rx_num(q6) @ u
            q5 = math.atan2(v[0], v[2]) - math.atan2(w[0], w[2])  # Ry turns z towards x
            pairs.append((q5, q6))
    return pairs


def test_ankle_angles_correct_against_a_numeric_solve():
    leg = ar601_leg()
    for x in leg.random_configurations(5, seed=4):
        T = leg.fk(x)
        u = T[:3, :3].T @ foot_ankle(T)
        assert ck._same_rows(np.array(_ankle_pairs_numeric(u, x[3])), ck._ankle_pairs(u, x[3]))
    assert ck.ankle_angles(_ankle_pairs_numeric, quiet=True).passed


@pytest.mark.parametrize("answer, code", [
    (lambda u, q4: [(-a, b) for a, b in _ankle_pairs_numeric(u, q4)], "ankle_q5_sign"),
    (lambda u, q4: _ankle_pairs_numeric(u, q4)[:1], "ankle_branch_missing"),
    (lambda u, q4: np.rad2deg(_ankle_pairs_numeric(u, q4)), "degrees_output"),
    (lambda u, q4: [(a + 0.1, b) for a, b in _ankle_pairs_numeric(u, q4)], "mismatch"),
    (lambda u, q4: 0.3, "shape"),
])
def test_ankle_angles_mistakes(answer, code):
    assert ck.ankle_angles(answer, quiet=True).diagnosis == code


# ---------------------------------------------------------------- the count of Task 3
def test_k_regular_is_robokins_count_at_random_poses():
    leg = ar601_leg()
    counts = {len(ar601_leg_ik(leg.fk(x)).q) for x in leg.random_configurations(10, seed=6)}
    assert counts == {8}
    for answer in (8, 8.0, np.int64(8)):
        assert ck.k_regular(answer, quiet=True).passed


@pytest.mark.parametrize("answer, code", [
    (4, "branch_missing"), (2, "branch_missing"), (6, "count"), (16, "count"),
    (None, "error"), ("8", "type"), (True, "type"), (np.zeros(3), "type"),
])
def test_k_regular_mistakes(answer, code):
    assert ck.k_regular(answer, quiet=True).diagnosis == code


# ---------------------------------------------------------------- the tests' stand-ins for the steps
def _wrapped(a):
    return (np.asarray(a, dtype=float) + np.pi) % (2 * np.pi) - np.pi


def test_reference_steps_pass_their_checks_and_agree_with_the_model():
    leg = ar601_leg()
    assert ck.ankle_point(ck.reference_ankle_point, quiet=True).passed
    assert ck.ankle_angles(ck.reference_ankle_angles, quiet=True).passed
    assert ck.knee_angle(ck.reference_knee_angle, quiet=True).passed
    for x in leg.random_configurations(20, seed=7):
        T, frames = leg.fk(x), leg.frames(x)
        assert np.allclose(ck.reference_ankle_point(T), frames[5][:3, 3], atol=1e-12)
        assert np.isclose(ck.reference_knee_angle(np.linalg.norm(frames[5][:3, 3])), abs(x[3]), atol=1e-7)
        u = T[:3, :3].T @ frames[5][:3, 3]
        pairs = ck.reference_ankle_angles(u, x[3])
        assert all(isinstance(p, tuple) and len(p) == 2 for p in pairs)
        assert ck._same_rows(np.array(pairs), np.array(_ankle_pairs_numeric(u, x[3])))
        R_H = frames[3][:3, :3]  # after the three hip joints
        hips = ck.reference_hip_angles(R_H)
        assert len(hips) == 2 and np.cos(hips[0][1]) > 0 > np.cos(hips[1][1])
        for a, b, c in hips:
            assert np.allclose(Rz(a)[:3, :3] * Ry(b)[:3, :3] * Rx(c)[:3, :3], R_H, atol=1e-12)
        assert np.abs(_wrapped(np.array(hips) - x[:3])).max(axis=1).min() < 1e-9


def test_reference_steps_in_a_leg_ik_give_robokins_solutions():
    leg = ar601_leg()

    def leg_ik(T):
        R, a = T[:3, :3], ck.reference_ankle_point(T)
        q4_abs = ck.reference_knee_angle(np.linalg.norm(a))
        rows = []
        for q4 in (q4_abs, -q4_abs):
            for q5, q6 in ck.reference_ankle_angles(R.T @ a, q4):
                M = np.array(Rx(q4)[:3, :3] * Ry(q5)[:3, :3] * Rx(q6)[:3, :3], dtype=float)
                rows += [[*h, q4, q5, q6] for h in ck.reference_hip_angles(R @ M.T)]
        return np.array(rows)

    for x in leg.random_configurations(5, seed=8):
        T = leg.fk(x)
        assert ck._same_rows(leg_ik(T), ar601_leg_ik(T).q)


def test_reference_knee_angle_at_the_stretched_leg_and_beyond():
    # d = L1 + L2: rounding puts the cosine a hair past 1 (1 + 2e-16), still the stretched knee
    assert ck.reference_knee_angle(0.3 + 0.3) == 0.0
    assert np.isnan(ck.reference_knee_angle(0.61)) and np.isnan(ck.reference_knee_angle(0.5, 0.1, 0.3))
    assert np.isclose(ck.reference_knee_angle(np.hypot(0.3, 0.3)), np.pi / 2)
    assert np.isclose(ck.reference_knee_angle(0.0), np.pi)  # folded: the ankle on the hip


@pytest.mark.parametrize("call", [
    lambda: ck.reference_ankle_point(np.eye(3)),
    lambda: ck.reference_knee_angle(-0.1),
    lambda: ck.reference_knee_angle(0.4, 0.0),
    lambda: ck.reference_hip_angles(2 * np.eye(3)),
    lambda: ck.reference_ankle_angles([0.0, 0.1], 0.3),
    lambda: ck.reference_ankle_angles([0.0, np.nan, -0.5], 0.3),
])
def test_reference_steps_reject_bad_input(call):
    with pytest.raises(ValueError):
        call()


# ---------------------------------------------------------------- sole_sweep
def _sweep(heights, leg_ik, row=0, none=np.nan, value=-1, sign=-1.0):
    """A sole_sweep: the rows of leg_ik for the sole level at each height, sigma at ``row``."""
    leg = ar601_leg()
    counts, sigmas = [], []
    for h in heights:
        Q = np.asarray(leg_ik(transform(np.eye(3), [0.0, 0.0, sign * h])))
        counts.append(len(Q))
        sigmas.append(leg.singular_values(Q[row])[value] if len(Q) else none)
    return np.array(counts), np.array(sigmas)


def test_sole_sweep_correct(capsys):
    assert ck.sole_sweep(_sweep).passed
    assert "6 heights" in capsys.readouterr().out


def _own_ik_only(heights, leg_ik):
    """Ignores leg_ik: robokin's closed form in its place."""
    return _sweep(heights, lambda T: ar601_leg_ik(T).q)


@pytest.mark.parametrize("answer, code", [
    (lambda h, ik: _sweep(h, ik, row=-1), "sigma_last_row"),
    (lambda h, ik: _sweep(h, ik, none=0.0), "zero_for_none"),
    (lambda h, ik: _sweep(h, ik, value=0), "largest_singular_value"),
    (lambda h, ik: _sweep(h, ik, sign=1.0), "height_sign"),
    (lambda h, ik: _sweep(h, lambda T: [q for q in ik(T) if ar601_leg().within_limits(q)]),
     "within_limits_only"),
    (_own_ik_only, "leg_ik_ignored"),
    (lambda h, ik: (_sweep(h, ik)[0] * 2, _sweep(h, ik)[1]), "count"),
    (lambda h, ik: 3, "type"),
    (None, "error"),
])
def test_sole_sweep_mistakes(answer, code):
    result = ck.sole_sweep(answer, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_later_functions_are_judged_on_robokins_steps():
    """my_leg_ik and unreachable_reason take their earlier steps as keyword parameters: the checks
    pass robokin's, so a wrong knee (the interior angle) of the student's leaves them correct."""
    def interior_knee(d, l1_=0.3, l2_=0.3):
        return np.arccos((l1_**2 + l2_**2 - d**2) / (2 * l1_ * l2_))

    def assembly(T, ankle=None, knee=interior_knee, ankle_angles=None, hip_angles=None):
        return ar601_leg_ik(T).q if knee is not interior_knee else np.zeros((0, 6))

    def reason(T, leg_ik=lambda T: np.zeros((0, 6))):
        return _reason_by_robokin(T) if len(leg_ik(ck.T_GOAL)) else "too_far"

    assert ck.leg_ik(assembly, quiet=True).passed
    assert ck.unreachable_reason(reason, quiet=True).passed
    # a function without those parameters is called as it is
    assert not ck.leg_ik(lambda T: np.zeros((0, 6)), quiet=True).passed


# ---------------------------------------------------------------- different_solutions
def _wrap_angles(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def _counted(Q, apart):
    """The rows of Q that differ from every earlier kept row by ``apart``, counted."""
    kept: list[np.ndarray] = []
    for q in Q:
        if all(apart(q - other) for other in kept):
            kept.append(q)
    return len(kept)


@pytest.mark.parametrize("answer", [
    lambda Q: _counted(Q, lambda d: np.abs(_wrap_angles(d)).max() > 1e-9),
    lambda Q: len(np.unique(np.hstack([np.cos(Q), np.sin(Q)]).round(9), axis=0)),
    lambda Q: np.int64(_counted(Q, lambda d: np.abs(np.arctan2(np.sin(d), np.cos(d))).max() > 1e-9)),
])
def test_different_solutions_correct(answer, capsys):
    assert ck.different_solutions(answer).passed
    assert "5 sets of rows" in capsys.readouterr().out


@pytest.mark.parametrize("answer, code", [
    (lambda Q: _counted(Q, lambda d: np.abs(d).max() > 1e-9), "no_wrapping"),
    (lambda Q: len(Q), "rows_counted"),
    (lambda Q: len(np.unique(_wrap_angles(Q), axis=0)), "exact_equality"),
    (lambda Q: _counted(Q, lambda d: np.abs(_wrap_angles(d)).max() > 0.0), "exact_equality"),
    (lambda Q: len(np.unique(_wrap_angles(Q).round(4), axis=0)), "tolerance_too_loose"),
    (lambda Q: 0, "count"),
    (lambda Q: None, "type"),
    (lambda Q: "2", "type"),
    (3, "constant"),
])
def test_different_solutions_mistakes(answer, code):
    result = ck.different_solutions(answer, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_delegation_lists_every_function_check_of_a_solving_task():
    """The sweep's rows come from the inverse kinematics it is given: robokin's closed form in
    its place is flagged for review (tools/grading/bridge/delegation.py reads this table)."""
    assert set(ck.DELEGATION) <= set(ck.__all__)
    assert "ar601_leg_ik" in ck.DELEGATION["sole_sweep"]


# ---------------------------------------------------------------- no answer in a message
def test_messages_of_wrong_answers_name_no_expected_value():
    """A wrong attempt learns its mistake and the principle, not the graded values: the target's
    hip-ankle distance (Task 3's d_goal), the right ankle point or ankle pairs, the count of
    solutions (k_regular) or the closed forms of the steps."""
    d_goal = np.linalg.norm(ck.reference_ankle_point(ck.T_GOAL))
    q_wrong_knee = ck._closed_form(ck.T_GOAL)[0] + [0, 0, 0, 0.05, 0, 0]
    messages = [
        ck.ik_solution(q_wrong_knee, quiet=True).message,
        ck.ik_solver(lambda T: ck._closed_form(T)[0] + [0, 0, 0, 0.05, 0, 0], quiet=True).message,
        ck.ankle_point(lambda T: np.zeros(3), quiet=True).message,
        ck.ankle_angles(lambda u, q4: [(0.0, 0.0)], quiet=True).message,
        ck.k_regular(4, quiet=True).message,
        ck.leg_ik(lambda T: ck._closed_form(T)[:1], quiet=True).message,
        ck.leg_ik(lambda T: ck._closed_form(T, "knee_branch_missing"), quiet=True).message,
        ck.leg_ik(lambda T: ck._closed_form(T, "hip_atan2_swapped"), quiet=True).message,
        ck.knee_angle(lambda d, l1, l2: np.arccos((l1**2 + l2**2 - d**2) / (2 * l1 * l2)), quiet=True).message,
    ]
    assert not any(result.startswith("✔") for result in messages)
    text = "\n".join(messages)
    assert f"{d_goal:.4f}" not in text and f"{d_goal:.3f}" not in text
    for closed_form in ("arccos(−L1 s4", "atan2(r21", "atan2(w_x", "(d² − L1² − L2²) / (2 L1 L2)", "has 8"):
        assert closed_form not in text, closed_form


# ---------------------------------------------------------------- hip_angles
def _hips_written_out(R_H, swap=False):
    """Both hip triples, written out as the chapter derives them (cos q2 > 0 first)."""
    out = []
    for c2 in (np.hypot(R_H[0, 0], R_H[1, 0]), -np.hypot(R_H[0, 0], R_H[1, 0])):
        first, second = (R_H[0, 0], R_H[1, 0]) if swap else (R_H[1, 0], R_H[0, 0])
        out.append((np.arctan2(first / c2, second / c2), np.arctan2(-R_H[2, 0], c2),
                    np.arctan2(R_H[2, 1] / c2, R_H[2, 2] / c2) if not swap
                    else np.arctan2(R_H[2, 2] / c2, R_H[2, 1] / c2)))
    return out


def test_hip_angles_correct(capsys):
    assert ck.hip_angles(_hips_written_out).passed
    assert ck.hip_angles(ck.reference_hip_angles).passed
    assert "20 random hip rotations" in capsys.readouterr().out


@pytest.mark.parametrize("answer, code", [
    (lambda R: _hips_written_out(R)[:1], "hip_branch_missing"),
    (lambda R: _hips_written_out(R, swap=True), "hip_atan2_swapped"),
    (lambda R: [(c, b, a) for a, b, c in _hips_written_out(R)], "hip_reversed"),
    (lambda R: _hips_written_out(R.T), "hip_transposed"),
    (lambda R: [(-a, -b, -c) for a, b, c in _hips_written_out(R.T)], "hip_order"),
    (lambda R: _hips_written_out(R)[::-1], "first_branch"),
    (lambda R: np.rad2deg(_hips_written_out(R)), "degrees_output"),
    (lambda R: _hips_written_out(R)[:1] * 2, "duplicate"),
    (lambda R: [], "missing"),
    (lambda R: [(0.0, 0.0, 0.0)], "mismatch"),
    (lambda R: np.zeros((2, 2)), "shape"),
    (None, "error"),
])
def test_hip_angles_mistakes(answer, code):
    result = ck.hip_angles(answer, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message
