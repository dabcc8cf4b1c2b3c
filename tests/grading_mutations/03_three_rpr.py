"""Wrong answers that each autograded test of chapter 3 (the planar 3-RPR robot) must reject.

Each entry rebinds the student's names the way a typical mistake would leave them (the
names computed from the changed one are recomputed as the answer cell would), see
``tests/test_grading_mutations.py``. A mutation that wraps the right function keeps it
under a private name (``_..._right``), restored with the others afterwards.
"""

_IK_TRANSPOSED = """
def ik(pose):
    x, y, phi = pose
    B = np.array([x, y]) + b_anchor @ rot(phi)  # R(-phi): the platform turned backwards
    return np.linalg.norm(B - A_anchor, axis=1)

rho0 = ik(POSE0)
"""

_ARM_FROM_ORIGIN = """
def inverse_jacobian(pose):
    x, y, phi = pose
    B = np.array([x, y]) + b_anchor @ rot(phi).T
    n = (B - A_anchor) / np.linalg.norm(B - A_anchor, axis=1)[:, None]
    return np.column_stack([n, B[:, 0] * n[:, 1] - B[:, 1] * n[:, 0]])  # arm O B_i

A0 = inverse_jacobian(POSE0)
J0 = np.linalg.inv(A0)
"""

_UNNORMALISED = """
def inverse_jacobian(pose):
    x, y, phi = pose
    B = np.array([x, y]) + b_anchor @ rot(phi).T
    d = B - A_anchor  # leg vectors, not unit vectors
    arm = B - np.array([x, y])
    return np.column_stack([d, arm[:, 0] * d[:, 1] - arm[:, 1] * d[:, 0]])

A0 = inverse_jacobian(POSE0)
J0 = np.linalg.inv(A0)
"""

_CUBIC_MODES = """
_sq1, _sq2, _sq3 = rho0**2
_cubic = [
    0.5 * (_sq1 - _sq2 + 4 - 2) + (_sq3 - _sq1),
    math.sqrt(3) / 2 * (4 - 4 + _sq2 - _sq1),
    0.5 * (_sq1 - _sq2) + _sq3 - 3 - _sq1,
    math.sqrt(3) / 2 * (_sq2 - _sq1),
]
modes0 = np.column_stack([np.zeros(3), np.zeros(3), 2 * np.arctan(np.sort(np.roots(_cubic).real))])
"""

_F_WITHOUT_D = """
def F_of_phi(phi, rho, robot=robot):
    M, r = linear_solve(phi, rho, robot)
    adj_r = np.array([[M[1, 1], -M[0, 1]], [-M[1, 0], M[0, 0]]]) @ r
    return adj_r @ adj_r - rho[0] ** 2  # the factor det(M)^2 forgotten
"""

MUTATIONS = {
    "task1_test1": [
        ("squared leg lengths",
         "_ik_right = ik\n\ndef ik(pose):\n    return _ik_right(pose) ** 2\n\nrho0 = ik(POSE0)"),
        ("platform turned by R(-phi) (rotation transposed)", _IK_TRANSPOSED),
    ],
    "task2_test1": [
        ("the factor t^2 divided out of the polynomial (degree 4)",
         "poly_t = sp.Poly(sp.cancel(poly_t.as_expr() / t**2), t)"),
        ("the mirror modes -phi dropped",
         "modes0 = my_fk(rho0)[2:]"),
    ],
    "task2_test2": [
        ("the orientations taken from the pitfall's cubic", _CUBIC_MODES),
    ],
    "task2_test3": [
        ("F without the factor det(M)^2 on rho1^2", _F_WITHOUT_D),
        ("modes6 solved for the exercise's robot instead of the classic one",
         "modes6 = my_fk(CLASSIC_RHO)"),
    ],
    "task3_test1": [
        ("moment arm from the base origin", _ARM_FROM_ORIGIN),
        ("leg vectors not normalised (rho_i rho_i-dot)", _UNNORMALISED),
    ],
    "task3_test2": [
        ("A0 with the moment arm from the base origin",
         "A0 = A0.copy()\n"
         "A0[:, 2] = robot.platform_points(POSE0)[:, 0] * A0[:, 1]"
         " - robot.platform_points(POSE0)[:, 1] * A0[:, 0]"),
    ],
    "task4_test1": [
        ("det A instead of rho1 rho2 rho3 det A (not a conic)",
         "det_prime = np.linalg.det(robot.jacobian(P_grid))\n"
         "conic, *_ = np.linalg.lstsq(basis, det_prime, rcond=None)"),
        ("the conic's centre taken as the singular pose",
         "pose_s = np.array([*centre, PHI_MAP])"),
    ],
    "task4_test2": [
        ("only the first three modes of the classic robot",
         "modes6 = modes6[:3]"),
    ],
}
