r"""Exercise checks of chapter 1: kinematics of the 3-DOF leg (ETH AMR exercise 1).

Every reference comes from :func:`robokin.models.eth_leg` (one model
definition): relative transforms are ratios of the model's frames,
``H_12 = frames[1]^{-1} frames[2]``, the foot position and Jacobian are the
model's ``fk`` and ``position_jacobian``.

=========================  ==================================================  =================
check                      the student's answer                                 inputs
=========================  ==================================================  =================
``rotation_B1/_12/_23``    R_B1(α), R_12(β), R_23(γ): 3×3                       one angle
``transform_B1/_12/_23``   H_B1(α), H_12(β), H_23(γ): 4×4                       one angle
``transform_3F``           H_3F: 4×4 constant                                   --
``transform_BF``           H_BF(q) = H_B1 H_12 H_23 H_3F                        q = (α, β, γ)
``foot_position``          B r_BF(q): 3-vector                                  q
``foot_jacobian``          J_sym(q) = ∂r_BF/∂q: 3×3                             q
``foot_jacobian_at``       J_lift, J at q = [0°, 60°, −120°]: numbers           --
``lift_velocity``          dq_cmd for the foot velocity v = [0, 0, −1] m/s       --
                           at that q
``joint_velocity``         function (v, jacobian) -> q̇ with J q̇ = v: (3,)      q, v
``newton_step``            function (q, r_goal) -> the next Newton iterate      q, r_goal
``newton_ik``              function (r_goal, q0, damping, tol, max_iterations)  start, goal, λ,
                           -> the iterates q^0 ... q^K, (K + 1, 3)              budget
``ik_closed_form``         function p -> every solution of r_BF(q) = p, (m, 3)  goal p
``ik_solution(q)``         q with r_BF(q) = [0.2, 0.5, −2] (any solution)       --
``tracking_controller``    function (q, r_des, v_des) -> q̇ = J⁺(v_des + Kp e)  q, r_des, v_des
``tracking_loop``          function (q0, r_des, v_des, kp, ts, feedforward)     start, reference,
                           -> joint angles at the N samples, (N, 3)             gain, time step
=========================  ==================================================  =================

Symbolic answers may use the symbols ``alpha, beta, gamma`` (any assumptions)
or ``q1, q2, q3``; functions may take the angles one by one or a vector ``q``.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    FAIL, PASS, Check, CheckResult, FunctionCheck, MatrixArgumentsCheck, Variable,
    alternatives, fmt, pack_joint_rows, packed_variants, report, show,
)
from robokin.check._registry import exercise
from robokin.validation import as_vector, check_positive

__all__ = [
    "rotation_B1", "rotation_12", "rotation_23",
    "transform_B1", "transform_12", "transform_23", "transform_3F", "transform_BF",
    "foot_position", "foot_jacobian", "foot_jacobian_at", "lift_velocity", "joint_velocity",
    "newton_step", "ik_solution", "tracking_controller", "newton_ik", "tracking_loop",
    "ik_closed_form",
    "Q_LIFT", "V_LIFT", "R_GOAL", "KP",
]

#: Configuration of task 3 (rad): [0°, 60°, −120°].
Q_LIFT = np.deg2rad([0.0, 60.0, -120.0])
#: Foot velocity of task 3 (m/s), as stated in the exercise.
V_LIFT = np.array([0.0, 0.0, -1.0])
#: Reachable IK goal of task 4 (m).
R_GOAL = np.array([0.2, 0.5, -2.0])
#: Gain of the tracking controller of task 5 (1/s).
KP = 10.0

_CHAPTER = "leg"
_PI = math.pi

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back (a newton_ik that calls solve_ik) is flagged for review by hand
#: (tools/grading/bridge/delegation.py reads this literal table without importing the module)
DELEGATION = {
    # the Jacobian written by differentiation, not the model's (r_BF.jacobian of sympy is fine)
    "foot_jacobian": {"position_jacobian": "SerialChain.position_jacobian"},
    "foot_jacobian_at": {"position_jacobian": "SerialChain.position_jacobian"},
    "newton_ik": {"solve_ik": "robokin.motion.solve_ik", "solve_ik_once": "robokin.motion.solve_ik_once",
                  "solve_ik_batch": "robokin.motion.solve_ik_batch"},
    "ik_closed_form": {"solve_ik": "robokin.motion.solve_ik", "solve_ik_once": "robokin.motion.solve_ik_once",
                       "solve_ik_batch": "robokin.motion.solve_ik_batch"},
    "tracking_loop": {"CartesianController": "robokin.motion.CartesianController",
                      "simulate": "robokin.motion.simulate",
                      "track_position_batch": "robokin.motion.track_position_batch"},
}


@lru_cache(maxsize=1)
def _leg():
    from robokin.models import eth_leg

    return eth_leg()


def _frames(q) -> np.ndarray:
    return _leg().frames(np.asarray(q, dtype=float))


def _relative(i: int, j: int, q) -> np.ndarray:
    """H_ij = (T_Bi)^-1 T_Bj from the model's frames (0 = B, 4 = F)."""
    F = _frames(q)
    return np.linalg.solve(F[i], F[j])


def _position(q) -> np.ndarray:
    return _leg().fk(np.asarray(q, dtype=float))[:3, 3]


def _jacobian(q) -> np.ndarray:
    return _leg().position_jacobian(np.asarray(q, dtype=float))


