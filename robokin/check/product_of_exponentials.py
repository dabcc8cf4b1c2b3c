r"""Exercise checks of chapter 8: the product of exponentials on the UR10.

Twists and screw axes are Lynch & Park's, **angular part first**, :math:`[\omega; v]`
(``book/conventions.md``). References come from robokin's own screw functions
(:func:`robokin.transforms.transform_exp`, :func:`robokin.transforms.adjoint`) and from the
UR10 of :func:`robokin.models.ur10` (its DH model: ``fk``, ``jacobian``, ``screw_axes``,
``space_jacobian``, ``body_jacobian``).

========================  =================================================  ==================================
check                     the student's answer                               inputs (random)
========================  =================================================  ==================================
``rodrigues``             ``rodrigues(omega, theta)`` -> e^{[ω]θ} (3, 3)       unit axis ω, angle θ
``screw_axis``            ``screw_axis(omega, point)`` -> [ω; v] (6,)          unit axis ω, point q on it
``screw_list``            ``screw_axes_at_home(frames, joint_axes)`` ->        a chain's frames and local axes
                          the screw axes, one per row (n, 6)
``exp6``                  ``exp6(S, theta)`` -> e^{[S]θ} (4, 4)                a revolute screw axis, θ
``forward_kinematics``    ``poe_fk(M, S_list, theta)`` -> T(θ) (4, 4)          the UR10's M and S, θ (6,)
``adjoint``               ``adjoint_matrix(T)`` -> [Ad_T] (6, 6)               a transform (roll, pitch, yaw, p)
``space_jacobian``        ``jacobian_in_space(S_list, theta)`` -> J_s (6, n)   the UR10's S, θ (6,)
``geometric_from_space``  ``geometric_from_space(J_s, T)`` -> [J_v; J_ω]       the UR10's J_s and T at θ
``body_jacobian``         ``jacobian_in_body(M, S_list, theta)`` -> J_b        the UR10's M and S, θ (6,)
``ik_body``               ``ik_body(M, S_list, T_goal, theta_start)`` ->       a goal T(θ_goal), a start near θ_goal
                          ``(theta, iterations)``: the pose reached
========================  =================================================  ==================================

Each check calls the student's function at 20 seeded random inputs of its own and compares
with the reference; a wrong answer is explained when one of the task's typical mistakes
reproduces it (a sign, the axis reversed, a joint's axis not turned into the base frame, the
order [v; ω] for [ω; v], the factors in the wrong order, a term of the exponential's
translation missing, the wrong transform's adjoint, degrees for radians). A function that takes
earlier steps as keyword arguments (``exp6(S, theta, rodrigues=..., skew=...)``, ...) is called
with robokin's steps (``reference_*``) in their place, so that a check's verdict (and the grading
report's) is on that step alone, not on a mistake in an earlier one.

Usage::

    from robokin.check import product_of_exponentials as check_poe
    check_poe.exp6(exp6)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache, partial
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    CheckResult, LaterStepCheck, MatrixArgumentsCheck, Variable, alternatives, with_reference_steps,
)
from robokin.check._registry import exercise
from robokin.validation import as_float_array

__all__ = [
    "rodrigues", "screw_axis", "screw_list", "exp6", "forward_kinematics", "adjoint",
    "space_jacobian", "geometric_from_space", "body_jacobian", "ik_body",
    "reference_skew", "reference_rodrigues", "reference_screw_axis", "reference_exp6", "reference_poe_fk",
    "reference_adjoint_matrix", "reference_jacobian_in_space", "reference_jacobian_in_body",
]

_CHAPTER = "product_of_exponentials"

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back is flagged for review by hand (tools/grading/bridge/delegation.py
#: reads this literal table without importing the module). Task 2's screw axes are read from
#: ``SerialChain.frames``, as the chapter asks: only ``screw_axes`` hands the answer back. The
#: ``reference_*`` functions below are the tests' stand-ins for a task's answer: an answer that
#: calls one hands that task's work to robokin.
DELEGATION = {
    "rodrigues": {"rotation_exp": "robokin.transforms.rotation_exp",
                  "reference_skew": "robokin.check.product_of_exponentials.reference_skew",
                  "reference_rodrigues": "robokin.check.product_of_exponentials.reference_rodrigues"},
    "screw_axis": {"reference_screw_axis": "robokin.check.product_of_exponentials.reference_screw_axis"},
    "screw_list": {"screw_axes": "SerialChain.screw_axes"},
    "exp6": {"transform_exp": "robokin.transforms.transform_exp",
             "reference_exp6": "robokin.check.product_of_exponentials.reference_exp6"},
    "forward_kinematics": {"product_of_exponentials": "robokin.chains.screws.product_of_exponentials",
                           "fk": "SerialChain.fk", "transform_exp": "robokin.transforms.transform_exp",
                           "reference_poe_fk": "robokin.check.product_of_exponentials.reference_poe_fk"},
    "adjoint": {"adjoint": "robokin.transforms.adjoint",
                "reference_adjoint_matrix": "robokin.check.product_of_exponentials.reference_adjoint_matrix"},
    "space_jacobian": {"space_jacobian": "SerialChain.space_jacobian",
                       "jacobian": "SerialChain.jacobian",
                       "reference_jacobian_in_space":
                            "robokin.check.product_of_exponentials.reference_jacobian_in_space"},
    "geometric_from_space": {"jacobian": "SerialChain.jacobian"},
    "body_jacobian": {"body_jacobian": "SerialChain.body_jacobian",
                      "space_jacobian": "SerialChain.space_jacobian",
                      "reference_jacobian_in_body": "robokin.check.product_of_exponentials.reference_jacobian_in_body"},
    "ik_body": {"solve_ik": "robokin.motion.solve_ik", "solve_ik_once": "robokin.motion.solve_ik_once",
                "ur10_ik": "robokin.models.ur10_ik", "body_jacobian": "SerialChain.body_jacobian"},
}


@lru_cache(maxsize=1)
def _ur10():
    from robokin.models import ur10

    return ur10()


@lru_cache(maxsize=1)
def _home() -> tuple[np.ndarray, np.ndarray]:
    M, S = _ur10().screw_axes()
    return M, S


# ------------------------------------------------------------------ the algebra, written out
def _skew(w: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _unit(a: np.ndarray) -> np.ndarray:
    return np.asarray(a, dtype=float) / np.linalg.norm(a)


def _rotation(omega: np.ndarray, theta: float, *, sin_sign: float = 1.0, square: bool = True) -> np.ndarray:
    W = _skew(omega)
    return np.eye(3) + sin_sign * np.sin(theta) * W + (1 - np.cos(theta)) * (W @ W if square else W)


def _exp(S: np.ndarray, theta: float, *, with_g: bool = True) -> np.ndarray:
    from robokin.transforms import transform_exp

    T = np.asarray(transform_exp(np.asarray(S, dtype=float) * theta), dtype=float)
    if not with_g:
        T[:3, 3] = S[3:] * theta
    return T


def _product(M: np.ndarray, S: np.ndarray, theta: np.ndarray, *, reverse: bool = False,
             m_left: bool = False, with_m: bool = True, with_g: bool = True) -> np.ndarray:
    factors = [_exp(s, t, with_g=with_g) for s, t in zip(S, theta)]
    if reverse:
        factors = factors[::-1]
    P = np.eye(4)
    for F in factors:
        P = P @ F
    if not with_m:
        return P
    return M @ P if m_left else P @ M


def _adjoint(T: np.ndarray) -> np.ndarray:
    from robokin.transforms import adjoint

    return np.asarray(adjoint(T), dtype=float)


def _swap(J: np.ndarray) -> np.ndarray:
    """[ω; v] <-> [v; ω]: the two blocks of rows traded."""
    return np.concatenate([J[3:], J[:3]], axis=0)


def _space(S: np.ndarray, theta: np.ndarray, *, reverse: bool = False, inverse: bool = False,
           adjoint_on: bool = True) -> np.ndarray:
    from robokin.transforms import transform_inverse

    columns, P = [], np.eye(4)
    for s, t in zip(S, theta):
        A = transform_inverse(P) if inverse else P
        columns.append(_adjoint(A) @ s if adjoint_on else np.array(s, dtype=float))
        E = _exp(s, t)
        P = E @ P if reverse else P @ E
    return np.column_stack(columns)


def _theta(x: np.ndarray) -> np.ndarray:
    return np.asarray(x[:6], dtype=float)


_AXIS = [Variable(f"axis_{c}", "other", -1.0, 1.0) for c in "xyz"]
_POINT = [Variable(f"point_{c}", "length", -1.0, 1.0) for c in "xyz"]
_ANGLE = [Variable("theta", "angle", -np.pi, np.pi, aliases=("θ",))]
_Q = [Variable(f"theta{i}", "angle", -np.pi, np.pi, aliases=(f"q{i}",)) for i in range(1, 7)]


# ------------------------------------------------------------------ Task 1: Rodrigues' formula
def _rodrigues_arguments(x: np.ndarray) -> tuple[np.ndarray, float]:
    return _unit(x[:3]), float(x[3])


def _rodrigues_reference(x: np.ndarray) -> np.ndarray:
    from robokin.transforms import rotation_exp

    omega, theta = _rodrigues_arguments(x)
    return np.asarray(rotation_exp(omega * theta), dtype=float)


def _rodrigues_mistakes():
    def sin_sign(x):
        return _rotation(*_rodrigues_arguments(x), sin_sign=-1.0)

    def no_square(x):
        return _rotation(*_rodrigues_arguments(x), square=False)

    def swapped(x):
        omega, theta = _rodrigues_arguments(x)
        W = _skew(omega)
        return np.eye(3) + (1 - np.cos(theta)) * W + np.sin(theta) * (W @ W)

    return [
        alternatives("transpose", [(sin_sign, (
            "{name} turns by −θ: it is the transpose of e^{{[ω]θ}}. Check the sign of the term "
            "that collects the odd powers of [ω]θ, with [ω]x = ω × x."
        ))]),
        alternatives("missing_square", [(no_square, (
            "{name} multiplies the even powers' sum by [ω]: reduce the even powers of [ω] with "
            "[ω]³ = −[ω] and see which power of [ω] is left."
        ))]),
        alternatives("sin_cos_swapped", [(swapped, (
            "{name} has the two series' sums traded: which one collects the odd powers of [ω]θ, "
            "and which the even ones?"
        ))]),
        dg.degrees(),
    ]


rodrigues = exercise(_CHAPTER, "rodrigues", MatrixArgumentsCheck(
    name="rodrigues(omega, theta)",
    reference=_rodrigues_reference,
    variables=[*_AXIS, *_ANGLE],
    diagnoses=_rodrigues_mistakes(),
    noun="axes and angles",
    arguments=_rodrigues_arguments,
    signature="rodrigues(omega, theta) -> (3, 3) array",
    hint="Sum the series of e^{[ω]θ} with [ω]³ = −[ω] for a unit ω.",
    doc="Check rodrigues(omega, theta) -> the rotation e^{[ω]θ} (3, 3) about the unit axis omega.",
))


# ------------------------------------------------------------------ Task 2: screw axes
def _screw_axis_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return _unit(x[:3]), np.asarray(x[3:6], dtype=float)


def _screw_axis_reference(x: np.ndarray) -> np.ndarray:
    omega, point = _screw_axis_arguments(x)
    return np.concatenate([omega, -np.cross(omega, point)])


_SIGN_TEXT = (
    "the linear part of {name} has the wrong sign: it describes the same axis through −q. v is "
    "the velocity of the body point at the origin of {{s}} when the body turns at unit rate about "
    "the axis through q: write the velocity of a point r turning about that axis (it depends on "
    "r − q), then put r at the origin; mind the order of the cross product's factors."
)
_ORDER_TEXT = (
    "{name} is ordered [v; ω]: Lynch & Park's screw axis puts the angular part first, "
    "S = [ω; v] (this book's geometric Jacobian is [v; ω]: the two orders differ)."
)


def _screw_axis_mistakes():
    def sign(x):
        omega, point = _screw_axis_arguments(x)
        return np.concatenate([omega, np.cross(omega, point)])

    def order(x):
        return _swap(_screw_axis_reference(x))

    def order_and_sign(x):
        omega, point = _screw_axis_arguments(x)
        return np.concatenate([np.cross(omega, point), omega])

    def point_as_v(x):
        omega, point = _screw_axis_arguments(x)
        return np.concatenate([omega, point])

    def reversed_axis(x):
        return -_screw_axis_reference(x)

    def angular_sign(x):
        omega, point = _screw_axis_arguments(x)
        return np.concatenate([-omega, -np.cross(omega, point)])

    return [
        alternatives("cross_sign", [(sign, _SIGN_TEXT)]),
        alternatives("twist_order", [
            (order, _ORDER_TEXT),
            (order_and_sign, "{name} is ordered [v; ω] and its v has the wrong sign: the angular part comes "
             "first, and v is the velocity of the body point at the origin of {{s}}."),
        ]),
        alternatives("point_for_velocity", [(point_as_v, (
            "the linear part of {name} is the point q itself; it is a velocity: that of the body "
            "point at the origin of {{s}} when the body turns about the axis through q."
        ))]),
        alternatives("axis_sign", [
            (reversed_axis, (
                "{name} is −S: both parts have the wrong sign, a joint turning about −ω. The angular "
                "part is the axis ω as given."
            )),
            (angular_sign, (
                "the angular part of {name} is −ω: it is the joint's axis ω as given (its v is right)."
            )),
        ]),
    ]


screw_axis = exercise(_CHAPTER, "screw_axis", MatrixArgumentsCheck(
    name="screw_axis(omega, point)",
    reference=_screw_axis_reference,
    variables=[*_AXIS, *_POINT],
    diagnoses=_screw_axis_mistakes(),
    noun="axes and points",
    arguments=_screw_axis_arguments,
    signature="screw_axis(omega, point) -> (6,) array",
    hint="S = [ω; v] with v the velocity of the body point at the origin of {s}.",
    doc="Check screw_axis(omega, point) -> the screw axis [ω; v] (6,) of a revolute joint.",
))


#: the chain of the screw_list check: its joints, and per sample the roll, pitch, yaw and origin of
#: each of its frames (the base, the joints' frames, the end-effector) and the spherical angles of each
#: joint's unit axis in its own frame
_CHAIN_JOINTS = 4
_CHAIN = ([Variable(f"frame{k}_{part}", "other", low, high)
           for k in range(_CHAIN_JOINTS + 2)
           for part, low, high in (("roll", -math.pi, math.pi), ("pitch", -1.5, 1.5), ("yaw", -math.pi, math.pi),
                                   ("x", -1.0, 1.0), ("y", -1.0, 1.0), ("z", -1.0, 1.0))]
          + [Variable(f"axis{i}_{part}", "other", low, high)
             for i in range(1, _CHAIN_JOINTS + 1)
             for part, low, high in (("azimuth", -math.pi, math.pi), ("elevation", -1.5, 1.5))])


def _screw_list_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(frames (n + 2, 4, 4), joint_axes (n, 3)) of the sample ``x``: a chain of the check's own."""
    from robokin.transforms import transform_from_rpy

    x = np.asarray(x, dtype=float)
    poses = x[:6 * (_CHAIN_JOINTS + 2)].reshape(-1, 6)
    frames = np.array([transform_from_rpy(pose[:3], pose[3:]) for pose in poses])
    azimuth, elevation = x[6 * (_CHAIN_JOINTS + 2):].reshape(-1, 2).T
    axes = np.column_stack([np.cos(elevation) * np.cos(azimuth), np.cos(elevation) * np.sin(azimuth),
                            np.sin(elevation)])
    return frames, axes


