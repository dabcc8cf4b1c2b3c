"""Batch IK on the UR10 and Baxter: convergence on >= 500 reachable 6D targets,
limits respected, success never claimed above tolerance, unreachable targets."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from support.ik_support import baxter_left, reachable_targets, ur10, within_limits

from robokin.motion import solve_ik_batch

N_TARGETS = 500
TOL = 1e-6

ROBOTS = {"ur10": ur10, "baxter_left": baxter_left}

# Methods meant to converge (Newton-type), with the options used.  Restarts are
# raised and the LM polish switched off so that each method is tested alone.
# A damped step converges only linearly, at the rate lambda^2 / (sigma^2 +
# lambda^2) along a direction with singular value sigma, so near-singular
# targets need a patient stall rule and more iterations.
# At an exactly singular target (sigma_min -> 0) a fixed damping cannot converge
# at all, so the damped methods are checked on the targets whose generating
# configuration has sigma_min >= 5e-3 (about 95 % of them).
PATIENT = {"stall_iterations": 50, "max_iterations": 600}
DAMPED = {"dls", "dls-manipulability"}
CONVERGING: dict[str, dict[str, Any]] = {
    "lm": {},
    "pinv": {"restarts": 60, "polish": False},
    "weighted": {"weights": "ramp", "restarts": 60, "polish": False},
    "dls": {"restarts": 60, "polish": False, **PATIENT},
    "dls-manipulability": {"adaptive": "manipulability", "restarts": 60, "polish": False, **PATIENT},
    "nullspace": {"restarts": 60, "polish": False},
}


@pytest.fixture(scope="module", params=sorted(ROBOTS))
def robot(request):
    chain = ROBOTS[request.param]()
    Q, T = reachable_targets(chain, N_TARGETS, seed=2024)
    return chain, Q, T


@pytest.mark.parametrize("name", sorted(CONVERGING))
def test_methods_converge_on_reachable_6d_targets(robot, name):
    chain, Q, T = robot
    if name in DAMPED:
        regular = np.linalg.svd(chain.jacobian(Q), compute_uv=False)[:, -1] >= 5e-3
        assert regular.sum() >= 450
        T = T[regular]
    opts = dict(CONVERGING[name])
    method = name.split("-")[0]
    if opts.get("weights") == "ramp":
        opts["weights"] = np.linspace(1.0, 3.0, chain.n)
    res = solve_ik_batch(chain, T, method=method, tol=TOL, **opts)
    assert res.q.shape == (len(T), chain.n)
    assert res.success.shape == res.iterations.shape == (len(T),)
    assert res.success.all(), (
        f"{name} on {chain.name}: {np.count_nonzero(~res.success)} failures, "
        f"reasons {np.unique(res.reason[~res.success])}"
    )
    assert np.all(res.position_error <= TOL) and np.all(res.orientation_error <= TOL)
    assert np.all(within_limits(chain, res.q))
    # the reported error is the true error of the returned configuration
    T_sol = chain.fk(res.q)
    assert np.allclose(T_sol[:, :3, 3], T[:, :3, 3], atol=2 * TOL)
    assert np.allclose(T_sol[:, :3, :3], T[:, :3, :3], atol=4 * TOL)


def test_default_method_solves_every_target_with_default_options(robot):
    chain, _, T = robot
    res = solve_ik_batch(chain, T)
    assert res.method == "lm"
    assert res.success.all()
    assert np.all(res.position_error <= 1e-6) and np.all(res.orientation_error <= 1e-6)
    assert set(res.reason) == {"converged"}


@pytest.mark.parametrize("method", ["lm", "pinv", "transpose"])
def test_success_never_reported_above_tolerance(robot, method):
    chain, _, T = robot
    # a loose budget so that there are failures to look at
    res = solve_ik_batch(chain, T[:100], method=method, tol=1e-8, max_iterations=8, restarts=1, polish=False)
    ok = res.success
    assert np.all(res.position_error[ok] <= 1e-8)
    assert np.all(res.orientation_error[ok] <= 1e-8)
    bad = ~ok
    assert np.all((res.position_error[bad] > 1e-8) | (res.orientation_error[bad] > 1e-8))
    assert np.all(res.reason[ok] == "converged") and not np.any(res.reason[bad] == "converged")
    assert np.all(within_limits(chain, res.q))


def test_position_only_batch(robot):
    chain, _, T = robot
    P = T[:200, :3, 3]
    res = solve_ik_batch(chain, P)
    assert res.success.all()
    assert np.allclose(chain.fk(res.q)[:, :3, 3], P, atol=1e-6)


def test_unreachable_targets_in_a_batch(robot):
    chain, _, T = robot
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.5]
    targets = np.stack([T[0], far, T[1]])
    res = solve_ik_batch(chain, targets)
    assert list(res.success) == [True, False, True]
    assert res.reason[1] == "unreachable"
    assert res.position_error[1] > 3.0
    assert within_limits(chain, res.q[1])
    # best configuration: the arm stretches towards the target
    p = chain.fk(res.q[1])[:3, 3]
    assert np.dot(p, far[:3, 3]) > 0


def test_batch_is_reproducible_and_accepts_q0_batch():
    chain = ur10()
    Q, T = reachable_targets(chain, 50, seed=7)
    a = solve_ik_batch(chain, T, seed=3)
    b = solve_ik_batch(chain, T, seed=3)
    assert np.array_equal(a.q, b.q) and np.array_equal(a.iterations, b.iterations)
    c = solve_ik_batch(chain, T, q0=Q + 0.01)
    assert c.success.all() and np.all(c.attempts == 1)
