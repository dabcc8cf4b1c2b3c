"""Tests of the chapter-1 exercise checks (robokin.check.leg).

The correct answers below are written out independently of robokin (sympy and
NumPy formulas re-derived by hand), so they also test the model's references.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from robokin import check
from robokin.check import leg as L

a, b, g = sp.symbols("alpha beta gamma", real=True)
S = sp.sin
C = sp.cos


def Rx(t):
    return sp.Matrix([[1, 0, 0], [0, C(t), -S(t)], [0, S(t), C(t)]])


def Ry(t):
    return sp.Matrix([[C(t), 0, S(t)], [0, 1, 0], [-S(t), 0, C(t)]])


def Rz(t):
    return sp.Matrix([[C(t), -S(t), 0], [S(t), C(t), 0], [0, 0, 1]])


def H(R, p):
    M = sp.eye(4)
    M[:3, :3] = R
    M[:3, 3] = sp.Matrix(p)
    return M


H_B1 = H(Rx(a), [0, 1, 0])
H_12 = H(Ry(b), [0, 0, -1])
H_23 = H(Ry(g), [0, 0, -1])
H_3F = H(sp.eye(3), [0, 0, -1])
H_BF = H_B1 * H_12 * H_23 * H_3F
LEN = 1 + C(b) + C(b + g)
R_BF = sp.Matrix([-S(b) - S(b + g), S(a) * LEN + 1, -C(a) * LEN])  # re-derived by hand
#: H_BF in its short form (the two pitch rotations add up), written by hand, checked below: no
#: ``simplify`` at import, which every pytest worker would pay for
H_BF_SHORT = H(Rx(a) * Ry(b + g), R_BF)
J = R_BF.jacobian([a, b, g])


def r_np(q):
    al, be, ga = q
    ln = 1 + np.cos(be) + np.cos(be + ga)
    return np.array([-np.sin(be) - np.sin(be + ga), np.sin(al) * ln + 1, -np.cos(al) * ln])


_J_FUNCTION = sp.lambdify([(a, b, g)], J, "numpy")


def J_np(q):
    return np.array(_J_FUNCTION(np.asarray(q, dtype=float)), dtype=float)


Q_LIFT = np.deg2rad([0, 60, -120])


# ---------------------------------------------------------------- registry
def test_registry_lists_every_check_of_the_chapter():
    names = set(check.checks_of("leg"))
    assert names == {
        "rotation_B1", "rotation_12", "rotation_23", "transform_B1", "transform_12",
        "transform_23", "transform_3F", "transform_BF", "foot_position", "foot_jacobian",
        "foot_jacobian_at", "lift_velocity", "joint_velocity", "newton_step", "tracking_controller",
        "newton_ik", "tracking_loop", "ik_closed_form",
    }
    assert check.leg is L and "leg" in dir(check)


def test_hand_derived_position_matches_the_model():
    from robokin.models import eth_leg

    leg = eth_leg()
    for q in np.random.default_rng(1).uniform(-3, 3, (5, 3)):
        assert np.allclose(leg.fk(q)[:3, 3], r_np(q))
    assert sp.simplify(H_BF[:3, 3] - R_BF) == sp.zeros(3, 1)
    assert (H_BF - H_BF_SHORT).applyfunc(lambda e: sp.expand(sp.expand_trig(e))) == sp.zeros(4, 4)


# ---------------------------------------------------------------- correct answers, every form
@pytest.mark.parametrize(
    "chk, answers",
    [
        (L.rotation_B1, [Rx(a), Rx(sp.Symbol("q1")), lambda alpha: np.array(Rx(alpha).evalf(), float)]),
        (L.rotation_12, [Ry(b), Ry(sp.Symbol("beta"))]),
        (L.rotation_23, [Ry(g), lambda gamma: np.array(Ry(gamma).evalf(), float)]),
        (L.transform_B1, [H_B1]),
        (L.transform_12, [H_12]),
        (L.transform_23, [H_23]),
        (L.transform_3F, [H_3F, np.array(H_3F, dtype=float), lambda: np.array(H_3F, float)]),
        (L.transform_BF, [H_BF, H_BF_SHORT]),
        (L.foot_position, [R_BF, R_BF.T, r_np, lambda al, be, ga: r_np([al, be, ga]),
                           (H_BF * sp.Matrix([0, 0, 0, 1]))[:3, :]]),
        (L.foot_jacobian, [J, J_np]),
        (L.foot_jacobian_at, [J_np(Q_LIFT), np.round(J_np(Q_LIFT), 4), J]),
        (L.lift_velocity, [[0, -0.5774, 1.1547], np.linalg.solve(J_np(Q_LIFT), [0, 0, -1])]),
    ],
)
def test_correct_answers_pass(chk, answers):
    for ans in answers:
        r = chk(ans, quiet=True)
        assert r.passed, r.message
        assert r.message.startswith("✔ ") and r.message.count("\n") == 0


def test_pass_message_wording(capsys):
    L.rotation_B1(Rx(a))
    assert capsys.readouterr().out == "✔ R_B1 is correct (checked at 20 random angles).\n"
    L.foot_jacobian_at(J_np(Q_LIFT))
    assert capsys.readouterr().out == "✔ J_lift at q = [0°, 60°, −120°] is correct.\n"


# ---------------------------------------------------------------- diagnoses specific to the leg
@pytest.mark.parametrize(
    "chk, answer, code, text",
    [
        (L.rotation_B1, Ry(a), "wrong_axis", "rotates about the y axis, but α turns about the x axis"),
        (L.rotation_B1, Rz(-a), "wrong_axis", "z axis (and in the opposite direction)"),
        (L.rotation_12, Rx(b), "wrong_axis", "β turns about the y axis"),
        (L.rotation_12, Ry(b).T, "transpose", "R_12 is transposed"),
        (L.rotation_23, Ry(g * sp.pi / 180), "degrees_input", "treats its angles as degrees"),
        (L.transform_B1, H(Rx(a), Rx(a) * sp.Matrix([0, 1, 0])), "translation_rotated", "R·p"),
        (L.transform_B1, H(Ry(a), [0, 1, 0]), "wrong_axis", "about the y axis"),
        (L.transform_12, H_12.inv(), "inverse", "H_12 is inverted"),
        (L.transform_23, H(Ry(g), [0, 0, 1]), "translation_sign", "wrong sign"),
        (L.transform_3F, H(sp.eye(3), [0, 0, 1]), "inverse", "H_3F is inverted"),
        (L.transform_3F, sp.Matrix([0, 0, -1]), "shape", "should be a 4×4 matrix"),
        (L.transform_BF, H_3F * H_23 * H_12 * H_B1, "composition_order", "H_3F·H_23·H_12·H_B1"),
        (L.transform_BF, H_12 * H_B1 * H_23 * H_3F, "composition_order", "H_12·H_B1·H_23·H_3F"),
        (L.transform_BF, H_B1 * H_12 * H_23, "missing_factor", "leaves out the factor H_3F"),
        (L.foot_position, R_BF - sp.Matrix([0, 1, 0]), "missing_offset", "B r_B1 = [0, 1, 0]"),
        (L.foot_position, (H_B1 * H_12 * H_23)[:3, 3], "wrong_frame", "position of the knee"),
        (L.foot_position, H_BF * sp.Matrix([0, 0, 0, 1]), "shape", "first 3 entries are right"),
        (L.foot_position, R_BF.subs(g, -g), "negated_variable", "sign of γ is flipped"),
        (L.foot_jacobian, J.T, "transpose", "one column per joint"),
        (L.foot_jacobian, J.subs({b: g, g: b}, simultaneous=True), "swapped_variables", "β and γ"),
    ],
)
def test_wrong_answers_are_diagnosed(chk, answer, code, text):
    r = chk(answer, quiet=True)
    assert not r.passed
    assert r.diagnosis == code, r.message
    assert text in r.message, r.message
    assert r.message.startswith("✘ ")


def test_jacobian_column_sign_slip_of_the_symbolic_code():
    # d r_x / d beta written as -cos(beta + gamma) + cos(beta): a single sign slip
    Jw = J.copy()
    Jw[0, 1] = -C(b + g) + C(b)
    r = L.foot_jacobian(Jw, quiet=True)
    assert r.diagnosis == "mismatch" and "entry (1, 2)" in r.message
    Jc = J.copy()
    Jc[:, 1] = -Jc[:, 1]
    r = L.foot_jacobian(Jc, quiet=True)
    assert r.message == "✘ Column 2 (∂/∂β) of J_sym(q) has the wrong sign."


def test_printed_jacobian_with_a_sign_slip_in_entry_3_3():
    Jp = np.array([[0, -1, -0.5], [2, 0, 0], [0, 0, 0.866]])
    r = L.foot_jacobian_at(Jp, quiet=True)
    assert r.diagnosis == "sign_entry"
    assert r.message == "✘ Entry (3, 3) of J_lift has the wrong sign."


def test_jacobian_evaluated_at_degrees():
    r = L.foot_jacobian_at(J_np([0.0, 60.0, -120.0]), quiet=True)
    assert r.diagnosis == "degrees_evaluated" and "sin(60) instead of sin(60°)" in r.message


def test_numbers_the_statement_asks_for_name_wrong_entries_not_their_values():
    """At the one input of J_lift, dq_cmd and H_3F the reference is the answer itself: a wrong
    attempt learns which entries differ and the principle, not what they should be."""
    J_slip = J_np(Q_LIFT)
    J_slip[0, 1] += 0.3
    dq_slip = np.linalg.solve(J_np(Q_LIFT), [0, 0, -1]) + [0, 0.2, 0]
    H_slip = H(sp.eye(3), [0, 0, -2])
    for check_of, answer, entries in [
        (L.foot_jacobian_at, J_slip, "entry (1, 2) differs"),
        (L.lift_velocity, dq_slip, "entry [2] differs"),
        (L.transform_3F, H_slip, "entry (3, 4) differs"),
    ]:
        r = check_of(answer, quiet=True)
        assert r.diagnosis == "mismatch" and entries in r.message, r.message
        assert "should be" not in r.message and "yours is" not in r.message, r.message
    assert "J_lift @ dq_cmd gives v" in L.lift_velocity(dq_slip, quiet=True).message


@pytest.mark.parametrize(
    "answer, code, text",
    [
        ([0, 0.5774, -1.1547], "velocity_sign", "v = [0, 0, +1] m/s"),
        (np.rad2deg([0, -0.57735, 1.1547]), "degrees_output", "in degrees"),
        (J_np(Q_LIFT).T @ [0, 0, -1], "transpose", "Jᵀ v"),
        ([0, -0.5774], "shape", "vector of length 3"),
    ],
)
def test_lift_velocity_mistakes(answer, code, text):
    r = L.lift_velocity(answer, quiet=True)
    assert r.diagnosis == code and text in r.message, r.message


# ---------------------------------------------------------------- IK
def good_step(q, r_goal):
    return q + np.linalg.solve(J_np(q), r_goal - r_np(q))


@pytest.mark.parametrize(
    "step, code",
    [
        (good_step, None),
        (lambda q, r_goal: q - np.linalg.solve(J_np(q), r_goal - r_np(q)), "error_sign"),
        (lambda q, r_goal: np.linalg.solve(J_np(q), r_goal - r_np(q)), "delta_only"),
        (lambda q, r_goal: q + J_np(q).T @ (r_goal - r_np(q)), "jacobian_transpose"),
        (lambda q, r_goal: np.deg2rad(good_step(np.rad2deg(q), r_goal)), "mismatch"),
    ],
)
def test_newton_step(step, code):
    r = L.newton_step(step, quiet=True)
    assert r.diagnosis == code, r.message


def _ik_solutions():
    """Both solutions of r_BF(q) = [0.2, 0.5, -2], by the geometry of the leg."""
    goal = np.array([0.2, 0.5, -2.0])
    d = goal - [0, 1, 0]
    out = []
    rho = np.hypot(d[1], d[2])
    alpha = np.arctan2(d[1], -d[2])  # leg plane through the goal, foot below the hip axis
    u, w = d[0], -rho + 1.0  # foot relative to the beta joint, in the leg plane
    for sign in (1, -1):
        gamma = sign * np.arccos((u * u + w * w - 2) / 2)
        beta = np.arctan2(-u, -w) - np.arctan2(np.sin(gamma), 1 + np.cos(gamma))
        out.append(np.array([alpha, beta, gamma]))
    return out


def test_ik_solution_accepts_every_solution():
    sols = _ik_solutions()
    assert not np.allclose(sols[0], sols[1])
    for q in sols:
        assert np.allclose(r_np(q), [0.2, 0.5, -2.0])
        r = L.ik_solution(q, quiet=True)
        assert r.passed, r.message
        assert L.ik_solution(list(q + 2 * np.pi), quiet=True).passed  # angles modulo 2π


def test_ik_solution_mistakes():
    q = _ik_solutions()[0]
    assert L.ik_solution(np.rad2deg(q), quiet=True).diagnosis == "degrees_output"
    r = L.ik_solution([0.0, 0.0, 0.0], quiet=True)
    assert r.diagnosis == "mismatch" and "r_BF(q) = [0, 1, -3]" in r.message
    assert L.ik_solution([0.0, 0.0], quiet=True).diagnosis == "shape"
    assert L.ik_solution("abc", quiet=True).diagnosis == "error"
    assert L.ik_solution([np.nan, 0, 0], quiet=True).diagnosis == "error"
    with pytest.raises(AssertionError):
        L.ik_solution([0.0, 0.0, 0.0], quiet=True, raise_on_fail=True)
    far = [-1.5, 1.0, -2.5]
    assert not L.ik_solution(q, goal=far, quiet=True).passed


def test_ik_solution_names_the_answer_as_the_notebook_does():
    r = L.ik_solution(np.rad2deg(_ik_solutions()[0]), name="found[0]", quiet=True)
    assert r.name == "found[0]" and r.message.startswith("✘ found[0] is in degrees")
    with pytest.raises(TypeError, match="name must be a str"):
        L.ik_solution(_ik_solutions()[0], name=3, quiet=True)  # type: ignore[arg-type]  # a wrong type on purpose


# ---------------------------------------------------------------- tracking controller
def ctrl(q, r_des, v_des, kp=10.0):
    return np.linalg.solve(J_np(q), v_des + kp * (r_des - r_np(q)))


@pytest.mark.parametrize(
    "controller, code, text",
    [
        (ctrl, None, "✔ controller is correct"),
        (lambda q, r_des, v_des: ctrl(q, r_des, 0 * v_des), "no_feedforward", "Add the feed-forward"),
        (lambda q, r, v: np.linalg.solve(J_np(q), v - 10 * (r - r_np(q))), "error_sign", "r_des − r"),
        (lambda q, r, v: 10 * np.linalg.solve(J_np(q), v + r - r_np(q)), "gain_on_feedforward", "too"),
        (lambda q, r, v: J_np(q).T @ (v + 10 * (r - r_np(q))), "jacobian_transpose", "J⁺"),
        (lambda q, r, v: ctrl(q, r, v, kp=5.0), "mismatch", "not correct"),
    ],
)
def test_tracking_controller(controller, code, text):
    r = L.tracking_controller(controller, quiet=True)
    assert r.diagnosis == code, r.message
    assert text in r.message


def test_tracking_controller_accepts_one_vector_per_argument_or_scalars():
    def scalars(a1, b1, g1, x, y, z, vx, vy, vz):
        return ctrl(np.array([a1, b1, g1]), np.array([x, y, z]), np.array([vx, vy, vz]))

    assert L.tracking_controller(scalars, quiet=True).passed


# ---------------------------------------------------------------- the student's own loops
def newton_ik(r_goal, q0, damping=0.0, tol=1e-10, max_iterations=50):
    """Newton's method written independently: normal equations, J^T J + lambda^2 I."""
    q = np.array(q0, dtype=float)
    iterates = [q]
    for _ in range(int(max_iterations)):
        e = np.asarray(r_goal) - r_np(q)
        if np.linalg.norm(e) <= tol:
            break
        Jq = J_np(q)
        q = q + np.linalg.solve(Jq.T @ Jq + damping**2 * np.eye(3), Jq.T @ e)
        iterates.append(q)
    return np.array(iterates)


