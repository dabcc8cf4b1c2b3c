r"""Exercise checks of chapter 4: Cartesian control of a tool frame.

Each check compares the student's answer with robokin's own model of the
exercise: the course's arm, :func:`robokin.models.genova_arm` (7 joints, joint 6
prismatic), with the exercise's tool and goal. Orientations are given as the
course writes them, **YPR triples** (yaw, pitch, roll); which rotation a triple
stands for is part of the exercise. Twists and errors stack the linear part
first, ``[v; ω]``, in the base frame (the course writes ``[ω; v]``).

=======================  ==========================================================  ==========================================
check                    the student's answer                                        compared
=======================  ==========================================================  ==========================================
``tool_frame``           the 4×4 array :math:`{}^{E}\mathbf{T}_{T}`                     with the model's tool frame, to 1e-4
``goal_frame``           the 4×4 array :math:`{}^{B}\mathbf{T}_{G}`                     with the model's goal frame, to 1e-4
``tool_pose``            ``f(q)`` -> :math:`{}^{B}\mathbf{T}_{T}` (4×4)                  at 20 random configurations
``orientation_error``    ``f(R, R_goal)`` -> :math:`\theta\mathbf{h}` (3,), base frame    at 20 random pairs of rotations
``tool_jacobian``        ``f(J_e, R_be, p_et)`` -> :math:`\mathbf{J}_T` (6×n)              at 20 random configurations and offsets
``tool_jacobian_of_q``   ``f(q, offset)`` -> :math:`\mathbf{J}_T(\mathbf{q})` (6×7)      at 20 random configurations and offsets
``control_law``          ``f(J, e, gain_linear, gain_angular)`` -> :math:`\dot{\mathbf{q}}`    at 20 random configurations, errors, gains
``kinematic_loop``       ``f(twist_of, q0, ts, t_end, robot)`` -> ``(Q, V)``         on P laws to 20 random goals near the start
``rpy_rate_matrix``      ``f(R)`` -> :math:`\mathbf{E}(\boldsymbol\phi)` (3×3)       at 20 random rotations
=======================  ==========================================================  ==========================================

Inputs: configurations of the course's arm drawn within its limits (the
slide ``q6`` in metres); rotations from random roll–pitch–yaw angles;
orientation errors of up to 2.7 rad (below π, where the axis of the
angle–axis error is unique); gains in [0.2, 2] /s. The random inputs are
seeded (the same on every run); the functions are compared to an absolute
tolerance of 1e-8 (1e-7 for ``orientation_error`` and ``control_law``) and a
relative one of 1e-6. A wrong answer is explained in the terms of the
exercise when a known mistake reproduces it (a triple read in the wrong order,
a wrong unit, a wrong sign or frame, angles in degrees, and so on).

Usage::

    from robokin.check import cartesian
    cartesian.tool_frame(T_ET)
    cartesian.orientation_error(my_orientation_error)
"""
from __future__ import annotations

import math
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np

from robokin.check._core import (
    Check, Diagnosis, MatrixArgumentsCheck, Variable, alternatives, fmt,
)
from robokin.check._registry import exercise
from robokin.check.diagnoses import inverse_transform, transform_mistakes
from robokin.transforms import (
    quaternion_from_rotation,
    rotation_exp,
    rotation_from_rpy,
    rotation_log,
    rotx,
    roty,
    rotz,
    rpy_from_rotation,
    skew,
    transform,
)

__all__ = [
    "N_JOINTS",
    "control_law",
    "goal_frame",
    "kinematic_loop",
    "orientation_error",
    "reference_goal",
    "reference_orientation_error",
    "reference_rpy_difference",
    "reference_tool_arm",
    "rpy_rate_matrix",
    "tool_frame",
    "tool_jacobian",
    "tool_jacobian_of_q",
    "tool_pose",
]

_CHAPTER = "cartesian"

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back (an orientation_error that calls rotation_log) is flagged for
#: review by hand (tools/grading/bridge/delegation.py reads this literal table without importing it)
DELEGATION = {
    "kinematic_loop": {"simulate": "robokin.motion.simulate",
                       "CartesianController": "robokin.motion.CartesianController"},
    "orientation_error": {"rotation_log": "robokin.transforms.rotation_log",
                          "pose_error": "robokin.motion.pose_error",
                          "angle_axis_from_rotation": "robokin.transforms.angle_axis_from_rotation",
                          "reference_orientation_error":
                              "robokin.check.cartesian.reference_orientation_error"},
    "tool_frame": {"reference_tool_arm": "robokin.check.cartesian.reference_tool_arm"},
    "goal_frame": {"reference_goal": "robokin.check.cartesian.reference_goal"},
}
#: Number of joints of the course's arm.
N_JOINTS = 7
# The tool's orientation as the course writes it, (yaw, pitch, roll) in rad, and its offset
# in metres (frame E); the goal's orientation and its origin in metres (frame B). Private:
# the student reads them from the sheet in a task, so help() of this module does not list them.
_TOOL_YPR = (0.0, 0.0, math.pi / 10)
_TOOL_OFFSET = (0.2, 0.0, 0.0)
_GOAL_YPR = (-3.02, -0.40, -1.33)
_GOAL_POSITION = (-0.14, -0.85, 0.6)


@lru_cache(maxsize=1)
def _robot():
    from robokin.models.genova_arm import genova_arm

    return genova_arm()


def _transform(R: np.ndarray, p: Any) -> np.ndarray:
    """The 4×4 transform [[R, p], [0, 1]] (R a rotation by construction, not checked)."""
    return transform(R, p, check=False)


