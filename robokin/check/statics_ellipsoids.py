r"""Exercise checks of chapter 9: statics and the velocity and force ellipsoids.

The exercise's arm is :func:`robokin.models.planar_two_link` with :math:`l_1 = 1` m and
:math:`l_2 = 0.6` m (:data:`LINKS`); the functions of Tasks 2–6 take a Jacobian, and the checks
hand them the arm's 2×2 position Jacobian at random configurations away from its singularities.

=======================  =========================================================  ==============
check                    the student's answer                                       inputs
=======================  =========================================================  ==============
``tool_jacobian``        J(q) = ∂p/∂q of the tool position, 2×2, m/rad              q1, q2
``joint_torques``        τ(q, F), N·m, for the tool force F (N)                     q1, q2, Fx, Fy
``leg_torques``          τ(q, m): chapter 1's leg holding a body of mass m (kg)     α, β, γ, m
                         on its foot, N·m
``velocity_ellipse``     (radii, axes) of {J q̇ : ‖q̇‖ ≤ 1}, radii descending         J (2×2)
``force_ellipse``        (radii, axes) of {F : ‖Jᵀ F‖ ≤ 1}, radii descending        J (2×2)
``force_from_velocity``  the force ellipse from the velocity ellipse alone          radii_v, axes_v
``manipulability``       w(J) = √det(J Jᵀ)                                          J (2×2)
``w_formula``            w of the two-link arm in closed form, f(q2, l1, l2)        q2, l1, l2
``condition_number``     κ(J) = σ_max / σ_min                                       J (2×2)
``push_capacity``        the largest force along the unit d with ‖Jᵀ F‖ ≤ 1          J (2×2), d
``posture_measures``     (w, κ, σ_min) of a Jacobian                                J (2×2)
=======================  =========================================================  ==============

Each check compares with robokin's reference at 20 seeded random inputs (to an absolute
tolerance of 1e-8 and a relative one of 1e-6 unless a check says otherwise). An ellipse
answer is compared with its axes' signs made canonical (each column's largest-magnitude
entry positive): an axis and its opposite describe the same ellipse. A wrong answer is
explained when one of the chapter's typical mistakes reproduces it (a transpose, squared or
inverted lengths, the radii in ascending order, radii and axes sorted apart, degrees for
radians).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache, partial
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    AnswerError,
    Check,
    CheckResult,
    MatrixArgumentsCheck,
    Variable,
    alternatives,
)
from robokin.check._registry import exercise
from robokin.errors import ShapeError
from robokin.validation import as_float_array

__all__ = [
    "LINKS",
    "condition_number",
    "force_ellipse",
    "force_from_velocity",
    "joint_torques",
    "leg_torques",
    "manipulability",
    "posture_measures",
    "push_capacity",
    "reference_posture_measures",
    "reference_tool_jacobian",
    "reference_velocity_ellipse",
    "tool_jacobian",
    "velocity_ellipse",
    "w_formula",
]

_CHAPTER = "statics_ellipsoids"

#: the exercise arm's link lengths l1, l2 (m)
LINKS = (1.0, 0.6)

#: the gravity of the chapter (m/s²)
GRAVITY = 9.81

#: check -> {the robokin function that solves its task: how the grading report names it}: an
#: answer that hands one back (``tool_jacobian = ...position_jacobian``) is flagged for review by
#: hand (tools/grading/bridge/delegation.py reads this literal table without importing the module).
#: ``manipulability`` and ``condition_number`` are left out: the answers take a Jacobian, robokin's
#: methods of the same names a configuration, and the finder would take the answer's own name
#: (``manipulability = ...``) for a call of robokin's.
DELEGATION = {
    "tool_jacobian": {"position_jacobian": "SerialChain.position_jacobian", "jacobian": "SerialChain.jacobian",
                      "reference_tool_jacobian": "robokin.check.statics_ellipsoids.reference_tool_jacobian"},
    "joint_torques": {"static_torques": "robokin.chains.ellipsoids.static_torques",
                      "reference_tool_jacobian": "robokin.check.statics_ellipsoids.reference_tool_jacobian"},
    "leg_torques": {"static_torques": "robokin.chains.ellipsoids.static_torques"},
    "velocity_ellipse": {"velocity_ellipsoid": "robokin.chains.ellipsoids.velocity_ellipsoid",
                         "reference_velocity_ellipse": "robokin.check.statics_ellipsoids.reference_velocity_ellipse"},
    "force_ellipse": {"force_ellipsoid": "robokin.chains.ellipsoids.force_ellipsoid",
                      "reference_velocity_ellipse": "robokin.check.statics_ellipsoids.reference_velocity_ellipse"},
    "posture_measures": {
        "reference_posture_measures": "robokin.check.statics_ellipsoids.reference_posture_measures"},
    # the closed form derived, not w evaluated numerically on a model of the arm built by the answer
    "w_formula": {"planar_two_link": "robokin.models.planar_two_link",
                  "position_jacobian": "SerialChain.position_jacobian"},
}


@lru_cache(maxsize=1)
def _arm():
    from robokin.models import planar_two_link

    return planar_two_link(*LINKS)


def _jacobian(x: np.ndarray) -> np.ndarray:
    return np.asarray(_arm().position_jacobian(np.asarray(x[:2], dtype=float)), dtype=float)[:2]


# Configurations away from the singular q2 = 0, π; the angle of d last where there is one.
_Q = [Variable("q1"), Variable("q2", "angle", 0.4, 2.7)]
_ANGLE_D = Variable("direction_angle", "other", -np.pi, np.pi)


def _signed(axes: np.ndarray) -> np.ndarray:
    """The axes (columns) with the sign that makes each one's largest-magnitude entry positive."""
    largest = axes[np.argmax(np.abs(axes), axis=0), np.arange(axes.shape[1])]
    return axes * np.where(largest < 0.0, -1.0, 1.0)