def _screw_rows(x: np.ndarray, *, frame_offset: int = 1, axis: str = "turned", sign: float = -1.0,
                order: bool = False) -> np.ndarray:
    """The chain's screw axes, one per row; the keywords make the typical mistakes."""
    frames, axes = _screw_list_arguments(x)
    rows = []
    for i, local in enumerate(axes):
        frame = frames[i + frame_offset]
        R, p = frame[:3, :3], frame[:3, 3]
        omega = {"turned": R @ local, "local": local, "transposed": R.T @ local, "z": R[:, 2],
                 "shifted": R @ local + p}[axis]
        row = np.concatenate([omega, sign * np.cross(omega, p)])
        rows.append(_swap(row) if order else row)
    return np.array(rows)


def _screw_list_mistakes():
    return [
        alternatives("cross_sign", [(partial(_screw_rows, sign=1.0), (
            "the linear parts of {name}'s rows have the wrong sign: v_i is the velocity of the body "
            "point at the origin of {{s}} when the body turns about joint i's axis."
        ))]),
        alternatives("twist_order", [(partial(_screw_rows, order=True), (
            "the rows of {name} are ordered [v; ω]; a screw axis is [ω; v], angular part first."
        ))]),
        alternatives("frame_before", [(partial(_screw_rows, frame_offset=0), (
            "{name} reads joint i's axis from the frame before it (frames[i − 1]); joint i turns "
            "about an axis through the origin of frames[i], its own frame."
        ))]),
        alternatives("axis_not_turned", [
            (partial(_screw_rows, axis="local"), (
                "{name} uses joint_axes[i − 1] as ω_i as it is: that axis is written in joint i's own "
                "frame, and S_i needs it in {{s}} (turned by the frame's rotation)."
            )),
            (partial(_screw_rows, axis="transposed"), (
                "{name} turns each axis by the transpose of its frame's rotation: Rᵀ maps a direction "
                "written in {{s}} into the frame, the opposite of what ω_i needs."
            )),
            (partial(_screw_rows, axis="z"), (
                "{name} takes every joint's z axis: joint i turns about joint_axes[i − 1], written in "
                "its own frame (z for every UR10 joint, not for every robot)."
            )),
            (partial(_screw_rows, axis="shifted"), (
                "{name} adds the frame's origin to each axis: an axis is a direction, turned by the "
                "frame's rotation and not shifted by its origin."
            )),
        ]),
    ]


