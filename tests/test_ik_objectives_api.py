"""Objectives take joint limits directly, steps return a named result, the context is
optional where it can be (so that a reader can call one step or one objective alone); the
null-space gain is the same for a plain gradient function as for the named joint-limit
objective (a gradient written by hand once moved half as fast as the named one)."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from support.ik_support import reachable_targets, ur10

from robokin.chains import SerialChain
from robokin.motion import (
    DampedLeastSquares,
    JacobianTranspose,
    JointLimitDistance,
    LevenbergMarquardt,
    Manipulability,
    NullSpace,
    PseudoInverse,
    WeightedPseudoInverse,
    solve_ik,
)
from robokin.motion.ik import StepResult
from robokin.motion.ik.problem import make_context

# the working limits of Chapter 2's UR10 cell (smallest range pi)
WORK_LIMITS = np.array([[-np.pi, np.pi], [-np.pi, 0.0], [0.0, np.pi],
                        [-np.pi, 0.0], [-np.pi, 0.0], [-np.pi, np.pi]])
Q_PARKED = np.array([0.0, -2.6, 2.6, -np.pi / 2, -np.pi / 2, 0.0])


def joint_limit_gradient(q, limits=WORK_LIMITS):
    """A student's gradient of Siciliano eq. 3.57 (as in Chapter 2, Task 3)."""
    middle, span = limits.mean(axis=1), limits[:, 1] - limits[:, 0]
    return -(q - middle) / span**2 / len(middle)


@pytest.fixture(scope="module")
def cell():
    robot = ur10()
    return SerialChain(robot.elements, limits=WORK_LIMITS, frame_names=robot.frame_names, name="ur10_cell")


# ------------------------------------------------------------ null-space gain
def test_a_plain_gradient_gets_the_joint_limit_gain(cell):
    ctx = make_context(cell, np.array([True] * 3 + [False] * 3), None, "limits")
    expected = 6 * np.pi**2 / 2  # n * (smallest range)^2 / 2 = 29.6
    assert NullSpace().resolved_gain(ctx) == pytest.approx(expected)
    assert NullSpace(objective=joint_limit_gradient).resolved_gain(ctx) == pytest.approx(expected)
    assert NullSpace(objective=joint_limit_gradient, gain=1.0).resolved_gain(ctx) == 1.0  # explicit gain kept
    assert NullSpace(objective="manipulability").resolved_gain(ctx) == 1.0  # its own default


def test_own_gradient_runs_like_the_named_objective(cell):
    """Chapter 2, Task 3 with objective=joint_limit_gradient: same gain, same run (no silent stall)."""
    target = cell.fk(np.array([0.4, -1.2, 1.9, -2.0, -1.4, 0.3]))[:3, 3]
    common: dict[str, Any] = dict(q0=Q_PARKED, method="nullspace", max_step=0.5, restarts=0, polish=False, tol=1e-9)
    named = solve_ik(cell, target, objective="joint_limits", **common)
    own = solve_ik(cell, target, objective=joint_limit_gradient, **common)
    assert named.success and own.success
    assert own.iterations == named.iterations
    assert own.history is not None and named.history is not None
    assert np.allclose(own.history.q, named.history.q, atol=1e-9)
    # what the silent drop to k = 1 did: the run stalls, with a worse objective
    weak = solve_ik(cell, target, objective=joint_limit_gradient, gain=1.0, **common)
    assert weak.reason == "stalled" and not weak.success
    H = JointLimitDistance(WORK_LIMITS)
    assert H.value(own.q) > H.value(weak.q) + 1e-3


