"""Wrong answers that each autograded test of the chapter must reject (``MUTATIONS``,
tests/test_grading_mutations.py), and correct answers written another way that must keep
full marks (``VARIANTS``, tests/support/benign_variants.py and tests/test_grading_trust.py).

``MUTATIONS``: ``{grade id of a test cell: [(what is wrong, code appended to the answer
cells), ...]}``, at least one per graded test. ``VARIANTS``: ``{grade id of an answer cell:
(how it differs, code appended to that cell)}``: another method, not only other names
(without ``VARIANTS``, the trust suite derives a weaker default: each answer wrapped).
The first line of each variant's code must be ASCII without quotes.
"""

_SHOULDER = """
def shoulder_angles(T, wrist_centre=wrist_centre):
    x, y, _ = wrist_centre(T)
    r = np.hypot(x, y)
    if r < abs(D4):
        return np.zeros(0)
    psi, beta = {psi}, np.arccos({d4} / r)
    return wrap({rows})
"""

_WRIST = """
def wrist_angles(T, q1):
    z1 = np.array([np.sin(q1), -np.cos(q1), 0.0])
    x6z, y6z, c5 = T[:3, :3].T @ z1
    rows = []
    for sign in {signs}:
        s5 = sign * np.hypot(x6z, y6z)
        rows.append([np.arctan2(s5, c5), {q6}])
    return wrap(rows)
"""

_ARM = """
def arm_angles(T, q1, q5, q6, wrist_centre=wrist_centre):
    R = T[:3, :3]
    c1, s1, c5, s5 = np.cos(q1), np.sin(q1), np.cos(q5), np.sin(q5)
    z4 = R @ [-np.sin(q6), -np.cos(q6), 0.0]
    x4 = R @ [c5 * np.cos(q6), -c5 * np.sin(q6), -s5]
    p4 = wrist_centre(T) - {d5} * z4
    a2, a3 = {a2}, {a3}
    X, Y = c1 * p4[0] + s1 * p4[1], p4[2] - D1
    c3 = (X**2 + Y**2 - a2**2 - a3**2) / (2 * a2 * a3)
    if abs(c3) > 1:
        return np.zeros((0, 3))
    phi = np.arctan2(x4[2], c1 * x4[0] + s1 * x4[1])
    rows = []
    for q3 in {elbows}:
        q2 = np.arctan2(Y, X) - np.arctan2(a3 * np.sin(q3), a2 + a3 * np.cos(q3))
        rows.append([q2, q3, phi - q2 - q3])
    return wrap(rows)
"""

_LOOP = """
def all_solutions(T, shoulder_angles=shoulder_angles, wrist_angles=wrist_angles, arm_angles=arm_angles):
    solutions = []
    shoulders = shoulder_angles(T)
    for q1 in shoulders:
        for q5, q6 in {wrist}:
            for q2, q3, q4 in arm_angles(T, q1, q5, q6):
                q = np.array({row})
                if np.abs(robot.fk(q) - T).max() < 1e-9:
                    solutions.append(q)
    return np.array(solutions).reshape(-1, 6)


Q_goal = all_solutions(T_goal)
"""

_DEGREES = "(lambda f: lambda *args, **steps: np.rad2deg(np.asarray(f(*args, **steps), dtype=float)))({name})"


def _shoulder(psi="np.arctan2(y, x)", d4="D4", rows="[psi + np.pi / 2 + beta, psi + np.pi / 2 - beta]"):
    return _SHOULDER.format(psi=psi, d4=d4, rows=rows)


def _wrist(signs="(1, -1)", q6="np.arctan2(-y6z / s5, x6z / s5)"):
    return _WRIST.format(signs=signs, q6=q6)


def _arm(d5="D5", a2="A2", a3="A3", elbows="(np.arccos(c3), -np.arccos(c3))"):
    return _ARM.format(d5=d5, a2=a2, a3=a3, elbows=elbows)


def _loop(wrist="wrist_angles(T, q1)", row="[q1, q2, q3, q4, q5, q6]"):
    return _LOOP.format(wrist=wrist, row=row)


