"""Wrong answers that each autograded test of the chapter must reject (``MUTATIONS``,
tests/test_grading_mutations.py), and correct answers written another way that must keep
full marks (``VARIANTS``, tests/support/benign_variants.py and tests/test_grading_trust.py).

``MUTATIONS``: ``{grade id of a test cell: [(what is wrong, code appended to the answer
cells), ...]}``, at least one per graded test. ``VARIANTS``: ``{grade id of an answer cell:
(how it differs, code appended to that cell)}``: another method, not only other names.
The first line of each variant's code must be ASCII without quotes.
"""

_RECOMPUTE = "\nQ_ptp, Qd_ptp, Qdd_ptp = synchronised_motion(t_ptp, Q_A, Q_B, V_MAX, A_MAX)"


def _motion_mistake(code: str) -> str:
    """synchronised_motion replaced by the check module's typical mistake ``code``."""
    return (
        "from robokin.check.trajectories import _motion as _wrong_motion\n"
        "def synchronised_motion(t, q_start, q_end, v_max, a_max, least_duration=least_duration):\n"
        "    args = [np.asarray(x, dtype=float) for x in (t, q_start, q_end, v_max, a_max)]\n"
        f"    return _wrong_motion(*args, mistake={code!r})" + _RECOMPUTE
    )


def _via_mistake(code: str) -> str:
    """via_point_cubics replaced by the check module's typical mistake ``code``."""
    return (
        "from robokin.check.trajectories import _via_coefficients as _wrong_via\n"
        "def via_point_cubics(points, durations):\n"
        "    args = [np.asarray(x, dtype=float) for x in (points, durations)]\n"
        f"    return _wrong_via(*args, mistake={code!r})\n"
        "via_coefficients = via_point_cubics(Q_VIA, T_VIA)"
    )


