"""Wrong answers that each autograded test of the chapter must reject (``MUTATIONS``,
tests/test_grading_mutations.py), and correct answers written another way that must keep
full marks (``VARIANTS``, tests/support/benign_variants.py and tests/test_grading_trust.py).

``MUTATIONS``: ``{grade id of a test cell: [(what is wrong, code appended to the answer
cells), ...]}``, at least one per graded test. ``VARIANTS``: ``{grade id of an answer cell:
(how it differs, code appended to that cell)}``: another method, not only other names.
The first line of each variant's code must be ASCII without quotes.
"""

MUTATIONS = {
    "task1_test1": [
        ("the transposed Jacobian", "tool_jacobian = (lambda f: lambda q: f(q).T)(tool_jacobian)"),
        ("degrees for radians", "tool_jacobian = (lambda f: lambda q: f(np.rad2deg(q)))(tool_jacobian)"),
        ("the second link's own angle q2 instead of q1 + q2",
         "def tool_jacobian(q):\n    q1, q2 = q\n"
         "    return np.array([[-L1 * np.sin(q1) - L2 * np.sin(q2), -L2 * np.sin(q2)],\n"
         "                     [L1 * np.cos(q1) + L2 * np.cos(q2), L2 * np.cos(q2)]])"),
    ],
    "task1_test2": [
        ("J instead of J^T",
         "joint_torques = lambda q, F, tool_jacobian=tool_jacobian:"
         " tool_jacobian(q) @ np.asarray(F, dtype=float)"),
        ("the opposite sign",
         "joint_torques = (lambda f: lambda q, F, tool_jacobian=tool_jacobian:"
         " -f(q, F, tool_jacobian))(joint_torques)"),
        ("tau0 from the load's weight (0, -m g)", "tau0 = joint_torques(Q0, -F0)"),
        ("degrees for radians",
         "joint_torques = (lambda f: lambda q, F, tool_jacobian=tool_jacobian:"
         " f(np.rad2deg(q), F, tool_jacobian))(joint_torques)"),
        ("tau0 from a Jacobian transposed, not from joint_torques",
         "tau0 = tool_jacobian(Q0) @ F0"),
    ],
    "task1_test3": [
        ("the foot pushing up, as a hand holding a load",
         "leg_torques = (lambda f: lambda q, m: -f(q, m))(leg_torques)"),
        ("J instead of J^T",
         "leg_torques = lambda q, m: foot_jacobian(q) @ np.array([0.0, 0.0, -m * GRAVITY])"),
        ("the mass for the weight (no g)",
         "leg_torques = lambda q, m: foot_jacobian(q).T @ np.array([0.0, 0.0, -m])"),
    ],
    "task2_test1": [
        ("the eigenvalues of J J^T as semi-axes (squared lengths)",
         "velocity_ellipse = (lambda f: lambda J: (f(J)[0] ** 2, f(J)[1]))(velocity_ellipse)"),
        ("ascending order, as eigh returns them",
         "def velocity_ellipse(J):\n    values, vectors = np.linalg.eigh(J @ J.T)\n"
         "    return np.sqrt(values), vectors"),
        ("the eigenvectors of J^T J (joint space)",
         "def velocity_ellipse(J):\n    values, vectors = np.linalg.eigh(J.T @ J)\n"
         "    return np.sqrt(np.clip(values[::-1], 0, None)), vectors[:, ::-1]"),
        ("the force ellipse's lengths 1/sigma",
         "velocity_ellipse = (lambda f: lambda J: (1 / f(J)[0], f(J)[1]))(velocity_ellipse)"),
    ],
    "task3_test1": [
        ("the lengths not inverted",
         "force_ellipse = lambda J, velocity_ellipse=velocity_ellipse: velocity_ellipse(J)"),
        ("1/sigma^2 (inverse eigenvalues)",
         "force_ellipse = (lambda f: lambda J, velocity_ellipse=velocity_ellipse: "
         "(f(J, velocity_ellipse)[0] ** 2, f(J, velocity_ellipse)[1]))(force_ellipse)"),
        ("1/sigma in ascending order",
         "force_ellipse = (lambda f: lambda J, velocity_ellipse=velocity_ellipse: "
         "(f(J, velocity_ellipse)[0][::-1], f(J, velocity_ellipse)[1][:, ::-1]))(force_ellipse)"),
        ("the inverted lengths on the velocity ellipse's axes in their order",
         "force_ellipse = (lambda f: lambda J, velocity_ellipse=velocity_ellipse: "
         "(f(J, velocity_ellipse)[0], f(J, velocity_ellipse)[1][:, ::-1]))(force_ellipse)"),
    ],
    "task3_test2": [
        ("force_from_velocity: the velocity ellipse unchanged",
         "force_from_velocity = lambda radii_v, axes_v: (radii_v, axes_v)"),
        ("force_from_velocity: 1/sigma in the velocity ellipse's order",
         "force_from_velocity = lambda radii_v, axes_v: (1 / np.asarray(radii_v), axes_v)"),
        ("force_from_velocity: the radii reversed, the axes left in their order",
         "force_from_velocity = lambda radii_v, axes_v: (1 / np.asarray(radii_v)[::-1], axes_v)"),
        ("force_from_velocity: 1/sigma^2",
         "force_from_velocity = lambda radii_v, axes_v: "
         "(1 / np.asarray(radii_v)[::-1] ** 2, np.asarray(axes_v)[:, ::-1])"),
    ],
    "task4_test1": [
        ("det(J J^T) without the square root",
         "manipulability = lambda J: float(np.linalg.det(J @ J.T))"),
    ],
    "task4_test2": [
        ("the closed form without the absolute value",
         "w_formula = lambda q2, l1, l2: l1 * l2 * np.sin(q2)"),
        ("the closed form in degrees",
         "w_formula = lambda q2, l1, l2: abs(l1 * l2 * np.sin(np.deg2rad(q2)))"),
        ("the closed form with cos q2", "w_formula = lambda q2, l1, l2: abs(l1 * l2 * np.cos(q2))"),
    ],
    "task4_test3": [
        ("the elbow at 45 degrees", "q2_best = np.pi / 4"),
        ("the angle in degrees", "q2_best = 90.0"),
    ],
    "task4_test4": [
        ("the ratio of the eigenvalues (kappa squared)",
         "condition_number = (lambda f: lambda J: f(J) ** 2)(condition_number)"),
        ("sigma_min / sigma_max", "condition_number = (lambda f: lambda J: 1 / f(J))(condition_number)"),
    ],
    "task4_test5": [
        ("l2 = sqrt(2) l1", "l_ratio_iso = np.sqrt(2)"),
        ("the elbow at 45 degrees", "q2_iso = np.pi / 4"),
    ],
    "task5_test1": [
        ("the norm of J^T d, not inverted", "push_capacity = lambda J, d: float(np.linalg.norm(J.T @ d))"),
        ("1 / |J^T d|^2", "push_capacity = lambda J, d: float(1 / np.linalg.norm(J.T @ d) ** 2)"),
        ("J instead of J^T", "push_capacity = lambda J, d: float(1 / np.linalg.norm(J @ np.resize(d, J.shape[1])))"),
    ],
    "task5_test2": [
        ("the height where the push down is weakest",
         "z_strongest = z_line[int(np.argmin([push_capacity(ur10.position_jacobian(q), DOWN)"
         " for q in q_line]))]"),
        ("the top of the line", "z_strongest = z_line[-1]"),
        ("the eigenvalues of J_v J_v^T for sigma_line", "sigma_line = sigma_line ** 2"),
        ("sigma_line ascending", "sigma_line = sigma_line[:, ::-1]"),
        ("push_down as |J_v^T d|, not its inverse, and its largest value",
         "push_down = np.array([np.linalg.norm(ur10.position_jacobian(q).T @ DOWN) for q in q_line])\n"
         "z_strongest = z_line[int(np.argmax(push_down))]"),
    ],
    "task5_test3": [
        ("the velocity ellipsoid's semi-axes for the force ellipsoid's", "force_line = sigma_line.copy()"),
        ("1/sigma in the velocity ellipsoid's order (ascending)", "force_line = 1 / sigma_line"),
        ("the velocity ellipsoid's longest axis for the strongest push",
         "strong_axis_top = velocity_ellipse(ur10.position_jacobian(q_line[-1]))[1][:, 0]"),
    ],
    "task6_test1": [
        ("the eigenvalues of J J^T for the singular values",
         "posture_measures = (lambda f: lambda J: tuple(v ** 2 for v in f(J)))(posture_measures)"),
        ("sigma_min / sigma_max for the condition number",
         "posture_measures = (lambda f: lambda J: (f(J)[0], 1 / f(J)[1], f(J)[2]))(posture_measures)"),
        ("sigma_max for sigma_min",
         "posture_measures = (lambda f: lambda J: (*f(J)[:2], f(J)[0] / f(J)[2]))(posture_measures)"),
    ],
    "task6_test2": [
        ("the largest condition number preferred",
         "preferred_postures = (lambda f: lambda jacobians, measures=posture_measures: "
         "{**f(jacobians, measures), 'condition_number': int("
         "np.argmax([measures(J)[1] for J in jacobians]))})(preferred_postures)"),
        ("one posture for all three measures",
         "preferred_postures = (lambda f: lambda jacobians, measures=posture_measures: dict.fromkeys("
         "f(jacobians, measures), f(jacobians, measures)['manipulability']))(preferred_postures)"),
        ("the verdict at POSTURES_6 typed in, w at 90 degrees for all",
         "choice_6 = {'manipulability': 1, 'condition_number': 1, 'sigma_min': 1}"),
    ],
    "task6_test3": [
        ("every pair in reverse order", "blind_spots = {key: pair[::-1] for key, pair in blind_spots.items()}"),
        ("kappa's pair with a larger J_b that is slower in one direction",
         "blind_spots = {**blind_spots, 'condition_number': (0.5 * np.eye(2), np.diag([4.0, 0.4]))}"),
        ("w's pair with J_b faster in its slowest direction, but not twice as fast",
         "blind_spots = {**blind_spots, 'manipulability': (np.diag([4.0, 0.3]), 0.4 * np.eye(2))}"),
        ("sigma_min's pair with J_b slower in its slowest direction by a half",
         "blind_spots = {**blind_spots, 'sigma_min': (np.eye(2), np.diag([20.0, 0.5]))}"),
    ],
}

