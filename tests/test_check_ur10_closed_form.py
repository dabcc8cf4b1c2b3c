"""Tests of the chapter-7 exercise checks (robokin.check.ur10_closed_form).

The correct answers are written here independently of the check module: each step of the
closed form from the DH table, and all solutions by a dense multi-start Newton search on
the forward kinematics (no closed form). Each typical mistake is written out as a student
would make it and must be named by its diagnosis.
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

from robokin.check import solution_set
from robokin.models import ur10, ur10_ik
from robokin.models.ur10 import UR10_DH

chk = importlib.import_module("robokin.check.ur10_closed_form")
ROBOT = ur10()
D1, A2, A3 = UR10_DH[0][0], UR10_DH[1][2], UR10_DH[2][2]
D4, D5, D6 = UR10_DH[3][0], UR10_DH[4][0], UR10_DH[5][0]


def wrap(a):
    return np.pi - np.mod(np.pi - np.asarray(a, dtype=float), 2 * np.pi)


def centre(T, sign=-1.0):
    return T[:3, 3] + sign * D6 * T[:3, 2]


def shoulder(T, *, swap=False, d4=D4, dropped=False, solved=""):
    x, y, _ = centre(T)
    r = math.hypot(x, y)
    psi = math.atan2(x, y) if swap else math.atan2(y, x)
    if solved == "arcsin":  # sin(q1 - psi) = d4 / r taken as q1 - psi = +-arcsin(d4 / r)
        return wrap([psi + math.asin(d4 / r), psi - math.asin(d4 / r)])
    if solved == "cosine":  # r cos(q1 - psi) = d4 solved instead
        return wrap([psi + math.acos(d4 / r), psi - math.acos(d4 / r)])
    beta = math.acos(min(1.0, max(-1.0, d4 / r)))  # clipped: the flange point may be inside |d4|
    out = [psi + math.pi / 2 + beta, psi + math.pi / 2 - beta]
    return wrap(out[:1] if dropped else out)


def wrist(T, q1, *, swap=False, dropped=False, degrees=False, z1_sign=1.0, keep_q6=False):
    z1 = z1_sign * np.array([math.sin(q1), -math.cos(q1), 0.0])
    a, b, c5 = T[:3, :3].T @ z1  # (c6 s5, -s6 s5, c5)
    rows = []
    for sign in (1.0, -1.0)[: 1 if dropped else 2]:
        s5 = sign * math.hypot(a, b)
        q6 = math.atan2(a / s5, -b / s5) if swap else math.atan2(-b / s5, a / s5)
        rows.append([math.atan2(s5, c5), math.atan2(-b, a) if keep_q6 else q6])
    rows = wrap(rows)
    return np.rad2deg(rows) if degrees else rows


def arm(T, q1, q5, q6, *, a_sign=1.0, dropped=False, wrist_point=False, height=D1, phi_swapped=False,
        inner=-1.0, q4_without_q3=False):
    R = T[:3, :3]
    z4 = R @ [-math.sin(q6), -math.cos(q6), 0.0]
    x4 = R @ [math.cos(q5) * math.cos(q6), -math.cos(q5) * math.sin(q6), -math.sin(q5)]
    p4 = centre(T) - (0.0 if wrist_point else D5) * z4
    X, Y = math.cos(q1) * p4[0] + math.sin(q1) * p4[1], p4[2] - height
    a2, a3 = a_sign * A2, a_sign * A3
    c3 = (X * X + Y * Y - a2 * a2 - a3 * a3) / (2 * a2 * a3)
    if abs(c3) > 1:
        return np.zeros((0, 3))
    along_x1, along_y1 = math.cos(q1) * x4[0] + math.sin(q1) * x4[1], x4[2]
    phi = math.atan2(along_x1, along_y1) if phi_swapped else math.atan2(along_y1, along_x1)
    rows = []
    for q3 in (math.acos(c3), -math.acos(c3))[: 1 if dropped else 2]:
        q2 = math.atan2(Y, X) + inner * math.atan2(a3 * math.sin(q3), a2 + a3 * math.cos(q3))
        rows.append([q2, q3, phi - q2 - (0.0 if q4_without_q3 else q3)])
    return wrap(rows)


def every_solution(T):
    rows = []
    for q1 in shoulder(T):
        for q5, q6 in wrist(T, q1):
            for q2, q3, q4 in arm(T, q1, q5, q6):
                q = np.array([q1, q2, q3, q4, q5, q6])
                if np.abs(ROBOT.fk(q) - T).max() < 1e-9:
                    rows.append(q)
    return np.array(rows).reshape(-1, 6)


def newton_search(T, starts=60, seed=3):
    """All solutions by Newton's method on the pose error from many random starts."""
    from robokin.transforms import rotation_log

    rng = np.random.default_rng(seed)
    found: list[np.ndarray] = []
    for q in rng.uniform(-np.pi, np.pi, (starts, 6)):
        for _ in range(60):
            F = ROBOT.fk(q)
            error = np.r_[T[:3, 3] - F[:3, 3], rotation_log(T[:3, :3] @ F[:3, :3].T)]
            if np.linalg.norm(error) < 1e-13:
                break
            q = q + np.linalg.lstsq(ROBOT.jacobian(q), error, rcond=None)[0]
        if np.abs(ROBOT.fk(q) - T).max() < 1e-10:
            q = wrap(q)
            if not any(np.abs(wrap(q - f)).max() < 1e-6 for f in found):
                found.append(q)
    return np.array(found).reshape(-1, 6)