MUTATIONS = {
    "task1_test1": [
        ("the rates taken with respect to tau, not t",
         "cubic_scaling = (lambda f: lambda t, T: np.asarray(f(t, T)) * np.array([1.0, T, T * T]))"
         "(cubic_scaling)"),
        ("a timing law without rest at the ends (s = t/T)",
         "def quintic_scaling(t, T):\n    return np.array([t / T, 1.0 / T, 0.0])"),
        ("the cubic given for the quintic", "quintic_scaling = cubic_scaling"),
    ],
    "task1_test2": [
        ("the rows swapped", "peak_factors = np.asarray(peak_factors)[::-1]"),
        ("the quintic's acceleration read at tau = 1/2 (zero)",
         "peak_factors = np.array([[1.5, 6.0], [15 / 8, 0.0]])"),
        ("the peaks of the laws at T = 2 s, not the factors",
         "peak_factors = np.asarray(peak_factors) * [1 / 2, 1 / 4]"),
    ],
    "task2_test1": [
        ("the triangular case missed (a negative cruise time)",
         "def trapezoid_time(distance, v_max, a_max):\n    return distance / v_max + v_max / a_max"),
        ("v_max and a_max swapped",
         "trapezoid_time = (lambda f: lambda d, v, a: f(d, a, v))(trapezoid_time)"),
        ("the triangle from D = v_max^2/(2 a_max) only",
         "def trapezoid_time(distance, v_max, a_max):\n"
         "    if distance >= v_max**2 / (2 * a_max):\n"
         "        return distance / v_max + v_max / a_max\n"
         "    return 2.0 * np.sqrt(distance / a_max)"),
    ],
    "task3_test1": [
        ("synchronised by the fastest moving joint",
         "def least_duration(q_start, q_end, v_max, a_max, trapezoid_time=trapezoid_time):\n"
         "    times = [trapezoid_time(abs(b - a), v, acc) for a, b, v, acc in zip(q_start, q_end, v_max, a_max)]\n"
         "    return min(time for time in times if time > 0)\n"
         "ptp_duration = least_duration(Q_A, Q_B, V_MAX, A_MAX)"),
        ("the joints' times added (one after the other)",
         "def least_duration(q_start, q_end, v_max, a_max, trapezoid_time=trapezoid_time):\n"
         "    return sum(trapezoid_time(abs(b - a), v, acc) for a, b, v, acc in zip(q_start, q_end, v_max, a_max))\n"
         "ptp_duration = least_duration(Q_A, Q_B, V_MAX, A_MAX)"),
        ("the duration of the UR10's move alone, whatever the move",
         "least_duration = (lambda T: lambda q_start, q_end, v_max, a_max, trapezoid_time=None: T)(ptp_duration)"),
    ],
    "task3_test2": [
        ("synchronised by the fastest joint", _motion_mistake("fastest_joint")),
        ("every joint in its own minimum time (unsynchronised)", _motion_mistake("unsynchronised")),
        ("v_max and a_max swapped", _motion_mistake("swapped_limits")),
        ("the slowest joint's profile stretched for every joint", _motion_mistake("same_shape")),
        ("the cruise speed from the quadratic's root with an unguarded square root (a rounding-"
         "negative discriminant at a triangle: NaN)",
         "def synchronised_motion(t, q_start, q_end, v_max, a_max, least_duration=least_duration):\n"
         "    t = np.asarray(t, dtype=float)\n"
         "    delta = np.asarray(q_end, dtype=float) - np.asarray(q_start, dtype=float)\n"
         "    T = least_duration(q_start, q_end, v_max, a_max)\n"
         "    Q, Qd, Qdd = (np.tile(np.zeros(len(delta)), (len(t), 1)) for _ in range(3))\n"
         "    for j, (d, a) in enumerate(zip(delta, a_max)):\n"
         "        D, sign = abs(d), np.sign(d)\n"
         "        v = (a * T - np.sqrt((a * T) ** 2 - 4 * a * D)) / 2\n"
         "        ramp = v / a\n"
         "        left = T - t\n"
         "        first, last = t < ramp, t > T - ramp\n"
         "        pos = np.where(first, a * t**2 / 2, np.where(last, D - a * left**2 / 2,"
         " v * ramp / 2 + v * (t - ramp)))\n"
         "        vel = np.where(first, a * t, np.where(last, a * left, v))\n"
         "        acc = np.where(first, a, np.where(last, -a, 0.0))\n"
         "        Q[:, j] = q_start[j] + sign * pos\n"
         "        Qd[:, j], Qdd[:, j] = sign * vel, sign * acc\n"
         "    return Q, Qd, Qdd\n" + _RECOMPUTE.lstrip("\n")),
    ],
    "task4_test1": [
        ("each segment's own slope at both ends (velocity jumps, ends moving)", _via_mistake("segment_slope")),
        ("the coefficients in the normalised time tau = sigma/T_k", _via_mistake("normalised_time")),
        ("the coefficients highest power first", _via_mistake("reversed_order")),
    ],
    "task4_test2": [
        ("the mean of the slopes also where the joint turns back", _via_mistake("no_sign_rule")),
        ("the chord's slope at a via point", _via_mistake("central_difference")),
        ("a stop at every via point", _via_mistake("stop_at_via")),
        ("the slopes with the durations in reverse order", _via_mistake("durations_reversed")),
        ("the slopes without dividing by the durations", _via_mistake("differences")),
        ("the velocity at via point k taken as the slope of the segment before it",
         "def via_point_cubics(points, durations, _right=via_point_cubics):\n"
         "    points, durations = np.asarray(points, dtype=float), np.asarray(durations, dtype=float)\n"
         "    out = np.asarray(_right(points, durations), dtype=float).copy()\n"
         "    slopes = np.diff(points, axis=0) / durations[:, None]\n"
         "    for k, T in enumerate(durations):\n"
         "        start = slopes[k - 1] if k > 0 else 0 * slopes[0]\n"
         "        end = slopes[k] if k < len(durations) - 1 else 0 * slopes[0]\n"
         "        step = points[k + 1] - points[k]\n"
         "        out[k] = [points[k], start, (3 * step / T - 2 * start - end) / T,\n"
         "                  (-2 * step / T + start + end) / T**2]\n"
         "    return out\n"
         "via_coefficients = via_point_cubics(Q_VIA, T_VIA)"),
    ],
    "task5_test1": [
        ("slerp without the sign flip (the long way round)",
         "def slerp(q0, q1, s):\n"
         "    q0, q1 = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)\n"
         "    omega = np.arccos(np.clip(q0 @ q1, -1.0, 1.0))\n"
         "    if omega < 1e-9:\n"
         "        return q0\n"
         "    return (np.sin((1 - s) * omega) * q0 + np.sin(s * omega) * q1) / np.sin(omega)"),
        ("the normalised straight-line interpolation (nlerp)",
         "def slerp(q0, q1, s):\n"
         "    q0, q1 = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)\n"
         "    q1 = q1 if q0 @ q1 >= 0 else -q1\n"
         "    q = (1 - s) * q0 + s * q1\n"
         "    return q / np.linalg.norm(q)"),
        ("NaN for equal rotations (0/0)",
         "def slerp(q0, q1, s):\n"
         "    q0, q1 = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)\n"
         "    q1 = q1 if q0 @ q1 >= 0 else -q1\n"
         "    omega = np.arccos(np.clip(q0 @ q1, -1.0, 1.0))\n"
         "    return (np.sin((1 - s) * omega) * q0 + np.sin(s * omega) * q1) / np.sin(omega)"),
    ],
    "task6_test1": [
        ("the angular velocity in the tool's start frame",
         "def line_reference(t, T_start, T_end, duration, quintic_scaling=quintic_scaling, slerp=slerp,\n"
         "                   _right=line_reference):\n"
         "    pose, twist = _right(t, T_start, T_end, duration, quintic_scaling, slerp)\n"
         "    return pose, np.concatenate([twist[:3], T_start[:3, :3].T @ twist[3:]])"),
        ("a constant angular velocity (not scaled by the timing law)",
         "def line_reference(t, T_start, T_end, duration, quintic_scaling=quintic_scaling, slerp=slerp,\n"
         "                   _right=line_reference):\n"
         "    pose, twist = _right(t, T_start, T_end, duration, quintic_scaling, slerp)\n"
         "    w = T_start[:3, :3] @ rotation_log(T_start[:3, :3].T @ T_end[:3, :3])\n"
         "    return pose, np.concatenate([twist[:3], w / duration])"),
    ],
    "task6_test2": [
        ("no feed-forward twist",
         "track = (lambda f: lambda q0, poses, twists, ts, gain: f(q0, poses, 0 * np.asarray(twists), ts, gain))"
         "(track)\n"
         "Q_line = track(Q_B, poses_line, twists_line, TS_LINE, GAIN)\n"
         "position_errors = np.linalg.norm(poses_line[:, :3, 3] - ur10.fk(Q_line)[:, :3, 3], axis=1)"),
        ("the error with the wrong sign",
         "def track(q0, poses, twists, ts, gain):\n"
         "    q, out = np.array(q0, dtype=float), []\n"
         "    for pose, twist in zip(poses, twists):\n"
         "        out.append(q)\n"
         "        now = ur10.fk(q)\n"
         "        error = np.concatenate([now[:3, 3] - pose[:3, 3], rotation_log(now[:3, :3] @ pose[:3, :3].T)])\n"
         "        q = q + ts * np.linalg.solve(ur10.jacobian(q), twist + gain * error)\n"
         "    return np.array(out)"),
    ],
}

