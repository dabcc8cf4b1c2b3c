r"""Exercise checks of chapter 2: inverse kinematics of the UR10.

The student writes three small functions of matrices; each check calls them
with the position Jacobian :math:`\mathbf{J}_v(\mathbf{q})` (3×6, metres) of
:func:`robokin.models.ur10` at seeded random configurations away from the
singularities, and compares with robokin's reference (to an absolute tolerance
of 1e-8 and a relative one of 1e-6 unless stated):

=======================  ===========================================================  ======================
check                    the student's function                                       compared
=======================  ===========================================================  ======================
``weighted_pinv``        ``f(J, W)`` -> :math:`J_W^+` (6×3)                            at 20 random J and W
``dls_step``             ``f(J, e, damping)`` -> :math:`\Delta q` (6,)                 at 20 random J, e, λ
``nullspace_projector``  ``f(J)`` -> :math:`N` (6×6)                                   at 20 random J
``ik_position``          ``f(chain, p_goal, q0, step, max_step, tol, max_iterations)``  the IK loop below
                         -> ``(q, converged, iterations)``
=======================  ===========================================================  ======================

``W`` is a diagonal weight matrix (weights sampled in [0.5, 4]), ``e`` a position
error in metres (components in [−0.1, 0.1]), ``damping`` the λ of damped least
squares in metres (in [0.01, 0.5]). A wrong answer is explained in the terms of
the exercise when a known mistake reproduces it (the weights in the wrong
place, a wrong power of λ, the wrong subspace for the projector, and so on).

``ik_position`` is the whole iteration (the style of Lynch & Park's ``IKinBody``):
with :math:`e = p_{goal} - p(q)`, while :math:`\|e\| >` ``tol`` and fewer than
``max_iterations`` steps were taken: ``dq = step(J_v(q), e, q)``, scaled down to
the norm ``max_step`` if longer, ``q = clip(q + dq, lower, upper)``. It is called
on the UR10 with the chapter's working joint limits (:data:`WORK_LIMITS`), a
pseudoinverse step, seeded starts and goals, and iteration budgets of 1 to 12
steps; the returned ``(q, converged, iterations)`` is compared with this loop.
Diagnosed: the error's sign flipped, no step cap, the cap applied joint by
joint, no joint limits, no early stop.

Two checks call the student's joint-limit objective of Task 2 (c) and its gradient at
configurations of their own (passing the work cell's limits, another chain's, and none: the
default), and name the typical mistake:

- ``joint_limit_objective(q, limits=WORK_LIMITS)``: Siciliano's :math:`H` (eq. 3.57) at single
  configurations and at batches (N, n) (the sign, the factor 1/(2n) left out or another factor,
  the ranges not normalised, q not measured from mid-range, the default limits for the given
  ones, a batch summed whole);
- ``joint_limit_gradient(q, limits=WORK_LIMITS)``: :math:`\nabla H` (the sign, 2n times it,
  half of it, the range not squared, not normalised, not centred, the default limits; any other
  mismatch is shown against central differences of :math:`H`).

Four more checks call the student's functions of Tasks 3 to 6 on inputs of their own
and name the typical mistake:

- ``summary(chain, p_goal, path)``: the figures of one run, on random iterates whose
  start is the nearest to a limit and the least manipulable, on the work cell and on a
  chain with other limits (the start included in a minimum, the chord for the path, the
  default limits for the chain's, det for its square root, ...);
- ``self_motion(chain, p_goal, q_start, gain, steps)``: the self-motion
  :math:`q \leftarrow q + J^+e + N k \nabla H(q)` (no :math:`J^+e`, :math:`\nabla H` not
  projected or descended, the gain left out, the rows recorded after the step, the
  default limits);
- ``ik_restarts(chain, p_goal, starts, step)``: ``ik_position`` from each start in turn
  (the steps of the last attempt only, no restart, a restart from the last attempt's end,
  attempts counted from 0, no stop after success, the first attempt's q);
- ``bisect(f, low, high, tol)``: a root within ``tol`` on rising and falling functions,
  ``ValueError`` without a bracket (the wrong half kept, a fixed number of halvings, the
  sign of ``f(middle)`` alone, no ``ValueError``).

The ``reference_*`` functions are robokin's answers to the steps of Task 2
(``reference_weighted_pinv``, ``reference_dls_step``, ``reference_nullspace_projector``,
``reference_joint_limit_objective``, ``reference_joint_limit_gradient`` and the loop
``reference_ik_position``): the graded tests of the later tasks pass them to the student's
functions (``summary``, ``self_motion``, ``ik_restarts`` take the steps they build on as
arguments) so that a mistake in one step costs the points of that step only. The checks of
those three pass them too (``objective=``, ``projector=``, ``gradient=``, ``solve=``, where the
student's function has those parameters), so that their verdicts, and the grading report's, blame
no later step for an earlier one.

Usage::

    from robokin.check import ur10 as check_ur10
    check_ur10.weighted_pinv(my_weighted_pinv)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np

from robokin.check._core import (
    CheckResult,
    FunctionCheck,
    MatrixArgumentsCheck,
    Variable,
    alternatives,
    fmt,
    with_reference_steps,
)
from robokin.check._registry import exercise
from robokin.validation import (
    as_batch,
    as_float_array,
    check_callable,
    check_chain,
    check_int,
    check_result_finite,
)

__all__ = ["weighted_pinv", "dls_step", "nullspace_projector", "joint_limit_objective",
           "joint_limit_gradient", "ik_position", "summary", "self_motion",
           "ik_restarts", "bisect", "N_JOINTS", "WORK_LIMITS", "PseudoinverseStep", "reference_dls_step",
           "reference_ik_position", "reference_joint_limit_gradient", "reference_joint_limit_objective",
           "reference_nullspace_projector", "reference_weighted_pinv", "NULLSPACE_GAIN", "step_rules",
           "assert_steps_follow", "loop_as_solve_ik", "assert_self_motion_rows", "assert_path_figures",
           "assert_summary_of_path"]

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
            "{name} uses W where W⁻¹ belongs: it makes the joints with a LARGE weight move MORE. "
            "The step minimises Δqᵀ W Δq, so a large w_i must penalise (slow down) joint i: see "
            "which of W, W⁻¹ the stationarity condition of the Lagrangian gives."
        ))]),
        alternatives("weights_after_pinv", [
            (after_pinv, (
                "{name} is W⁻¹ J⁺: the plain pseudoinverse scaled joint by joint afterwards. That is "
                "not a (weighted) inverse: J (W⁻¹ J⁺) ≠ I, so the step no longer achieves the commanded "
                "displacement. The weights belong inside the inverse: derive the minimiser of "
                "½ Δqᵀ W Δq subject to J Δq = e with a Lagrange multiplier."
            )),
            (w_times_pinv, (
                "{name} is W J⁺: the plain pseudoinverse multiplied by W afterwards. Then "
                "J·{name} ≠ I: the weights belong inside the inverse (derive the minimiser of "
                "½ Δqᵀ W Δq subject to J Δq = e)."
            )),
        ]),
        alternatives("unweighted", [(plain, (
            "{name} ignores W: it is the plain pseudoinverse J⁺, the minimiser for W = I. Derive "
            "the minimiser of ½ Δqᵀ W Δq subject to J Δq = e with W in it."
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
    diagnoses=_weighted_pinv_mistakes(),
    noun="configurations and weights",
    arguments=_weighted_pinv_arguments,
    signature="weighted_pinv(J, W) -> (n, m) array",
    hint="Check J @ answer == I (3×3) and that a larger w_i makes row i smaller.",
    doc=("Check a function weighted_pinv(J, W) -> J_W⁺ (6×3) (J: 3×6, W: 6×6 diagonal): compared "
         "with the reference at 20 random configurations and weights."),
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
                "{name} adds λ·I where λ²·I belongs: the objective's damping term is λ² ‖Δq‖² "
                "(λ has the units of J, here metres)."
            )),
            (squared_twice, "{name} adds λ⁴·I: the objective's damping term is λ² ‖Δq‖², λ = damping "
                            "squared once."),
        ]),
        alternatives("undamped", [(undamped, (
            "{name} has no damping: it is the pseudoinverse step J⁺ e, the minimiser for λ = 0. "
            "Set the gradient of ‖J Δq − e‖² + λ² ‖Δq‖² to zero with λ in it."
        ))]),
        alternatives("damping_sign", [(minus, (
            "{name} subtracts λ² I: the damping term λ² ‖Δq‖² adds to the objective, and so to "
            "the matrix of its normal equations, which it keeps positive definite."
        ))]),
        alternatives("error_sign", [(sign, (
            "{name} points away from the target: the error is e = p_goal − p(q), and the step "
            "minimises ‖J Δq − e‖², so J Δq points along e, not against it."
        ))]),
        alternatives("jacobian_transpose", [(transpose_only, (
            "{name} is the Jacobian-transpose step J^T e: it leaves out the linear system of the "
            "damped least-squares problem (set the gradient of ‖J Δq − e‖² + λ² ‖Δq‖² to zero)."
        ))]),
    ]


dls_step = exercise(_CHAPTER, "dls_step", MatrixArgumentsCheck(
    name="dls_step(J, e, damping)",
    reference=_damped_least_squares_reference,
    variables=[*_Q, *_E, *_LAM],
    diagnoses=_damped_least_squares_mistakes(),
    noun="configurations, errors and dampings",
    arguments=_damped_least_squares_arguments,
    signature="dls_step(J, e, damping) -> (n,) array",
    hint=("Δq minimises ‖J Δq − e‖² + λ² ‖Δq‖², λ = damping: for a tiny λ it is the "
          "pseudoinverse step J⁺e, and a larger λ shortens it."),
    doc=("Check a function dls_step(J, e, damping) -> Δq (n,), the damped least-squares step with "
         "λ = damping: compared with the reference at 20 random configurations, errors and dampings."),
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
            "move the tool). The null-space projector is its complement."
        ))]),
        alternatives("transpose_for_pinv", [(transpose_for_pinv, (
            "{name} = I − J^T J uses the transpose where the pseudoinverse belongs (J^T J is "
            "no projector unless the rows of J are orthonormal)."
        ))]),
        alternatives("sign", [(negated, (
            "{name} has the wrong sign: a projector has the eigenvalues 0 and 1, and N v = v for "
            "a joint motion v that does not move the flange."
        ))]),
    ]


nullspace_projector = exercise(_CHAPTER, "nullspace_projector", MatrixArgumentsCheck(
    name="nullspace_projector(J)",
    reference=_nullspace_projector_reference,
    variables=_Q,
    diagnoses=_nullspace_projector_mistakes(),
    noun="configurations",
    arguments=_nullspace_projector_arguments,
    signature="nullspace_projector(J) -> (n, n) array",
    hint=("The null-space projector N is n×n (n = 6 joints), symmetric, with J N = 0, N N = N, "
          "and N v = v for every v with J v = 0."),
    doc=("Check a function nullspace_projector(J) -> N (n×n), the projector onto the null space "
         "of J: compared with the reference at 20 random configurations."),
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


@dataclasses.dataclass(frozen=True)
class PseudoinverseStep:
    r"""The plain pseudoinverse step :math:`\Delta q = J^+ e` as a step rule ``step(J, e, q)``.

    A test hands it to the student's ``ik_restarts``, which passes it on to the loop it is
    given (robokin's :func:`reference_ik_position` in the graded test). Being data, not a
    function of the test, it goes to the student's kernel and back whole: the grader calls a
    function of its own (the loop) with it, not a function of the student's.
    """

    def __call__(self, J: Any, e: Any, q: Any = None) -> np.ndarray:
        """The step J⁺e (n,) for the task Jacobian ``J`` (m, n) and the error ``e`` (m,);
        ``q`` is not used."""
        return np.linalg.pinv(np.asarray(J, dtype=float)) @ np.asarray(e, dtype=float)


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


def _describe_loop(x: np.ndarray) -> str:
    """The call of the student's loop at the sample ``x``, as a failure's example writes it."""
    _, p_goal, q0, _, max_step, tol, budget = _loop_args(x)
    return (f"ik_position(cell, p_goal = {fmt(p_goal)} m, q0 = {fmt(q0)} rad, step = the "
            f"pseudoinverse step J⁺e, max_step = {max_step:g}, tol = {tol:g}, max_iterations = {budget})")


def _loop_entry(idx: tuple[int, ...]) -> str:
    """What entry ``idx`` of the packed ``[q (6), converged, iterations]`` is."""
    i = idx[0]
    return f"q[{i}]" if i < N_JOINTS else ("converged" if i == N_JOINTS else "iterations")


def _pack_loop(out: Any) -> np.ndarray:
    """The loop's ``(q, converged, iterations)`` packed as ``[q (6), converged, iterations]``."""
    if not isinstance(out, tuple) or len(out) != 3:
        raise TypeError(
            "the loop should return a tuple (q, converged, iterations); got "
            f"{type(out).__name__}"
            + (f" of length {len(out)}" if isinstance(out, tuple) else "")
        )
    q, converged, iterations = out
    return np.r_[np.asarray(q, dtype=float).ravel(), float(bool(converged)), float(iterations)]


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

ik_position = exercise(_CHAPTER, "ik_position", MatrixArgumentsCheck(
    name="ik_position(chain, p_goal, q0, step, ...)",
    reference=_loop_ref,
    variables=[*_Q0, *_DQ, *_BUDGET],
    diagnoses=_loop_mistakes(),
    noun="starts, goals and iteration budgets",
    arguments=_loop_args,
    describe=_describe_loop,
    entry_label=_loop_entry,
    signature="ik_position(chain, p_goal, q0, step, max_step, tol, max_iterations) -> (q, converged, iterations)",
    hint=("The loop: e = p_goal − p(q); while ‖e‖ > tol and fewer than max_iterations steps: "
          "dq = step(J_v(q), e, q), capped to the norm max_step, q = clip(q + dq, limits), "
          "recompute e; return (q, ‖e‖ <= tol, steps taken)."),
    atol=1e-7,
    doc="Check an IK loop ik_position(chain, p_goal, q0, step, max_step, tol, max_iterations).",
    pack=_pack_loop,
))


# ------------------------------------------------------------------ helpers of the checks below
def _other_limits_chain():
    """The UR10 with joint ranges other than :data:`WORK_LIMITS` (to tell the chain's limits
    from the defaults)."""
    from robokin.chains import SerialChain

    robot = _robot()
    limits = np.array([[-2.5, 2.0], [-2.8, -0.2], [0.2, 2.9], [-2.6, 0.4], [-2.9, -0.1], [-1.0, 3.0]])
    return SerialChain(robot.elements, limits=limits, frame_names=robot.frame_names, name="ur10_other")


def _objective(q: np.ndarray, limits: np.ndarray) -> float:
    """Siciliano's joint-limit objective H(q) = −1/(2n) Σ ((q_i − q̄_i)/(q_M,i − q_m,i))²."""
    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]
    return float(-np.sum(((np.asarray(q) - middle) / span) ** 2) / (2 * len(middle)))