# ------------------------------------------------------------ objectives
def test_joint_limit_distance_takes_limits_directly():
    rng = np.random.default_rng(3)
    q = rng.uniform(WORK_LIMITS[:, 0], WORK_LIMITS[:, 1], size=(5, 6))
    ctx = SimpleNamespace(lower=WORK_LIMITS[:, 0], upper=WORK_LIMITS[:, 1])
    reference_value, reference_gradient = JointLimitDistance().value(q, ctx), JointLimitDistance().gradient(q, ctx)
    for H, arg in ((JointLimitDistance(WORK_LIMITS), None), (JointLimitDistance(), WORK_LIMITS),
                   (JointLimitDistance(limits=WORK_LIMITS.tolist()), ctx)):
        assert np.array_equal(H.value(q, arg), reference_value)
        assert np.array_equal(H.gradient(q, arg), reference_gradient)
    assert np.allclose(JointLimitDistance(WORK_LIMITS).gradient(q[0]), joint_limit_gradient(q[0]), atol=1e-15)


def test_objectives_without_what_they_need_say_so():
    with pytest.raises(TypeError, match="limits"):
        JointLimitDistance().value(np.zeros(6))
    with pytest.raises(ValueError, match="limits"):
        JointLimitDistance([[1.0, -1.0]])
    with pytest.raises(TypeError, match="context"):
        Manipulability().value(np.zeros(6), None)
    with pytest.raises(TypeError, match="gain"):
        NullSpace(objective=joint_limit_gradient).step(np.eye(3, 6), np.ones(3), np.zeros(6))
    with pytest.raises(TypeError, match="mask"):  # error weights of 6 components, 3 task rows
        LevenbergMarquardt(error_weights=[1, 1, 1, 2, 2, 2]).step(np.eye(3, 6), np.ones(3))


# ------------------------------------------------------------ steps
@pytest.fixture(scope="module")
def jacobian_and_error():
    chain = ur10()
    Q, T = reachable_targets(chain, 2, seed=5)
    J = chain.jacobian(Q[0])
    e = np.r_[T[1][:3, 3] - T[0][:3, 3], 0.1, -0.2, 0.05]
    return chain, Q[0], J, e


STEP_RULES = [PseudoInverse(), JacobianTranspose(), WeightedPseudoInverse(weights=np.arange(1.0, 7.0)),
              DampedLeastSquares(damping=0.1), DampedLeastSquares(adaptive="singular_value"),
              LevenbergMarquardt(), LevenbergMarquardt(error_weights=[1, 1, 1, 2, 2, 2])]


@pytest.mark.parametrize("method", STEP_RULES, ids=repr)
def test_steps_return_a_named_result_and_need_no_context(jacobian_and_error, method):
    chain, q, J, e = jacobian_and_error
    ctx = make_context(chain, np.ones(6, dtype=bool), None, "limits")
    with_ctx = method.step(J, e, q, ctx)
    without = method.step(J, e)
    assert isinstance(with_ctx, StepResult) and isinstance(without, StepResult)
    assert with_ctx[0] is with_ctx.step and with_ctx[1] is with_ctx.damping
    assert np.array_equal(with_ctx.step, without.step) and np.array_equal(with_ctx.damping, without.damping)
    dq, damping = with_ctx  # still unpacks as a pair
    assert dq.shape == (6,) and np.ndim(damping) == 0


def test_nullspace_step_with_limits_in_the_objective(jacobian_and_error):
    chain, q, J, e = jacobian_and_error
    q = np.clip(q, WORK_LIMITS[:, 0], WORK_LIMITS[:, 1])
    Jv = J[:3]
    ctx = SimpleNamespace(lower=WORK_LIMITS[:, 0], upper=WORK_LIMITS[:, 1])
    via_ctx = NullSpace().step(Jv, e[:3], q, ctx)  # type: ignore[arg-type]  # a stand-in: the bounds step reads
    direct = NullSpace(objective=JointLimitDistance(WORK_LIMITS)).step(Jv, e[:3], q)
    assert np.array_equal(via_ctx.step, direct.step)
    # the secondary term lies in the null space: J dq equals J J^+ e
    assert np.allclose(Jv @ direct.step, e[:3], atol=1e-9)
