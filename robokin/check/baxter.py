r"""Exercise checks of chapter 5: the Baxter left arm tracking a circle.

Every reference comes from :func:`robokin.models.baxter_left` with
``base="shoulder"`` (base frame = the s0 joint frame, z up along the s0 axis,
as in the Imperial College tutorial) and the ``left_hand`` flange as the
end-effector. The circle starts where the hand is at the mid-range
configuration :data:`Q_START` and turns counter-clockwise (seen from above)
in the horizontal plane, with the exercise's velocity profile, radius
:data:`RADIUS` and angular rate :data:`OMEGA` (one turn in :data:`PERIOD`).
The functions of time are compared with the reference at 20 seeded random
times in [0, 4] s; the control law and the loop at seeded random inputs of
their own.

=======================  ==================================================  ====================
check                    the student's answer                                 inputs
=======================  ==================================================  ====================
``circle_position``      function ``r_des(t)`` -> (3,) (m)                     t in [0, 4] s
``circle_velocity``      function ``v_des(t)`` -> (3,) (m/s)                   t in [0, 4] s
``resolved_rate``        function ``(q, r_des, v_des)`` -> q̇ (7,) (rad/s)     q, r_des, v_des
                         :math:`\mathbf J_v^+(\mathbf q)(\dot{\mathbf r}_{des} + K_p(\mathbf r_{des}-\mathbf r(\mathbf q)))`, :data:`KP`
``tracking_loop``        function ``track(q0, r_des, v_des, kp, ts)`` ->      start, reference,
                         joint angles (N, 7) (rad), Euler steps of that law   gain, time step
                         (robokin's law as ``rate=``, if it takes one)
``forward_kinematics``   function ``T(q)`` -> 4×4, shoulder frame -> hand      q within the limits
``hand_position_at``     numbers: the hand position at :data:`Q_START` (m)     --
``sigma_min``            function ``sigma_min_of(q)`` -> smallest singular    q within the limits
                         value of the position Jacobian J_v (m/rad)
``closest_approach``     function ``closest_approach(Q, ts, threshold)`` ->   joint paths, time
                         (smallest σ_min along the run, time of the first     steps, thresholds
                         sample below threshold or None)
``link_transform``       function ``mdh_link(a, alpha, d, theta)`` -> 4×4      rows of a table
``chord_length``         function ``chord_length(rho, step)`` -> the hand's   radius, step
                         displacement (m) when a joint turns by step (rad)
``damped_rate``          function ``dls_rate(q, r_des, v_des, kp, damping)``  q, r_des, v_des,
                         -> the damped least-squares command q̇ (7,)          gain, damping
=======================  ==================================================  ====================

The forward-kinematics checks accept answers within 1 mm (so a table with the
lengths rounded to 0.1 mm passes) and recognise the typical mistakes of the
exercise: a joint offset of the tutorial's table, the DH convention, the base
frame, the end-effector point, degrees.

Usage::

    from robokin.check import baxter as check_baxter
    check_baxter.circle_velocity(my_velocity)
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    FAIL,
    Check,
    CheckResult,
    FunctionCheck,
    LaterStepCheck,
    MatrixArgumentsCheck,
    Variable,
    alternatives,
    fmt,
    pack_joint_rows,
    packed_variants,
)
from robokin.check._registry import exercise
from robokin.validation import as_scalar, as_vector

__all__ = [
    "circle_position", "circle_velocity", "resolved_rate", "tracking_loop", "forward_kinematics",
    "hand_position_at", "sigma_min", "closest_approach", "link_transform", "chord_length", "damped_rate",
    "Q_START", "P_START", "RADIUS", "OMEGA", "PERIOD", "TS", "KP", "reference_resolved_rate",
]

_CHAPTER = "baxter"

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back (a track that calls track_position_batch) is flagged for review
#: by hand (tools/grading/bridge/delegation.py reads this literal table without importing it)
DELEGATION = {
    "resolved_rate": {"CartesianController": "robokin.motion.CartesianController",
                      "simulate": "robokin.motion.simulate",
                      "track_position_batch": "robokin.motion.track_position_batch",
                      "reference_resolved_rate": "robokin.check.baxter.reference_resolved_rate"},
    "tracking_loop": {"CartesianController": "robokin.motion.CartesianController",
                      "simulate": "robokin.motion.simulate",
                      "track_position_batch": "robokin.motion.track_position_batch",
                      "reference_resolved_rate": "robokin.check.baxter.reference_resolved_rate"},
    "sigma_min": {"singular_values": "SerialChain.singular_values",
                  "track_position_batch": "robokin.motion.track_position_batch (its sigma_min)"},
    "damped_rate": {"CartesianController": "robokin.motion.CartesianController",
                    "track_position_batch": "robokin.motion.track_position_batch"},
    "closest_approach": {"singular_values": "SerialChain.singular_values",
                         "track_position_batch": "robokin.motion.track_position_batch (its sigma_min)"},
}
_PI = math.pi

#: Joint limits of the left arm (rad), s0 … w2 (URDF).
_LIMITS = np.array([
    [-1.70167993878, 1.70167993878], [-2.147, 1.047], [-3.05417993878, 3.05417993878],
    [-0.05, 2.618], [-3.059, 3.059], [-1.57079632679, 2.094], [-3.059, 3.059],
])
#: Start configuration (rad): the middle of every joint range, lower + 0.5·range.
Q_START = _LIMITS.mean(axis=1)
#: Radius of the circle (m).
RADIUS = 0.05
#: Angular speed on the circle (rad/s): one turn in 4 s.
OMEGA = 0.5 * _PI
#: Duration of one turn (s).
PERIOD = 2 * _PI / OMEGA
#: Time step of the tutorial (s).
TS = 0.002
#: Position gain of the closed-loop resolved-rate law (1/s).
KP = 10.0
# The offset the tutorial's table lacks (the answer of Task 1: private, not shown by help()).
_JOINT2_OFFSET = np.array([0.0, _PI / 2, 0.0, 0.0, 0.0, 0.0, 0.0])


@cache
def _arm(base: str = "shoulder", end: str = "hand"):
    from robokin.models.baxter import baxter_left

    return baxter_left(base=base, end=end)


@cache
def _standard_dh_reading(with_offset: bool):
    """The modified-DH numbers of the table read as a standard-DH table (a mistake)."""
    from robokin.chains import from_dh

    rows = [(0.27035, 0.0, 0.0), (0.0, 0.069, -_PI / 2), (0.36442, 0.0, _PI / 2), (0.0, 0.069, -_PI / 2),
            (0.37429, 0.0, _PI / 2), (0.0, 0.010, -_PI / 2), (0.229525, 0.0, _PI / 2)]
    table = [[d, (_PI / 2 if (with_offset and i == 1) else 0.0), a, al] for i, (d, a, al) in enumerate(rows)]
    return from_dh(table)


#: The hand flange's offset along z7 (m), the model's.
_D_HAND = 0.229525


def _shift_z(d: float) -> np.ndarray:
    """The translation T_z(d) along z (4×4)."""
    shift = np.eye(4)
    shift[2, 3] = d
    return shift


def _pose(q, base: str = "shoulder", end: str = "hand") -> np.ndarray:
    return _arm(base, end).fk(np.asarray(q, dtype=float))


def _position(q) -> np.ndarray:
    return _pose(q)[:3, 3]


#: Hand position at Q_START (m), shoulder frame.
P_START = _position(Q_START)
# Centre of the circle (m), an answer of Task 2: private, not shown by help().
_CENTRE = P_START - np.array([RADIUS, 0.0, 0.0])


# ------------------------------------------------------------------ the circle
_T = [Variable("t", "other", 0.0, PERIOD, aliases=("time",))]


def _circle(t, centre=_CENTRE, radius=RADIUS, omega=OMEGA, phase=0.0, sense=1.0):
    a = omega * float(np.ravel(t)[0]) + phase
    return centre + radius * np.array([math.cos(a), sense * math.sin(a), 0.0])


def _circle_dot(t, radius=RADIUS, omega=OMEGA, factor=None, phase=0.0, sense=1.0):
    a = omega * float(np.ravel(t)[0]) + phase
    k = radius * (omega if factor is None else factor)
    return k * np.array([-math.sin(a), sense * math.cos(a), 0.0])


circle_position = exercise(_CHAPTER, "circle_position", Check(
    name="r_des(t)",
    reference=lambda x: _circle(x),
    variables=_T,
    groups=[("t", [0])],
    diagnoses=[
        alternatives("centre_at_start", [(
            lambda x: _circle(x, centre=P_START),
            ("{name} is centred at the hand's start position: then the reference starts r = 5 cm away "
             "from the hand and the first steps jump. The circle starts at the hand: find the centre "
             "from where r_des(0) lies on the circle."),
        )]),
        alternatives("phase", [
            (lambda x: _circle(x, phase=_PI / 2),
             ("{name} starts a quarter turn late (phase error of π/2): at t = 0 it must be at the "
              "hand's start position, and its derivative the exercise's velocity profile.")),
            (lambda x: _circle(x, phase=-_PI / 2),
             ("{name} starts a quarter turn early (phase error of −π/2): at t = 0 it must be at the "
              "hand's start position, and its derivative the exercise's velocity profile.")),
        ]),
        alternatives("swapped_sin_cos", [(
            lambda x: _CENTRE + RADIUS * np.array([math.sin(OMEGA * x[0]), math.cos(OMEGA * x[0]), 0.0]),
            ("{name} swaps sin and cos: it starts a quarter circle away from the hand and turns "
             "clockwise. Integrate the exercise's velocity profile from the hand's start position."),
        )]),
        alternatives("direction", [(
            lambda x: _circle(x, sense=-1.0),
            ("{name} turns clockwise (seen from above): the exercise's velocity profile turns "
             "counter-clockwise (ẏ = r ω cos ωt > 0 at t = 0)."),
        )]),
        alternatives("degrees", [(
            lambda x: _circle(x, omega=90.0),
            ("{name} uses ω = 90 (degrees per second) inside cos and sin, which expect radians: "
             "ω = π/2 rad/s."),
        )]),
        dg.offset(),
        dg.scale(),
    ],
    noun="times",
    atol=1e-6,
    doc=("Check a function r_des(t) -> the circle's position (3,) (m), r = 0.05 m, ω = π/2 rad/s: "
         "compared with the reference at 20 random times in [0, 4] s, to 1e-6."),
))

circle_velocity = exercise(_CHAPTER, "circle_velocity", Check(
    name="v_des(t)",
    reference=lambda x: _circle_dot(x),
    variables=_T,
    groups=[("t", [0])],
    diagnoses=[
        alternatives("missing_chain_rule", [(
            lambda x: _circle_dot(x, factor=1.0),
            ("{name} misses the factor ω of the chain rule: d/dt cos(ωt) = −ω sin(ωt), so "
             "v_des = r ω [−sin ωt, cos ωt, 0]."),
        )]),
        alternatives("phase", [
            (lambda x: _circle_dot(x, phase=_PI / 2),
             ("{name} is a quarter turn out of phase: it is parallel to r_des − c, not tangent to "
              "the circle. The velocity is the derivative of the position: r ω [−sin ωt, cos ωt, 0].")),
            (lambda x: _circle_dot(x, phase=-_PI / 2),
             ("{name} is a quarter turn out of phase: it points towards the centre, not along the "
              "circle. The velocity is r ω [−sin ωt, cos ωt, 0].")),
            (lambda x: _circle_dot(x, phase=_PI),
             ("{name} has the wrong sign: the hand goes round the wrong way. "
              "d/dt cos(ωt) = −ω sin(ωt).")),
        ]),
        alternatives("swapped_sin_cos", [(
            lambda x: RADIUS * OMEGA * np.array([math.cos(OMEGA * x[0]), -math.sin(OMEGA * x[0]), 0.0]),
            ("{name} is the derivative of a circle with sin and cos swapped (starting at c + [0, r, 0], "
             "clockwise). Differentiate c + r [cos ωt, sin ωt, 0]: r ω [−sin ωt, cos ωt, 0]."),
        )]),
        alternatives("direction", [(
            lambda x: _circle_dot(x, sense=-1.0),
            "{name} has the wrong sign in y: the circle turns counter-clockwise, v_y = r ω cos ωt.",
        )]),
        alternatives("degrees", [
            (lambda x: _circle_dot(x, omega=90.0),
             ("{name} uses ω = 90 (degrees per second) where radians per second are needed: "
              "ω = π/2 rad/s.")),
            (lambda x: _circle_dot(x, omega=90.0, factor=OMEGA),
             ("{name} evaluates sin and cos at 90·t (degrees) while the factor is π/2: "
              "use ω = π/2 rad/s in both.")),
            (lambda x: _circle_dot(x, factor=90.0),
             "{name} has the factor ω in degrees per second (90): r ω with ω = π/2 rad/s."),
        ]),
        dg.scale(),
    ],
    noun="times",
    atol=1e-6,
    doc=("Check a function v_des(t) -> the circle's velocity (3,) (m/s), r = 0.05 m, ω = π/2 rad/s: "
         "compared with the reference at 20 random times in [0, 4] s, to 1e-6."),
))


# ------------------------------------------------------------------ the resolved-rate law
def _angles(lo_frac: float = 0.2, hi_frac: float = 0.8) -> list[Variable]:
    names = ("s0", "s1", "e0", "e1", "w0", "w1", "w2")
    out = []
    for k, (name, (lo, hi)) in enumerate(zip(names, _LIMITS), start=1):
        span = hi - lo
        out.append(Variable(f"q{k}", "angle", lo + lo_frac * span, lo + hi_frac * span,
                            aliases=(name, f"theta{k}", f"q_{k}")))
    return out


_Q_REGULAR = _angles(0.35, 0.65)   # around the mid-range pose, well away from singularities
_Q_ANY = _angles(0.0, 1.0)         # anywhere within the limits
_RDES = [Variable(f"{c}_des", "length", p - 0.1, p + 0.1) for c, p in zip("xyz", P_START)]
_VDES = [Variable(f"{c}_dot_des", "other", -0.1, 0.1) for c in "xyz"]


def _rate(x, kp=KP, feedforward=True, error_sign=1.0, gain_on_ff=False, inverse="pinv", q_shift=None):
    q, r_des, v_des = np.asarray(x[:7], dtype=float), x[7:10], x[10:13]
    qm = q if q_shift is None else q + q_shift
    arm = _arm()
    e = error_sign * (r_des - arm.fk(qm)[:3, 3])
    v = kp * (v_des + e) if gain_on_ff else (v_des if feedforward else 0.0) + kp * e
    if inverse == "full":
        return np.linalg.pinv(arm.jacobian(qm)) @ np.r_[v, 0.0, 0.0, 0.0]
    J = arm.position_jacobian(qm)
    return (J.T if inverse == "transpose" else np.linalg.pinv(J)) @ v


resolved_rate = exercise(_CHAPTER, "resolved_rate", Check(
    name="qdot(q, r_des, v_des)",
    reference=_rate,
    variables=[*_Q_REGULAR, *_RDES, *_VDES],
    groups=[("q", list(range(7))), ("r_des", [7, 8, 9]), ("v_des", [10, 11, 12])],
    diagnoses=[
        alternatives("open_loop", [(
            lambda x: _rate(x, feedforward=True, kp=0.0),
            ("{name} is the open-loop law q̇ = J⁺ ṙ_des: nothing corrects the position error, so "
             "the integration error and any model error accumulate (drift). Add the feedback "
             "term: q̇ = J⁺(ṙ_des + Kp (r_des − r(q))) with Kp = 10 /s."),
        )]),
        alternatives("no_feedforward", [(
            lambda x: _rate(x, feedforward=False),
            ("{name} is the pure proportional law q̇ = J⁺ Kp (r_des − r): it lags behind the moving "
             "reference. Add the feed-forward velocity ṙ_des."),
        )]),
        alternatives("error_sign", [(
            lambda x: _rate(x, error_sign=-1.0),
            ("{name} feeds back r − r_des: the error is r_des − r(q), otherwise the loop pushes "
             "the hand away from the circle."),
        )]),
        alternatives("gain_on_feedforward", [(
            lambda x: _rate(x, gain_on_ff=True),
            "{name} multiplies the feed-forward velocity by Kp too: q̇ = J⁺(ṙ_des + Kp (r_des − r)).",
        )]),
        alternatives("jacobian_transpose", [(
            lambda x: _rate(x, inverse="transpose"),
            "{name} uses Jᵀ; resolved-rate control inverts the Jacobian with the pseudoinverse J⁺.",
        )]),
        alternatives("full_jacobian", [(
            lambda x: _rate(x, inverse="full"),
            ("{name} inverts the full 6×7 Jacobian with a zero angular velocity: that also holds the "
             "hand's orientation fixed. The task is the position only: use the 3×7 position "
             "Jacobian J_v (the top three rows)."),
        )]),
        alternatives("missing_joint2_offset", [(
            lambda x: _rate(x, q_shift=-_JOINT2_OFFSET),
            ("{name} uses a model without the +π/2 offset of joint 2 (the tutorial's table as "
             "printed): its r(q) and J(q) belong to another pose of the arm. Use θ2 = q2 + π/2 "
             "(robokin.models.baxter_left)."),
        )]),
        dg.degrees(),
        dg.scale(),
    ],
    noun="configurations",
    atol=1e-6,
    doc=("Check a function qdot(q, r_des, v_des) -> J_v⁺(q)(v_des + Kp (r_des − r(q))), Kp = 10 /s, "
          "Baxter left arm, shoulder frame, hand flange."),
))


def reference_resolved_rate(q: Any, r_des: Any, v_des: Any, kp: float = KP) -> np.ndarray:
    """robokin's answer to the step ``resolved_rate`` of Task 3 (the tests' stand-in).

    The graded test of the loop ``track(q0, r_des, v_des, kp, ts, rate=resolved_rate)`` passes
    this function in place of the student's own law, so that a mistake in ``resolved_rate``
    costs the points of its own test only.

    Parameters
    ----------
    q : array_like, shape (7,)
        A configuration of the left arm (rad).
    r_des, v_des : array_like, shape (3,)
        The reference position (m) and velocity (m/s) of the hand, shoulder frame.
    kp : float
        The position gain (1/s); 0 for the open loop.

    Returns
    -------
    numpy.ndarray, shape (7,)
        The joint velocity the law of Task 3 commands (rad/s).
    """
    x = np.concatenate([as_vector(q, 7, "q"), as_vector(r_des, 3, "r_des"), as_vector(v_des, 3, "v_des")])
    return _rate(x, kp=as_scalar(kp, "kp"))


# ------------------------------------------------------------------ the tracking loop
_TRACK_SAMPLES = 6


def _track_loop(q0, r_des, v_des, kp, ts, *, sign=1.0, record_after=False, gain_on_ff=False,
                feedforward=True, open_loop=False) -> np.ndarray:
    """The reference Euler loop (and, with the keywords, its typical mistakes): the joint
    angles at the samples, shape (N, 7), row 0 = q0."""
    arm = _arm()
    q = np.array(q0, dtype=float)
    gain = 0.0 if open_loop else kp
    Q = []
    for r_d, v_d in zip(r_des, v_des):
        if not record_after:
            Q.append(q.copy())
        e = sign * (r_d - arm.fk(q)[:3, 3])
        v = gain * (v_d + e) if gain_on_ff else (v_d if feedforward else 0.0) + gain * e
        q = q + ts * (np.linalg.pinv(arm.position_jacobian(q)) @ v)
        if record_after:
            Q.append(q.copy())
    return np.array(Q)


def _track_args(x: np.ndarray) -> tuple:
    """``(q0, r_des, v_des, kp, ts)``: a straight reference line that starts near the hand,
    sampled at N = 6 instants."""
    q0 = np.array(x[:7])
    kp, ts = float(x[13]), float(x[14])
    k = np.arange(_TRACK_SAMPLES)[:, None]
    v_des = np.tile(x[10:13], (_TRACK_SAMPLES, 1))
    r_des = _position(q0) + x[7:10] + k * ts * v_des
    return q0, r_des, v_des, kp, ts


_pack_track = pack_joint_rows("track", _TRACK_SAMPLES, 7)
_track_variant = packed_variants(_track_loop, _track_args, _pack_track)


tracking_loop = exercise(_CHAPTER, "tracking_loop", LaterStepCheck(
    name="track(q0, r_des, v_des, kp, ts)",
    reference=_track_variant(),
    variables=[
        *_Q_REGULAR,
        *[Variable(f"offset_{c}", "other", -0.02, 0.02) for c in "xyz"],
        *[Variable(f"v_{c}", "other", -0.2, 0.2) for c in "xyz"],
        Variable("kp", "other", 2.0, 20.0),
        Variable("ts", "other", 0.005, 0.04),
    ],
    diagnoses=[
        alternatives("open_loop", [(_track_variant(open_loop=True), (
            "{name} ignores the gain kp: it integrates the open-loop law q̇ = J⁺ ṙ_des. The "
            "command is q̇ = J⁺(ṙ_des + kp (r_des − r(q))), kp = 0 only for the open loop."
        ))]),
        alternatives("no_feedforward", [(_track_variant(feedforward=False), (
            "{name} never adds the feed-forward velocity: the command is "
            "q̇ = J⁺(ṙ_des + kp (r_des − r))."
        ))]),
        alternatives("error_sign", [(_track_variant(sign=-1.0), (
            "{name} feeds back r − r_des: the error must be r_des − r, otherwise the loop "
            "pushes the hand away."
        ))]),
        alternatives("recorded_after_step", [(_track_variant(record_after=True), (
            "{name} records q after the Euler step: row k must be the configuration at "
            "sample k, the one the command of sample k is computed from (row 0 = q0)."
        ))]),
        alternatives("gain_on_feedforward", [(_track_variant(gain_on_ff=True), (
            "{name} multiplies the feed-forward velocity by kp too: q̇ = J⁺(ṙ_des + kp "
            "(r_des − r))."
        ))]),
    ],
    noun="starts, references, gains and time steps",
    arguments=_track_args,
    signature="track(q0, r_des, v_des, kp, ts) -> joint angles (N, 7)",
    hint=("Compare your rows with the task's contract: row 0 is q0, and row k + 1 is row k "
          "plus ts times the command of the law at row k, with the reference's row k and "
          "the gain kp."),
    atol=1e-7,
    doc=("Check a resolved-rate tracking loop track(q0, r_des, v_des, kp, ts) that returns "
         "the joint angles at the samples, shape (N, 7), row 0 = q0 (Baxter left arm, "
         "shoulder frame, hand flange); a loop with a parameter rate= is given robokin's law "
         "there, so that the loop alone is checked."),
    pack=_pack_track,
    steps=lambda: {"rate": reference_resolved_rate},
))


# ------------------------------------------------------------------ forward kinematics
def _forward_kinematics_mistakes() -> list:
    return [
        alternatives("missing_joint2_offset", [
            (lambda x: _pose(np.asarray(x) - _JOINT2_OFFSET),
             ("{name} has no +π/2 offset on joint 2: it uses θ2 = q2 (the tutorial's table as "
              "printed), so q = 0 is not the URDF zero pose (the stretched arm). Use θ2 = q2 + π/2.")),
            (lambda x: _pose(np.asarray(x) - 2 * _JOINT2_OFFSET),
             "{name} uses θ2 = q2 − π/2: the offset of joint 2 is +π/2."),
        ]),
        alternatives("standard_dh", [
            (lambda x: _standard_dh_reading(True).fk(np.asarray(x)),
             ("{name} reads the modified-DH (Craig) table as a standard DH table: "
              "Rz(θ)Tz(d)Tx(a)Rx(α) instead of Rx(α_(i−1)) Tx(a_(i−1)) Rz(θ_i) Tz(d_i). "
              "The tutorial's table is in the modified convention.")),
            (lambda x: _standard_dh_reading(False).fk(np.asarray(x)),
             ("{name} reads the modified-DH table as a standard DH table and also misses the "
              "+π/2 offset of joint 2.")),
        ]),
        alternatives("torso_frame", [(
            lambda x: _pose(x, base="torso"),
            ("{name} is expressed in Baxter's torso frame; this chapter uses the shoulder (s0) "
             "frame of the tutorial: baxter_left(base='shoulder')."),
        )]),
        alternatives("gripper_frame", [(
            lambda x: _pose(x, end="gripper"),
            ("{name} ends at the gripper tip (5 cm beyond the hand flange); the tutorial's last "
             "link ends at the flange, d7 = 0.2295 m."),
        )]),
        alternatives("flange_twice", [(
            lambda x: _pose(x) @ _shift_z(_D_HAND),
            ("{name} puts the hand a second flange offset beyond the flange, along z7: the offset "
             "0.2295 m is counted twice, as the last row's d and again as d_hand. In a table like "
             "MDH the flange offset is d_hand alone, and the last row's d is 0."),
        )]),
        *dg.standard("transform"),
    ]


forward_kinematics = exercise(_CHAPTER, "forward_kinematics", Check(
    name="T_BE(q)",
    reference=lambda x: _pose(x),
    variables=_Q_ANY,
    groups=[("q", list(range(7)))],
    diagnoses=_forward_kinematics_mistakes(),
    noun="configurations",
    atol=1e-3,
    rtol=0.0,
    hint="Compare with robokin.models.baxter_left(base='shoulder').fk(q).",
    doc=("Check a function T_BE(q) -> 4×4 pose of the hand flange in the base frame B "
         "(the s0 joint frame), within 1 mm, at 20 random configurations within the limits "
         "(Baxter left arm)."),
))


def _position_mistakes() -> list:
    return [
        alternatives("missing_joint2_offset", [(
            lambda x: _position(np.asarray(x) - _JOINT2_OFFSET),
            ("{name} is computed without the +π/2 offset of joint 2 (the tutorial's table as "
             "printed): that is another pose of the arm. Use θ2 = q2 + π/2."),
        )]),
        alternatives("standard_dh", [(
            lambda x: _standard_dh_reading(True).fk(np.asarray(x))[:3, 3],
             "{name} reads the modified-DH table as a standard DH table.",
        )]),
        alternatives("torso_frame", [(
            lambda x: _pose(x, base="torso")[:3, 3],
             "{name} is in Baxter's torso frame; use the shoulder (s0) frame.",
        )]),
        alternatives("gripper_frame", [(
            lambda x: _pose(x, end="gripper")[:3, 3],
             "{name} is the gripper tip, 5 cm beyond the hand flange.",
        )]),
        *dg.standard("vector"),
    ]


hand_position_at = exercise(_CHAPTER, "hand_position_at", Check(
    name="r_hand(q_start)",
    reference=lambda x: _position(x),
    variables=_Q_ANY,
    diagnoses=_position_mistakes(),
    at=Q_START,
    at_text="q_start = lower + 0.5·range",
    atol=1e-3,
    rtol=0.0,
    values_shown=False,
    hint=("It is the top of the last column of your forward kinematics of MDH at q_start (in radians): "
          "the product of the seven link transforms and the flange's T_z(d_hand), in the shoulder frame."),
    doc="Check the hand position (m, shoulder frame) at the mid-range configuration Q_START, within 1 mm.",
))


# ------------------------------------------------------------------ distance to a singularity
def _singular_values(x, rows: str = "position") -> np.ndarray:
    """The singular values of the Jacobian at the configuration x (largest first): of the
    3×7 position Jacobian J_v, or of the full 6×7 Jacobian (a mistake)."""
    arm = _arm()
    q = np.asarray(x[:7], dtype=float)
    jacobian = arm.position_jacobian(q) if rows == "position" else arm.jacobian(q)
    return np.linalg.svd(jacobian, compute_uv=False)


sigma_min = exercise(_CHAPTER, "sigma_min", Check(
    name="sigma_min_of(q)",
    reference=lambda x: _singular_values(x)[-1],
    variables=_Q_ANY,
    groups=[("q", list(range(7)))],
    diagnoses=[
        alternatives("largest_singular_value", [(
            lambda x: _singular_values(x)[0],
            ("{name} is the largest singular value of J_v: the distance to a singular "
             "configuration is the smallest one (np.linalg.svd sorts them largest first)."),
        )]),
        alternatives("eigenvalue_not_root", [(
            lambda x: _singular_values(x)[-1] ** 2,
            ("{name} is the smallest eigenvalue of J_v J_vᵀ, in m²/rad²: the singular values "
             "are the square roots of those eigenvalues."),
        )]),
        alternatives("full_jacobian", [(
            lambda x: _singular_values(x, rows="full")[-1],
            ("{name} is the smallest singular value of the full 6×7 Jacobian: the task is the "
             "hand position, whose Jacobian is the 3×7 J_v (the top three rows)."),
        )]),
        alternatives("manipulability", [(
            lambda x: np.asarray(np.prod(_singular_values(x))),
            ("{name} is the manipulability, the product of the singular values: it vanishes "
             "at the same configurations, but the distance to them is the smallest singular "
             "value σ_min, in m/rad."),
        )]),
        dg.degrees(),
    ],
    noun="configurations",
    atol=1e-9,
    doc=("Check a function sigma_min_of(q) -> the smallest singular value of the 3×7 position "
         "Jacobian J_v of the Baxter left arm (shoulder frame, hand flange), in m/rad."),
))


# ------------------------------------------------------------------ the first loss of rank along a run
#: The runs of the closest_approach check: (start, the W1 angles of a straight joint path
#: towards the straight wrist, time step [s], thresholds [m/rad]). The runs come within their
#: first threshold first at a sample other than the first, the last and the most singular one
#: (sigma_min falls and rises again along the second), and never within their last.
_RUN_CASES = (
    (Q_START, (0.6, -0.4, 41), 0.05, (0.2, 0.1)),
    (np.array([-1.16, -3.29, -2.44, 0.24, -2.56, 0.03, -2.53]), (0.4, -0.3, 50), 0.03, (0.03, 0.01, 0.003)),
)


def _run_cases() -> list[tuple[np.ndarray, float, float]]:
    """``(run, ts, threshold)``: straight joint paths (N, 7) that turn W1 through zero."""
    cases = []
    for start, (first, last, samples), ts, thresholds in _RUN_CASES:
        run = np.tile(start, (samples, 1))
        run[:, 5] = np.linspace(first, last, samples)
        cases += [(run, ts, threshold) for threshold in thresholds]
    return cases


def _approach(sigma: np.ndarray, ts: float, threshold: float, mistake: str = "") -> tuple:
    """``(smallest sigma_min, time of the first sample below threshold or None)`` of the values
    ``sigma`` (N,) of a run, and, with ``mistake``, what a typical slip of it returns."""
    below = np.flatnonzero(sigma < (0.01 if mistake == "threshold_ignored" else threshold))
    smallest = float(sigma.max() if mistake == "largest_value" else sigma.min())
    if not below.size:
        return smallest, None
    index = {"time_of_minimum": int(np.argmin(sigma)), "last_sample": int(below[-1]),
             "counted_from_one": int(below[0]) + 1}.get(mistake, int(below[0]))
    if mistake == "time_of_minimum" and sigma.min() >= threshold:
        return smallest, None
    if mistake == "index_not_time":
        return smallest, float(index)
    return smallest, (TS if mistake == "time_step_ignored" else ts) * index


_APPROACH_MISTAKES = (
    ("time_of_minimum", ("{name} gives the time of the smallest σ_min, not of the first sample below the "
                         "threshold: a run can come within the threshold samples before it is closest.")),
    ("last_sample", "{name} gives the time of the last sample below the threshold, not of the first."),
    ("counted_from_one", ("{name} gives (k + 1)·ts for sample k: row 0 of the run is at time 0, so "
                          "sample k is at k·ts.")),
    ("index_not_time", "{name} gives the index k of the sample, not its time k·ts in seconds."),
    ("time_step_ignored", "{name} ignores its argument ts: the samples are ts seconds apart, not 2 ms."),
    ("threshold_ignored", "{name} ignores its argument threshold: it compares with 0.01 m/rad always."),
    ("largest_value", "{name} gives the largest σ_min along the run: the closest approach is the smallest."),
)


class _ClosestApproachCheck(FunctionCheck):
    """Check ``closest_approach(Q, ts, threshold) -> (sigma, time)`` on joint paths of its own."""

    def judge(self, answer: Any) -> CheckResult:
        cases = _run_cases()
        n = len(cases)
        sigmas = [_arm().singular_values(run, position_only=True)[:, -1] for run, _, _ in cases]
        got = []
        for run, ts, threshold in cases:
            where = f"for a run of {len(run)} samples, ts = {ts:g} s, threshold = {threshold:g} m/rad"
            out = self.call(answer, (run.copy(), ts, threshold), where, samples=n)
            try:
                smallest, time = out
                got.append((float(smallest), None if time is None else float(time)))
            except (TypeError, ValueError):
                return self.failure("shape", (f"{self.name} must return a pair (sigma, time): the smallest "
                                              f"σ_min in m/rad and a time in s, or None; got {out!r}."), n)

        def same(pairs) -> bool:
            for (s, t), (s_ref, t_ref) in zip(got, pairs):
                if not np.isclose(s, s_ref, rtol=1e-9, atol=1e-12) or (t is None) != (t_ref is None):
                    return False
                if t is not None and not np.isclose(t, t_ref, rtol=1e-9, atol=1e-12):
                    return False
            return True

        def expected(mistake: str = "") -> list:
            return [_approach(sigma, ts, threshold, mistake) for (_, ts, threshold), sigma in zip(cases, sigmas)]

        if same(expected()):
            return self.success(f"{self.name} is correct (checked on {n} runs, time steps and thresholds "
                                "of its own).", n)
        found = self.diagnose(_APPROACH_MISTAKES, lambda code: same(expected(code)), n)
        if found is not None:
            return found
        for ((run, ts, threshold), (s, t), (s_ref, t_ref)) in zip(cases, got, expected()):
            if not np.isclose(s, s_ref, rtol=1e-9, atol=1e-12):
                return self.failure("mismatch", (
                    f"{self.name}: the smallest σ_min along a run of {len(run)} samples is {fmt(s_ref)} "
                    f"m/rad; yours {fmt(s)}. Check your σ_min of one configuration first."), n)
            if (t is None) != (t_ref is None):
                said = "None (never)" if t is None else f"{fmt(t)} s"
                return self.failure("mismatch", (
                    f"{self.name}: with ts = {ts:g} s and threshold = {threshold:g} m/rad your time is "
                    f"{said}, but {'a sample is' if t_ref is not None else 'no sample is'} below the "
                    "threshold: the time is None exactly when no sample is."), n)
        return self.failure("mismatch", (
            f"{self.name} gives other times than those of the first sample below the threshold "
            "(row k of the run is at k·ts)."), n)


closest_approach = exercise(_CHAPTER, "closest_approach", _ClosestApproachCheck(
    name="closest_approach(Q, ts, threshold)",
    signature="closest_approach(Q, ts, threshold) -> (sigma, time)",
    noun="runs",
    doc=("Check a function closest_approach(Q, ts, threshold) -> (sigma, time): the smallest σ_min of "
         "J_v along the run Q (N, 7) and the time of its first sample below threshold (None: none is), "
         "on joint paths, time steps and thresholds of its own (Baxter left arm)."),
))


# ------------------------------------------------------------------ the link transform and the chord
def _elementary(x) -> list[np.ndarray]:
    """R_x(α), T_x(a), R_z(θ), T_z(d) at ``x = (a, α, d, θ)``."""
    a, alpha, d, theta = (float(v) for v in x[:4])
    rot_x, shift_x, rot_z, shift_z = np.eye(4), np.eye(4), np.eye(4), np.eye(4)
    c, s = math.cos(alpha), math.sin(alpha)
    rot_x[1:3, 1:3] = [[c, -s], [s, c]]
    shift_x[0, 3] = a
    c, s = math.cos(theta), math.sin(theta)
    rot_z[:2, :2] = [[c, -s], [s, c]]
    shift_z[2, 3] = d
    return [rot_x, shift_x, rot_z, shift_z]


def _link(x, order=(0, 1, 2, 3)) -> np.ndarray:
    factors = _elementary(x)
    return factors[order[0]] @ factors[order[1]] @ factors[order[2]] @ factors[order[3]]


def _factor(k: int):
    """The function x -> the k-th elementary transform of the link (see :func:`_elementary`)."""
    return lambda x: _elementary(x)[k]


_LINK_FACTORS = [(name, _factor(k)) for k, name in enumerate(("R_x(α)", "T_x(a)", "R_z(θ)", "T_z(d)"))]

link_transform = exercise(_CHAPTER, "link_transform", Check(
    name="mdh_link(a, alpha, d, theta)",
    reference=_link,
    variables=[Variable("a", "length", -0.4, 0.4), Variable("alpha", "angle", -3.0, 3.0),
               Variable("d", "length", -0.4, 0.4), Variable("theta", "angle", -3.0, 3.0)],
    groups=[("a", [0]), ("alpha", [1]), ("d", [2]), ("theta", [3])],
    diagnoses=[
        alternatives("standard_dh", [(
            lambda x: _link(x, order=(2, 3, 1, 0)),
            ("{name} is the standard (Denavit–Hartenberg) link transform R_z(θ) T_z(d) T_x(a) R_x(α): "
             "the table is in the modified (Craig) convention, R_x(α) T_x(a) R_z(θ) T_z(d)."),
        )]),
        dg.composition_order(_LINK_FACTORS, "ⁱ⁻¹T_i"),
        dg.missing_factor(_LINK_FACTORS, "ⁱ⁻¹T_i"),
        *dg.standard("transform"),
    ],
    noun="rows (a, α, d, θ)",
    atol=1e-9,
    doc=("Check a function mdh_link(a, alpha, d, theta) -> the 4×4 link transform of one row of a "
         "modified (Craig) DH table, at 20 random rows."),
))


def _chord(x, factor=2.0, angle=0.5, arc=False) -> np.ndarray:
    rho, step = float(x[0]), float(x[1])
    return np.asarray(rho * step if arc else factor * rho * math.sin(angle * step))


chord_length = exercise(_CHAPTER, "chord_length", Check(
    name="chord_length(rho, step)",
    reference=_chord,
    variables=[Variable("rho", "length", 0.0, 0.5), Variable("step", "angle", 0.1, 3.0)],
    groups=[("rho", [0]), ("step", [1])],
    diagnoses=[
        alternatives("arc", [(
            lambda x: _chord(x, arc=True),
            ("{name} is the arc ρ·Δθ the hand travels, not the straight distance between its two "
             "positions (the chord): they agree only for small steps."),
        )]),
        alternatives("full_angle", [(
            lambda x: _chord(x, angle=1.0),
            ("{name} takes the sine of the whole step: the two radii to the ends of the chord and the "
             "chord form an isosceles triangle, and its altitude from the axis halves the step."),
        )]),
        alternatives("half_chord", [(
            lambda x: _chord(x, factor=1.0),
            "{name} is half the chord: the isosceles triangle has two halves, one on each side.",
        )]),
        dg.degrees(),
        dg.scale(),
    ],
    noun="radii and steps",
    atol=1e-12,
    doc=("Check a function chord_length(rho, step) -> the distance (m) between the two positions of a "
         "point at distance rho (m) from a revolute joint's axis when the joint turns by step (rad)."),
))


# ------------------------------------------------------------------ damped least squares
_DAMPED_VARIABLES = [*_Q_ANY, *_RDES, *_VDES, Variable("kp", "other", 2.0, 20.0),
                     Variable("damping", "length", 0.01, 0.1)]


def _damped(x, *, squared=True, feedback=True, damped=True, error_sign=1.0) -> np.ndarray:
    """J_v^T (J_v J_v^T + λ² I)^-1 (v_des + kp (r_des − r(q))) at ``x = (q, r_des, v_des, kp, λ)``
    (and, with the keywords, its typical mistakes)."""
    q, r_des, v_des, kp, damping = np.asarray(x[:7]), x[7:10], x[10:13], float(x[13]), float(x[14])
    arm = _arm()
    J = arm.position_jacobian(q)
    v = v_des + (kp * error_sign * (r_des - arm.fk(q)[:3, 3]) if feedback else 0.0)
    if not damped:
        return np.linalg.pinv(J) @ v
    return J.T @ np.linalg.solve(J @ J.T + (damping**2 if squared else damping) * np.eye(3), v)


class _DampedRateCheck(MatrixArgumentsCheck):
    """The damped command at the sampled dampings, then without damping: the law of Task 3."""

    def evaluate(self, answer: Any) -> CheckResult:
        result = super().evaluate(answer)
        build = self.arguments
        if not result.passed or build is None:
            return result
        undamped = self.sample_points()[:5].copy()
        undamped[:, 14] = 0.0
        for x in undamped:
            try:
                value = np.array(answer(*build(x)), dtype=np.float64)
                same = value.shape == (7,) and np.allclose(value, _damped(x), atol=self.atol)
            except Exception:  # noqa: BLE001 - a singular solve is the mistake named below
                same = False
            if not same:
                return CheckResult(self.name, False, (
                    f"{FAIL} {self.name} with damping = 0 is not J_v⁺ v, the command of Task 3 (checked at "
                    "5 configurations): J_vᵀJ_v (7×7) has rank 3 and no inverse; damp J_v J_vᵀ (3×3), "
                    "which has one away from singular configurations."), "undamped", len(undamped))
        return result


damped_rate = exercise(_CHAPTER, "damped_rate", _DampedRateCheck(
    name="dls_rate(q, r_des, v_des, kp, damping)",
    reference=_damped,
    variables=_DAMPED_VARIABLES,
    diagnoses=[
        alternatives("damping_not_squared", [(
            lambda x: _damped(x, squared=False),
            ("{name} adds λ I to J_v J_vᵀ: λ is in m and J_v J_vᵀ in m², so the damping term is "
             "λ² I."),
        )]),
        alternatives("no_damping", [(
            lambda x: _damped(x, damped=False),
            "{name} is the undamped pseudoinverse law: the damping λ never enters.",
        )]),
        alternatives("no_feedback", [(
            lambda x: _damped(x, feedback=False),
            "{name} leaves out the feedback term kp (r_des − r(q)): damp the same command as in Task 3.",
        )]),
        alternatives("error_sign", [(
            lambda x: _damped(x, error_sign=-1.0),
            "{name} feeds back r − r_des: the error is r_des − r(q).",
        )]),
        dg.degrees(),
        dg.scale(),
    ],
    noun="configurations, references, gains and dampings",
    arguments=lambda x: (np.array(x[:7]), np.array(x[7:10]), np.array(x[10:13]), float(x[13]),
                         float(x[14])),
    signature="dls_rate(q, r_des, v_des, kp, damping) -> joint velocity (7,)",
    atol=1e-7,
    doc=("Check a damped least-squares command dls_rate(q, r_des, v_des, kp, damping) -> joint "
         "velocity (7,) in rad/s, at random configurations within the limits, and without damping "
         "(Baxter left arm, shoulder frame, hand flange)."),
))
