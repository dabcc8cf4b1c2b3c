"""Wrong answers that each autograded test of chapter 8 (the product of exponentials) must
reject (``MUTATIONS``, tests/test_grading_mutations.py), and correct answers written another
way that must keep full marks (``VARIANTS``, tests/support/benign_variants.py and
tests/test_grading_trust.py).

``MUTATIONS``: ``{grade id of a test cell: [(what is wrong, code appended to the answer
cells), ...]}``, at least one per graded test; a mutation recomputes the names the answer
cell computes from the changed function (``T0``, ``Js0``, ``Jb0``). ``VARIANTS``: ``{grade id
of an answer cell: (how it differs, code appended to that cell)}``: another method, not only
other names. The first line of each variant's code must be ASCII without quotes.
"""

_RODRIGUES_SIN_SIGN = """
def rodrigues(omega, theta):
    W = skew(omega)
    return np.eye(3) - np.sin(theta) * W + (1.0 - np.cos(theta)) * (W @ W)  # turns by -theta
"""

_RODRIGUES_NO_SQUARE = """
def rodrigues(omega, theta):
    W = skew(omega)
    return np.eye(3) + np.sin(theta) * W + (1.0 - np.cos(theta)) * W  # [w] for [w]^2
"""

_SCREW_SIGN = """
def screw_axis(omega, point):
    omega = np.asarray(omega, dtype=float)
    return np.concatenate([omega, np.cross(omega, point)])  # +w x q
"""

_SCREW_ORDER = """
def screw_axis(omega, point):
    omega = np.asarray(omega, dtype=float)
    return np.concatenate([-np.cross(omega, point), omega])  # [v; w]
"""

_SCREWS_FRAME_BEFORE = """
def screw_axes_at_home(frames, joint_axes, screw_axis=screw_axis):
    rows = []
    for i, axis in enumerate(joint_axes, start=1):
        R, p = frames[i - 1][:3, :3], frames[i - 1][:3, 3]  # the frame before joint i
        rows.append(screw_axis(R @ axis, p))
    return np.array(rows)


S_list = screw_axes_at_home(home_frames, ur10.joint_axes)
"""

_SCREWS_ORDER = """
def screw_axes_at_home(frames, joint_axes, screw_axis=screw_axis):
    rows = []
    for i, axis in enumerate(joint_axes, start=1):
        R, p = frames[i][:3, :3], frames[i][:3, 3]
        rows.append(screw_axis(R @ axis, p)[[3, 4, 5, 0, 1, 2]])  # [v; w]
    return np.array(rows)


S_list = screw_axes_at_home(home_frames, ur10.joint_axes)
"""

_SCREWS_Z_AXIS = """
def screw_axes_at_home(frames, joint_axes, screw_axis=screw_axis):
    rows = []
    for i in range(1, len(frames) - 1):
        rows.append(screw_axis(frames[i][:3, 2], frames[i][:3, 3]))  # z, whatever the axis
    return np.array(rows)


S_list = screw_axes_at_home(home_frames, ur10.joint_axes)
"""

_SCREWS_AXIS_NOT_TURNED = """
def screw_axes_at_home(frames, joint_axes, screw_axis=screw_axis):
    rows = []
    for i, axis in enumerate(joint_axes, start=1):
        rows.append(screw_axis(np.asarray(axis, dtype=float), frames[i][:3, 3]))  # not R a
    return np.array(rows)


S_list = screw_axes_at_home(home_frames, ur10.joint_axes)
"""

_SCREWS_UR10_ONLY = """
screw_axes_at_home = (lambda S: lambda frames, joint_axes, **steps: S)(S_list)  # the UR10's
"""

_EXP_WITHOUT_G = """
def exp6(S, theta, rodrigues=rodrigues, skew=skew):
    omega, v = np.asarray(S[:3], dtype=float), np.asarray(S[3:], dtype=float)
    T = np.eye(4)
    T[:3, :3] = rodrigues(omega, theta)
    T[:3, 3] = v * theta  # G(theta) forgotten
    return T
"""

_FK_REVERSED = """
def poe_fk(M, S_list, theta, exp6=exp6):
    T = np.eye(4)
    for S, angle in zip(S_list, theta):
        T = exp6(S, angle) @ T  # joint n on the left
    return T @ M

T0 = poe_fk(M, S_list, THETA0)
"""

_FK_M_LEFT = """
def poe_fk(M, S_list, theta, exp6=exp6):
    T = M.copy()  # M on the left
    for S, angle in zip(S_list, theta):
        T = T @ exp6(S, angle)
    return T

T0 = poe_fk(M, S_list, THETA0)
"""