# ---------------------------------------------------------------- correct answers
@pytest.mark.parametrize("name, answer", [
    ("wrist_centre", centre),
    ("shoulder_angles", shoulder),
    ("wrist_angles", wrist),
    ("arm_angles", arm),
    ("all_solutions", every_solution),
])
def test_correct_answers_pass(name, answer):
    result = getattr(chk, name)(answer, quiet=True)
    assert result.passed and result.diagnosis is None, result.message
    assert result.samples == 20


def test_a_later_step_is_judged_on_robokins_earlier_steps():
    """A step that takes earlier ones as keyword arguments (the student's own by default) is
    checked with robokin's in their place: a wrong earlier step is not blamed on it (the grading
    report asks these checks about the bare answers)."""
    def flange_point(T):  # a wrong wrist centre: the flange's origin
        return T[:3, 3]

    def shoulder_from(T, wrist_centre=flange_point):
        x, y, _ = wrist_centre(T)
        psi, beta = math.atan2(y, x), math.acos(D4 / math.hypot(x, y))
        return wrap([psi + math.pi / 2 + beta, psi + math.pi / 2 - beta])

    def no_arm(T, q1, q5, q6):  # a wrong planar step: never a solution
        return np.zeros((0, 3))

    def loop(T, shoulder_angles=shoulder, wrist_angles=wrist, arm_angles=no_arm):
        rows = [np.r_[q1, q234, q5, q6] for q1 in shoulder_angles(T) for q5, q6 in wrist_angles(T, q1)
                for q234 in arm_angles(T, q1, q5, q6)]
        return np.array([q for q in rows if np.abs(ROBOT.fk(q) - T).max() < 1e-9]).reshape(-1, 6)

    for name, answer in [("shoulder_angles", shoulder_from), ("all_solutions", loop)]:
        assert getattr(chk, name)(answer, quiet=True).passed
        # called without its keyword parameters, it runs on the wrong step it holds
        assert not getattr(chk, name)(lambda T, f=answer: f(T), quiet=True).passed


def test_the_references_are_what_a_dense_numerical_search_finds():
    for x in chk.all_solutions.sample_points()[:3]:
        T = chk._pose(x)
        reference = chk._all(T)
        assert solution_set(newton_search(T), reference, quiet=True).passed
        assert solution_set(every_solution(T), reference, quiet=True).passed


def test_the_samples_are_away_from_the_singular_cases():
    for x in chk.all_solutions.sample_points():
        result = ur10_ik(chk._pose(x))
        assert result.success and not result.singular and len(result) in (4, 8)
        assert np.abs(np.sin(result.q[:, [2, 4]])).min() > 0.1
        assert np.hypot(*result.wrist_centre[:2]) > abs(D4) + 1e-3


def test_the_wrist_centre_reference_is_frame_5():
    for x in chk.wrist_centre.sample_points()[:5]:
        assert np.allclose(chk.wrist_centre.reference(x), centre(ROBOT.fk(x)), atol=1e-12)