@pytest.mark.parametrize(
    "loop, code",
    [
        (newton_ik, None),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, d, tol, m)[1:], "no_start_row"),
        (lambda g, q0, d, tol, m: _newton_wrong_sign(g, q0, d, tol, m), "error_sign"),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, np.sqrt(d), tol, m), "damping_not_squared"),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, d, -1.0, m), "no_early_stop"),
        # a stop test on the step size reaches the accuracy asked: a correct answer
        (lambda g, q0, d, tol, m: _newton_stopped_by_step(g, q0, d, tol, m), None),
        (lambda g, q0, d, tol, m: _newton_step_tested_first(g, q0, d, tol, m), None),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, d, 1e-2, m), "stops_short"),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, d, -1.0, m + 1), "budget"),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, d, tol, m - 1), "stops_short"),  # rows counted
        (lambda g, q0, d, tol, m: newton_ik(g, q0 + 0.1, d, tol, m), "start"),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, d, tol, m) * np.nan, "error"),
        (lambda g, q0, d, tol, m: (newton_ik(g, q0, d, tol, m), True), "error"),
        (lambda g, q0, d, tol, m: newton_ik(g, q0, d, tol, m)[-1], "error"),
        ("not a function", "constant"),
    ],
)
def test_newton_ik(loop, code):
    r = L.newton_ik(loop, quiet=True)
    assert r.diagnosis == code, r.message