def _ypr(yaw: float, pitch: float, roll: float) -> np.ndarray:
    """The course's YPR rotation Rz(yaw) Ry(pitch) Rx(roll)."""
    return rotz(yaw) @ roty(pitch) @ rotx(roll)


def _T_ET() -> np.ndarray:
    return _transform(_ypr(*_TOOL_YPR), _TOOL_OFFSET)


def _T_BG() -> np.ndarray:
    return _transform(_ypr(*_GOAL_YPR), _GOAL_POSITION)


def _joint_variables() -> list[Variable]:
    from robokin.models.genova_arm import GENOVA_ARM_JOINT_TYPES, GENOVA_ARM_LIMITS

    out = []
    for i, ((lo, hi), kind) in enumerate(zip(GENOVA_ARM_LIMITS, GENOVA_ARM_JOINT_TYPES)):
        margin = 0.05 * (hi - lo) if kind == "P" else 0.05
        out.append(Variable(f"q{i + 1}", "length" if kind == "P" else "angle", lo + margin, hi - margin))
    return out


_Q = _joint_variables()


# ------------------------------------------------------------------ tool frame (a constant)
_SWAPPED_TOOL = (
    "{name} reads the triple η = [0, 0, π/10] as (roll, pitch, yaw), so its last angle became "
    "a yaw. The course lists a YPR triple as (yaw, pitch, roll) (the Conventions table): "
    "reverse the list before you pass it to rotation_from_rpy(roll, pitch, yaw)."
)


def _tool_frame_mistakes():
    R, p = _ypr(*_TOOL_YPR), np.array(_TOOL_OFFSET)
    R_swapped = _ypr(*_TOOL_YPR[::-1])
    return [
        alternatives("offset_in_cm", [(lambda x: _transform(R, p / 100.0), (
            "the offset of {name} is 0.002 m: 0.2 was read as centimetres (look at your "
            "TOOL_OFFSET, the offset {name} is built from). The robot's link table and the goal "
            "are in metres (the goal is about 1 m from the base), and a 2 mm tool would barely "
            "leave the end-effector: ask whether the number makes sense in that unit."
        ))]),
        alternatives("rpy_order", [
            (lambda x: _transform(R_swapped, p), _SWAPPED_TOOL),
            (lambda x: _transform(R_swapped, p / 100.0), _SWAPPED_TOOL + " Also, its offset was read as "
                                                          "centimetres: the exercise is in metres."),
        ]),
        alternatives("degrees_input", [(lambda x: _transform(rotx(math.radians(math.pi / 10)), p), (
            "the rotation of {name} is π/10 DEGREES: pass radians (π/10 rad = 18°)."
        ))]),
        inverse_transform(),
        *transform_mistakes(),
    ]


tool_frame = exercise(_CHAPTER, "tool_frame", Check(
    name="T_ET",
    reference=lambda x: _T_ET(),
    diagnoses=_tool_frame_mistakes(),
    atol=1e-4, rtol=1e-4,
    values_shown=False,
    hint=("Its rotation block is the rotation of the YPR triple ᴱη_T, read as the course lists it "
          "(the Conventions table), the top of its last column the offset ₑr_ET in metres, and its "
          "last row [0, 0, 0, 1]."),
    doc=("Check the tool frame T_ET (4×4) built from the exercise's YPR triple and offset: "
         "compared with the model's tool frame to 1e-4."),
))


# ------------------------------------------------------------------ goal frame (a constant)
def _goal_frame_mistakes():
    p = np.array(_GOAL_POSITION)
    y, pi_, r = _GOAL_YPR
    return [
        alternatives("rpy_order", [(lambda x: _transform(_ypr(r, pi_, y), p), (
            "{name} reads η_G = (−3.02, −0.40, −1.33) as (roll, pitch, yaw): its first angle "
            "became the roll and its last the yaw. The course lists a YPR triple as (yaw, pitch, "
            "roll) (the Conventions table): reverse the list before you pass it to "
            "rotation_from_rpy(roll, pitch, yaw)."
        ))]),
        alternatives("composition_order", [
            (lambda x: _transform(rotx(r) @ roty(pi_) @ rotz(y), p), (
                "{name} multiplies the three rotations in the reverse order, Rx(roll) Ry(pitch) "
                "Rz(yaw). The angles are right, but the product is R = Rz(yaw) Ry(pitch) Rx(roll): "
                "turn about the fixed x axis first, then y, then z (or z, new y, newest x)."
            )),
            (lambda x: _transform(rotx(y) @ roty(pi_) @ rotz(r), p), (
                "{name} reverses both the order of the angles and the order of the product: the "
                "course's triple is (yaw, pitch, roll) and its rotation R = Rz(yaw) Ry(pitch) "
                "Rx(roll) (the Conventions table)."
            )),
        ]),
        alternatives("degrees_input", [(lambda x: _transform(_ypr(*np.radians(_GOAL_YPR)), p), (
            "the angles of {name} were taken as DEGREES: −3.02, −0.40, −1.33 are radians."
        ))]),
        inverse_transform(),
        *transform_mistakes(),
    ]


