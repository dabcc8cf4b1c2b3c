"""Tests of the chapter-4 exercise checks (robokin.check.cartesian).

Correct answers are written independently of the reference: the tool and goal
frames from explicit matrices in the course's YPR convention
(R = Rz(yaw) Ry(pitch) Rx(roll), the triple listed yaw first), the tool pose
from the course's link table multiplied out with plain numpy, the orientation
error from the quaternion (θ = 2 atan2(|ε|, η)), the tool Jacobian from the
cross-product formula v_T = v_E + ω × r, the control law from a least-norm
solve (lstsq) of J q̇ = ν, the kinematic loop as a while loop with a least-squares solve
and np.minimum/np.maximum for the clamp, E(φ) from its closed form.
"""

from __future__ import annotations

import importlib
from functools import partial

import numpy as np
import pytest

from robokin.models import genova_arm
from robokin.transforms import quaternion_from_rotation, rotation_log, rpy_from_rotation

cart = importlib.import_module("robokin.check.cartesian")
ROBOT = genova_arm()


def _tf(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def rotx(a):
    return np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])


def roty(a):
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def rotz(a):
    return np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])


C, S = np.cos(np.pi / 10), np.sin(np.pi / 10)
# YPR (0, 0, pi/10): a roll of pi/10 about x_E, written out
T_ET = np.array([[1, 0, 0, 0.2], [0, C, -S, 0], [0, S, C, 0], [0, 0, 0, 1.0]])
# YPR (-3.02, -0.40, -1.33): Rz(yaw) Ry(pitch) Rx(roll)
R_BG = rotz(-3.02) @ roty(-0.40) @ rotx(-1.33)
P_BG = [-0.14, -0.85, 0.6]

# the course's link table (R_i rows, p_i in m), joint 6 prismatic
TABLE = [
    (np.eye(3), [0, 0, 0.105]),
    ([[0, 1, 0], [0, 0, 1], [1, 0, 0]], [0, 0, 0.110]),
    ([[0, 0, 1], [0, -1, 0], [1, 0, 0]], [0.1, 0, 0]),
    ([[0, 0, 1], [0, -1, 0], [1, 0, 0]], [0, 0, 0.325]),
    ([[0, 0, 1], [-1, 0, 0], [0, -1, 0]], [0.095, 0, 0]),
    (np.diag([-1, -1, 1]), [0, 0, 0.095]),
    (np.eye(3), [0, 0, 0.355]),
]


def fk_table(q):
    T = np.eye(4)
    for i, (R, p) in enumerate(TABLE):
        M = _tf(R, p)
        J = _tf(np.eye(3), [0, 0, q[i]]) if i == 5 else _tf(rotz(q[i]), [0, 0, 0])
        T = T @ M @ J
    return T


def tool_pose(q):
    return fk_table(q) @ T_ET


def orientation_error_quat(R, R_goal):
    w, *vector = quaternion_from_rotation(R_goal @ R.T)
    v = np.array(vector)
    s = np.linalg.norm(v)
    return np.zeros(3) if s < 1e-15 else 2 * np.arctan2(s, w) * v / s


def tool_jacobian_point(J_e, R_be, p_et):
    # v_T = v_E + w x (R p): column by column
    r = R_be @ p_et
    return np.vstack([J_e[:3] + np.cross(J_e[3:].T, r).T, J_e[3:]])


def my_tool_jacobian(q, offset=(0.2, 0.0, 0.0)):
    # the tool's Jacobian of the exercise, column by column from the arm's J_E(q)
    return tool_jacobian_point(ROBOT.jacobian(q), fk_table(q)[:3, :3], np.asarray(offset, dtype=float))


def control_lstsq(J, e, gain_linear, gain_angular):
    return np.linalg.lstsq(J, np.r_[gain_linear * e[:3], gain_angular * e[3:]], rcond=None)[0]


STOP = 0.01  # the exercise's stop threshold (m/s, rad/s)