def _describe_chain(x: np.ndarray) -> str:
    frames, axes = _screw_list_arguments(x)
    return (f"{len(axes)} joints of the check's own, frames {len(frames)} random poses and joint_axes = "
            f"{np.round(axes, 3).tolist()}")


screw_list = exercise(_CHAPTER, "screw_list", LaterStepCheck(
    steps=lambda: {"screw_axis": reference_screw_axis},
    name="screw_axes_at_home",
    reference=_screw_rows,
    variables=_CHAIN,
    diagnoses=_screw_list_mistakes(),
    noun="chains",
    arguments=_screw_list_arguments,
    signature="screw_axes_at_home(frames, joint_axes) -> (n, 6) array",
    describe=_describe_chain,
    hint="Joint i's frame is frames[i] (frames[0] is the base); its axis joint_axes[i − 1] is written "
         "in that frame, and the screw axis S_i is written in {s}.",
    doc="Check screw_axes_at_home(frames, joint_axes) -> the screw axes [ω_i; v_i] of a chain's revolute "
        "joints at home, one per row (n, 6).",
))


# ------------------------------------------------------------------ Task 3: exponential and FK
# ------------------------------------------------------------------ the later steps, judged alone



def _exp6_arguments(x: np.ndarray) -> tuple[np.ndarray, float]:
    omega, point = _unit(x[:3]), np.asarray(x[3:6], dtype=float)
    return np.concatenate([omega, -np.cross(omega, point)]), float(x[6])