MUTATIONS = {
    "task1_test1": [
        ("the flange position for the wrist centre", "def wrist_centre(T):\n    return T[:3, 3].copy()"),
        ("d6 added instead of subtracted", "def wrist_centre(T):\n    return T[:3, 3] + D6 * T[:3, 2]"),
        ("the third row of R for z6", "def wrist_centre(T):\n    return T[:3, 3] - D6 * T[2, :3]"),
    ],
    "task1_test2": [
        ("one shoulder branch dropped", _shoulder(rows="[psi + np.pi / 2 + beta]")),
        ("the arguments of atan2 swapped", _shoulder(psi="np.arctan2(x, y)")),
        ("the sign of d4", _shoulder(d4="-D4")),
        ("degrees for radians", "shoulder_angles = " + _DEGREES.format(name="shoulder_angles")),
        ("the flange point for the wrist centre",
         "shoulder_angles = (lambda f: lambda T, **steps: f(np.vstack([np.c_[T[:3, :3], T[:3, 3] + D6 * T[:3, 2]], "
         "T[3:]]), **steps))(shoulder_angles)"),
    ],
    "task1_test3": [
        ("the two q1 taken to coincide on the base axis", "r_shoulder = 0.0"),
        ("the flange offset d6 added to d4", "r_shoulder = abs(D4) + D6"),
    ],
    "task2_test1": [
        ("one wrist branch dropped", _wrist(signs="(1,)")),
        ("the arguments of atan2 swapped in q6", _wrist(q6="np.arctan2(x6z / s5, -y6z / s5)")),
        ("the sign of q6", _wrist(q6="np.arctan2(y6z / s5, x6z / s5)")),
        ("degrees for radians", "wrist_angles = " + _DEGREES.format(name="wrist_angles")),
        ("the second wrist branch as (-q5, q6)",
         "wrist_angles = (lambda f: lambda T, q1: np.array([f(T, q1)[0], f(T, q1)[0] * [-1, 1]]))(wrist_angles)"),
    ],
    "task2_test2": [
        ("q5 = pi forgotten", "q5_singular = [0.0]"),
        ("the wrist at cos q5 = 0", "q5_singular = [np.pi / 2, -np.pi / 2]"),
        ("an angle where q6 is defined added", "q5_singular = [0.0, np.pi, np.pi / 2]"),
    ],
    "task3_test1": [
        ("positive a2 and a3", _arm(a2="abs(A2)", a3="abs(A3)")),
        ("one elbow branch dropped", _arm(elbows="(np.arccos(c3),)")),
        ("the wrist centre for p4", _arm(d5="0.0")),
        ("degrees for radians", "arm_angles = " + _DEGREES.format(name="arm_angles")),
    ],
    "task4_test1": [
        ("only the first shoulder solution",
         "all_solutions = (lambda f: lambda T, **steps: np.asarray(f(T, **steps)).reshape(-1, 6)[:4])"
         "(all_solutions)\nQ_goal = all_solutions(T_goal)"),
        ("every solution twice",
         "all_solutions = (lambda f: lambda T, **steps: np.tile(np.asarray(f(T, **steps)).reshape(-1, 6), (2, 1)))"
         "(all_solutions)\nQ_goal = all_solutions(T_goal)"),
        ("degrees for radians",
         "all_solutions = " + _DEGREES.format(name="all_solutions") + "\nQ_goal = all_solutions(T_goal)"),
        ("unverified candidates kept (a wrong wrist branch)",
         "all_solutions = (lambda f: lambda T, **steps: np.vstack([np.asarray(f(T, **steps)).reshape(-1, 6), "
         "np.asarray(f(T, **steps)).reshape(-1, 6)[:1] + [0, 0, 0, 0, 0, 0.5]]))(all_solutions)\n"
         "Q_goal = all_solutions(T_goal)"),
        ("the wrist solutions of the first q1 used for both shoulder solutions",
         _loop(wrist="wrist_angles(T, shoulders[0])")),
        ("q5 and q6 swapped in the assembled configuration", _loop(row="[q1, q2, q3, q4, q6, q5]")),
        ("Q_goal stored with the first shoulder solution only",
         "Q_goal = np.asarray(all_solutions(T_goal)).reshape(-1, 6)[:4]"),
    ],
    "task5_test1": [
        ("the wrist at cos q5 = 0",
         "coinciding_branches = (lambda f: lambda q, **steps: [n for n in f(q, **steps) if n != 'wrist']"
         " + (['wrist'] if abs(np.cos(q[4])) < 1e-9 else []))(coinciding_branches)"),
        ("the elbow forgotten",
         "coinciding_branches = (lambda f: lambda q, **steps: [n for n in f(q, **steps) if n != 'elbow'])"
         "(coinciding_branches)"),
        ("the shoulder from the flange position",
         "coinciding_branches = (lambda f: lambda q, **steps: [n for n in f(q, **steps) if n != 'shoulder']"
         " + (['shoulder'] if abs(np.hypot(*robot.fk(q)[:2, 3]) - abs(D4)) < 1e-9 else []))"
         "(coinciding_branches)"),
        ("every configuration singular",
         "coinciding_branches = lambda q, **steps: ['shoulder', 'wrist', 'elbow']"),
    ],
}