def loop_while(twist_of, q0, ts, t_end, robot, scale=1.0, no_ts=False, skip=False, stop=STOP,
               transpose=False, test_after=False, clamp=True):
    """The Task 4 loop written as a while loop with a least-squares solve; the keywords make
    the typical mistakes."""
    lower, upper = robot.limits[:, 0], robot.limits[:, 1]
    q = np.array(q0, dtype=float)
    Q, V, k = [q], [], 0
    while True:
        nu = np.asarray(twist_of(q))
        slow = np.linalg.norm(nu[:3]) < stop and np.linalg.norm(nu[3:]) < stop
        if not test_after:
            V.append(nu)
            if slow or k == round(t_end / ts):
                break
        elif k == round(t_end / ts):
            V.append(nu)
            break
        J = robot.jacobian(q)
        qdot = J.T @ nu if transpose else np.linalg.lstsq(J, nu, rcond=None)[0]
        new = q + (qdot if no_ts else scale * ts * qdot)
        q = np.where((new < lower) | (new > upper), q, new) if skip else np.minimum(np.maximum(new, lower), upper)
        q = q if clamp else new
        Q.append(q)
        k += 1
        if test_after:
            V.append(nu)
            if slow:
                V.append(np.asarray(twist_of(q)))
                break
    return np.array(Q), np.array(V)


def rpy_rates_by_hand(R):
    """E(phi) from its closed form: columns [c_y c_p, s_y c_p, -s_p], [-s_y, c_y, 0], [0, 0, 1]."""
    _, pitch, yaw = rpy_from_rotation(R)
    cp, sp, cy, sy = np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    return np.array([[cy * cp, -sy, 0.0], [sy * cp, cy, 0.0], [-sp, 0.0, 1.0]])


CORRECT = {
    "kinematic_loop": loop_while,
    "rpy_rate_matrix": rpy_rates_by_hand,
    "tool_frame": T_ET,
    "goal_frame": _tf(R_BG, P_BG),
    "tool_pose": tool_pose,
    "orientation_error": orientation_error_quat,
    "tool_jacobian": tool_jacobian_point,
    "tool_jacobian_of_q": my_tool_jacobian,
    "control_law": control_lstsq,
}


@pytest.mark.parametrize("name", sorted(CORRECT))
def test_correct_answers_pass(name):
    r = getattr(cart, name)(CORRECT[name], quiet=True)
    assert r.passed and r.diagnosis is None, r.message


def test_pass_prints_one_line(capsys):
    cart.orientation_error(orientation_error_quat)
    out = capsys.readouterr().out
    assert out == ("✔ orientation_error(R, R_goal) is correct (checked at 20 random pairs of\n"
                   "  rotations).\n")                               # wrapped at 80 columns


def wrap(d):
    return np.pi - np.mod(np.pi - d, 2 * np.pi)