# ------------------------------------------------------------------ variables
def _angle(name: str, k: int, low: float = -_PI, high: float = _PI) -> Variable:
    return Variable(name, "angle", low, high, aliases=(f"q{k}", f"q_{k}", f"theta{k}"))


ALPHA, BETA, GAMMA = _angle("alpha", 1), _angle("beta", 2), _angle("gamma", 3)
Q = [ALPHA, BETA, GAMMA]
_QGROUP = [("q", [0, 1, 2])]
# Away from the singular configurations (knee stretched, foot on the hip axis), for
# checks that invert the Jacobian.
_Q_REGULAR = [
    _angle("alpha", 1, -1.0, 1.0), _angle("beta", 2, -1.2, 1.2), _angle("gamma", 3, 0.3, 2.5)
]

_AXIS_NAMES = "xyz"
#: the joint of each relative transform: (frame i, frame j, variable, axis index)
_JOINTS = {"B1": (0, 1, ALPHA, 0), "12": (1, 2, BETA, 1), "23": (2, 3, GAMMA, 1)}


def _elementary(axis: int, angle: float) -> np.ndarray:
    from robokin.transforms import rotx, roty, rotz

    return (rotx, roty, rotz)[axis](float(angle))


def _wrong_axis(key: str, homogeneous: bool):
    """Rotations about the other two axes (either direction) instead of the right one."""
    i, j, var, axis = _JOINTS[key]
    items = []
    for other in range(3):
        if other == axis:
            continue
        for sign, how in ((1, ""), (-1, " (and in the opposite direction)")):
            def fn(x, other=other, sign=sign):
                R = _elementary(other, sign * x[0])
                if not homogeneous:
                    return R
                H = _relative(i, j, _configuration_for(key, x[0])).copy()
                H[:3, :3] = R
                return H

            items.append((fn, (
                f"{{name}} rotates about the {_AXIS_NAMES[other]} axis{how}, but {var.label} "
                f"turns about the {_AXIS_NAMES[axis]} axis of frame {key[-1]}: the "
                f"{_AXIS_NAMES[axis]} column and row of the rotation are those of the identity."
            )))
    return alternatives("wrong_axis", items)


def _configuration_for(key: str, angle: float) -> np.ndarray:
    q = np.zeros(3)
    q[{"B1": 0, "12": 1, "23": 2}[key]] = angle
    return q


def _rotation_check(key: str) -> Check:
    i, j, var, _ = _JOINTS[key]
    return Check(
        name=f"R_{key}",
        reference=lambda x: _relative(i, j, _configuration_for(key, x[0]))[:3, :3],
        variables=[var],
        diagnoses=[_wrong_axis(key, False), *dg.standard("rotation")],
        noun="angles",
        doc=f"Check R_{key}({var.name}): a sympy Matrix, a function of {var.name}, ...",
    )


def _transform_check(key: str) -> Check:
    i, j, var, _ = _JOINTS[key]
    return Check(
        name=f"H_{key}",
        reference=lambda x: _relative(i, j, _configuration_for(key, x[0])),
        variables=[var],
        diagnoses=[_wrong_axis(key, True), *dg.standard("transform")],
        noun="angles",
        doc=f"Check the homogeneous transform H_{key}({var.name}) (4×4).",
    )


rotation_B1 = exercise(_CHAPTER, "rotation_B1", _rotation_check("B1"))
rotation_12 = exercise(_CHAPTER, "rotation_12", _rotation_check("12"))
rotation_23 = exercise(_CHAPTER, "rotation_23", _rotation_check("23"))
transform_B1 = exercise(_CHAPTER, "transform_B1", _transform_check("B1"))
transform_12 = exercise(_CHAPTER, "transform_12", _transform_check("12"))
transform_23 = exercise(_CHAPTER, "transform_23", _transform_check("23"))
transform_3F = exercise(_CHAPTER, "transform_3F", Check(
    name="H_3F",
    reference=lambda x: _relative(3, 4, np.zeros(3)),
    diagnoses=dg.standard("transform"),
    values_shown=False,
    hint=("Its rotation block holds the foot frame's axes written in frame 3, the top of its last "
          "column the foot's position in frame 3, ₃r_3F of the problem statement, and its last "
          "row is [0, 0, 0, 1]."),
    doc="Check the constant transform H_3F from the knee frame 3 to the foot frame F.",
))

# ------------------------------------------------------------------ H_BF
_FACTOR_FRAMES = [("H_B1", 0, 1), ("H_12", 1, 2), ("H_23", 2, 3), ("H_3F", 3, 4)]


def _factor(i: int, j: int):
    return lambda x: _relative(i, j, x)


_FACTORS = [(nm, _factor(i, j)) for nm, i, j in _FACTOR_FRAMES]


transform_BF = exercise(_CHAPTER, "transform_BF", Check(
    name="H_BF",
    reference=lambda x: _relative(0, 4, x),
    variables=Q,
    groups=_QGROUP,
    diagnoses=[
        dg.composition_order(_FACTORS, "H_BF"),
        dg.missing_factor(_FACTORS, "H_BF"),
        *dg.standard("transform"),
    ],
    noun="configurations",
    doc="Check H_BF(α, β, γ), the pose of the foot frame in the base frame.",
))

