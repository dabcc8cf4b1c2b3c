"""Wrong answers that each autograded test of chapter 4 (Cartesian control of a tool frame) must reject.

Each entry rebinds the student's names the way a typical mistake would leave them (the
names that depend on the changed one are recomputed as the answer cell would), see
``tests/test_grading_mutations.py``.
"""

# the tool read as (roll, pitch, yaw): everything of Task 1 built from it
_TOOL_AS_RPY = """
from robokin.transforms import rotation_log
def transform_from_ypr(ypr, position):
    return transform_from_rpy(ypr, position)  # the list taken as (roll, pitch, yaw)

T_ET = transform_from_ypr(TOOL_YPR, TOOL_OFFSET)
tool_arm = chain_with_tool(arm, T_ET)
T_BT0 = tool_arm.fk(Q0)
T_ET_rpy = transform_from_rpy(TOOL_YPR, TOOL_OFFSET)  # the same reading: no other tool
tool_angle_rpy = float(np.linalg.norm(rotation_log(T_ET[:3, :3].T @ T_ET_rpy[:3, :3])))
"""

# the offset taken in centimetres
_OFFSET_CM = """
TOOL_OFFSET = np.array([0.002, 0.0, 0.0])  # "0.2 cm"
T_ET = transform_from_ypr(TOOL_YPR, TOOL_OFFSET)
tool_arm = chain_with_tool(arm, T_ET)
T_BT0 = tool_arm.fk(Q0)
T_ET_rpy = transform_from_rpy(TOOL_YPR, TOOL_OFFSET)
"""

# the angle between the two tools left in degrees
_TOOL_ANGLE_DEGREES = """
from robokin.transforms import rotation_log
tool_angle_rpy = float(np.degrees(np.linalg.norm(rotation_log(T_ET[:3, :3].T @ T_ET_rpy[:3, :3]))))
"""

# the angle between the two tools taken as the sum of the two turns of pi/10
_TOOL_ANGLE_SUM = """
tool_angle_rpy = 2 * np.pi / 10
"""

# both readings swapped: the tool read as (roll, pitch, yaw), the "other" reading as YPR
_READINGS_SWAPPED = """
T_ET_rpy = transform_from_ypr(TOOL_YPR, TOOL_OFFSET)
T_ET = transform_from_rpy(TOOL_YPR, TOOL_OFFSET)
tool_arm = chain_with_tool(arm, T_ET)
T_BT0 = tool_arm.fk(Q0)
"""

# the tool composed on the wrong side
_TOOL_ORDER = """
T_BT0 = T_ET @ T_BE0
"""

# the three rotations multiplied in the reverse order, Rx(roll) Ry(pitch) Rz(yaw): the tool's
# triple turns about x alone and is right; a triple of three angles is not
_PRODUCT_REVERSED = """
def transform_from_ypr(ypr, position):
    yaw, pitch, roll = ypr
    pose = np.eye(4)
    pose[:3, :3] = (rotation_from_rpy(roll, 0.0, 0.0) @ rotation_from_rpy(0.0, pitch, 0.0)
                    @ rotation_from_rpy(0.0, 0.0, yaw))
    pose[:3, 3] = position
    return pose
"""

# the triple stored in robokin's order (roll, pitch, yaw) and passed on unreversed
_TRIPLE_IN_RPY_ORDER = """
TOOL_YPR = np.array([np.pi / 10, 0.0, 0.0])  # stored as (roll, pitch, yaw)

def transform_from_ypr(ypr, position):
    return transform_from_rpy(ypr, position)
"""

# the goal read as (roll, pitch, yaw)
_GOAL_AS_RPY = """
from robokin.motion import pose_error
from robokin.transforms import angle_axis_from_rotation
T_BG = transform_from_rpy(GOAL_YPR, GOAL_POSITION)
e0 = pose_error(T_BT0, T_BG)
h_T, theta = angle_axis_from_rotation((transform_inverse(T_BT0) @ T_BG)[:3, :3])
h_B = T_BT0[:3, :3] @ h_T
"""

