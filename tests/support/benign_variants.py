"""Correct answers written another way, per chapter: a right answer earns full marks however it is written.

tests/test_grading_trust.py grades, for every chapter, the instructor's solutions
with some answers re-computed by another valid method -- genuinely different code,
with other intermediate names -- and expects full marks: a grader that compares
*how* an answer is computed, instead of *what* it computes, would fail them.

:data:`VARIANTS` maps ``chapter -> {grade_id: (what, code)}``: ``code`` is appended
to that answer cell of the solutions (it redefines the cell's answers, so the tests
read the variant), ``what`` says in a few words how it differs. Each chapter has at
least one variant that is another method (``np.linalg.solve`` instead of an inverse,
a cross product instead of components written out, a closed form instead of a library
call, another finite-difference stencil), not only other names.

:data:`CRASH` and :data:`HANG` are the incidents the trust suite puts in a chapter's one benign
submission (tests/test_grading_trust.py), after the code of ungraded cells: a kernel that dies, at
the end of the last *Try it yourself* cell (:func:`with_incident`), and a cell that never ends (it
sleeps, so that waiting for the time limit costs no CPU; interrupted at the limit), at the end of
an earlier one (:func:`with_earlier_hang`): the notebook runs on after the hang, and the crash
comes after it. Where no test follows the last *Try it yourself* cell, the crash is not run at
all: the student's kernel stops after the last cell that is graded or holds an answer.
"""

from __future__ import annotations

import ast
import copy
import importlib.util
import json
import os
from pathlib import Path

#: ``os._exit`` in an ungraded cell: the kernel dies
CRASH = "import os\n\nos._exit(1)  # my experiment killed the kernel\n"

#: a cell that never ends (it sleeps: waiting for the time limit costs no CPU)
HANG = "import time\n\nwhile True:  # my experiment never ends\n    time.sleep(0.5)\n"