# ------------------------------------------------------------------ foot position and Jacobian
_P_B1 = lambda: _relative(0, 1, np.zeros(3))[:3, 3]  # noqa: E731  (B r_B1 from the model)

foot_position = exercise(_CHAPTER, "foot_position", Check(
    name="r_BF(q)",
    reference=_position,
    variables=Q,
    groups=_QGROUP,
    diagnoses=[
        alternatives("missing_offset", [(
            lambda x: _position(x) - _P_B1(),
            "{name} misses the constant offset B r_B1 = [0, 1, 0] from the base to the hip "
            "(the last column of H_B1).",
        )]),
        alternatives("wrong_frame", [(
            lambda x: _frames(x)[3][:3, 3],
            "{name} is the position of the knee (origin of frame 3), not of the foot: "
            "include H_3F.",
        )]),
        *dg.standard("vector"),
    ],
    noun="configurations",
    doc="Check the foot position B r_BF(α, β, γ) (3-vector).",
))

foot_jacobian = exercise(_CHAPTER, "foot_jacobian", Check(
    name="J_sym(q)",
    reference=_jacobian,
    variables=Q,
    groups=_QGROUP,
    diagnoses=dg.standard("jacobian"),
    noun="configurations",
    doc="Check the foot-point Jacobian J(α, β, γ) = ∂ r_BF / ∂q (3×3).",
))

_AT_LIFT = "q = [0°, 60°, −120°]"

foot_jacobian_at = exercise(_CHAPTER, "foot_jacobian_at", Check(
    name="J_lift",
    reference=_jacobian,
    variables=Q,
    at=Q_LIFT,
    at_text=_AT_LIFT,
    atol=1e-3,
    rtol=1e-3,
    diagnoses=dg.standard("jacobian"),
    values_shown=False,
    hint=("Substitute this q (in radians) into your J_sym: column i is the derivative of r_BF "
          "with respect to the i-th joint angle."),
    doc="Check the numbers of the foot Jacobian at q = [0°, 60°, −120°].",
))


def _lift(x, v=V_LIFT):
    return np.linalg.pinv(_jacobian(x)) @ v


lift_velocity = exercise(_CHAPTER, "lift_velocity", Check(
    name="dq_cmd",
    reference=_lift,
    variables=Q,
    at=Q_LIFT,
    at_text=f"{_AT_LIFT} for v = [0, 0, −1] m/s",
    atol=1e-3,
    rtol=1e-3,
    diagnoses=[
        alternatives("velocity_sign", [(
            lambda x: _lift(x, -V_LIFT),
            "{name} moves the foot with v = [0, 0, +1] m/s, not with the exercise's "
            "v = [0, 0, −1] m/s: solve J q̇ = v for the v the statement gives.",
        )]),
        alternatives("transpose", [(
            lambda x: _jacobian(x).T @ V_LIFT,
            "{name} uses Jᵀ v; the joint velocity is J⁻¹ v (J⁺ v): the transpose is not "
            "the inverse.",
        )]),
        *dg.standard("angles"),
    ],
    values_shown=False,
    hint="It must solve J q̇ = v with the Jacobian at this q: check that J_lift @ dq_cmd gives v.",
    doc=("Check the joint velocity q̇ (rad/s) that moves the foot with v = [0, 0, −1] m/s at "
         "q = [0°, 60°, −120°], against the model's Jacobian."),
))

_V_FOOT = [Variable(f"v_{c}", "other", -1.0, 1.0) for c in "xyz"]


def _joint_velocity_arguments(x: np.ndarray) -> tuple:
    """``(v, J)``: a foot velocity and the model's Jacobian at a regular configuration."""
    return np.array(x[3:6]), _jacobian(x[:3])


def _solved_velocity(x: np.ndarray, jacobian=None, sign: float = 1.0) -> np.ndarray:
    v, J = _joint_velocity_arguments(x)
    return sign * np.linalg.solve(J if jacobian is None else jacobian, v)


joint_velocity = exercise(_CHAPTER, "joint_velocity", MatrixArgumentsCheck(
    name="joint_velocity(v, jacobian)",
    reference=_solved_velocity,
    variables=[*_Q_REGULAR, *_V_FOOT],
    diagnoses=[
        alternatives("velocity_sign", [(lambda x: _solved_velocity(x, sign=-1.0), (
            "{name} returns −J⁻¹ v: that joint velocity moves the foot with −v."
        ))]),
        alternatives("transpose", [(lambda x: _joint_velocity_arguments(x)[1].T @ x[3:6], (
            "{name} returns Jᵀ v; the joint velocity solves J q̇ = v (q̇ = J⁻¹ v): the "
            "transpose is not the inverse."
        ))]),
        alternatives("argument_ignored", [(lambda x: _solved_velocity(x, jacobian=_jacobian(Q_LIFT)), (
            "{name} ignores its argument jacobian and uses the Jacobian at "
            "q = [0°, 60°, −120°] (your J_lift?) whatever it is given."
        ))]),
        dg.degrees_output(),
    ],
    noun="configurations and foot velocities",
    arguments=_joint_velocity_arguments,
    signature="joint_velocity(v, jacobian) -> (3,) array",
    atol=1e-9,
    doc=("Check a function joint_velocity(v, jacobian) -> q̇ (3,), the joint velocity (rad/s) "
         "that gives the foot the velocity v (m/s) where its Jacobian is jacobian: compared "
         "with the model's Jacobian at 20 random regular configurations and foot velocities."),
))