# the axis left in tool coordinates
_AXIS_IN_TOOL_FRAME = """
from robokin.transforms import angle_axis_from_rotation
h_B, theta = angle_axis_from_rotation((transform_inverse(T_BT0) @ T_BG)[:3, :3])
"""

# the error from the goal to the tool (sign)
_ERROR_SIGN = """
from robokin.motion import pose_error
e0 = pose_error(T_BG, T_BT0)
"""

# the goal's pose inverted instead of the tool's: the relative rotation is the identity
_INVERTED_THE_GOAL = """
from robokin.transforms import angle_axis_from_rotation
T_TG = transform_inverse(T_BG) @ T_BG
h_T, theta = angle_axis_from_rotation(T_TG[:3, :3])
h_B = T_BT0[:3, :3] @ h_T
"""

# the offset used without rotating it into the base frame
_OFFSET_NOT_ROTATED = """
def my_tool_jacobian(q, offset=TOOL_OFFSET):
    r = offset  # E r_ET used as if it were B r_ET
    J_rb = np.block([[np.eye(3), -skew(r)], [np.zeros((3, 3)), np.eye(3)]])
    return J_rb @ arm.jacobian(q)

J_T0 = my_tool_jacobian(Q0)
qdot0 = np.linalg.pinv(J_T0) @ twist0
"""

# the tool's own offset used instead of the argument offset
_OFFSET_ARGUMENT_IGNORED = """
def my_tool_jacobian(q, offset=TOOL_OFFSET):
    r = arm.fk(q)[:3, :3] @ TOOL_OFFSET  # the argument offset left unused
    J_rb = np.block([[np.eye(3), -skew(r)], [np.zeros((3, 3)), np.eye(3)]])
    return J_rb @ arm.jacobian(q)
"""

# the course's transport matrix (angular rows first) pasted into linear-first code
_COURSE_TRANSPORT = """
def my_tool_jacobian(q, offset=TOOL_OFFSET):
    r = arm.fk(q)[:3, :3] @ offset
    J_rb = np.block([[np.eye(3), np.zeros((3, 3))], [skew(r).T, np.eye(3)]])
    return J_rb @ arm.jacobian(q)

J_T0 = my_tool_jacobian(Q0)
qdot0 = np.linalg.pinv(J_T0) @ twist0
"""

# the desired twist stacked in the course's order [w; v]
_TWIST_COURSE_ORDER = """
def my_twist(q, orientation_error=orientation_error):
    T = tool_arm.fk(q)
    e_o = orientation_error(T[:3, :3], T_BG[:3, :3])
    return np.r_[GAIN_ANGULAR * e_o, GAIN_LINEAR * (GOAL_POSITION - T[:3, 3])]

twist0 = my_twist(Q0)
qdot0 = np.linalg.pinv(J_T0) @ twist0
"""

# the row swap taken as the identity
_SWAP_IDENTITY = """
S = np.eye(6)
"""

# the spare joint dropped: a square 6x6 system solved for joints 1-6, joint 7 at rest
_SQUARE_SYSTEM = """
qdot0 = np.r_[np.linalg.solve(J_T0[:, :6], twist0), 0.0]
"""

# the slide's column given an angular part, as if the slide turned about its axis
_SLIDE_TURNS = """
def slide_column(q):
    z6 = arm.frames(q)[6][:3, 2]
    return np.r_[z6, z6]
"""

# the slide's column along the tool's z axis instead of the slide's
_SLIDE_ALONG_TOOL_Z = """
def slide_column(q):
    return np.r_[tool_arm.fk(q)[:3, 2], 0.0, 0.0, 0.0]
"""

