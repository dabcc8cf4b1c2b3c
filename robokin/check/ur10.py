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
``nullspace_projector``  ``f(J)`` -> :math:`N` (6×6)                                   :math:`I - J^+J`
``ik_position``          ``f(chain, p_goal, q0, step, max_step, tol, max_iterations)``  the IK loop below
                         -> ``(q, converged, iterations)``
=======================  ===========================================================  ======================

``W`` is a diagonal weight matrix (weights sampled in [0.5, 4]), ``e`` a position
error in metres (components in [−0.1, 0.1]), ``damping`` the λ of damped least
squares in metres (in [0.01, 0.5]). A wrong answer is explained in the terms of
the exercise: ``W`` used where ``W⁻¹`` belongs, the weights applied after the
plain pseudoinverse, λ where λ² belongs, the projector onto the range of
:math:`J^T` instead of the null space of :math:`J`, and so on.

``ik_position`` is the whole iteration (the style of Lynch & Park's ``IKinBody``):
with :math:`e = p_{goal} - p(q)`, while :math:`\|e\| >` ``tol`` and fewer than
``max_iterations`` steps were taken: ``dq = step(J_v(q), e, q)``, scaled down to
the norm ``max_step`` if longer, ``q = clip(q + dq, lower, upper)``. It is called
on the UR10 with the chapter's working joint limits (:data:`WORK_LIMITS`), a
pseudoinverse step, seeded starts and goals, and iteration budgets of 1 to 12
steps; the returned ``(q, converged, iterations)`` is compared with this loop.
Diagnosed: the error's sign flipped, no step cap, the cap applied joint by
joint, no joint limits, no early stop.

Usage::

    from robokin.check import ur10 as check_ur10
    check_ur10.weighted_pinv(my_weighted_pinv)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from robokin.check._core import CheckResult, MatrixArgumentsCheck, Variable, alternatives
from robokin.check._registry import exercise

__all__ = ["weighted_pinv", "dls_step", "nullspace_projector", "ik_position", "N_JOINTS", "WORK_LIMITS"]

_CHAPTER = "ur10"
#: Number of joints of the UR10.
N_JOINTS = 6
#: The working joint limits of chapter 2's work cell (rad), one row ``[lower, upper]`` per joint.
WORK_LIMITS = np.array([
    [-math.pi, math.pi],
    [-math.pi, 0.0],
    [0.0, math.pi],
    [-math.pi, 0.0],
    [-math.pi, 0.0],
    [-math.pi, math.pi],
])


@lru_cache(maxsize=1)
def _robot():
    from robokin.models import ur10

    return ur10()


def _position_jacobian(q: np.ndarray) -> np.ndarray:
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


def _group(nvar: int) -> list[tuple[str, list[int]]]:
    return [("x", list(range(nvar)))]


# ------------------------------------------------------------------ weighted pseudoinverse
def _weighted_pinv_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return _position_jacobian(x[:6]), np.diag(x[6:12])


def _weighted(J: np.ndarray, W: np.ndarray) -> np.ndarray:
    Wi = np.linalg.inv(W)
    return Wi @ J.T @ np.linalg.inv(J @ Wi @ J.T)


def _weighted_pinv_reference(x: np.ndarray) -> np.ndarray:
    return _weighted(*_weighted_pinv_arguments(x))


def _weighted_pinv_mistakes():
    def w_not_inverted(x):
        J, W = _weighted_pinv_arguments(x)
        return W @ J.T @ np.linalg.inv(J @ W @ J.T)

    def after_pinv(x):
        J, W = _weighted_pinv_arguments(x)
        return np.linalg.inv(W) @ np.linalg.pinv(J)

    def w_times_pinv(x):
        J, W = _weighted_pinv_arguments(x)
        return W @ np.linalg.pinv(J)

    def plain(x):
        J, _ = _weighted_pinv_arguments(x)
        return np.linalg.pinv(J)

    def sqrt_w(x):
        J, W = _weighted_pinv_arguments(x)
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
                "{name} is W⁻¹ J⁺ (= W⁻¹ J^T (J J^T)⁻¹): the plain pseudoinverse scaled joint by joint "
                "afterwards. That is not a (weighted) inverse: J (W⁻¹ J⁺) ≠ I, so the step no longer achieves the "
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


weighted_pinv = exercise(_CHAPTER, "weighted_pinv", MatrixArgumentsCheck(
    name="weighted_pinv(J, W)",
    reference=_weighted_pinv_reference,
    variables=[*_Q, *_W],
    groups=_group(12),
    diagnoses=_weighted_pinv_mistakes(),
    noun="configurations and weights",
    arguments=_weighted_pinv_arguments,
    signature="weighted_pinv(J, W) -> (n, m) array",
    hint="Check J @ answer == I (3×3) and that a larger w_i makes row i smaller.",
    doc="Check a function weighted_pinv(J, W) -> W⁻¹ Jᵀ (J W⁻¹ Jᵀ)⁻¹ (J: 3×6, W: 6×6 diagonal).",
))


# ------------------------------------------------------------------ damped least squares
def _damped_least_squares_arguments(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    return _position_jacobian(x[:6]), np.array(x[6:9]), float(x[9])


def _dls(J: np.ndarray, e: np.ndarray, lam2: float) -> np.ndarray:
    return J.T @ np.linalg.solve(J @ J.T + lam2 * np.eye(J.shape[0]), e)


def _damped_least_squares_reference(x: np.ndarray) -> np.ndarray:
    J, e, lam = _damped_least_squares_arguments(x)
    return _dls(J, e, lam**2)


def _damped_least_squares_mistakes():
    def not_squared(x):
        J, e, lam = _damped_least_squares_arguments(x)
        return _dls(J, e, lam)

    def undamped(x):
        J, e, _ = _damped_least_squares_arguments(x)
        return np.linalg.pinv(J) @ e

    def minus(x):
        J, e, lam = _damped_least_squares_arguments(x)
        return _dls(J, e, -(lam**2))

    def sign(x):
        return -_damped_least_squares_reference(x)

    def transpose_only(x):
        J, e, _ = _damped_least_squares_arguments(x)
        return J.T @ e

    def squared_twice(x):
        J, e, lam = _damped_least_squares_arguments(x)
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


dls_step = exercise(_CHAPTER, "dls_step", MatrixArgumentsCheck(
    name="dls_step(J, e, damping)",
    reference=_damped_least_squares_reference,
    variables=[*_Q, *_E, *_LAM],
    groups=_group(10),
    diagnoses=_damped_least_squares_mistakes(),
    noun="configurations, errors and dampings",
    arguments=_damped_least_squares_arguments,
    signature="dls_step(J, e, damping) -> (n,) array",
    hint="The step is J^T (J J^T + λ² I)⁻¹ e; λ = damping.",
    doc="Check a function dls_step(J, e, damping) -> Jᵀ (J Jᵀ + λ² I)⁻¹ e.",
))


# ------------------------------------------------------------------ null-space projector
def _nullspace_projector_arguments(x: np.ndarray) -> tuple[np.ndarray]:
    return (_position_jacobian(x[:6]),)


def _nullspace_projector_reference(x: np.ndarray) -> np.ndarray:
    (J,) = _nullspace_projector_arguments(x)
    return np.eye(J.shape[1]) - np.linalg.pinv(J) @ J


def _nullspace_projector_mistakes():
    def range_projector(x):
        (J,) = _nullspace_projector_arguments(x)
        return np.linalg.pinv(J) @ J

    def transpose_for_pinv(x):
        (J,) = _nullspace_projector_arguments(x)
        return np.eye(J.shape[1]) - J.T @ J

    def negated(x):
        return -_nullspace_projector_reference(x)

    return [
        alternatives("range_projector", [(range_projector, (
            "{name} is J⁺J, the projector onto the row space of J (the joint motions that DO "
            "move the tool). The null-space projector is its complement, I − J⁺J."
        ))]),
        alternatives("transpose_for_pinv", [(transpose_for_pinv, (
            "{name} = I − J^T J uses the transpose where the pseudoinverse belongs: "
            "I − J⁺J with J⁺ = J^T (J J^T)⁻¹."
        ))]),
        alternatives("sign", [(negated, "{name} has the wrong sign: N = I − J⁺J.")]),
    ]


nullspace_projector = exercise(_CHAPTER, "nullspace_projector", MatrixArgumentsCheck(
    name="nullspace_projector(J)",
    reference=_nullspace_projector_reference,
    variables=_Q,
    groups=_group(6),
    diagnoses=_nullspace_projector_mistakes(),
    noun="configurations",
    arguments=_nullspace_projector_arguments,
    signature="nullspace_projector(J) -> (n, n) array",
    hint="The projector N = I − J⁺J is n×n (n = 6 joints) and satisfies J P = 0, P P = P.",
    doc="Check a function nullspace_projector(J) -> I − J⁺ J (n×n).",
))


# ------------------------------------------------------------------ the IK loop
@lru_cache(maxsize=1)
def _cell():
    from robokin.chains import SerialChain

    robot = _robot()
    return SerialChain(robot.elements, limits=WORK_LIMITS, frame_names=robot.frame_names, name="ur10_cell")


#: Step cap (rad) and tolerance (m) the check passes to the student's loop.
_LOOP_MAX_STEP = 0.4
_LOOP_TOL = 1e-9


def _pinv_step(J: np.ndarray, e: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The step the check hands to the loop: the pseudoinverse step J⁺ e."""
    return np.linalg.pinv(J) @ e


def _loop_args(x: np.ndarray) -> tuple:
    """(chain, p_goal, q0, step, max_step, tol, max_iterations) from the sampled scalars."""
    chain = _cell()
    lower, upper = WORK_LIMITS[:, 0], WORK_LIMITS[:, 1]
    q0 = np.array(x[:6])
    q_goal = np.clip(q0 + x[6:12], lower, upper)
    p_goal = chain.fk(q_goal)[:3, 3]
    return chain, p_goal, q0, _pinv_step, _LOOP_MAX_STEP, _LOOP_TOL, int(x[12])


def _loop(chain, p_goal, q0, step, max_step, tol, max_iterations, *, sign=1.0, cap="norm",
          clamp=True, early_stop=True) -> np.ndarray:
    """The reference loop (and, with the keywords, its typical mistakes), packed as
    ``[q (6), converged, iterations]``."""
    lower, upper = chain.limits[:, 0], chain.limits[:, 1]
    q = np.array(q0, dtype=float)
    e = sign * (p_goal - chain.fk(q)[:3, 3])
    iterations = 0
    while (np.linalg.norm(e) > tol or not early_stop) and iterations < max_iterations:
        dq = step(chain.position_jacobian(q), e, q)
        if cap == "norm":
            length = np.linalg.norm(dq)
            if length > max_step:
                dq = dq * (max_step / length)
        elif cap == "joint":
            dq = np.clip(dq, -max_step, max_step)
        q = q + dq
        if clamp:
            q = np.clip(q, lower, upper)
        e = sign * (p_goal - chain.fk(q)[:3, 3])
        iterations += 1
    return np.r_[q, float(np.linalg.norm(e) <= tol), float(iterations)]


def _loop_ref(x: np.ndarray) -> np.ndarray:
    return _loop(*_loop_args(x))


def _loop_mistakes():
    def variant(**kwargs):
        return lambda x: _loop(*_loop_args(x), **kwargs)

    return [
        alternatives("error_sign", [(variant(sign=-1.0), (
            "{name} steps away from the goal: the error is e = p_goal − p(q) (goal minus "
            "current), and the step J⁺e then moves the flange towards the goal."
        ))]),
        alternatives("no_step_cap", [(variant(cap=None), (
            "{name} does not cap the step: scale dq down to the norm max_step when "
            "‖dq‖ > max_step (dq ← dq · max_step/‖dq‖), so that far from the goal, where "
            "the linearisation is poor, the loop takes short steps."
        ))]),
        alternatives("step_cap_per_joint", [(variant(cap="joint"), (
            "{name} clips every joint's step to ±max_step: that changes the step's "
            "direction. Scale the whole step instead: dq ← dq · max_step/‖dq‖ when "
            "‖dq‖ > max_step."
        ))]),
        alternatives("no_joint_limits", [(variant(clamp=False), (
            "{name} lets the joints leave their limits: clamp q to [lower, upper] "
            "(chain.limits) after every step, q = np.clip(q + dq, lower, upper)."
        ))]),
        alternatives("no_early_stop", [(variant(early_stop=False), (
            "{name} always takes max_iterations steps: stop as soon as ‖e‖ <= tol, "
            "and return the number of steps taken."
        ))]),
    ]


@dataclass
class LoopCheck(MatrixArgumentsCheck):
    """Check of an IK loop ``f(chain, p_goal, q0, step, max_step, tol, max_iterations)``.

    The loop returns ``(q, converged, iterations)``: ``q`` (6,) rad, a bool and an
    int; the three are packed into one vector (6 + 2,) and compared with the
    reference loop's on the check's sample arguments (see :class:`MatrixArgumentsCheck`).
    """

    def evaluate(self, answer: Any) -> CheckResult:
        if callable(answer) and not isinstance(answer, np.ndarray):
            student = answer

            def packed(*args):
                out = student(*args)
                if not isinstance(out, tuple) or len(out) != 3:
                    raise TypeError(
                        "the loop should return a tuple (q, converged, iterations); got "
                        f"{type(out).__name__}"
                        + (f" of length {len(out)}" if isinstance(out, tuple) else "")
                    )
                q, converged, iterations = out
                return np.r_[np.asarray(q, dtype=float).ravel(), float(bool(converged)), float(iterations)]

            return super().evaluate(packed)
        return super().evaluate(answer)


_Q0 = [
    Variable("q1", "angle", -2.5, 2.5),
    Variable("q2", "angle", -2.6, -0.6),
    Variable("q3", "angle", 0.4, 2.6),
    Variable("q4", "angle", -2.8, -0.3),
    Variable("q5", "angle", -2.8, -0.4),
    Variable("q6", "angle", -2.5, 2.5),
]
_DQ = [Variable(f"dq{i}", "other", -0.9, 0.9) for i in range(1, N_JOINTS + 1)]
_BUDGET = [Variable("max_iterations", "other", 1.0, 12.999)]

ik_position = exercise(_CHAPTER, "ik_position", LoopCheck(
    name="ik_position(chain, p_goal, q0, step, ...)",
    reference=_loop_ref,
    variables=[*_Q0, *_DQ, *_BUDGET],
    groups=_group(13),
    diagnoses=_loop_mistakes(),
    noun="starts, goals and iteration budgets",
    arguments=_loop_args,
    signature="ik_position(chain, p_goal, q0, step, max_step, tol, max_iterations) -> (q, converged, iterations)",
    hint=("The loop: e = p_goal − p(q); while ‖e‖ > tol and fewer than max_iterations steps: "
          "dq = step(J_v(q), e, q), capped to the norm max_step, q = clip(q + dq, limits), "
          "recompute e; return (q, ‖e‖ <= tol, steps taken)."),
    atol=1e-7,
    doc="Check an IK loop ik_position(chain, p_goal, q0, step, max_step, tol, max_iterations).",
))