# ------------------------------------------------------------------ inverse kinematics
def _box(name: str, low: float, high: float) -> Variable:
    return Variable(name, "length", low, high)


_GOAL = [_box("x_goal", -1.0, 1.0), _box("y_goal", 0.0, 2.0), _box("z_goal", -2.5, -1.0)]


def _newton(x, sign=1.0, use_transpose=False, delta_only=False):
    q, goal = x[:3], x[3:]
    J = _jacobian(q)
    step = (J.T if use_transpose else np.linalg.pinv(J)) @ (goal - _position(q))
    return sign * step if delta_only else q + sign * step


newton_step = exercise(_CHAPTER, "newton_step", Check(
    name="newton_step",
    reference=_newton,
    variables=[*_Q_REGULAR, *_GOAL],
    groups=[("q", [0, 1, 2]), ("r_goal", [3, 4, 5])],
    diagnoses=[
        alternatives("error_sign", [(
            lambda x: _newton(x, sign=-1.0),
            "{name} steps away from the goal: the error is r_goal − r(q), not r(q) − r_goal.",
        )]),
        alternatives("delta_only", [(
            lambda x: _newton(x, delta_only=True),
            "{name} returns only the step Δq = J⁺(r_goal − r(q)); return the new "
            "configuration q + Δq.",
        )]),
        alternatives("jacobian_transpose", [(
            lambda x: _newton(x, use_transpose=True),
            "{name} uses Jᵀ (a gradient step); Newton's method uses the pseudoinverse J⁺.",
        )]),
        dg.degrees(),
    ],
    noun="configurations and goals",
    doc=("Check a function step(q, r_goal) -> the next configuration of Newton's method (3,), "
         "compared with the reference at 20 random configurations and goals."),
))


def _joint_angles(q: object, name: str) -> tuple[np.ndarray | None, str | None, str]:
    """``q`` as 3 finite joint angles, or ``(None, code, message)`` saying what is wrong with it."""
    try:
        if np.asarray(q).dtype.kind == "c":
            raise TypeError
        qa = np.array(q, dtype=float).ravel()
    except (TypeError, ValueError):
        return None, "error", f"{name} must be 3 numbers (radians); got {type(q).__name__}."
    if qa.shape != (3,):
        return None, "shape", f"{name} must be 3 joint angles; got {qa.size} numbers."
    if not np.all(np.isfinite(qa)):
        return None, "error", f"{name} contains NaN or infinite values."
    return qa, None, ""


def ik_solution(
    q: object, goal: object = None, *, tol: float = 1e-3, name: str = "q_goal",
    raise_on_fail: bool = False, quiet: bool = False,
) -> CheckResult:
    """Check a solution of the inverse kinematics: ``r_BF(q)`` must reach ``goal``.

    Any solution is accepted: ``q`` is compared with the goal by the model's
    forward kinematics.

    Parameters
    ----------
    q : array_like, shape (3,)
        Joint angles (α, β, γ) in rad.
    goal : array_like, shape (3,), optional
        Foot position in the base frame, m (default :data:`R_GOAL`).
    tol : float, optional
        Allowed foot-position error, m.
    name : str, optional
        The answer's name in the messages (default ``"q_goal"``), e.g. ``"found[0]"``.
    raise_on_fail, quiet : bool, optional
        Raise ``AssertionError`` on failure; print nothing.

    Returns
    -------
    CheckResult
    """
    if not isinstance(name, str):
        raise TypeError(f"name must be a str; got {type(name).__name__}")
    goal = R_GOAL if goal is None else as_vector(goal, 3, "goal")
    tol = check_positive(tol, "tol", scalar=True)
    qa, code, msg = _joint_angles(q, name)
    if qa is not None:
        miss = float(np.linalg.norm(_position(qa) - goal))
        if miss <= tol:
            text = f"{PASS} {name} is correct: r_BF(q) reaches {fmt(goal)} (within {fmt(tol, 6)} m)."
            result = CheckResult(name, True, text, None, 1)
            if not quiet:
                show(text)
            return result
        if np.linalg.norm(_position(np.deg2rad(qa)) - goal) <= tol:
            code, msg = "degrees_output", (
                f"{name} is in degrees: np.deg2rad({name}) solves the problem. robokin "
                "works in radians."
            )
        else:
            code, msg = "mismatch", (
                f"{name} does not reach the goal: r_BF(q) = {fmt(_position(qa))}, "
                f"{fmt(miss)} m away from {fmt(goal)}."
            )
    return report(CheckResult(name, False, f"{FAIL} {msg}", code, 1), raise_on_fail=raise_on_fail, quiet=quiet)


# ------------------------------------------------------------------ tracking control
_RDES = [_box("x_des", -1.0, 1.0), _box("y_des", 0.0, 2.0), _box("z_des", -2.5, -1.0)]
_VDES = [Variable(f"{c}_dot_des", "other", -1.0, 1.0) for c in "xyz"]


def _control(x, kp=KP, feedforward=True, error_sign=1.0, gain_on_ff=False, transpose=False):
    q, r_des, v_des = x[:3], x[3:6], x[6:9]
    J = _jacobian(q)
    e = error_sign * (r_des - _position(q))
    v = (kp * (v_des + e) if gain_on_ff else (v_des if feedforward else 0.0) + kp * e)
    return (J.T if transpose else np.linalg.pinv(J)) @ v