def test_loop_mistakes_without_a_name_are_shown_in_the_student_terms():
    """Mistakes the checks have no name for (half the undamped step; twice the gain): the
    example writes the call and names the rows of Q, not the sampled scalars or a packed
    index; a mistake of the undamped step alone is named where it shows."""
    def undamped_halved(r_goal, q0, damping, tol, max_iterations):
        if damping > 0:
            return newton_ik(r_goal, q0, damping, tol, max_iterations)
        rows = [np.array(q0, dtype=float)]
        for _ in range(max_iterations):
            e = np.asarray(r_goal) - r_np(rows[-1])
            if np.linalg.norm(e) <= tol:
                break
            rows.append(rows[-1] + 0.5 * np.linalg.solve(J_np(rows[-1]), e))
        return np.array(rows)

    r = L.newton_ik(undamped_halved, quiet=True)
    assert r.diagnosis == "mismatch", r.message
    assert "Q = newton_ik(r_goal = [" in r.message and "damping = 0 m" in r.message
    assert "the step from Q[0] to Q[1]" in r.message and "tol_exponent" not in r.message

    def undamped_flipped(r_goal, q0, damping, tol, max_iterations):
        return (newton_ik(r_goal, q0, damping, tol, max_iterations) if damping > 0
                else _newton_wrong_sign(r_goal, q0, damping, tol, max_iterations))

    assert L.newton_ik(undamped_flipped, quiet=True).diagnosis == "error_sign"
    r = L.tracking_loop(lambda q0, r, v, kp, ts, ff: track(q0, r, v, 2 * kp, ts, ff), quiet=True)
    assert r.diagnosis == "mismatch" and "Q = track(q0 = [" in r.message and "Q[1, " in r.message


