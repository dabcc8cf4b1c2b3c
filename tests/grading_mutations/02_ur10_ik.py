"""Wrong answers that each autograded test of chapter 02 (the UR10) must reject.

Each entry rebinds names of the student's answers (functions or values) to a
typical mistake, computed in the notebook's namespace just before the test cell;
the test cell must then raise. The helpers below write the shapes that recur (an answer
function changed in one place, and the names computed from it recomputed as its answer cell
does).
"""

from textwrap import indent

#: the figures of Task 3 from ``summary``, recomputed as the answer cell does
_STATS3 = "stats3 = {(t, m): summary(cell, TARGETS[t], res.history.q) for (t, m), res in runs.items()}"

#: the figures of Task 4 from ``self_q``, recomputed as the answer cell does
_SELF_FIGURES = (
    "self_q = self_motion(cell, TARGETS['B'], runs['B', 'weighted'].q, K_SELF, 121)\n"
    "self_H = np.array([joint_limit_objective(q) for q in self_q])\n"
    "self_err = np.array([np.linalg.norm(TARGETS['B'] - cell.fk(q)[:3, 3]) for q in self_q])\n"
    "self_dist = np.min(np.minimum(self_q - WORK_LIMITS[:, 0], WORK_LIMITS[:, 1] - self_q), axis=1)"
)


def _summary_with(change: str) -> str:
    """``summary`` with some of its figures changed: ``change`` is code on the right dict ``s``
    (and ``chain``, ``p_goal``, ``path`` as an array, ``objective``); ``stats3`` is recomputed."""
    return (
        "_right_summary = summary\n"
        "def summary(chain, p_goal, path, objective=joint_limit_objective):\n"
        "    s = dict(_right_summary(chain, p_goal, path, objective))\n"
        "    path = np.asarray(path)\n"
        + indent(change, "    ") + "\n"
        "    return s\n"
        + _STATS3
    )


def _self_motion_with(update: str, record: str = "before") -> str:
    """``self_motion`` whose step is ``q = <update>`` (in terms of ``q``, ``e``, ``J``, ``N``,
    ``g`` = ∇H with the chain's limits, ``gain`` and the arguments ``projector`` and
    ``gradient``), recording ``q`` before (or after) each step; the figures of Task 4 are
    recomputed."""
    before, after = ("        path.append(q)\n", "") if record == "before" else ("", "        path.append(q)\n")
    return (
        "def self_motion(chain, p_goal, q_start, gain, steps, projector=nullspace_projector,\n"
        "                gradient=joint_limit_gradient):\n"
        "    q = np.array(q_start, dtype=float)\n"
        "    path = []\n"
        "    for step in range(steps):\n"
        + before
        + "        e = p_goal - chain.fk(q)[:3, 3]\n"
        "        J = chain.position_jacobian(q)\n"
        "        N = projector(J)\n"
        "        g = gradient(q, chain.limits)\n"
        f"        q = {update}\n"
        + after
        + "    return np.array(path)\n"
        + _SELF_FIGURES
    )


def _restarts_with(result: str) -> str:
    """``ik_restarts`` that returns ``result``, an expression of the right answer's
    ``(q, converged, attempts, iterations)``."""
    return (
        "_right_restarts = ik_restarts\n"
        "def ik_restarts(chain, p_goal, starts, step, solve=ik_position):\n"
        "    q, converged, attempts, iterations = _right_restarts(chain, p_goal, starts, step, solve)\n"
        f"    return {result}"
    )


def _bisect_with(*, no_bracket: str = "raise ValueError('same sign')",
                 loop: str = "while high - low > 2 * tol:",
                 root_right: str = "np.sign(f(middle)) == np.sign(f(low))") -> str:
    """A bisection with one part changed: what it does without a bracket, its loop, and the
    test that the root lies in [middle, high]."""
    return (
        "def bisect(f, low, high, tol=1e-13):\n"
        "    if np.sign(f(low)) == np.sign(f(high)):\n"
        f"        {no_bracket}\n"
        f"    {loop}\n"
        "        middle = 0.5 * (low + high)\n"
        f"        if {root_right}:\n"
        "            low = middle\n"
        "        else:\n"
        "            high = middle\n"
        "    return 0.5 * (low + high)"
    )