tracking_controller = exercise(_CHAPTER, "tracking_controller", Check(
    name="controller",
    reference=_control,
    variables=[*_Q_REGULAR, *_RDES, *_VDES],
    groups=[("q", [0, 1, 2]), ("r_des", [3, 4, 5]), ("v_des", [6, 7, 8])],
    diagnoses=[
        alternatives("no_feedforward", [(
            lambda x: _control(x, feedforward=False),
            "{name} is the pure proportional law q̇ = J⁺ Kp (r_des − r): it works, but lags "
            "behind a moving target. Add the feed-forward velocity: q̇ = J⁺(ṙ_des + Kp (r_des − r)).",
        )]),
        alternatives("error_sign", [(
            lambda x: _control(x, error_sign=-1.0),
            "{name} feeds back r − r_des: the error must be r_des − r, otherwise the loop "
            "pushes the foot away.",
        )]),
        alternatives("gain_on_feedforward", [(
            lambda x: _control(x, gain_on_ff=True),
            "{name} multiplies the feed-forward velocity by Kp too: q̇ = J⁺(ṙ_des + Kp (r_des − r)).",
        )]),
        alternatives("jacobian_transpose", [(
            lambda x: _control(x, transpose=True),
            "{name} uses Jᵀ; resolved-rate control inverts the Jacobian: J⁺.",
        )]),
        dg.degrees(),
        dg.scale(),
    ],
    noun="configurations",
    doc=(
        "Check a function controller(q, r_des, v_des) -> q̇ = J⁺(q)(v_des + Kp (r_des − r(q))) "
        "with Kp = 10 /s."
    ),
))


# ------------------------------------------------------------------ the student's own loops
def _iterates(out: Any, name: str) -> np.ndarray:
    """The iterates a loop returned, as an array (K + 1, 3); a clear error otherwise."""
    if isinstance(out, tuple):
        raise TypeError(f"{name} should return one array of joint angles (K + 1, 3), not a tuple "
                        f"of {len(out)} items")
    Q = np.asarray(out, dtype=float)
    if Q.ndim != 2 or Q.shape[1] != 3 or len(Q) == 0:
        raise TypeError(f"{name} should return an array of shape (K + 1, 3), one row per "
                        f"iterate; got shape {Q.shape}")
    return Q


# -- Newton's method (task 4)
#: a step of the student's loop equals the reference step within these tolerances
_STEP_ATOL, _STEP_RTOL = 1e-7, 1e-6


def _newton_step(q, r_goal, damping, *, sign=1.0, transpose=False, damping_power=2) -> np.ndarray:
    """The step Δq of Newton's method at ``q`` (damped least squares when ``damping`` > 0) or,
    with the keywords, of one of its typical mistakes."""
    e = sign * (r_goal - _position(q))
    J = _jacobian(q)
    if transpose:
        return J.T @ e
    if damping == 0.0:
        return np.linalg.pinv(J) @ e
    return J.T @ np.linalg.solve(J @ J.T + damping**damping_power * np.eye(3), e)


_Q_START = [
    _angle("alpha", 1, -1.0, 1.0), _angle("beta", 2, -1.0, 1.0), _angle("gamma", 3, 0.5, 2.4)
]
_DQ_GOAL = [Variable(f"dq_{k}", "other", -0.25, 0.25) for k in (1, 2, 3)]
_NEWTON_MORE = [
    Variable("damping_choice", "other", 0.0, 0.3),
    Variable("max_iterations", "other", 1.0, 8.999),
    Variable("tol_exponent", "other", 4.0, 10.0),
]


def _newton_args(x: np.ndarray) -> tuple:
    """``(r_goal, q0, damping, tol, max_iterations)`` from a sample: a goal the leg reaches
    near the start; no damping for half the samples, else λ in [0.05, 0.2] m."""
    q0 = np.array(x[:3])
    r_goal = _position(q0 + x[3:6])
    damping = 0.0 if x[6] < 0.15 else float(x[6] - 0.1)
    return r_goal, q0, damping, 10.0 ** -x[8], int(x[7])


def _describe_newton(x: np.ndarray) -> str:
    """The call of the student's Newton loop at the sample ``x``, as a failure's example writes it."""
    r_goal, q0, damping, tol, budget = _newton_args(x)
    return (f"Q = newton_ik(r_goal = {fmt(r_goal)} m, q0 = {fmt(q0)} rad, damping = {damping:.3g} m, "
            f"tol = {tol:.1e} m, max_iterations = {budget})")


#: the steps of typical mistakes: (code, keywords of :func:`_newton_step`, message)
_STEP_MISTAKES: list[tuple[str, dict[str, Any], str]] = [
    ("error_sign", {"sign": -1.0},
     "{name} steps away from the goal: the error is e = r_goal − r(q) (goal minus current); the "
     "step J⁺e then moves the foot towards the goal."),
    ("damping_not_squared", {"damping_power": 1},
     "{name} adds λ·I where λ²·I belongs: the damped step is Jᵀ(J Jᵀ + λ² I)⁻¹ e (λ in m, λ² in m² "
     "like J Jᵀ)."),
    ("jacobian_transpose", {"transpose": True},
     "{name} uses Jᵀ e (a gradient step); Newton's method uses J⁺ e."),
]