goal_frame = exercise(_CHAPTER, "goal_frame", Check(
    name="T_BG",
    reference=lambda x: _T_BG(),
    diagnoses=_goal_frame_mistakes(),
    atol=1e-4, rtol=1e-4,
    values_shown=False,
    hint=("Its rotation block is the rotation of the YPR triple ᴮη_G, read as the course lists it "
          "(the Conventions table), the top of its last column the goal's origin ᴮr_BG in metres, "
          "and its last row [0, 0, 0, 1]."),
    doc=("Check the goal frame T_BG (4×4) built from the exercise's YPR triple and origin: "
         "compared with the model's goal frame to 1e-4."),
))


# ------------------------------------------------------------------ tool pose f(q)
def _tool_pose_mistakes():
    T_et = _T_ET()

    def fk(x):
        return _robot().fk(np.asarray(x, dtype=float))

    return [
        alternatives("composition_order", [(lambda x: T_et @ fk(x), (
            "{name} multiplies in the wrong order: ᴱT_T ᴮT_E. Match the inner letters (the "
            "tool is attached after the end-effector)."
        ))]),
        alternatives("no_tool", [(fk, "{name} is the end-effector pose ᴮT_E: the tool transform ᴱT_T is missing.")]),
        alternatives("inverse_tool", [(lambda x: fk(x) @ np.linalg.inv(T_et), (
            "{name} uses the inverse tool transform ᵀT_E = (ᴱT_T)⁻¹: match the inner letters."
        ))]),
        alternatives("offset_not_rotated", [(lambda x: _transform(fk(x)[:3, :3] @ T_et[:3, :3],
                                                          fk(x)[:3, 3] + T_et[:3, 3]), (
            "the tool origin in {name} adds the offset ₑr_ET as if it were written in the base "
            "frame: it is written in E, so it must be rotated into B first."
        ))]),
    ]


tool_pose = exercise(_CHAPTER, "tool_pose", Check(
    name="tool_pose(q)",
    reference=lambda x: _robot().fk(np.asarray(x, dtype=float)) @ _T_ET(),
    variables=_Q,
    groups=[("q", list(range(N_JOINTS)))],
    diagnoses=_tool_pose_mistakes(),
    noun="configurations",
    hint="Compose the arm's end-effector pose with the tool's pose in E, matching the inner letters.",
    doc=("Check a function tool_pose(q) -> ᴮT_T(q) (4×4) of the course's arm with the exercise's "
         "tool: compared with the model at 20 random configurations within the joint limits."),
))


# ------------------------------------------------------------------ orientation error f(R, R_goal)
_ROT = [Variable(n, "angle", -math.pi, math.pi) for n in ("roll", "pitch", "yaw")]
_W = [Variable(f"w_{c}", "other", -1.55, 1.55) for c in "xyz"]   # |w| <= 2.69 rad < pi


def _orientation_error_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    R = rotation_from_rpy(*x[:3])
    return R, rotation_exp(x[3:6]) @ R


def _orientation_error_reference(x: np.ndarray) -> np.ndarray:
    R, Rg = _orientation_error_arguments(x)
    return rotation_log(Rg @ R.T, check=False)


def _orientation_error_mistakes():
    def tool_frame_err(x):
        R, Rg = _orientation_error_arguments(x)
        return rotation_log(R.T @ Rg, check=False)

    def tool_frame_other(x):
        R, Rg = _orientation_error_arguments(x)
        return rotation_log(Rg.T @ R, check=False)

    def rpy_diff(x):
        R, Rg = _orientation_error_arguments(x)
        d = np.asarray(rpy_from_rotation(Rg)) - np.asarray(rpy_from_rotation(R))
        return np.pi - np.mod(np.pi - d, 2 * np.pi)

    def quat_vec(x):
        R, Rg = _orientation_error_arguments(x)
        qe = np.asarray(quaternion_from_rotation(Rg @ R.T))
        return qe[1:] * (1.0 if qe[0] >= 0 else -1.0)

    return [
        alternatives("sign", [(lambda x: -_orientation_error_reference(x), (
            "{name} has the wrong sign: it is the rotation from the goal back to the current "
            "frame. The error is the rotation still to do, from R to R_goal, so that "
            "ω = K θh turns the tool TOWARDS the goal (with the opposite sign the loop diverges)."
        ))]),
        alternatives("wrong_frame", [
            (tool_frame_err, (
                "{name} is the right rotation vector but expressed in the TOOL frame (the axis "
                "of Rᵀ R_goal is written in tool coordinates). The controller commands ω in the "
                "base frame: express the axis there."
            )),
            (tool_frame_other, (
                "{name} is expressed in the tool frame AND has the wrong sign (the rotation "
                "from the goal back to R): the error is the rotation from R to R_goal, its axis "
                "in the base frame."
            )),
        ]),
        alternatives("degrees_output", [(lambda x: np.degrees(_orientation_error_reference(x)), (
            "{name} gives θ in degrees: keep radians, so that ω = K θh is in rad/s."
        ))]),
        alternatives("rpy_difference", [(rpy_diff, (
            "{name} is the difference of roll–pitch–yaw angles. That is not a rotation vector: "
            "its components are angles about three different, moving axes, near pitch = ±π/2 two "
            "almost equal rotations can differ by whole radians in roll and yaw, and it cannot be "
            "used as an angular velocity without the matrix E(φ) of the Euler-angle rates."
        ))]),
        alternatives("quaternion", [
            (quat_vec, (
                "{name} is the vector part ε = sin(θ/2)h of the error quaternion: the direction is "
                "right but the size is not θ. Use θh (angle–axis), or 2ε if you choose the "
                "quaternion error (then the gain acts on 2 sin(θ/2), not on θ)."
            )),
            (lambda x: 2 * quat_vec(x), (
                "{name} is 2ε = 2 sin(θ/2)h, the quaternion error: a valid alternative error, but "
                "the exercise asks for the angle–axis error θh (they agree only for small θ)."
            )),
        ]),
    ]