def _exp6_reference(x: np.ndarray) -> np.ndarray:
    return _exp(*_exp6_arguments(x))


_NO_G_TEXT = (
    "the translation of {name} is v θ: G(θ) is missing. Sum the series' translation column "
    "as Task 1 summed the rotation: its powers of [ω] reduce with [ω]³ = −[ω]."
)


def _exp6_mistakes():
    def no_g(x):
        return _exp(*_exp6_arguments(x), with_g=False)

    def no_theta(x):
        S, theta = _exp6_arguments(x)
        T = _exp(S, theta)
        T[:3, 3] = S[3:]
        return T

    def reversed_rotation(x):
        S, theta = _exp6_arguments(x)
        T = _exp(S, theta)
        T[:3, :3] = T[:3, :3].T
        return T

    def order(x):
        S, theta = _exp6_arguments(x)
        return _exp(_swap(S), theta)

    return [
        alternatives("missing_G", [
            (no_g, _NO_G_TEXT),
            (no_theta, "the translation of {name} is v: it is G(θ) v, with G(θ) the sum of the "
                       "series' translation column (the powers of [ω] times θ^k/k!)."),
        ]),
        alternatives("rotation_transposed", [(reversed_rotation, (
            "the rotation of {name} turns by −θ (its transpose): the rotation block is e^{{[ω]θ}}, "
            "the rodrigues it is given, as it is."
        ))]),
        alternatives("twist_order", [(order, (
            "{name} reads S as [v; ω]: S = [ω; v], the angular part first."
        ))]),
        dg.degrees(),
    ]


exp6 = exercise(_CHAPTER, "exp6", LaterStepCheck(
    steps=lambda: {"rodrigues": reference_rodrigues, "skew": reference_skew},
    name="exp6(S, theta)",
    reference=_exp6_reference,
    variables=[*_AXIS, *_POINT, *_ANGLE],
    diagnoses=_exp6_mistakes(),
    noun="screw axes and angles",
    arguments=_exp6_arguments,
    signature="exp6(S, theta) -> (4, 4) array",
    hint="e^{[S]θ} = [[e^{[ω]θ}, G(θ) v], [0, 1]] for a unit ω.",
    doc="Check exp6(S, theta) -> e^{[S]θ} (4, 4) for a screw axis S = [ω; v] with a unit ω.",
))


def _fk_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    M, S = _home()
    return M.copy(), S.copy(), _theta(x)


def _fk_reference(x: np.ndarray) -> np.ndarray:
    return np.asarray(_ur10().fk(_theta(x)), dtype=float)