# ---------------------------------------------------------------- typical mistakes
MISTAKES = [
    ("wrist_centre", lambda T: centre(T, sign=0.0), "flange_point"),
    ("wrist_centre", lambda T: centre(T, sign=1.0), "d6_sign"),
    ("wrist_centre", lambda T: T[:3, 3] - D6 * T[2, :3], "wrong_axis"),
    ("wrist_centre", lambda T: T[:3, 3] - D5 * T[:3, 2], "d5_for_d6"),
    ("shoulder_angles", lambda T: shoulder(T, solved="arcsin"), "arcsin_branch"),
    ("shoulder_angles", lambda T: shoulder(T, solved="cosine"), "cosine_for_sine"),
    ("shoulder_angles", lambda T: shoulder(T, swap=True), "atan2_swapped"),
    ("shoulder_angles", lambda T: shoulder(T, d4=-D4), "d4_sign"),
    ("shoulder_angles", lambda T: shoulder(T, dropped=True), "branch_dropped"),
    ("shoulder_angles", lambda T: np.rad2deg(shoulder(T)), "degrees_output"),
    ("shoulder_angles", lambda T: shoulder(np.vstack([np.c_[T[:3, :3], centre(T, 1.0)], T[3:]])), "flange_point"),
    ("wrist_angles", lambda T, q1: wrist(T, q1, swap=True), "atan2_swapped"),
    ("wrist_angles", lambda T, q1: wrist(T, q1) * [1, -1], "q6_sign"),
    ("wrist_angles", lambda T, q1: wrist(T, q1, dropped=True), "branch_dropped"),
    ("wrist_angles", lambda T, q1: wrist(T, q1, z1_sign=-1.0), "z1_sign"),
    ("wrist_angles", lambda T, q1: wrist(T, q1, keep_q6=True), "q6_not_flipped"),
    ("wrist_angles", lambda T, q1: wrist(T, q1, degrees=True), "degrees_output"),
    ("arm_angles", lambda T, q1, q5, q6: arm(T, q1, q5, q6, a_sign=-1.0), "a_sign"),
    ("arm_angles", lambda T, q1, q5, q6: arm(T, q1, q5, q6, dropped=True), "branch_dropped"),
    ("arm_angles", lambda T, q1, q5, q6: arm(T, q1, q5, q6, wrist_point=True), "wrist_point"),
    ("arm_angles", lambda T, q1, q5, q6: arm(T, q1, q5, q6, height=0.0), "shoulder_height"),
    ("arm_angles", lambda T, q1, q5, q6: arm(T, q1, q5, q6, phi_swapped=True), "atan2_swapped_phi"),
    ("arm_angles", lambda T, q1, q5, q6: arm(T, q1, q5, q6, inner=1.0), "inner_angle_sign"),
    ("arm_angles", lambda T, q1, q5, q6: arm(T, q1, q5, q6, q4_without_q3=True), "q3_missing_in_q4"),
    ("arm_angles", lambda T, q1, q5, q6: np.rad2deg(arm(T, q1, q5, q6)), "degrees_output"),
    ("all_solutions", lambda T: every_solution(T)[:2], "branch_dropped"),
    ("all_solutions", lambda T: np.rad2deg(every_solution(T)), "degrees_output"),
    ("all_solutions", lambda T: np.vstack([every_solution(T)] * 2), "duplicate"),
    ("all_solutions", lambda T: every_solution(T) + [0, 0, 0, 0, 0, 0.5], "extra"),
]