orientation_error = exercise(_CHAPTER, "orientation_error", MatrixArgumentsCheck(
    name="orientation_error(R, R_goal)",
    reference=_orientation_error_reference,
    variables=[*_ROT, *_W],
    diagnoses=_orientation_error_mistakes(),
    noun="pairs of rotations",
    arguments=_orientation_error_arguments,
    signature="orientation_error(R, R_goal) -> (3,) array",
    atol=1e-7,
    hint=("θh is the rotation that takes R to R_goal, with θ in [0, π] and h the unit axis "
          "written in the base frame."),
    doc=("Check a function orientation_error(R, R_goal) -> θh (3,), base frame, radians: compared "
         "with the model at 20 random pairs of rotations (errors below π), to 1e-7."),
))


# ------------------------------------------------------------------ tool Jacobian f(J_e, R_be, p_et)
_P = [Variable(f"p_{c}", "length", -0.3, 0.3) for c in "xyz"]


def _tool_jacobian_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    q = np.asarray(x[:N_JOINTS], dtype=float)
    return _robot().jacobian(q), _robot().fk(q)[:3, :3], np.array(x[N_JOINTS:N_JOINTS + 3])


def _rigid_body(r: np.ndarray) -> np.ndarray:
    """The rigid-body Jacobian J_rb(r) = [[I, -[r×]], [0, I]] for twists [v; ω]."""
    J_rb = np.eye(6)
    J_rb[:3, 3:] = -skew(r)
    return J_rb


def _tool_jacobian_reference(x: np.ndarray) -> np.ndarray:
    J, r, _p = _tool_jacobian_parts(x)
    return _rigid_body(r) @ J


def _tool_jacobian_parts(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """J_E (6×7), ᴮr_ET = ᴮR_E ₑr_ET and ₑr_ET (3,) from the check's inputs x."""
    J, R, p = _tool_jacobian_arguments(x)
    return J, R @ p, p


def _transport_mistakes(parts: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]],
                        offset_words: str, of_q: str) -> list[Diagnosis]:
    """The typical mistakes of transporting an end-effector Jacobian J_E to the tool.

    Parameters
    ----------
    parts : callable
        ``parts(x) -> (J_E (6, n), ᴮr_ET (3,), ₑr_ET (3,))`` at the inputs x: the
        Jacobian, the offset from E to T in the base frame and the same offset in E.
    offset_words : str
        How the messages name the offset ₑr_ET (``"ₑr_ET"``, ``"ₑr_ET = [0.2, 0, 0] m"``).
    of_q : str
        ``"(q)"`` where the messages write J_E and ᴮR_E as functions of q, else ``""``.

    Returns
    -------
    list of Diagnosis
    """
    def not_rotated(x):
        J, _r, r_in_e = parts(x)
        return _rigid_body(r_in_e) @ J

    def plus_skew(x):
        J, r, _r_in_e = parts(x)
        return _rigid_body(-r) @ J

    def angular_first_block(x):
        J, r, _r_in_e = parts(x)
        M = np.eye(6)
        M[3:, :3] = skew(r).T
        return M @ J

    def transposed(x):
        J, r, _r_in_e = parts(x)
        return _rigid_body(r).T @ J

    def untouched(x):
        return parts(x)[0]

    return [
        alternatives("offset_not_rotated", [(not_rotated, (
            f"{{name}} uses the offset {offset_words} as if it were written in the base "
            f"frame: it is written in E, and the transport needs it in B (the two agree only "
            f"while ᴮR_E{of_q} = I)."
        ))]),
        alternatives("cross_sign", [(plus_skew, (
            "{name} has the sign of the cross-product block reversed: write v_T = v_E + ω × r "
            "(r from E to T) as a matrix times ω, with the skew-symmetric matrix of the "
            "conventions page."
        ))]),
        alternatives("twist_order", [(angular_first_block, (
            "{name} uses [[I, 0], [[r×]ᵀ, I]], the course's transport for twists ordered [ω; v] "
            "(angular first), on robokin's Jacobian ordered [v; ω]: convert the map with the row "
            "swap S of the Conventions section (S M S)."
        ))]),
        alternatives("transposed_transport", [(transposed, (
            "{name} uses the transposed transport matrix (it carries wrenches, not twists): "
            "derive it from v_T = v_E + ω × r and ω_T = ω_E."
        ))]),
        alternatives("no_transport", [(untouched, (
            f"{{name}} is the end-effector Jacobian J_E{of_q}: the tool offset is ignored."
        ))]),
    ]


tool_jacobian = exercise(_CHAPTER, "tool_jacobian", MatrixArgumentsCheck(
    name="tool_jacobian(J_e, R_be, p_et)",
    reference=_tool_jacobian_reference,
    variables=[*_Q, *_P],
    diagnoses=_transport_mistakes(_tool_jacobian_parts, "ₑr_ET", ""),
    noun="configurations and offsets",
    arguments=_tool_jacobian_arguments,
    signature="tool_jacobian(J_e, R_be, p_et) -> (6, n) array",
    hint=("The tool and E are one rigid body: the same ω, and v_T = v_E + ω × r with r from E "
          "to T in the base frame (rows [v; ω])."),
    doc=("Check a function tool_jacobian(J_e, R_be, p_et) -> J_T (6×n), rows [v; ω]: compared "
         "with the model at 20 random configurations and tool offsets."),
))