VARIANTS = {
    "task1_answer1": ("q1 from arcsin and the wrist centre as a homogeneous point", """

# written another way: r sin(q1 - psi) = d4 solved with arcsin, p5 = T (0, 0, -d6, 1)
def wrist_centre(T):
    return (np.asarray(T, dtype=float) @ np.array([0.0, 0.0, -D6, 1.0]))[:3]


def shoulder_angles(T, wrist_centre=wrist_centre):
    centre = wrist_centre(T)
    r = float(np.hypot(centre[0], centre[1]))
    if r < abs(D4):
        return np.zeros(0)
    psi = float(np.arctan2(centre[1], centre[0]))
    first = np.arcsin(D4 / r)
    return wrap(np.array([psi + first, psi + np.pi - first]))
"""),
    "task2_answer1": ("q5 from arccos and q6 with the sign of sin q5 moved out", """

# written another way: q5 = +-arccos(c5), q6 from atan2 of the signed components
def wrist_angles(T, q1):
    axis = np.array([np.sin(q1), -np.cos(q1), 0.0])
    along_x, along_y, along_z = np.asarray(T, dtype=float)[:3, :3].T @ axis
    first = np.arccos(np.clip(along_z, -1.0, 1.0))
    q6_first = np.arctan2(-along_y, along_x)
    return wrap(np.array([[first, q6_first], [-first, q6_first + np.pi]]))
"""),
    "task3_answer1": ("the planar problem with complex numbers, angles in [0, 2 pi)", """

# written another way: the plane of the arm as the complex plane, the links as a2 + a3 e^(i q3),
# the wrist centre from T itself (the argument wrist_centre not called)
def arm_angles(T, q1, q5, q6, wrist_centre=None):
    T = np.asarray(T, dtype=float)
    R = T[:3, :3]
    x1 = np.array([np.cos(q1), np.sin(q1), 0.0])
    y1 = np.array([0.0, 0.0, 1.0])
    z4 = R @ np.array([-np.sin(q6), -np.cos(q6), 0.0])
    x4 = R @ np.array([np.cos(q5) * np.cos(q6), -np.cos(q5) * np.sin(q6), -np.sin(q5)])
    point = T[:3, 3] - D6 * R[:, 2] - D5 * z4 - np.array([0.0, 0.0, D1])
    w = complex(point @ x1, point @ y1)
    cosine = (abs(w) ** 2 - A2**2 - A3**2) / (2 * A2 * A3)
    if abs(cosine) > 1:
        return np.zeros((0, 3))
    total = np.angle(complex(x4 @ x1, x4 @ y1))
    rows = []
    for q3 in (np.arccos(cosine), -np.arccos(cosine)):
        q2 = np.angle(w / (A2 + A3 * np.exp(1j * q3)))
        rows.append([q2, q3, total - q2 - q3])
    return np.mod(np.array(rows), 2 * np.pi)  # another valid range: nothing asks for (-pi, pi]
"""),
    "task4_answer1": ("itertools.product over the branches and np.allclose", """

# written another way: the branches by index with itertools.product, verified with np.allclose
import itertools


def all_solutions(T, shoulder_angles=shoulder_angles, wrist_angles=wrist_angles, arm_angles=arm_angles):
    T = np.asarray(T, dtype=float)
    found = []
    shoulders = np.atleast_1d(shoulder_angles(T))
    for i, j in itertools.product(range(len(shoulders)), range(2)):
        q5, q6 = np.asarray(wrist_angles(T, shoulders[i]))[j]
        for q2, q3, q4 in np.asarray(arm_angles(T, shoulders[i], q5, q6)).reshape(-1, 3):
            candidate = np.array([shoulders[i], q2, q3, q4, q5, q6])
            if np.allclose(robot.fk(candidate), T, rtol=0.0, atol=1e-9):
                found.append(candidate)
    return np.reshape(found, (-1, 6))


Q_goal = all_solutions(T_goal)
"""),
    "task5_answer1": ("the shoulder from the last factor of det J, the sines as remainders", """

# written another way: X of the wrist centre in frame 1 is 0 on the cylinder; q mod pi near 0
def coinciding_branches(q, tol=1e-9, wrist_centre=None):
    q = np.asarray(q, dtype=float)
    X = A2 * np.cos(q[1]) + A3 * np.cos(q[1] + q[2]) + D5 * np.sin(q[1] + q[2] + q[3])
    near_zero = lambda angle: min(angle % np.pi, np.pi - angle % np.pi) < tol  # noqa: E731
    found = {"shoulder": abs(X) < tol, "wrist": near_zero(q[4]), "elbow": near_zero(q[2])}
    return [name for name, singular in found.items() if singular]
"""),
}