def _gradient(q: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """∇H of :func:`_objective`, shape (n,)."""
    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]
    return -(np.asarray(q) - middle) / span**2 / len(middle)


# ------------------------------------------------------------------ the joint-limit objective (task 2 c)
def _limit_cases() -> list[tuple[str, np.ndarray | None, np.ndarray]]:
    """(what, limits or None for the default, configurations (4, n)): the work cell's limits
    passed, another chain's passed, and the default; the configurations within the limits."""
    other = _other_limits_chain()
    return [
        ("with limits = WORK_LIMITS", WORK_LIMITS, _cell().random_configurations(4, seed=71)),
        ("with other joint limits", other.limits, other.random_configurations(4, seed=72)),
        ("with the default limits", None, _cell().random_configurations(4, seed=73)),
    ]


def _objective_variant(q: np.ndarray, limits: np.ndarray, code: str = "") -> np.ndarray:
    """H of :func:`_objective` over the last axis of ``q`` (or the typical mistake ``code``)."""
    limits = WORK_LIMITS if code == "default_limits" else limits
    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]
    n = len(middle)
    centre = 0.0 if code == "not_centred" else middle
    scale = 1.0 if code == "not_normalised" else span
    factor = {"no_factor": 1.0, "sign": -1.0 / (2 * n)}.get(code, 1.0 / (2 * n))
    return -factor * np.sum(((q - centre) / scale) ** 2, axis=-1)


_OBJECTIVE_MISTAKES = [
    ("sign",
     "{name} is −H: H = −1/(2n) Σ ((q_i − q̄_i)/(q_M,i − q_m,i))² is ≤ 0, and 0 with every joint "
     "at mid-range, its maximum."),
    ("no_factor",
     "{name} leaves out the factor 1/(2n) of eq. 3.57: H = −1/(2n) Σ ((q_i − q̄_i)/(q_M,i − "
     "q_m,i))², n = 6 joints."),
    ("not_normalised",
     "{name} does not divide by the joints' ranges: each term is ((q_i − q̄_i)/(q_M,i − q_m,i))², "
     "the distance from mid-range as a fraction of joint i's range."),
    ("not_centred",
     "{name} measures q_i from 0, not from the middle of its range q̄_i = (q_m,i + q_M,i)/2."),
    ("default_limits",
     "{name} ignores its argument limits: it uses WORK_LIMITS whatever limits it is given."),
]