def _newton_wrong_sign(r_goal, q0, damping, tol, max_iterations):
    q = np.array(q0, dtype=float)
    iterates = [q]
    for _ in range(int(max_iterations)):
        e = r_np(q) - np.asarray(r_goal)
        if np.linalg.norm(e) <= tol:
            break
        Jq = J_np(q)
        q = q + np.linalg.solve(Jq.T @ Jq + damping**2 * np.eye(3), Jq.T @ e)
        iterates.append(q)
    return np.array(iterates)


def _newton_stopped_by_step(r_goal, q0, damping, tol, max_iterations):
    """A while loop that stops when the step, not the error, is below tol."""
    q = np.array(q0, dtype=float)
    iterates, step, k = [q], np.ones(3), 0
    while k < max_iterations and np.linalg.norm(step) > tol:
        Jq = J_np(q)
        e = np.asarray(r_goal) - r_np(q)
        step = np.linalg.solve(Jq.T @ Jq + damping**2 * np.eye(3), Jq.T @ e)
        q = q + step
        iterates.append(q)
        k += 1
    return np.array(iterates)


def _newton_step_tested_first(r_goal, q0, damping, tol, max_iterations):
    """A loop that computes the step and stops, without taking it, when it is below tol."""
    q = np.array(q0, dtype=float)
    iterates = [q]
    for _ in range(int(max_iterations)):
        Jq = J_np(q)
        step = np.linalg.solve(Jq.T @ Jq + damping**2 * np.eye(3), Jq.T @ (np.asarray(r_goal) - r_np(q)))
        if np.linalg.norm(step) <= tol:
            break
        q = q + step
        iterates.append(q)
    return np.array(iterates)


