"""Wrong answers that each autograded test of chapter 3 (the planar 3-RPR robot) must reject.

Each entry rebinds the student's names the way a typical mistake would leave them (the
names computed from the changed one are recomputed as the answer cell would), see
``tests/test_grading_mutations.py``. A mutation that wraps the right function keeps it
under a private name (``_..._right``), restored with the others afterwards.
"""

_IK_TRANSPOSED = """
def ik(pose, robot=robot):
    x, y, phi = pose
    # R(-phi): the platform turned backwards
    B = np.array([x, y]) + robot.platform_anchors @ rot(phi)
    return np.linalg.norm(B - robot.base_anchors, axis=1)

rho0 = ik(POSE0)
"""

_ARM_FROM_ORIGIN = """
def inverse_jacobian(pose, robot=robot):
    B = robot.platform_points(pose)
    n = (B - robot.base_anchors) / np.linalg.norm(B - robot.base_anchors, axis=1)[:, None]
    return np.column_stack([n, B[:, 0] * n[:, 1] - B[:, 1] * n[:, 0]])  # arm O B_i

A0 = inverse_jacobian(POSE0)
J0 = np.linalg.inv(A0)
"""

_UNNORMALISED = """
def inverse_jacobian(pose, robot=robot):
    B = robot.platform_points(pose)
    d = B - robot.base_anchors  # leg vectors, not unit vectors
    arm = B - np.asarray(pose, dtype=float)[:2]
    return np.column_stack([d, arm[:, 0] * d[:, 1] - arm[:, 1] * d[:, 0]])

A0 = inverse_jacobian(POSE0)
J0 = np.linalg.inv(A0)
"""

_F_WITHOUT_D = """
def F_of_phi(phi, rho, robot=robot):
    M, r = linear_solve(phi, rho, robot)
    adj_r = np.array([[M[1, 1], -M[0, 1]], [-M[1, 0], M[0, 0]]]) @ r
    return adj_r @ adj_r - rho[0] ** 2  # the factor det(M)^2 forgotten
"""

_MODES_WITHOUT_ANGLE = """
_my_fk_right = my_fk

def my_fk(rho, robot=robot, F=F_of_phi):
    modes = _my_fk_right(rho, robot, F)
    return modes[:, :2]  # the orientation dropped

modes0 = my_fk(rho0)
"""

_SPURIOUS_ROOT_KEPT = """
_my_fk_right = my_fk

def my_fk(rho, robot=robot, F=F_of_phi):
    modes = _my_fk_right(rho, robot, F)
    phi = 2 * math.atan(1e-9)  # the root t = 0 of the polynomial, kept: there D = 0
    M, r = linear_solve(phi, rho, robot)
    u = np.linalg.solve(M, r)  # Cramer's rule dividing by D near 0
    return np.vstack([modes, [u[0], u[1], phi]])

modes0 = my_fk(rho0)
"""

_CRAMER_NO_CONJUGATE = """
def cramer_parts(phi, rho, robot=robot):
    a = robot.base_anchors[:, 0] + 1j * robot.base_anchors[:, 1]
    b = robot.platform_anchors[:, 0] + 1j * robot.platform_anchors[:, 1]
    E = np.exp(1j * phi) * (b[1:] - b[0]) - (a[1:] - a[0])
    r = rho[1:] ** 2 - rho[0] ** 2 - np.abs(E) ** 2
    return r[0] * E[1] - r[1] * E[0], E[0] * E[1]  # Delta without the conjugates
"""

_CRAMER_REAL_FORM = """
def cramer_parts(phi, rho, robot=robot):
    M, r = linear_solve(phi, rho, robot)
    u = np.linalg.solve(M, r)
    return complex(*u), 1.0  # the right w, but not Cramer's rule: not a sum of powers of z
"""

_IK_FROM_ROBOKIN = """
def ik(pose, robot=robot):
    return robot.inverse_kinematics(np.asarray(pose, dtype=float))  # robokin's solver

rho0 = ik(POSE0)
"""

_IK_OF_THE_EXERCISE_ONLY = """
def ik(pose, robot=robot):
    x, y, phi = pose
    # the exercise's anchors, whatever robot is given
    B = np.array([x, y]) + b_anchor @ rot(phi).T
    return np.linalg.norm(B - A_anchor, axis=1)

rho0 = ik(POSE0)
"""

_FK_FROM_ROBOKIN = """
def my_fk(rho, robot=robot, F=F_of_phi):
    modes = robot.forward_kinematics(rho).poses  # robokin's solver
    return modes[np.argsort(modes[:, 2])]

modes0 = my_fk(rho0)
"""