class _JointLimitObjectiveCheck(FunctionCheck):
    """``joint_limit_objective(q, limits=WORK_LIMITS)``: H at one configuration and at a batch."""

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        cases = _limit_cases()
        n = sum(len(Q) for _, _, Q in cases) + len(cases)

        def arguments(q: np.ndarray, limits: np.ndarray | None) -> tuple:
            return (q.copy(),) if limits is None else (q.copy(), limits.copy())

        got: list[np.ndarray] = []
        for what, limits, Q in cases:
            values = []
            for q in Q:
                out = self.call(answer, arguments(q, limits), f"at q = {fmt(q)} rad {what}")
                try:
                    values.append(float(np.asarray(out, dtype=float).reshape(())))
                except (TypeError, ValueError):
                    return self.failure("type", f"{name} should return one number H for q of shape (n,); "
                                        f"{what} it returned {type(out).__name__} of shape "
                                        f"{np.shape(out)}.", n)
            out = self.call(answer, arguments(Q, limits), f"at a batch q of shape {Q.shape} {what}")
            try:
                batch = np.asarray(out, dtype=float)
            except (TypeError, ValueError):
                batch = np.full(0, np.nan)
            if batch.shape != (len(Q),):
                return self.failure("batch", (
                    f"{name} for a batch q of shape {Q.shape} {what} returns shape {batch.shape}; "
                    f"expected ({len(Q)},), one H per row: sum over the joints only, the last axis "
                    "(np.sum(..., axis=-1))."), n)
            got.append(np.r_[values, batch])

        def same(a: np.ndarray, b: np.ndarray) -> bool:
            return bool(np.allclose(a, b, rtol=1e-9, atol=1e-12))

        def expected(code: str = "") -> list[np.ndarray]:
            return [np.tile(_objective_variant(Q, WORK_LIMITS if limits is None else limits, code), 2)
                    for _, limits, Q in cases]

        if all(same(g, r) for g, r in zip(got, expected())):
            return self.success(f"{name} is correct (checked at {n - len(cases)} configurations and "
                                f"{len(cases)} batches, with other joint limits and the default).", n)
        named = self.diagnose(_OBJECTIVE_MISTAKES, lambda code: all(
            same(g, r) for g, r in zip(got, expected(code))), n)
        if named is not None:
            return named
        ratio = np.concatenate(got) / np.concatenate(expected())
        if np.allclose(ratio, ratio[0], rtol=1e-9):
            return self.failure("factor", (
                f"{name} is {ratio[0]:.6g} × H at every configuration: the factor in front of the "
                "sum is −1/(2n), n = 6 joints, H = −1/(2n) Σ ((q_i − q̄_i)/(q_M,i − q_m,i))²."), n)
        k = next(i for i, (g, r) in enumerate(zip(got, expected())) if not same(g, r))
        what, limits, Q = cases[k]
        row = int(np.argmax(~np.isclose(got[k], expected()[k], rtol=1e-9, atol=1e-12))) % len(Q)
        return self.failure("mismatch", (
            f"{name} at q = {fmt(Q[row])} rad {what} returns {got[k][row]:.6g}; H = "
            f"{expected()[k][row]:.6g}. H = −1/(2n) Σ ((q_i − q̄_i)/(q_M,i − q_m,i))², q̄_i the "
            "middle of joint i's range."), n)


joint_limit_objective = exercise(_CHAPTER, "joint_limit_objective", _JointLimitObjectiveCheck(
    name="joint_limit_objective",
    signature="joint_limit_objective(q, limits=WORK_LIMITS) -> H (a number; (N,) for q (N, n))",
    noun="configurations",
    doc=("Check joint_limit_objective(q, limits=WORK_LIMITS) -> H, Siciliano's eq. 3.57, at "
         "configurations and batches of the work cell and of a chain with other joint limits."),
))


def _gradient_variant(q: np.ndarray, limits: np.ndarray, code: str = "") -> np.ndarray:
    """∇H of :func:`_gradient` (or the typical mistake ``code``), shape (n,)."""
    limits = WORK_LIMITS if code == "default_limits" else limits
    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]
    n = len(middle)
    if code == "span_not_squared":
        return -(q - middle) / span / n
    if code == "not_normalised":
        return -(q - middle) / n
    if code == "not_centred":
        return -q / span**2 / n
    factor = {"sign": -1.0, "no_factor": 2.0 * n, "square_not_brought_down": 0.5}.get(code, 1.0)
    return factor * _gradient(q, limits)


_GRADIENT_MISTAKES = [
    ("sign",
     "{name} is −∇H: it points towards the joint limits. H is largest (0) with every joint at "
     "mid-range, so its gradient points from each joint towards the middle of its range."),
    ("no_factor",
     "{name} is 2n times ∇H: the gradient of the sum without H's factor −1/(2n)."),
    ("square_not_brought_down",
     "{name} is ∇H/2: the derivative of x² is 2x (the chain rule on each square)."),
    ("span_not_squared",
     "{name} divides by the range (q_M,i − q_m,i) once: each term is ((q_i − q̄_i)/(q_M,i − "
     "q_m,i))², a square of the quotient, the range's too."),
    ("not_normalised",
     "{name} does not divide by the joints' ranges: each term of H is ((q_i − q̄_i)/(q_M,i − "
     "q_m,i))²."),
    ("not_centred",
     "{name} measures q_i from 0, not from the middle of its range q̄_i = (q_m,i + q_M,i)/2."),
    ("default_limits",
     "{name} ignores its argument limits: it uses WORK_LIMITS whatever limits it is given."),
]


class _JointLimitGradientCheck(FunctionCheck):
    """``joint_limit_gradient(q, limits=WORK_LIMITS)``: ∇H at configurations of its own."""

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        cases = _limit_cases()
        n = sum(len(Q) for _, _, Q in cases)
        got: list[np.ndarray] = []
        for what, limits, Q in cases:
            for q in Q:
                args = (q.copy(),) if limits is None else (q.copy(), limits.copy())
                out = self.call(answer, args, f"at q = {fmt(q)} rad {what}")
                try:
                    value = np.asarray(out, dtype=float)
                except (TypeError, ValueError):
                    value = np.full(0, np.nan)
                if value.shape != (N_JOINTS,):
                    return self.failure("shape", (
                        f"{name} at q = {fmt(q)} rad {what} returns {type(out).__name__} of shape "
                        f"{np.shape(out)}; expected shape ({N_JOINTS},), one ∂H/∂q_i per joint."), n)
                got.append(value)
        points = [(q, WORK_LIMITS if limits is None else limits, what) for what, limits, Q in cases for q in Q]

        def explains(code: str) -> bool:
            return all(np.allclose(g, _gradient_variant(q, limits, code), rtol=1e-9, atol=1e-12)
                       for g, (q, limits, _) in zip(got, points))

        if explains(""):
            return self.success(f"{name} is correct (checked at {n} configurations, with other joint "
                                "limits and the default).", n)
        named = self.diagnose(_GRADIENT_MISTAKES, explains, n)
        if named is not None:
            return named
        k = next(i for i, (g, (q, limits, _)) in enumerate(zip(got, points))
                 if not np.allclose(g, _gradient(q, limits), rtol=1e-9, atol=1e-12))
        q, limits, what = points[k]
        wrong = ", ".join(f"[{i + 1}]" for i in np.flatnonzero(
            ~np.isclose(got[k], _gradient(q, limits), rtol=1e-9, atol=1e-12)))
        return self.failure("mismatch", (
            f"{name} at q = {fmt(q)} rad {what} returns {fmt(got[k])}; it is not the slope of H "
            f"(eq. 3.57) in its entries {wrong}: compare them with central differences of your H, "
            "(H(q + h e_i) − H(q − h e_i)) / (2h). Differentiate H term by term (the chain rule "
            "on each square)."), n)


joint_limit_gradient = exercise(_CHAPTER, "joint_limit_gradient", _JointLimitGradientCheck(
    name="joint_limit_gradient",
    signature="joint_limit_gradient(q, limits=WORK_LIMITS) -> (n,) array",
    noun="configurations",
    doc=("Check joint_limit_gradient(q, limits=WORK_LIMITS) -> ∇H (n,), the gradient of "
         "Siciliano's eq. 3.57, at configurations of the work cell and of a chain with other "
         "joint limits."),
))


# ------------------------------------------------------------------ bisection (task 6)
def _bisect_cases() -> list[tuple[str, Any, float, float, float | None, float, bool]]:
    """(description, f, low, high, tol or None for the default, root, f rises through it)."""
    return [
        ("f(x) = x³ − 2 on [0, 2]", lambda x: x**3 - 2.0, 0.0, 2.0, 1e-12, 2.0 ** (1 / 3), True),
        ("f(x) = e^x − 3 on [−1, 4]", lambda x: math.exp(x) - 3.0, -1.0, 4.0, 1e-11, math.log(3.0),
         True),
        ("f(x) = cos x on [0, 3], the default tol", np.cos, 0.0, 3.0, None, math.pi / 2, False),
        ("f(x) = 0.7 − x on [−3, 5]", lambda x: 0.7 - x, -3.0, 5.0, 1e-12, 0.7, False),
        ("f(x) = sin x on [2, 4.5], tol = 1e-4", np.sin, 2.0, 4.5, 1e-4, math.pi, False),
        ("f(x) = sin x on [2, 4.5], tol = 1e-10", np.sin, 2.0, 4.5, 1e-10, math.pi, False),
    ]