def _same_step(got: np.ndarray, want: np.ndarray) -> bool:
    return bool(np.allclose(got, want, atol=_STEP_ATOL, rtol=_STEP_RTOL))


def _newton_verdict(Q: np.ndarray, x: np.ndarray) -> tuple[str, str] | None:
    """What is wrong with the iterates ``Q`` the student's loop returned at the sample ``x``:
    ``(code, message)`` (``{name}`` for the check's name), or None when they are right.

    Right means: row 0 is q0; every row is the previous one plus the Newton (or damped) step
    computed there; at most max_iterations steps; the last iterate within tol of the goal
    unless the budget is spent; and no step once the iteration has converged: at an iterate
    within tol that a step below tol led to (a test on the error stops there or earlier, one
    on the step size there). Either stop test is a correct answer.
    """
    r_goal, q0, damping, tol, budget = _newton_args(x)
    call = _describe_newton(x)
    if not np.all(np.isfinite(Q)):
        return "error", f"{{name}} returns NaN or infinite joint angles in {call}."
    if not np.allclose(Q[0], q0, atol=1e-9):
        if _same_step(Q[0] - q0, _newton_step(q0, r_goal, damping)):
            return "no_start_row", (
                "{name} leaves out the start: the iterates begin with q^0 = q0, so that row k of the "
                "log is iterate k (K steps give K + 1 rows).")
        return "start", (f"{{name}} does not start at q0: in {call}, row 0 is {fmt(Q[0])} rad. Row k of "
                         "the iterates is iterate k, and iterate 0 is the start q0.")
    steps = len(Q) - 1
    if steps > budget:
        return "budget", (f"{{name}} takes {steps} steps in {call}: at most max_iterations = {budget}, "
                          "the budget it is given.")
    for k in range(steps):
        got, want = Q[k + 1] - Q[k], _newton_step(Q[k], r_goal, damping)
        if _same_step(got, want):
            continue
        for code, keywords, text in _STEP_MISTAKES:
            if (code != "damping_not_squared" or damping > 0) and _same_step(
                    got, _newton_step(Q[k], r_goal, damping, **keywords)):
                return code, text
        return "mismatch", (
            f"{{name}} is not correct: in {call}, the step from Q[{k}] to Q[{k + 1}] is {fmt(got)} rad, "
            f"but the {'damped ' if damping > 0 else ''}Newton step at Q[{k}] is {fmt(want)} rad "
            "(rows before it are right). Each row must be the previous iterate plus the step "
            "computed at that iterate, with the error and the Jacobian of that iterate.")
    errors = np.linalg.norm(r_goal - _leg().fk(Q)[:, :3, 3], axis=1)
    moved = np.r_[np.inf, np.linalg.norm(np.diff(Q, axis=0), axis=1)]  # the step into each row
    if steps < budget and errors[-1] > tol:
        small = moved[-1] <= tol or np.linalg.norm(_newton_step(Q[-1], r_goal, damping)) <= tol
        why = (" Its step ‖Δq‖ there is below tol, but a small step is not a small error: tol is "
               "the accuracy asked of the foot (m), and the error decides." if small else
               " One step more was allowed: max_iterations counts the steps, and K steps give K + 1 "
               "rows." if steps == budget - 1 else "")
        return "stops_short", (
            f"{{name}} stops before the foot is within tol of the goal: in {call} it ends after "
            f"{steps} of its {budget} steps with ‖r_goal − r(q^K)‖ = {errors[-1]:.1e} m > tol.{why}")
    # converged: within tol, and the step into it below tol too (a stop test on the step size
    # needs that step, even from a start on the goal)
    done = np.flatnonzero((errors <= tol) & (moved <= tol))
    if len(done) and steps > done[0]:
        first = int(np.argmax(errors <= tol))
        return "no_early_stop", (
            f"{{name}} goes on after it has converged: in {call}, iterate {first} is within tol of "
            f"the goal (‖e‖ = {errors[first]:.1e} m), yet the loop goes on to iterate {steps}. Stop as "
            "soon as the foot is within tol of the goal, before computing another step.")
    return None


class _NewtonLoopCheck(FunctionCheck):
    """``newton_ik(r_goal, q0, damping, tol, max_iterations) -> (K + 1, 3)``: judged step by step
    (see :func:`_newton_verdict`), so that any correct stop test keeps full marks."""

    def judge(self, answer: Any) -> CheckResult:
        X = self.sample_points()
        n = len(X)
        for x in X:
            r_goal, q0, damping, tol, budget = _newton_args(x)
            out = self.call(answer, (r_goal.copy(), q0.copy(), damping, tol, budget),
                            f"in {_describe_newton(x)}", n)
            try:
                Q = _iterates(out, "newton_ik")
            except TypeError as exc:
                return self.failure("error", f"{self.name}: {exc}.", n)
            verdict = _newton_verdict(Q, x)
            if verdict is not None:
                code, text = verdict
                return self.failure(code, text.format(name=self.name), n)
        return self.success(f"{self.name} is correct (checked at {n} random {self.noun}).", n)