def _fk_mistakes():
    def variant(**kwargs):
        return lambda x: _product(*_fk_arguments(x), **kwargs)

    return [
        alternatives("product_order", [(variant(reverse=True), (
            "{name} multiplies the exponentials in the reverse order: which screw axes are still "
            "valid, in {{s}}, when joint i turns?"
        ))]),
        alternatives("M_on_left", [
            (variant(m_left=True), (
                "{name} puts M on the left: the screw axes S_i are written in the space frame {{s}}, "
                "so the exponentials act from the left on the home pose."
            )),
            (variant(with_m=False), (
                "{name} leaves out the home pose M: the product of exponentials moves M, the pose at "
                "θ = 0."
            )),
        ]),
        alternatives("missing_G", [(variant(with_g=False), (
            "the exponentials in {name} have the translation v θ: G(θ) is missing (the translation "
            "is G(θ) v, as in exp6)."
        ))]),
        dg.degrees(),
    ]


forward_kinematics = exercise(_CHAPTER, "forward_kinematics", LaterStepCheck(
    steps=lambda: {"exp6": reference_exp6},
    name="poe_fk(M, S_list, theta)",
    reference=_fk_reference,
    variables=_Q,
    diagnoses=_fk_mistakes(),
    noun="configurations",
    arguments=_fk_arguments,
    signature="poe_fk(M, S_list, theta) -> (4, 4) array",
    hint="The UR10's DH forward kinematics is the reference: compare poe_fk with ur10.fk.",
    doc="Check poe_fk(M, S_list, theta) -> the pose T(θ) (4, 4), on the UR10's M and screw axes.",
))


# ------------------------------------------------------------------ Task 4: adjoint and J_s
_POSE = [*[Variable(n, "angle", -np.pi, np.pi) for n in ("roll", "pitch", "yaw")],
         *[Variable(f"p_{c}", "length", -1.0, 1.0) for c in "xyz"]]


def _adjoint_arguments(x: np.ndarray) -> tuple[np.ndarray]:
    from robokin.transforms import rotation_from_rpy

    T = np.eye(4)
    T[:3, :3] = np.asarray(rotation_from_rpy(x[:3]), dtype=float)
    T[:3, 3] = x[3:6]
    return (T,)


def _adjoint_reference(x: np.ndarray) -> np.ndarray:
    return _adjoint(*_adjoint_arguments(x))


def _adjoint_mistakes():
    from robokin.transforms import transform_inverse

    def blocks(x, *, lower=None, order=False):
        (T,) = _adjoint_arguments(x)
        R, p = T[:3, :3], T[:3, 3]
        A = np.zeros((6, 6))
        A[:3, :3] = A[3:, 3:] = R
        A[3:, :3] = _skew(p) @ R if lower is None else lower(R, p)
        return _swap(_swap(A).T).T if order else A

    return [
        alternatives("twist_order", [(lambda x: blocks(x, order=True), (
            "{name} is the adjoint for twists ordered [v; ω]; the twists here are [ω; v], the "
            "angular part first."
        ))]),
        alternatives("product_order", [(lambda x: blocks(x, lower=lambda R, p: R @ _skew(p)), (
            "the lower-left block of {name} is R[p], the factors in the wrong order: the velocity "
            "gained at the fixed frame's origin comes from the angular velocity written in the "
            "fixed frame, Rω, not ω."
        ))]),
        alternatives("sign", [(lambda x: blocks(x, lower=lambda R, p: -_skew(p) @ R), (
            "the lower-left block of {name} has the wrong sign: the fixed frame's origin is at −p "
            "from the moved frame's, and [p]x = p × x."
        ))]),
        alternatives("inverse_transform", [(lambda x: _adjoint(transform_inverse(_adjoint_arguments(x)[0])), (
            "{name} is the adjoint of T⁻¹, [Ad_T]⁻¹: it maps twists from the fixed frame to the "
            "moved one, the opposite way."
        ))]),
    ]


adjoint = exercise(_CHAPTER, "adjoint", LaterStepCheck(
    steps=lambda: {"skew": reference_skew},
    name="adjoint_matrix(T)",
    reference=_adjoint_reference,
    variables=_POSE,
    diagnoses=_adjoint_mistakes(),
    noun="transforms",
    arguments=_adjoint_arguments,
    signature="adjoint_matrix(T) -> (6, 6) array",
    hint="[Ad_T] maps a twist [ω; v] written in the moved frame to the fixed one.",
    doc="Check adjoint_matrix(T) -> [Ad_T] (6, 6), for twists ordered [ω; v].",
))


def _space_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return _home()[1].copy(), _theta(x)


def _space_reference(x: np.ndarray) -> np.ndarray:
    return np.asarray(_ur10().space_jacobian(_theta(x)), dtype=float)


_ADJOINT_INVERSE_TEXT = (
    "{name} takes the adjoint of the inverse of the partial product: that moves the screw "
    "axis back, while the joints before joint i carry it forward from its home place."
)


def _space_mistakes():
    def variant(**kwargs):
        return lambda x: _space(*_space_arguments(x), **kwargs)

    return [
        alternatives("twist_order", [(lambda x: _swap(_space_reference(x)), (
            "the rows of {name} are ordered [v; ω]: the space Jacobian's columns are twists [ω; v]."
        ))]),
        alternatives("product_order", [(variant(reverse=True), (
            "{name} builds the partial products in the reverse order: multiply them in the order "
            "of the product of exponentials."
        ))]),
        alternatives("adjoint_of_inverse", [(variant(inverse=True), _ADJOINT_INVERSE_TEXT)]),
        alternatives("home_axes", [(variant(adjoint_on=False), (
            "{name} returns the screw axes at home: column i is joint i's screw axis at the "
            "configuration θ, carried by the motions of the joints before it."
        ))]),
        dg.degrees(),
    ]


space_jacobian = exercise(_CHAPTER, "space_jacobian", LaterStepCheck(
    steps=lambda: {"exp6": reference_exp6, "adjoint_matrix": reference_adjoint_matrix},
    name="jacobian_in_space(S_list, theta)",
    reference=_space_reference,
    variables=_Q,
    diagnoses=_space_mistakes(),
    noun="configurations",
    arguments=_space_arguments,
    signature="jacobian_in_space(S_list, theta) -> (6, n) array",
    hint="Column i is the screw axis of joint i moved by the joints before it.",
    doc="Check jacobian_in_space(S_list, theta) -> J_s (6, n), rows [ω; v], on the UR10.",
))