class _BisectCheck(FunctionCheck):
    """``bisect(f, low, high, tol=1e-13)``: a root within tol; ValueError without a bracket."""

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        cases = _bisect_cases()
        n = len(cases)
        misses = []
        for text, f, low, high, tol, root, rising in cases:
            args = (f, low, high) if tol is None else (f, low, high, tol)
            x = self.call(answer, args, f"for {text}")
            try:
                x = float(x)
            except (TypeError, ValueError):
                return self.failure("type", f"{name} should return one number x (the root); for {text} "
                                    f"it returned {type(x).__name__}.", 1)
            tol_used = 1e-13 if tol is None else tol
            if not abs(x - root) <= tol_used + 1e-15:
                misses.append((text, low, high, tol_used, root, x, rising))
        if misses:
            if not any(miss[6] for miss in misses):
                return self.failure("rising_only", (
                    f"{name} finds the roots of functions that rise through 0 but not of "
                    f"those that fall ({misses[0][0]}): it keeps the half by the sign of "
                    "f(middle) alone (f(middle) < 0 → low = middle). Compare with the sign of "
                    "f(low): when f(middle) has the sign of f(low) the root is in [middle, high]."), n)
            text, low, high, tol_used, root, x, _ = misses[0]
            head = f"{name} for {text} returns {x!r}; the root is {root!r}"
            if min(abs(x - low), abs(x - high)) < 1e-6:
                return self.failure("wrong_half", head + (
                    ", an end of the bracket: it keeps the half WITHOUT the sign change. When "
                    "f(middle) has the sign of f(low), the root is in [middle, high] (low = "
                    "middle), else in [low, middle]."), n)
            if abs(x - root) < 1e-3:
                return self.failure("tolerance", head + (
                    f" (off by {abs(x - root):.1e}, tol = {tol_used:g}): it stops before the "
                    "bracket is narrow enough. Halve until high − low <= 2 tol and return the "
                    "middle, which is then within tol of the root; a fixed number of halvings "
                    "ignores tol."), n)
            return self.failure("mismatch", head + ". Keep a bracket [low, high] with f(low) and "
                                "f(high) of opposite signs and halve it until it is 2 tol wide.", n)
        try:
            x = answer(lambda t: t * t + 1.0, -1.0, 1.0)
        except Exception as exc:  # noqa: BLE001 - the student's exception is the answer here
            described = f"{type(exc).__name__}: {exc}"
            if isinstance(exc, ValueError) or "ValueError" in described:
                return self.success(f"{name} is correct (checked on {n} brackets, rising and falling "
                                    "functions, several tolerances, and a bracket without a sign "
                                    "change).", n + 1)
            return self.failure("wrong_exception", (
                f"{name} raises {type(exc).__name__} when f(low) and f(high) have the same "
                "sign (f(x) = x² + 1 on [−1, 1]); raise ValueError, the error for a value that is "
                "not allowed."), n + 1)
        return self.failure("no_value_error", (
            f"{name} returns {x!r} for f(x) = x² + 1 on [−1, 1], which has no root: when "
            "f(low) and f(high) have the same sign there is no bracket, and it should raise "
            "ValueError instead of returning a number."), n + 1)


bisect = exercise(_CHAPTER, "bisect", _BisectCheck(
    name="bisect",
    signature="bisect(f, low, high, tol=1e-13) -> x",
    noun="brackets",
    doc=("Check a bisection bisect(f, low, high, tol=1e-13) -> x within tol of a root of f in "
         "[low, high]; ValueError when f(low) and f(high) have the same sign."),
))


# ------------------------------------------------------------------ restarts (task 5)
#: The chapter's step cap (rad), tolerance (m) and iteration budget: ``ik_position``'s defaults,
#: with which ``ik_restarts`` runs it.
_RESTART_MAX_STEP, _RESTART_TOL, _RESTART_BUDGET = 0.5, 1e-9, 100


def _attempt(p_goal: np.ndarray, q_start: np.ndarray) -> tuple[np.ndarray, bool, int]:
    """One attempt of the chapter's loop with the pseudoinverse step, from ``q_start``."""
    packed = _loop(_cell(), p_goal, q_start, _pinv_step, _RESTART_MAX_STEP, _RESTART_TOL,
                   _RESTART_BUDGET)
    return packed[:6], bool(packed[6]), int(packed[7])


def _restarts(p_goal: np.ndarray, starts: np.ndarray, variant: str = "") -> np.ndarray:
    """The reference restart loop (or a typical mistake), packed as
    ``[q (6), converged, attempts, iterations]``."""
    total, runs = 0, []
    q_from = starts[0]
    for q_start in starts:
        q, converged, iterations = _attempt(p_goal, q_from if variant == "continue_from_last" else q_start)
        runs.append((q, converged, iterations))
        total += iterations
        q_from = q
        if variant == "no_restart" or (converged and variant != "no_break"):
            break
    q, converged, iterations = runs[-1]
    if variant == "no_break":
        converged = any(run[1] for run in runs)
    if variant == "first_attempt_q":
        q = runs[0][0]
    counted = {"last_attempt_only": iterations}.get(variant, total)
    attempts = len(runs)
    made = attempts - 1 if variant == "attempts_from_zero" else attempts
    return np.r_[q, float(converged), float(made), float(counted)]


@lru_cache(maxsize=1)
def _restart_cases() -> tuple[tuple[str, np.ndarray, np.ndarray], ...]:
    """(what, p_goal, starts (3, 6)): the first start converges; the first misses and the
    second converges; no start converges (a goal out of reach)."""
    cell = _cell()
    starts = cell.random_configurations(3, seed=23)
    cases = [("a goal the first start reaches", cell.fk(starts[0] + 0.3)[:3, 3], starts)]
    for goal in cell.fk(cell.random_configurations(60, seed=22))[:, :3, 3]:
        first, second = _attempt(goal, starts[0]), _attempt(goal, starts[1])
        if not first[1] and second[1]:
            cases.append(("a goal the first start misses and the second reaches", goal, starts))
            break
    cases.append(("a goal out of reach", np.array([2.0, 1.0, 1.0]), starts))
    return tuple(cases)


_RESTART_MISTAKES = [
    ("last_attempt_only",
     "{name} counts the steps of the last attempt only: iterations is the number of steps over "
     "ALL the attempts made (add each attempt's iterations)."),
    ("no_restart",
     "{name} makes one attempt only: when ik_position does not converge from a start, try the "
     "next row of starts, until one converges or the starts run out."),
    ("continue_from_last",
     "{name} starts each new attempt from where the last one ended: a restart begins at the "
     "next row of starts, q_start = starts[k]."),
    ("attempts_from_zero",
     "{name} counts the attempts from 0: attempts is the number of attempts made, 1 when the "
     "first start converges, s (the number of starts) when none does."),
    ("no_break",
     "{name} goes on after an attempt converged: stop at the first attempt that converges and "
     "return its q."),
    ("first_attempt_q",
     "{name} returns the first attempt's q: return the configuration of the LAST attempt made "
     "(the one that converged, if any)."),
]


@dataclasses.dataclass(repr=False)
class _LaterStepFunctionCheck(FunctionCheck):
    """A :class:`FunctionCheck` of a function that builds on earlier steps: it is called with
    robokin's steps (``steps()``, by the names of its keyword parameters: ``solve=``,
    ``objective=``, ``projector=``, ``gradient=``; :func:`with_reference_steps`) in place of the
    student's own defaults, as the graded tests call it, so that its verdict (and the grading
    report's) is on this step alone, not on a mistake in an earlier one."""

    steps: Callable[[], dict[str, Callable[..., Any]]] = dict

    def evaluate(self, answer: Any) -> CheckResult:
        """:meth:`FunctionCheck.evaluate` of ``answer`` given robokin's earlier steps."""
        if callable(answer):
            answer = with_reference_steps(answer, self.steps())
        return super().evaluate(answer)


class _RestartsCheck(_LaterStepFunctionCheck):
    """``ik_restarts(chain, p_goal, starts, step) -> (q, converged, attempts, iterations)``."""

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        cases = _restart_cases()
        n = len(cases)
        got = []
        for what, goal, starts in cases:
            out = self.call(answer, (_cell(), goal.copy(), starts.copy(), PseudoinverseStep()),
                            f"for {what}")
            if not isinstance(out, tuple) or len(out) != 4:
                return self.failure("type", (
                    f"{name} should return the tuple (q, converged, attempts, iterations); "
                    f"for {what} it returned {type(out).__name__}"
                    + (f" of length {len(out)}." if isinstance(out, tuple) else ".")), n)
            q, converged, attempts, iterations = out
            try:
                got.append(np.r_[np.asarray(q, dtype=float).ravel(), float(bool(converged)),
                                 float(attempts), float(iterations)])
            except (TypeError, ValueError):
                return self.failure("type", f"{name}'s q should be 6 joint angles and attempts, "
                                    "iterations numbers.", n)

        def same(a: np.ndarray, b: np.ndarray) -> bool:
            return a.shape == b.shape and bool(np.allclose(a, b, rtol=0.0, atol=1e-7))

        refs = [_restarts(goal, starts) for _, goal, starts in cases]
        if all(same(g, r) for g, r in zip(got, refs)):
            return self.success(f"{name} is correct (checked on {n} goals: reached from the first "
                                "start, from the second, and out of reach).", n)
        named = self.diagnose(_RESTART_MISTAKES, lambda code: all(
            same(g, _restarts(goal, starts, code)) for g, (_, goal, starts) in zip(got, cases)), n)
        if named is not None:
            return named
        k = next(i for i, (g, r) in enumerate(zip(got, refs)) if not same(g, r))
        fields = ["q", "converged", "attempts", "iterations"]
        g, r = got[k], refs[k]
        if g.shape != r.shape:
            wrong = "q"
        else:
            parts = [g[:6], g[6], g[7], g[8]], [r[:6], r[6], r[7], r[8]]
            wrong = next(f for f, a, b in zip(fields, *parts) if not np.allclose(a, b, atol=1e-7))
        expected = {"q": "", "converged": f" (expected {bool(r[6])})",
                    "attempts": f" (expected {int(r[7])})", "iterations": f" (expected {int(r[8])})"}
        return self.failure("mismatch", (
            f"{name} for {cases[k][0]} (3 starts, the pseudoinverse step) returns a wrong "
            f"{wrong}{expected[wrong]}. It was given robokin's loop as solve, as the graded test "
            "gives it: if it runs the solve it is given, the cause is in ik_restarts itself; if it "
            "calls your ik_position directly, a mistake there shows here too (if "
            "check_ur10.ik_position(ik_position) fails, fix ik_position first, and run solve). "
            "Run solve from each start in turn, with its defaults, stop at the first that "
            "converges, and return that attempt's q, whether it converged, the attempts made and "
            "the steps over all of them."), n)