newton_ik = exercise(_CHAPTER, "newton_ik", _NewtonLoopCheck(
    name="newton_ik(r_goal, q0, damping, tol, max_iterations)",
    variables=[*_Q_START, *_DQ_GOAL, *_NEWTON_MORE],
    noun="starts, goals, dampings and iteration budgets",
    signature="newton_ik(r_goal, q0, damping, tol, max_iterations) -> iterates (K + 1, 3)",
    doc=("Check a Newton iteration newton_ik(r_goal, q0, damping, tol, max_iterations) that "
         "returns its iterates q^0 ... q^K, shape (K + 1, 3): each iterate the step of "
         "Newton's method (damped least squares when damping > 0) from the one before, at most "
         "max_iterations steps, and the last within tol of the goal unless they are spent. A stop "
         "test on the error or on the step size is fine."),
))


# -- the resolved-rate tracking loop (task 5)
_TRACK_SAMPLES = 8


def _track_loop(q0, r_des, v_des, kp, ts, feedforward, *, sign=1.0, ff=None,
                record_after=False, gain_on_ff=False) -> np.ndarray:
    """The reference Euler loop (and, with the keywords, its typical mistakes): the joint
    angles at the samples, shape (N, 3), row 0 = q0."""
    use_ff = feedforward if ff is None else ff
    q = np.array(q0, dtype=float)
    Q = []
    for r_d, v_d in zip(r_des, v_des):
        if not record_after:
            Q.append(q.copy())
        e = sign * (r_d - _position(q))
        v = kp * (v_d + e) if (gain_on_ff and use_ff) else (v_d if use_ff else 0.0) + kp * e
        q = q + ts * (np.linalg.pinv(_jacobian(q)) @ v)
        if record_after:
            Q.append(q.copy())
    return np.array(Q)


def _track_args(x: np.ndarray) -> tuple:
    """``(q0, r_des, v_des, kp, ts, feedforward)``: a reference line that starts near the
    foot, sampled at N = 8 instants."""
    q0 = np.array(x[:3])
    ts, kp, feedforward = float(x[10]), float(x[9]), bool(x[11] > 0.5)
    k = np.arange(_TRACK_SAMPLES)[:, None]
    v_des = np.tile(x[6:9], (_TRACK_SAMPLES, 1))
    r_des = _position(q0) + x[3:6] + k * ts * v_des
    return q0, r_des, v_des, kp, ts, feedforward


_pack_track = pack_joint_rows("track", _TRACK_SAMPLES, 3)
_track_variant = packed_variants(_track_loop, _track_args, _pack_track)


def _describe_track(x: np.ndarray) -> str:
    """The call of the student's tracking loop at the sample ``x``, as a failure's example writes it."""
    q0, r_des, v_des, kp, ts, feedforward = _track_args(x)
    return (f"Q = track(q0 = {fmt(q0)} rad, r_des = {len(r_des)} points of a line from "
            f"{fmt(r_des[0])} m, v_des = {fmt(v_des[0])} m/s at each, kp = {kp:.3g}, ts = {ts:.3g}, "
            f"feedforward = {feedforward})")


def _track_entry(idx: tuple[int, ...]) -> str:
    """What entry ``idx`` of the flattened joint angles ``Q`` (N, 3) is."""
    row, column = divmod(idx[0], 3)
    return f"Q[{row}, {column}]"


tracking_loop = exercise(_CHAPTER, "tracking_loop", MatrixArgumentsCheck(
    name="track(q0, r_des, v_des, kp, ts, feedforward)",
    reference=_track_variant(),
    variables=[
        *_Q_REGULAR,
        *[Variable(f"offset_{c}", "other", -0.1, 0.1) for c in "xyz"],
        *[Variable(f"v_{c}", "other", -0.5, 0.5) for c in "xyz"],
        Variable("kp", "other", 2.0, 20.0),
        Variable("ts", "other", 0.005, 0.04),
        Variable("feedforward_choice", "other", 0.0, 1.0),
    ],
    diagnoses=[
        alternatives("no_feedforward", [(_track_variant(ff=False), (
            "{name} never adds the feed-forward velocity: with feedforward=True the "
            "command is q̇ = J⁺(ṙ_des + Kp (r_des − r))."
        ))]),
        alternatives("always_feedforward", [(_track_variant(ff=True), (
            "{name} adds the feed-forward velocity also with feedforward=False: the P-only "
            "command is q̇ = J⁺ Kp (r_des − r)."
        ))]),
        alternatives("error_sign", [(_track_variant(sign=-1.0), (
            "{name} feeds back r − r_des: the error must be r_des − r, otherwise the loop "
            "pushes the foot away."
        ))]),
        alternatives("recorded_after_step", [(_track_variant(record_after=True), (
            "{name} records q after the Euler step: row k must be the configuration at "
            "sample k, the one the command of sample k is computed from (row 0 = q0)."
        ))]),
        alternatives("gain_on_feedforward", [(_track_variant(gain_on_ff=True), (
            "{name} multiplies the feed-forward velocity by Kp too: q̇ = J⁺(ṙ_des + Kp "
            "(r_des − r))."
        ))]),
    ],
    noun="starts, references, gains and time steps",
    arguments=_track_args,
    describe=_describe_track,
    entry_label=_track_entry,
    signature="track(q0, r_des, v_des, kp, ts, feedforward) -> joint angles (N, 3)",
    hint=("Row k must be the joint angles at sample k (row 0 = q0), and row k + 1 one Euler step "
          "of ts from row k with the resolved-rate command of Task 5 computed at row k from r_des[k] "
          "and v_des[k] (v_des[k] left out when feedforward is False): the first row that differs "
          "is the step to look at."),
    atol=1e-7,
    doc=("Check a resolved-rate tracking loop track(q0, r_des, v_des, kp, ts, feedforward) "
         "that returns the joint angles at the samples, shape (N, 3), row 0 = q0."),
    pack=_pack_track,
))


