"""Tests of the chapter-8 exercise checks (robokin.check.product_of_exponentials).

The correct answers come from the Modern Robotics library (``MatrixExp3``, ``MatrixExp6``,
``FKinSpace``, ``Adjoint``, ``JacobianSpace``, ``JacobianBody``), not from robokin, and the
UR10's screw axes are written out from its DH table; each typical mistake is written by
hand and must be named by its diagnosis.
"""

from __future__ import annotations

import importlib
from functools import partial

import numpy as np
import pytest

mr = pytest.importorskip("modern_robotics", reason="modern_robotics (requirements.txt) gives the answers")
chk = importlib.import_module("robokin.check.product_of_exponentials")

# The UR10 (CB3) at home, from its DH table (d1 = 0.1273, a2 = -0.612, a3 = -0.5723,
# d4 = 0.163941, d5 = 0.1157, d6 = 0.0922 m): axes and points in the base frame.
_D1, _A2, _A3, _D4, _D5, _D6 = 0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922
AXES = np.array([[0, 0, 1], [0, -1, 0], [0, -1, 0], [0, -1, 0], [0, 0, -1], [0, -1, 0]], dtype=float)
POINTS = np.array([
    [0, 0, 0], [0, 0, _D1], [_A2, 0, _D1], [_A2 + _A3, 0, _D1],
    [_A2 + _A3, -_D4, _D1], [_A2 + _A3, -_D4, _D1 - _D5],
])
S_UR10 = np.hstack([AXES, -np.cross(AXES, POINTS)])
M_UR10 = np.array([[1, 0, 0, _A2 + _A3], [0, 0, -1, -_D4 - _D6], [0, 1, 0, _D1 - _D5], [0, 0, 0, 1]])


def skew(w):
    return mr.VecToso3(np.asarray(w, dtype=float))


def rodrigues(omega, theta):
    return mr.MatrixExp3(skew(omega) * theta)


def screw_axis(omega, point):
    return np.r_[omega, np.cross(point, omega)]


def screw_axes_at_home(frames, joint_axes, offset=1, axis=lambda R, p, a: R @ a, sign=1.0, order=(0, 1)):
    """Rows [ω; p × ω] for ω = R a; the keywords make the typical mistakes."""
    rows = []
    for F, a in zip(frames[offset:], joint_axes):
        omega = axis(F[:3, :3], F[:3, 3], np.asarray(a, dtype=float))
        parts = (omega, sign * np.cross(F[:3, 3], omega))
        rows.append(np.r_[parts[order[0]], parts[order[1]]])
    return np.array(rows)


def exp6(S, theta):
    return mr.MatrixExp6(mr.VecTose3(np.asarray(S, dtype=float) * theta))


def poe_fk(M, S_list, theta):
    return mr.FKinSpace(M, np.asarray(S_list).T, theta)


def adjoint_matrix(T):
    return mr.Adjoint(T)


def jacobian_in_space(S_list, theta):
    return mr.JacobianSpace(np.asarray(S_list).T, theta)


def geometric_from_space(J_s, T):
    p = T[:3, 3]
    return np.vstack([J_s[3:] + np.cross(J_s[:3].T, p).T, J_s[:3]])


def jacobian_in_body(M, S_list, theta):
    B = mr.Adjoint(mr.TransInv(M)) @ np.asarray(S_list).T
    return mr.JacobianBody(B, theta)


def ik_body(M, S_list, T_goal, theta_start):
    B = mr.Adjoint(mr.TransInv(M)) @ np.asarray(S_list).T
    theta, success = mr.IKinBody(B, M, T_goal, np.asarray(theta_start, dtype=float), 1e-12, 1e-12)
    return theta, 5


CORRECT = [
    (chk.rodrigues, rodrigues), (chk.screw_axis, screw_axis), (chk.screw_list, screw_axes_at_home),
    (chk.exp6, exp6), (chk.forward_kinematics, poe_fk), (chk.adjoint, adjoint_matrix),
    (chk.space_jacobian, jacobian_in_space), (chk.geometric_from_space, geometric_from_space),
    (chk.body_jacobian, jacobian_in_body), (chk.ik_body, ik_body),
]