VARIANTS: dict[str, dict[str, tuple[str, str]]] = {
    "01_leg_kinematics": {
        "task3_answer1": ("the Jacobian column by column (sp.diff), the rates by least squares", '''

# written another way: the Jacobian one column per joint, the rates by least squares
columns = [sp.diff(r_BF, joint) for joint in q_sym]
J_sym = sp.Matrix.hstack(*columns)


def joint_velocity(v, J=J_lift):
    return np.linalg.lstsq(J, v, rcond=None)[0]


lifts = bool(v_cmd[2] > 0)  # z of B points up: only a positive z velocity lifts
v_lift = -v_cmd / np.linalg.norm(v_cmd)
dq_cmd = joint_velocity(v_cmd)
dq_lift = joint_velocity(v_lift)
'''),
        "task4_answer1": ("Newton's method as a while loop on the normal equations (no pseudoinverse), "
                          "stopped when the step, not the error, is below tol", '''

def newton_ik(r_goal, q0, damping=0.0, tol=1e-10, max_iterations=50):
    """Written another way: a while loop, steps from (J^T J + lambda^2 I) dq = J^T e, that
    stops once a step is below tol (the foot is then within tol of the goal as well)."""
    path = [np.asarray(q0, dtype=float)]
    step_size = np.inf
    while step_size > tol and len(path) <= max_iterations:
        jac = leg.position_jacobian(path[-1])
        error = r_goal - leg.fk(path[-1])[:3, 3]
        normal = jac.T @ jac + damping**2 * np.eye(3)
        step = np.linalg.solve(normal, jac.T @ error)
        path.append(path[-1] + step)
        step_size = np.linalg.norm(step)
    return np.vstack(path)


Q_newton = newton_ik(r_goal, q0_ik)
r_iter = np.array([leg.fk(q)[:3, 3] for q in Q_newton])
e_iter = np.array([np.linalg.norm(r_goal - r) for r in r_iter])
'''),
        "task4_answer2": ("the closed form by the law of cosines on the knee, a list per branch; "
                          "the grid by itertools.product, the ends wrapped by atan2", '''

def ik_closed_form(p):
    """Written another way: the knee angle from the law of cosines, beta from two angles."""
    rel = np.asarray(p, dtype=float) - HIP
    solutions = []
    for side in (1.0, -1.0):  # foot below / above the hip's x axis
        dist = side * np.hypot(rel[1], rel[2])  # signed distance L in the leg plane
        alpha_ = np.arctan2(side * rel[1], -side * rel[2])
        u_, w_ = rel[0], 1.0 - dist  # the foot seen from the beta joint
        reach_sq = u_**2 + w_**2
        cos_inner = (2.0 - reach_sq) / 2.0  # the angle between thigh and shank
        if reach_sq == 0 or abs(cos_inner) > 1:
            continue
        inner = np.arccos(cos_inner)
        for knee in (np.pi - inner, inner - np.pi):
            beta_ = np.arctan2(-u_, -w_) - knee / 2
            q = np.array([alpha_, beta_, knee])
            solutions.append(np.arctan2(np.sin(q), np.cos(q)))
    return np.array(solutions).reshape(-1, 3)


closed = ik_closed_form(r_goal)

import itertools  # written another way: the 27 starts as a product, a list of ends

starts = itertools.product(np.deg2rad([-60, 0, 60]), np.deg2rad([-60, 0, 60]),
                           np.deg2rad([-150, 10, 150]))
ends = []
for start in starts:
    end = newton_ik(r_goal, np.array(start))[-1]
    end = np.arctan2(np.sin(end), np.cos(end))
    new_end = all(np.max(np.abs(end - other)) > 1e-6 for other in ends)
    if np.linalg.norm(leg.fk(end)[:3, 3] - r_goal) <= 1e-10 and new_end:
        ends.append(end)
found = np.array(ends)[np.argsort([end[2] for end in ends])]
'''),
        "task5_answer1": (
            "the loop indexed by k with np.linalg.solve, the circle from complex numbers, the discrete lag",
            '''

phase = np.exp(1j * OMEGA * t)  # written another way: the circle as a complex number
r_des = c + RADIUS * np.column_stack([phase.imag, np.zeros_like(t), phase.real])
v_des = RADIUS * OMEGA * np.column_stack([phase.real, np.zeros_like(t), -phase.imag])


def track(q0, r_des, v_des, kp=KP, ts=TS, feedforward=True):
    """Written another way: preallocated rows, indexed by k, J solved instead of J+."""
    rows = np.empty((len(r_des), 3))
    q = np.asarray(q0, dtype=float)
    for k in range(len(r_des)):
        rows[k] = q
        wanted = kp * (r_des[k] - leg.fk(q)[:3, 3])
        if feedforward:
            wanted = wanted + v_des[k]
        q = q + ts * np.linalg.solve(leg.position_jacobian(q), wanted)
    return rows


Q_ff = track(q0_track, r_des, v_des)
Q_p = track(q0_track, r_des, v_des, feedforward=False)
err_ff = np.linalg.norm(r_des - leg.fk(Q_ff)[:, :3, 3], axis=1)
err_p = np.linalg.norm(r_des - leg.fk(Q_p)[:, :3, 3], axis=1)
z_step = np.exp(1j * OMEGA * TS)  # the exact discrete-time lag of the Euler loop
lag_predicted = RADIUS * abs(z_step - 1) / abs(z_step - 1 + KP * TS)
'''),
    },
    "03_three_rpr": {
        "task1_answer1": ("leg lengths one leg at a time with hypot", '''

def ik(pose, robot=robot):  # written another way: leg by leg, the platform point rotated by hand
    x, y, phi = pose
    c, s = np.cos(phi), np.sin(phi)
    lengths = [np.hypot(x + c * bx - s * by - ax, y + s * bx + c * by - ay)
               for (ax, ay), (bx, by) in zip(robot.base_anchors, robot.platform_anchors)]
    return np.array(lengths)


# checked with robokin after writing my own
assert np.allclose(ik(POSE0), robot.inverse_kinematics(POSE0))


rho0 = ik(POSE0)
'''),
        "task2_answer1": ("the twin pose through complex numbers, w' = -conj(z) w", '''

def twin_pose(pose, robot=robot):  # written another way: B1 - A1 as a complex number w, z = e^(i phi)
    a1 = complex(*robot.base_anchors[0])
    twin = a1 - np.exp(-1j * pose[2]) * (complex(pose[0], pose[1]) - a1)
    return np.array([twin.real, twin.imag, -pose[2]])
'''),
        "task2_answer2": ("modes with phi in [0, 2 pi), N and Delta both times z", '''

_my_fk_principal = my_fk


def my_fk(rho, robot=robot, F=F_of_phi):  # written another way: angles in [0, 2 pi), sorted there
    modes = _my_fk_principal(rho, robot, F).copy()
    modes[:, 2] = np.mod(modes[:, 2], 2 * np.pi)
    return modes[np.argsort(modes[:, 2])]


# checked with robokin after writing my own
assert len(my_fk(CLASSIC_RHO, three_rpr_classic())) == three_rpr_classic().forward_kinematics(CLASSIC_RHO).count


_cramer_principal = cramer_parts


def cramer_parts(phi, rho, robot=robot):  # written another way: w = (z N) / (z Delta)
    N, Delta = _cramer_principal(phi, rho, robot)
    return np.exp(1j * phi) * N, np.exp(1j * phi) * Delta


N_powers, Delta_powers = (0, 3), (0, 2)
modes0 = my_fk(rho0)
'''),
        "task3_answer1": ("the moment column by a 3D cross product", '''

def inverse_jacobian(pose, robot=robot):  # written another way: rows [u_i, (R b_i x u_i)_z], np.cross
    x, y, phi = pose
    rotated = robot.platform_anchors @ rot(phi).T
    legs = np.array([x, y]) + rotated - robot.base_anchors
    units = legs / np.linalg.norm(legs, axis=1, keepdims=True)
    flat = np.zeros((len(legs), 1))
    moments = np.cross(np.hstack([rotated, flat]), np.hstack([units, flat]))[:, 2]
    return np.column_stack([units, moments])


A0 = inverse_jacobian(POSE0)
J0 = np.linalg.inv(A0)
'''),
    },
    "04_cartesian_control": {
        "task1_answer1": ("Rz Ry Rx multiplied out by hand instead of transform_from_rpy", '''

def transform_from_ypr(ypr, position):  # written another way: the three rotations by hand
    yaw, pitch, roll = ypr
    cz, sz, cy, sy, cx, sx = (np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch),
                              np.cos(roll), np.sin(roll))
    about_z = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    about_y = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
    about_x = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    pose = np.eye(4)
    pose[:3, :3] = about_z @ about_y @ about_x
    pose[:3, 3] = position
    return pose


T_ET = transform_from_ypr(TOOL_YPR, TOOL_OFFSET)
tool_arm = chain_with_tool(arm, T_ET, name="genova_arm+tool")
T_BT0 = tool_arm.fk(Q0)
'''),
        "task2_answer1": ("the angle and axis from the unit quaternion, the error from R_goal R^T", '''

def angle_axis(R):  # written another way: from the unit quaternion (w >= 0) of R
    w, x, y, z = quaternion_from_rotation(R)
    vector = np.sign(w) * np.array([x, y, z])
    return vector / np.linalg.norm(vector), 2 * np.arctan2(np.linalg.norm(vector), abs(w))


def orientation_error(R, R_goal):  # written another way: R_goal R^T is already in B
    axis, angle = angle_axis(R_goal @ R.T)
    return angle * axis
'''),
        "task3_answer1": ("the transport column by column with cross products; the slide's column as the "
                          "tool's motion per metre of slide; spare with the other sign", '''

def my_tool_jacobian(q, offset=TOOL_OFFSET):  # written another way: v_T = v_E + w x r, per column
    J_E = arm.jacobian(q)
    r = arm.fk(q)[:3, :3] @ np.asarray(offset, dtype=float)
    return np.vstack([J_E[:3] + np.cross(J_E[3:].T, r).T, J_E[3:]])


J_T0 = my_tool_jacobian(Q0)
qdot0 = np.linalg.pinv(J_T0) @ twist0

def slide_column(q):  # written another way: the tool pose is affine in q6, so a secant is exact
    step = np.zeros(7)
    step[5] = 0.1  # m along the slide
    before = tool_arm.fk(q)
    after = tool_arm.fk(np.asarray(q, dtype=float) + step)
    moved = np.r_[after[:3, 3] - before[:3, 3], rotation_log(after[:3, :3] @ before[:3, :3].T)]
    return moved / 0.1


# written another way: the null space as the last column of a complete QR of J_T^T, with the
# other sign than the solutions' (either sign is right)
spare = np.linalg.qr(J_T0.T, mode="complete")[0][:, -1]
spare = -spare * np.sign(spare[np.flatnonzero(np.abs(spare) > 1e-6)[0]])
'''),
        "task4_answer1": ("the loop over the sample times, preallocated rows, J^+ nu by least squares, "
                          "the clamp by minimum and maximum", '''

# written another way: the sample times from linspace, rows filled in place, the minimum-norm
# joint rates by lstsq, the limits by np.minimum and np.maximum
def kinematic_loop(twist_of, q0, ts=TS, t_end=T_END, robot=tool_arm):
    low, high = robot.limits[:, 0], robot.limits[:, 1]
    times = np.linspace(0.0, t_end, int(round(t_end / ts)) + 1)
    configurations = np.empty((len(times), len(q0)))
    twists = np.empty((len(times), 6))
    configurations[0] = q0
    for k, _ in enumerate(times):
        twists[k] = twist_of(configurations[k])
        speeds = np.linalg.norm(twists[k].reshape(2, 3), axis=1)  # |v|, |w|
        if np.all(speeds < STOP) or k == len(times) - 1:
            return configurations[: k + 1].copy(), twists[: k + 1].copy()
        rates = np.linalg.lstsq(robot.jacobian(configurations[k]), twists[k], rcond=None)[0]
        configurations[k + 1] = np.minimum(np.maximum(configurations[k] + ts * rates, low), high)
'''),
        "task4_answer2": ("the final error from the last commanded twist divided by the gains", '''

# written another way: the loop stops on the twist kappa e, so e at the last sample is the twist
# there divided by the gains
Q_run, V_run = kinematic_loop(my_twist, Q0)
k_stop = len(V_run) - 1
q_final = Q_run[k_stop]
T_final = fk_table(q_final) @ T_ET
e_final = V_run[-1] / np.repeat([GAIN_LINEAR, GAIN_ANGULAR], 3)
'''),
        "task4_answer3": ("the distance from the line by a cross product, the limits by each joint's range", '''

# written another way: the (roll, pitch, yaw) tool built again, its pose by the arm's pose
swapped_tool = transform_from_rpy(TOOL_YPR, TOOL_OFFSET)
swapped_arm = chain_with_tool(arm, swapped_tool)


def swapped_twist(q):
    pose = arm.fk(q) @ swapped_tool
    turn = orientation_error(pose[:3, :3], T_BG_rpy[:3, :3])
    return np.concatenate([GAIN_LINEAR * (T_BG_rpy[:3, 3] - pose[:3, 3]), GAIN_ANGULAR * turn])


Q_swapped, V_swapped = kinematic_loop(swapped_twist, Q0, robot=swapped_arm)
swapped_stops = bool(np.all(np.linalg.norm(V_swapped[-1].reshape(2, 3), axis=1) < STOP))
reached = (Q_swapped.min(axis=0) <= Q_MIN) | (Q_swapped.max(axis=0) >= Q_MAX)
joints_at_limit = int(np.count_nonzero(reached))
origins = np.array([(fk_table(q) @ T_ET)[:3, 3] for q in Q_run])
chord = origins[-1] - origins[0]
off_line = float(np.max(np.linalg.norm(np.cross(origins - origins[0], chord), axis=1))
                 / np.linalg.norm(chord))
'''),
        "task4_answer4": ("the stop predicted by stepping the model's error, the continuous stop by logs", '''

# written another way: the first-order model stepped until its twist meets the stop test
factor_per_step = float(1.0 - TS * GAIN_LINEAR)
model_error_0 = np.array([np.linalg.norm(e0[:3]), np.linalg.norm(e0[3:])])
model_error, k_predicted = model_error_0.copy(), 0
while np.any(np.r_[GAIN_LINEAR, GAIN_ANGULAR] * model_error >= STOP):
    model_error = factor_per_step * model_error
    k_predicted += 1
# in continuous time each part meets the test at ln(kappa |e(0)| / STOP) / kappa: the later one
t_continuous = float(max(np.log(gain * size / STOP) / gain
                         for gain, size in zip([GAIN_LINEAR, GAIN_ANGULAR], model_error_0)))
kts_limit = 1.0 - (-1.0)  # 1 - kappa ts reaches -1
'''),
        "task5_answer1": ("angles wrapped by the complex exponential, the angle between by arctan2, "
                          "the true error by the trace", '''

def rpy_difference(R, R_goal):  # written another way: wrapped as the angle of exp(i x)
    goal, now = np.array(rpy_from_rotation(R_goal)), np.array(rpy_from_rotation(R))
    return np.angle(np.exp(1j * (goal - now)))


R_goal = T_BG[:3, :3]
tool_rotations = [tool_arm.fk(q)[:3, :3] for q in Q_run]
E_rpy = np.vstack([rpy_difference(R, R_goal) for R in tool_rotations])
E_aa = np.vstack([orientation_error(R, R_goal) for R in tool_rotations])
angle_between = np.degrees(np.arctan2(np.linalg.norm(np.cross(E_rpy, E_aa), axis=1),
                                      np.einsum("ij,ij->i", E_rpy, E_aa)))


def naive_twist(q):  # written another way: my_twist's linear part, the RPY difference as w
    return np.r_[my_twist(q)[:3], GAIN_ANGULAR * rpy_difference(tool_arm.fk(q)[:3, :3], R_goal)]


Q_naive = kinematic_loop(naive_twist, Q0)[0]
theta_naive = np.array([
    np.arccos(np.clip((np.trace(R_goal @ tool_arm.fk(q)[:3, :3].T) - 1) / 2, -1.0, 1.0))
    for q in Q_naive
])
'''),
        "task5_answer2": ("E(phi) from the columns of R: the roll axis is R x, the pitch axis z x R x "
                          "normalised", '''

def rpy_rate_matrix(R):  # written another way: Rz Ry Rx x = R x, and Rz y is z x (R x) / cos(pitch)
    roll_axis = np.asarray(R)[:, 0]
    pitch_axis = np.cross([0.0, 0.0, 1.0], roll_axis)
    return np.column_stack([roll_axis, pitch_axis / np.linalg.norm(pitch_axis), [0.0, 0.0, 1.0]])


def analytic_twist(q, rpy_difference=rpy_difference):
    R = tool_arm.fk(q)[:3, :3]
    return np.r_[my_twist(q)[:3], GAIN_ANGULAR * rpy_rate_matrix(R) @ rpy_difference(R, T_BG[:3, :3])]


Q_analytic, V_analytic = kinematic_loop(analytic_twist, Q0)
analytic_stops = bool(np.all(np.linalg.norm(V_analytic[-1].reshape(2, 3), axis=1) < STOP))
pitch_singular = float(np.arccos(0.0))  # det E(phi) = cos(pitch) = 0
'''),
    },
    "05_baxter_circle": {
        "task1_answer2": ("a fourth-order central difference stencil", '''

def jv_fd(q, h=1e-4):  # written another way: the five-point stencil, error O(h^4)
    def hand(dq):
        return arm.fk(q + dq)[:3, 3]

    return np.column_stack([
        (hand(-2 * step) - 8 * hand(-step) + 8 * hand(step) - hand(2 * step)) / (12 * h)
        for step in h * np.eye(7)
    ])
'''),
        "task2_answer1": ("the circle as a complex number, its velocity as omega x (r - centre)", '''

def reference(time):  # written another way: c + r exp(i omega t), velocity omega e_z x (r - c)
    turn = RADIUS * np.exp(1j * OMEGA * np.atleast_1d(np.asarray(time, dtype=float)))
    offset = np.column_stack([turn.real, turn.imag, np.zeros(turn.shape)])
    return CENTRE + offset, np.cross([0.0, 0.0, OMEGA], offset)
'''),
        "task3_answer1": ("the loop with a preallocated array and J^T (J J^T)^-1", '''

def resolved_rate(q, r_des, v_des, kp=KP):  # written another way: the right inverse by solve
    J = arm.position_jacobian(q)
    return J.T @ np.linalg.solve(J @ J.T, v_des + kp * (r_des - arm.fk(q)[:3, 3]))


def track(q0, r_des, v_des, kp=KP, ts=TS, rate=resolved_rate):  # another way: rows in place
    Q = np.empty((len(r_des), 7))
    Q[0] = q0
    for k in range(len(r_des) - 1):
        Q[k + 1] = Q[k] + ts * rate(Q[k], r_des[k], v_des[k], kp)
    return Q
'''),
        "task4_answer1": ("rho as the lengths of J_v's columns, the chord by the law of cosines", '''

# written another way: a revolute joint's column of J_v is z_j x (r - p_j), of length rho_j
rho = np.linalg.norm(arm.position_jacobian(Q_START), axis=0)


def chord_length(rho, step):  # written another way: |p1 - p0|^2 = 2 rho^2 (1 - cos step)
    return float(np.sqrt(2 * rho**2 * (1 - np.cos(step))))


chord = np.array([chord_length(r, s) for r, s in zip(rho, 0.1 * SPAN)])
'''),
        "task4_answer2": ("hand_to with J^T (J J^T)^-1 and a while loop", '''

def hand_to(q, target, tol=1e-10, max_steps=50):  # written another way
    q = np.asarray(q, dtype=float).copy()
    steps = 0
    while steps < max_steps:
        J = arm.position_jacobian(q)
        e = np.asarray(target, dtype=float) - arm.fk(q)[:3, 3]
        if e @ e < tol**2:
            break
        q += J.T @ np.linalg.solve(J @ J.T, e)
        steps += 1
    return q


Q_SAME = np.array([hand_to(guess, P_START) for guess in guesses])
same_q = np.array([track(q, r_ref, v_ref) for q in Q_SAME])
# written another way: the hand as the origin of the last of the chain's frames
same_hand = arm.frames(same_q.reshape(-1, 7))[:, -1, :3, 3].reshape(len(Q_SAME), -1, 3)
'''),
        "task5_answer1": ("sigma_min as the root of the smallest eigenvalue of J_v J_v^T, the "
                          "first crossing by a while loop", '''

def sigma_min_of(q):  # written another way: sigma_i^2 are the eigenvalues of J J^T
    J = arm.position_jacobian(q)
    return float(np.sqrt(max(np.linalg.eigvalsh(J @ J.T)[0], 0.0)))


def closest_approach(Q, ts=TS, threshold=0.01):  # written another way: one sample at a time
    values = [sigma_min_of(q) for q in Q]
    k = 0
    while k < len(values) and values[k] >= threshold:
        k += 1
    return min(values), (k * ts if k < len(values) else None)
'''),
        "task5_answer2": ("the failing run found by its threshold crossing, u_3 from the "
                          "eigenvectors of J_v J_v^T", '''

# written another way: the lost direction is the eigenvector of J J^T of the smallest eigenvalue
crossings = {name: closest_approach(Q)[1] for name, Q in runs_open.items()}
failing = [name for name, time in crossings.items() if time is not None][0]
t_loss = crossings[failing]
sample = int(np.rint(t_loss / TS))
J_loss = arm.position_jacobian(runs_open[failing][sample])
lost_direction = np.linalg.eigh(J_loss @ J_loss.T)[1][:, 0]
step = runs_open[failing][sample + 1] - runs_open[failing][sample]
speed_loss = float(np.sqrt(step @ step)) / TS
'''),
        "task5_answer3": ("DLS as the least-squares solution of [J; lambda I] qdot = [v; 0]", '''

def dls_rate(q, r_des, v_des, kp=KP, damping=LAMBDA):  # written another way: augmented lstsq
    J = arm.position_jacobian(q)
    v = v_des + kp * (r_des - arm.fk(q)[:3, 3])
    stacked = np.vstack([J, damping * np.eye(7)])
    return np.linalg.lstsq(stacked, np.r_[v, np.zeros(7)], rcond=None)[0]


def track_damped(q0, r_des, v_des, kp=KP, ts=TS, damping=LAMBDA):  # rows filled in place
    Q = np.empty((len(r_des), 7))
    Q[0] = q0
    for k in range(len(r_des) - 1):
        Q[k + 1] = Q[k] + ts * dls_rate(Q[k], r_des[k], v_des[k], kp, damping)
    return Q
'''),
    },
    "06_ar601_leg_ik": {
        "task2_answer2": ("the report's cosine from the foot position written out", '''

def report_theta6(p, L12, L3_):  # written another way: the cosine as a ratio of arrays
    position = np.asarray(p, dtype=float)
    squared = position[0] ** 2 + position[2] ** 2
    return float(np.arccos((squared - L12 * L12 - L3_ * L3_) / (2.0 * L12 * L3_)))


def report_theta6_of_q6(q6, L12, L3_):  # written another way: x^2 + z^2 expanded
    reach = L12 + L3_ * np.cos(q6)
    return float(np.arccos((reach**2 - L12**2 - L3_**2) / (2.0 * L12 * L3_)))
'''),
        "task3_answer1": ("the knee from the interior angle (pi - arccos), the ankle point "
                          "by a homogeneous product", '''

def ankle_point(T, L3_=L3):  # written another way: the point (0, 0, L3) of the foot frame
    return (T @ np.array([0.0, 0.0, L3_, 1.0]))[:3]


def knee_angle(d, l1_=L1, l2_=L2):  # written another way: pi minus the interior angle
    cos_interior = (l1_**2 + l2_**2 - d**2) / (2 * l1_ * l2_)
    if not abs(cos_interior) <= 1 + 1e-9:
        return float("nan")  # out of reach
    return np.pi - np.arccos(min(1.0, max(-1.0, cos_interior)))


d_goal = float(np.sqrt(np.sum(ankle_point(T_goal) ** 2)))
'''),
        "task5_answer1": ("the sweep as one comprehension per array, the different rows by "
                          "pairwise differences", '''

def sole_sweep(heights, leg_ik=my_leg_ik):  # written another way: all solutions first
    solutions = [np.reshape(leg_ik(transform(np.eye(3), [0, 0, -h])), (-1, 6)) for h in heights]
    counts = np.array([Q.shape[0] for Q in solutions], dtype=int)
    smallest = np.array([np.linalg.svd(leg.jacobian(Q[0]), compute_uv=False).min()
                         if Q.shape[0] else float("nan") for Q in solutions])
    return counts, smallest


def different_solutions(Q):  # written another way: a row counts unless an earlier one is it
    Q = np.reshape(Q, (-1, 6))
    gaps = np.abs(np.angle(np.exp(1j * (Q[:, None, :] - Q[None, :, :])))).max(axis=2)
    return int(sum(not np.any(gaps[k, :k] <= 1e-9) for k in range(len(Q))))


n_solutions, sigma_min = sole_sweep(heights)
'''),
    },
}