_F_FROM_ROBOKIN = """
def F_of_phi(phi, rho, robot=robot):
    s = math.tan(phi / 2)  # robokin's polynomial, evaluated
    return np.polyval(robot.orientation_polynomial(rho)[::-1], s) / (1 + s**2) ** 3
"""

_F_SIGN = """
def F_of_phi(phi, rho, robot=robot):
    M, r = linear_solve(phi, rho, robot)
    adj_r = np.array([[M[1, 1], -M[0, 1]], [-M[1, 0], M[0, 0]]]) @ r
    return adj_r @ adj_r + rho[0] ** 2 * np.linalg.det(M) ** 2  # the sign of rho1^2 D^2
"""

_JACOBIAN_FROM_ROBOKIN = """
def inverse_jacobian(pose, robot=robot):
    return robot.jacobian(pose)  # robokin's solver

A0 = inverse_jacobian(POSE0)
J0 = np.linalg.inv(A0)
"""

_TWIN_TRANSPOSED = """
def twin_pose(pose, robot=robot):
    x, y, phi = pose
    c, s = math.cos(phi), math.sin(phi)
    return np.array([-(c * x - s * y), -(s * x + c * y), -phi])  # -R(phi) (x, y)
"""

_TWIN_A1_AT_ORIGIN = """
def twin_pose(pose, robot=robot):
    x, y, phi = pose
    c, s = math.cos(phi), math.sin(phi)
    return np.array([-(c * x + s * y), s * x - c * y, -phi])  # -R(phi)^T (x, y): B1 - A1 with A1 = 0
"""

_TWIN_FROM_ROBOKIN = """
def twin_pose(pose, robot=robot):
    pose = np.asarray(pose, dtype=float)
    modes = robot.forward_kinematics(robot.inverse_kinematics(pose)).poses  # robokin's solver
    return modes[np.argmin(np.abs(np.angle(np.exp(1j * (modes[:, 2] + pose[2])))))]
"""

_TWIN_FROM_THE_EXERCISE_ROBOT = """
def twin_pose(pose, robot=robot):
    pose = np.asarray(pose, dtype=float)
    exercise = three_rpr()  # the exercise's robot, whatever robot is given
    modes = exercise.forward_kinematics(exercise.inverse_kinematics(pose)).poses
    return modes[np.argmin(np.abs(np.angle(np.exp(1j * (modes[:, 2] + pose[2])))))]
"""

_PIVOT_AT_B1 = """
pivot = np.asarray(pose_s[:2], dtype=float).copy()  # the platform's reference point
"""