def test_a_step_size_stop_short_of_the_accuracy_is_named():
    """A damped step can be below tol while the error is not: a loop that stops there has not
    reached the accuracy asked, and the message says why."""
    x = L.newton_ik.sample_points()[0].copy()
    x[6], x[7] = 0.25, 8.5  # damping 0.15 m, a budget of 8 steps
    r_goal, q0, damping, _, _ = L._newton_args(x)
    Q = newton_ik(r_goal, q0, damping, 0.0, 8)
    errors = np.linalg.norm(r_goal - np.array([r_np(q) for q in Q]), axis=1)
    steps = np.linalg.norm(np.diff(Q, axis=0), axis=1)  # steps[k]: the step computed at Q[k]
    k = int(np.argmax(steps < errors[:-1]))  # the step below the error there
    assert k < 8 and steps[k] < errors[k]
    x[8] = -np.log10(np.sqrt(steps[k] * errors[k]))  # tol between the two
    verdict = L._newton_verdict(Q[: k + 1], x)
    assert verdict is not None
    code, text = verdict
    assert code == "stops_short" and "a small step is not a small error" in text, text


def test_a_start_on_the_goal_ends_either_stop_test_and_nothing_more():
    x = L.newton_ik.sample_points()[0].copy()
    x[3:6], x[6], x[7] = 0.0, 0.0, 5.5  # the goal is the start's foot; undamped; 5 steps
    r_goal, q0, damping, tol, budget = L._newton_args(x)
    assert L._newton_verdict(newton_ik(r_goal, q0, damping, tol, budget), x) is None  # no step
    assert L._newton_verdict(_newton_stopped_by_step(r_goal, q0, damping, tol, budget), x) is None
    verdict = L._newton_verdict(newton_ik(r_goal, q0, damping, -1.0, budget), x)
    assert verdict is not None and verdict[0] == "no_early_stop", verdict