# the loop that steps first and tests afterwards (one step further)
_STEP_THEN_TEST = '''
from robokin.motion import pose_error
def kinematic_loop(twist_of, q0, ts=TS, t_end=T_END, robot=tool_arm):
    lower, upper = robot.limits.T
    q, Q, V = np.array(q0, dtype=float), [np.array(q0, dtype=float)], []
    for k in range(int(round(t_end / ts))):
        nu = twist_of(q)
        q = np.clip(q + ts * np.linalg.pinv(robot.jacobian(q)) @ nu, lower, upper)
        Q.append(q)
        V.append(nu)
        if np.linalg.norm(nu[:3]) < STOP and np.linalg.norm(nu[3:]) < STOP:
            break
    V.append(twist_of(q))
    return np.array(Q), np.array(V)

Q_run, V_run = kinematic_loop(my_twist, Q0)
k_stop = len(Q_run) - 1
q_final = Q_run[-1]
T_final = tool_arm.fk(q_final)
e_final = pose_error(T_final, T_BG)
'''

# the stop test on the error instead of the commanded twist
_STOP_ON_ERROR = '''
from robokin.motion import pose_error
def kinematic_loop(twist_of, q0, ts=TS, t_end=T_END, robot=tool_arm):
    lower, upper = robot.limits.T
    q, Q, V = np.array(q0, dtype=float), [], []
    for k in range(int(round(t_end / ts)) + 1):
        nu = twist_of(q)
        Q.append(q)
        V.append(nu)
        if np.linalg.norm(nu[:3]) / 0.8 < STOP and np.linalg.norm(nu[3:]) / 0.8 < STOP:
            break
        q = np.clip(q + ts * np.linalg.pinv(robot.jacobian(q)) @ nu, lower, upper)
    return np.array(Q), np.array(V)

Q_run, V_run = kinematic_loop(my_twist, Q0)
k_stop = len(Q_run) - 1
q_final = Q_run[-1]
T_final = tool_arm.fk(q_final)
e_final = pose_error(T_final, T_BG)
'''

# the report's rule: a joint whose new value is out of its limits is not updated
_NO_CLAMP = '''
def kinematic_loop(twist_of, q0, ts=TS, t_end=T_END, robot=tool_arm):
    q, Q, V = np.array(q0, dtype=float), [], []
    for k in range(int(round(t_end / ts)) + 1):
        nu = twist_of(q)
        Q.append(q)
        V.append(nu)
        if np.linalg.norm(nu[:3]) < STOP and np.linalg.norm(nu[3:]) < STOP:
            break
        q = q + ts * np.linalg.pinv(robot.jacobian(q)) @ nu
    return np.array(Q), np.array(V)
'''

_SKIP_RULE = '''
def kinematic_loop(twist_of, q0, ts=TS, t_end=T_END, robot=tool_arm):
    lower, upper = robot.limits.T
    q, Q, V = np.array(q0, dtype=float), [], []
    for k in range(int(round(t_end / ts)) + 1):
        nu = twist_of(q)
        Q.append(q)
        V.append(nu)
        if np.linalg.norm(nu[:3]) < STOP and np.linalg.norm(nu[3:]) < STOP:
            break
        q_new = q + ts * np.linalg.pinv(robot.jacobian(q)) @ nu
        q = np.where((q_new >= lower) & (q_new <= upper), q_new, q)
    return np.array(Q), np.array(V)
'''

# the run made with a ten times finer step than the exercise's
_RUN_FINER_STEP = """
Q_run, V_run = kinematic_loop(my_twist, Q0, ts=TS / 10)
k_stop = len(Q_run) - 1
q_final = Q_run[-1]
T_final = tool_arm.fk(q_final)
e_final = pose_error(T_final, T_BG)
"""

# the final pose of the end-effector, without the tool
_FINAL_END_EFFECTOR = """
T_final = arm.fk(q_final)
e_final = pose_error(T_final, T_BG)
"""

# the final error from the goal to the tool (sign)
_FINAL_ERROR_SIGN = """
e_final = pose_error(T_BG, T_final)
"""

# the final error stacked in the course's order [e_o; e_p]
_FINAL_ERROR_ORDER = """
e_final = np.r_[pose_error(T_final, T_BG)[3:], pose_error(T_final, T_BG)[:3]]
"""