# ------------------------------------------------------------------ tool Jacobian f(q, offset) of the exercise
def _tool_jacobian_of_q_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The student's arguments at x: the configuration q (7,) and the tool offset ₑr_ET (3,) [m]."""
    return np.asarray(x[:N_JOINTS], dtype=float), np.array(x[N_JOINTS:N_JOINTS + 3])


def _tool_jacobian_of_q_parts(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The arm's J_E(q) (6×7), the offset ᴮr_ET = ᴮR_E(q) ₑr_ET and ₑr_ET (3,) at x."""
    q, offset = _tool_jacobian_of_q_arguments(x)
    return _robot().jacobian(q), _robot().fk(q)[:3, :3] @ offset, offset


def _tool_jacobian_of_q_reference(x: np.ndarray) -> np.ndarray:
    J, r, _offset = _tool_jacobian_of_q_parts(x)
    return _rigid_body(r) @ J


def _offset_ignored_mistakes() -> list[Diagnosis]:
    """The answer transports with a fixed offset (the exercise's, in m or read as cm), not its argument."""
    def fixed_offset(offset: tuple[float, float, float]) -> Callable[[np.ndarray], np.ndarray]:
        def answer(x):
            q = np.asarray(x[:N_JOINTS], dtype=float)
            return _rigid_body(_robot().fk(q)[:3, :3] @ np.array(offset)) @ _robot().jacobian(q)
        return answer

    message = ("{name} returns the same Jacobian whatever offset is passed: it transports with a "
               "fixed offset (your TOOL_OFFSET?) instead of its argument offset.")
    return [alternatives("offset_ignored", [
        (fixed_offset(_TOOL_OFFSET), message),
        (fixed_offset(tuple(0.01 * np.array(_TOOL_OFFSET))), message),
    ])]


tool_jacobian_of_q = exercise(_CHAPTER, "tool_jacobian_of_q", MatrixArgumentsCheck(
    name="my_tool_jacobian(q, offset)",
    reference=_tool_jacobian_of_q_reference,
    variables=[*_Q, *_P],
    diagnoses=[*_offset_ignored_mistakes(),
               *_transport_mistakes(_tool_jacobian_of_q_parts, "ₑr_ET (the argument offset)", "(q)")],
    noun="configurations and offsets",
    arguments=_tool_jacobian_of_q_arguments,
    signature="my_tool_jacobian(q, offset) -> (6, 7) array",
    hint=("The tool and E are one rigid body: the same ω, and v_T = v_E + ω × r with r from E "
          "to T in the base frame (rows [v; ω])."),
    doc=("Check a function my_tool_jacobian(q, offset) -> J_T(q) (6×7), rows [v; ω], of the course's "
         "arm with a tool at the offset ₑr_ET (3,) [m] from E: compared with the model at 20 random "
         "configurations and offsets."),
))


# ------------------------------------------------------------------ control law f(J, e, k_l, k_a)
_E = [Variable(f"e_{c}", "length", -0.3, 0.3) for c in ("px", "py", "pz")] + \
     [Variable(f"e_{c}", "other", -1.0, 1.0) for c in ("ox", "oy", "oz")]
_GAINS = [Variable("gain_linear", "other", 0.2, 2.0, aliases=("k_l", "kl")),
          Variable("gain_angular", "other", 0.2, 2.0, aliases=("k_a", "ka"))]


def _control_law_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, float]:
    q = np.asarray(x[:N_JOINTS], dtype=float)
    J = _robot().jacobian(q)
    return J, np.array(x[N_JOINTS:N_JOINTS + 6]), float(x[N_JOINTS + 6]), float(x[N_JOINTS + 7])


def _law(J: np.ndarray, nu: np.ndarray) -> np.ndarray:
    return np.linalg.pinv(J) @ nu


def _control_law_reference(x: np.ndarray) -> np.ndarray:
    J, e, kl, ka = _control_law_arguments(x)
    return _law(J, np.r_[kl * e[:3], ka * e[3:]])


def _control_law_mistakes():
    def swapped_gains(x):
        J, e, kl, ka = _control_law_arguments(x)
        return _law(J, np.r_[ka * e[:3], kl * e[3:]])

    def swapped_blocks(x):
        J, e, kl, ka = _control_law_arguments(x)
        return _law(J, np.r_[ka * e[3:], kl * e[:3]])

    def transpose_law(x):
        J, e, kl, ka = _control_law_arguments(x)
        return J.T @ np.r_[kl * e[:3], ka * e[3:]]

    return [
        alternatives("error_sign", [(lambda x: -_control_law_reference(x), (
            "{name} moves away from the goal: the error is e = goal − current and q̇ = +J⁺ K e."
        ))]),
        alternatives("twist_order", [(swapped_blocks, (
            "{name} stacks the desired twist angular part first, [κ_a e_o; κ_l e_p], as the course "
            "writes it, but robokin's Jacobian rows are [v; ω] (linear first): the linear error then "
            "drives the rotation. Keep one order everywhere: ν = [κ_l e_p; κ_a e_o] with J = [J_v; J_ω]."
        ))]),
        alternatives("swapped_gains", [(swapped_gains, (
            "{name} applies the angular gain to the position error and the linear gain to the "
            "orientation error."
        ))]),
        alternatives("jacobian_transpose", [(transpose_law, (
            "{name} uses the Jacobian transpose Jᵀ where the pseudoinverse J⁺ belongs: "
            "J Jᵀ ν ≠ ν, so the tool does not move with the desired twist."
        ))]),
    ]


