"""Wrong answers that each autograded test of chapter 02 (the UR10) must reject.

Each entry rebinds names of the student's answers (functions or values) to a
typical mistake, computed in the notebook's namespace just before the test cell;
the test cell must then raise.
"""

MUTATIONS = {
    "task1_test1": [
        ("lengths left in metres where millimetres are asked", "length_gap_mm = length_gap_mm / 1000"),
        (
            "the manufacturer's signs instead of the exercise's",
            "ex_conventions = from_dh(UR10_DH)\n"
            "convention_gap = np.abs(\n"
            "    ex_conventions.fk(Q_compare) - T_flip @ robot.fk(Q_compare) @ np.linalg.inv(T_flip)\n"
            ").max()",
        ),
    ],
    "task1_test2": [
        (
            "alpha_1, alpha_4, alpha_5 not flipped (the manufacturer's signs)",
            "def exercise_table(d1, a2, a3, d4, d5, d6):\n"
            "    return [[d1, 0, 0, np.pi / 2], [0, 0, a2, 0], [0, 0, a3, 0],\n"
            "            [d4, 0, 0, np.pi / 2], [d5, 0, 0, -np.pi / 2], [d6, 0, 0, 0]]\n"
            "ex_conventions = from_dh(exercise_table(*ur_lengths))",
        ),
    ],
    "task2_test1": [
        ("W where W^-1 belongs", "weighted_pinv = lambda J, W: W @ J.T @ np.linalg.inv(J @ W @ J.T)"),
        ("weights applied after the plain pseudoinverse",
         "weighted_pinv = lambda J, W: np.linalg.inv(W) @ np.linalg.pinv(J)"),
    ],
    "task2_test2": [
        ("lambda where lambda^2 belongs",
         "dls_step = lambda J, e, damping: J.T @ np.linalg.solve(J @ J.T + damping * np.eye(J.shape[0]), e)"),
        ("lambda^2 = 0.1 read in mm^2 (lambda = sqrt(0.1)/1000 m)", "LAMBDA = np.sqrt(0.1) / 1000"),
    ],
    "task2_test3": [
        ("J+ J, the projector onto the row space", "nullspace_projector = lambda J: np.linalg.pinv(J) @ J"),
        (
            "the gradient's sign flipped (descends H)",
            "def joint_limit_gradient(q, limits=WORK_LIMITS):\n"
            "    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]\n"
            "    return (q - middle) / span**2 / len(middle)",
        ),
    ],
    "task2_test4": [
        (
            "no step cap in the loop",
            "def ik_position(chain, p_goal, q0, step, max_step=MAX_STEP, tol=1e-9, max_iterations=100):\n"
            "    lower, upper = chain.limits[:, 0], chain.limits[:, 1]\n"
            "    q = np.array(q0, dtype=float)\n"
            "    e = p_goal - chain.fk(q)[:3, 3]\n"
            "    iterations = 0\n"
            "    while np.linalg.norm(e) > tol and iterations < max_iterations:\n"
            "        q = np.clip(q + step(chain.position_jacobian(q), e, q), lower, upper)\n"
            "        e = p_goal - chain.fk(q)[:3, 3]\n"
            "        iterations += 1\n"
            "    return q, bool(np.linalg.norm(e) <= tol), iterations\n"
            "loop_runs = {\n"
            "    'a': ik_position(cell, TARGETS['A'], Q0, STEPS['weighted']),\n"
            "    'b': ik_position(cell, TARGETS['A'], Q0, STEPS['DLS']),\n"
            "    'c': ik_position(cell, TARGETS['B'], Q0, STEPS['null space']),\n"
            "}",
        ),
        (
            "the error's sign flipped (e = p(q) - p_goal)",
            "loop_runs = {\n"
            "    run: ik_position(cell, TARGETS[t], Q0, lambda J, e, q, s=STEPS[m]: s(J, -e, q))\n"
            "    for run, t, m in (('a', 'A', 'weighted'), ('b', 'A', 'DLS'), ('c', 'B', 'null space'))\n"
            "}",
        ),
        (
            "the null-space term not projected (k grad H added to the step)",
            "STEPS = {**STEPS, 'null space': lambda J, e, q: (\n"
            "    np.linalg.pinv(J) @ e + K_NULL * joint_limit_gradient(q))}\n"
            "loop_runs = {**loop_runs, 'c': ik_position(cell, TARGETS['B'], Q0, STEPS['null space'])}",
        ),
    ],
    "task3_test1": [
        (
            "min_w includes the start q0",
            "stats3 = {key: {**s, 'min_w': min(s['min_w'], robot.manipulability(Q0, position_only=True))}\n"
            "          for key, s in stats3.items()}",
        ),
        (
            "own gradient as the objective with the gain k = 1: the null-space runs stall",
            "METHODS3 = {**METHODS3, 'null space': dict(method='nullspace', objective=joint_limit_gradient,\n"
            "                                           gain=1.0)}\n"
            "runs = {(t, m): solve_ik_once(cell, TARGETS[t], q0=Q0, max_step=MAX_STEP,\n"
            "                              tol=1e-9, **METHODS3[m]) for t in TARGETS for m in METHODS3}\n"
            "stats3 = {key: summary(res) for key, res in runs.items()}",
        ),
    ],
    "task4_test1": [
        (
            "self-motion without the J+ e correction",
            "q = runs['B', 'weighted'].q.copy()\n"
            "self_q, self_H, self_err, self_JN = [], [], [], []\n"
            "for step in range(121):\n"
            "    e = TARGETS['B'] - cell.fk(q)[:3, 3]\n"
            "    J = cell.position_jacobian(q)\n"
            "    N = nullspace_projector(J)\n"
            "    self_q.append(q)\n"
            "    self_H.append(joint_limit_objective(q))\n"
            "    self_err.append(np.linalg.norm(e))\n"
            "    self_JN.append(np.abs(J @ N).max())\n"
            "    q = q + N @ (K_SELF * joint_limit_gradient(q))\n"
            "self_q, self_H, self_err = np.array(self_q), np.array(self_H), np.array(self_err)\n"
            "self_dist = np.min(np.minimum(self_q - WORK_LIMITS[:, 0], WORK_LIMITS[:, 1] - self_q), axis=1)",
        ),
    ],
    "task5_test1": [
        (
            "the position targets solved for the pose task too",
            "batch = {(task, m): solve_ik_batch(cell, TASKS['position'], q0=Q0, max_step=MAX_STEP, tol=1e-9,\n"
            "                                   seed=0, polish=False, **opts)\n"
            "         for task in TASKS for m, opts in METHODS5.items()}",
        ),
    ],
    "task6_test1": [
        ("the flange point instead of the wrist point", "wrist_point = lambda q: robot.fk(q)[:3, 3]"),
        ("the two singular values swapped (J_v first)",
         "sigma_min = {name: (s3, s6) for name, (s6, s3) in sigma_min.items()}"),
    ],
    "task6_test2": [
        (
            "stall_iterations=300 not passed: slow runs end after 20 iterations",
            "crossing = {}\n"
            "for name, j in CROSS_JOINT.items():\n"
            "    delta = 0.05 * np.eye(6)[j]\n"
            "    for m, opts in CROSS_METHODS.items():\n"
            "        crossing[name, m] = solve_ik_once(robot, robot.fk(SINGULAR[name] + delta),\n"
            "                                          q0=SINGULAR[name] - delta,\n"
            "                                          tol=1e-9, max_iterations=300, **opts)",
        ),
    ],
    "task6_test3": [
        ("the target left in metres for the millimetre robot",
         "e_mm = TARGETS['A'] - robot_mm.fk(Q0)[:3, 3]"),
        ("the metres' damping converted to mm (lambda = 1000 sqrt(0.1) mm): the same step",
         "step_mm = dls_step(J_mm, e_mm, 1000 * np.sqrt(0.1))"),
    ],
}