# the RPY difference without wrapping the yaw into (-pi, pi]
_UNWRAPPED = """
E_rpy = np.array(
    [
        GOAL_YPR[::-1] - np.array(rpy_from_rotation(tool_arm.fk(q)[:3, :3]))
        for q in Q_run
    ]
)
"""

# the angle between the error vectors left in radians
_ANGLE_IN_RADIANS = """
angle_between = np.arccos(
    np.clip(
        np.sum(E_rpy * E_aa, axis=1)
        / np.linalg.norm(E_rpy, axis=1)
        / np.linalg.norm(E_aa, axis=1),
        -1,
        1,
    )
)
"""

# the "naive" loop that converts the rates with E(phi) after all: it converges
_NAIVE_CONVERTED = """
def naive_twist(q):
    T = tool_arm.fk(q)
    e = pose_error(T, T_BG, representation="rpy")
    _, pitch, yaw = rpy_from_rotation(T[:3, :3])
    E = np.column_stack(
        [rotation_from_rpy(0.0, pitch, yaw)[:, 0], rotz(yaw)[:, 1], [0.0, 0.0, 1.0]]
    )
    return np.r_[GAIN_LINEAR * e[:3], GAIN_ANGULAR * E @ e[3:]]

Q_naive, _ = kinematic_loop(naive_twist, Q0)
theta_naive = np.array(
    [np.linalg.norm(pose_error(tool_arm.fk(q), T_BG)[3:]) for q in Q_naive]
)
"""

# the orientation error left in the frame of the current orientation
_ERROR_IN_TOOL_FRAME = """
def orientation_error(R, R_goal):
    h_T, angle = angle_axis(R.T @ R_goal)
    return angle * h_T
"""

# the axis from R^T - R: the opposite direction
_AXIS_SIGN = """
_angle_axis = angle_axis

def angle_axis(R):
    h, angle = _angle_axis(R)
    return -np.asarray(h), angle
"""

# the error from the goal to the tool, inside orientation_error (sign)
_ERROR_FUNCTION_SIGN = """
_right_error = orientation_error

def orientation_error(R, R_goal):
    return -np.asarray(_right_error(R, R_goal))
"""

# the Euler step of the loop multiplied by the gain once more (the twist already has it)
_STEP_WITH_GAIN = """
def kinematic_loop(twist_of, q0, ts=TS, t_end=T_END, robot=tool_arm):
    lower, upper = robot.limits.T
    q, Q, V = np.array(q0, dtype=float), [], []
    for k in range(int(round(t_end / ts)) + 1):
        nu = twist_of(q)
        Q.append(q)
        V.append(nu)
        if np.linalg.norm(nu[:3]) < STOP and np.linalg.norm(nu[3:]) < STOP:
            break
        qdot = np.linalg.pinv(robot.jacobian(q)) @ nu
        q = np.clip(q + GAIN_LINEAR * ts * qdot, lower, upper)
    return np.array(Q), np.array(V)
"""

# the Euler step without the time step: q + J^+ nu
_STEP_WITHOUT_TS = _STEP_WITH_GAIN.replace("GAIN_LINEAR * ts * qdot", "qdot")

# the (roll, pitch, yaw) run with the YPR tool still on the arm
_SWAPPED_RUN_KEEPS_TOOL = """
def swapped_twist(q):
    T = tool_arm.fk(q)
    e_o = orientation_error(T[:3, :3], T_BG_rpy[:3, :3])
    return np.r_[GAIN_LINEAR * (T_BG_rpy[:3, 3] - T[:3, 3]), GAIN_ANGULAR * e_o]

swapped_arm = tool_arm
Q_swapped, V_swapped = kinematic_loop(swapped_twist, Q0, robot=tool_arm)
"""

