"""Robustness defects found in a review of bad inputs, one regression test each (and one per class found).

The property suite (test_robustness_fuzz.py) covers every public function; these
are the readable examples: what a student typed, and the error or result they now get.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from robokin.errors import DomainError, RobokinError, ShapeError
from robokin.models import planar_two_link, three_rpr, ur10
from robokin.motion import CartesianController, simulate, solve_ik, solve_ik_batch, time_law
from robokin.transforms import rotation_exp, rotation_from_quaternion, rotation_of, translation_of, unskew

UR10 = ur10()
Q = np.array([0.1, -1.2, 1.3, -1.5, -1.4, 0.3])


# ---------------------------------------------------------------- the examples of the issue
@pytest.mark.parametrize("q, exc, text", [
    ([np.nan, 0, 0, 0, 0, 0], DomainError, r"q must be finite; got nan at index \(0,\)"),
    ([0, 0, 0, np.inf, 0, 0], DomainError, "q must be finite"),
    ("abc", TypeError, "q must contain real numbers"),
    ([0.0] * 5, ShapeError, r"q must have shape \(6,\); got shape \(5,\)"),
])
def test_controller_call_validates_q(q, exc, text):
    ctrl = CartesianController(UR10, UR10.fk(Q))
    with pytest.raises(exc, match=text):
        ctrl(0.0, q)
    with pytest.raises(TypeError, match="t must"):
        ctrl(None, Q)  # type: ignore[arg-type]  # a wrong type on purpose


@pytest.mark.parametrize("chain", [None, "ur10", 3])
def test_ik_rejects_a_chain_that_is_not_one(chain):
    with pytest.raises(TypeError, match="chain must be a kinematic chain"):
        solve_ik(chain, np.eye(4))
    with pytest.raises(TypeError, match="chain must be a kinematic chain"):
        solve_ik_batch(chain, np.eye(4)[None])


def test_rotation_of_checks_that_T_is_a_transform():
    T = np.eye(4)
    T[3] = [1, 0, 0, 1]
    with pytest.raises(DomainError, match="bottom row"):
        rotation_of(T)
    S = np.eye(4)
    S[:3, :3] *= 1.5
    with pytest.raises(DomainError, match="not a rotation"):
        translation_of(S)
    assert np.array_equal(rotation_of(T, check=False), T[:3, :3])        # the documented escape


@pytest.mark.parametrize("w", [[1e200, 0, 0], [-9.9e188, 4.3e16, 2.4e16], [0, 0, 1e300]])
def test_rotation_exp_of_a_huge_vector_is_a_rotation(w):
    R = rotation_exp(w)
    assert np.all(np.isfinite(R)) and np.allclose(R @ R.T, np.eye(3)) and np.isclose(np.linalg.det(R), 1)
    assert np.allclose(rotation_exp(np.array([w, [0.1, 0.2, 0.3]]))[0], R)
    with pytest.raises(DomainError, match="w is too large"):
        rotation_exp([1.7e308] * 3)


def test_empty_batches_give_empty_results():
    assert unskew(np.zeros((0, 3, 3))).shape == (0, 3)
    assert rotation_exp(np.zeros((0, 3))).shape == (0, 3, 3)
    assert UR10.fk(np.zeros((0, 6))).shape == (0, 4, 4)
    res = solve_ik_batch(UR10, np.zeros((0, 3)))
    assert res.q.shape == (0, 6) and res.success.shape == (0,)


def test_three_rpr_leg_lengths_of_a_huge_pose_are_finite_or_refused():
    robot = three_rpr()
    rho = robot.inverse_kinematics([1e200, 0.0, 0.3])
    assert np.all(np.isfinite(rho)) and np.allclose(rho, 1e200)
    with pytest.raises(DomainError, match="pose is too large"):
        robot.inverse_kinematics([1.7e308, 1.7e308, 0.0])


# ---------------------------------------------------------------- one per class found by the suite
def test_norms_do_not_overflow_into_a_wrong_answer():
    # |q| overflowed to inf and q / inf = 0 gave the identity, silently
    R = rotation_from_quaternion([1e308, 1e308, 0.0, 0.0])
    assert np.allclose(R, rotation_from_quaternion([1.0, 1.0, 0.0, 0.0]))


def test_scalar_parameters_reject_arrays_and_nonsense():
    with pytest.raises(ShapeError, match="tol must be a single number"):
        UR10.within_limits(Q, tol=[0.1, 0.2])  # type: ignore[arg-type]  # a wrong type on purpose
    with pytest.raises(DomainError, match="tol must be non-negative"):
        UR10.within_limits(Q, tol=-1.0)
    with pytest.raises(TypeError, match="tau"):
        time_law(None)
    with pytest.raises(DomainError, match="tau must be finite"):
        time_law(np.nan)


def test_model_lengths_are_named():
    with pytest.raises(TypeError, match="l1 must be a number"):
        planar_two_link(None)
    with pytest.raises(DomainError, match="l2 must be a positive length"):
        planar_two_link(1.0, -0.5)


def test_counts_that_would_exhaust_the_memory_are_refused():
    with pytest.raises(DomainError, match="N must be <="):
        UR10.random_configurations(10**15)
    ctrl = CartesianController(UR10, UR10.fk(Q))
    with pytest.raises(DomainError, match="t_end / ts"):
        simulate(UR10, ctrl, Q, 1e-300, 1.0)


def test_no_numpy_warning_before_the_error():
    with warnings.catch_warnings():
        warnings.simplefilter("error")                 # a RuntimeWarning would turn into an error here
        with pytest.raises(DomainError, match="q must be finite"):
            UR10.fk([np.inf, 0, 0, 0, 0, 0])


def test_ik_targets_beyond_1e100_m_are_refused_not_garbled():
    with pytest.raises(DomainError, match="target is too far away"):
        solve_ik(UR10, [1e200, 0.0, 0.0])
    far = solve_ik(UR10, [1e6, 0.0, 0.0], restarts=1)
    assert not far.success and np.isfinite(far.position_error) and far.position_error > 9e5
    assert far.reason in ("unreachable", "stalled", "joint_limits")


def test_all_robokin_errors_are_value_errors():
    for exc in (ShapeError, DomainError):
        assert issubclass(exc, ValueError) and issubclass(exc, RobokinError)