WRONG = [
    ("tool_frame", _tf(T_ET[:3, :3], [0.002, 0, 0]), "offset_in_cm"),
    ("tool_frame", _tf(rotz(np.pi / 10), [0.2, 0, 0]), "rpy_order"),            # roll read as yaw
    ("tool_frame", _tf(rotz(np.pi / 10), [0.002, 0, 0]), "rpy_order"),
    ("tool_frame", _tf(rotx(np.radians(np.pi / 10)), [0.2, 0, 0]), "degrees_input"),
    ("tool_frame", np.linalg.inv(T_ET), "inverse"),
    ("tool_frame", _tf(T_ET[:3, :3].T, [0.2, 0, 0]), "rotation_block_transposed"),
    ("tool_frame", _tf(np.eye(3), [0.3, 0, 0]), "mismatch"),
    ("goal_frame", _tf(rotz(-1.33) @ roty(-0.40) @ rotx(-3.02), P_BG), "rpy_order"),   # roll read as yaw
    ("goal_frame", _tf(rotx(-1.33) @ roty(-0.40) @ rotz(-3.02), P_BG), "composition_order"),
    ("goal_frame", _tf(rotz(np.radians(-3.02)) @ roty(np.radians(-0.4)) @ rotx(np.radians(-1.33)), P_BG),
     "degrees_input"),
    ("goal_frame", np.linalg.inv(_tf(R_BG, P_BG)), "inverse"),
    ("goal_frame", _tf(R_BG.T, P_BG), "rotation_block_transposed"),
    ("tool_pose", lambda q: T_ET @ ROBOT.fk(q), "composition_order"),
    ("tool_pose", lambda q: ROBOT.fk(q), "no_tool"),
    ("tool_pose", lambda q: _tf(ROBOT.fk(q)[:3, :3] @ T_ET[:3, :3], ROBOT.fk(q)[:3, 3] + [0.2, 0, 0]),
     "offset_not_rotated"),
    ("tool_pose", lambda q: tool_pose(q)[:3, :3], "shape"),
    ("orientation_error", lambda R, Rg: rotation_log(R @ Rg.T), "sign"),
    ("orientation_error", lambda R, Rg: rotation_log(R.T @ Rg), "wrong_frame"),
    ("orientation_error", lambda R, Rg: np.degrees(rotation_log(Rg @ R.T)), "degrees_output"),
    ("orientation_error", lambda R, Rg: wrap(rpy_from_rotation(Rg) - rpy_from_rotation(R)), "rpy_difference"),
    ("orientation_error", lambda R, Rg: quaternion_from_rotation(Rg @ R.T)[1:], "quaternion"),
    ("tool_jacobian", lambda J, R, p: tool_jacobian_point(J, np.eye(3), p), "offset_not_rotated"),
    ("tool_jacobian", lambda J, R, p: tool_jacobian_point(J, -R, p), "cross_sign"),
    ("tool_jacobian", lambda J, R, p: J, "no_transport"),
    ("tool_jacobian", lambda J, R, p: np.vstack([J[:3], J[3:] - np.cross(R @ p, J[:3].T).T]), "twist_order"),
    ("tool_jacobian", lambda J, R, p: np.vstack([J[:3], J[3:] + np.cross(R @ p, J[:3].T).T]),
     "transposed_transport"),
    ("tool_jacobian_of_q", lambda q, p: tool_jacobian_point(ROBOT.jacobian(q), np.eye(3), p),
     "offset_not_rotated"),
    ("tool_jacobian_of_q", lambda q, p: tool_jacobian_point(ROBOT.jacobian(q), -fk_table(q)[:3, :3], p),
     "cross_sign"),
    ("tool_jacobian_of_q", lambda q, p: ROBOT.jacobian(q), "no_transport"),
    ("tool_jacobian_of_q", lambda q, p: my_tool_jacobian(q), "offset_ignored"),       # the sheet's tool
    ("tool_jacobian_of_q", lambda q, p: my_tool_jacobian(q, [0.002, 0, 0]), "offset_ignored"),  # in cm
    ("tool_jacobian_of_q", lambda q, p: my_tool_jacobian(q, p)[:, :6], "shape"),
    ("control_law", lambda J, e, kl, ka: -control_lstsq(J, e, kl, ka), "error_sign"),
    ("control_law", lambda J, e, kl, ka: control_lstsq(J, e, ka, kl), "swapped_gains"),
    ("control_law", lambda J, e, kl, ka: np.linalg.pinv(J) @ np.r_[ka * e[3:], kl * e[:3]], "twist_order"),
    ("control_law", lambda J, e, kl, ka: J.T @ np.r_[kl * e[:3], ka * e[3:]], "jacobian_transpose"),
    ("control_law", lambda J, e, kl, ka: control_lstsq(J, e, kl, ka)[:6], "shape"),
    ("kinematic_loop", partial(loop_while, test_after=True), "step_before_test"),
    ("kinematic_loop", partial(loop_while, scale=0.8), "gain_in_step"),
    ("kinematic_loop", partial(loop_while, no_ts=True), "no_time_step"),
    ("kinematic_loop", partial(loop_while, skip=True), "skip_rule"),
    ("kinematic_loop", partial(loop_while, stop=0.8 * STOP), "stop_on_error"),
    ("kinematic_loop", partial(loop_while, transpose=True), "jacobian_transpose"),
    ("kinematic_loop", partial(loop_while, clamp=False), "no_clamp"),
    ("kinematic_loop", lambda *a: loop_while(*a)[0], "error"),                   # Q alone
    ("rpy_rate_matrix", lambda R: rpy_rates_by_hand(R)[:, ::-1], "columns_reversed"),
    ("rpy_rate_matrix", lambda R: np.column_stack([rotz(rpy_from_rotation(R)[2])[:, 0], rpy_rates_by_hand(R)[:, 1:]]),
     "roll_axis_without_pitch"),
    ("rpy_rate_matrix", lambda R: rpy_rates_by_hand(R).T, "transpose"),
    ("rpy_rate_matrix", lambda R: R.T @ rpy_rates_by_hand(R), "moving_frame"),
    ("rpy_rate_matrix", lambda R: np.eye(3), "mismatch"),                             # the naive loop's E
]