def _geometric_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    chain, theta = _ur10(), _theta(x)
    return np.asarray(chain.space_jacobian(theta), dtype=float), np.asarray(chain.fk(theta), dtype=float)


def _geometric_reference(x: np.ndarray) -> np.ndarray:
    return np.asarray(_ur10().jacobian(_theta(x)), dtype=float)


def _geometric_mistakes():
    def relation(sign: float):
        def f(x):
            Js, T = _geometric_arguments(x)
            return np.concatenate([Js[3:] + sign * _skew(T[:3, 3]) @ Js[:3], Js[:3]])
        return f

    return [
        alternatives("rows_swapped_only", [(relation(0.0), (
            "{name} only swaps the rows: v_s is the velocity of the body point at the origin of "
            "{{s}}, not of the end-effector's origin p: move it to p as for any rigid body."
        ))]),
        alternatives("cross_sign", [(relation(1.0), (
            "{name} moves the velocity to p with the wrong sign: mind the order of the cross "
            "product's factors (a × b = −b × a)."
        ))]),
        alternatives("twist_order", [(lambda x: _geometric_arguments(x)[0], (
            "{name} is J_s itself ([ω; v_s]); robokin's geometric Jacobian is [J_v; J_ω], "
            "J_v the velocity of the end-effector's origin."
        ))]),
    ]


geometric_from_space = exercise(_CHAPTER, "geometric_from_space", LaterStepCheck(
    steps=lambda: {"skew": reference_skew},
    name="geometric_from_space(J_s, T)",
    reference=_geometric_reference,
    variables=_Q,
    diagnoses=_geometric_mistakes(),
    noun="configurations",
    arguments=_geometric_arguments,
    signature="geometric_from_space(J_s, T) -> (6, n) array",
    hint=("v_s is the velocity of the body point at the origin of {s}; J_v needs that of the "
          "end-effector's origin p, the same rigid body's point at p."),
    doc="Check geometric_from_space(J_s, T) -> robokin's geometric Jacobian [J_v; J_ω] (6, n).",
))


# ------------------------------------------------------------------ Task 5: J_b
def _body_reference(x: np.ndarray) -> np.ndarray:
    return np.asarray(_ur10().body_jacobian(_theta(x)), dtype=float)


def _body_mistakes():
    from robokin.transforms import transform_inverse

    def with_adjoint(pick):
        def f(x):
            M, S, theta = _fk_arguments(x)
            T = _product(M, S, theta)
            return _adjoint(pick(T, M)) @ _space(S, theta)
        return f

    return [
        alternatives("adjoint_of_T", [(with_adjoint(lambda T, M: T), (
            "{name} is [Ad_T] J_s: [Ad_T] maps twists written in the end-effector frame to {{s}}, "
            "the opposite of the change of frame the body Jacobian needs."
        ))]),
        alternatives("home_pose", [(with_adjoint(lambda T, M: transform_inverse(M)), (
            "{name} is [Ad_{{M⁻¹}}] J_s: the home pose M in place of the current pose T(θ)."
        ))]),
        alternatives("space_jacobian", [(with_adjoint(lambda T, M: np.eye(4)), (
            "{name} is the space Jacobian J_s, its twists written in {{s}}; the body Jacobian's "
            "are written in the end-effector frame."
        ))]),
        alternatives("twist_order", [(lambda x: _swap(_body_reference(x)), (
            "the rows of {name} are ordered [v; ω]: the body Jacobian's columns are twists [ω; v]."
        ))]),
        dg.degrees(),
    ]


body_jacobian = exercise(_CHAPTER, "body_jacobian", LaterStepCheck(
    steps=lambda: {"poe_fk": reference_poe_fk, "jacobian_in_space": reference_jacobian_in_space,
                   "adjoint_matrix": reference_adjoint_matrix},
    name="jacobian_in_body(M, S_list, theta)",
    reference=_body_reference,
    variables=_Q,
    diagnoses=_body_mistakes(),
    noun="configurations",
    arguments=_fk_arguments,
    signature="jacobian_in_body(M, S_list, theta) -> (6, n) array",
    hint=("J_b holds the joints' twists of J_s written in the end-effector frame at the "
          "current pose: a change of frame as in Task 4."),
    doc="Check jacobian_in_body(M, S_list, theta) -> J_b (6, n), rows [ω; v], on the UR10.",
))


# ------------------------------------------------------------------ Task 6: IK with the body twist
_OFFSET = [Variable(f"offset{i}", "other", -0.3, 0.3) for i in range(1, 7)]


def _ik_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    M, S = _home()
    goal = np.asarray(_ur10().fk(_theta(x)), dtype=float)
    return M.copy(), S.copy(), goal, _theta(x) + np.asarray(x[6:12], dtype=float)


def _ik_reference(x: np.ndarray) -> np.ndarray:
    return np.asarray(_ur10().fk(_theta(x)), dtype=float)


def _configuration(result: Any) -> np.ndarray:
    """The joint angles of an answer ``(theta, iterations)`` (a tuple or, handed over, a list)."""
    if isinstance(result, (tuple, list)) and len(result) == 2 and np.ndim(result[1]) == 0:
        result = result[0]
    return np.asarray(result, dtype=float)


def _pose_reached(result: Any) -> np.ndarray:
    """The pose (4×4) that the joint angles of an answer ``(theta, iterations)`` reach."""
    return np.asarray(_ur10().fk(_configuration(result)), dtype=float)


