"""Wrong answers that each autograded test of chapter 6 (AR-601 leg, closed-form IK) must reject.

Each entry rebinds the student's names the way a typical mistake would leave them (the
names computed from the changed one are recomputed as the answer cell would), see
``tests/test_grading_mutations.py``. A mutation that wraps the right function keeps it
under a private name (``_..._right``), restored with the others afterwards.
"""

MUTATIONS = {
    "task1_test1": [
        ("T_z(+L_i): the leg points up",
         "T_sym = ar601_leg(-l1, -l2, -l3).fk(list(q_sym))\n"
         "p_sym = sp.Matrix([sp.simplify(e) for e in T_sym[:3, 3]])"),
        ("the ankle point given as the foot position (the sole's L3 left out)",
         "p_sym = sp.Matrix([sp.simplify(e) for e in T_sym[:3, 3] + l3 * T_sym[:3, 2]])"),
    ],
    "task2_test1": [
        ("report_theta6 written in the y-z plane: not the report's formula",
         "def report_theta6(p, L12, L3_):\n"
         "    _, y, z = p\n"
         "    return np.arccos((y**2 + z**2 - L12**2 - L3_**2) / (2 * L12 * L3_))"),
        ("the report's answers put into the model's leg (0.3 m) instead of the report's lengths",
         "report_miss = {name: np.linalg.norm(leg.fk(theta)[:3, 3] - target)\n"
         "               for name, (target, theta) in report_cases.items()}"),
        ("the joint axes all read from the x column of the frames",
         "ax_home = np.array([F[:3, 0] for F in leg.frames(Q_HOME)[1:7]])"),
    ],
    "task3_test1": [
        ("ankle point backed off along the base z axis",
         "def ankle_point(T, L3_=L3):\n"
         "    return T[:3, 3] + np.array([0.0, 0.0, L3_])"),
        ("knee angle as the interior angle of the triangle",
         "def knee_angle(d, l1_=L1, l2_=L2):\n"
         "    return np.arccos((l1_**2 + l2_**2 - d**2) / (2 * l1_ * l2_))"),
    ],
    "task3_test2": [
        ("(q6, q5) returned instead of (q5, q6)",
         "_ankle_angles_right = ankle_angles\n\n"
         "def ankle_angles(u, q4, l1_=L1, l2_=L2):\n"
         "    return [(q6, q5) for q5, q6 in _ankle_angles_right(u, q4, l1_, l2_)]"),
        ("only one of the two arccos branches of q6",
         "_ankle_angles_right = ankle_angles\n\n"
         "def ankle_angles(u, q4, l1_=L1, l2_=L2):\n"
         "    return _ankle_angles_right(u, q4, l1_, l2_)[:1]"),
    ],
    "task3_test3": [
        ("R_H transposed",
         "_hip_angles_right = hip_angles\n\n"
         "def hip_angles(R_H):\n"
         "    return _hip_angles_right(R_H.T)"),
        ("angles returned in the order (q3, q2, q1), as rpy_from_rotation gives them",
         "_hip_angles_right = hip_angles\n\n"
         "def hip_angles(R_H):\n"
         "    return [(c, b, a) for a, b, c in _hip_angles_right(R_H)]"),
    ],
    "task3_test4": [
        ("only the positive knee branch (4 solutions)",
         "_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point):\n"
         "    return _leg_ik_right(T, ankle)[:4]"),
        ("ankle point along the base z axis inside the solver",
         "_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point):\n"
         "    return _leg_ik_right(T, lambda T: T[:3, 3] + np.array([0.0, 0.0, L3]))"),
    ],
    "task4_test1": [
        ("the solutions array instead of the result object",
         "res_goal = ar601_leg_ik(T_goal).q"),
        ("only the solutions within the limits",
         "res_goal = ar601_leg_ik(T_goal, within_limits=True)"),
        ("one knee per solution, duplicates kept",
         "distinct_knees = np.array([leg.frames(q)[4][:3, 3] for q in res_goal.q])"),
    ],
    "task5_test1": [
        ("q2 = pi/4: no gimbal lock",
         "q_lock = np.array([0.3, np.pi / 4, -0.2, 0.8, 0.1, -0.3])\n"
         "res_lock = ar601_leg_ik(leg.fk(q_lock))"),
        ("solutions counted within the joint limits only",
         "n_solutions = np.array([\n"
         "    len(ar601_leg_ik(transform(np.eye(3), [0.0, 0.0, -h]), within_limits=True))\n"
         "    for h in heights\n"
         "])"),
        ("the closed form called without within_limits=True",
         "unreachable = {name: (ar601_leg_ik(T), pair[1]) for name, (T, pair) in\n"
         "               zip(out_of_reach, zip(out_of_reach.values(), unreachable.values()))}"),
    ],
    "task6_test1": [
        ("closed form counted within the joint limits (fewer than 8)",
         "closed_all8 = [len(ar601_leg_ik(T, within_limits=True)) == 8 for T in T_bench]"),
        ("the generator compared with the first closed-form solution only",
         "found_generator = [np.abs(wrap(ar601_leg_ik(T).q[0] - q)).max() < 1e-8\n"
         "                   for q, T in zip(Q_bench, T_bench)]"),
    ],
}