# -- all solutions in closed form (task 4)
def _closed_form(p, branches=(1.0, -1.0), knees=(1.0, -1.0)) -> np.ndarray:
    """All solutions of r_BF(q) = p, wrapped to (-π, π], from the leg's geometry (the
    reference of :data:`ik_closed_form`; ``branches``/``knees`` leave some out)."""
    d = np.asarray(p, dtype=float) - _P_B1()
    rho = math.hypot(d[1], d[2])
    out = []
    for branch in branches:  # foot below (+1) or above (-1) the hip's x axis
        a = math.atan2(branch * d[1], -branch * d[2])
        u, w = d[0], 1.0 - branch * rho
        c = (u * u + w * w - 2.0) / 2.0
        if abs(c) > 1.0:
            continue
        for knee in knees:
            g = knee * math.acos(c)
            b = math.atan2(-u, -w) - g / 2.0
            out.append(np.angle(np.exp(1j * np.array([a, b, g]))))
    return np.array(out).reshape(-1, 3)


_CLOSED_GOALS = [
    _box("x_goal", -1.6, 1.6), _box("y_goal", -0.2, 2.2), _box("z_goal", -2.6, 1.0),
]


def _same_set(A: np.ndarray, B: np.ndarray, atol: float = 1e-7) -> bool:
    """Equal as sets of configurations, angles modulo 2π, each once."""
    if A.shape != B.shape:
        return False
    unused = list(range(len(B)))
    for a in A:
        hit = [j for j in unused if np.allclose(np.angle(np.exp(1j * (a - B[j]))), 0.0, atol=atol)]
        if not hit:
            return False
        unused.remove(hit[0])
    return True


_CLOSED_FORM_MISTAKES = {
    "one_branch": (lambda x: _closed_form(x, branches=(1.0,)),
                   "{name} misses the solutions with the foot above the hip's x axis (α + π, the "
                   "leg swung over the top): where that branch is in reach, a goal has 4 solutions."),
    "one_knee": (lambda x: _closed_form(x, knees=(1.0,)),
                 "{name} returns one knee per leg plane: the planar arm of β and γ reaches a "
                 "point with the knee bent either way (±γ)."),
}


class _SolutionSetCheck(FunctionCheck):
    """``ik_closed_form(p) -> (m, 3)``: every solution, each once, in any order."""

    def judge(self, answer: Any) -> CheckResult:
        X = self.sample_points()
        name, n = self.name, len(X)
        got = []
        for x in X:
            S = np.asarray(self.call(answer, (np.array(x, dtype=float),), f"at p = {fmt(x)}", n), dtype=float)
            if S.size == 0:
                S = S.reshape(0, 3)
            if S.ndim != 2 or S.shape[1] != 3:
                return self.failure("shape", f"{name} should return an array (m, 3), one solution per "
                                    f"row (m may be 0); got shape {S.shape} at p = {fmt(x)}.", n)
            got.append(S)
        refs = [_closed_form(x) for x in X]
        if all(_same_set(S, R) for S, R in zip(got, refs)):
            return self.success(f"{name} is correct (checked at {n} random goals, with 0, 2 and 4 "
                                "solutions).", n)
        if all(_same_set(np.deg2rad(S), R) for S, R in zip(got, refs)):
            return self.failure("degrees_output", f"{name} returns degrees: np.deg2rad of it solves the "
                                "problem. robokin works in radians.", n)
        named = self.diagnose(((code, text) for code, (_, text) in _CLOSED_FORM_MISTAKES.items()),
                              lambda code: all(_same_set(S, _closed_form_of(code, x)) for S, x in zip(got, X)), n)
        if named is not None:
            return named
        k = next(i for i, (S, R) in enumerate(zip(got, refs)) if not _same_set(S, R))
        # how many of its rows reach the goal: the student can check that too (no solution shown)
        reach = sum(bool(np.all(np.isfinite(q))) and np.linalg.norm(_leg().fk(q)[:3, 3] - X[k]) < 1e-7
                    for q in got[k])
        return self.failure("mismatch", (
            f"{name} is not correct: at p = {fmt(X[k])} it returns {len(got[k])} solution(s), "
            f"{reach} of them reaching the goal (r_BF(q) = p), and the goal has {len(refs[k])}, "
            "each once. Check every row with the forward kinematics, and count the ways the leg "
            "can reach a point: where α can put the leg plane, and how the knee can bend."), n)


def _closed_form_of(code: str, x: np.ndarray) -> np.ndarray:
    """The solutions (m, 3) that the mistake ``code`` of :data:`_CLOSED_FORM_MISTAKES` gives at ``x``."""
    return np.asarray(_CLOSED_FORM_MISTAKES[code][0](x), dtype=float).reshape(-1, 3)


ik_closed_form = exercise(_CHAPTER, "ik_closed_form", _SolutionSetCheck(
    name="ik_closed_form",
    signature="ik_closed_form(p) -> (m, 3) array",
    variables=_CLOSED_GOALS,
    samples=40,
    noun="goals",
    doc=("Check a function ik_closed_form(p) -> (m, 3) that returns every solution of "
         "r_BF(q) = p, each once (angles compared modulo 2π)."),
))