_ADJOINT_R_P = """
def adjoint_matrix(T, skew=skew):
    R, p = T[:3, :3], T[:3, 3]
    A = np.zeros((6, 6))
    A[:3, :3] = R
    A[3:, 3:] = R
    A[3:, :3] = R @ skew(p)  # R [p] for [p] R
    return A
"""

_ADJOINT_ORDER = """
def adjoint_matrix(T, skew=skew):
    R, p = T[:3, :3], T[:3, 3]
    A = np.zeros((6, 6))
    A[:3, :3] = R
    A[3:, 3:] = R
    A[:3, 3:] = skew(p) @ R  # the adjoint for [v; w]
    return A
"""

_SPACE_NO_ADJOINT = """
def jacobian_in_space(S_list, theta, exp6=exp6, adjoint_matrix=adjoint_matrix):
    return np.array(S_list, dtype=float).T  # the screw axes at home

Js0 = jacobian_in_space(S_list, THETA0)
"""

_SPACE_REVERSED = """
def jacobian_in_space(S_list, theta, exp6=exp6, adjoint_matrix=adjoint_matrix):
    columns, P = [], np.eye(4)
    for S, angle in zip(S_list, theta):
        columns.append(adjoint_matrix(P) @ S)
        P = exp6(S, angle) @ P  # the partial product in the wrong order
    return np.column_stack(columns)

Js0 = jacobian_in_space(S_list, THETA0)
"""

_GEOMETRIC_SWAP_ONLY = """
def geometric_from_space(J_s, T, skew=skew):
    return np.vstack([J_s[3:], J_s[:3]])  # rows swapped, the point not moved
"""

_GEOMETRIC_SIGN = """
def geometric_from_space(J_s, T, skew=skew):
    return np.vstack([J_s[3:] + skew(T[:3, 3]) @ J_s[:3], J_s[:3]])  # +[p] for -[p]
"""

_BODY_ADJOINT_T = """
def jacobian_in_body(M, S_list, theta, poe_fk=poe_fk, jacobian_in_space=jacobian_in_space,
                     adjoint_matrix=adjoint_matrix):
    T = poe_fk(M, S_list, theta)
    return adjoint_matrix(T) @ jacobian_in_space(S_list, theta)  # Ad(T) for Ad(T^-1)

Jb0 = jacobian_in_body(M, S_list, THETA0)
"""

_BODY_HOME = """
def jacobian_in_body(M, S_list, theta, poe_fk=poe_fk, jacobian_in_space=jacobian_in_space,
                     adjoint_matrix=adjoint_matrix):
    return adjoint_matrix(transform_inverse(M)) @ jacobian_in_space(S_list, theta)  # M for T

Jb0 = jacobian_in_body(M, S_list, THETA0)
"""

_IK_STEP_SIGN = """
def ik_body(M, S_list, T_goal, theta_start, tolerance=1e-10, max_iterations=30, poe_fk=poe_fk,
            jacobian_in_body=jacobian_in_body):
    theta = np.array(theta_start, dtype=float)
    for iteration in range(max_iterations + 1):
        V_b = transform_log(transform_inverse(poe_fk(M, S_list, theta)) @ T_goal)
        if np.linalg.norm(V_b) < tolerance or iteration == max_iterations:
            return theta, iteration
        theta = theta - np.linalg.pinv(jacobian_in_body(M, S_list, theta)) @ V_b  # the sign

theta_ik, iterations_ik = ik_body(M, S_list, T_GOAL, THETA_START)
"""

_IK_SPACE_JACOBIAN = """
def ik_body(M, S_list, T_goal, theta_start, tolerance=1e-10, max_iterations=30, poe_fk=poe_fk,
            jacobian_in_body=jacobian_in_body):
    theta = np.array(theta_start, dtype=float)
    for iteration in range(max_iterations + 1):
        V_b = transform_log(transform_inverse(poe_fk(M, S_list, theta)) @ T_goal)
        if np.linalg.norm(V_b) < tolerance or iteration == max_iterations:
            return theta, iteration
        theta = theta + np.linalg.pinv(jacobian_in_space(S_list, theta)) @ V_b  # J_s with V_b

theta_ik, iterations_ik = ik_body(M, S_list, T_GOAL, THETA_START)
"""