control_law = exercise(_CHAPTER, "control_law", MatrixArgumentsCheck(
    name="control_law(J, e, gain_linear, gain_angular)",
    reference=_control_law_reference,
    variables=[*_Q, *_E, *_GAINS],
    diagnoses=_control_law_mistakes(),
    noun="configurations, errors and gains",
    arguments=_control_law_arguments,
    signature="control_law(J, e, gain_linear, gain_angular) -> (n,) array",
    atol=1e-7,
    hint="q̇ = J⁺ [κ_l e_p; κ_a e_o] with e = [e_p; e_o] and J (6×n) rows [v; ω].",
    doc=("Check a function control_law(J, e, gain_linear, gain_angular) -> q̇ (n,): compared with "
         "the model at 20 random configurations, errors e = [e_p; e_o] and gains, to 1e-7."),
))


# ------------------------------------------------------------------ the kinematic loop of Task 4
_LOOP_STOP = 0.01  # the exercise's stop threshold on each part of the twist (m/s, rad/s)
_LOOP_GAIN = 0.8  # the exercise's gains: the factor of a loop that applies one again
_LOOP_STEPS = 12  # t_end = 12 ts in every call
_LOOP_START = (math.pi / 2, -math.pi / 4, 0.0, -math.pi / 4, 0.0, 0.15, math.pi / 4)  # the sheet's q0
_LOOP_VARIABLES = [
    *[Variable(f"dq{i + 1}", "other", -0.05 if i == 5 else -0.3, 0.05 if i == 5 else 0.3)
      for i in range(N_JOINTS)],
    *[Variable(f"goal_{c}", "length", -0.03, 0.03) for c in "xyz"],
    *[Variable(f"turn_{c}", "other", -0.1, 0.1) for c in "xyz"],
    Variable("gain", "other", 0.5, 1.5),
    Variable("ts", "other", 0.2, 0.5),
    Variable("joint5_margin", "other", 0.0, 0.05),
]


def _loop_robot(q0: np.ndarray, margin: float) -> Any:
    """The course's arm with the exercise's tool, joint 5 free only ``margin`` either side of q0's
    (joint 7 turns about the same axis: the arm keeps six independent motions)."""
    from robokin.models.genova_arm import GENOVA_ARM_LIMITS, genova_arm
    from robokin.motion.tool import chain_with_tool

    limits = np.array(GENOVA_ARM_LIMITS, dtype=float)
    limits[4] = q0[4] - margin, q0[4] + margin
    return chain_with_tool(genova_arm(limits=limits), _T_ET())


def _loop_args(x: np.ndarray) -> tuple:
    """``(twist_of, q0, ts, t_end, robot)``: a P law towards a goal near the start pose."""
    from robokin.motion import pose_error

    x = np.asarray(x, dtype=float)
    q0 = np.array(_LOOP_START) + x[:N_JOINTS]
    robot = _loop_robot(q0, float(x[15]))
    start = robot.fk(q0)
    goal = _transform(rotation_exp(x[10:13]) @ start[:3, :3], start[:3, 3] + x[7:10])
    gain, ts = float(x[13]), float(x[14])

    def twist_of(q: np.ndarray) -> np.ndarray:
        return gain * pose_error(robot.fk(q), goal)

    return twist_of, q0, ts, _LOOP_STEPS * ts, robot


def _loop(twist_of, q0, ts, t_end, robot, *, step_scale=1.0, no_ts=False, skip=False,
          stop_scale=1.0, transpose=False, step_first=False, no_clamp=False) -> tuple[np.ndarray, np.ndarray]:
    """The reference loop (and, with the keywords, its typical mistakes): ``(Q, V)``."""
    lower, upper = robot.limits[:, 0], robot.limits[:, 1]
    q = np.array(q0, dtype=float)
    Q, V = [q.copy()], []
    steps = int(round(t_end / ts))

    def stops(nu: np.ndarray) -> bool:
        return max(np.linalg.norm(nu[:3]), np.linalg.norm(nu[3:])) < _LOOP_STOP * stop_scale

    for k in range(steps + 1):
        nu = np.asarray(twist_of(q), dtype=float)
        if not step_first:
            V.append(nu)
            if stops(nu) or k == steps:
                break
        elif k == steps:
            break
        J = robot.jacobian(q)
        qdot = (J.T if transpose else np.linalg.pinv(J)) @ nu
        new = q + (qdot if no_ts else step_scale * ts * qdot)
        if no_clamp:
            q = new
        else:
            q = np.where((new >= lower) & (new <= upper), new, q) if skip else np.clip(new, lower, upper)
        Q.append(q.copy())
        if step_first:
            V.append(nu)
            if stops(nu):
                break
    if step_first:
        V.append(np.asarray(twist_of(q), dtype=float))
    return np.array(Q), np.array(V)


def _pack_loop(out: Any) -> np.ndarray:
    """``[K, q_K (7), q_1 (7), ν_K (6)]`` of a loop's ``(Q, V)``; a ``TypeError`` that says
    what the value should be otherwise."""
    if not isinstance(out, tuple) or len(out) != 2:
        raise TypeError("kinematic_loop should return the pair (Q, V): the configurations (K+1, 7) "
                        "and the twists (K+1, 6) at the samples")
    Q, V = (np.asarray(part, dtype=float) for part in out)
    if Q.ndim != 2 or Q.shape[1] != N_JOINTS or V.ndim != 2 or V.shape != (len(Q), 6):
        raise TypeError(f"kinematic_loop should return Q (K+1, 7) and V (K+1, 6), one row per sample; "
                        f"got shapes {Q.shape} and {V.shape}")
    return np.concatenate([[len(Q) - 1], Q[-1], Q[min(1, len(Q) - 1)], V[-1]])