def test_a_loop_that_counts_rows_is_told_what_max_iterations_counts():
    r = L.newton_ik(lambda g, q0, d, tol, m: newton_ik(g, q0, d, tol, m - 1), quiet=True)
    assert r.diagnosis == "stops_short" and "max_iterations counts the steps" in r.message, r.message


def test_newton_ik_reference_converges_quadratically_and_damped_settles():
    goal, q0 = np.array([0.2, 0.5, -2.0]), np.deg2rad([0.0, -30.0, 60.0])
    Q = newton_ik(goal, q0)
    errors = np.linalg.norm(goal - np.array([r_np(q) for q in Q]), axis=1)
    assert len(Q) == 6 and errors[-1] <= 1e-10
    assert np.all(errors[1:5] / errors[:4] ** 2 < 1.0)
    assert L.newton_ik(newton_ik, quiet=True).passed


def track(q0, r_des, v_des, kp=10.0, ts=0.01, feedforward=True):
    """The resolved-rate Euler loop written independently (solve instead of pinv)."""
    q = np.array(q0, dtype=float)
    rows = []
    for r_d, v_d in zip(r_des, v_des):
        rows.append(q)
        v = kp * (r_d - r_np(q)) + (v_d if feedforward else 0.0)
        q = q + ts * np.linalg.solve(J_np(q), v)
    return np.array(rows)


@pytest.mark.parametrize(
    "loop, code",
    [
        (track, None),
        (lambda q0, r, v, kp, ts, ff: track(q0, r, v, kp, ts, False), "no_feedforward"),
        (lambda q0, r, v, kp, ts, ff: track(q0, r, v, kp, ts, True), "always_feedforward"),
        (lambda q0, r, v, kp, ts, ff: np.vstack([track(q0, r, v, kp, ts, ff)[1:],
                                                 _one_more(q0, r, v, kp, ts, ff)]),
         "recorded_after_step"),
        (lambda q0, r, v, kp, ts, ff: track(q0, r, v, kp, ts, ff)[:-1], "error"),
        (lambda q0, r, v, kp, ts, ff: track(q0, r, v, 2 * kp, ts, ff), "mismatch"),
    ],
)
def test_tracking_loop(loop, code):
    r = L.tracking_loop(loop, quiet=True)
    assert r.diagnosis == code, r.message


