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
``foot_jacobian``          J(q) = ∂r_BF/∂q: 3×3                                 q
``foot_jacobian_at``       J at q = [0°, 60°, −120°]: numbers                   --
``lift_velocity``          q̇ = J⁺ v at that q, v = [0, 0, −1] m/s: numbers     --
``newton_step``            function (q, r_goal) -> q + J⁺ (r_goal − r(q))       q, r_goal
``ik_solution(q)``         q with r_BF(q) = [0.2, 0.5, −2] (any solution)       --
``tracking_controller``    function (q, r_des, v_des) -> q̇ = J⁺(v_des + Kp e)  q, r_des, v_des
=========================  ==================================================  =================

Symbolic answers may use the symbols ``alpha, beta, gamma`` (any assumptions)
or ``q1, q2, q3``; functions may take the angles one by one or a vector ``q``.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import PASS, FAIL, Check, CheckResult, Variable, alternatives, fmt, report, show
from robokin.check._registry import exercise
from robokin.validation import as_vector, check_positive

__all__ = [
    "rotation_B1", "rotation_12", "rotation_23",
    "transform_B1", "transform_12", "transform_23", "transform_3F", "transform_BF",
    "foot_position", "foot_jacobian", "foot_jacobian_at", "lift_velocity",
    "newton_step", "ik_solution", "tracking_controller",
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
    name="J_BF(q)",
    reference=_jacobian,
    variables=Q,
    groups=_QGROUP,
    diagnoses=dg.standard("jacobian"),
    noun="configurations",
    doc="Check the foot-point Jacobian J(α, β, γ) = ∂ r_BF / ∂q (3×3).",
))

_AT_LIFT = "q = [0°, 60°, −120°]"

foot_jacobian_at = exercise(_CHAPTER, "foot_jacobian_at", Check(
    name="J_BF",
    reference=_jacobian,
    variables=Q,
    at=Q_LIFT,
    at_text=_AT_LIFT,
    atol=1e-3,
    rtol=1e-3,
    diagnoses=dg.standard("jacobian"),
    doc="Check the numbers of the foot Jacobian at q = [0°, 60°, −120°].",
))


def _lift(x, v=V_LIFT):
    return np.linalg.pinv(_jacobian(x)) @ v


lift_velocity = exercise(_CHAPTER, "lift_velocity", Check(
    name="q̇",
    reference=_lift,
    variables=Q,
    at=Q_LIFT,
    at_text=f"{_AT_LIFT} for v = [0, 0, −1] m/s",
    atol=1e-3,
    rtol=1e-3,
    diagnoses=[
        alternatives("velocity_sign", [(
            lambda x: _lift(x, -V_LIFT),
            "{name} moves the foot with v = [0, 0, +1] m/s (upwards: z of B points up), "
            "not with the exercise's v = [0, 0, −1] m/s.",
        )]),
        alternatives("transpose", [(
            lambda x: _jacobian(x).T @ V_LIFT,
            "{name} uses Jᵀ v; the joint velocity is J⁻¹ v (J⁺ v): the transpose is not "
            "the inverse.",
        )]),
        *dg.standard("angles"),
    ],
    doc="Check the joint velocity q̇ = J⁺ v at q = [0°, 60°, −120°], v = [0, 0, −1] m/s.",
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
    doc="Check a function step(q, r_goal) -> q + J⁺(q)(r_goal − r(q)).",
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
    q: object, goal: object = None, *, tol: float = 1e-3, raise_on_fail: bool = False,
    quiet: bool = False,
) -> CheckResult:
    """Check a solution of the inverse kinematics: ``r_BF(q)`` must reach ``goal``.

    Any solution is accepted (the goal of task 4 has two).

    Parameters
    ----------
    q : array_like, shape (3,)
        Joint angles (α, β, γ) in rad.
    goal : array_like, shape (3,), optional
        Foot position in the base frame, m (default :data:`R_GOAL`).
    tol : float, optional
        Allowed foot-position error, m.
    raise_on_fail, quiet : bool, optional
        Raise ``AssertionError`` on failure; print nothing.

    Returns
    -------
    CheckResult
    """
    name = "q_goal"
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