ik_restarts = exercise(_CHAPTER, "ik_restarts", _RestartsCheck(
    steps=lambda: {"solve": reference_ik_position},
    name="ik_restarts",
    signature="ik_restarts(chain, p_goal, starts, step) -> (q, converged, attempts, iterations)",
    noun="goals",
    doc=("Check ik_restarts(chain, p_goal, starts, step) -> (q, converged, attempts, "
         "iterations): ik_position from each row of starts in turn until one converges."),
))


# ------------------------------------------------------------------ the figures of a run (task 3)
_SUMMARY_KEYS = ("iterations", "error_nm", "path", "min_limit", "end_limit", "end_H", "min_w", "end_w")


def _limit_distance(path: np.ndarray, limits: np.ndarray) -> np.ndarray:
    return np.min(np.minimum(path - limits[:, 0], limits[:, 1] - path), axis=1)


def _manipulability(chain, path: np.ndarray, full: bool = False, squared: bool = False) -> np.ndarray:
    out = []
    for q in path:
        J = chain.jacobian(q) if full else chain.position_jacobian(q)
        det = max(float(np.linalg.det(J @ J.T)), 0.0)
        out.append(det if squared else math.sqrt(det))
    return np.array(out)


def _summary(chain, p_goal: np.ndarray, path: np.ndarray) -> dict[str, float]:
    near, w = _limit_distance(path, chain.limits), _manipulability(chain, path)
    return dict(
        iterations=float(len(path) - 1),
        error_nm=1e9 * float(np.linalg.norm(p_goal - chain.fk(path[-1])[:3, 3])),
        path=float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum()),
        min_limit=float(near[1:].min()), end_limit=float(near[-1]),
        end_H=_objective(path[-1], chain.limits),
        min_w=float(w[1:].min()), end_w=float(w[-1]),
    )


def _summary_mistakes(chain, p_goal: np.ndarray, path: np.ndarray) -> dict[str, list[tuple[str, float, str]]]:
    """Per key, (code, the value the mistake gives, message)."""
    near = _limit_distance(path, chain.limits)
    near_default = _limit_distance(path, WORK_LIMITS)
    lower_only = np.min(path - chain.limits[:, 0], axis=1)
    w = _manipulability(chain, path)
    error_m = float(np.linalg.norm(p_goal - chain.fk(path[-1])[:3, 3]))
    steps = np.diff(path, axis=0)
    return {
        "iterations": [("iterations_rows", float(len(path)),
                        "counts the rows of path: k + 1 iterates are k steps (iterations = len(path) − 1)")],
        "error_nm": [
            ("error_in_m", error_m, "is in metres: the key asks for nanometres (× 1e9)"),
            ("error_in_mm", 1e3 * error_m, "is in millimetres: the key asks for nanometres (× 1e9 from m)"),
            ("error_at_start", 1e9 * float(np.linalg.norm(p_goal - chain.fk(path[0])[:3, 3])),
             "is the error at the start path[0]: the final error is at the last iterate path[-1]"),
        ],
        "path": [
            ("path_chord", float(np.linalg.norm(path[-1] - path[0])),
             "is the distance from the start to the end: the path length is the sum of the lengths "
             "of the k steps, Σ‖q_(i+1) − q_i‖"),
            ("path_l1", float(np.abs(steps).sum()),
             "adds the joints' |Δq_j|: a step's length is its Euclidean norm ‖Δq‖"),
            ("path_squared", float((steps**2).sum()),
             "adds the squared step lengths: the path length is Σ‖Δq‖, not Σ‖Δq‖²"),
        ],
        "min_limit": [
            ("min_limit_with_start", float(near.min()),
             "is taken over every iterate, the start included: the smallest over the iterates "
             "AFTER the start, path[1:]"),
            ("limits_not_the_chains", float(near_default[1:].min()),
             "uses WORK_LIMITS, not the chain's limits: measure with chain.limits"),
            ("lower_limits_only", float(lower_only[1:].min()),
             "measures from the lower limits only: a joint is near a limit when it is near "
             "either end, min(q − lower, upper − q)"),
        ],
        "end_limit": [
            ("end_limit_at_start", float(near[0]), "is the value at the start: the key asks for the last iterate"),
            ("limits_not_the_chains", float(near_default[-1]),
             "uses WORK_LIMITS, not the chain's limits: measure with chain.limits"),
        ],
        "end_H": [
            ("H_default_limits", _objective(path[-1], WORK_LIMITS),
             "is H with the default limits WORK_LIMITS: pass the chain's, "
             "joint_limit_objective(q, chain.limits)"),
            ("H_at_start", _objective(path[0], chain.limits), "is H at the start: the key asks for the last iterate"),
        ],
        "min_w": [
            ("min_w_with_start", float(w.min()),
             "is taken over every iterate, the start included: the smallest over path[1:]"),
            ("w_squared", float(_manipulability(chain, path[1:], squared=True).min()),
             "is det(J_v J_vᵀ): the manipulability is its square root, w = √det(J_v J_vᵀ)"),
            ("w_full_jacobian", float(_manipulability(chain, path[1:], full=True).min()),
             "uses the full 6×6 Jacobian: the position manipulability uses J_v (3×6)"),
        ],
        "end_w": [
            ("end_w_at_start", float(w[0]), "is the value at the start: the key asks for the last iterate"),
            ("w_squared", float(_manipulability(chain, path[-1:], squared=True)[0]),
             "is det(J_v J_vᵀ): the manipulability is its square root, w = √det(J_v J_vᵀ)"),
        ],
    }


@lru_cache(maxsize=1)
def _summary_cases() -> tuple[tuple[str, Any, np.ndarray, np.ndarray], ...]:
    """(what, chain, p_goal, path (6, 6)): random iterates whose start is the nearest to a joint
    limit and has the smallest manipulability (so that a figure taken with the start differs),
    on the work cell and on a chain with other limits."""
    out = []
    for seed, chain, what in ((11, _cell(), "the work cell"), (12, _other_limits_chain(),
                                                               "a chain with other joint limits")):
        path = chain.random_configurations(6, seed=seed)
        path = path[np.argsort(_manipulability(chain, path))]  # the start has the smallest w
        # and its last joint 1 mrad from a limit (q6 turns the flange about its own point,
        # so w does not change)
        path[0, 5] = chain.limits[5, 0] + 0.001
        goal = chain.fk(chain.random_configurations(1, seed=seed + 10)[0])[:3, 3]
        out.append((what, chain, goal, path))
    return tuple(out)


class _SummaryCheck(_LaterStepFunctionCheck):
    """``summary(chain, p_goal, path) -> dict`` of the figures of one IK run."""

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        cases = _summary_cases()
        n = len(cases)
        for what, chain, goal, path in cases:
            out = self.call(answer, (chain, goal.copy(), path.copy()), f"on random iterates ({what})")
            if not isinstance(out, dict):
                return self.failure("type", f"{name} should return a dict with the keys "
                                    f"{', '.join(_SUMMARY_KEYS)}; got {type(out).__name__}.", n)
            missing = [key for key in _SUMMARY_KEYS if key not in out]
            if missing:
                return self.failure("missing_key", f"{name}'s dict lacks the key(s) {', '.join(missing)}.", n)
            reference = _summary(chain, goal, path)
            for key in _SUMMARY_KEYS:
                try:
                    value = float(out[key])
                except (TypeError, ValueError):
                    return self.failure("type", f"{name}['{key}'] should be a number; got "
                                        f"{type(out[key]).__name__}.", n)
                if math.isclose(value, reference[key], rel_tol=1e-7, abs_tol=1e-9):
                    continue
                head = (f"{name}['{key}'] on {len(path) - 1}-step random iterates ({what}) "
                        f"is {value:.6g}, expected {reference[key]:.6g}")
                for code, wrong, text in _summary_mistakes(chain, goal, path)[key]:
                    if math.isclose(value, wrong, rel_tol=1e-7, abs_tol=1e-9):
                        return self.failure(code, f"{head}: it {text}.", n)
                return self.failure(f"{key}_wrong", head + ".", n)
        return self.success(f"{name} is correct (checked on random iterates of the work cell and of "
                            "a chain with other joint limits).", n)


summary = exercise(_CHAPTER, "summary", _SummaryCheck(
    steps=lambda: {"objective": reference_joint_limit_objective},
    name="summary",
    signature="summary(chain, p_goal, path) -> dict",
    noun="runs",
    doc=("Check summary(chain, p_goal, path) -> dict with iterations, error_nm, path, min_limit, "
         "end_limit, end_H, min_w, end_w of the iterates path (k + 1, n)."),
))


# ------------------------------------------------------------------ self-motion (task 4)
def _self_motion(chain, p_goal, q_start, gain, steps, variant: str = "") -> np.ndarray:
    """The reference self-motion q ← q + J⁺e + N k ∇H(q) (or a typical mistake): the
    configurations before each step, shape (steps, n)."""
    limits = WORK_LIMITS if variant == "default_limits" else chain.limits
    q = np.array(q_start, dtype=float)
    rows = []
    for _ in range(steps + (1 if variant == "rows_after_step" else 0)):
        rows.append(q)
        e = p_goal - chain.fk(q)[:3, 3]
        J = chain.position_jacobian(q)
        J_pinv = np.linalg.pinv(J)
        N = np.eye(len(q)) - J_pinv @ J
        g = {"gradient_sign": -1.0, "no_gain": 1.0 / gain}.get(variant, 1.0) * gain * _gradient(q, limits)
        correction = np.zeros_like(q) if variant == "no_correction" else J_pinv @ e
        q = q + correction + (g if variant == "not_projected" else N @ g)
    out = np.array(rows)
    return out[1:] if variant == "rows_after_step" else out