@pytest.mark.parametrize("name, answer, code", WRONG, ids=[f"{n}-{c}" for n, _, c in WRONG])
def test_mistakes_are_diagnosed(name, answer, code):
    r = getattr(cart, name)(answer, quiet=True)
    assert not r.passed
    assert r.diagnosis == code, r.message
    assert r.message.startswith("✘")


def test_non_function_answer_is_explained():
    r = cart.orientation_error(np.zeros(3), quiet=True)
    assert not r.passed and r.diagnosis == "constant" and "Python function" in r.message


def test_student_exception_is_reported():
    r = cart.control_law(lambda J, e, kl, ka: np.linalg.inv(J) @ e, quiet=True)
    assert not r.passed and r.diagnosis == "error" and "LinAlgError" in r.message


def test_raise_on_fail():
    with pytest.raises(AssertionError, match="wrong sign"):
        cart.orientation_error(lambda R, Rg: -orientation_error_quat(R, Rg), raise_on_fail=True, quiet=True)


def test_registered():
    from robokin.check._registry import _REGISTRY

    assert set(_REGISTRY["cartesian"]) == set(CORRECT)


def test_course_convention_is_the_reference():
    """The course's YPR reading passes; the same numbers read as (roll, pitch, yaw) do not."""
    from robokin.transforms import rotation_from_rpy

    yaw, pitch, roll = cart._TOOL_YPR
    assert cart.tool_frame(_tf(rotation_from_rpy(roll, pitch, yaw), cart._TOOL_OFFSET), quiet=True).passed
    assert np.allclose(rotation_from_rpy(*cart._TOOL_YPR[::-1]), rotx(np.pi / 10))
    assert not {"TOOL_YPR", "TOOL_RPY", "GOAL_YPR", "GOAL_RPY"} & set(dir(cart))
    yaw, pitch, roll = cart._GOAL_YPR
    assert cart.goal_frame(_tf(rotation_from_rpy(roll, pitch, yaw), cart._GOAL_POSITION), quiet=True).passed
    swapped = cart.goal_frame(_tf(rotation_from_rpy(*cart._GOAL_YPR), cart._GOAL_POSITION), quiet=True)
    assert not swapped.passed and swapped.diagnosis == "rpy_order"
    assert "(yaw, pitch, roll)" in swapped.message


def test_checks_use_the_course_arm():
    """tool_pose samples the course's arm within its limits, the slide q6 in metres."""
    X = cart.tool_pose.sample_points()
    assert X.shape == (20, 7)
    assert ((X[:, 5] > 0.0) & (X[:, 5] < 1.0)).all()
    assert ROBOT.within_limits(X).all()


def test_reference_steps_pass_their_checks_and_agree_with_the_sheet():
    """The later tests' stand-ins: the orientation error passes its check and agrees with the
    quaternion form; the tool arm carries the sheet's tool (its fk is the table's pose times
    E T_T); the goal is the sheet's."""
    assert cart.orientation_error(cart.reference_orientation_error, quiet=True).passed
    rng = np.random.default_rng(5)
    for _ in range(5):
        R, R_goal = (rotation_from_rpy_local(*rng.uniform(-3, 3, 3)) for _ in range(2))
        assert np.allclose(cart.reference_orientation_error(R, R_goal), orientation_error_quat(R, R_goal),
                           atol=1e-9)
    tool_arm = cart.reference_tool_arm()
    assert np.allclose(tool_arm.tool, T_ET, atol=1e-12)
    for q in ROBOT.random_configurations(5, seed=3):
        assert np.allclose(tool_arm.fk(q), fk_table(q) @ T_ET, atol=1e-12)
    assert np.allclose(cart.reference_goal(), _tf(R_BG, P_BG), atol=1e-12)
    assert cart.tool_frame(tool_arm.tool, quiet=True).passed and cart.goal_frame(cart.reference_goal(),
                                                                                   quiet=True).passed


