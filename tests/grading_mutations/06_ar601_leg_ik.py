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
        ("report_theta6_of_q6 returns q6: the report's formula taken at its word",
         "def report_theta6_of_q6(q6, L12, L3_):\n"
         "    return q6"),
        ("report_theta6_of_q6 with the sole's offset added along z: cos q6 + L3 sin^2 q6 / (2 L12)",
         "def report_theta6_of_q6(q6, L12, L3_):\n"
         "    return np.arccos(np.clip(np.cos(q6) + L3_ * np.sin(q6) ** 2 / (2 * L12), -1, 1))"),
    ],
    "task3_test1": [
        ("ankle point backed off along the base z axis",
         "def ankle_point(T, L3_=L3):\n"
         "    return T[:3, 3] + np.array([0.0, 0.0, L3_])"),
        ("knee angle as the interior angle of the triangle",
         "def knee_angle(d, l1_=L1, l2_=L2):\n"
         "    return np.arccos((l1_**2 + l2_**2 - d**2) / (2 * l1_ * l2_))"),
        ("no clip in the knee angle: nan for the stretched leg, where rounding puts the cosine past 1",
         "def knee_angle(d, l1_=L1, l2_=L2):\n"
         "    return np.arccos((d**2 - l1_**2 - l2_**2) / (2 * l1_ * l2_))"),
        ("a distance out of reach clipped to the stretched knee instead of nan",
         "def knee_angle(d, l1_=L1, l2_=L2):\n"
         "    return np.arccos(np.clip((d**2 - l1_**2 - l2_**2) / (2 * l1_ * l2_), -1.0, 1.0))"),
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
        ("q5 with the wrong sign (R_y taken to turn x towards z)",
         "_ankle_angles_right = ankle_angles\n\n"
         "def ankle_angles(u, q4, l1_=L1, l2_=L2):\n"
         "    return [(-q5, q6) for q5, q6 in _ankle_angles_right(u, q4, l1_, l2_)]"),
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
        ("the count of one knee sign only (4)", "k_regular = 4"),
        ("only the positive knee branch (4 solutions)",
         "_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, **steps):\n"
         "    return _leg_ik_right(T, ankle, **steps)[:4]"),
        ("ankle point along the base z axis inside the solver",
         "_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, **steps):\n"
         "    return _leg_ik_right(T, lambda T: T[:3, 3] + np.array([0.0, 0.0, L3]), **steps)"),
        ("no clip at the stretched knee: rounding leaves the stretched leg without solutions",
         "_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, **steps):\n"
         "    a = ankle(T)\n"
         "    if (a @ a - L1**2 - L2**2) / (2 * L1 * L2) > 1:\n"
         "        return np.zeros((0, 6))\n"
         "    return _leg_ik_right(T, ankle, **steps)"),
        ("R_H = (Rx(q4) Ry(q5) Rx(q6))^T R: the hip taken last in the product",
         "def my_leg_ik(T, ankle=ankle_point, knee=knee_angle, ankle_angles=ankle_angles,\n"
         "              hip_angles=hip_angles):\n"
         "    R, a = T[:3, :3], ankle(T)\n"
         "    q4_abs = knee(np.linalg.norm(a))\n"
         "    if np.isnan(q4_abs):\n"
         "        return np.zeros((0, 6))\n"
         "    sols = []\n"
         "    for q4 in (q4_abs, -q4_abs):\n"
         "        for q5, q6 in ankle_angles(R.T @ a, q4):\n"
         "            R_H = (rotx(q4) @ roty(q5) @ rotx(q6)).T @ R\n"
         "            sols += [[q1, q2, q3, q4, q5, q6] for q1, q2, q3 in hip_angles(R_H)]\n"
         "    return np.array(sols).reshape(-1, 6)"),
        ("the two hip branches counted as one posture: 4 solutions", "k_regular = 4"),
    ],
    "task4_test1": [
        ("the hip branch with cos q2 < 0 dropped (4 solutions)",
         "_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, **steps):\n"
         "    Q = _leg_ik_right(T, ankle, **steps)\n"
         "    return Q[np.cos(Q[:, 1]) > 0]"),
        ("atan2's arguments swapped in the hip angles",
         "def hip_angles(R_H):\n"
         "    out = []\n"
         "    for sign in (1, -1):\n"
         "        c2 = sign * np.hypot(R_H[0, 0], R_H[1, 0])\n"
         "        out.append((np.arctan2(R_H[0, 0] / c2, R_H[1, 0] / c2),\n"
         "                    np.arctan2(-R_H[2, 0], c2),\n"
         "                    np.arctan2(R_H[2, 2] / c2, R_H[2, 1] / c2)))\n"
         "    return out""\n\n_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, knee=knee_angle, ankle_angles=ankle_angles,\n"
         "              hip_angles=hip_angles):\n"
         "    return _leg_ik_right(T, ankle, knee, ankle_angles, hip_angles)"),
        ("the hip angles read as if R_H = Rx(q3) Ry(q2) Rz(q1)",
         "_hip_angles_right = hip_angles\n\n"
         "def hip_angles(R_H):\n"
         "    return [(-a, -b, -c) for a, b, c in _hip_angles_right(R_H.T)]""\n\n_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, knee=knee_angle, ankle_angles=ankle_angles,\n"
         "              hip_angles=hip_angles):\n"
         "    return _leg_ik_right(T, ankle, knee, ankle_angles, hip_angles)"),
        ("the solutions returned in degrees",
         "_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, **steps):\n"
         "    return np.rad2deg(_leg_ik_right(T, ankle, **steps))"),
        ("one q6 branch returned twice (8 rows, 4 different)",
         "_ankle_angles_right = ankle_angles\n\n"
         "def ankle_angles(u, q4, l1_=L1, l2_=L2):\n"
         "    pairs = _ankle_angles_right(u, q4, l1_, l2_)\n"
         "    return pairs[:1] * len(pairs)""\n\n_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, knee=knee_angle, ankle_angles=ankle_angles,\n"
         "              hip_angles=hip_angles):\n"
         "    return _leg_ik_right(T, ankle, knee, ankle_angles, hip_angles)"),
        ("the knee as the interior angle in knee_angle, my_leg_ik built on it",
         "def knee_angle(d, l1_=L1, l2_=L2):\n"
         "    return np.arccos(np.clip((l1_**2 + l2_**2 - d**2) / (2 * l1_ * l2_), -1.0, 1.0))"
         "\n\n_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, knee=knee_angle, ankle_angles=ankle_angles,\n"
         "              hip_angles=hip_angles):\n"
         "    return _leg_ik_right(T, ankle, knee, ankle_angles, hip_angles)"),
        ("q5 with the wrong sign in ankle_angles, my_leg_ik built on it",
         "_ankle_angles_right = ankle_angles\n\n"
         "def ankle_angles(u, q4, l1_=L1, l2_=L2):\n"
         "    return [(-q5, q6) for q5, q6 in _ankle_angles_right(u, q4, l1_, l2_)]""\n\n_leg_ik_right = my_leg_ik\n\n"
         "def my_leg_ik(T, ankle=ankle_point, knee=knee_angle, ankle_angles=ankle_angles,\n"
         "              hip_angles=hip_angles):\n"
         "    return _leg_ik_right(T, ankle, knee, ankle_angles, hip_angles)"),
    ],
    "task4_test2": [
        ("every configuration its own posture, duplicates included",
         "def postures_of(Q):\n"
         "    return np.reshape(Q, (-1, 6))\n\n"
         "postures = postures_of(Q_mine)"),
        ("the postures told apart by the hip point (frame 3): one posture",
         "def postures_of(Q):\n"
         "    Q = np.reshape(Q, (-1, 6))\n"
         "    hips = leg.frames(Q)[:, 3, :3, 3].round(9)\n"
         "    return Q[np.unique(hips, axis=0, return_index=True)[1]]\n\n"
         "postures = postures_of(Q_mine)"),
        ("the postures told apart by their joint angles up to full turns: 8 postures",
         "def postures_of(Q):\n"
         "    Q = np.reshape(Q, (-1, 6))\n"
         "    return Q[np.unique(wrap(Q).round(9), axis=0, return_index=True)[1]]\n\n"
         "postures = postures_of(Q_mine)"),
        ("the postures told apart by the whole joint frames, orientations too",
         "def postures_of(Q):\n"
         "    Q = np.reshape(Q, (-1, 6))\n"
         "    frames = leg.frames(Q)[:, :, :3, :].reshape(len(Q), -1).round(9)\n"
         "    return Q[np.unique(frames, axis=0, return_index=True)[1]]\n\n"
         "postures = postures_of(Q_mine)"),
        ("every solution counted as within the limits",
         "in_limits = Q_mine"),
    ],
    "task5_test1": [
        ("solutions counted within the joint limits only",
         "_sweep_right = sole_sweep\n\n"
         "def sole_sweep(heights, leg_ik=my_leg_ik):\n"
         "    counts, sigmas = _sweep_right(heights, leg_ik)\n"
         "    inside = [int(np.sum(leg.within_limits(np.reshape(\n"
         "        leg_ik(transform(np.eye(3), [0.0, 0.0, -h])), (-1, 6))))) for h in heights]\n"
         "    return np.array(inside), sigmas"),
        ("the largest singular value taken for the smallest",
         "def sole_sweep(heights, leg_ik=my_leg_ik):\n"
         "    counts, sigmas = [], []\n"
         "    for h in heights:\n"
         "        Q = leg_ik(transform(np.eye(3), [0.0, 0.0, -h]))\n"
         "        counts.append(len(Q))\n"
         "        sigmas.append(leg.singular_values(Q[0])[0] if len(Q) else np.nan)\n"
         "    return np.array(counts), np.array(sigmas)"),
        ("sigma_min taken at the last row instead of the first",
         "def sole_sweep(heights, leg_ik=my_leg_ik):\n"
         "    counts, sigmas = [], []\n"
         "    for h in heights:\n"
         "        Q = leg_ik(transform(np.eye(3), [0.0, 0.0, -h]))\n"
         "        counts.append(len(Q))\n"
         "        sigmas.append(leg.singular_values(Q[-1])[-1] if len(Q) else np.nan)\n"
         "    return np.array(counts), np.array(sigmas)"),
        ("my_leg_ik called directly: the argument leg_ik ignored",
         "_sweep_right = sole_sweep\n\n"
         "def sole_sweep(heights, leg_ik=my_leg_ik):\n"
         "    return _sweep_right(heights, my_leg_ik)"),
        ("the sole put above the hip (+h)",
         "_sweep_right = sole_sweep\n\n"
         "def sole_sweep(heights, leg_ik=my_leg_ik):\n"
         "    return _sweep_right(-np.asarray(heights), leg_ik)"),
        ("every row of the stretched leg counted as a different solution",
         "def different_solutions(Q):\n"
         "    return len(Q)"),
        ("rows compared without wrapping: full turns counted as different solutions",
         "def different_solutions(Q):\n"
         "    kept = []\n"
         "    for q in Q:\n"
         "        if all(np.abs(q - other).max() > 1e-9 for other in kept):\n"
         "            kept.append(q)\n"
         "    return len(kept)"),
        ("rows compared exactly after wrapping: copies moved by rounding counted twice",
         "def different_solutions(Q):\n"
         "    return len(np.unique(wrap(np.asarray(Q, dtype=float)), axis=0))"),
    ],
    "task5_test2": [
        ("q2 = pi/4: no gimbal lock, and the family moves q2 too",
         "q_lock = np.array([0.3, np.pi / 4, -0.2, 0.8, 0.1, -0.3])\n"
         "family = [np.array([t, np.pi / 4 + t, t - 0.5, 0.8, 0.1, -0.3]) for t in (0.0, 0.1)]"),
        ("q1 + q3 held instead of q1 - q3 (the other sign of the lock)",
         "family = [np.array([t, np.pi / 2, 0.1 - t, 0.8, 0.1, -0.3]) for t in (-0.5, 0.5)]"),
    ],
    "task5_test3": [
        ("the ankle's range not checked: every failure called too_far",
         "_reason_right = unreachable_reason\n\n"
         "def unreachable_reason(T, leg_ik=my_leg_ik):\n"
         "    reason = _reason_right(T, leg_ik)\n"
         "    return \"too_far\" if reason == \"ankle_range\" else reason\n\n"
         "unreachable = {name: (unreachable_reason(T), unreachable[name][1])\n"
         "               for name, T in out_of_reach.items()}"),
        ("the joint limits not checked",
         "_reason_right = unreachable_reason\n\n"
         "def unreachable_reason(T, leg_ik=my_leg_ik):\n"
         "    reason = _reason_right(T, leg_ik)\n"
         "    return None if reason == \"joint_limits\" else reason\n\n"
         "unreachable = {name: (unreachable_reason(T), unreachable[name][1])\n"
         "               for name, T in out_of_reach.items()}"),
    ],
    "task6_test1": [
        ("closed form counted within the joint limits (fewer than 8)",
         "closed_complete = [int(np.sum(leg.within_limits(my_leg_ik(T)))) == k_regular\n"
         "                   for T in T_bench]"),
        ("the generator compared with the first closed-form solution only",
         "found_generator = [np.abs(wrap(my_leg_ik(T)[0] - q)).max() < 1e-8\n"
         "                   for q, T in zip(Q_bench, T_bench)]"),
        ("numeric_ok compared with the generating configuration, not the closed form's",
         "numeric_ok = []\n"
         "for q, T in zip(Q_bench, T_bench):\n"
         "    num = solve_ik(leg, T, q0=Q_HOME, tol=1e-10)\n"
         "    numeric_ok.append(num.success and np.abs(wrap(num.q - q)).max() < 1e-6)"),
    ],
}