_SELF_MISTAKES = [
    ("no_correction",
     "{name} leaves out the correction J⁺e: each finite null-space step moves the flange to "
     "second order, and without q ← q + J⁺e + N k ∇H the drift adds up."),
    ("not_projected",
     "{name} adds k ∇H(q) without projecting it: only N k ∇H (N the null-space projector, "
     "projector(J)) leaves the flange in place."),
    ("gradient_sign",
     "{name} descends H: the step N k ∇H(q) with k > 0 climbs H, moving the joints towards the "
     "middle of their ranges."),
    ("no_gain",
     "{name} leaves out the gain: the null-space term is N k ∇H(q) with k = gain."),
    ("rows_after_step",
     "{name} records the configurations AFTER each step: row i is the configuration before "
     "step i, so the first row is q_start."),
    ("default_limits",
     "{name} takes ∇H with the default limits WORK_LIMITS: use the chain's, "
     "joint_limit_gradient(q, chain.limits)."),
]


@lru_cache(maxsize=1)
def _self_motion_cases() -> tuple[tuple[str, Any, np.ndarray, np.ndarray, float, int], ...]:
    """(what, chain, p_goal, q_start, gain, steps)."""
    out = []
    for seed, chain, gain, steps, offset, what in (
        (31, _cell(), 1.5, 6, 0.0, "a start on its goal, on the work cell"),
        (32, _cell(), 0.75, 4, 0.002, "a goal 2 mm off the start, on the work cell"),
        (33, _other_limits_chain(), 1.0, 5, 0.0, "a chain with other joint limits"),
    ):
        q_start = chain.random_configurations(1, seed=seed)[0]
        goal = chain.fk(q_start)[:3, 3] + offset
        out.append((what, chain, goal, q_start, gain, steps))
    return tuple(out)


class _SelfMotionCheck(_LaterStepFunctionCheck):
    """``self_motion(chain, p_goal, q_start, gain, steps) -> (steps, n)``."""

    def judge(self, answer: Any) -> CheckResult:
        name = self.name
        cases = _self_motion_cases()
        n = len(cases)
        got = []
        for what, chain, goal, q_start, gain, steps in cases:
            out = self.call(answer, (chain, goal.copy(), q_start.copy(), gain, steps), f"for {what}")
            try:
                got.append(np.asarray(out, dtype=float))
            except (TypeError, ValueError):
                return self.failure("type", f"{name} should return an array (steps, n) of "
                                    f"configurations; got {type(out).__name__}.", n)

        def same(a: np.ndarray, b: np.ndarray) -> bool:
            return a.shape == b.shape and bool(np.allclose(a, b, rtol=0.0, atol=1e-9))

        refs = [_self_motion(chain, goal, q0, gain, steps) for _, chain, goal, q0, gain, steps in cases]
        if all(same(g, r) for g, r in zip(got, refs)):
            return self.success(f"{name} is correct (checked on {n} starts, gains and step counts, one "
                                "on a chain with other joint limits).", n)
        named = self.diagnose(_SELF_MISTAKES, lambda code: all(
            same(g, _self_motion(chain, goal, q0, gain, steps, code))
            for g, (_, chain, goal, q0, gain, steps) in zip(got, cases)), n)
        if named is not None:
            return named
        k = next(i for i, (g, r) in enumerate(zip(got, refs)) if not same(g, r))
        g, r = got[k], refs[k]
        if g.shape != r.shape:
            return self.failure("shape", (
                f"{name} for {cases[k][0]} with steps = {cases[k][5]} returns shape {g.shape}; "
                f"expected {r.shape}: one row per step, the configuration before it (the first row "
                "is q_start)."), n)
        row = int(np.argmax(np.abs(g - r).max(axis=1) > 1e-9))
        return self.failure("mismatch", (
            f"{name} for {cases[k][0]} differs from q ← q + J⁺e + N k ∇H(q) from row {row} "
            f"on (row 0 is q_start). It was given robokin's projector and gradient, as the graded "
            "test gives them: if it takes N and ∇H from its arguments projector and gradient, the "
            "cause is in self_motion itself; if it calls your nullspace_projector or "
            "joint_limit_gradient directly, a mistake of Task 2 shows here too (if Task 2's test "
            "of them fails, fix those first, and take them from the arguments). Check the step "
            "e = p_goal − p(q), J⁺, N = projector(J) and ∇H = gradient(q, chain.limits)."), n)


self_motion = exercise(_CHAPTER, "self_motion", _SelfMotionCheck(
    steps=lambda: {"projector": reference_nullspace_projector, "gradient": reference_joint_limit_gradient},
    name="self_motion",
    signature="self_motion(chain, p_goal, q_start, gain, steps) -> (steps, n) array",
    noun="starts",
    doc=("Check self_motion(chain, p_goal, q_start, gain, steps) -> the configurations before "
         "each step q ← q + J⁺e + N k ∇H(q), shape (steps, n)."),
))


# ------------------------------------------------------------------ robokin's steps (the tests' stand-ins)
def reference_weighted_pinv(J: Any, W: Any) -> np.ndarray:
    r"""robokin's answer to ``weighted_pinv`` of Task 2 (the tests' stand-in).

    The graded tests of the later steps pass robokin's steps to the student's functions in
    place of the student's own, so that a mistake in one step costs the points of that step
    only.

    Parameters
    ----------
    J : array_like, shape (m, 6)
        A task Jacobian of the UR10, of full row rank.
    W : array_like, shape (6, 6)
        A positive-definite weight matrix.

    Returns
    -------
    numpy.ndarray, shape (6, m)
        :math:`J_W^+`, the weighted pseudoinverse (its closed form is the answer of Task 2 (a),
        so it is not written here).
    """
    J = as_float_array(J, "J", shape=(None, N_JOINTS))
    W = as_float_array(W, "W", shape=(N_JOINTS, N_JOINTS))
    with np.errstate(all="ignore"):
        try:
            out = _weighted(J, W)
        except np.linalg.LinAlgError:
            raise ValueError("the weighted step has no unique minimiser: J must have full row "
                             "rank and W be positive definite") from None
    return check_result_finite(out, "the weighted pseudoinverse", J=J, W=W)


def reference_dls_step(J: Any, e: Any, damping: float) -> np.ndarray:
    r"""robokin's answer to ``dls_step`` of Task 2 (the tests' stand-in).

    As :func:`reference_weighted_pinv`, for the damped least-squares step.

    Parameters
    ----------
    J : array_like, shape (m, 6)
        A task Jacobian of the UR10.
    e : array_like, shape (m,)
        The task error.
    damping : float
        The damping :math:`\lambda`, in the units of ``J``.

    Returns
    -------
    numpy.ndarray, shape (6,)
        The step that minimises :math:`\lVert J \Delta q - e\rVert^2 + \lambda^2 \lVert \Delta q\rVert^2`
        (its closed form is the answer of Task 2 (b), so it is not written here).
    """
    J = as_float_array(J, "J", shape=(None, N_JOINTS))
    e = as_float_array(e, "e", shape=(J.shape[0],))
    damping = float(as_float_array(damping, "damping", shape=()))
    with np.errstate(all="ignore"):
        try:
            out = _dls(J, e, damping**2)
        except np.linalg.LinAlgError:
            raise ValueError("the damped step has no unique minimiser: give a damping > 0 or a "
                             "J of full row rank") from None
    return check_result_finite(out, "the damped step", J=J, e=e, damping=damping)


def reference_nullspace_projector(J: Any) -> np.ndarray:
    r"""robokin's answer to ``nullspace_projector`` of Task 2 (the tests' stand-in).

    As :func:`reference_weighted_pinv`, for the null-space projector.

    Parameters
    ----------
    J : array_like, shape (m, 6)
        A task Jacobian of the UR10.

    Returns
    -------
    numpy.ndarray, shape (6, 6)
        The orthogonal projector onto the null space of ``J`` (its closed form is the answer
        of Task 2 (c), so it is not written here).
    """
    J = as_float_array(J, "J", shape=(None, N_JOINTS))
    with np.errstate(all="ignore"):
        try:
            out = np.eye(J.shape[1]) - np.linalg.pinv(J) @ J
        except np.linalg.LinAlgError:
            raise ValueError("J has no singular value decomposition (its entries overflow)") from None
    return check_result_finite(out, "the null-space projector", J=J)


def _limits_of(q: np.ndarray, limits: Any) -> np.ndarray:
    """``limits`` as an (n, 2) array of floats for configurations ``q`` (..., n), each range
    of positive length."""
    limits = as_float_array(limits, "limits", shape=(q.shape[-1], 2))
    if not np.all(limits[:, 1] > limits[:, 0]):
        raise ValueError("limits must hold [lower, upper] with lower < upper for every joint")
    return limits