VARIANTS = {
    "task1_answer1": ("the Jacobian from complex link vectors, the torques as moments about the joints", """

# written another way: column k of J is i times the links after joint k (complex numbers),
# and each torque is the moment of F about its joint
def tool_jacobian(q):
    first, second = np.asarray(q, dtype=float)
    elbow, tip = L1 * np.exp(1j * first), L2 * np.exp(1j * (first + second))
    columns = [1j * (elbow + tip), 1j * tip]
    return np.array([[column.real for column in columns], [column.imag for column in columns]])


def joint_torques(q, F, tool_jacobian=tool_jacobian):  # the moments need no Jacobian
    first, second = np.asarray(q, dtype=float)
    elbow = L1 * np.array([np.cos(first), np.sin(first)])
    tip = elbow + L2 * np.array([np.cos(first + second), np.sin(first + second)])
    arms = [tip, tip - elbow]
    return np.array([arm[0] * F[1] - arm[1] * F[0] for arm in arms])


tau0 = joint_torques(Q0, F0)
"""),
    "task1_answer2": ("the torques as minus the gradient of the foot height, by sympy", """

# written another way: tau = dV/dq with V = -m g z_F(q), z_F differentiated symbolically
_angles = sp.symbols("alpha beta gamma", real=True)
_z_foot = -sp.cos(_angles[0]) * (1 + sp.cos(_angles[1]) + sp.cos(_angles[1] + _angles[2]))
_dz_dq = sp.lambdify(_angles, [sp.diff(_z_foot, angle) for angle in _angles], "numpy")


def leg_torques(q, m):
    return -m * GRAVITY * np.array(_dz_dq(*np.asarray(q, dtype=float)), dtype=float)


tau_stand = leg_torques(Q_STAND, BODY_MASS)
"""),
    "task2_answer1": ("the singular value decomposition of J", """

# written another way: the left singular vectors and the singular values of J
def velocity_ellipse(J):
    left, singular_values, _ = np.linalg.svd(np.asarray(J, dtype=float))
    return singular_values, left
"""),
    "task3_answer1": ("the force ellipse on the velocity ellipse passed in; from the velocity "
                      "ellipse alone by an eigen-decomposition of J J^T rebuilt", """

# written another way: the velocity ellipse passed in, its radii inverted and reordered by argsort
def force_ellipse(J, velocity_ellipse=velocity_ellipse):
    radii_v, axes_v = (np.asarray(a, dtype=float) for a in velocity_ellipse(J))
    order = np.argsort(radii_v)  # the shortest velocity axis is the longest force axis
    return 1.0 / radii_v[order], axes_v[:, order]


# and from the velocity ellipse alone: rebuild J J^T = A diag(r^2) A^T, then the same
def force_from_velocity(radii_v, axes_v):
    axes_v = np.asarray(axes_v, dtype=float)
    values, vectors = np.linalg.eigh(axes_v @ np.diag(np.asarray(radii_v, dtype=float) ** 2) @ axes_v.T)
    return 1.0 / np.sqrt(values), vectors
"""),
    "task4_answer1": ("the product of the singular values, the closed form as |det J|", """

# written another way: w is the product of the semi-axes; for the arm, the determinant of J
def manipulability(J):
    return float(np.prod(np.linalg.svd(np.asarray(J, dtype=float), compute_uv=False)))


def w_formula(q2, l1, l2):
    jacobian_at_zero = np.array([[-l2 * np.sin(q2), -l2 * np.sin(q2)],
                                 [l1 + l2 * np.cos(q2), l2 * np.cos(q2)]])
    return float(abs(np.linalg.det(jacobian_at_zero)))


q2_best = float(np.arccos(0.0))
"""),
    "task4_answer2": ("the condition number from the eigenvalues, the design from its equations", """

# written another way: kappa from the eigenvalues of J J^T; the design from c2 = -l2/l1, l1^2 = 2 l2^2
def condition_number(J):
    values = np.linalg.eigvalsh(np.asarray(J, dtype=float) @ np.asarray(J, dtype=float).T)
    return float(np.sqrt(values[-1] / values[0]))


l_ratio_iso = float(np.sqrt(0.5))
q2_iso = float(np.arccos(-l_ratio_iso))
"""),
    "task5_answer1": ("the radius of the force ellipsoid along d", """

# written another way: the force ellipsoid's radius along d, 1 / sqrt(sum (a_i . d / r_i)^2)
def push_capacity(J, d):
    radii, axes = force_ellipse(J)
    return float(1.0 / np.sqrt(np.sum((np.asarray(axes).T @ d / radii) ** 2)))


push_down = np.array([push_capacity(ur10.position_jacobian(q), DOWN) for q in q_line])
z_strongest = float(z_line[int(np.argmax(push_down))])
sigma_line = np.array([np.linalg.svd(ur10.position_jacobian(q), compute_uv=False) for q in q_line])
# the force ellipsoid's own radii and axes, from force_ellipse; the axis of its longest one
force_line = np.array([force_ellipse(ur10.position_jacobian(q))[0] for q in q_line])
strong_axis_top = -np.asarray(force_ellipse(ur10.position_jacobian(q_line[-1]))[1])[:, 0]
"""),
    "task6_answer1": ("the measures from the eigenvalues of J J^T, the choice by sorting", """

# written another way: sigma_i^2 are the eigenvalues of J J^T; each measure ranks by sorting
def posture_measures(J):
    values = np.linalg.eigvalsh(np.asarray(J, dtype=float) @ np.asarray(J, dtype=float).T)
    return (float(np.sqrt(np.prod(values))), float(np.sqrt(values[-1] / values[0])),
            float(np.sqrt(values[0])))


def preferred_postures(jacobians, measures=posture_measures):
    rows = [measures(J) for J in jacobians]
    order = range(len(rows))
    return {"manipulability": max(order, key=lambda i: rows[i][0]),
            "condition_number": min(order, key=lambda i: rows[i][1]),
            "sigma_min": max(order, key=lambda i: rows[i][2])}


choice_6 = preferred_postures(J_6)
# other examples, turned by rotations on both sides (the singular values stay)
_left, _right = np.array([[0.6, -0.8], [0.8, 0.6]]), np.array([[0.0, 1.0], [-1.0, 0.0]])
blind_spots = {
    "manipulability": (_left @ np.diag([3.0, 0.2]) @ _right, 0.45 * np.eye(2)),
    "condition_number": (0.3 * _left, np.diag([3.0, 0.5]) @ _right),
    "sigma_min": (np.diag([2.0, 1.0]), _left @ np.diag([25.0, 0.99])),
}
"""),
}