MUTATIONS = {
    "task1_test1": [
        ("squared leg lengths",
         "_ik_right = ik\n\ndef ik(pose):\n    return _ik_right(pose) ** 2\n\nrho0 = ik(POSE0)"),
        ("platform turned by R(-phi) (rotation transposed)", _IK_TRANSPOSED),
        ("ik hands the task to robokin's inverse_kinematics", _IK_FROM_ROBOKIN),
        ("ik of the exercise's anchors whatever robot it is given", _IK_OF_THE_EXERCISE_ONLY),
        ("the answer right at x0 only (a table of one pose)",
         "_rho0_right = rho0.copy()\n\ndef ik(pose):\n    return _rho0_right.copy()\n"),
    ],
    "task2_test1": [
        ("the factor t^2 divided out of the polynomial (degree 4)",
         "poly_t = sp.Poly(sp.cancel(poly_t.as_expr() / t**2), t)"),
        ("F without the factor D^2 on rho1^2 (a polynomial of other roots)",
         "poly_t = sp.Poly(sp.expand(poly_t.as_expr() + 5 * t**2), t)"),
        ("the sign of rho1^2 D^2 flipped",
         "poly_t = sp.Poly(sp.expand(sp.cancel((F_t + 2 * r1**2 * D**2) * (1 + t**2) ** 3)), t)"),
        ("the term rho1^2 D^2 missing",
         "poly_t = sp.Poly(sp.expand(sp.cancel((F_t + r1**2 * D**2) * (1 + t**2) ** 3)), t)"),
        ("multiplied by (1 + t^2)^4 (degree 8)",
         "poly_t = sp.Poly(sp.expand(poly_t.as_expr() * (1 + t**2)), t)"),
    ],
    "task2_test2": [
        ("the exercise's set written in, whatever polynomial it is given",
         "def vanishing_coefficients(poly=poly_t):\n    return {0, 1, 3, 5}\n"),
        ("a coefficient that vanishes at equal leg lengths taken as vanishing",
         "def vanishing_coefficients(poly=poly_t):\n"
         "    C = [sp.sympify(c) for c in reversed(poly.all_coeffs())]\n"
         "    return {k for k, c in enumerate(C) if c.subs({s: 1 for s in c.free_symbols}) == 0}\n"),
        ("D's zero put at phi = pi (the root t = infinity)", "D_zero_phi = np.pi"),
        ("only the coefficients D does not explain blamed on the twin (C_1 left out)",
         "twin_coefficients = {3, 5}"),
        ("every vanishing coefficient blamed on the twin (C_0 is D's factor t^2)",
         "twin_coefficients = {0, 1, 3, 5}"),
        ("k counted from the highest power (Poly.all_coeffs() order)",
         "def vanishing_coefficients(poly=poly_t):\n"
         "    return {k for k, c in enumerate(poly.all_coeffs()) if c == 0}\n"),
        ("only the odd coefficients kept (C_0, the factor of D, left out)",
         "def vanishing_coefficients(poly=poly_t):\n"
         "    return {k for k, c in enumerate(reversed(poly.all_coeffs())) if c == 0 and k % 2}\n"),
    ],
    "task2_test3": [
        ("the twin pose taken as the mirror image (x, -y, -phi)",
         "def twin_pose(pose, robot=robot):\n    return np.array([pose[0], -pose[1], -pose[2]])\n"),
        ("the twin's position turned by R(phi) instead of R(phi)^T", _TWIN_TRANSPOSED),
        ("the exercise's closed form, A1 taken at the origin whatever robot is given",
         _TWIN_A1_AT_ORIGIN),
        ("twin_pose hands the task to robokin's forward_kinematics", _TWIN_FROM_ROBOKIN),
        ("twin_pose from robokin's forward kinematics of the exercise's robot, whatever robot "
         "it is given", _TWIN_FROM_THE_EXERCISE_ROBOT),
    ],
    "task2_test4": [
        ("Delta without the conjugates", _CRAMER_NO_CONJUGATE),
        ("w itself returned (no Cramer's rule)", _CRAMER_REAL_FORM),
        ("the powers of the real form (order 2 each)", "N_powers, Delta_powers = (-2, 2), (-2, 2)"),
        ("the naive count of harmonics: order 4, degree 8", "highest_harmonic = 4"),
    ],
    "task2_test5": [
        ("the mirror modes -phi dropped",
         "modes0 = my_fk(rho0)[2:]"),
        ("the orientation dropped from the modes", _MODES_WITHOUT_ANGLE),
        ("the root t = 0, where D = 0, kept as a mode", _SPURIOUS_ROOT_KEPT),
        ("my_fk hands the task to robokin's forward_kinematics", _FK_FROM_ROBOKIN),
        ("my_fk solves the exercise's robot whatever robot it is given",
         "_my_fk_right = my_fk\n\ndef my_fk(rho, robot=robot, F=F_of_phi):\n"
         "    return _my_fk_right(rho)\n"),
    ],
    "task2_test6": [
        ("F without the factor det(M)^2 on rho1^2", _F_WITHOUT_D),
        ("F_of_phi from robokin's orientation polynomial", _F_FROM_ROBOKIN),
        ("F_of_phi with + rho1^2 D^2", _F_SIGN),
        ("modes6 solved for the exercise's robot instead of the classic one",
         "modes6 = my_fk(CLASSIC_RHO)"),
    ],
    "task3_test1": [
        ("moment arm from the base origin", _ARM_FROM_ORIGIN),
        ("leg vectors not normalised (rho_i rho_i-dot)", _UNNORMALISED),
        ("J0 = A0 (the direct Jacobian taken for the inverse one)", "J0 = A0"),
        ("inverse_jacobian hands the task to robokin's jacobian", _JACOBIAN_FROM_ROBOKIN),
    ],
    "task4_test1": [
        ("det A instead of rho1 rho2 rho3 det A (not a conic)",
         "det_prime = np.linalg.det(robot.jacobian(P_grid))\n"
         "conic, *_ = np.linalg.lstsq(basis, det_prime, rcond=None)"),
        ("the conic's centre taken as the singular pose",
         "pose_s = np.array([*centre, PHI_MAP])"),
    ],
    "task4_test2": [
        ("the pivot taken at B1", _PIVOT_AT_B1),
        ("every position singular at phi = pi/2 (not 0)",
         "phi_all_singular = np.pi / 2"),
    ],
}