# the (roll, pitch, yaw) twist towards the YPR goal
_SWAPPED_TWIST_YPR_GOAL = """
def swapped_twist(q):
    T = swapped_arm.fk(q)
    e_o = orientation_error(T[:3, :3], T_BG[:3, :3])
    return np.r_[GAIN_LINEAR * (T_BG[:3, 3] - T[:3, 3]), GAIN_ANGULAR * e_o]

Q_swapped, V_swapped = kinematic_loop(swapped_twist, Q0, robot=swapped_arm)
"""

# the joints at a limit counted strictly beyond it: a clamped joint is never beyond
_LIMITS_STRICT = """
joints_at_limit = int(((Q_swapped < Q_MIN) | (Q_swapped > Q_MAX)).any(axis=0).sum())
"""

# the distance from the line taken as the length of the chord
_OFF_LINE_CHORD = """
path = np.array([tool_arm.fk(q)[:3, 3] for q in Q_run])
off_line = float(np.linalg.norm(path[-1] - path[0]))
"""

# the distance from the line left in millimetres
_OFF_LINE_MM = """
off_line = 1000 * off_line
"""

# E(phi) with its columns in the order (yaw, pitch, roll)
_E_COLUMNS_REVERSED = """
def rpy_rate_matrix(R):
    _, pitch, yaw = rpy_from_rotation(R)
    return np.column_stack(
        [[0.0, 0.0, 1.0], rotz(yaw)[:, 1], rotation_from_rpy(0.0, pitch, yaw)[:, 0]]
    )
"""

# the roll axis taken as Rz(yaw) x, forgetting the pitch turn before it
_E_ROLL_AXIS_WITHOUT_PITCH = """
def rpy_rate_matrix(R):
    _, pitch, yaw = rpy_from_rotation(R)
    return np.column_stack([rotz(yaw)[:, 0], rotz(yaw)[:, 1], [0.0, 0.0, 1.0]])
"""

# E(phi) transposed
_E_TRANSPOSED = """
def rpy_rate_matrix(R):
    _, pitch, yaw = rpy_from_rotation(R)
    return np.column_stack(
        [rotation_from_rpy(0.0, pitch, yaw)[:, 0], rotz(yaw)[:, 1], [0.0, 0.0, 1.0]]
    ).T
"""