MUTATIONS = {
    "task1_test1": [
        ("lengths left in metres where millimetres are asked", "length_gap_mm = length_gap_mm / 1000"),
        ("the mean flange gap, not the largest", "length_gap_mm = 1000 * flange_gaps.mean()"),
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
        (
            "H without its factor 1/(2n)",
            "def joint_limit_objective(q, limits=WORK_LIMITS):\n"
            "    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]\n"
            "    return -np.sum(((q - middle) / span) ** 2, axis=-1)",
        ),
        (
            "H and its gradient with the ranges not normalised (consistent with each other)",
            "def joint_limit_objective(q, limits=WORK_LIMITS):\n"
            "    middle = limits.mean(axis=1)\n"
            "    return -np.sum((q - middle) ** 2, axis=-1) / (2 * len(middle))\n"
            "def joint_limit_gradient(q, limits=WORK_LIMITS):\n"
            "    return -(q - limits.mean(axis=1)) / len(limits)",
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
        (
            "the null-space gain doubled (k = n pi^2)",
            "K_NULL = len(Q0) * np.pi**2\n"
            "STEPS = {**STEPS, 'null space': lambda J, e, q: (\n"
            "    np.linalg.pinv(J) @ e + nullspace_projector(J) @ (K_NULL * joint_limit_gradient(q)))}\n"
            "loop_runs = {**loop_runs, 'c': ik_position(cell, TARGETS['B'], Q0, STEPS['null space'])}",
        ),
        ("run (c) taken with the weighted step",
         "loop_runs = {**loop_runs, 'c': ik_position(cell, TARGETS['B'], Q0, STEPS['weighted'])}"),
        (
            "ik_position left as the stub, the runs taken from robokin's solve_ik_once",
            "def ik_position(chain, p_goal, q0, step, max_step=MAX_STEP, tol=1e-9, max_iterations=100):\n"
            "    raise NotImplementedError()\n"
            "loop_runs = {}\n"
            "for run, target, options in (\n"
            "    ('a', 'A', dict(method='weighted', weights=W_DIAG)),\n"
            "    ('b', 'A', dict(method='dls', damping=np.sqrt(0.1))),\n"
            "    ('c', 'B', dict(method='nullspace', objective='joint_limits')),\n"
            "):\n"
            "    res = solve_ik_once(cell, TARGETS[target], q0=Q0, max_step=MAX_STEP, tol=1e-9, **options)\n"
            "    loop_runs[run] = (res.q, res.success, res.iterations)",
        ),
    ],
    "task3_test1": [
        ("min_w over every iterate, the start q0 included",
         _summary_with("s['min_w'] = min(s['min_w'], chain.manipulability(path[0], position_only=True))")),
        ("the path length as the distance from the start to the end",
         _summary_with("s['path'] = np.linalg.norm(path[-1] - path[0])")),
        ("the distance to the limits measured from the lower limits only",
         _summary_with("near = np.min(path - chain.limits[:, 0], axis=1)\n"
                       "s['min_limit'], s['end_limit'] = near[1:].min(), near[-1]")),
        ("H with limits other than the chain's",
         _summary_with("s['end_H'] = objective(path[-1], np.array([[-2.0, 2.0]] * 6))")),
        ("H with the default limits, not the chain's (the same on the work cell)",
         _summary_with("s['end_H'] = objective(path[-1])")),
        ("the iterates counted, not the steps", _summary_with("s['iterations'] = len(path)")),
        ("the final error left in metres", _summary_with("s['error_nm'] = s['error_nm'] / 1e9")),
    ],
    "task3_test2": [
        ("DLS read as quadratic", "convergence = {**convergence, 'DLS': 'quadratic'}"),
        ("the null-space method read as quadratic", "convergence = {**convergence, 'null space': 'quadratic'}"),
    ],
    "task4_test1": [
        ("self_q taken with half the gain", "self_q = self_motion(cell, TARGETS['B'], runs['B', 'weighted'].q, "
         "K_SELF / 2, 121)"),
        ("self_H with H's sign flipped", "self_H = -self_H"),
        ("self-motion without the J+ e correction", _self_motion_with("q + N @ (gain * g)")),
        ("the gradient not projected: the flange moves",
         _self_motion_with("q + np.linalg.pinv(J) @ e + gain * g")),
        ("the gradient's sign flipped: H falls",
         _self_motion_with("q + np.linalg.pinv(J) @ e - N @ (gain * g)")),
        ("the gain left out (k = 1)", _self_motion_with("q + np.linalg.pinv(J) @ e + N @ g")),
        ("the configurations recorded after each step",
         _self_motion_with("q + np.linalg.pinv(J) @ e + N @ (gain * g)", record="after")),
        ("grad H with the default limits, not the chain's (the same on the work cell)",
         _self_motion_with("q + np.linalg.pinv(J) @ e + N @ (gain * gradient(q))")),
    ],
    "task5_test1": [
        (
            "the steps of the last attempt only",
            "def ik_restarts(chain, p_goal, starts, step, solve=ik_position):\n"
            "    for attempts, q_start in enumerate(starts, start=1):\n"
            "        q, converged, iterations = solve(chain, p_goal, q_start, step)\n"
            "        if converged:\n"
            "            break\n"
            "    return q, converged, attempts, iterations",
        ),
        (
            "no restart: the first start only",
            "def ik_restarts(chain, p_goal, starts, step, solve=ik_position):\n"
            "    q, converged, iterations = solve(chain, p_goal, starts[0], step)\n"
            "    return q, converged, 1, iterations",
        ),
        (
            "each restart goes on from where the last attempt ended",
            "def ik_restarts(chain, p_goal, starts, step, solve=ik_position):\n"
            "    total, q = 0, starts[0]\n"
            "    for attempts in range(1, len(starts) + 1):\n"
            "        q, converged, iterations = solve(chain, p_goal, q, step)\n"
            "        total += iterations\n"
            "        if converged:\n"
            "            break\n"
            "    return q, converged, attempts, total",
        ),
        ("the attempts counted from 0", _restarts_with("q, converged, attempts - 1, iterations")),
        ("the start of the last attempt returned, not where it ended",
         _restarts_with("starts[attempts - 1], converged, attempts, iterations")),
        (
            "no stop after an attempt converged",
            "def ik_restarts(chain, p_goal, starts, step, solve=ik_position):\n"
            "    total, ever = 0, False\n"
            "    for attempts, q_start in enumerate(starts, start=1):\n"
            "        q, converged, iterations = solve(chain, p_goal, q_start, step)\n"
            "        total += iterations\n"
            "        ever = ever or converged\n"
            "    return q, ever, attempts, total",
        ),
    ],
    "task5_test2": [
        ("the weighted method to stay away from the limits",
         "recommend = {**recommend, 'position, joints away from their limits': 'weighted'}"),
        ("the null-space method for the full pose", "recommend = {**recommend, 'full pose': 'null space'}"),
    ],
    "task6_test1": [
        ("a fixed number of halvings, not the tolerance", _bisect_with(loop="for _ in range(20):")),
        ("keeps the half without the sign change",
         _bisect_with(root_right="np.sign(f(middle)) != np.sign(f(low))")),
        ("assumes f rises through its root", _bisect_with(root_right="f(middle) < 0")),
        ("no check of the bracket: a wrong answer instead of ValueError",
         _bisect_with(no_bracket="return 0.5 * (low + high)")),
        ("another error than ValueError without a bracket",
         _bisect_with(no_bracket="raise RuntimeError('same sign')")),
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
        ("step_mm taken on the metre model", "step_mm = dls_step(J_m, e_m, np.sqrt(0.1))"),
        ("the target left in metres for the millimetre robot",
         "e_mm = TARGETS['A'] - robot_mm.fk(Q0)[:3, 3]"),
        ("the metres' damping converted to mm (lambda = 1000 sqrt(0.1) mm): the same step",
         "step_mm = dls_step(J_mm, e_mm, 1000 * np.sqrt(0.1))"),
        ("lambda in metres read as sqrt(0.1) m", "lambda_in_m = np.sqrt(0.1)"),
        ("lambda in metres as lambda^2 / 1000", "lambda_in_m = 0.1 / 1000"),
    ],
}

#: answers computed another way, which must keep full marks (the trust suite reads them for a
#: chapter that tests/support/benign_variants.py does not list; each one also passes its registered check,
#: tests/test_check_ur10.py)
VARIANTS = {
    "task2_answer1": ("the weighted pseudoinverse by two linear solves, no inverse", '''

def weighted_pinv(J, W):  # written another way: X = W^-1 J^T, then X (J X)^-1 by solving
    X = np.linalg.solve(W, J.T)
    return np.linalg.solve((J @ X).T, X.T).T
'''),
    "task2_answer2": ("the damped step from the normal equations (J^T J + lambda^2 I) dq = J^T e", '''

def dls_step(J, e, damping):  # written another way: the n x n normal equations, not J J^T
    return np.linalg.solve(J.T @ J + damping**2 * np.eye(J.shape[1]), J.T @ e)
'''),
    "task2_answer3": ("the null-space projector from the SVD: V_0 V_0^T", '''

def nullspace_projector(J):  # written another way: the right singular vectors of sigma = 0
    _, sigma, Vt = np.linalg.svd(J)
    rank = int(np.sum(sigma > sigma.max() * max(J.shape) * np.finfo(float).eps))
    kernel = Vt[rank:]
    return kernel.T @ kernel


def joint_limit_objective(q, limits=WORK_LIMITS):  # written another way: half ranges, einsum
    half = (limits[:, 1] - limits[:, 0]) / 2
    x = (np.asarray(q, dtype=float) - (limits[:, 0] + half)) / (2 * half)
    return -np.einsum("...i,...i->...", x, x) / (2 * limits.shape[0])


def joint_limit_gradient(q, limits=WORK_LIMITS):  # written another way: weights 1/range^2
    weights = 1.0 / np.diff(limits, axis=1)[:, 0] ** 2
    return weights * (limits.mean(axis=1) - np.asarray(q, dtype=float)) / len(limits)
'''),
    "task2_answer5": ("the DLS rule of STEPS as a least-squares problem [J; lambda I] dq = [e; 0]", '''

# written another way: the damped step of STEPS as min |J dq - e|^2 + lambda^2 |dq|^2
STEPS = dict(STEPS, DLS=lambda J, e, q: np.linalg.lstsq(
    np.vstack([J, LAMBDA * np.eye(J.shape[1])]), np.r_[e, np.zeros(J.shape[1])], rcond=None)[0])
loop_runs = dict(loop_runs, b=ik_position(cell, TARGETS["A"], Q0, STEPS["DLS"]))
'''),
    "task3_answer1": ("the figures with robokin's measures of a run and a cumulative sum", '''

def summary(chain, p_goal, path, objective=joint_limit_objective):  # another way: robokin's measures
    path = np.asarray(path, dtype=float)
    gaps = np.concatenate([path - chain.limits[:, 0], chain.limits[:, 1] - path], axis=1)
    nearest = gaps.min(axis=1)
    w = chain.manipulability(path, position_only=True)
    travelled = np.cumsum(np.linalg.norm(path[1:] - path[:-1], axis=1))
    return {
        "iterations": len(path) - 1,
        "error_nm": float(np.sqrt(np.sum((p_goal - chain.fk(path[-1])[:3, 3]) ** 2))) * 1e9,
        "path": travelled[-1],
        "min_limit": np.sort(nearest[1:])[0],
        "end_limit": nearest[-1],
        "end_H": objective(path[-1], limits=chain.limits),
        "min_w": np.sort(w[1:])[0],
        "end_w": w[-1],
    }


stats3 = {key: summary(cell, TARGETS[key[0]], run.history.q) for key, run in runs.items()}
'''),
    "task4_answer1": ("self-motion with a preallocated array and the projector from the SVD", '''

def self_motion(chain, p_goal, q_start, gain, steps, projector=nullspace_projector,
                gradient=joint_limit_gradient):  # written another way: rows filled in place
    rows = np.empty((steps, len(q_start)))
    q = np.asarray(q_start, dtype=float)
    for i in range(steps):
        rows[i] = q
        J = chain.position_jacobian(q)
        kernel = np.linalg.svd(J)[2][J.shape[0]:]  # full row rank: the null space of J
        correction = np.linalg.lstsq(J, p_goal - chain.fk(q)[:3, 3], rcond=None)[0]
        q = q + correction + kernel.T @ (kernel @ (gain * gradient(q, chain.limits)))
    return rows


self_q = self_motion(cell, TARGETS["B"], runs["B", "weighted"].q, K_SELF, 121)
self_H = np.array([joint_limit_objective(q) for q in self_q])
self_err = np.array([np.linalg.norm(TARGETS["B"] - cell.fk(q)[:3, 3]) for q in self_q])
self_JN = np.array([
    np.abs(J @ nullspace_projector(J)).max()
    for J in (cell.position_jacobian(q) for q in self_q)
])
self_dist = np.min(np.minimum(self_q - WORK_LIMITS[:, 0], WORK_LIMITS[:, 1] - self_q), axis=1)
'''),
    "task5_answer1": ("the restarts by recursion on the remaining starts", '''

def ik_restarts(chain, p_goal, starts, step, solve=ik_position):  # written another way: recursion
    q, converged, iterations = solve(chain, p_goal, starts[0], step)
    if converged or len(starts) == 1:
        return q, converged, 1, iterations
    q, converged, attempts, more = ik_restarts(chain, p_goal, starts[1:], step, solve)
    return q, converged, attempts + 1, iterations + more
'''),
    "task6_answer1": ("bisection by recursion on the bracket", '''

def bisect(f, low, high, tol=1e-13):  # written another way: recursion, signs by comparison
    f_low, f_high = f(low), f(high)
    if (f_low > 0) == (f_high > 0) and f_low != 0 and f_high != 0:
        raise ValueError(f"f({low}) and f({high}) have the same sign")
    if f_low == 0:
        return low
    if f_high == 0:
        return high
    middle = low + (high - low) / 2
    if high - low <= 2 * tol or middle in (low, high):
        return middle
    if (f(middle) > 0) == (f_low > 0):
        return bisect(f, middle, high, tol)
    return bisect(f, low, middle, tol)
'''),
}