def reference_joint_limit_objective(q: Any, limits: Any = WORK_LIMITS) -> float | np.ndarray:
    r"""robokin's answer to ``joint_limit_objective`` of Task 2 (the tests' stand-in).

    As :func:`reference_weighted_pinv`, for Siciliano's joint-limit objective.

    Parameters
    ----------
    q : array_like, shape (n,) or (N, n)
        One configuration or a batch (rad).
    limits : array_like, shape (n, 2)
        ``[lower, upper]`` of each joint (rad); the chapter's working limits by default.

    Returns
    -------
    float or numpy.ndarray, shape (N,)
        :math:`H(q) = -\frac{1}{2n}\sum_i \left(\frac{q_i - \bar q_i}{q_{M,i} - q_{m,i}}\right)^2`.
    """
    q, batched = as_batch(q, None, "q")
    limits = _limits_of(q, limits)
    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]
    with np.errstate(all="ignore"):
        H = -np.sum(((q - middle) / span) ** 2, axis=-1) / (2 * len(middle))
    H = check_result_finite(H, "H", q=q, limits=limits)
    return H if batched else float(H)


def reference_joint_limit_gradient(q: Any, limits: Any = WORK_LIMITS) -> np.ndarray:
    r"""robokin's answer to ``joint_limit_gradient`` of Task 2 (the tests' stand-in).

    As :func:`reference_weighted_pinv`, for the gradient of
    :func:`reference_joint_limit_objective`.

    Parameters
    ----------
    q : array_like, shape (n,)
        A configuration (rad).
    limits : array_like, shape (n, 2)
        ``[lower, upper]`` of each joint (rad); the chapter's working limits by default.

    Returns
    -------
    numpy.ndarray, shape (n,)
        :math:`\nabla H(q)`, the gradient of :func:`reference_joint_limit_objective` with the
        same ``limits`` (its closed form is the answer of Task 2 (c), so it is not written here).
    """
    q = as_float_array(q, "q", shape=(None,))
    limits = _limits_of(q, limits)
    with np.errstate(all="ignore"):
        out = _gradient(q, limits)
    return check_result_finite(out, "the gradient of H", q=q, limits=limits)


def reference_ik_position(chain: Any, p_goal: Any, q0: Any, step: Any, max_step: float = 0.5,
                          tol: float = 1e-9, max_iterations: int = 100) -> tuple[np.ndarray, bool, int]:
    r"""robokin's answer to ``ik_position`` of Task 2 (the tests' stand-in).

    As :func:`reference_weighted_pinv`, for the IK loop: the graded test of ``ik_restarts``
    passes it in place of the student's ``ik_position``.

    Parameters
    ----------
    chain : robokin chain
        Its ``fk``, ``position_jacobian`` and ``limits`` (n, 2) are used.
    p_goal : array_like, shape (3,)
        The goal position of the flange (m, base frame).
    q0 : array_like, shape (n,)
        The start (rad).
    step : callable
        ``step(J, e, q) -> dq`` (n,), with ``J`` the 3×n position Jacobian and
        :math:`e = p_{goal} - p(q)`.
    max_step : float
        Cap on the norm of a step (rad); the chapter's 0.5 by default.
    tol : float
        Stop when :math:`\|e\| \le` ``tol`` (m).
    max_iterations : int
        At most this many steps.

    Returns
    -------
    tuple
        ``(q, converged, iterations)``: the last configuration (n,), whether
        :math:`\|e(q)\| \le` ``tol``, and the number of steps taken.
    """
    check_chain(chain, "chain", methods=("fk", "position_jacobian"))
    p_goal = as_float_array(p_goal, "p_goal", shape=(3,))
    q0 = as_float_array(q0, "q0", shape=(chain.n,))
    check_callable(step, "step", "step(J, e, q) -> dq (n,)")
    max_step = float(as_float_array(max_step, "max_step", shape=()))
    tol = float(as_float_array(tol, "tol", shape=()))
    if max_step <= 0 or tol < 0:
        raise ValueError(f"max_step must be > 0 and tol >= 0; got max_step {max_step}, tol {tol}")
    max_iterations = check_int(max_iterations, "max_iterations", minimum=0, maximum=100_000)
    packed = _loop(chain, p_goal, q0, step, max_step, tol, max_iterations)
    n = len(packed) - 2
    return packed[:n], bool(packed[n]), int(packed[n + 1])



# ------------------------------------------------------------------ the graded tests' machinery
#: The gain k of the null-space step of Task 2 (d) for the joint-limit objective, n π²/2:
#: ``solve_ik``'s own for ``objective="joint_limits"`` on the work cell.
NULLSPACE_GAIN = N_JOINTS * np.pi**2 / 2


def step_rules(weights: Any, damping: float = math.sqrt(0.1), gain: float = NULLSPACE_GAIN,
               weighted_pinv: Any = reference_weighted_pinv, dls_step: Any = reference_dls_step,
               nullspace_projector: Any = reference_nullspace_projector,
               joint_limit_gradient: Any = reference_joint_limit_gradient) -> dict[str, Any]:
    r"""The three step rules ``step(J, e, q) -> dq`` of Task 2 (d), built on the given steps.

    The graded test of Task 2 (d) runs the student's loop with robokin's steps of parts
    (a)-(c) (the defaults), and checks the student's ``STEPS`` against these rules built on
    the student's steps or on robokin's, so that a mistake in one part costs that part's
    points only.

    Parameters
    ----------
    weights : array_like, shape (6,)
        The diagonal of the weight matrix :math:`W` (the chapter's ``W_DIAG``).
    damping : float, optional
        The :math:`\lambda` of the damped step (m); the chapter's :math:`\sqrt{0.1}`.
    gain : float, optional
        The gain :math:`k` of the null-space term; :data:`NULLSPACE_GAIN` by default.
    weighted_pinv, dls_step, nullspace_projector, joint_limit_gradient : callable, optional
        The steps of parts (a)-(c): ``weighted_pinv(J, W)``, ``dls_step(J, e, damping)``,
        ``nullspace_projector(J)``, ``joint_limit_gradient(q)``; robokin's by default.

    Returns
    -------
    dict
        ``"weighted"``: :math:`J_W^+ e`, ``"DLS"``: ``dls_step(J, e, damping)``, ``"null
        space"``: :math:`J^+ e + N k \nabla H(q)`.
    """
    W = np.diag(as_float_array(weights, "weights", shape=(N_JOINTS,)))
    damping = float(as_float_array(damping, "damping", shape=()))
    gain = float(as_float_array(gain, "gain", shape=()))
    for name, part in (("weighted_pinv", weighted_pinv), ("dls_step", dls_step),
                       ("nullspace_projector", nullspace_projector),
                       ("joint_limit_gradient", joint_limit_gradient)):
        check_callable(part, name, "a step of Task 2 (a)-(c)")
    return {
        "weighted": lambda J, e, q: weighted_pinv(J, W) @ e,
        "DLS": lambda J, e, q: dls_step(J, e, damping),
        "null space": lambda J, e, q: (
            np.linalg.pinv(J) @ e + nullspace_projector(J) @ (gain * joint_limit_gradient(q))
        ),
    }


def _same_step(dq: np.ndarray, rule: Any, J: np.ndarray, e: np.ndarray, q: np.ndarray) -> bool:
    """Whether ``dq`` is the step of ``rule`` at (J, e, q) (False if the rule raises: a student's
    step of that part that fails its own test)."""
    try:
        return bool(np.allclose(dq, rule(J, e, q), rtol=1e-9, atol=1e-12))
    except Exception:  # noqa: BLE001 - the other rule decides
        return False


def assert_steps_follow(chain: Any, configurations: Any, steps: Any, rules: Any,
                        error: Any = (0.04, -0.03, 0.02)) -> None:
    """Assert that each step rule of ``steps`` is the rule of its name in one of ``rules``.

    Parameters
    ----------
    chain : robokin chain
        ``J`` is its position Jacobian at each configuration.
    configurations : array_like, shape (K, n)
        Where the steps are compared (rad).
    steps : dict
        The student's ``STEPS``: name -> ``step(J, e, q)``.
    rules : sequence of dict
        Rules with the same names (:func:`step_rules` on the student's steps, on robokin's).
    error : array_like, shape (3,), optional
        The position error ``e`` (m) they are given.

    Raises
    ------
    AssertionError
        Naming the first step that follows none of ``rules`` (to rtol 1e-9, atol 1e-12), or
        the names when they differ from the rules'.
    """
    names = sorted(rules[0])
    if sorted(steps) != names:
        raise AssertionError(f"STEPS has the keys {sorted(steps)}; expected {names}")
    e = as_float_array(error, "error", shape=(3,))
    for q in as_float_array(configurations, "configurations", shape=(None, chain.n)):
        J = chain.position_jacobian(q)
        for name in names:
            dq = np.asarray(steps[name](J, e.copy(), q.copy()), dtype=float)
            if not any(_same_step(dq, rule[name], J, e, q) for rule in rules):
                raise AssertionError(f"STEPS[{name!r}] is not the step of part (d) at q = {fmt(q)} rad")


