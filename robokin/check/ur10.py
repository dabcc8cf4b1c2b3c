r"""Exercise checks of chapter 2: inverse kinematics of the UR10.

The student writes three small functions of matrices; each check calls them
with the position Jacobian :math:`\mathbf{J}_v(\mathbf{q})` (3×6, metres) of
:func:`robokin.models.ur10` at seeded random configurations away from the
singularities, and compares with the reference formula:

=======================  ===========================================================  ======================
check                    the student's function                                       reference
=======================  ===========================================================  ======================
``weighted_pinv``        ``f(J, W)`` -> :math:`J_W^+` (6×3)                            :math:`W^{-1}J^T(JW^{-1}J^T)^{-1}`
``dls_step``             ``f(J, e, damping)`` -> :math:`\Delta q` (6,)                 :math:`J^T(JJ^T+\lambda^2 I)^{-1}e`
``nullspace_projector``  ``f(J)`` -> :math:`P` (6×6)                                   :math:`I - J^+J`
=======================  ===========================================================  ======================

``W`` is a diagonal weight matrix (weights sampled in [0.5, 4]), ``e`` a position
error in metres (components in [−0.1, 0.1]), ``damping`` the λ of damped least
squares in metres (in [0.01, 0.5]). A wrong answer is explained in the terms of
the exercise: ``W`` used where ``W⁻¹`` belongs, the weights applied after the
plain pseudoinverse, λ where λ² belongs, the projector onto the range of
:math:`J^T` instead of the null space of :math:`J`, and so on.

Usage::

    from robokin.check import ur10 as check_ur10
    check_ur10.weighted_pinv(my_weighted_pinv)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from robokin.check._core import Check, CheckResult, Variable, alternatives
from robokin.check._registry import exercise

__all__ = ["weighted_pinv", "dls_step", "nullspace_projector", "N_JOINTS"]

_CH = "ur10"
#: Number of joints of the UR10.
N_JOINTS = 6


@lru_cache(maxsize=1)
def _robot():
    from robokin.models import ur10

    return ur10()


def _Jv(q: np.ndarray) -> np.ndarray:
    """Position Jacobian (3×6, m/rad) of the UR10 flange at ``q``."""
    return _robot().position_jacobian(np.asarray(q, dtype=float))


# ------------------------------------------------------------------ inputs
# Away from the singularities: elbow bent (q3 in [0.5, 2.5]), wrist 2 away from 0 and ±π,
# shoulder lift such that the flange stays away from the base axis.
_Q = [
    Variable("q1", "angle", -math.pi, math.pi),
    Variable("q2", "angle", -2.2, -0.9),
    Variable("q3", "angle", 0.5, 2.5),
    Variable("q4", "angle", -math.pi, math.pi),
    Variable("q5", "angle", 0.4, 2.7),
    Variable("q6", "angle", -math.pi, math.pi),
]
_W = [Variable(f"w{i}", "other", 0.5, 4.0) for i in range(1, N_JOINTS + 1)]
_E = [Variable(f"e_{c}", "length", -0.1, 0.1) for c in "xyz"]
_LAM = [Variable("damping", "length", 0.01, 0.5, aliases=("lambda", "lam"))]


@dataclass
class MatrixArgumentsCheck(Check):
    """A :class:`~robokin.check.Check` whose answer is a function of matrices.

    ``arguments(x)`` turns the sampled scalars ``x`` into the arguments of the
    student's function (e.g. ``(J, W)``); the answer is called as
    ``answer(*arguments(x))``. Arrays and other non-callables are passed to the
    generic check unchanged (which then explains that a function is expected).
    """

    arguments: Callable[[np.ndarray], tuple] | None = None
    signature: str = ""

    def evaluate(self, answer: Any) -> CheckResult:  # noqa: D102 - see Check.evaluate
        if callable(answer) and not isinstance(answer, np.ndarray) and self.arguments is not None:
            build = self.arguments
            student = answer

            def wrapped(x):
                return student(*build(np.asarray(x, dtype=float)))

            return super().evaluate(wrapped)
        if answer is not None and not callable(answer):
            from robokin.check._core import FAIL

            return CheckResult(
                self.name, False,
                f"{FAIL} {self.name} should be a Python function {self.signature}; "
                f"got {type(answer).__name__}.",
                "constant", 0,
            )
        return super().evaluate(answer)


def _group(nvar: int) -> list[tuple[str, list[int]]]:
    return [("x", list(range(nvar)))]


# ------------------------------------------------------------------ weighted pseudoinverse
def _wp_args(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return _Jv(x[:6]), np.diag(x[6:12])


def _weighted(J: np.ndarray, W: np.ndarray) -> np.ndarray:
    Wi = np.linalg.inv(W)
    return Wi @ J.T @ np.linalg.inv(J @ Wi @ J.T)


def _wp_ref(x: np.ndarray) -> np.ndarray:
    return _weighted(*_wp_args(x))


def _wp_mistakes():
    def w_not_inverted(x):
        J, W = _wp_args(x)
        return W @ J.T @ np.linalg.inv(J @ W @ J.T)

    def after_pinv(x):
        J, W = _wp_args(x)
        return np.linalg.inv(W) @ np.linalg.pinv(J)

    def w_times_pinv(x):
        J, W = _wp_args(x)
        return W @ np.linalg.pinv(J)

    def plain(x):
        J, _ = _wp_args(x)
        return np.linalg.pinv(J)

    def sqrt_w(x):
        J, W = _wp_args(x)
        Wi = np.diag(1.0 / np.sqrt(np.diag(W)))
        return Wi @ J.T @ np.linalg.inv(J @ Wi @ J.T)

    return [
        alternatives("weights_not_inverted", [(w_not_inverted, (
            "{name} uses W where W⁻¹ belongs: W J^T (J W J^T)⁻¹ makes the joints with a LARGE "
            "weight move MORE. The weighted pseudoinverse is W⁻¹ J^T (J W⁻¹ J^T)⁻¹; it minimises "
            "Δqᵀ W Δq, so a large w_i penalises (slows down) joint i."
        ))]),
        alternatives("weights_after_pinv", [
            (after_pinv, (
                "{name} is W⁻¹ J⁺ (= W⁻¹ J^T (J J^T)⁻¹): the plain pseudoinverse scaled joint by joint afterwards. That "
                "is not a (weighted) inverse: J (W⁻¹ J⁺) ≠ I, so the step no longer achieves the "
                "commanded displacement. Put W⁻¹ inside: W⁻¹ J^T (J W⁻¹ J^T)⁻¹."
            )),
            (w_times_pinv, (
                "{name} is W J⁺: the plain pseudoinverse multiplied by W afterwards. Then "
                "J·{name} ≠ I. The weighted pseudoinverse is W⁻¹ J^T (J W⁻¹ J^T)⁻¹."
            )),
        ]),
        alternatives("unweighted", [(plain, (
            "{name} ignores W: it is the plain pseudoinverse J⁺ = J^T (J J^T)⁻¹. Insert W⁻¹: "
            "W⁻¹ J^T (J W⁻¹ J^T)⁻¹."
        ))]),
        alternatives("sqrt_weights", [(sqrt_w, (
            "{name} uses W^(-1/2) where W⁻¹ belongs (the weighted norm is Δqᵀ W Δq, "
            "not Δqᵀ W^(1/2) Δq)."
        ))]),
    ]


weighted_pinv = exercise(_CH, "weighted_pinv", MatrixArgumentsCheck(
    name="weighted_pinv(J, W)",
    reference=_wp_ref,
    variables=[*_Q, *_W],
    groups=_group(12),
    diagnoses=_wp_mistakes(),
    noun="configurations and weights",
    arguments=_wp_args,
    signature="weighted_pinv(J, W) -> (n, m) array",
    hint="Check J @ answer == I (3×3) and that a larger w_i makes row i smaller.",
    doc="Check a function weighted_pinv(J, W) -> W⁻¹ Jᵀ (J W⁻¹ Jᵀ)⁻¹ (J: 3×6, W: 6×6 diagonal).",
))


# ------------------------------------------------------------------ damped least squares
def _dls_args(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    return _Jv(x[:6]), np.array(x[6:9]), float(x[9])


def _dls(J: np.ndarray, e: np.ndarray, lam2: float) -> np.ndarray:
    return J.T @ np.linalg.solve(J @ J.T + lam2 * np.eye(J.shape[0]), e)


def _dls_ref(x: np.ndarray) -> np.ndarray:
    J, e, lam = _dls_args(x)
    return _dls(J, e, lam**2)


def _dls_mistakes():
    def not_squared(x):
        J, e, lam = _dls_args(x)
        return _dls(J, e, lam)

    def undamped(x):
        J, e, _ = _dls_args(x)
        return np.linalg.pinv(J) @ e

    def minus(x):
        J, e, lam = _dls_args(x)
        return _dls(J, e, -(lam**2))

    def sign(x):
        return -_dls_ref(x)

    def transpose_only(x):
        J, e, _ = _dls_args(x)
        return J.T @ e

    def squared_twice(x):
        J, e, lam = _dls_args(x)
        return _dls(J, e, lam**4)

    return [
        alternatives("damping_not_squared", [
            (not_squared, (
                "{name} adds λ·I where λ²·I belongs: the damped least-squares step is "
                "J^T (J J^T + λ² I)⁻¹ e (λ has the units of J, here metres)."
            )),
            (squared_twice, "{name} adds λ⁴·I: square the damping λ once, J^T (J J^T + λ² I)⁻¹ e."),
        ]),
        alternatives("undamped", [(undamped, (
            "{name} has no damping: it is the pseudoinverse step J⁺ e. Add λ² I to J J^T."
        ))]),
        alternatives("damping_sign", [(minus, (
            "{name} subtracts λ² I: the damping is added, J^T (J J^T + λ² I)⁻¹ e, which "
            "keeps the matrix positive definite."
        ))]),
        alternatives("error_sign", [(sign, (
            "{name} points away from the target: the error is e = p_goal − p(q) and the step "
            "is +J^T (J J^T + λ² I)⁻¹ e."
        ))]),
        alternatives("jacobian_transpose", [(transpose_only, (
            "{name} is the Jacobian-transpose step J^T e; damped least squares solves "
            "(J J^T + λ² I) y = e first: Δq = J^T y."
        ))]),
    ]


dls_step = exercise(_CH, "dls_step", MatrixArgumentsCheck(
    name="dls_step(J, e, damping)",
    reference=_dls_ref,
    variables=[*_Q, *_E, *_LAM],
    groups=_group(10),
    diagnoses=_dls_mistakes(),
    noun="configurations, errors and dampings",
    arguments=_dls_args,
    signature="dls_step(J, e, damping) -> (n,) array",
    hint="The step is J^T (J J^T + λ² I)⁻¹ e; λ = damping.",
    doc="Check a function dls_step(J, e, damping) -> Jᵀ (J Jᵀ + λ² I)⁻¹ e.",
))


# ------------------------------------------------------------------ null-space projector
def _ns_args(x: np.ndarray) -> tuple[np.ndarray]:
    return (_Jv(x[:6]),)


def _ns_ref(x: np.ndarray) -> np.ndarray:
    (J,) = _ns_args(x)
    return np.eye(J.shape[1]) - np.linalg.pinv(J) @ J


def _ns_mistakes():
    def range_projector(x):
        (J,) = _ns_args(x)
        return np.linalg.pinv(J) @ J

    def transpose_for_pinv(x):
        (J,) = _ns_args(x)
        return np.eye(J.shape[1]) - J.T @ J

    def negated(x):
        return -_ns_ref(x)

    return [
        alternatives("range_projector", [(range_projector, (
            "{name} is J⁺J, the projector onto the row space of J (the joint motions that DO "
            "move the tool). The null-space projector is its complement, I − J⁺J."
        ))]),
        alternatives("transpose_for_pinv", [(transpose_for_pinv, (
            "{name} = I − J^T J uses the transpose where the pseudoinverse belongs: "
            "I − J⁺J with J⁺ = J^T (J J^T)⁻¹."
        ))]),
        alternatives("sign", [(negated, "{name} has the wrong sign: P = I − J⁺J.")]),
    ]


nullspace_projector = exercise(_CH, "nullspace_projector", MatrixArgumentsCheck(
    name="nullspace_projector(J)",
    reference=_ns_ref,
    variables=_Q,
    groups=_group(6),
    diagnoses=_ns_mistakes(),
    noun="configurations",
    arguments=_ns_args,
    signature="nullspace_projector(J) -> (n, n) array",
    hint="The projector P = I − J⁺J is n×n (n = 6 joints) and satisfies J P = 0, P P = P.",
    doc="Check a function nullspace_projector(J) -> I − J⁺ J (n×n).",
))