def test_reference_rpy_difference_is_robokins_rpy_error():
    """The stand-in for rpy_difference: robokin's RPY error (pose_error with the "rpy"
    representation), each difference in (-pi, pi], zero between equal rotations."""
    from robokin.motion import pose_error

    rng = np.random.default_rng(8)
    for _ in range(10):
        R, R_goal = (rotation_from_rpy_local(*rng.uniform([-3, -1.4, -3], [3, 1.4, 3])) for _ in range(2))
        difference = cart.reference_rpy_difference(R, R_goal)
        assert np.all(difference > -np.pi) and np.all(difference <= np.pi)
        expected = pose_error(_tf(R, np.zeros(3)), _tf(R_goal, np.zeros(3)), representation="rpy")[3:]
        assert np.allclose(difference, expected, atol=1e-12)
        assert np.allclose(cart.reference_rpy_difference(R, R), 0.0, atol=1e-12)
    with pytest.raises(ValueError):
        cart.reference_rpy_difference(np.eye(3), np.eye(4))


def rotation_from_rpy_local(roll, pitch, yaw):
    return rotz(yaw) @ roty(pitch) @ rotx(roll)


@pytest.mark.parametrize("call", [
    lambda: cart.reference_orientation_error(np.eye(3), np.eye(4)),
    lambda: cart.reference_orientation_error(np.eye(2), np.eye(3)),
])
def test_reference_orientation_error_rejects_what_is_not_two_rotations(call):
    with pytest.raises(ValueError):
        call()


@pytest.mark.parametrize("name, answer", [
    ("tool_frame", np.zeros((4, 4))),
    ("tool_frame", np.eye(4)),
    ("tool_frame", _tf(-T_ET[:3, :3], [0.2, 0, 0])),
    ("tool_frame", _tf(T_ET[:3, :3], [20.0, 0, 0])),
    ("goal_frame", np.zeros((4, 4))),
    ("goal_frame", _tf(np.eye(3), P_BG)),
    ("goal_frame", _tf(R_BG, [0.0, 0.0, 0.0])),
])
def test_wrong_constants_name_entries_not_their_values(name, answer):
    """T_ET and T_BG are the answers themselves (one input): a wrong attempt learns which entries
    differ and the principle, not what they should be, nor the rotation they hold."""
    r = getattr(cart, name)(answer, quiet=True)
    assert r.diagnosis == "mismatch" and "differ" in r.message, r.message
    for give_away in ("should be", "yours is", "Rx(π/10)", "0.2, 0, 0", "0.951", "−3.02", "-0.914",
                      "rotation_from_rpy(π/10", "rotation_from_rpy(−1.33"):
        assert give_away not in r.message, r.message


@pytest.mark.parametrize("name, answer", [w[:2] for w in WRONG if w[0] not in ("kinematic_loop",)])
def test_messages_state_no_closed_form(name, answer):
    """No diagnosis or hint writes the answer's closed form: the tool's rotation, the log of the
    error, the transport matrix, the first column of E(phi)."""
    message = getattr(cart, name)(answer, quiet=True).message
    for closed_form in ("Rx(π/10)", "log(R_goal Rᵀ)", "[[I, −[r×]], [0, I]]", "−[r×] ω",
                        "Rz(ψ) Ry(ϑ) x", "ᴮT_T = ᴮT_E ᴱT_T", "ᴮR_E ₑr_ET", "Rz(−3.02) Ry(−0.40)"):
        assert closed_form not in message, message