def _one_more(q0, r_des, v_des, kp, ts, feedforward):
    """The configuration after the last sample's Euler step."""
    q = track(q0, r_des, v_des, kp, ts, feedforward)[-1]
    v = kp * (r_des[-1] - r_np(q)) + (v_des[-1] if feedforward else 0.0)
    return q + ts * np.linalg.solve(J_np(q), v)


def closed_form(p):
    """Every solution of r_BF(q) = p, re-derived: both leg planes, both knees."""
    d = np.asarray(p, dtype=float) - [0.0, 1.0, 0.0]
    out = []
    for L_signed in (np.hypot(d[1], d[2]), -np.hypot(d[1], d[2])):
        alpha = np.arctan2(np.sign(L_signed) * d[1], -np.sign(L_signed) * d[2])
        u, w = d[0], 1.0 - L_signed
        cos_gamma = (u * u + w * w - 2.0) / 2.0
        if abs(cos_gamma) <= 1.0:
            for gamma in (np.arccos(cos_gamma), -np.arccos(cos_gamma)):
                beta = np.arctan2(-u, -w) - gamma / 2
                out.append([alpha, beta, gamma])
    return np.array(out).reshape(-1, 3)


def test_closed_form_reference_solves_the_goals():
    for p in L.ik_closed_form.sample_points():
        sols = closed_form(p)
        assert all(np.allclose(r_np(q), p) for q in sols)
    counts = {len(closed_form(p)) for p in L.ik_closed_form.sample_points()}
    assert counts == {0, 2, 4}


@pytest.mark.parametrize(
    "answer, code",
    [
        (closed_form, None),
        (lambda p: closed_form(p)[::-1] + 2 * np.pi, None),  # any order, angles modulo 2 pi
        (lambda p: closed_form(p)[:2] if len(closed_form(p)) else closed_form(p), "one_branch"),
        (lambda p: np.rad2deg(closed_form(p)), "degrees_output"),
        (lambda p: closed_form(p)[::2], "one_knee"),
        (lambda p: np.zeros((2, 3)), "mismatch"),
        (lambda p: np.zeros(3), "shape"),
        (lambda p: 1 / 0, "error"),
        (np.zeros((2, 3)), "constant"),
        (None, "error"),
    ],
)
def test_ik_closed_form(answer, code):
    r = L.ik_closed_form(answer, quiet=True)
    assert r.diagnosis == code, r.message


def test_ik_closed_form_mismatch_shows_no_solution():
    """A wrong set of solutions is told how many of its rows reach the goal and how many the
    goal has, not the solutions themselves (the answer asked for)."""
    def one_row_off(p):
        sols = closed_form(p)
        return np.vstack([sols[:1], sols[:1] + 0.3, sols[2:]]) if len(sols) else np.zeros((1, 3))

    r = L.ik_closed_form(one_row_off, quiet=True)
    assert r.diagnosis == "mismatch", r.message
    assert "1 of them reaching the goal" in r.message or "0 of them reaching" in r.message
    assert "(rad)" not in r.message and "; [" not in r.message


def test_joint_velocity_function():
    """joint_velocity(v, jacobian) solves J q̇ = v for the Jacobian it is given; typical mistakes named."""
    JL = J_np(Q_LIFT)
    right = [lambda v, jacobian: np.linalg.solve(jacobian, v),
             lambda v, J: np.linalg.lstsq(J, v, rcond=None)[0]]
    for answer in right:
        r = L.joint_velocity(answer, quiet=True)
        assert r.passed, r.message
    for answer, code in [
        (lambda v, jacobian: jacobian.T @ v, "transpose"),
        (lambda v, jacobian: -np.linalg.solve(jacobian, v), "velocity_sign"),
        (lambda v, jacobian: np.linalg.solve(JL, v), "argument_ignored"),
        (lambda v, jacobian: np.rad2deg(np.linalg.solve(jacobian, v)), "degrees_output"),
    ]:
        r = L.joint_velocity(answer, quiet=True)
        assert not r.passed and r.diagnosis == code, r.message