def _ik_mistakes():
    def start_pose(x):
        return np.asarray(_ur10().fk(_ik_arguments(x)[3]), dtype=float)

    return [
        alternatives("not_updated", [(start_pose, (
            "the joint angles {name} returns reach the pose of the start: the loop does not update "
            "θ after each Newton step."
        ))]),
    ]


#: the Newton steps a typical mistake takes from the start (code, the twist, the Jacobian, the sign
#: of the step, the message): each step of the loop sends the chain far off when the twist and the
#: Jacobian do not match, so the pose after 30 steps depends on the last bits of every number and
#: cannot be rebuilt; the first step can, and names the mistake
_FIRST_STEP_MISTAKES = (
    ("twist_in_space", "space", "body", 1.0, (
        "the first Newton step of {name} uses the error twist written in the base frame {{s}} with "
        "the body Jacobian J_b, whose columns are written in the flange frame: the twist and the "
        "Jacobian of one linearisation must be written in the same frame (a body twist is the "
        "motion from T(θ) to T_goal seen from the flange)."
    )),
    ("jacobian_in_space", "body", "space", 1.0, (
        "the first Newton step of {name} uses the body twist with the space Jacobian J_s, whose "
        "columns are written in {{s}}: the twist and the Jacobian of one linearisation must be "
        "written in the same frame."
    )),
    ("step_sign", "body", "body", -1.0, (
        "the first Newton step of {name} moves away from the goal: the error twist is the motion "
        "from T(θ) to T_goal, and the step Δθ makes J_b Δθ equal to it (check the order of the two "
        "poses in the twist and the sign of the update)."
    )),
)


def _newton_step(M: np.ndarray, S: np.ndarray, goal: np.ndarray, theta: np.ndarray, twist: str,
                 jacobian: str, sign: float) -> np.ndarray:
    """One Newton step of ``ik_body`` from ``theta`` with the given twist, Jacobian and sign."""
    from robokin.transforms import transform_inverse, transform_log

    T = _product(M, S, theta)
    error = goal @ transform_inverse(T) if twist == "space" else transform_inverse(T) @ goal
    J = (_space(S, theta) if jacobian == "space"
         else _adjoint(transform_inverse(T)) @ _space(S, theta))
    return theta + sign * np.linalg.pinv(J) @ np.asarray(transform_log(error), dtype=float)


@dataclass(repr=False)
class _IKBodyCheck(LaterStepCheck):
    """The check of ``ik_body``: the pose reached; an answer whose pose no typical mistake
    explains is then asked for one step (``max_iterations = 1``, the sixth argument of the
    statement's signature), which a mistake in the step's frames or sign reproduces."""

    def evaluate(self, answer: Any) -> CheckResult:
        """:meth:`LaterStepCheck.evaluate`, then the first step of an unexplained wrong loop."""
        result = super().evaluate(answer)
        if result.passed or result.diagnosis != "mismatch" or not callable(answer):
            return result
        student = with_reference_steps(answer, self.steps())
        firsts: list[np.ndarray] = []
        mistaken: dict[str, list[np.ndarray]] = {code: [] for code, *_ in _FIRST_STEP_MISTAKES}
        for x in self.sample_points()[:5]:
            M, S, goal, start = _ik_arguments(x)
            try:
                with np.errstate(all="ignore"):
                    firsts.append(_configuration(student(M.copy(), S.copy(), goal.copy(), start.copy(),
                                                         1e-10, 1)))
            except Exception:  # noqa: BLE001 - an answer that cannot take one step is not diagnosed
                return result
            for code, twist, jacobian, sign, _ in _FIRST_STEP_MISTAKES:
                mistaken[code].append(_newton_step(M, S, goal, start, twist, jacobian, sign))
        yours = np.array(firsts)
        for code, *_, text in _FIRST_STEP_MISTAKES:
            if yours.shape == np.shape(mistaken[code]) and np.allclose(yours, mistaken[code], atol=1e-8):
                return self._fail(code, text.format(name=self.name), result.samples)
        return result


ik_body = exercise(_CHAPTER, "ik_body", _IKBodyCheck(
    steps=lambda: {"poe_fk": reference_poe_fk, "jacobian_in_body": reference_jacobian_in_body},
    name="ik_body(M, S_list, T_goal, theta_start)",
    reference=_ik_reference,
    variables=[*_Q, *_OFFSET],
    diagnoses=_ik_mistakes(),
    noun="goals and starts",
    arguments=_ik_arguments,
    signature="ik_body(M, S_list, T_goal, theta_start) -> (theta, iterations)",
    hint=("The pose reached, T(θ) of the angles returned, is compared with the goal; the error "
          "is the body twist that carries the flange from T(θ) to T_goal in unit time, written "
          "in the flange frame."),
    doc="Check ik_body(M, S_list, T_goal, theta_start) -> (theta, iterations): T(theta) must be the goal.",
    pack=_pose_reached,
))


# ------------------------------------------------------------------ robokin's steps, for the tests
def _angle(theta: Any) -> float:
    a = as_float_array(theta, "theta", ())
    return float(a)


def _screws_and_angles(S_list: Any, theta: Any) -> tuple[np.ndarray, np.ndarray]:
    S = as_float_array(S_list, "S_list", (None, 6))
    angles = as_float_array(theta, "theta", (None,))
    if len(angles) != len(S):
        raise ValueError(f"theta must hold one angle per screw axis ({len(S)}); got {len(angles)}")
    return S, angles