_IK_SPACE_TWIST = """
def ik_body(M, S_list, T_goal, theta_start, tolerance=1e-10, max_iterations=30, poe_fk=poe_fk,
            jacobian_in_body=jacobian_in_body):
    theta = np.array(theta_start, dtype=float)
    for iteration in range(max_iterations + 1):
        T = poe_fk(M, S_list, theta)
        V_s = transform_log(T_goal @ transform_inverse(T))  # the space twist, with J_b below
        if np.linalg.norm(V_s) < tolerance or iteration == max_iterations:
            return theta, iteration
        theta = theta + np.linalg.pinv(jacobian_in_body(M, S_list, theta)) @ V_s

theta_ik, iterations_ik = ik_body(M, S_list, T_GOAL, THETA_START)
"""

_IK_STEP_FIRST = """
def ik_body(M, S_list, T_goal, theta_start, tolerance=1e-10, max_iterations=30, poe_fk=poe_fk,
            jacobian_in_body=jacobian_in_body):
    theta = np.array(theta_start, dtype=float)
    for iteration in range(1, max_iterations + 1):
        V_b = transform_log(transform_inverse(poe_fk(M, S_list, theta)) @ T_goal)
        theta = theta + np.linalg.pinv(jacobian_in_body(M, S_list, theta)) @ V_b  # a step first
        if np.linalg.norm(V_b) < tolerance:
            return theta, iteration
    return theta, max_iterations

theta_ik, iterations_ik = ik_body(M, S_list, T_GOAL, THETA_START)
"""

MUTATIONS = {
    "task1_test1": [
        ("[w] transposed", "skew = (lambda f: lambda w: f(w).T)(skew)"),
    ],
    "task1_test2": [
        ("the sine term with the wrong sign (a turn by -theta)", _RODRIGUES_SIN_SIGN),
        ("(1 - cos) [w] for (1 - cos) [w]^2", _RODRIGUES_NO_SQUARE),
        ("degrees for radians", "rodrigues = (lambda f: lambda w, t: f(w, np.deg2rad(t)))(rodrigues)"),
    ],
    "task2_test1": [
        ("v = w x q (the sign)", _SCREW_SIGN),
        ("the order [v; w]", _SCREW_ORDER),
    ],
    "task2_test2": [
        ("the axes read from the frame before each joint", _SCREWS_FRAME_BEFORE),
        ("the rows ordered [v; w]", _SCREWS_ORDER),
        ("every joint about its frame's z axis, whatever joint_axes says", _SCREWS_Z_AXIS),
        ("the joint axes not turned into the base frame", _SCREWS_AXIS_NOT_TURNED),
        ("the UR10's screw axes whatever the chain", _SCREWS_UR10_ONLY),
        ("S_list not the function's value at the UR10's home frames",
         "S_list = S_list * [1, 1, 1, -1, -1, -1]"),
    ],
    "task3_test1": [
        ("the translation v theta: G(theta) forgotten", _EXP_WITHOUT_G),
    ],
    "task3_test2": [
        ("the exponentials multiplied in the wrong order", _FK_REVERSED),
        ("M on the left", _FK_M_LEFT),
    ],
    "task4_test1": [
        ("R [p] for [p] R", _ADJOINT_R_P),
        ("the adjoint of twists ordered [v; w]", _ADJOINT_ORDER),
    ],
    "task4_test2": [
        ("the screw axes at home, not moved by the joints before", _SPACE_NO_ADJOINT),
        ("the partial products in the wrong order", _SPACE_REVERSED),
    ],
    "task4_test3": [
        ("the rows swapped, the point not moved", _GEOMETRIC_SWAP_ONLY),
        ("+[p] for -[p]", _GEOMETRIC_SIGN),
    ],
    "task5_test1": [
        ("Ad(T) for Ad(T^-1)", _BODY_ADJOINT_T),
        ("the home pose M for the current pose", _BODY_HOME),
    ],
    "task6_test1": [
        ("the Newton step with the wrong sign", _IK_STEP_SIGN),
        ("the space Jacobian with the body twist", _IK_SPACE_JACOBIAN),
        ("the space twist with the body Jacobian", _IK_SPACE_TWIST),
        ("a step before the convergence test (a start at the goal takes one step)", _IK_STEP_FIRST),
    ],
}

