"""Tests of the chapter-5 exercise checks (robokin.check.baxter).

The correct answers are written independently of the references: the circle from
its complex form c + r·exp(iωt), the resolved-rate law by solving the minimum-norm
problem with a KKT system, the forward kinematics by multiplying the modified-DH
link matrices by hand (Craig 2005, eq. 3.6) with the tutorial's rounded numbers and
the +π/2 offset of joint 2.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from robokin.models import baxter_left

cb = importlib.import_module("robokin.check.baxter")

ARM = baxter_left(base="shoulder")
R, W = cb.RADIUS, cb.OMEGA
C = ARM.fk(cb.Q_START)[:3, 3] - [R, 0.0, 0.0]  # the circle starts at the hand

#: The tutorial's modified-DH table, rows (a_{i-1}, alpha_{i-1}, d_i), as printed (no joint-2 offset).
TUTORIAL = [(0, 0, 0.2703), (0.069, -1.571, 0), (0, 1.571, 0.3644), (0.069, -1.571, 0),
            (0, 1.571, 0.3743), (0.01, -1.571, 0), (0, 1.571, 0.2295)]


def mdh_link(a, alpha, d, theta):
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array([[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d],
                     [0, 0, 0, 1.0]])


def fk_by_hand(q, offset2=np.pi / 2):
    T = np.eye(4)
    for i, ((a, alpha, d), qi) in enumerate(zip(TUTORIAL, q)):
        T = T @ mdh_link(a, alpha, d, qi + (offset2 if i == 1 else 0.0))
    return T


def circle_complex(t):
    z = (C[0] + 1j * C[1]) + R * np.exp(1j * W * t)
    return np.array([z.real, z.imag, C[2]])


def velocity_complex(t):
    z = 1j * W * R * np.exp(1j * W * t)
    return np.array([z.real, z.imag, 0.0])


def rate_kkt(q, r_des, v_des):
    J = ARM.position_jacobian(q)
    v = v_des + cb.KP * (r_des - ARM.fk(q)[:3, 3])
    K = np.block([[np.eye(7), J.T], [J, np.zeros((3, 3))]])
    return np.linalg.solve(K, np.r_[np.zeros(7), v])[:7]


def sigma_min_eigen(q):
    """sigma_min of J_v as the root of the smallest eigenvalue of J_v J_v^T (not an SVD)."""
    J = ARM.position_jacobian(q)
    return float(np.sqrt(max(np.linalg.eigvalsh(J @ J.T)[0], 0.0)))


# ---------------------------------------------------------------- reference values of the chapter
def test_constants():
    assert np.allclose(cb.Q_START, [0.0, -0.55, 0.0, 1.284, 0.0, 0.26160184, 0.0], atol=1e-8)
    assert cb.PERIOD == pytest.approx(4.0) and R * W == pytest.approx(0.0785398, rel=1e-6)
    assert np.allclose(cb._CENTRE + [R, 0, 0], ARM.fk(cb.Q_START)[:3, 3])


@pytest.mark.parametrize("q", [np.zeros(7), cb.Q_START, np.array([0.3, -1.0, 0.5, 1.5, -0.7, 1.0, 2.0])])
def test_tutorial_table_with_offset_matches_model_to_half_a_millimetre(q):
    assert np.linalg.norm(fk_by_hand(q)[:3, 3] - ARM.fk(q)[:3, 3]) < 5e-4


def test_zero_pose_is_the_stretched_arm():
    # URDF zero pose: upper arm horizontal along x; the tutorial's table as printed points it up
    p = ARM.fk(np.zeros(7))[:3, 3]
    assert p[0] > 1.0 and p[2] == pytest.approx(0.27035 - 0.069 - 0.010)   # two 'a' offsets step it down
    assert fk_by_hand(np.zeros(7), offset2=0.0)[2, 3] > 1.0


# ---------------------------------------------------------------- correct answers pass
@pytest.mark.parametrize("check, answer", [
    (cb.circle_position, circle_complex),
    (cb.circle_velocity, velocity_complex),
    (cb.resolved_rate, rate_kkt),
    (cb.forward_kinematics, fk_by_hand),
    (cb.forward_kinematics, ARM.fk),
    (cb.sigma_min, lambda q: sigma_min_eigen(q)),
])
def test_correct_answers_pass(check, answer):
    r = check(answer, quiet=True)
    assert r.passed and r.diagnosis is None, r.message


def test_hand_position_at_accepts_four_decimals(capsys):
    cb.hand_position_at(ARM.fk(cb.Q_START)[:3, 3].round(4))
    assert capsys.readouterr().out == "✔ r_hand(q_start) at q_start = lower + 0.5·range is correct.\n"


# ---------------------------------------------------------------- diagnosed mistakes
WRONG_POSITION = {
    "centre_at_start": lambda t: circle_complex(t) + [R, 0, 0],
    "phase": lambda t: C + R * np.array([-np.sin(W * t), np.cos(W * t), 0]),
    "swapped_sin_cos": lambda t: C + R * np.array([np.sin(W * t), np.cos(W * t), 0]),
    "direction": lambda t: C + R * np.array([np.cos(W * t), -np.sin(W * t), 0]),
    "degrees": lambda t: C + R * np.array([np.cos(90 * t), np.sin(90 * t), 0]),
    "shape": lambda t: circle_complex(t)[:2],
}

WRONG_VELOCITY = {
    "missing_chain_rule": lambda t: velocity_complex(t) / W,
    "phase": lambda t: R * W * np.array([np.cos(W * t), np.sin(W * t), 0]),
    "direction": lambda t: R * W * np.array([-np.sin(W * t), -np.cos(W * t), 0]),
    "degrees": lambda t: R * W * np.array([-np.sin(90 * t), np.cos(90 * t), 0]),
    "swapped_sin_cos": lambda t: R * W * np.array([np.cos(W * t), -np.sin(W * t), 0]),
}


def _q_mistake(q, r_des, v_des, **kw):
    J = kw.get("J", ARM.position_jacobian)(q)
    return np.linalg.pinv(J) @ (v_des + kw.get("kp", cb.KP) * kw.get("sign", 1) * (r_des - ARM.fk(q)[:3, 3]))


WRONG_RATE = {
    "open_loop": lambda q, r, v: _q_mistake(q, r, v, kp=0.0),
    "error_sign": lambda q, r, v: _q_mistake(q, r, v, sign=-1),
    "jacobian_transpose": lambda q, r, v: ARM.position_jacobian(q).T @ (v + cb.KP * (r - ARM.fk(q)[:3, 3])),
    "full_jacobian": lambda q, r, v: np.linalg.pinv(ARM.jacobian(q)) @ np.r_[v + cb.KP * (r - ARM.fk(q)[:3, 3]),
                                                                              0, 0, 0],
    "missing_joint2_offset": lambda q, r, v: rate_kkt(q - cb._JOINT2_OFFSET, r, v),
    "no_feedforward": lambda q, r, v: np.linalg.pinv(ARM.position_jacobian(q)) @ (cb.KP * (r - ARM.fk(q)[:3, 3])),
}

WRONG_FK = {
    "missing_joint2_offset": lambda q: fk_by_hand(q, offset2=0.0),
    "torso_frame": baxter_left(base="torso").fk,
    "gripper_frame": baxter_left(base="shoulder", end="gripper").fk,
    "degrees_input": lambda q: fk_by_hand(np.deg2rad(q)),
    "inverse": lambda q: np.linalg.inv(fk_by_hand(q)),
}


def _eigenvalues(q, jacobian=ARM.position_jacobian):
    J = jacobian(q)
    return np.linalg.eigvalsh(J @ J.T)  # smallest first: sigma_i^2


WRONG_SIGMA = {
    "largest_singular_value": lambda q: float(np.sqrt(_eigenvalues(q)[-1])),
    "eigenvalue_not_root": lambda q: float(_eigenvalues(q)[0]),
    "full_jacobian": lambda q: float(np.sqrt(max(_eigenvalues(q, ARM.jacobian)[0], 0.0))),
    "manipulability": lambda q: float(np.sqrt(np.prod(_eigenvalues(q)))),
    "degrees_evaluated": lambda q: sigma_min_eigen(np.degrees(q)),
}


@pytest.mark.parametrize("code", WRONG_SIGMA)
def test_sigma_min_mistakes(code):
    r = cb.sigma_min(WRONG_SIGMA[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


@pytest.mark.parametrize("code", WRONG_POSITION)
def test_circle_position_mistakes(code):
    r = cb.circle_position(WRONG_POSITION[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


@pytest.mark.parametrize("code", WRONG_VELOCITY)
def test_circle_velocity_mistakes(code):
    r = cb.circle_velocity(WRONG_VELOCITY[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


@pytest.mark.parametrize("code", WRONG_RATE)
def test_resolved_rate_mistakes(code):
    r = cb.resolved_rate(WRONG_RATE[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


@pytest.mark.parametrize("code", WRONG_FK)
def test_forward_kinematics_mistakes(code):
    r = cb.forward_kinematics(WRONG_FK[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_flange_offset_counted_twice_is_diagnosed():
    """The exercise's last row (0, 1.571, 0.2295) copied with its d and the flange offset added
    again as d_hand: the hand 0.2295 m beyond the flange along z7."""
    def twice(q):
        T = fk_by_hand(q)   # the tutorial's rows: the last one's d is the flange offset
        shift = np.eye(4)
        shift[2, 3] = 0.2295
        return T @ shift

    r = cb.forward_kinematics(twice, quiet=True)
    assert r.diagnosis == "flange_twice" and "counted twice" in r.message, r.message


def test_standard_dh_reading_is_diagnosed():
    from robokin.chains import from_dh

    table = [[d, (np.pi / 2 if i == 1 else 0.0), a, al] for i, (a, al, d) in enumerate(TUTORIAL)]
    r = cb.forward_kinematics(from_dh(table).fk, quiet=True)
    assert r.diagnosis == "standard_dh", r.message


def test_hand_position_mistakes():
    assert cb.hand_position_at(fk_by_hand(cb.Q_START, 0.0)[:3, 3], quiet=True).diagnosis == "missing_joint2_offset"
    assert cb.hand_position_at(baxter_left().fk(cb.Q_START)[:3, 3], quiet=True).diagnosis == "torso_frame"
    assert cb.hand_position_at([1.0, 2.0], quiet=True).diagnosis == "shape"


def test_not_a_function_and_raise_on_fail():
    assert cb.circle_velocity(np.zeros(3), quiet=True).diagnosis == "constant"
    with pytest.raises(AssertionError, match="chain rule"):
        cb.circle_velocity(WRONG_VELOCITY["missing_chain_rule"], quiet=True, raise_on_fail=True)


# ---------------------------------------------------------------- the tracking loop
def track_kkt(q0, r_des, v_des, kp=cb.KP, ts=cb.TS, *, sign=1.0, record_after=False, ff=True, ff_gain=1.0,
              ignore_kp=False):
    """Euler steps of the law, each command from the KKT system of the minimum-norm problem
    (and, with the keywords, the loop's typical mistakes)."""
    q, rows = np.array(q0, dtype=float), []
    gain = 0.0 if ignore_kp else kp
    for r_d, v_d in zip(r_des, v_des):
        if not record_after:
            rows.append(q.copy())
        J = ARM.position_jacobian(q)
        v = (ff_gain * v_d if ff else 0.0) + gain * sign * (r_d - ARM.fk(q)[:3, 3])
        K = np.block([[np.eye(7), J.T], [J, np.zeros((3, 3))]])
        q = q + ts * np.linalg.solve(K, np.r_[np.zeros(7), v])[:7]
        if record_after:
            rows.append(q.copy())
    return np.array(rows)


def test_tracking_loop_correct_answer_passes():
    r = cb.tracking_loop(track_kkt, quiet=True)
    assert r.passed and r.diagnosis is None, r.message


def test_tracking_loop_reduces_to_the_resolved_rate_law():
    """One step of the loop is q0 + ts times the law that resolved_rate checks."""
    q0 = cb.Q_START + 0.05
    r_des = np.array([ARM.fk(q0)[:3, 3] + [0.01, 0.0, 0.0]] * 2)
    v_des = np.array([[0.0, 0.05, 0.0]] * 2)
    Q = track_kkt(q0, r_des, v_des, kp=5.0, ts=0.01)
    J = ARM.position_jacobian(q0)
    assert np.allclose(J @ (Q[1] - Q[0]) / 0.01, v_des[0] + 5.0 * (r_des[0] - ARM.fk(q0)[:3, 3]))


WRONG_TRACK = {
    "open_loop": lambda q0, r, v, kp=cb.KP, ts=cb.TS: track_kkt(q0, r, v, kp, ts, ignore_kp=True),
    "no_feedforward": lambda q0, r, v, kp=cb.KP, ts=cb.TS: track_kkt(q0, r, v, kp, ts, ff=False),
    "error_sign": lambda q0, r, v, kp=cb.KP, ts=cb.TS: track_kkt(q0, r, v, kp, ts, sign=-1.0),
    "recorded_after_step": lambda q0, r, v, kp=cb.KP, ts=cb.TS: track_kkt(q0, r, v, kp, ts, record_after=True),
    "gain_on_feedforward": lambda q0, r, v, kp=cb.KP, ts=cb.TS: track_kkt(q0, r, v, kp, ts, ff_gain=kp),
}


@pytest.mark.parametrize("code", WRONG_TRACK)
def test_tracking_loop_mistakes(code):
    r = cb.tracking_loop(WRONG_TRACK[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_tracking_loop_wrong_shape_is_explained():
    r = cb.tracking_loop(lambda q0, r, v, kp=cb.KP, ts=cb.TS: track_kkt(q0, r, v, kp, ts)[1:], quiet=True)
    assert not r.passed and "shape (6, 7)" in r.message


def test_reference_resolved_rate_is_the_law_of_task_3():
    """robokin's law, the stand-in the test of track passes as rate=: the minimum-norm command
    (the KKT system) at configurations and references of this test's own; kp = 0 the open loop."""
    rng = np.random.default_rng(5)
    for q in ARM.random_configurations(5, seed=8):
        r_d, v_d = ARM.fk(q)[:3, 3] + 0.01 * rng.standard_normal(3), 0.1 * rng.standard_normal(3)
        assert np.allclose(cb.reference_resolved_rate(q, r_d, v_d), rate_kkt(q, r_d, v_d))
        J = ARM.position_jacobian(q)
        assert np.allclose(J @ cb.reference_resolved_rate(q, r_d, v_d, kp=0.0), v_d)
    with pytest.raises(ValueError, match="q"):
        cb.reference_resolved_rate(np.zeros(6), np.zeros(3), np.zeros(3))


def test_tracking_loop_is_judged_with_robokin_law_passed_as_rate():
    """A loop that takes its law as rate= is checked with robokin's: a wrong default law (the
    student's resolved_rate) does not make a right loop wrong, and a wrong loop is still named."""
    def wrong_law(q, r_des, v_des, kp):
        return cb.reference_resolved_rate(q, r_des, v_des, -kp)

    def loop(q0, r_des, v_des, kp=cb.KP, ts=cb.TS, rate=wrong_law, after=False):
        q, rows = np.array(q0, dtype=float), []
        for r_d, v_d in zip(r_des, v_des):
            if not after:
                rows.append(q)
            q = q + ts * rate(q, r_d, v_d, kp)
            if after:
                rows.append(q)
        return np.array(rows)

    assert cb.tracking_loop(loop, quiet=True).passed
    wrong = cb.tracking_loop(lambda q0, r, v, kp=cb.KP, ts=cb.TS, rate=wrong_law: loop(q0, r, v, kp, ts, rate,
                                                                                        after=True), quiet=True)
    assert wrong.diagnosis == "recorded_after_step", wrong.message
    # a loop without the argument is called as it is: its own law decides
    assert cb.tracking_loop(lambda q0, r, v, kp=cb.KP, ts=cb.TS: loop(q0, r, v, kp, ts), quiet=True).diagnosis \
        == "error_sign"


def test_hand_position_at_names_wrong_entries_not_their_values():
    """The hand at q_start is the answer of Task 1: a wrong attempt learns which coordinates
    differ and what the hand position is, not the numbers."""
    p = ARM.fk(cb.Q_START)[:3, 3]
    for answer, what in [(p + [0.0, 0.0, 0.02], "entry [3] differs"), (np.zeros(3), "entries [1], [3] differ"),
                         (p + 0.01, "every entry differs")]:
        r = cb.hand_position_at(answer, quiet=True)
        assert r.diagnosis == "mismatch" and what in r.message, r.message
        assert "should be" not in r.message and "0.81" not in r.message and "forward kinematics" in r.message


def test_help_shows_no_answer():
    """help() lists the module's data: the circle's centre (Task 2) and the joint-2 offset
    (Task 1) are answers, so they stay private."""
    import pydoc

    text = pydoc.plain(pydoc.render_doc(cb))
    data = text[text.index("DATA"):]
    for answer in ("CENTRE", "JOINT2_OFFSET"):
        assert answer not in data and answer not in cb.__all__
    assert np.allclose(cb._JOINT2_OFFSET, [0.0, np.pi / 2, 0.0, 0.0, 0.0, 0.0, 0.0])


# ---------------------------------------------------------------- the first loss of rank, the link, the chord
def approach_by_loop(Q, ts=cb.TS, threshold=0.01):
    """One sample at a time, sigma_min from the eigenvalues of J_v J_v^T (not an SVD)."""
    values = [sigma_min_eigen(q) for q in Q]
    first = next((k for k, value in enumerate(values) if value < threshold), None)
    return min(values), (None if first is None else first * ts)


def _approach_mistake(**slip):
    def answer(Q, ts=cb.TS, threshold=0.01):
        values = np.array([sigma_min_eigen(q) for q in Q])
        below = np.flatnonzero(values < slip.get("threshold", threshold))
        if not below.size:
            return values.min(), None
        k = slip.get("pick", lambda below, values: below[0])(below, values)
        return values.min(), (k if slip.get("index") else slip.get("ts", ts) * (k + slip.get("shift", 0)))
    return answer


WRONG_APPROACH = {
    "time_of_minimum": _approach_mistake(pick=lambda below, values: int(np.argmin(values))),
    "last_sample": _approach_mistake(pick=lambda below, values: below[-1]),
    "counted_from_one": _approach_mistake(shift=1),
    "index_not_time": _approach_mistake(index=True),
    "time_step_ignored": _approach_mistake(ts=cb.TS),
    "threshold_ignored": _approach_mistake(threshold=0.01),
}


def test_closest_approach_correct_answer_passes():
    r = cb.closest_approach(approach_by_loop, quiet=True)
    assert r.passed and r.diagnosis is None, r.message


@pytest.mark.parametrize("code", WRONG_APPROACH)
def test_closest_approach_mistakes(code):
    r = cb.closest_approach(WRONG_APPROACH[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_closest_approach_explains_a_wrong_form_and_a_wrong_none():
    assert cb.closest_approach(lambda Q, ts, threshold: 0.1, quiet=True).diagnosis == "shape"
    never = cb.closest_approach(lambda Q, ts, threshold: (approach_by_loop(Q, ts, threshold)[0], None), quiet=True)
    assert never.diagnosis == "mismatch" and "None exactly when no sample is" in never.message


def link_by_product(a, alpha, d, theta):
    """R_x(alpha) T_x(a) R_z(theta) T_z(d) from the rotation and translation of each factor."""
    def transform(rotation=None, shift=(0.0, 0.0, 0.0)):
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = np.eye(3) if rotation is None else rotation, shift
        return T

    c, s = np.cos(alpha), np.sin(alpha)
    rx = transform(np.array([[1, 0, 0], [0, c, -s], [0, s, c]]))
    c, s = np.cos(theta), np.sin(theta)
    rz = transform(np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]))
    return rx @ transform(shift=[a, 0, 0]) @ rz @ transform(shift=[0, 0, d])


def test_link_transform_is_the_rows_of_the_table():
    assert cb.link_transform(mdh_link, quiet=True).passed
    assert cb.link_transform(link_by_product, quiet=True).passed
    # the table of the tutorial multiplied link by link is the model (with the flange)
    q = np.array([0.3, -1.0, 0.5, 1.5, -0.7, 1.0, 2.0])
    assert np.linalg.norm(fk_by_hand(q)[:3, 3] - ARM.fk(q)[:3, 3]) < 5e-4


@pytest.mark.parametrize("code, answer", [
    ("standard_dh", lambda a, alpha, d, theta: (link_by_product(0, 0, d, theta) @ link_by_product(a, 0, 0, 0)
                                                 @ link_by_product(0, alpha, 0, 0))),
    ("composition_order", lambda a, alpha, d, theta: (link_by_product(0, alpha, 0, theta)
                                                       @ link_by_product(a, 0, 0, 0) @ link_by_product(0, 0, d, 0))),
    ("degrees_input", lambda a, alpha, d, theta: link_by_product(a, np.radians(alpha), d, np.radians(theta))),
])
def test_link_transform_mistakes(code, answer):
    r = cb.link_transform(answer, quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def chord_by_cosines(rho, step):
    """The chord by the law of cosines: |p1 - p0|^2 = 2 rho^2 (1 - cos step)."""
    return np.sqrt(2 * rho**2 * (1 - np.cos(step)))


@pytest.mark.parametrize("code, answer", [
    (None, chord_by_cosines),
    ("arc", lambda rho, step: rho * step),
    ("full_angle", lambda rho, step: chord_by_cosines(rho, 2 * step)),
    ("half_chord", lambda rho, step: chord_by_cosines(rho, step) / 2),
])
def test_chord_length(code, answer):
    r = cb.chord_length(answer, quiet=True)
    assert r.passed == (code is None) and r.diagnosis == code, r.message


def dls_by_stacking(q, r_des, v_des, kp=cb.KP, damping=0.02, *, damping_term=None, feedback=True):
    """The damped command as the least-squares solution of [J; damping I] qdot = [v; 0] (not the
    closed form), and, with the keywords, its typical mistakes."""
    J = ARM.position_jacobian(q)
    v = v_des + (kp * (r_des - ARM.fk(q)[:3, 3]) if feedback else 0.0)
    weight = damping if damping_term is None else damping_term
    return np.linalg.lstsq(np.vstack([J, weight * np.eye(7)]), np.r_[v, np.zeros(7)], rcond=None)[0]


@pytest.mark.parametrize("code, answer", [
    (None, dls_by_stacking),
    ("damping_not_squared", lambda q, r, v, kp, damping: dls_by_stacking(q, r, v, kp, damping,
                                                                          damping_term=np.sqrt(damping))),
    ("no_damping", lambda q, r, v, kp, damping: dls_by_stacking(q, r, v, kp, damping, damping_term=0.0)),
    ("no_feedback", lambda q, r, v, kp, damping: dls_by_stacking(q, r, v, kp, damping, feedback=False)),
    ("undamped", lambda q, r, v, kp, damping: np.linalg.solve(
        ARM.position_jacobian(q).T @ ARM.position_jacobian(q) + damping**2 * np.eye(7),
        ARM.position_jacobian(q).T @ (v + kp * (r - ARM.fk(q)[:3, 3])))),
])
def test_damped_rate(code, answer):
    r = cb.damped_rate(answer, quiet=True)
    assert r.passed == (code is None) and r.diagnosis == code, r.message