def loop_as_solve_ik(chain: Any, p_goal: Any, q0: Any, method: str, weights: Any, max_step: float, *,
                     loop: Any, tol: float = 1e-9) -> tuple[np.ndarray, int]:
    """Assert that the student's loop, run with robokin's step, is robokin's ``solve_ik_once``.

    Runs ``loop(chain, p_goal, q0, step)`` with its defaults (``max_step``, ``tol``)
    and ``step`` robokin's rule ``method`` (:func:`step_rules`), and
    ``robokin.motion.solve_ik_once(chain, p_goal, q0=q0, max_step=max_step, tol=tol, ...)``
    with that method's options: one attempt of the method alone, the same iteration.

    Parameters
    ----------
    chain : robokin chain
        The work cell.
    p_goal : array_like, shape (3,)
        The goal (m).
    q0 : array_like, shape (n,)
        The start (rad).
    method : {"weighted", "DLS", "null space"}
        The step rule.
    weights : array_like, shape (6,)
        The weights of the weighted pseudoinverse.
    max_step : float
        The default of the student's loop, handed to ``solve_ik_once``.
    loop : callable
        The student's ``ik_position``, returning ``(q, converged, iterations)``.
    tol : float, optional
        The default of the student's loop, handed to ``solve_ik_once``.

    Returns
    -------
    tuple
        ``(q, iterations)`` of the student's loop.

    Raises
    ------
    AssertionError
        When the two differ in success, number of steps or final ``q`` (by more than 1e-9 rad).
    """
    from robokin.motion import solve_ik_once

    all_options: dict[str, dict[str, Any]] = {
        "weighted": dict(method="weighted", weights=np.asarray(weights, dtype=float)),
        "DLS": dict(method="dls", damping=math.sqrt(0.1)),
        "null space": dict(method="nullspace", objective="joint_limits"),
    }
    options = all_options[method]
    q, converged, iterations = loop(chain, p_goal, q0, step_rules(weights)[method])
    reference = solve_ik_once(chain, p_goal, q0=q0, max_step=max_step, tol=tol, **options)
    assert reference.success, f"solve_ik_once did not converge with the {method} step"
    assert converged, f"your ik_position with robokin's {method} step did not converge"
    assert iterations == reference.iterations, (
        f"your ik_position with robokin's {method} step took {iterations} steps; "
        f"solve_ik_once took {reference.iterations}")
    q = np.asarray(q, dtype=float)
    assert np.allclose(q, reference.q, rtol=0.0, atol=1e-9), (
        f"your ik_position with robokin's {method} step ends at q = {fmt(q)} rad; "
        f"solve_ik_once at {fmt(reference.q)} rad")
    return q, int(iterations)


def assert_self_motion_rows(path: Any, chain: Any, p_goal: Any, gain: float, atol: float = 1e-12) -> None:
    r"""Assert that each row of ``path`` is the self-motion step of Task 4 from the row before.

    :math:`q_{i+1} = q_i + J^+ e + N\,k\,\nabla H(q_i)`, with :math:`N` the null-space projector of
    :math:`J`, the chain's position Jacobian at :math:`q_i`, :math:`e = p_{goal} - p(q_i)`,
    :math:`k` = ``gain`` and
    :math:`\nabla H` robokin's gradient of the joint-limit objective for the chain's limits.

    Raises
    ------
    AssertionError
        Naming the first row that differs by more than ``atol`` (rad).
    """
    path = as_float_array(path, "path", shape=(None, chain.n))
    p_goal = as_float_array(p_goal, "p_goal", shape=(3,))
    for row, (q, q_next) in enumerate(zip(path[:-1], path[1:]), start=1):
        J = chain.position_jacobian(q)
        J_pinv = np.linalg.pinv(J)
        e = p_goal - chain.fk(q)[:3, 3]
        expected = q + J_pinv @ e + (np.eye(chain.n) - J_pinv @ J) @ (gain * _gradient(q, chain.limits))
        assert np.allclose(q_next, expected, rtol=0.0, atol=atol), (
            f"row {row} is not q + J⁺e + N k ∇H(q) of row {row - 1}")



def assert_path_figures(chain: Any, p_goal: Any, path: Any, figures: Any, objective: Any,
                        projector: Any) -> None:
    r"""Assert the figures of Task 4 along a path against the given functions, run again.

    Parameters
    ----------
    chain : robokin chain
        Its ``fk``, ``position_jacobian`` and ``limits``.
    p_goal : array_like, shape (3,)
        The goal of the flange (m).
    path : array_like, shape (K, n)
        The configurations (rad).
    figures : dict
        Shape (K,) each: ``"H"`` (``objective(q)``), ``"error"`` (the flange's distance from
        ``p_goal``, m), ``"JN"`` (the largest entry of :math:`|J\,N|`, N = ``projector(J)``)
        and ``"distance"`` (of the joint nearest to a limit of ``chain.limits``, rad).
    objective, projector : callable
        ``objective(q)`` and ``projector(J)`` (the student's :math:`H` and :math:`N`).

    Raises
    ------
    AssertionError
        Naming the first figure that differs (``"JN"``, 0 to rounding, to 1e-12 absolute).
    """
    path = as_float_array(path, "path", shape=(None, chain.n))
    p_goal = as_float_array(p_goal, "p_goal", shape=(3,))
    lower, upper = chain.limits[:, 0], chain.limits[:, 1]
    expected = {
        "H": [objective(q) for q in path],
        "error": np.linalg.norm(p_goal - chain.fk(path)[:, :3, 3], axis=1),
        "JN": [np.abs(J @ projector(J)).max() for J in chain.position_jacobian(path)],
        "distance": np.min(np.minimum(path - lower, upper - path), axis=1),
    }
    assert sorted(figures) == sorted(expected), f"figures {sorted(figures)}; expected {sorted(expected)}"
    for name, values in expected.items():
        rtol, atol = (1e-6, 1e-12) if name == "JN" else (1e-5, 1e-8)  # 1e-5, 1e-8: NumPy's defaults
        assert np.allclose(figures[name], values, rtol=rtol, atol=atol), (
            f"the figure {name} differs from its value computed again along the path")



def assert_summary_of_path(chain: Any, p_goal: Any, path: Any, figures: Any) -> None:
    r"""Assert a ``summary`` dict of Task 3 against the figures of ``path`` computed here.

    The figures are computed with robokin's own tools: the forward kinematics for
    ``error_nm``, the sum of the step lengths for ``path``, the joints' distances to
    ``chain.limits`` for ``min_limit`` and ``end_limit``, robokin's joint-limit objective
    (:class:`robokin.motion.JointLimitDistance`) for ``end_H``, and the chain's position
    manipulability for ``min_w`` and ``end_w`` (the minima over the iterates after the start).

    Parameters
    ----------
    chain : robokin chain
        The chain of the run.
    p_goal : array_like, shape (3,)
        Its goal (m).
    path : array_like, shape (k + 1, n)
        Its iterates (rad), ``path[0]`` the start.
    figures : dict
        What the student's ``summary(chain, p_goal, path, objective=...)`` returned, with
        robokin's :math:`H` for ``objective``.

    Raises
    ------
    AssertionError
        Naming the first figure that differs.
    """
    from robokin.motion import JointLimitDistance

    path = as_float_array(path, "path", shape=(None, chain.n))
    p_goal = as_float_array(p_goal, "p_goal", shape=(3,))
    lower, upper = chain.limits[:, 0], chain.limits[:, 1]
    near = np.array([min(np.min(q - lower), np.min(upper - q)) for q in path])
    w = chain.manipulability(path, position_only=True)
    expected = {
        "iterations": len(path) - 1,
        "error_nm": 1e9 * np.linalg.norm(p_goal - chain.fk(path[-1])[:3, 3]),
        "path": np.linalg.norm(np.diff(path, axis=0), axis=1).sum(),
        "min_limit": near[1:].min(),
        "end_limit": near[-1],
        "end_H": JointLimitDistance(chain.limits).value(path[-1]),
        "min_w": w[1:].min(),
        "end_w": w[-1],
    }
    assert figures["iterations"] == expected["iterations"], (
        f"iterations is {figures['iterations']}; the path has {expected['iterations']} steps")
    for name, value in expected.items():
        assert np.isclose(figures[name], value), f"{name} is {figures[name]}; expected {value:.6g}"


#: check -> {robokin (or SciPy) function that solves its task: how the review report names it}
#: (an answer that hands one back is flagged for review by hand).
DELEGATION = {
    # robokin's step rules give the step J_W⁺ e and the damped step outright (Task 2's tests
    # compare with them): an answer built on them hands back robokin's solution
    "weighted_pinv": {"reference_weighted_pinv": "robokin.check.ur10.reference_weighted_pinv",
                      "WeightedPseudoInverse": "robokin.motion.WeightedPseudoInverse"},
    "dls_step": {"reference_dls_step": "robokin.check.ur10.reference_dls_step",
                 "DampedLeastSquares": "robokin.motion.DampedLeastSquares"},
    "nullspace_projector": {"reference_nullspace_projector": "robokin.check.ur10.reference_nullspace_projector"},
    "joint_limit_objective": {
        "reference_joint_limit_objective": "robokin.check.ur10.reference_joint_limit_objective",
        "JointLimitDistance": "robokin.motion.JointLimitDistance"},
    "joint_limit_gradient": {
        "reference_joint_limit_gradient": "robokin.check.ur10.reference_joint_limit_gradient",
        "JointLimitDistance": "robokin.motion.JointLimitDistance"},
    "ik_position": {"reference_ik_position": "robokin.check.ur10.reference_ik_position"},
    "summary": {"reference_joint_limit_objective": "robokin.check.ur10.reference_joint_limit_objective"},
    "self_motion": {"reference_nullspace_projector": "robokin.check.ur10.reference_nullspace_projector",
                    "reference_joint_limit_gradient": "robokin.check.ur10.reference_joint_limit_gradient"},
    "ik_restarts": {"solve_ik": "robokin.motion.solve_ik", "solve_ik_batch": "robokin.motion.solve_ik_batch",
                    "reference_ik_position": "robokin.check.ur10.reference_ik_position"},
    "bisect": {"brentq": "scipy.optimize.brentq", "root_scalar": "scipy.optimize.root_scalar",
               "brenth": "scipy.optimize.brenth", "ridder": "scipy.optimize.ridder"},
}
