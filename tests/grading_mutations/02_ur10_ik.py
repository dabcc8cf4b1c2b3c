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
            "min_w over every iterate, the start q0 included",
            "_right_summary = summary\n"
            "def summary(chain, p_goal, path):\n"
            "    s = dict(_right_summary(chain, p_goal, path))\n"
            "    s['min_w'] = min(s['min_w'], chain.manipulability(path[0], position_only=True))\n"
            "    return s\n"
            "stats3 = {(t, m): summary(cell, TARGETS[t], res.history.q) for (t, m), res in runs.items()}",
        ),
        (
            "the path length as the distance from the start to the end",
            "_right_summary = summary\n"
            "def summary(chain, p_goal, path):\n"
            "    s = dict(_right_summary(chain, p_goal, path))\n"
            "    s['path'] = np.linalg.norm(np.asarray(path)[-1] - np.asarray(path)[0])\n"
            "    return s\n"
            "stats3 = {(t, m): summary(cell, TARGETS[t], res.history.q) for (t, m), res in runs.items()}",
        ),
        (
            "the distance to the limits measured from the lower limits only",
            "_right_summary = summary\n"
            "def summary(chain, p_goal, path):\n"
            "    s = dict(_right_summary(chain, p_goal, path))\n"
            "    near = np.min(np.asarray(path) - chain.limits[:, 0], axis=1)\n"
            "    s['min_limit'], s['end_limit'] = near[1:].min(), near[-1]\n"
            "    return s\n"
            "stats3 = {(t, m): summary(cell, TARGETS[t], res.history.q) for (t, m), res in runs.items()}",
        ),
        (
            "H with limits other than the chain's",
            "_right_summary = summary\n"
            "def summary(chain, p_goal, path):\n"
            "    s = dict(_right_summary(chain, p_goal, path))\n"
            "    s['end_H'] = joint_limit_objective(np.asarray(path)[-1], np.array([[-2.0, 2.0]] * 6))\n"
            "    return s\n"
            "stats3 = {(t, m): summary(cell, TARGETS[t], res.history.q) for (t, m), res in runs.items()}",
        ),
    ],
    "task3_test2": [
        ("DLS read as quadratic", "convergence = {**convergence, 'DLS': 'quadratic'}"),
        ("the null-space method read as quadratic", "convergence = {**convergence, 'null space': 'quadratic'}"),
    ],
    "task4_test1": [
        (
            "self-motion without the J+ e correction",
            "def self_motion(chain, p_goal, q_start, gain, steps):\n"
            "    q = np.array(q_start, dtype=float)\n"
            "    path = []\n"
            "    for step in range(steps):\n"
            "        path.append(q)\n"
            "        e = p_goal - chain.fk(q)[:3, 3]\n"
            "        J = chain.position_jacobian(q)\n"
            "        N = nullspace_projector(J)\n"
            "        g = joint_limit_gradient(q, chain.limits)\n"
            "        q = q + N @ (gain * g)\n"
            "    return np.array(path)\n"
            "self_q = self_motion(cell, TARGETS['B'], runs['B', 'weighted'].q, K_SELF, 121)\n"
            "self_H = np.array([joint_limit_objective(q) for q in self_q])\n"
            "self_err = np.array([np.linalg.norm(TARGETS['B'] - cell.fk(q)[:3, 3]) for q in self_q])\n"
            "self_dist = np.min(np.minimum(self_q - WORK_LIMITS[:, 0], WORK_LIMITS[:, 1] - self_q), axis=1)",
        ),
        (
            "the gradient not projected: the flange moves",
            "def self_motion(chain, p_goal, q_start, gain, steps):\n"
            "    q = np.array(q_start, dtype=float)\n"
            "    path = []\n"
            "    for step in range(steps):\n"
            "        path.append(q)\n"
            "        e = p_goal - chain.fk(q)[:3, 3]\n"
            "        J = chain.position_jacobian(q)\n"
            "        N = nullspace_projector(J)\n"
            "        g = joint_limit_gradient(q, chain.limits)\n"
            "        q = q + np.linalg.pinv(J) @ e + gain * g\n"
            "    return np.array(path)\n"
            "self_q = self_motion(cell, TARGETS['B'], runs['B', 'weighted'].q, K_SELF, 121)\n"
            "self_H = np.array([joint_limit_objective(q) for q in self_q])\n"
            "self_err = np.array([np.linalg.norm(TARGETS['B'] - cell.fk(q)[:3, 3]) for q in self_q])\n"
            "self_dist = np.min(np.minimum(self_q - WORK_LIMITS[:, 0], WORK_LIMITS[:, 1] - self_q), axis=1)",
        ),
        (
            "the gradient's sign flipped: H falls",
            "def self_motion(chain, p_goal, q_start, gain, steps):\n"
            "    q = np.array(q_start, dtype=float)\n"
            "    path = []\n"
            "    for step in range(steps):\n"
            "        path.append(q)\n"
            "        e = p_goal - chain.fk(q)[:3, 3]\n"
            "        J = chain.position_jacobian(q)\n"
            "        N = nullspace_projector(J)\n"
            "        g = joint_limit_gradient(q, chain.limits)\n"
            "        q = q + np.linalg.pinv(J) @ e - N @ (gain * g)\n"
            "    return np.array(path)\n"
            "self_q = self_motion(cell, TARGETS['B'], runs['B', 'weighted'].q, K_SELF, 121)\n"
            "self_H = np.array([joint_limit_objective(q) for q in self_q])\n"
            "self_err = np.array([np.linalg.norm(TARGETS['B'] - cell.fk(q)[:3, 3]) for q in self_q])\n"
            "self_dist = np.min(np.minimum(self_q - WORK_LIMITS[:, 0], WORK_LIMITS[:, 1] - self_q), axis=1)",
        ),
        (
            "the gain left out (k = 1)",
            "def self_motion(chain, p_goal, q_start, gain, steps):\n"
            "    q = np.array(q_start, dtype=float)\n"
            "    path = []\n"
            "    for step in range(steps):\n"
            "        path.append(q)\n"
            "        e = p_goal - chain.fk(q)[:3, 3]\n"
            "        J = chain.position_jacobian(q)\n"
            "        N = nullspace_projector(J)\n"
            "        g = joint_limit_gradient(q, chain.limits)\n"
            "        q = q + np.linalg.pinv(J) @ e + N @ g\n"
            "    return np.array(path)\n"
            "self_q = self_motion(cell, TARGETS['B'], runs['B', 'weighted'].q, K_SELF, 121)\n"
            "self_H = np.array([joint_limit_objective(q) for q in self_q])\n"
            "self_err = np.array([np.linalg.norm(TARGETS['B'] - cell.fk(q)[:3, 3]) for q in self_q])\n"
            "self_dist = np.min(np.minimum(self_q - WORK_LIMITS[:, 0], WORK_LIMITS[:, 1] - self_q), axis=1)",
        ),
    ],
    "task5_test1": [
        (
            "the steps of the last attempt only",
            "def ik_restarts(chain, p_goal, starts, step):\n"
            "    for attempts, q_start in enumerate(starts, start=1):\n"
            "        q, converged, iterations = ik_position(chain, p_goal, q_start, step)\n"
            "        if converged:\n"
            "            break\n"
            "    return q, converged, attempts, iterations",
        ),
        (
            "no restart: the first start only",
            "def ik_restarts(chain, p_goal, starts, step):\n"
            "    q, converged, iterations = ik_position(chain, p_goal, starts[0], step)\n"
            "    return q, converged, 1, iterations",
        ),
        (
            "each restart goes on from where the last attempt ended",
            "def ik_restarts(chain, p_goal, starts, step):\n"
            "    total, q = 0, starts[0]\n"
            "    for attempts in range(1, len(starts) + 1):\n"
            "        q, converged, iterations = ik_position(chain, p_goal, q, step)\n"
            "        total += iterations\n"
            "        if converged:\n"
            "            break\n"
            "    return q, converged, attempts, total",
        ),
        (
            "the attempts counted from 0",
            "_right_restarts = ik_restarts\n"
            "def ik_restarts(chain, p_goal, starts, step):\n"
            "    q, converged, attempts, iterations = _right_restarts(chain, p_goal, starts, step)\n"
            "    return q, converged, attempts - 1, iterations",
        ),
    ],
    "task5_test2": [
        ("the weighted method to stay away from the limits",
         "recommend = {**recommend, 'position, joints away from their limits': 'weighted'}"),
        ("the null-space method for the full pose", "recommend = {**recommend, 'full pose': 'null space'}"),
    ],
    "task6_test1": [
        (
            "a fixed number of halvings, not the tolerance",
            "def bisect(f, low, high, tol=1e-13):\n"
            "    if np.sign(f(low)) == np.sign(f(high)):\n"
            "        raise ValueError('same sign')\n"
            "    for _ in range(20):\n"
            "        middle = 0.5 * (low + high)\n"
            "        if np.sign(f(middle)) == np.sign(f(low)):\n"
            "            low = middle\n"
            "        else:\n"
            "            high = middle\n"
            "    return 0.5 * (low + high)",
        ),
        (
            "keeps the half without the sign change",
            "def bisect(f, low, high, tol=1e-13):\n"
            "    if np.sign(f(low)) == np.sign(f(high)):\n"
            "        raise ValueError('same sign')\n"
            "    while high - low > 2 * tol:\n"
            "        middle = 0.5 * (low + high)\n"
            "        if np.sign(f(middle)) == np.sign(f(low)):\n"
            "            high = middle\n"
            "        else:\n"
            "            low = middle\n"
            "    return 0.5 * (low + high)",
        ),
        (
            "assumes f rises through its root",
            "def bisect(f, low, high, tol=1e-13):\n"
            "    if np.sign(f(low)) == np.sign(f(high)):\n"
            "        raise ValueError('same sign')\n"
            "    while high - low > 2 * tol:\n"
            "        middle = 0.5 * (low + high)\n"
            "        if f(middle) < 0:\n"
            "            low = middle\n"
            "        else:\n"
            "            high = middle\n"
            "    return 0.5 * (low + high)",
        ),
        (
            "no check of the bracket: a wrong answer instead of ValueError",
            "_right_bisect = bisect\n"
            "def bisect(f, low, high, tol=1e-13):\n"
            "    if np.sign(f(low)) == np.sign(f(high)):\n"
            "        return 0.5 * (low + high)\n"
            "    return _right_bisect(f, low, high, tol)",
        ),
    ],
    "task6_test2": [
        ("the flange point instead of the wrist point", "wrist_point = lambda q: robot.fk(q)[:3, 3]"),
        ("the two singular values swapped (J_v first)",
         "sigma_min = {name: (s3, s6) for name, (s6, s3) in sigma_min.items()}"),
        (
            "in_plane_distance changes the caller's q",
            "def in_plane_distance(q2, q):\n"
            "    q[1] = q2\n"
            "    p = wrist_point(q)\n"
            "    return p[0] * np.cos(q[0]) + p[1] * np.sin(q[0])",
        ),
        (
            "the smallest singular value of J_v^T J_v (sigma squared)",
            "sigma_min = {name: (s6, s3**2) for name, (s6, s3) in sigma_min.items()}",
        ),
    ],
    "task6_test3": [
        ("the target left in metres for the millimetre robot",
         "e_mm = TARGETS['A'] - robot_mm.fk(Q0)[:3, 3]"),
        ("the metres' damping converted to mm (lambda = 1000 sqrt(0.1) mm): the same step",
         "step_mm = dls_step(J_mm, e_mm, 1000 * np.sqrt(0.1))"),
        ("lambda in metres read as sqrt(0.1) m", "lambda_in_m = np.sqrt(0.1)"),
        ("lambda in metres as lambda^2 / 1000", "lambda_in_m = 0.1 / 1000"),
    ],
}