VARIANTS = {
    "task1_answer1": ("the polynomials written out, the factors from their closed forms", """

# written another way: s(tau) and its derivatives as explicit polynomials (np.polyval)
def cubic_scaling(t, T):
    tau = t / T
    return np.array([np.polyval([-2.0, 3.0, 0.0, 0.0], tau), np.polyval([-6.0, 6.0, 0.0], tau) / T,
                     np.polyval([-12.0, 6.0], tau) / T**2])


def quintic_scaling(t, T):
    tau = t / T
    s = np.polyval([6.0, -15.0, 10.0, 0.0, 0.0, 0.0], tau)
    sd = np.polyval([30.0, -60.0, 30.0, 0.0, 0.0], tau) / T
    sdd = np.polyval([120.0, -180.0, 60.0, 0.0], tau) / T**2
    return np.array([s, sd, sdd])


peak_factors = np.array([[1.5, 6.0], [30.0 / 16.0, 10.0 * np.sqrt(3.0) / 3.0]])
"""),
    "task2_answer1": ("the peak speed min(v_max, sqrt(D a_max)) in one formula", """

# written another way: the peak speed is v_max or the triangle's sqrt(D a_max), whichever is lower
def trapezoid_time(distance, v_max, a_max):
    if distance == 0:
        return 0.0
    peak = min(v_max, float(np.sqrt(distance * a_max)))
    return distance / peak + peak / a_max
"""),
    "task3_answer1": ("one joint at a time, the ramp time from Siciliano's formula", """

# written another way: the joints' minimum times at once (the peak speed min(v_max, sqrt(D a_max)));
# a loop over the joints; the ramp time t_c = T/2 - sqrt((T^2 a - 4 D)/a)/2
def least_duration(q_start, q_end, v_max, a_max, trapezoid_time=trapezoid_time):
    D = np.abs(np.subtract(q_end, q_start, dtype=float))
    peak = np.minimum(v_max, np.sqrt(D * np.asarray(a_max, dtype=float)))
    times = np.divide(D, peak, out=np.zeros_like(D), where=D > 0) + np.where(D > 0, peak / a_max, 0.0)
    return float(times.max())


def synchronised_motion(t, q_start, q_end, v_max, a_max, least_duration=least_duration):
    t = np.asarray(t, dtype=float)
    q_start, q_end = np.asarray(q_start, dtype=float), np.asarray(q_end, dtype=float)
    T = least_duration(q_start, q_end, v_max, a_max)
    columns = []
    for a, b, acc in zip(q_start, q_end, np.asarray(a_max, dtype=float)):
        D, sign = abs(b - a), np.sign(b - a)
        t_c = T / 2 - 0.5 * np.sqrt(max((T * T * acc - 4 * D) / acc, 0.0))
        peak = acc * t_c
        q = np.empty_like(t)
        qd = np.empty_like(t)
        qdd = np.empty_like(t)
        for k, time in enumerate(t):
            if time < t_c:
                q[k], qd[k], qdd[k] = 0.5 * acc * time**2, acc * time, acc
            elif time > T - t_c:
                q[k], qd[k], qdd[k] = D - 0.5 * acc * (T - time) ** 2, acc * (T - time), -acc
            else:
                q[k], qd[k], qdd[k] = peak * (time - t_c / 2), peak, 0.0
        columns.append((a + sign * q, sign * qd, sign * qdd))
    return tuple(np.column_stack([c[i] for c in columns]) for i in range(3))


ptp_duration = least_duration(Q_A, Q_B, V_MAX, A_MAX)
Q_ptp, Qd_ptp, Qdd_ptp = synchronised_motion(t_ptp, Q_A, Q_B, V_MAX, A_MAX)
"""),
    "task4_answer1": ("each segment's cubic from its 4 x 4 linear system, joint by joint", """

# written another way: the rule joint by joint, each cubic from the linear system of its end conditions
def via_point_cubics(points, durations):
    points, durations = np.asarray(points, dtype=float), np.asarray(durations, dtype=float)
    m, n = len(durations), points.shape[1]
    rates = np.zeros((m + 1, n))
    for j in range(n):
        for k in range(1, m):
            before = (points[k, j] - points[k - 1, j]) / durations[k - 1]
            after = (points[k + 1, j] - points[k, j]) / durations[k]
            if before * after > 0:
                rates[k, j] = (before + after) / 2
    out = np.zeros((m, 4, n))
    for k, T in enumerate(durations):
        system = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [1, T, T**2, T**3], [0, 1, 2 * T, 3 * T**2]])
        out[k] = np.linalg.solve(system, np.stack([points[k], rates[k], points[k + 1], rates[k + 1]]))
    return out


via_coefficients = via_point_cubics(Q_VIA, T_VIA)
"""),
    "task5_answer1": ("slerp as q0 (q0* q1)^s, through the axis and angle", """

# written another way: the relative rotation q0* q1 raised to the power s
def slerp(q0, q1, s):
    q0, q1 = np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)
    w0, v0, w1, v1 = q0[0], q0[1:], q1[0], q1[1:]
    rel = np.concatenate([[w0 * w1 + v0 @ v1], w0 * v1 - w1 * v0 - np.cross(v0, v1)])
    if rel[0] < 0:
        rel = -rel
    half = np.arctan2(np.linalg.norm(rel[1:]), rel[0])
    if half == 0.0:
        return q0.copy()
    axis = rel[1:] / np.linalg.norm(rel[1:])
    part = np.concatenate([[np.cos(s * half)], np.sin(s * half) * axis])
    wp, vp = part[0], part[1:]
    return np.concatenate([[w0 * wp - v0 @ vp], w0 * vp + wp * v0 + np.cross(v0, vp)])
"""),
    "task6_answer1": ("the orientation by the matrix exponential, the loop by least squares", """

# written another way: R(t) = R0 exp([w] s) with rotation_exp, and the step by lstsq
from robokin.transforms import rotation_exp


def line_reference(t, T_start, T_end, duration, quintic_scaling=quintic_scaling, slerp=slerp):
    s, sd, _ = quintic_scaling(t, duration)
    R0 = T_start[:3, :3]
    w = rotation_log(R0.T @ T_end[:3, :3])
    pose = np.eye(4)
    pose[:3, :3] = R0 @ rotation_exp(s * w)
    pose[:3, 3] = (1 - s) * T_start[:3, 3] + s * T_end[:3, 3]
    return pose, np.concatenate([sd * (T_end[:3, 3] - T_start[:3, 3]), sd * (R0 @ w)])


poses_line = np.array([line_reference(t, T_line_start, T_line_end, LINE_DURATION)[0] for t in t_line])
twists_line = np.array([line_reference(t, T_line_start, T_line_end, LINE_DURATION)[1] for t in t_line])


def track(q0, poses, twists, ts, gain):
    rows = [np.array(q0, dtype=float)]
    for pose, twist in zip(poses[:-1], twists[:-1]):
        q = rows[-1]
        now = ur10.fk(q)
        error = np.concatenate([pose[:3, 3] - now[:3, 3], rotation_log(pose[:3, :3] @ now[:3, :3].T)])
        rows.append(q + ts * np.linalg.lstsq(ur10.jacobian(q), twist + gain * error, rcond=None)[0])
    return np.array(rows)


Q_line = track(Q_B, poses_line, twists_line, TS_LINE, GAIN)
position_errors = np.linalg.norm(poses_line[:, :3, 3] - ur10.fk(Q_line)[:, :3, 3], axis=1)
"""),
}