@pytest.mark.parametrize("name, answer, code", MISTAKES, ids=[f"{m[0]}-{m[2]}" for m in MISTAKES])
def test_typical_mistakes_are_named(name, answer, code):
    result = getattr(chk, name)(answer, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message
    assert name in result.message


def test_messages_name_the_fix(capsys):
    chk.shoulder_angles(lambda T: shoulder(T, swap=True))
    assert "atan2(y, x)" in capsys.readouterr().out
    chk.arm_angles(lambda T, q1, q5, q6: arm(T, q1, q5, q6, a_sign=-1.0))
    assert "negative" in capsys.readouterr().out


# ---------------------------------------------------------------- answers that are no answer
@pytest.mark.parametrize("name", ["wrist_centre", "shoulder_angles", "wrist_angles", "arm_angles", "all_solutions"])
@pytest.mark.parametrize("answer", [None, 3.0, "abc", np.zeros(6), lambda *a: None, lambda *a: "x", lambda *a: 1 / 0,
                                    lambda *a: np.full((2, 6), np.nan), lambda *a: np.zeros((2, 5, 7))])
def test_garbage_gives_a_failed_result(name, answer):
    result = getattr(chk, name)(answer, quiet=True)
    assert not result.passed and isinstance(result.message, str) and result.message


def test_an_unreachable_answer_set_is_empty_for_arm_angles():
    q = np.array([0.4, -1.0, 0.8, -0.5, 1.1, 0.3])
    T = ROBOT.fk(q)
    T[:3, 3] += 2.0 * T[:3, 3] / np.linalg.norm(T[:3, 3])
    assert chk._arm(T, q[0], q[4], q[5]).shape == (0, 3)


def test_delegation_names_the_closed_form():
    assert set(chk.DELEGATION) == {"wrist_centre", "shoulder_angles", "wrist_angles", "arm_angles", "all_solutions",
                                   "coinciding_branches"}
    assert all("ur10_ik" in table for table in chk.DELEGATION.values())


@pytest.mark.parametrize("name", ["wrist_centre", "shoulder_angles", "wrist_angles", "arm_angles", "all_solutions"])
def test_help_and_repr_show_no_closed_form(name):
    """What a student sees of a check before answering (``help()``, the bare name in a cell, the
    module's help) names the function and its contract, not a message of a typical mistake."""
    import pydoc

    item = getattr(chk, name)
    shown = [repr(item), pydoc.plain(pydoc.render_doc(item)),
             pydoc.plain(pydoc.render_doc(chk))]
    assert name in shown[0] and item.signature in shown[0]
    for text in shown:
        for formula in ("arccos", "arcsin", "atan2(", "d6 z6", "p5 − d5", "π/2", "y6·z1"):
            assert formula not in text, (name, formula)


# ---------------------------------------------------------------- robokin's steps, the tests' stand-ins
REFERENCE_STEPS = {
    "wrist_centre": chk.reference_wrist_centre,
    "shoulder_angles": chk.reference_shoulder_angles,
    "wrist_angles": chk.reference_wrist_angles,
    "arm_angles": chk.reference_arm_angles,
}


@pytest.mark.parametrize("name", sorted(REFERENCE_STEPS))
def test_reference_steps_pass_their_checks(name):
    result = getattr(chk, name)(REFERENCE_STEPS[name], quiet=True)
    assert result.passed, result.message


def test_reference_steps_agree_with_the_steps_written_here_and_the_model():
    rng = np.random.default_rng(17)
    for q in rng.uniform(-np.pi, np.pi, (40, 6)):
        T = ROBOT.fk(q)
        assert np.allclose(chk.reference_wrist_centre(T), ROBOT.frames(q)[6][:3, 3], atol=1e-12)
        q1_all = chk.reference_shoulder_angles(T)
        assert np.abs(wrap(q1_all - q[0])).min() < 1e-9
        assert np.allclose(np.sort(q1_all), np.sort(shoulder(T)), atol=1e-12)
        rows = chk.reference_wrist_angles(T, q[0])
        assert np.allclose(rows, wrist(T, q[0]), atol=1e-12) and np.sin(rows[0, 0]) > 0
        elbows = chk.reference_arm_angles(T, q[0], q[4], q[5])
        assert np.allclose(elbows, arm(T, q[0], q[4], q[5]), atol=1e-12)
        assert np.abs(wrap(elbows - q[1:4])).max(axis=1).min() < 1e-8


def test_reference_steps_in_the_loop_give_robokins_solutions():
    from robokin.models.ur_ik import ur10_ik

    rng = np.random.default_rng(18)
    for q in rng.uniform(-np.pi, np.pi, (20, 6)):
        T = ROBOT.fk(q)
        rows = []
        for q1 in chk.reference_shoulder_angles(T):
            for q5, q6 in chk.reference_wrist_angles(T, q1):
                for q2, q3, q4 in chk.reference_arm_angles(T, q1, q5, q6):
                    x = np.array([q1, q2, q3, q4, q5, q6])
                    if np.abs(ROBOT.fk(x) - T).max() < 1e-9:
                        rows.append(x)
        assert solution_set(np.array(rows).reshape(-1, 6), ur10_ik(T).q, quiet=True).passed


def test_reference_steps_at_the_edges_of_their_steps():
    q = np.array([0.3, -1.2, 1.0, 0.4, 0.0, 0.2])  # q5 = 0: q6 undefined, robokin's choice
    assert np.allclose(chk.reference_wrist_angles(ROBOT.fk(q), q[0]), [[0.0, 0.0], [0.0, np.pi]])
    T_inside = ROBOT.fk(q)
    T_inside[:3, 3] = [0.05, -0.08, 0.6] + D6 * T_inside[:3, 2]  # wrist centre at 0.094 m < d4
    assert chk.reference_shoulder_angles(T_inside).shape == (0,)
    T_far = ROBOT.fk(q)
    T_far[:3, 3] *= 1e6
    assert chk.reference_arm_angles(T_far, 0.3, 0.9, 0.2).shape == (0, 3)


@pytest.mark.parametrize("call", [
    lambda: chk.reference_wrist_centre(np.eye(3)),
    lambda: chk.reference_shoulder_angles(2.0 * np.eye(4)),
    lambda: chk.reference_wrist_angles(np.eye(4), np.nan),
    lambda: chk.reference_arm_angles(np.eye(4), 0.1, "x", 0.2),
])
def test_reference_steps_reject_bad_input(call):
    with pytest.raises((ValueError, TypeError)):
        call()


def test_branch_and_step_messages_state_no_closed_form():
    """A dropped branch or a typical mistake is named with its principle, not with the closed
    form of the step (the tasks ask the student to derive them) nor the count of solutions."""
    messages = [
        chk.shoulder_angles(lambda T: shoulder(T, dropped=True), quiet=True).message,
        chk.shoulder_angles(lambda T: shoulder(T, d4=-D4), quiet=True).message,
        chk.wrist_angles(lambda T, q1: wrist(T, q1, dropped=True), quiet=True).message,
        chk.wrist_angles(lambda T, q1: wrist(T, q1, swap=True), quiet=True).message,
        chk.arm_angles(lambda T, q1, q5, q6: chk.reference_arm_angles(T, q1, q5, q6)[:1], quiet=True).message,
        chk.all_solutions(lambda T: chk._all(T)[::2], quiet=True).message,
    ]
    assert not any(message.startswith("✔") for message in messages)
    text = "\n".join(messages)
    for closed_form in ("arccos(d4/r)", "arccos(z6·z1)", "±arccos(c3)", "atan2(−y6", "has 8", "× 2"):
        assert closed_form not in text, closed_form


# ---------------------------------------------------------------- coinciding_branches
def _coinciding(wrist="sin", elbow="sin", shoulder=True, tol=1e-6):
    """A coinciding_branches: the three conditions, or a typical mistake in one of them."""
    def answer(q, wrist_centre=centre):
        names = []
        p5 = wrist_centre(ROBOT.fk(q))
        if shoulder and abs(math.hypot(p5[0], p5[1]) - abs(D4)) < tol:
            names.append("shoulder")
        if abs(math.sin(q[4]) if wrist == "sin" else q[4]) < tol:
            names.append("wrist")
        if abs(math.sin(q[2]) if elbow == "sin" else q[2]) < tol:
            names.append("elbow")
        return names
    return answer


def test_coinciding_branches_cases_are_the_arms_singularities():
    """Each case's steps are those whose two solutions coincide: det J vanishes exactly there
    (s3, s5 and the wrist centre's X in frame 1), and robokin's closed form flags a single one."""
    for q, expected in chk._coinciding_cases():
        p5 = ROBOT.frames(q)[6][:3, 3]
        holds = {"shoulder": abs(math.hypot(p5[0], p5[1]) - abs(D4)) < 1e-12,
                 "wrist": abs(math.sin(q[4])) < 1e-12, "elbow": abs(math.sin(q[2])) < 1e-12}
        assert {step for step, held in holds.items() if held} == expected
        assert (abs(np.linalg.det(ROBOT.jacobian(q))) < 1e-12) == bool(expected)
        if len(expected) == 1:
            assert set(ur10_ik(ROBOT.fk(q)).singular) == expected
    assert {frozenset(expected) for _, expected in chk._coinciding_cases()} >= {
        frozenset(), frozenset({"wrist"}), frozenset({"elbow", "wrist"}),
        frozenset({"shoulder", "wrist", "elbow"})}


def test_coinciding_branches_correct(capsys):
    assert chk.coinciding_branches(_coinciding()).passed
    assert "13 configurations" in capsys.readouterr().out


@pytest.mark.parametrize("answer, code", [
    (_coinciding(wrist="zero"), "wrist_partly"),
    (_coinciding(elbow="zero"), "elbow_partly"),
    (_coinciding(shoulder=False), "shoulder_missed"),
    (_coinciding(tol=1e-2), "wrist_extra"),
    (lambda q, wrist_centre=centre: "wrist", "type"),
    (lambda q, wrist_centre=centre: ["Wrist"], "unknown_name"),
    (None, "error"),
])
def test_coinciding_branches_mistakes(answer, code):
    result = chk.coinciding_branches(answer, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_coinciding_branches_is_given_robokins_wrist_centre():
    """A wrong wrist centre of the student's (the flange point) leaves the verdict on
    coinciding_branches alone: the check passes robokin's."""
    assert chk.coinciding_branches(lambda q, wrist_centre=lambda T: T[:3, 3]: _coinciding()(q, wrist_centre),
                                   quiet=True).passed
