"""The IK guarantees, over seeded random targets: what a caller may rely on whatever the target.

For thousands of seeded targets on the UR10 and the Baxter arm -- reachable
poses (forward kinematics of random configurations, some of them next to a
singularity), positions, and unreachable ones (far outside the workspace, just
beyond its boundary, or a reachable position with an impossible orientation):

- no ``success=True`` whose forward kinematics misses the target by more than
  the tolerance (recomputed here, independently of the solver's own numbers);
- no answer outside the joint limits;
- no NaN or inf anywhere in the result, and the reported errors are the true ones;
- and, so that the test can fail for a solver that gives up: the reachable
  targets are (almost) all solved, the unreachable ones never.
"""

from __future__ import annotations

import numpy as np
import pytest

from robokin.models import baxter_left, ur10
from robokin.motion import solve_ik, solve_ik_batch

TOL = 1e-6
ROBOTS = {"ur10": ur10(), "baxter_left": baxter_left()}


def _rotation_angle(R: np.ndarray) -> np.ndarray:
    """Angle of rotations (..., 3, 3), robust near 0 and pi (atan2 of the skew and trace parts)."""
    v = np.stack([R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]], -1)
    return np.arctan2(0.5 * np.linalg.norm(v, axis=-1), 0.5 * (np.trace(R, axis1=-2, axis2=-1) - 1.0))


def _targets(robot, seed: int, count: int):
    """(poses (N, 4, 4), kind (N,) str) -- half reachable, half not."""
    rng = np.random.default_rng(seed)
    lim = robot.limits
    Q = robot.random_configurations(count, seed=seed)
    k = count // 8
    # a quarter of the reachable ones next to a singularity: wrist (UR10 q5, Baxter w1) or elbow straight
    wrist, elbow = (4, 2) if robot.n == 6 else (5, 3)
    Q[:k, wrist] = np.clip(rng.normal(0.0, 1e-4, k), lim[wrist, 0], lim[wrist, 1])
    Q[k:2 * k, elbow] = np.clip(rng.normal(0.0, 1e-4, k), lim[elbow, 0], lim[elbow, 1])
    T = robot.fk(Q)
    kind = np.array(["reachable"] * count, dtype=object)
    reach = np.linalg.norm(robot.fk(np.zeros(robot.n), frame=1)[:3, 3]) + float(
        np.max(np.linalg.norm(T[:, :3, 3], axis=1)))
    base = robot.fk(np.zeros(robot.n), frame=1)[:3, 3]
    u = rng.normal(size=(count, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    h = count // 2
    # far outside the workspace, just beyond its boundary, or an impossible orientation at a reachable point
    T[h:h + k, :3, 3] = base + u[h:h + k] * rng.uniform(2.0, 50.0, (k, 1)) * reach
    T[h + k:h + 3 * k, :3, 3] = base + u[h + k:h + 3 * k] * 1.05 * reach
    kind[h:h + 3 * k] = "unreachable"
    kind[h + 3 * k:] = "any"   # random orientation at a reachable position: may or may not be solvable
    R = np.linalg.qr(rng.normal(size=(count - h - 3 * k, 3, 3)))[0]
    R *= np.sign(np.linalg.det(R))[:, None, None]
    T[h + 3 * k:, :3, :3] = R
    return T, kind


def _assert_guarantees(robot, T, q, success, pos_err, ori_err, reason):
    assert np.all(np.isfinite(q)) and np.all(np.isfinite(pos_err)) and np.all(np.isfinite(ori_err))
    assert np.all(robot.within_limits(q, tol=1e-12)), "an answer outside the joint limits"
    F = robot.fk(q)
    dp = np.linalg.norm(F[..., :3, 3] - T[..., :3, 3], axis=-1)
    dr = _rotation_angle(np.swapaxes(F[..., :3, :3], -1, -2) @ T[..., :3, :3])
    bad = success & ((dp > TOL * (1 + 1e-9)) | (dr > TOL * (1 + 1e-9)))
    assert not bad.any(), f"success=True but the pose misses the target: {dp[bad][:3]}, {dr[bad][:3]}"
    assert np.allclose(pos_err, dp, atol=1e-9) and np.allclose(ori_err, dr, atol=1e-8)
    assert np.all(np.where(success, reason == "converged", reason != "converged"))


@pytest.mark.parametrize("name", ROBOTS)
def test_batch_ik_guarantees_over_random_targets(name):
    robot = ROBOTS[name]
    T, kind = _targets(robot, seed=13, count=2000)
    res = solve_ik_batch(robot, T, tol=TOL, seed=0)
    _assert_guarantees(robot, T, res.q, res.success, res.position_error, res.orientation_error, res.reason)
    reachable, unreachable = kind == "reachable", kind == "unreachable"
    assert res.success[reachable].mean() >= 0.99, f"only {res.success[reachable].mean():.1%} of reachable targets"
    assert not res.success[unreachable].any()
    assert set(res.reason[unreachable]) <= {"unreachable", "joint_limits", "stalled", "max_iterations"}
    # positions only: the same guarantees on the position error
    P = T[:, :3, 3]
    pos = solve_ik_batch(robot, P, tol=TOL, seed=1)
    assert np.all(np.isfinite(pos.q)) and np.all(robot.within_limits(pos.q, tol=1e-12))
    miss = np.linalg.norm(robot.fk(pos.q)[:, :3, 3] - P, axis=1)
    assert not (pos.success & (miss > TOL * (1 + 1e-9))).any()
    assert pos.success[reachable].mean() >= 0.99 and not pos.success[unreachable].any()


@pytest.mark.parametrize("name", ROBOTS)
def test_single_ik_guarantees_on_a_sample(name):
    robot = ROBOTS[name]
    T, kind = _targets(robot, seed=7, count=80)
    results = [solve_ik(robot, t, tol=TOL, record_history=False) for t in T]
    q = np.array([r.q for r in results])
    success = np.array([r.success for r in results])
    _assert_guarantees(robot, T, q, success, np.array([r.position_error for r in results]),
                       np.array([r.orientation_error for r in results]), np.array([r.reason for r in results]))
    assert success[kind == "reachable"].mean() >= 0.95 and not success[kind == "unreachable"].any()