def _canonical(pair: Any, name: str) -> np.ndarray:
    """``(radii (2,), axes (2, 2))`` as one array: the radii, then the signed axes row by row."""
    if not isinstance(pair, (tuple, list)) or len(pair) != 2:
        raise AnswerError("shape", f"{name} should return a pair (radii, axes); it returned "
                                   f"{type(pair).__name__}" + (f" of {len(pair)} items" if isinstance(
                                       pair, (tuple, list)) else "") + ".")
    try:
        radii = np.asarray(pair[0], dtype=float).ravel()
        axes = np.asarray(pair[1], dtype=float)
    except (TypeError, ValueError) as exc:
        raise AnswerError("shape", f"{name}: the radii and axes should be arrays of numbers ({exc}).") from None
    if radii.shape != (2,) or axes.shape != (2, 2):
        raise AnswerError("shape", f"{name} for a 2×2 Jacobian should return radii of shape (2,) and "
                                   f"axes of shape (2, 2); got {radii.shape} and {axes.shape}.")
    return np.concatenate([radii, _signed(axes).ravel()])


class _EllipseCheck(MatrixArgumentsCheck):
    """A check of a function ``f(J) -> (radii, axes)``, compared in canonical form (``pack``)."""

    def evaluate(self, answer: Any) -> CheckResult:
        if callable(answer) and not isinstance(answer, np.ndarray) and self.arguments is not None:
            try:   # the form of the pair, told as such (not as an error raised by the answer)
                _canonical(answer(*self.arguments(self.sample_points()[0])), self.name)
            except AnswerError as exc:
                return self._fail(exc.code, exc.message, 1)
            except Exception:  # noqa: BLE001 - the evaluation below reports the student's error
                pass
        return super().evaluate(answer)


def _number(value: Any) -> Any:
    """A value of one entry ((), (1,), (1, 1)) as a number; any other value as it is."""
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return value   # reported by the check as it is
    return array.reshape(()) if array.size == 1 else value


def _as_number(answer: Any) -> Any:
    """A function answer whose values of one entry ((), (1,), (1, 1)) become numbers."""
    if not callable(answer) or isinstance(answer, np.ndarray):
        return answer

    def number(*arguments: Any) -> Any:
        return _number(answer(*arguments))

    return number


class _ScalarCheck(Check):
    """A check of a function of scalars with a number for value."""

    def evaluate(self, answer: Any) -> CheckResult:
        return super().evaluate(_as_number(answer))