# ------------------------------------------------------------ chapters without an entry above
# A chapter that :data:`VARIANTS` does not list (a new one, made by tools/authoring/new_chapter.py) takes
# the ``VARIANTS`` of its grading-mutation file (tests/grading_mutations/<chapter>.py, which the
# scaffold writes with another method for each of its tasks), or else a default derived from
# its notebook (:func:`derived_variants`), so that no per-chapter entry is needed here.

#: the chapters' grading-mutation files (as tests/test_grading_mutations.py reads them)
MUTATIONS_DIR = Path(os.environ.get("ROBOKIN_GRADING_MUTATIONS",
                                    Path(__file__).resolve().parent.parent / "grading_mutations")).resolve()
#: the chapter notebooks (as tests/test_nbgrader.py reads them)
NOTEBOOKS = Path(os.environ.get("ROBOKIN_NBGRADER_NOTEBOOKS",
                                Path(__file__).resolve().parents[2] / "notebooks")).resolve()


def file_variants(chapter: str) -> dict[str, tuple[str, str]] | None:
    """``VARIANTS`` of the chapter's grading-mutation file, or None when it has none."""
    path = MUTATIONS_DIR / f"{chapter}.py"
    if not path.is_file():
        return None
    spec = importlib.util.spec_from_file_location(f"grading_variants_{chapter}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    found = getattr(module, "VARIANTS", None)
    if found is None:
        return None
    assert isinstance(found, dict) and all(isinstance(v, tuple) and len(v) == 2 for v in found.values()), (
        f"{chapter}: VARIANTS in {path} must be {{grade_id: (what, code)}}")
    return found


def derived_variants(nb: dict) -> dict[str, tuple[str, str]]:
    """A default for a chapter without variants: every answer cell that defines a function it
    declares (``metadata.robokin.declare``) redefines it under other names, calling the first.

    Not another method (write one in the chapter's grading-mutation file), but a test that
    the grader reads *what* a declared answer computes: its name, code and object change.
    """
    out: dict[str, tuple[str, str]] = {}
    for cell in nb["cells"]:
        meta = cell.get("metadata", {}).get("robokin", {})
        grade_id = _grade_id(cell)
        if cell["cell_type"] != "code" or meta.get("role") != "answer" or not grade_id:
            continue
        try:
            tree = ast.parse(_source(cell))
        except SyntaxError:
            continue
        functions = {s.name for s in tree.body if isinstance(s, ast.FunctionDef)}
        name = next((n for n in meta.get("declare", []) if n in functions), None)
        if name is None:
            continue
        out[grade_id] = (f"{name} redefined under other names, calling the first definition", f"""

# written another way: {name} wrapped under other names (a default: no variant written)
import functools

{name}_as_first_written = {name}


@functools.wraps({name}_as_first_written)
def {name}(*arguments, **keywords):
    result_of_the_first = {name}_as_first_written(*arguments, **keywords)
    return result_of_the_first
""")
    assert out, "no answer cell defines a function it declares: write VARIANTS in the chapter's grading-mutation file"
    return out


class _WithDefaults(dict):
    """:data:`VARIANTS` with, for a chapter it does not list, the variants of :func:`file_variants`
    or :func:`derived_variants` (read once, on first use)."""

    def __missing__(self, chapter: str) -> dict[str, tuple[str, str]]:
        found = file_variants(chapter)
        if found is None:
            path = NOTEBOOKS / f"{chapter}.ipynb"
            if not path.is_file():
                raise KeyError(chapter)
            found = derived_variants(json.loads(path.read_text(encoding="utf-8")))
        self[chapter] = found
        return found


VARIANTS = _WithDefaults(VARIANTS)


def _grade_id(cell: dict) -> str | None:
    return cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")


def _source(cell: dict) -> str:
    text = cell.get("source", "")
    return "".join(text) if isinstance(text, list) else text


def written_another_way(correct: dict, chapter: str) -> dict:
    """``correct`` (the solutions) with the answers of :data:`VARIANTS` [chapter] re-computed."""
    nb = copy.deepcopy(correct)
    missing = set(VARIANTS[chapter])
    for cell in nb["cells"]:
        variant = VARIANTS[chapter].get(_grade_id(cell) or "")
        if variant:
            cell["source"] = _source(cell).rstrip() + "\n" + variant[1]
            missing.discard(_grade_id(cell))
    assert not missing, f"{chapter}: no answer cells {sorted(missing)} for the variants"
    return nb


def last_try_cell(nb: dict) -> dict:
    """The last ungraded code cell a student may edit (a *Try it yourself* cell: no nbgrader metadata)."""
    return [c for c in nb["cells"] if c["cell_type"] == "code" and "nbgrader" not in c.get("metadata", {})][-1]


def with_incident(nb: dict, code: str) -> dict:
    """``nb`` with ``code`` at the end of its last ungraded (*Try it yourself*) cell."""
    nb = copy.deepcopy(nb)
    cell = last_try_cell(nb)
    cell["source"] = _source(cell).rstrip() + "\n\n" + code
    return nb


def earlier_try_cell(nb: dict) -> dict | None:
    """The ungraded code cell a student may edit before :func:`last_try_cell`, None when the chapter has one."""
    cells = [c for c in nb["cells"] if c["cell_type"] == "code" and "nbgrader" not in c.get("metadata", {})]
    return cells[-2] if len(cells) > 1 else None


#: the id of the cell :func:`with_own_cell` adds (:func:`with_earlier_hang`, where a chapter has one
#: *Try it yourself* cell)
OWN_CELL_ID = "my-own-experiment"


def with_earlier_hang(nb: dict, code: str) -> dict:
    """``nb`` with ``code`` in an ungraded cell before the last one, where :func:`with_incident` puts the crash.

    At the end of the *Try it yourself* cell before the last (:func:`earlier_try_cell`); in a
    chapter that has one only, in a code cell of the student's own (:func:`with_own_cell`).
    Either way tests come after it in every chapter, so that their full marks show that the
    notebook ran on after the cell was stopped.
    """
    nb = copy.deepcopy(nb)
    cell = earlier_try_cell(nb)
    if cell is None:
        return with_own_cell(nb, code)
    cell["source"] = _source(cell).rstrip() + "\n\n" + code
    return nb


def with_own_cell(nb: dict, code: str) -> dict:
    """``nb`` with ``code`` in a code cell of the student's own, added right after the first test cell.

    As a student adds a cell to experiment in, ungraded like the *Try it yourself* cells (no
    nbgrader metadata); tests come after it in every chapter, so that the student's kernel runs it
    (it stops after the last cell that is graded or holds an answer).
    """
    nb = copy.deepcopy(nb)
    cells = nb["cells"]
    first_test = next(i for i, c in enumerate(cells)
                      if c["cell_type"] == "code" and c.get("metadata", {}).get("nbgrader", {}).get("grade"))
    own: dict = {"cell_type": "code", "metadata": {}, "source": code, "outputs": [], "execution_count": None}
    if "id" in cells[first_test]:
        own["id"] = OWN_CELL_ID
    cells.insert(first_test + 1, own)
    return nb