def _loop_variant(**mistake: Any) -> Callable[[np.ndarray], np.ndarray]:
    return lambda x: _pack_loop(_loop(*_loop_args(x), **mistake))


def _describe_loop(x: np.ndarray) -> str:
    """The call of the student's loop at the sample ``x``, as a failure's example writes it."""
    x = np.asarray(x, dtype=float)
    return (f"kinematic_loop(twist_of = {x[13]:.3g} × pose error towards a goal {fmt(x[7:10])} m and "
            f"{np.linalg.norm(x[10:13]):.3g} rad from the start, q0 = {fmt(np.array(_LOOP_START) + x[:N_JOINTS])}, "
            f"ts = {x[14]:.3g} s, t_end = {_LOOP_STEPS * x[14]:.3g} s, robot = the arm with the tool, "
            f"joint 5 within {x[15]:.3g} rad of its start)")


def _loop_entry(idx: tuple[int, ...]) -> str:
    """What entry ``idx`` of the packed ``[K, q_K, q_1, ν_K]`` is."""
    i = idx[0]
    if i == 0:
        return "the number of steps K = len(Q) − 1"
    if i <= N_JOINTS:
        return f"the last configuration Q[-1][{i - 1}]"
    if i <= 2 * N_JOINTS:
        return f"the first step's configuration Q[1][{i - N_JOINTS - 1}]"
    return f"the last twist V[-1][{i - 2 * N_JOINTS - 1}]"


kinematic_loop = exercise(_CHAPTER, "kinematic_loop", MatrixArgumentsCheck(
    name="kinematic_loop(twist_of, q0, ts, t_end, robot)",
    reference=_loop_variant(),
    variables=_LOOP_VARIABLES,
    diagnoses=[
        alternatives("step_before_test", [(_loop_variant(step_first=True), (
            "{name} takes the step before it tests the twist the step was computed from, and "
            "stops one step late: at each sample compute the twist, stop if both parts are "
            "below STOP (that sample is the last), and only then step."
        ))]),
        alternatives("gain_in_step", [(_loop_variant(step_scale=_LOOP_GAIN), (
            "{name} scales the Euler step by 0.8, the gain once more: twist_of(q) already "
            "returns the desired twist κ e, and the step is q + ts J⁺ν."
        ))]),
        alternatives("no_time_step", [(_loop_variant(no_ts=True), (
            "{name} adds J⁺ν without the time step: one Euler step of ts is q + ts J⁺ν."
        ))]),
        alternatives("skip_rule", [(_loop_variant(skip=True), (
            "{name} leaves a joint where it was when its new value would leave the limits (the "
            "report's rule), which freezes it short of the limit: clamp the new value instead "
            "(np.clip)."
        ))]),
        alternatives("no_clamp", [(_loop_variant(no_clamp=True), (
            "{name} lets the joints leave their limits: the statement keeps every joint within "
            "its limits, so clamp each new value to them (np.clip) after the Euler step."
        ))]),
        alternatives("stop_on_error", [(_loop_variant(stop_scale=_LOOP_GAIN), (
            "{name} tests the error (the twist divided by the gain 0.8) against STOP: the stop "
            "test is on both parts of the commanded twist."
        ))]),
        alternatives("jacobian_transpose", [(_loop_variant(transpose=True), (
            "{name} uses the Jacobian transpose Jᵀ where the pseudoinverse J⁺ belongs."
        ))]),
    ],
    noun="start configurations, goals, gains and time steps",
    arguments=_loop_args,
    describe=_describe_loop,
    entry_label=_loop_entry,
    signature="kinematic_loop(twist_of, q0, ts, t_end, robot) -> (Q (K+1, n), V (K+1, 6))",
    hint=("Check the order of the loop's steps, the Euler step of ts, the clamp to the limits and "
          "the stop test against the statement of Task 4."),
    atol=1e-7,
    doc=("Check a loop kinematic_loop(twist_of, q0, ts, t_end, robot) -> (Q, V): run on P laws "
         "towards 20 random goals within 3 cm and 0.1 rad of starts near the sheet's q0 (the "
         "course's arm with its tool, joint 5 held near its start), with random gains and time "
         "steps, to 1e-7."),
    pack=_pack_loop,
))


# ------------------------------------------------------------------ E(φ) of the RPY angles (Task 5)
_RPY_ANGLES = [Variable("roll", "angle", -3.0, 3.0), Variable("pitch", "angle", -1.4, 1.4),
               Variable("yaw", "angle", -3.0, 3.0)]


def _rpy_rate_arguments(x: np.ndarray) -> tuple[np.ndarray]:
    return (rotation_from_rpy(float(x[0]), float(x[1]), float(x[2])),)


