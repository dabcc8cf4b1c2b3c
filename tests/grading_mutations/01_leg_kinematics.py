"""Wrong answers that each autograded test of chapter 1 must reject."""

# the student's Newton loop with one line changed, and the answers that use it recomputed
_NEWTON = """
def newton_ik(r_goal, q0, damping=0.0, tol=1e-10, max_iterations=50):
    q = np.array(q0, dtype=float)
    iterates = [q]
    for _ in range(max_iterations):
        e = {error}
        if {stop}:
            break
        J = leg.position_jacobian(q)
        dq = {step}
        q = q + dq
        iterates.append(q)
    return np.array(iterates{rows})
Q_newton = newton_ik(r_goal, q0_ik)
r_iter = leg.fk(Q_newton)[:, :3, 3]
e_iter = np.linalg.norm(r_goal - r_iter, axis=1)
"""
_GOOD = dict(
    error="r_goal - leg.fk(q)[:3, 3]",
    stop="np.linalg.norm(e) <= tol",
    step="np.linalg.pinv(J) @ e if damping == 0 else J.T @ np.linalg.solve(J @ J.T + damping**2 * np.eye(3), e)",
    rows="",
)


def _newton(**change: str) -> str:
    return _NEWTON.format(**{**_GOOD, **change})


# the student's tracking loop with one line changed, and the runs recomputed
_TRACK = """
def track(q0, r_des, v_des, kp=KP, ts=TS, feedforward=True):
    q = np.array(q0, dtype=float)
    Q = []
    for r_d, v_d in zip(r_des, v_des):
        Q.append(q)
        e = {error}
        v = {command}
        q = q + ts * (np.linalg.pinv(leg.position_jacobian(q)) @ v)
    return np.array(Q)
Q_ff = track(q0_track, r_des, v_des)
Q_p = track(q0_track, r_des, v_des, feedforward=False)
err_ff = np.linalg.norm(r_des - leg.fk(Q_ff)[:, :3, 3], axis=1)
err_p = np.linalg.norm(r_des - leg.fk(Q_p)[:, :3, 3], axis=1)
"""


def _track(error: str = "r_d - leg.fk(q)[:3, 3]", command: str = "(v_d if feedforward else 0.0) + kp * e") -> str:
    return _TRACK.format(error=error, command=command)


