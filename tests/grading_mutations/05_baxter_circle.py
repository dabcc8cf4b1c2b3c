"""Wrong answers that each autograded test of chapter 5 must reject."""

_P_ONLY_LOG = (
    "log = simulate(arm, CartesianController(arm, lambda time: reference(time).positions,"
    " position_gain=KP), Q_START, TS, T_END, tol=None)\n"
    "Q_run = log.q\n"
    "v_hand = np.gradient(log.pose[:, :3, 3], TS, axis=0)"
)

MUTATIONS = {
    "task1_test1": [
        ("the joint-2 offset left out of with_offset",
         "with_offset = as_printed\ngap_offset = max(hand_gap(with_offset, q) for q in Q_TEST)"),
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
    ],
    "task2_test1": [
        ("the circle centred on the hand", "CENTRE = P_START\nref = reference(t)"),
    ],
    "task2_test2": [
        ("v_des without the chain rule's factor omega",
         "def v_des(time):\n"
         "    return RADIUS * np.array([-np.sin(OMEGA * time), np.cos(OMEGA * time), 0.0])"),
        ("omega in degrees per second",
         "reference = lambda time: circle_trajectory(time, CENTRE, RADIUS, normal=[0, 0, 1],"
         " angular_speed=90.0)"),
    ],
    "task3_test1": [
        ("the closed loop run without feedback",
         "Q_loop = {'open loop': Q_loop['open loop'], 'closed loop': Q_loop['open loop']}"),
        ("simulate with the open-loop law",
         "log = simulate(arm, CartesianController(arm, lambda time: reference(time).positions,"
         " position_gain=0.0, feedforward=lambda time: reference(time).velocities),"
         " Q_START, TS, T_END, tol=None)"),
    ],
    "task3_test3": [
        ("errors in metres, not millimetres",
         "drift = {ts: [e / 1e3 for e in pair] for ts, pair in drift.items()}"),
        ("closed-loop column from a P-only law",
         "drift = {ts: [e_open, 20 * e_closed] for ts, (e_open, e_closed) in drift.items()}"),
    ],
    "task3_test2": [
        ("skip_first_step ignored",
         "_euler_loop = euler_loop\n"
         "def euler_loop(kp, q0=Q_START, skip_first_step=False):\n"
         "    return _euler_loop(kp, q0)"),
    ],
    "task3_test4": [
        ("no feed-forward in the controller (the hand lags)", _P_ONLY_LOG),
    ],
    "task3_test5": [
        ("the open-loop law",
         "_resolved_rate = resolved_rate\n"
         "resolved_rate = lambda q, r_des, v_des, kp=KP: _resolved_rate(q, r_des, v_des, kp=0.0)"),
    ],
    "task4_test1": [
        ("the sweep tracked open loop",
         "sweep = track_position_batch(arm, Q_SWEEP, TS, P0_SWEEP[:, None, :] + relative,"
         " ref.velocities, gain=0.0)\nworst = sweep.position_error.max(axis=1)"),
    ],
    "task4_test2": [
        ("every run given the circle of q_start, not one through its own start",
         "sweep = track_position_batch(arm, Q_SWEEP, TS, np.broadcast_to(ref.positions,"
         " (63,) + ref.positions.shape), ref.velocities, gain=KP)"),
        ("rho measured from the joint's origin, not from its axis",
         "rho = np.array([np.linalg.norm(P_START - arm.frames(Q_START)[j + 1][:3, 3])"
         " for j in range(7)])"),
    ],
    "task4_test3": [
        ("the IK guesses used without solving", "Q_SAME = guesses"),
        ("hand_to always goes to the hand at q_start, whatever the target",
         "_hand_to = hand_to\n"
         "def hand_to(q, target, tol=1e-10, max_steps=50):\n"
         "    return _hand_to(q, P_START, tol, max_steps)"),
    ],
    "task4_test4": [
        ("five copies of q_start",
         "same = track_position_batch(arm, np.tile(Q_START, (5, 1)), TS, ref.positions,"
         " ref.velocities, gain=KP)"),
    ],
    "task5_test1": [
        ("the best-conditioned run taken for the worst",
         "m_w = int(np.argmax(smin.min(axis=1)))\nj_w, i_w = divmod(m_w, 9)"),
    ],
    "task5_test3": [
        ("damping of 0.02 mm instead of 0.02 m",
         "bad = dict(bad)\n"
         "bad[dls_name] = track_position_batch(arm, starts, TS, p_bad + relative,"
         " ref.velocities, clamp=False, gain=KP, inverse='dls', damping=2e-5)"),
    ],
    "task5_test2": [
        ("the last step taken for the most singular one",
         "k_s = np.full(len(starts), len(t) - 1)\nq_s = b.q[np.arange(len(starts)), k_s]\n"
         "J_s = arm.position_jacobian(q_s)\n"
         "column_w0 = 1e3 * np.linalg.norm(J_s[:, :, 4], axis=1)"),
    ],
}