VARIANTS = {
    "task1_answer1": ("[w] from cross products, the rotation from the axis' projector", """

# written another way: column j of [w] is w x e_j, and R = cos I + sin [w] + (1 - cos) w w^T
def skew(w):
    return np.cross(np.asarray(w, dtype=float), np.eye(3)).T


def rodrigues(omega, theta):
    omega = np.asarray(omega, dtype=float)
    return (np.cos(theta) * np.eye(3) + np.sin(theta) * skew(omega)
            + (1.0 - np.cos(theta)) * np.outer(omega, omega))
"""),
    "task2_answer1": ("v as q x w, all the axes at once", """

# written another way: v = q x w, and the rows computed in one call (einsum turns each axis;
# the screw_axis given is left unused)
def screw_axis(omega, point):
    omega = np.asarray(omega, dtype=float)
    return np.hstack([omega, np.cross(np.asarray(point, dtype=float), omega)])


def screw_axes_at_home(frames, joint_axes, screw_axis=screw_axis):
    joints = np.asarray(frames)[1:-1]
    axes = np.einsum("kij,kj->ki", joints[:, :3, :3], np.asarray(joint_axes, dtype=float))
    return np.hstack([axes, np.cross(joints[:, :3, 3], axes)])


S_list = screw_axes_at_home(home_frames, ur10.joint_axes)
"""),
    "task3_answer1": ("a turn about the axis point plus a slide along it, the product by reduce", """

# written another way: S = [w; v] is a turn about the axis through q = w x v (the point of
# the axis nearest the origin) and a slide h theta along w, h = w . v; the product by reduce
from functools import reduce


def exp6(S, theta, rodrigues=rodrigues, skew=skew):
    omega, v = np.asarray(S[:3], dtype=float), np.asarray(S[3:], dtype=float)
    R = rodrigues(omega, theta)
    point, pitch = np.cross(omega, v), omega @ v
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = (np.eye(3) - R) @ point + pitch * theta * omega
    return T


def poe_fk(M, S_list, theta, exp6=exp6):
    factors = [exp6(S, angle) for S, angle in zip(S_list, theta)]
    return reduce(np.matmul, factors, np.eye(4)) @ M


T0 = poe_fk(M, S_list, THETA0)
"""),
    "task4_answer1": ("the adjoint by blocks, each partial product anew, the velocity by cross products", """

# written another way: np.block, the partial product rebuilt for each column, and
# v_point = v_s + w x p column by column
def adjoint_matrix(T, skew=skew):
    R, p = T[:3, :3], T[:3, 3]
    return np.block([[R, np.zeros((3, 3))], [skew(p) @ R, R]])


def jacobian_in_space(S_list, theta, exp6=exp6, adjoint_matrix=adjoint_matrix):
    n = len(theta)
    J = np.zeros((6, n))
    for i in range(n):
        P = np.eye(4)
        for k in range(i):
            P = P @ exp6(S_list[k], theta[k])
        J[:, i] = adjoint_matrix(P) @ S_list[i]
    return J


def geometric_from_space(J_s, T, skew=skew):
    J_s = np.asarray(J_s, dtype=float)
    v_point = J_s[3:] + np.cross(J_s[:3].T, T[:3, 3]).T
    return np.vstack([v_point, J_s[:3]])


Js0 = jacobian_in_space(S_list, THETA0)
"""),
    "task5_answer1": ("the body twists written out: R^T w and R^T (v + w x p)", """

# written another way: w_b = R^T w_s and v_b = R^T (v_s + w_s x p), the block form of Ad(T^-1)
def jacobian_in_body(M, S_list, theta, poe_fk=poe_fk, jacobian_in_space=jacobian_in_space,
                     adjoint_matrix=adjoint_matrix):
    T = poe_fk(M, S_list, theta)
    R, p = T[:3, :3], T[:3, 3]
    J_s = jacobian_in_space(S_list, theta)
    return np.vstack([R.T @ J_s[:3], R.T @ (J_s[3:] + np.cross(J_s[:3].T, p).T)])


Jb0 = jacobian_in_body(M, S_list, THETA0)
"""),
    "task6_answer1": ("a while loop and the step by least squares", """

# written another way: a while loop, and the Newton step from np.linalg.lstsq
def ik_body(M, S_list, T_goal, theta_start, tolerance=1e-10, max_iterations=30, poe_fk=poe_fk,
            jacobian_in_body=jacobian_in_body):
    theta, steps = np.asarray(theta_start, dtype=float).copy(), 0
    while True:
        error = transform_log(transform_inverse(poe_fk(M, S_list, theta)) @ T_goal)
        if np.all(np.linalg.norm(error.reshape(2, 3), axis=1) < tolerance) or steps == max_iterations:
            return theta, steps
        step = np.linalg.lstsq(jacobian_in_body(M, S_list, theta), error, rcond=None)[0]
        theta, steps = theta + step, steps + 1


theta_ik, iterations_ik = ik_body(M, S_list, T_GOAL, THETA_START)
"""),
}