MUTATIONS = {
    "task1_test1": [
        ("R_12 transposed (the rotation the other way round)", "R_12 = R_12.T"),
        ("the knee about x instead of y", "R_23 = rotx(gamma)"),
        ("R_B1 turning twice as fast", "R_B1 = rotx(2 * alpha)"),
    ],
    "task2_test1": [
        ("no hip offset B r_B1 in H_B1", "H_B1 = transform(R_B1, [0, 0, 0])"),
        ("factors composed in the wrong order", "H_BF = sp.simplify(H_3F * H_23 * H_12 * H_B1)"),
        ("the knee frame's origin taken for the foot",
         "r_BF = sp.simplify(H_B1 * H_12 * H_23)[:3, 3]"),
        # with a wrong rotation of Task 1 the transforms are graded as built from it: a
        # mistake of Task 2's own is still rejected
        ("R_12 transposed in Task 1, and the factors composed in the wrong order",
         "R_12 = R_12.T\nH_12 = transform(R_12, [0, 0, -1])\n"
         "H_BF = sp.simplify(H_3F * H_23 * H_12 * H_B1)\nr_BF = H_BF[:3, 3]"),
        ("the knee about x in Task 1, and no offset in H_23",
         "R_23 = rotx(gamma)\nH_23 = transform(R_23, [0, 0, 0])\n"
         "H_BF = sp.simplify(H_B1 * H_12 * H_23 * H_3F)\nr_BF = H_BF[:3, 3]"),
    ],
    "task3_test1": [
        ("sign slip in entry (3, 3) of J", "J_lift = J_lift.copy()\nJ_lift[2, 2] = -J_lift[2, 2]"),
        ("J evaluated at degrees", "J_lift = np.array(J_sym.subs(dict(zip(q_sym, [0.0, 60.0, -120.0]))), dtype=float)"),
        ("J_sym transposed (one row per joint)", "J_sym = J_sym.T\nJ_lift = J_lift.T.copy()"),
        # with a wrong foot position of Task 2, J is graded as the Jacobian of it: a mistake
        # of Task 3's own is still rejected
        ("the factors in the wrong order in Task 2, and J evaluated at degrees",
         "H_BF = sp.simplify(H_3F * H_23 * H_12 * H_B1)\nr_BF = H_BF[:3, 3]\n"
         "J_sym = r_BF.jacobian(q_sym)\n"
         "J_lift = np.array(J_sym.subs(dict(zip(q_sym, [0.0, 60.0, -120.0]))), dtype=float)"),
        ("R_12 transposed in Task 1, and J at q_lift transposed",
         "R_12 = R_12.T\nr_BF = (transform(R_B1, [0, 1, 0]) * transform(R_12, [0, 0, -1])\n"
         "        * transform(R_23, [0, 0, -1]) * transform(sp.eye(3), [0, 0, -1]))[:3, 3]\n"
         "J_sym = r_BF.jacobian(q_sym)\n"
         "J_lift = np.array(J_sym.subs(dict(zip(q_sym, q_lift))), dtype=float).T"),
    ],
    "task3_test2": [
        ("v_cmd taken as the lift [0, 0, +1] m/s", "v_cmd = np.array([0.0, 0.0, 1.0])"),
        ("J^T v instead of J^-1 v", "def joint_velocity(v, jacobian=J_lift):\n    return jacobian.T @ v"),
        ("the joint velocity with the wrong sign",
         "def joint_velocity(v, jacobian=J_lift):\n    return -np.linalg.solve(jacobian, v)"),
        ("the joint velocity in deg/s",
         "def joint_velocity(v, jacobian=J_lift):\n    return np.rad2deg(np.linalg.solve(jacobian, v))"),
        ("the argument jacobian ignored: always the student's J_lift",
         "def joint_velocity(v, jacobian=J_lift):\n    return np.linalg.solve(J_lift, v)"),
        # with the knee's origin taken for the foot in Task 2 the student's own J is singular
        # at q_lift: joint_velocity is graded on the model's Jacobian, and its mistake caught
        ("the knee's origin as r_BF in Task 2, and J^T v instead of J^-1 v",
         "r_BF = sp.simplify(H_B1 * H_12 * H_23)[:3, 3]\nJ_sym = r_BF.jacobian(q_sym)\n"
         "J_lift = np.array(J_sym.subs(dict(zip(q_sym, q_lift))), dtype=float)\n"
         "def joint_velocity(v, jacobian=J_lift):\n    return jacobian.T @ v"),
    ],
    "task3_test3": [
        ("the statement's 'lift' taken at its word", "lifts = True"),
        ("the lift with v = [0, 0, -1] m/s", "v_lift = v_cmd"),
        ("the lift at the wrong speed (2 m/s)", "v_lift = 2 * v_lift"),
        ("the lift as a joint velocity (the answer of the question before)", "v_lift = dq_lift"),
        ("J evaluated at degrees in the part above, and the lift with v = [0, 0, -1] m/s",
         "J_lift = np.array(J_sym.subs(dict(zip(q_sym, [0.0, 60.0, -120.0]))), dtype=float)\n"
         "v_lift = np.array([0.0, 0.0, -1.0])"),
    ],
    "task4_test1": [
        ("the error's sign flipped (r(q) - r_goal)", _newton(error="leg.fk(q)[:3, 3] - r_goal")),
        ("the start left out of the iterates", _newton(rows="[1:]")),
        ("stopped at the exercise's tolerance of 1 cm", _newton(stop="np.linalg.norm(e) <= 1e-2")),
        ("a gradient step J^T e instead of J+ e", _newton(step="J.T @ e")),
        ("lambda where lambda^2 belongs in the damped step",
         _newton(step="np.linalg.pinv(J) @ e if damping == 0 else "
                      "J.T @ np.linalg.solve(J @ J.T + damping * np.eye(3), e)")),
        ("no stop test: always max_iterations steps", _newton(stop="False")),
        ("error log shifted by one iterate", "e_iter = np.r_[e_iter[1:], e_iter[-1]]"),
        ("foot positions of the next iterate logged", "r_iter = np.r_[r_iter[1:], r_iter[-1:]]"),
        ("robokin's solver called instead of the loop, the log from its result",
         "from robokin.motion import solve_ik\n"
         "Q_newton = np.array([solve_ik(leg, r_goal, q0_ik, method='pinv', restarts=0, tol=1e-10).q])"),
    ],
    "task4_test2": [
        ("only one knee found", "closed = closed[:1]\nfound = found[:1]"),
        ("solutions in degrees", "found = np.rad2deg(found)"),
        ("found from the one run of Q_newton instead of the 27 starts of the grid",
         "found = np.angle(np.exp(1j * Q_newton[-1:]))"),
        ("the closed form misses the leg swung over the top",
         "_closed_full = ik_closed_form\n"
         "ik_closed_form = lambda p: np.array([q for q in _closed_full(p) "
         "if abs(q[0] - np.arctan2(p[1] - 1, -p[2])) < 1e-9]).reshape(-1, 3)"),
        ("the closed form returns a constant (the values at r_goal)",
         "_closed_at_goal = np.asarray(closed).copy()\nik_closed_form = lambda p: _closed_at_goal"),
    ],
    "task4_test3": [
        ("distance measured from the hip instead of the beta joint", "gap = np.linalg.norm(r_far - HIP)"),
        ("the damped run taken for the undamped one (no jumps)", "far_newton = far_dls"),
        ("the closest point on the line from the hip",
         "r_best = HIP + 2.0 * (r_far - HIP) / np.linalg.norm(r_far - HIP)"),
        ("the damped run with a tenth of the damping (lambda = 0.02 m)",
         "far_dls = newton_ik(r_far, q0_ik, damping=0.02, max_iterations=20)"),
        ("both runs only 5 iterations", "far_newton = far_newton[:6]\nfar_dls = far_dls[:6]"),
    ],
    "task5_test1": [
        ("no feed-forward in the feed-forward run", "Q_ff = Q_p\nerr_ff = err_p"),
        ("a circle of 1 Hz instead of 0.25 Hz",
         "r_des = c + RADIUS * np.column_stack([np.sin(2 * np.pi * t), 0 * t, np.cos(2 * np.pi * t)])"),
        ("the velocity without the factor omega",
         "v_des = RADIUS * np.column_stack([np.cos(OMEGA * t), 0 * t, -np.sin(OMEGA * t)])"),
        ("the loop's error sign flipped", _track(error="leg.fk(q)[:3, 3] - r_d")),
        ("the loop never adds the feed-forward", _track(command="kp * e")),
        ("the gain applied to the feed-forward too", _track(command="kp * ((v_d if feedforward else 0.0) + e)")),
        ("the P-only error taken from the feed-forward run", "err_p = err_ff"),
    ],
    "task5_test2": [
        ("the rule of thumb omega R / Kp as the prediction", "lag_predicted = RADIUS * OMEGA / KP"),
        ("the measured lag copied as the prediction", "lag_predicted = err_p[t >= 2.0].mean()"),
        ("the lag predicted in millimetres", "lag_predicted = 1e3 * lag_predicted"),
        ("the discrete prediction in the wrong units (the phase in degrees)",
         "lag_predicted = np.rad2deg(np.arctan(OMEGA / KP))"),
    ],
}