@pytest.mark.parametrize(("check", "answer"), CORRECT, ids=[c.name for c, _ in CORRECT])
def test_correct_answers_pass(check, answer):
    result = check(answer, quiet=True)
    assert result.passed and result.diagnosis is None, result.message


def test_a_later_step_is_judged_on_robokins_earlier_steps():
    """A step that takes earlier ones as keyword arguments (the student's own by default) is
    checked with robokin's in their place: a wrong earlier step is not blamed on it (the grading
    report asks these checks about the bare answers)."""
    def transposed_skew(w):  # a wrong [w]: its transpose
        return skew(w).T

    def adjoint_with(T, skew=transposed_skew):
        R, p = T[:3, :3], T[:3, 3]
        return np.block([[R, np.zeros((3, 3))], [skew(p) @ R, R]])

    def exp6_with(S, theta, rodrigues=rodrigues, skew=transposed_skew):
        w, v = np.asarray(S[:3], dtype=float), np.asarray(S[3:], dtype=float)
        W = skew(w)
        G = np.eye(3) * theta + (1 - np.cos(theta)) * W + (theta - np.sin(theta)) * W @ W
        return np.block([[rodrigues(w, theta), (G @ v)[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]])

    def space_with(S_list, theta, exp6=exp6_with, adjoint_matrix=adjoint_with):
        columns, T = [], np.eye(4)
        for S, angle in zip(S_list, theta):
            columns.append(adjoint_matrix(T) @ S)
            T = T @ exp6(S, angle)
        return np.column_stack(columns)

    for check, answer in [(chk.adjoint, adjoint_with), (chk.exp6, exp6_with),
                          (chk.space_jacobian, space_with)]:
        assert check(answer, quiet=True).passed
        # called without its keyword parameters, it runs on the wrong steps it holds
        assert not check(lambda *arguments, f=answer: f(*arguments), quiet=True).passed


def test_screw_axes_at_home_is_judged_on_robokins_screw_axis():
    """A wrong screw_axis does not make a right screw_axes_at_home that takes it as an
    argument wrong (Task 2's two tests); without the argument, it runs on the wrong step."""
    def flipped(omega, point):
        return np.r_[omega, np.cross(omega, point)]

    def at_home(frames, joint_axes, screw_axis=flipped):
        return np.array([screw_axis(F[:3, :3] @ a, F[:3, 3]) for F, a in zip(frames[1:], joint_axes)])

    assert chk.screw_list(at_home, quiet=True).passed
    result = chk.screw_list(lambda frames, axes: at_home(frames, axes), quiet=True)
    assert result.diagnosis == "cross_sign", result.message
    assert np.allclose(chk.reference_screw_axis([0.0, 0.0, 1.0], [1.0, 0.0, 0.0]), [0, 0, 1, 0, -1, 0])


def test_ur10_data_written_out_match_the_model():
    from robokin.models import ur10

    M, S = ur10().screw_axes()
    assert np.allclose(S, S_UR10, atol=1e-12) and np.allclose(M, M_UR10, atol=1e-12)


def test_pass_message(capsys):
    chk.exp6(exp6)
    assert capsys.readouterr().out == "✔ exp6(S, theta) is correct (checked at 20 random screw axes and angles).\n"


# ---------------------------------------------------------------- diagnosed mistakes
def _swap(a):
    return np.concatenate([a[3:], a[:3]], axis=0)


def _exp_without_g(S, theta):
    T = exp6(S, theta)
    T[:3, 3] = np.asarray(S[3:]) * theta
    return T


def _fk_m_left(M, S_list, theta):
    return M @ poe_fk(np.eye(4), S_list, theta)


def _space_reversed(S_list, theta):
    columns, P = [], np.eye(4)
    for S, angle in zip(S_list, theta):
        columns.append(mr.Adjoint(P) @ S)
        P = exp6(S, angle) @ P
    return np.column_stack(columns)


def _space_inverse(S_list, theta):
    columns, P = [], np.eye(4)
    for S, angle in zip(S_list, theta):
        columns.append(mr.Adjoint(mr.TransInv(P)) @ S)
        P = P @ exp6(S, angle)
    return np.column_stack(columns)


def test_screw_axes_at_home_gives_the_ur10s_from_its_dh_table():
    from robokin.models import ur10

    robot = ur10()
    assert np.allclose(screw_axes_at_home(robot.frames(np.zeros(6)), robot.joint_axes), S_UR10, atol=1e-12)


WRONG = [
    (chk.rodrigues, lambda w, t: rodrigues(w, -t), "transpose"),
    (chk.rodrigues, lambda w, t: np.eye(3) + np.sin(t) * skew(w) + (1 - np.cos(t)) * skew(w), "missing_square"),
    (chk.rodrigues, lambda w, t: np.eye(3) + (1 - np.cos(t)) * skew(w) + np.sin(t) * skew(w) @ skew(w),
     "sin_cos_swapped"),
    (chk.rodrigues, lambda w, t: rodrigues(w, np.deg2rad(t)), "degrees_input"),
    (chk.screw_axis, lambda w, q: np.r_[w, np.cross(w, q)], "cross_sign"),
    (chk.screw_axis, lambda w, q: _swap(screw_axis(w, q)), "twist_order"),
    (chk.screw_axis, lambda w, q: np.r_[np.cross(w, q), w], "twist_order"),
    (chk.screw_axis, lambda w, q: np.r_[w, q], "point_for_velocity"),
    (chk.screw_axis, lambda w, q: -screw_axis(w, q), "axis_sign"),
    (chk.screw_axis, lambda w, q: np.r_[-np.asarray(w), np.cross(q, w)], "axis_sign"),
    (chk.screw_list, partial(screw_axes_at_home, sign=-1.0), "cross_sign"),
    (chk.screw_list, partial(screw_axes_at_home, order=(1, 0)), "twist_order"),
    (chk.screw_list, partial(screw_axes_at_home, offset=0), "frame_before"),
    (chk.screw_list, partial(screw_axes_at_home, axis=lambda R, p, a: a), "axis_not_turned"),
    (chk.screw_list, partial(screw_axes_at_home, axis=lambda R, p, a: R.T @ a), "axis_not_turned"),
    (chk.screw_list, partial(screw_axes_at_home, axis=lambda R, p, a: R[:, 2]), "axis_not_turned"),
    (chk.screw_list, partial(screw_axes_at_home, axis=lambda R, p, a: R @ a + p), "axis_not_turned"),
    (chk.exp6, _exp_without_g, "missing_G"),
    (chk.exp6, lambda S, t: exp6(_swap(np.asarray(S)), t), "twist_order"),
    (chk.exp6, lambda S, t: exp6(S, np.deg2rad(t)), "degrees_input"),
    (chk.forward_kinematics, lambda M, S, t: poe_fk(M, S[::-1], t[::-1]), "product_order"),
    (chk.forward_kinematics, _fk_m_left, "M_on_left"),
    (chk.forward_kinematics, lambda M, S, t: poe_fk(np.eye(4), S, t), "M_on_left"),
    (chk.forward_kinematics,
     lambda M, S, t: np.linalg.multi_dot([_exp_without_g(s, a) for s, a in zip(S, t)] + [M]), "missing_G"),
    (chk.adjoint, lambda T: mr.Adjoint(mr.TransInv(T)), "inverse_transform"),
    (chk.adjoint, lambda T: np.block([[T[:3, :3], skew(T[:3, 3]) @ T[:3, :3]], [np.zeros((3, 3)), T[:3, :3]]]),
     "twist_order"),
    (chk.adjoint, lambda T: np.block([[T[:3, :3], np.zeros((3, 3))], [T[:3, :3] @ skew(T[:3, 3]), T[:3, :3]]]),
     "product_order"),
    (chk.space_jacobian, lambda S, t: _swap(jacobian_in_space(S, t)), "twist_order"),
    (chk.space_jacobian, _space_reversed, "product_order"),
    (chk.space_jacobian, _space_inverse, "adjoint_of_inverse"),
    (chk.space_jacobian, lambda S, t: np.asarray(S).T, "home_axes"),
    (chk.geometric_from_space, lambda J, T: _swap(J), "rows_swapped_only"),
    (chk.geometric_from_space, lambda J, T: np.vstack([J[3:] - np.cross(J[:3].T, T[:3, 3]).T, J[:3]]), "cross_sign"),
    (chk.body_jacobian, lambda M, S, t: mr.Adjoint(poe_fk(M, S, t)) @ jacobian_in_space(S, t), "adjoint_of_T"),
    (chk.body_jacobian, lambda M, S, t: mr.Adjoint(mr.TransInv(M)) @ jacobian_in_space(S, t), "home_pose"),
    (chk.body_jacobian, lambda M, S, t: jacobian_in_space(S, t), "space_jacobian"),
    (chk.body_jacobian, lambda M, S, t: _swap(jacobian_in_body(M, S, t)), "twist_order"),
]


@pytest.mark.parametrize(("check", "answer", "code"), WRONG,
                         ids=[f"{c.name.split('(')[0]}-{code}-{i}" for i, (c, _, code) in enumerate(WRONG)])
def test_mistakes_are_diagnosed(check, answer, code):
    result = check(answer, quiet=True)
    assert not result.passed
    assert result.diagnosis == code, result.message


def test_ik_answer_forms():
    """(theta, iterations) as a tuple, as the list a handed-over tuple becomes, or theta alone."""
    assert chk.ik_body(lambda *a: list(ik_body(*a)), quiet=True).passed
    assert chk.ik_body(lambda *a: ik_body(*a)[0], quiet=True).passed


def test_ik_mistakes():
    result = chk.ik_body(lambda M, S, T, t: (np.asarray(t), 0), quiet=True)
    assert not result.passed and result.diagnosis == "not_updated"
    result = chk.ik_body(lambda M, S, T, t: (ik_body(M, S, T, t)[0] + 0.1, 5), quiet=True)
    assert not result.passed and result.diagnosis == "mismatch"
    assert "the body twist that carries the flange from T(θ) to T_goal" in result.message


def _ik_written(twist="body", jacobian="body", sign=1.0):
    """Lynch and Park's loop with a typical mistake: the twist or the Jacobian in the wrong frame,
    or the step's sign."""
    def ik(M, S_list, T_goal, theta_start, tolerance=1e-10, max_iterations=30):
        theta = np.array(theta_start, dtype=float)
        for iteration in range(max_iterations + 1):
            T = poe_fk(M, S_list, theta)
            V_b = mr.se3ToVec(mr.MatrixLog6(mr.TransInv(T) @ T_goal))
            if max(np.linalg.norm(V_b[:3]), np.linalg.norm(V_b[3:])) < tolerance or iteration == max_iterations:
                return theta, iteration
            V = mr.se3ToVec(mr.MatrixLog6(T_goal @ mr.TransInv(T))) if twist == "space" else V_b
            J = jacobian_in_space(S_list, theta) if jacobian == "space" else jacobian_in_body(M, S_list, theta)
            theta = theta + sign * np.linalg.pinv(J) @ V
        return theta, max_iterations
    return ik


@pytest.mark.parametrize(("mistake", "code"), [
    ({"twist": "space"}, "twist_in_space"), ({"jacobian": "space"}, "jacobian_in_space"),
    ({"sign": -1.0}, "step_sign"),
])
def test_ik_step_mistakes_are_named_by_the_first_step(mistake, code):
    """A loop whose twist and Jacobian are in different frames wanders far off: its pose after 30
    steps cannot be rebuilt, its first step can. The message names the frames, not the formula."""
    assert chk.ik_body(_ik_written(), quiet=True).passed
    result = chk.ik_body(_ik_written(**mistake), quiet=True)
    assert not result.passed and result.diagnosis == code, result.message
    assert "same frame" in result.message or "away from the goal" in result.message
    assert "log" not in result.message and "T⁻¹" not in result.message


def test_ik_without_max_iterations_is_not_diagnosed_by_a_step():
    """An answer that cannot be asked for one step keeps the generic verdict."""
    def ik(M, S_list, T_goal, theta_start):
        return _ik_written(twist="space")(M, S_list, T_goal, theta_start)

    assert chk.ik_body(ik, quiet=True).diagnosis == "mismatch"


def test_screw_sign_message_states_no_formula():
    result = chk.screw_axis(lambda w, q: np.r_[w, np.cross(w, q)], quiet=True)
    assert result.diagnosis == "cross_sign" and "= −ω" not in result.message and "−q" in result.message


def test_unknown_mistake_is_a_mismatch():
    result = chk.exp6(lambda S, t: exp6(S, t) + np.diag([0, 0, 0.01, 0]), quiet=True)
    assert not result.passed and result.diagnosis == "mismatch" and "entry (3, 3)" in result.message


def test_bad_answers():
    assert chk.exp6(None, quiet=True).diagnosis == "error"
    assert chk.exp6(np.eye(4), quiet=True).diagnosis == "constant"
    assert chk.screw_list(lambda frames, axes: screw_axes_at_home(frames, axes).T, quiet=True).diagnosis == "shape"
    assert chk.screw_list(S_UR10, quiet=True).diagnosis == "constant"
    result = chk.forward_kinematics(lambda M, S, t: 1 / 0, quiet=True)
    assert result.diagnosis == "error" and "ZeroDivisionError" in result.message


def test_delegation_table_names_registered_checks():
    assert set(chk.DELEGATION) <= set(chk.__all__)


# ---------------------------------------------------------------- robokin's steps, for the tests
REFERENCE_STEPS = [
    (chk.rodrigues, chk.reference_rodrigues),
    (chk.screw_axis, chk.reference_screw_axis),
    (chk.exp6, chk.reference_exp6),
    (chk.forward_kinematics, chk.reference_poe_fk),
    (chk.adjoint, chk.reference_adjoint_matrix),
    (chk.space_jacobian, chk.reference_jacobian_in_space),
    (chk.body_jacobian, chk.reference_jacobian_in_body),
]


@pytest.mark.parametrize("check, reference", REFERENCE_STEPS, ids=[r.__name__ for _, r in REFERENCE_STEPS])
def test_reference_steps_pass_their_checks(check, reference):
    assert check(reference, quiet=True).passed


def test_reference_steps_agree_with_modern_robotics_on_seven_joints():
    rng = np.random.default_rng(8)
    S = np.vstack([S_UR10, S_UR10[2]])  # a seventh joint, on joint 3's axis
    for theta in rng.uniform(-np.pi, np.pi, (5, 7)):
        assert np.allclose(chk.reference_poe_fk(M_UR10, S, theta), mr.FKinSpace(M_UR10, S.T, theta), atol=1e-12)
        assert np.allclose(chk.reference_jacobian_in_space(S, theta), mr.JacobianSpace(S.T, theta), atol=1e-12)
        B = mr.Adjoint(mr.TransInv(M_UR10)) @ S.T
        assert np.allclose(chk.reference_jacobian_in_body(M_UR10, S, theta), mr.JacobianBody(B, theta), atol=1e-12)
    omega, V = np.array([0.0, 0.6, 0.8]), np.array([0.0, 0.6, 0.8, 0.3, -0.2, 0.1])
    assert np.allclose(chk.reference_rodrigues(omega, 0.7), mr.MatrixExp3(mr.VecToso3(omega) * 0.7), atol=1e-14)
    assert np.allclose(chk.reference_exp6(V, 0.7), mr.MatrixExp6(mr.VecTose3(V) * 0.7), atol=1e-14)
    T = mr.MatrixExp6(mr.VecTose3(V))
    assert np.allclose(chk.reference_adjoint_matrix(T), mr.Adjoint(T), atol=1e-14)
    assert np.allclose(chk.reference_skew(V[3:]), mr.VecToso3(V[3:]), atol=0)


@pytest.mark.parametrize("call", [
    lambda: chk.reference_skew([0.0, 1.0]),
    lambda: chk.reference_rodrigues([0.0, 1.0], 0.3),
    lambda: chk.reference_screw_axis([0.0, 0.0, 1.0], [0.0, np.nan, 0.0]),
    lambda: chk.reference_exp6(np.zeros(6), np.nan),
    lambda: chk.reference_poe_fk(np.eye(4), S_UR10, np.zeros(5)),
    lambda: chk.reference_adjoint_matrix(np.eye(3)),
    lambda: chk.reference_jacobian_in_space(S_UR10[:, :5], np.zeros(6)),
    lambda: chk.reference_jacobian_in_body(np.eye(4), S_UR10, "theta"),
])
def test_reference_steps_reject_bad_input(call):
    with pytest.raises((TypeError, ValueError)):   # TypeError: not numbers; ValueError: shape, NaN
        call()
