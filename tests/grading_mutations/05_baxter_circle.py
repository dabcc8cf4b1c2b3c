"""Wrong answers that each autograded test of chapter 5 must reject."""

MUTATIONS = {
    "task1_test1": [
        ("the link transform in standard-DH order, R_z T_z T_x R_x",
         "def mdh_link(a, alpha, d, theta):\n"
         "    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)\n"
         "    return np.array([[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st],\n"
         "                     [0.0, sa, ca, d], [0.0, 0.0, 0.0, 1.0]])"),
        ("the joint offsets of the table left out",
         "def fk_table(table, q, d_hand=D_HAND):\n"
         "    T = np.eye(4)\n"
         "    for (a, alpha, d, off), qi in zip(table, q):\n"
         "        T = T @ mdh_link(a, alpha, d, qi)\n"
         "    return T @ mdh_link(0.0, 0.0, d_hand, 0.0)"),
        ("the hand flange left out (the pose of joint 7)",
         "def fk_table(table, q, d_hand=D_HAND):\n"
         "    T = np.eye(4)\n"
         "    for (a, alpha, d, off), qi in zip(table, q):\n"
         "        T = T @ mdh_link(a, alpha, d, qi + off)\n"
         "    return T"),
        ("the joint-2 offset left out of with_offset",
         "with_offset = as_printed\n"
         "gap_offset = max(np.linalg.norm(fk_table(with_offset, q, D_HAND_TUTORIAL)[:3, 3]"
         " - arm.fk(q)[:3, 3]) for q in Q_TEST)"),
        ("the hand at q_start taken from the table as printed", "p_start = p_start_printed"),
        ("the verdict: not the same links", "same_links = False"),
        ("the verdict: the same pose for the same joint reading", "same_pose = True"),
        ("the printed table compared with the robot at q + offset instead of q - offset",
         "gap_shifted = max(np.linalg.norm(fk_table(as_printed, q, D_HAND_TUTORIAL)[:3, 3]"
         " - arm.fk(q + JOINT2_OFFSET)[:3, 3]) for q in Q_TEST)"),
    ],
    "task1_test2": [
        ("central difference not divided by 2",
         "def jv_fd(q, h=1e-6):\n"
         "    return np.column_stack([(arm.fk(q + dq)[:3, 3] - arm.fk(q - dq)[:3, 3]) / h"
         " for dq in h * np.eye(7)])"),
    ],
    "task1_test3": [
        ("'as printed' table already carrying the offset", "as_printed = with_offset"),
        ("the flange offset kept in the last row and added again as d_hand",
         "with_offset = [*with_offset[:6], (0.0, 1.571, 0.2295, 0.0)]"),
        ("the table 'with the offset' left as printed", "with_offset = as_printed"),
    ],
    "task2_test1": [
        ("the circle centred on the hand", "CENTRE = P_START"),
        ("the speed taken as the angular speed omega", "SPEED = OMEGA"),
        ("the period taken as 1 / omega", "PERIOD = 1 / OMEGA"),
        ("the velocity without the chain rule's factor omega",
         "_reference = reference\n"
         "def reference(time):\n"
         "    positions, velocities = _reference(time)\n"
         "    return positions, velocities / OMEGA"),
        ("omega in degrees per second",
         "def reference(time):\n"
         "    angle = 90.0 * np.asarray(time, dtype=float).reshape(-1)\n"
         "    zero = 0 * angle\n"
         "    return (CENTRE + RADIUS * np.column_stack([np.cos(angle), np.sin(angle), zero]),\n"
         "            RADIUS * 90.0 * np.column_stack([-np.sin(angle), np.cos(angle), zero]))"),
        ("clockwise positions with the counter-clockwise profile",
         "_reference = reference\n"
         "def reference(time):\n"
         "    positions, velocities = _reference(time)\n"
         "    positions = positions.copy()\n"
         "    positions[:, 1] = 2 * CENTRE[1] - positions[:, 1]\n"
         "    return positions, velocities"),
    ],
    "task3_test1": [
        ("the open-loop law whatever kp",
         "_resolved_rate = resolved_rate\n"
         "def resolved_rate(q, r_des, v_des, kp=KP):\n"
         "    return _resolved_rate(q, r_des, v_des, kp=0.0)"),
        ("the Jacobian transpose instead of the pseudoinverse",
         "def resolved_rate(q, r_des, v_des, kp=KP):\n"
         "    J = arm.position_jacobian(q)\n"
         "    return J.T @ (v_des + kp * (r_des - arm.fk(q)[:3, 3]))"),
        ("the error fed back as r - r_des",
         "def resolved_rate(q, r_des, v_des, kp=KP):\n"
         "    J = arm.position_jacobian(q)\n"
         "    return np.linalg.pinv(J) @ (v_des + kp * (arm.fk(q)[:3, 3] - r_des))"),
    ],
    "task3_test2": [
        ("the closed loop run without feedback",
         "Q_loop = {'open loop': Q_loop['open loop'], 'closed loop': Q_loop['open loop']}"),
        ("q recorded after the Euler step",
         "def track(q0, r_des, v_des, kp=KP, ts=TS, rate=resolved_rate):\n"
         "    q = np.array(q0, dtype=float)\n"
         "    Q = []\n"
         "    for r_d, v_d in zip(r_des, v_des):\n"
         "        q = q + ts * rate(q, r_d, v_d, kp)\n"
         "        Q.append(q)\n"
         "    return np.array(Q)"),
        ("the gain kp ignored (always the open loop)",
         "_track = track\n"
         "def track(q0, r_des, v_des, kp=KP, ts=TS, rate=resolved_rate):\n"
         "    return _track(q0, r_des, v_des, kp=0.0, ts=ts, rate=rate)"),
        ("the closed-loop run without feed-forward (the hand lags)",
         "Q_loop = {**Q_loop, 'closed loop': track(Q_START, r_ref, 0 * v_ref, kp=KP)}\n"
         "hand = {**hand, 'closed loop': arm.fk(Q_loop['closed loop'])[:, :3, 3]}"),
        ("the loop calls resolved_rate, not its argument rate, with the sign of the error flipped",
         "def resolved_rate(q, r_des, v_des, kp=KP):\n"
         "    J = arm.position_jacobian(q)\n"
         "    return np.linalg.pinv(J) @ (v_des + kp * (arm.fk(q)[:3, 3] - r_des))\n"
         "def track(q0, r_des, v_des, kp=KP, ts=TS, rate=resolved_rate):\n"
         "    q = np.array(q0, dtype=float)\n"
         "    Q = []\n"
         "    for r_d, v_d in zip(r_des, v_des):\n"
         "        Q.append(q)\n"
         "        q = q + ts * resolved_rate(q, r_d, v_d, kp)\n"
         "    return np.array(Q)"),
    ],
    "task3_test3": [
        ("the open-loop hand taken from the closed-loop run",
         "hand = {'open loop': hand['closed loop'], 'closed loop': hand['closed loop']}"),
    ],
    "task3_test4": [
        ("errors in metres, not millimetres",
         "drift = {ts: [e / 1e3 for e in pair] for ts, pair in drift.items()}"),
        ("closed-loop column from a P-only law",
         "drift = {ts: [e_open, 20 * e_closed] for ts, (e_open, e_closed) in drift.items()}"),
        ("the orders taken as the slopes of error against ts, not of their logarithms",
         "order_open, order_closed = np.polyfit(list(drift), np.array(list(drift.values())),"
         " 1)[0]"),
    ],
    "task3_test5": [
        ("the margin to the limits taken from the lower limits only",
         "margin = (Q_loop['closed loop'] - LOWER).min(axis=0)"),
    ],
    "task4_test1": [
        ("the chosen runs tracked open loop",
         "Q_CHOSEN = np.array([track(Q_SWEEP[m], P0_SWEEP[m] + relative, v_ref, kp=0.0)"
         " for m in CHOSEN])"),
        ("every run given the circle of q_start, not one through its own start",
         "Q_CHOSEN = np.array([track(Q_SWEEP[m], r_ref, v_ref) for m in CHOSEN])"),
        ("no two neighbouring starts of one joint", "CHOSEN = [31, 10, 50]"),
    ],
    "task4_test2": [
        ("rho measured from the joint's origin, not from its axis",
         "rho = np.array([np.linalg.norm(P_START - arm.frames(Q_START)[j + 1][:3, 3])"
         " for j in range(7)])"),
        ("the chord taken as the arc rho dtheta",
         "def chord_length(rho, step):\n"
         "    return rho * step\n"
         "chord = chord_length(rho, 0.1 * SPAN)"),
        ("the chords read off the start points, chord_length the arc",
         "def chord_length(rho, step):\n"
         "    return rho * step\n"
         "chord = np.linalg.norm(P0_SWEEP[1::9] - P0_SWEEP[::9], axis=1)"),
        ("the centres taken as the start points", "centres_chosen = P0_SWEEP[CHOSEN]"),
    ],
    "task4_test3": [
        ("the IK guesses used without solving", "Q_SAME = guesses"),
        ("hand_to always goes to the hand at q_start, whatever the target",
         "_hand_to = hand_to\n"
         "def hand_to(q, target, tol=1e-10, max_steps=50):\n"
         "    return _hand_to(q, P_START, tol, max_steps)"),
        ("five copies of q_start",
         "same_q = np.array([track(Q_START, r_ref, v_ref)] * 5)"),
    ],
    "task4_test4": [
        ("the travel taken as the net change of each joint over the lap",
         "travel = np.abs(same_q[:, -1] - same_q[:, 0])"),
        ("every joint negated in the mirror image", "mirror = -np.ones(7)"),
        ("the pitch joints negated instead of the roll joints",
         "mirror = np.array([1, -1, 1, -1, 1, -1, 1])"),
        ("the neighbouring postures taken for the mirror images",
         "mirror_pairs = [(0, 1), (3, 4)]"),
    ],
    "task5_test1": [
        ("sigma_min taken as the largest singular value",
         "def sigma_min_of(q):\n"
         "    return np.linalg.svd(arm.position_jacobian(q), compute_uv=False)[0]"),
        ("sigma_min taken as the smallest eigenvalue of J_v J_v^T (no square root)",
         "def sigma_min_of(q):\n"
         "    J = arm.position_jacobian(q)\n"
         "    return np.linalg.eigvalsh(J @ J.T)[0]"),
        ("the time of the smallest sigma_min, not of the first sample below the threshold",
         "def closest_approach(Q, ts=TS, threshold=0.01):\n"
         "    sigma = np.array([sigma_min_of(q) for q in Q])\n"
         "    k = int(np.argmin(sigma))\n"
         "    return float(sigma[k]), (float(ts * k) if sigma[k] < threshold else None)"),
        ("the sample index returned instead of the time",
         "def closest_approach(Q, ts=TS, threshold=0.01):\n"
         "    sigma = np.array([sigma_min_of(q) for q in Q])\n"
         "    below = np.flatnonzero(sigma < threshold)\n"
         "    return float(sigma.min()), (int(below[0]) if below.size else None)"),
        ("the time step ts ignored (always the 2 ms of the lap)",
         "def closest_approach(Q, ts=TS, threshold=0.01):\n"
         "    sigma = np.array([sigma_min_of(q) for q in Q])\n"
         "    below = np.flatnonzero(sigma < threshold)\n"
         "    return float(sigma.min()), (float(TS * below[0]) if below.size else None)"),
        ("the threshold ignored (always 0.01 m/rad)",
         "def closest_approach(Q, ts=TS, threshold=0.01):\n"
         "    sigma = np.array([sigma_min_of(q) for q in Q])\n"
         "    below = np.flatnonzero(sigma < 0.01)\n"
         "    return float(sigma.min()), (float(ts * below[0]) if below.size else None)"),
        ("the last sample below the threshold, not the first",
         "def closest_approach(Q, ts=TS, threshold=0.01):\n"
         "    sigma = np.array([sigma_min_of(q) for q in Q])\n"
         "    below = np.flatnonzero(sigma < threshold)\n"
         "    return float(sigma.min()), (float(ts * below[-1]) if below.size else None)"),
        ("the first sample counted from t = ts (time of sample k taken as (k + 1) ts)",
         "def closest_approach(Q, ts=TS, threshold=0.01):\n"
         "    sigma = np.array([sigma_min_of(q) for q in Q])\n"
         "    below = np.flatnonzero(sigma < threshold)\n"
         "    return float(sigma.min()), (float(ts * (below[0] + 1)) if below.size else None)"),
    ],
    "task5_test2": [
        ("the elbow start taken for the failing one (its sigma_min at t = 0 is as small)",
         "failing = 'elbow straight'\n"
         "t_loss = closest_approach(runs_open[failing], threshold=0.06)[1]\n"
         "k_loss = int(round(t_loss / TS))\n"
         "Q_f = runs_open[failing]\n"
         "U, S, _ = np.linalg.svd(arm.position_jacobian(Q_f[k_loss]))\n"
         "lost_direction = U[:, -1]\n"
         "speed_loss = np.linalg.norm(Q_f[k_loss + 1] - Q_f[k_loss]) / TS"),
        ("the lost direction taken as u_1, the direction the hand moves in most easily",
         "lost_direction = U[:, 0]"),
        ("the joint speed taken per step, not per second",
         "speed_loss = speed_loss * TS"),
        ("the bound taken as the hand speed times sigma_min, not divided by it",
         "speed_bound = np.linalg.norm(v_ref[k_loss]) * S[-1]"),
        ("the time of the smallest sigma_min taken for the time of the rank loss",
         "t_loss = TS * int(np.argmin([sigma_min_of(q) for q in runs_open[failing]]))\n"
         "k_loss = int(round(t_loss / TS))\n"
         "U, S, _ = np.linalg.svd(arm.position_jacobian(Q_f[k_loss]))\n"
         "lost_direction = U[:, -1]\n"
         "speed_loss = np.linalg.norm(Q_f[k_loss + 1] - Q_f[k_loss]) / TS"),
    ],
    "task5_test3": [
        ("the damping added unsquared",
         "def dls_rate(q, r_des, v_des, kp=KP, damping=LAMBDA):\n"
         "    J = arm.position_jacobian(q)\n"
         "    v = v_des + kp * (r_des - arm.fk(q)[:3, 3])\n"
         "    return J.T @ np.linalg.solve(J @ J.T + damping * np.eye(3), v)"),
        ("no damping: the pseudoinverse law",
         "def dls_rate(q, r_des, v_des, kp=KP, damping=LAMBDA):\n"
         "    return resolved_rate(q, r_des, v_des, kp)"),
        ("the feedback term left out",
         "def dls_rate(q, r_des, v_des, kp=KP, damping=LAMBDA):\n"
         "    J = arm.position_jacobian(q)\n"
         "    return J.T @ np.linalg.solve(J @ J.T + damping**2 * np.eye(3), v_des)"),
        ("the damped law by the 7 x 7 normal equations, singular without damping",
         "def dls_rate(q, r_des, v_des, kp=KP, damping=LAMBDA):\n"
         "    J = arm.position_jacobian(q)\n"
         "    v = v_des + kp * (r_des - arm.fk(q)[:3, 3])\n"
         "    return np.linalg.solve(J.T @ J + damping**2 * np.eye(7), J.T @ v)"),
        ("the damped loop ignores its time step",
         "_track_damped_right = track_damped\n\n"
         "def track_damped(q0, r_des, v_des, kp=KP, ts=TS, damping=LAMBDA):\n"
         "    return _track_damped_right(q0, r_des, v_des, kp, TS, damping)"),
    ],
    "task5_test4": [
        ("damping of 0.02 mm instead of 0.02 m",
         "runs_bad = {**runs_bad, 'DLS': track_damped(q_ex, circle_bad, v_ref, damping=2e-5)}\n"
         "peak_speed = {**peak_speed, 'DLS': (np.linalg.norm(np.diff(runs_bad['DLS'], axis=0),"
         " axis=1) / TS).max()}"),
        ("the damped run without feedback",
         "runs_bad = {**runs_bad, 'DLS': track_damped(q_ex, circle_bad, v_ref, kp=0.0)}"),
        ("the joint speed taken per step, not per second",
         "peak_speed = {name: value * TS for name, value in peak_speed.items()}"),
        ("the final error in metres, not millimetres",
         "final_error = {name: value / 1e3 for name, value in final_error.items()}"),
    ],
}