def _svd(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    U, sigma, Vt = np.linalg.svd(_jacobian(x))
    return U, sigma, Vt.T


def _pair(radii: np.ndarray, axes: np.ndarray) -> np.ndarray:
    return np.concatenate([radii, _signed(axes).ravel()])


def _ellipse_mistakes(force: bool, from_velocity: bool = False) -> list:
    def make(transform: Callable[[np.ndarray, np.ndarray, np.ndarray], tuple]) -> Callable:
        def mistaken(x: np.ndarray) -> np.ndarray:
            return _pair(*transform(*_svd(x)))
        return mistaken

    def rev(a: np.ndarray) -> np.ndarray:
        return a[..., ::-1]

    unpaired = (
        "{name} orders the radii and the axes differently: column i of the axes must be the axis "
        "of radii[i]. Sort the eigenvectors with the same index as the eigenvalues "
        "(order = np.argsort(...); radii[order], axes[:, order]).")
    if from_velocity:
        unpaired = (
            "{name} orders the radii and the axes differently: column i of the axes must be the "
            "axis of radii[i], so reversing the order of the radii reverses the columns of the "
            "axes too.")
    squared = (
        "{name} returns squared lengths" + (" (or their reciprocals)" if force else "") + ": the "
        "eigenvalues of J Jᵀ have the unit of a length squared, and a semi-axis is a length "
        "(compare the units)."
    )
    if force:
        items = [
            alternatives("not_inverted", [
                (make(lambda U, s, V: (s, U)), (
                    "{name} has the velocity ellipse's lengths σ_i: write ‖Jᵀ F‖² = Fᵀ J Jᵀ F in "
                    "the coordinates of the eigenvectors of J Jᵀ and read the semi-axes of "
                    "{{F : ‖Jᵀ F‖ ≤ 1}} there (does a direction the arm moves fast in need much "
                    "torque or little?).")),
                (make(lambda U, s, V: (rev(s), rev(U))), (
                    "{name} has the velocity ellipse's lengths σ_i, in reverse order: the force "
                    "ellipse {{F : ‖Jᵀ F‖ ≤ 1}} is not the velocity ellipse; read its semi-axes from "
                    "Fᵀ J Jᵀ F in the coordinates of the eigenvectors of J Jᵀ.")),
            ]),
            alternatives("squared", [
                (make(lambda U, s, V: (rev(1 / s**2), rev(U))), squared),
                (make(lambda U, s, V: (rev(s**2), rev(U))), squared),
            ]),
            alternatives("ascending", [(make(lambda U, s, V: (1 / s, U)), (
                "{name} lists the radii in ascending order: give them descending, each axis in "
                "the column of its radius."))]),
            alternatives("axes_not_reordered", [
                (make(lambda U, s, V: (rev(1 / s), U)), unpaired),
                (make(lambda U, s, V: (1 / s, rev(U))), unpaired),
            ]),
        ]
        if not from_velocity:  # (no J to transpose: the answer is given the velocity ellipse)
            items.append(alternatives("jacobian_not_transposed", [(
                make(lambda U, s, V: (rev(1 / s), rev(V))), (
                    "the axes of {name} are the eigenvectors of Jᵀ J (joint space), as if J and Jᵀ "
                    "were swapped: the force ellipse lies in the task space, with the eigenvectors "
                    "of J Jᵀ (the left singular vectors u_i of J)."))]))
    else:
        items = [
            alternatives("squared", [
                (make(lambda U, s, V: (s**2, U)), squared),
                (make(lambda U, s, V: (rev(s**2), rev(U))), squared),
            ]),
            alternatives("inverted", [(make(lambda U, s, V: (rev(1 / s), rev(U))), (
                "{name} has reciprocal lengths: the velocity ellipse {{J q̇ : ‖q̇‖ ≤ 1}} grows "
                "with J (double J and every semi-axis doubles)."))]),
            alternatives("ascending", [(make(lambda U, s, V: (rev(s), rev(U))), (
                "{name} lists the radii in ascending order (as numpy.linalg.eigh returns "
                "eigenvalues): give them descending, each axis in the column of its radius."))]),
            alternatives("axes_not_reordered", [
                (make(lambda U, s, V: (s, rev(U))), unpaired),
                (make(lambda U, s, V: (rev(s), U)), unpaired),
            ]),
            alternatives("jacobian_not_transposed", [(make(lambda U, s, V: (s, V)), (
                "the axes of {name} are the eigenvectors of Jᵀ J (joint space), as if J and Jᵀ were "
                "swapped: the ellipse of tool velocities lies in the task space, with the "
                "eigenvectors of J Jᵀ (the left singular vectors u_i of J)."))]),
        ]
    return items


def _one_jacobian(x: np.ndarray) -> tuple[np.ndarray]:
    return (_jacobian(x),)


def _velocity_pair(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The velocity ellipse ``(radii_v, axes_v)`` of the arm's Jacobian at ``x``, from NumPy's SVD."""
    U, sigma, _ = np.linalg.svd(_jacobian(x))
    return sigma, U


def _ellipse_check(name: str, force: bool, doc: str, from_velocity: bool = False) -> _EllipseCheck:
    def reference(x: np.ndarray) -> np.ndarray:
        U, s, _ = _svd(x)
        return _pair(1.0 / s[::-1], U[:, ::-1]) if force else _pair(s, U)

    arguments: Callable[[np.ndarray], tuple]
    if from_velocity:
        arguments, signature, noun = (_velocity_pair, f"{name}(radii_v, axes_v) -> (radii (m,), axes (m, m))",
                                      "velocity ellipses of the arm")
        hint = ("Compare the two sets in the coordinates of the eigenvectors of J Jᵀ: which axes, "
                "which lengths, in which order (radii descending)?")
    else:
        arguments, signature, noun = _one_jacobian, f"{name}(J) -> (radii (m,), axes (m, m))", "Jacobians of the arm"
        hint = ("Write the set's boundary in the coordinates of the eigenvectors of J Jᵀ; radii "
                "descending, each axis in the column of its radius.")
    return _EllipseCheck(
        name=name,
        reference=reference,
        variables=_Q,
        diagnoses=_ellipse_mistakes(force, from_velocity),
        noun=noun,
        arguments=arguments,
        signature=signature,
        pack=partial(_canonical, name=name),
        hint=hint,
        doc=doc,
    )


# ------------------------------------------------------------------ Task 1: statics
tool_jacobian = exercise(_CHAPTER, "tool_jacobian", Check(
    name="tool_jacobian",
    reference=_jacobian,
    variables=[Variable("q1"), Variable("q2")],
    groups=[("q", [0, 1])],
    diagnoses=dg.standard("jacobian"),
    noun="angles",
    hint="Column j of J is ∂p/∂q_j: differentiate both rows of p(q) (l1 = 1 m, l2 = 0.6 m).",
    doc="Check tool_jacobian(q): the 2×2 Jacobian ∂p/∂q of the exercise arm's tool position, m/rad.",
))


def _torques_reference(x: np.ndarray) -> np.ndarray:
    return _jacobian(x).T @ x[2:4]


def _torques_mistakes() -> list:
    return [
        alternatives("jacobian_not_transposed", [(lambda x: _jacobian(x) @ x[2:4], (
            "{name} multiplies the force by J, which maps joint rates to tool velocities: forces "
            "go the other way. Write the virtual work, τ·δq = F·δp with δp = J δq, for every δq, "
            "and read which matrix maps F to τ."))]),
        alternatives("sign", [(lambda x: -_torques_reference(x), (
            "{name} has the opposite sign: the torques asked for make the tool push with F (they "
            "hold it against the environment's −F); check the signs of the virtual work "
            "balance."))]),
        dg.degrees(),
    ]


joint_torques = exercise(_CHAPTER, "joint_torques", Check(
    name="joint_torques",
    reference=_torques_reference,
    variables=[Variable("q1"), Variable("q2"), Variable("Fx", "other", -20.0, 20.0),
               Variable("Fy", "other", -20.0, 20.0)],
    groups=[("q", [0, 1]), ("F", [2, 3])],
    diagnoses=_torques_mistakes(),
    noun="configurations and forces",
    hint="Virtual work: the motors' work τ·δq equals the tool's work F·δp for every δq.",
    doc=("Check joint_torques(q, F): the torques τ (N·m) with which the arm's tool pushes with F (N), "
         "compared with the reference at 20 random configurations and forces."),
))


@lru_cache(maxsize=1)
def _leg():
    from robokin.models import eth_leg

    return eth_leg()


def _foot_jacobian(x: np.ndarray) -> np.ndarray:
    return np.asarray(_leg().position_jacobian(np.asarray(x[:3], dtype=float)), dtype=float)


def _leg_force(x: np.ndarray) -> np.ndarray:
    """The force (N) with which the foot pushes on the ground: the body's weight, down."""
    return np.array([0.0, 0.0, -x[3] * GRAVITY])


class _MassCheck(Check):
    """A check of a function ``f(q, m)`` whose mass ``m`` is handed over as a number."""

    def evaluate(self, answer: Any) -> CheckResult:
        if callable(answer) and not isinstance(answer, np.ndarray):
            student = answer

            def with_number(q: np.ndarray, m: np.ndarray) -> Any:
                return student(q, float(np.asarray(m, dtype=float).reshape(-1)[0]))

            return super().evaluate(with_number)
        return super().evaluate(answer)


leg_torques = exercise(_CHAPTER, "leg_torques", _MassCheck(
    name="leg_torques",
    reference=lambda x: _foot_jacobian(x).T @ _leg_force(x),
    variables=[Variable("alpha", "angle", -0.5, 0.5), Variable("beta", "angle", -1.2, 0.8),
               Variable("gamma", "angle", 0.3, 2.0), Variable("m", "other", 1.0, 30.0)],
    groups=[("q", [0, 1, 2]), ("m", [3])],
    diagnoses=[
        alternatives("sign", [(lambda x: -_foot_jacobian(x).T @ _leg_force(x), (
            "{name} has the opposite sign: which way does the foot push on the ground, and which "
            "way does a hand holding a load push on it? The body's potential energy decides: "
            "raise the body by a virtual displacement and compare the motors' work with the "
            "change of its energy."))]),
        alternatives("jacobian_not_transposed", [(lambda x: _foot_jacobian(x) @ _leg_force(x), (
            "{name} multiplies the force by J, which maps joint rates to foot velocities: "
            "forces go the other way (virtual work)."))]),
        alternatives("no_gravity", [(lambda x: _foot_jacobian(x).T @ _leg_force(x) / GRAVITY, (
            "{name} uses the mass m (kg) as a force: the weight is m g, g = 9.81 m/s²."))]),
        dg.degrees(),
    ],
    noun="configurations of the leg and body masses",
    hint="Which force, in which frame and with which sign? The body's potential energy decides.",
    doc="Check leg_torques(q, m): the torques (N·m) of chapter 1's leg holding a body of m kg on its foot.",
))


# ------------------------------------------------------------------ Tasks 2 and 3: the ellipses
velocity_ellipse = exercise(_CHAPTER, "velocity_ellipse", _ellipse_check(
    "velocity_ellipse", False,
    ("Check velocity_ellipse(J) -> (radii, axes): the semi-axes' lengths in descending order and "
     "the unit axes as columns, compared with the reference at 20 random Jacobians of the arm."),
))

force_ellipse = exercise(_CHAPTER, "force_ellipse", _ellipse_check(
    "force_ellipse", True,
    ("Check force_ellipse(J) -> (radii, axes): the semi-axes' lengths in descending order and "
     "the unit axes as columns, compared with the reference at 20 random Jacobians of the arm."),
))

force_from_velocity = exercise(_CHAPTER, "force_from_velocity", _ellipse_check(
    "force_from_velocity", True,
    ("Check force_from_velocity(radii_v, axes_v) -> (radii, axes): the force ellipse of a Jacobian "
     "from its velocity ellipse alone (radii descending, unit axes as columns), compared with the "
     "reference at the velocity ellipses (NumPy's SVD) of 20 random Jacobians of the arm."),
    from_velocity=True,
))


# ------------------------------------------------------------------ Task 4: measures
def _sigma(x: np.ndarray) -> np.ndarray:
    return np.linalg.svd(_jacobian(x), compute_uv=False)


manipulability = exercise(_CHAPTER, "manipulability", MatrixArgumentsCheck(
    name="manipulability",
    reference=lambda x: np.sqrt(np.linalg.det(_jacobian(x) @ _jacobian(x).T)),
    variables=_Q,
    diagnoses=[
        alternatives("squared", [(lambda x: np.linalg.det(_jacobian(x) @ _jacobian(x).T), (
            "{name} returns det(J Jᵀ) = w²: take the square root, w = √det(J Jᵀ) (the product of "
            "the semi-axes σ_i)."))]),
        alternatives("signed", [(lambda x: np.linalg.det(_jacobian(x)), (
            "{name} returns det J, which is negative for half of the configurations: "
            "w = √det(J Jᵀ) ≥ 0."))]),
    ],
    noun="Jacobians of the arm",
    arguments=_one_jacobian,
    signature="manipulability(J) -> float",
    doc="Check manipulability(J) -> w = √det(J Jᵀ).",
    pack=_number,
))

w_formula = exercise(_CHAPTER, "w_formula", _ScalarCheck(
    name="w_formula",
    reference=lambda x: np.abs(x[1] * x[2] * np.sin(x[0])),
    variables=[Variable("q2"), Variable("l1", "length", 0.2, 1.5), Variable("l2", "length", 0.2, 1.5)],
    diagnoses=[
        alternatives("absolute_value", [(lambda x: x[1] * x[2] * np.sin(x[0]), (
            "{name} is negative for q2 in (−π, 0): w = √det(J Jᵀ) is a square root, never "
            "negative."))]),
        alternatives("squared", [(lambda x: (x[1] * x[2] * np.sin(x[0])) ** 2, (
            "{name} is det(J Jᵀ) = w²: take the square root."))]),
        dg.degrees(),
    ],
    noun="elbow angles and link lengths",
    hint="det(J Jᵀ) = (det J)² for the square J of the arm.",
    doc="Check w_formula(q2, l1, l2): the two-link arm's manipulability in closed form.",
))

condition_number = exercise(_CHAPTER, "condition_number", MatrixArgumentsCheck(
    name="condition_number",
    reference=lambda x: _sigma(x)[0] / _sigma(x)[-1],
    variables=_Q,
    diagnoses=[
        alternatives("squared", [(lambda x: (_sigma(x)[0] / _sigma(x)[-1]) ** 2, (
            "{name} is the ratio of the eigenvalues of J Jᵀ, σ_max²/σ_min²: the condition number "
            "is the ratio of the semi-axes, σ_max/σ_min."))]),
        alternatives("inverted", [(lambda x: _sigma(x)[-1] / _sigma(x)[0], (
            "{name} is σ_min/σ_max ≤ 1: the condition number is σ_max/σ_min ≥ 1 (1 for an "
            "isotropic arm, infinite at a singularity)."))]),
    ],
    noun="Jacobians of the arm",
    arguments=_one_jacobian,
    signature="condition_number(J) -> float",
    doc="Check condition_number(J) -> κ = σ_max / σ_min.",
    pack=_number,
))


# ------------------------------------------------------------------ Task 5: the push along d
def _direction(x: np.ndarray) -> np.ndarray:
    return np.array([np.cos(x[2]), np.sin(x[2])])


def _push_reference(x: np.ndarray) -> np.ndarray:
    return np.asarray(1.0 / np.linalg.norm(_jacobian(x).T @ _direction(x)))


push_capacity = exercise(_CHAPTER, "push_capacity", MatrixArgumentsCheck(
    name="push_capacity",
    reference=_push_reference,
    variables=[*_Q, _ANGLE_D],
    diagnoses=[
        alternatives("not_inverted", [(lambda x: np.asarray(np.linalg.norm(_jacobian(x).T @ _direction(x))), (
            "{name} returns ‖Jᵀ d‖, the torque norm a unit force along d costs: how large may f "
            "grow before the force f d costs a torque norm of 1?"))]),
        alternatives("jacobian_not_transposed", [(
            lambda x: np.asarray(1.0 / np.linalg.norm(_jacobian(x) @ _direction(x))), (
                "{name} uses J d: J maps joint rates to tool velocities; the torques a force "
                "costs come from virtual work, as in Task 1.")),
        ]),
        alternatives("squared", [(lambda x: np.asarray(1.0 / np.linalg.norm(_jacobian(x).T @ _direction(x)) ** 2), (
            "{name} is 1/‖Jᵀ d‖²: the torque norm of the force f d grows in proportion to f, "
            "not to f²."))]),
    ],
    noun="Jacobians and directions",
    arguments=lambda x: (_jacobian(x), _direction(x)),
    signature="push_capacity(J, d) -> float",
    doc=("Check push_capacity(J, d) -> the largest force along the unit d with ‖Jᵀ F‖ ≤ 1, "
         "compared with the reference at 20 random Jacobians and directions."),
    pack=_number,
))


# ------------------------------------------------------------------ Task 6: choosing a posture
def _measures(x: np.ndarray) -> np.ndarray:
    sigma = _sigma(x)
    return np.array([np.prod(sigma), sigma[0] / sigma[-1], sigma[-1]])


def _measures_mistakes() -> list:
    def with_sigma(change: Callable[[np.ndarray], np.ndarray]) -> Callable[[np.ndarray], np.ndarray]:
        def mistaken(x: np.ndarray) -> np.ndarray:
            sigma = change(_sigma(x))
            return np.array([np.prod(sigma), sigma[0] / sigma[-1], sigma[-1]])
        return mistaken

    return [
        alternatives("squared", [(with_sigma(lambda s: s ** 2), (
            "{name} works with the eigenvalues of J Jᵀ, σ_i²: the measures are those of the "
            "semi-axes σ_i, their square roots."))]),
        alternatives("inverted", [(lambda x: _measures(x) ** np.array([1.0, -1.0, 1.0]), (
            "{name}'s condition number is σ_min/σ_max ≤ 1: κ = σ_max/σ_min ≥ 1."))]),
        alternatives("sigma_max", [(lambda x: np.array([*_measures(x)[:2], _sigma(x)[0]]), (
            "{name}'s third value is σ_max: the minimum singular value σ_min is the speed in the "
            "slowest direction."))]),
    ]


posture_measures = exercise(_CHAPTER, "posture_measures", MatrixArgumentsCheck(
    name="posture_measures",
    reference=_measures,
    variables=_Q,
    diagnoses=_measures_mistakes(),
    noun="Jacobians of the arm",
    arguments=_one_jacobian,
    signature="posture_measures(J) -> (w, kappa, sigma_min)",
    hint="From the singular values σ_i of J: w = ∏ σ_i, κ = σ_max/σ_min, σ_min.",
    doc="Check posture_measures(J) -> (w, κ, σ_min): manipulability, condition number, minimum singular value.",
))


# ------------------------------------------------------------------ robokin's steps
def _wide_jacobian(J: Any) -> np.ndarray:
    """``J`` as a float array of shape (m, n) with 1 ≤ m ≤ n."""
    J = as_float_array(J, "J")
    if J.ndim != 2 or not 1 <= J.shape[0] <= J.shape[1]:
        raise ShapeError(f"J should be an (m, n) array with 1 <= m <= n; got the shape {J.shape}.")
    return J


def reference_tool_jacobian(q: Any) -> np.ndarray:
    """robokin's answer to ``tool_jacobian`` of Task 1 (the tests' stand-in).

    The test of ``joint_torques`` passes it as the student's argument ``tool_jacobian``, so that
    the torques are graded on their own, whatever the student's Jacobian.

    Parameters
    ----------
    q : array_like, shape (2,)
        The joint angles of the exercise arm (rad).

    Returns
    -------
    numpy.ndarray, shape (2, 2)
        The Jacobian ∂p/∂q of the tool position (rows x, y; columns q1, q2), m/rad.
    """
    return _jacobian(as_float_array(q, "q", (2,)))


def reference_velocity_ellipse(J: Any) -> tuple[np.ndarray, np.ndarray]:
    """robokin's answer to ``velocity_ellipse`` of Task 2 (the tests' stand-in).

    The test of ``force_ellipse`` passes it as the student's argument ``velocity_ellipse``.

    Parameters
    ----------
    J : array_like, shape (m, n)
        A Jacobian with m ≤ n and rank m.

    Returns
    -------
    radii : numpy.ndarray, shape (m,)
        The semi-axis lengths, descending.
    axes : numpy.ndarray, shape (m, m)
        The unit principal axes as columns, column i for ``radii[i]``.
    """
    J = _wide_jacobian(J)
    U, sigma, _ = np.linalg.svd(J)
    return sigma, U


def reference_posture_measures(J: Any) -> tuple[float, float, float]:
    """robokin's answer to ``posture_measures`` of Task 6 (the tests' stand-in).

    The test of ``preferred_postures`` passes it as the student's argument ``measures``.

    Parameters
    ----------
    J : array_like, shape (m, n)
        A Jacobian with m ≤ n.

    Returns
    -------
    tuple of float
        ``(w, kappa, sigma_min)``: the product of the singular values, their ratio
        σ_max/σ_min (infinite at a singularity) and the smallest one.
    """
    J = _wide_jacobian(J)
    sigma = np.linalg.svd(J, compute_uv=False)
    kappa = float(sigma[0] / sigma[-1]) if sigma[-1] > 0.0 else float("inf")
    return float(np.prod(sigma)), kappa, float(sigma[-1])