MUTATIONS = {
    "task1_test1": [
        ("the YPR triple read as (roll, pitch, yaw)", _TOOL_AS_RPY),
        ("the offset taken in centimetres", _OFFSET_CM),
        ("E T_T multiplied on the wrong side", _TOOL_ORDER),
        ("Rz Ry Rx multiplied in the reverse order", _PRODUCT_REVERSED),
    ],
    "task1_test2": [
        ("the YPR triple read as (roll, pitch, yaw)", _TOOL_AS_RPY),
        ("the triple stored in (roll, pitch, yaw) order", _TRIPLE_IN_RPY_ORDER),
        ("the angle between the two tools in degrees", _TOOL_ANGLE_DEGREES),
        ("the angle between the two tools as the sum of the turns", _TOOL_ANGLE_SUM),
        ("the two readings swapped", _READINGS_SWAPPED),
    ],
    "task2_test1": [
        ("orientation_error from the goal to the tool (sign)", _ERROR_FUNCTION_SIGN),
        ("the goal triple read as (roll, pitch, yaw)", _GOAL_AS_RPY),
        ("the rotation axis left in tool coordinates", _AXIS_IN_TOOL_FRAME),
        ("the error from the goal to the tool", _ERROR_SIGN),
        ("orientation_error left in the frame of R", _ERROR_IN_TOOL_FRAME),
        ("the axis of angle_axis with the wrong sign", _AXIS_SIGN),
    ],
    "task2_test2": [
        ("the goal's pose inverted instead of the tool's", _INVERTED_THE_GOAL),
        ("the goal triple read as (roll, pitch, yaw)", _GOAL_AS_RPY),
    ],
    "task3_test1": [
        ("the tool offset not rotated into the base frame", _OFFSET_NOT_ROTATED),
        ("the course's [w; v] transport matrix in linear-first code", _COURSE_TRANSPORT),
        ("the tool's own offset used instead of the argument offset", _OFFSET_ARGUMENT_IGNORED),
        ("the desired twist stacked [w; v]", _TWIST_COURSE_ORDER),
        ("the row swap taken as the identity", _SWAP_IDENTITY),
    ],
    "task3_test2": [
        ("spare_joints numbered from 0", "spare_joints = [4, 6]"),
        ("joint 7 dropped to solve a square 6x6 system", _SQUARE_SYSTEM),
        ("the first right singular vector taken for the null space",
         "spare = np.linalg.svd(J_T0)[2][0]"),
        ("the slide's column with an angular part (z_6 twice)", _SLIDE_TURNS),
        ("the slide's column along the tool's z axis", _SLIDE_ALONG_TOOL_Z),
    ],
    "task4_test1": [
        ("the step taken before the stop test", _STEP_THEN_TEST),
        ("the stop test on the error instead of the twist", _STOP_ON_ERROR),
        ("the report's skip rule instead of clamping", _SKIP_RULE),
        ("the joints left free of their limits", _NO_CLAMP),
        ("the Euler step multiplied by the gain again", _STEP_WITH_GAIN),
        ("the Euler step without the time step", _STEP_WITHOUT_TS),
    ],
    # the run's own mistakes: a wrong loop (task4_test1) or twist (task3_test1) loses the points
    # of its own test only, the run is graded as a correct use of them
    "task4_test2": [
        ("k_stop counts samples instead of steps", "k_stop = len(Q_run)"),
        ("the run with a ten times finer step", _RUN_FINER_STEP),
        ("T_final of the end-effector, without the tool", _FINAL_END_EFFECTOR),
        ("e_final from the goal to the tool", _FINAL_ERROR_SIGN),
        ("e_final stacked [e_o; e_p]", _FINAL_ERROR_ORDER),
    ],
    "task4_test3": [
        ("the (roll, pitch, yaw) run with the YPR tool", _SWAPPED_RUN_KEEPS_TOOL),
        ("the (roll, pitch, yaw) twist towards the YPR goal", _SWAPPED_TWIST_YPR_GOAL),
        ("swapped_stops taken as True", "swapped_stops = True"),
        ("joints at a limit counted strictly beyond it", _LIMITS_STRICT),
        ("off_line taken as the length of the chord", _OFF_LINE_CHORD),
        ("off_line in millimetres", _OFF_LINE_MM),
    ],
    "task4_test4": [
        ("the factor per step taken as exp(-kappa ts)",
         "factor_per_step = float(np.exp(-GAIN_ANGULAR * TS))"),
        ("the factor per step taken as kappa ts", "factor_per_step = GAIN_ANGULAR * TS"),
        ("the stop predicted from the position error",
         "k_predicted = int(np.ceil(np.log(STOP / (GAIN_ANGULAR * np.linalg.norm(e0[:3])))"
         " / np.log(factor_per_step)))"),
        ("the stability limit taken at kappa ts = 1", "kts_limit = 1.0"),
    ],
    "task5_test1": [
        ("the yaw difference not wrapped into (-pi, pi]", _UNWRAPPED),
        ("the angle between the errors in radians", _ANGLE_IN_RADIANS),
        ("the naive loop converts the rates with E(phi) after all", _NAIVE_CONVERTED),
        ("naive_stops taken as True", "naive_stops = True"),
    ],
    "task5_test2": [
        ("E(phi) with its columns in the order (yaw, pitch, roll)", _E_COLUMNS_REVERSED),
        ("the roll axis of E(phi) without the pitch turn", _E_ROLL_AXIS_WITHOUT_PITCH),
        ("E(phi) transposed", _E_TRANSPOSED),
        ("E(phi) left out: the naive loop's run", "Q_analytic = Q_naive"),
        ("analytic_stops taken as False", "analytic_stops = False"),
        ("E(phi) taken singular at pitch 0", "pitch_singular = 0.0"),
    ],
}