def reference_skew(w: Any) -> np.ndarray:
    """robokin's answer to ``skew`` of Task 1 (the tests' stand-in).

    The graded tests of ``exp6``, ``adjoint_matrix`` and ``geometric_from_space`` pass it to the
    student's functions in place of the student's ``skew``, so that a mistake in ``skew`` costs
    the points of Task 1 only.

    Parameters
    ----------
    w : array_like, shape (3,)
        A 3-vector.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        The skew-symmetric matrix [w] with [w] x = w × x.
    """
    return _skew(as_float_array(w, "w", (3,)))


def reference_rodrigues(omega: Any, theta: Any) -> np.ndarray:
    """robokin's answer to ``rodrigues`` of Task 1 (the tests' stand-in).

    The graded test of ``exp6`` passes it to the student's ``exp6`` in place of the student's
    own, so that a mistake in ``rodrigues`` costs the points of its own test only.

    Parameters
    ----------
    omega : array_like, shape (3,)
        A unit axis.
    theta : float
        The angle (rad).

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        The rotation by ``theta`` about ``omega`` (robokin's ``rotation_exp(omega * theta)``).
    """
    from robokin.transforms import rotation_exp

    return np.asarray(rotation_exp(as_float_array(omega, "omega", (3,)) * _angle(theta)), dtype=float)


def reference_screw_axis(omega: Any, point: Any) -> np.ndarray:
    """robokin's answer to ``screw_axis`` of Task 2 (the tests' stand-in).

    The graded test of ``screw_axes_at_home`` passes it to the student's function in place of
    the student's ``screw_axis``, so that a mistake in ``screw_axis`` costs the points of its
    own test only.

    Parameters
    ----------
    omega : array_like, shape (3,)
        The unit axis of a revolute joint, in the base frame.
    point : array_like, shape (3,)
        A point of the axis, in the base frame (m).

    Returns
    -------
    numpy.ndarray, shape (6,)
        The joint's screw axis [ω; v].
    """
    axis = as_float_array(omega, "omega", (3,))
    return np.concatenate([axis, -np.cross(axis, as_float_array(point, "point", (3,)))])


def reference_exp6(S: Any, theta: Any) -> np.ndarray:
    """robokin's answer to ``exp6`` of Task 3 (the tests' stand-in).

    The graded tests of ``poe_fk`` and ``jacobian_in_space`` pass it to the student's functions
    in place of the student's ``exp6``, so that a mistake in ``exp6`` costs the points of its own
    test only.

    Parameters
    ----------
    S : array_like, shape (6,)
        A screw axis [ω; v].
    theta : float
        The angle (rad).

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        The motion by ``theta`` about ``S`` (robokin's ``transform_exp(S * theta)``).
    """
    from robokin.transforms import transform_exp

    return np.asarray(transform_exp(as_float_array(S, "S", (6,)) * _angle(theta)), dtype=float)


def reference_poe_fk(M: Any, S_list: Any, theta: Any) -> np.ndarray:
    """robokin's answer to ``poe_fk`` of Task 3 (the tests' stand-in).

    The graded tests of ``jacobian_in_body`` and ``ik_body`` pass it to the student's functions
    in place of the student's ``poe_fk``.

    Parameters
    ----------
    M : array_like, shape (4, 4)
        The home pose of the end effector.
    S_list : array_like, shape (n, 6)
        The screw axes [ω; v] in the base frame, one per row.
    theta : array_like, shape (n,)
        The joint angles (rad).

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        The pose of the end effector, with robokin's exponentials.
    """
    home = as_float_array(M, "M", (4, 4))
    S, angles = _screws_and_angles(S_list, theta)
    return _product(home, S, angles)


def reference_adjoint_matrix(T: Any) -> np.ndarray:
    """robokin's answer to ``adjoint_matrix`` of Task 4 (the tests' stand-in).

    The graded tests of ``jacobian_in_space`` and ``jacobian_in_body`` pass it to the student's
    functions in place of the student's ``adjoint_matrix``.

    Parameters
    ----------
    T : array_like, shape (4, 4)
        A homogeneous transform.

    Returns
    -------
    numpy.ndarray, shape (6, 6)
        robokin's ``adjoint(T)``, for twists ordered [ω; v].
    """
    return _adjoint(as_float_array(T, "T", (4, 4)))


def reference_jacobian_in_space(S_list: Any, theta: Any) -> np.ndarray:
    """robokin's answer to ``jacobian_in_space`` of Task 4 (the tests' stand-in).

    The graded tests of ``jacobian_in_body`` pass it to the student's function in place of the
    student's own.

    Parameters
    ----------
    S_list : array_like, shape (n, 6)
        The screw axes [ω; v] in the base frame, one per row.
    theta : array_like, shape (n,)
        The joint angles (rad).

    Returns
    -------
    numpy.ndarray, shape (6, n)
        The space Jacobian, rows [ω; v], with robokin's exponentials and adjoint.
    """
    return _space(*_screws_and_angles(S_list, theta))


def reference_jacobian_in_body(M: Any, S_list: Any, theta: Any) -> np.ndarray:
    """robokin's answer to ``jacobian_in_body`` of Task 5 (the tests' stand-in).

    The graded tests of ``ik_body`` pass it to the student's function in place of the student's
    own.

    Parameters
    ----------
    M : array_like, shape (4, 4)
        The home pose of the end effector.
    S_list : array_like, shape (n, 6)
        The screw axes [ω; v] in the base frame, one per row.
    theta : array_like, shape (n,)
        The joint angles (rad).

    Returns
    -------
    numpy.ndarray, shape (6, n)
        The body Jacobian, rows [ω; v], with robokin's exponentials and adjoint.
    """
    from robokin.transforms import transform_inverse

    home = as_float_array(M, "M", (4, 4))
    S, angles = _screws_and_angles(S_list, theta)
    return _adjoint(transform_inverse(_product(home, S, angles))) @ _space(S, angles)
