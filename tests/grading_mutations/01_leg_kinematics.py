"""Wrong answers that each autograded test of chapter 1 must reject."""

MUTATIONS = {
    "task1_test1": [
        ("R_12 transposed (the rotation the other way round)", "R_12 = R_12.T"),
        ("the knee about x instead of y", "R_23 = rotx(gamma)"),
    ],
    "task2_test1": [
        ("no hip offset B r_B1 in H_B1", "H_B1 = transform(R_B1, [0, 0, 0])"),
        ("factors composed in the wrong order", "H_BF = sp.simplify(H_3F * H_23 * H_12 * H_B1)"),
    ],
    "task3_test1": [
        ("sign slip in entry (3, 3) of J", "J_lift = J_lift.copy()\nJ_lift[2, 2] = -J_lift[2, 2]"),
        ("the joint velocity that lifts the foot instead", "dq_cmd = -dq_cmd"),
    ],
    "task3_test2": [
        ("v_cmd taken as the lift [0, 0, +1] m/s", "v_cmd = np.array([0.0, 0.0, 1.0])"),
    ],
    "task4_test1": [
        ("stopped at the exercise's tolerance of 1 cm",
         "ik = solve_ik(leg, r_goal, q0_ik, method='pinv', restarts=0, tol=1e-2)"),
        ("error log shifted by one iterate", "e_iter = np.r_[e_iter[1:], e_iter[-1]]"),
    ],
    "task4_test2": [
        ("foot positions of the next iterate logged", "r_iter = leg.fk(ik.history.q[1:])[:, :3, 3]"),
    ],
    "task4_test3": [
        ("only one knee found", "closed = closed[:1]\nfound = found[:1]"),
        ("solutions in degrees", "found = np.rad2deg(found)"),
    ],
    "task4_test4": [
        ("distance measured from the hip instead of the beta joint", "gap = np.linalg.norm(r_far - HIP)"),
        ("damped run with a tolerance that calls it converged",
         "far_dls = solve_ik(leg, r_far, q0_ik, method='dls', damping=0.2, restarts=0, tol=0.2)"),
        ("the damped run taken for the undamped one (no jumps)", "far_pinv = far_dls"),
    ],
    "task4_test5": [
        ("the damped run taken for the undamped one", "far_pinv = far_dls"),
    ],
    "task5_test1": [
        ("no feed-forward in the feed-forward run",
         "runs = {'feed-forward': runs['P only'], 'P only': runs['P only']}\nlog_ff = log_p"),
        ("a circle of 1 Hz instead of 0.25 Hz",
         "r_des = c + RADIUS * np.column_stack([np.sin(2 * np.pi * t), 0 * t, np.cos(2 * np.pi * t)])"),
    ],
    "task5_test2": [
        ("the P-only error taken from the feed-forward run", "err_p = err_ff"),
        ("feed-forward in both runs", "err_p = err_ff\nlog_p = log_ff\nR_p = R_ff"),
    ],
}