def _rpy_rate_columns(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The axes of the roll, pitch and yaw turns in the base frame: Rz Ry x, Rz y, z."""
    pitch, yaw = float(x[1]), float(x[2])
    return rotz(yaw) @ roty(pitch) @ [1.0, 0.0, 0.0], rotz(yaw) @ [0.0, 1.0, 0.0], np.array([0.0, 0.0, 1.0])


def _rpy_rate_reference(x: np.ndarray) -> np.ndarray:
    return np.column_stack(_rpy_rate_columns(x))


def _rpy_rate_mistakes() -> list[Diagnosis]:
    def reversed_columns(x):
        return np.column_stack(_rpy_rate_columns(x)[::-1])

    def roll_axis_without_pitch(x):
        _, pitch_axis, yaw_axis = _rpy_rate_columns(x)
        return np.column_stack([rotz(float(x[2])) @ [1.0, 0.0, 0.0], pitch_axis, yaw_axis])

    def in_the_moving_frame(x):
        return _rpy_rate_arguments(x)[0].T @ _rpy_rate_reference(x)

    return [
        alternatives("columns_reversed", [(reversed_columns, (
            "{name} has its columns in the order (yaw, pitch, roll): the statement multiplies "
            "E(φ) by the rates of (roll, pitch, yaw), in that order."
        ))]),
        alternatives("roll_axis_without_pitch", [(roll_axis_without_pitch, (
            "{name} turns the roll's axis x by Rz(yaw) only: in R = Rz(ψ) Ry(ϑ) Rx(φ) the roll "
            "comes after the pitch too."
        ))]),
        alternatives("transpose", [(lambda x: _rpy_rate_reference(x).T, (
            "{name} is transposed: its columns are the axes of the three turns, in the base frame."
        ))]),
        alternatives("moving_frame", [(in_the_moving_frame, (
            "{name} gives the angular velocity in the rotated frame (Rᵀ ω): the controller "
            "commands ω in the base frame."
        ))]),
    ]


rpy_rate_matrix = exercise(_CHAPTER, "rpy_rate_matrix", MatrixArgumentsCheck(
    name="rpy_rate_matrix(R)",
    reference=_rpy_rate_reference,
    variables=_RPY_ANGLES,
    diagnoses=_rpy_rate_mistakes(),
    noun="rotations",
    arguments=_rpy_rate_arguments,
    signature="rpy_rate_matrix(R) -> (3, 3) array",
    hint="ω = E(φ) φ̇ with φ̇ the rates of (roll, pitch, yaw), ω in the base frame.",
    atol=1e-8,
    doc=("Check a function rpy_rate_matrix(R) -> E(φ) (3×3), ω = E(φ) (roll, pitch, yaw) rates in "
         "the base frame: compared at 20 random rotations (pitch within ±1.4 rad)."),
))


# ------------------------------------------------------------------ the later tests' stand-ins
def reference_orientation_error(R: Any, R_goal: Any) -> np.ndarray:
    r"""robokin's answer to ``orientation_error`` of Task 2 (the later tests' stand-in).

    The graded tests of the tasks after it pass this function to the student's functions that
    take an orientation error as an argument (``my_twist(q, orientation_error=...)``), so that a
    mistake in ``orientation_error`` costs the points of its own test only.

    Parameters
    ----------
    R, R_goal : array_like, shape (3, 3)
        Rotation matrices: the current orientation and the goal's, in the base frame.

    Returns
    -------
    numpy.ndarray, shape (3,)
        The rotation vector θh (rad) of the rotation that takes ``R`` to ``R_goal``, in the base
        frame, with θ in [0, π].
    """
    from robokin.validation import as_float_array, check_rotation_matrix

    R = check_rotation_matrix(as_float_array(R, "R", (3, 3)), name="R")
    R_goal = check_rotation_matrix(as_float_array(R_goal, "R_goal", (3, 3)), name="R_goal")
    return rotation_log(R_goal @ R.T, check=False)


def reference_rpy_difference(R: Any, R_goal: Any) -> np.ndarray:
    r"""robokin's answer to ``rpy_difference`` of Task 5 (the later test's stand-in).

    The graded test of ``analytic_twist(q, rpy_difference=...)`` passes it in place of the
    student's, so that a mistake in ``rpy_difference`` costs the points of its own test only.

    Parameters
    ----------
    R, R_goal : array_like, shape (3, 3)
        Rotation matrices: the current orientation and the goal's, in the base frame.

    Returns
    -------
    numpy.ndarray, shape (3,)
        The (roll, pitch, yaw) angles of ``R_goal`` minus those of ``R`` (rad), each difference
        wrapped into (−π, π]: coordinates of the rotation set, not a vector in the base frame.
    """
    from robokin.validation import as_float_array, check_rotation_matrix

    R = check_rotation_matrix(as_float_array(R, "R", (3, 3)), name="R")
    R_goal = check_rotation_matrix(as_float_array(R_goal, "R_goal", (3, 3)), name="R_goal")
    raw = np.asarray(rpy_from_rotation(R_goal)) - np.asarray(rpy_from_rotation(R))
    return np.pi - np.mod(np.pi - raw, 2.0 * np.pi)


def reference_tool_arm() -> Any:
    """robokin's answer to ``tool_arm`` of Task 1 (the later tests' stand-in).

    The graded tests of the tasks after it run the exercise's loop on this chain and towards
    :func:`reference_goal`, so that a mistake in the tool or the goal costs the points of their
    own tests only.

    Returns
    -------
    robokin.chains.SerialChain
        The course's arm with its end-effector moved to the exercise's tool.
    """
    from robokin.motion.tool import chain_with_tool

    return chain_with_tool(_robot(), _T_ET(), name="genova_arm+tool")


def reference_goal() -> np.ndarray:
    """robokin's answer to ``T_BG`` of Task 2 (the later tests' stand-in), as
    :func:`reference_tool_arm`.

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        The exercise's goal pose in the base frame (m).
    """
    return _T_BG()
