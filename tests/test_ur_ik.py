"""Tests of the closed-form inverse kinematics of the Universal Robots arms (robokin.models.ur_ik).

References: robokin's UR10 model (every solution must reproduce the pose under
``ur10().fk``; the residuals must be those of that FK), the generating
configuration (must be among the solutions), a dense multi-start search with
the numerical solver robokin.motion.solve_ik (must find the same set), the
published tables against robokin's chains (``ur10()``, ``from_dh``, the UR5 of
example-robot-data), and hand-made singular and unreachable poses.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from robokin.chains import SerialChain, from_dh
from robokin.errors import DomainError, ShapeError
from robokin.models import ur10
from robokin.models.ur_ik import (
    BRANCHES,
    REASONS,
    SINGULARITIES,
    UR5_DH,
    UR10_DH,
    UR10E_DH,
    UR_DH_TABLES,
    URIKBatchResult,
    URIKResult,
    ur10_ik,
    ur10_ik_batch,
)

UR10 = ur10()
N_RANDOM = 3000


def wrapped(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def gap_to(solutions, q):
    """Smallest max-abs angle difference (mod 2π) between q and the rows of solutions."""
    return np.abs(wrapped(np.asarray(solutions) - q)).max(axis=-1).min()


def residuals_by_chain(chain, Q, T):
    """Position (m) and rotation-angle (rad) residuals of rows Q under chain.fk."""
    F = chain.fk(Q).reshape(-1, 4, 4)
    dp = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1)
    Rrel = np.einsum("kji,jl->kil", F[:, :3, :3], T[:3, :3])
    skew = np.stack([Rrel[:, 2, 1] - Rrel[:, 1, 2], Rrel[:, 0, 2] - Rrel[:, 2, 0], Rrel[:, 1, 0] - Rrel[:, 0, 1]], 1)
    return dp, np.arctan2(np.linalg.norm(skew, axis=1) / 2, (np.trace(Rrel, axis1=1, axis2=2) - 1) / 2)


# ---------------------------------------------------------------- random reachable poses
@pytest.fixture(scope="module")
def random_cases():
    Q = UR10.random_configurations(N_RANDOM, seed=2026)
    T = UR10.fk(Q)
    return Q, T, [ur10_ik(Tq) for Tq in T], ur10_ik_batch(T)


def test_generating_configuration_is_found(random_cases):
    Q, _, singles, _ = random_cases
    gaps = np.array([gap_to(res.q, q) for q, res in zip(Q, singles)])
    assert gaps.max() < 1e-8, f"worst case {gaps.max():.3g} at {int(gaps.argmax())}"


def test_every_solution_reproduces_the_pose(random_cases):
    _, T, singles, _ = random_cases
    for Tq, res in zip(T, singles):
        assert res.success and res.reason == "solved" and isinstance(res, URIKResult)
        assert res.q.shape == (len(res), 6) and 1 <= len(res) <= 8
        assert np.abs(UR10.fk(res.q) - Tq).max() <= 1e-10
        assert res.position_residual.max() <= 1e-10 and res.orientation_residual.max() <= 1e-10


def test_residuals_are_those_of_the_models_fk(random_cases):
    _, T, singles, _ = random_cases
    for Tq, res in zip(T[:300], singles[:300]):
        dp, dr = residuals_by_chain(UR10, res.q, Tq)
        assert np.allclose(res.position_residual, dp, rtol=0, atol=1e-13)
        assert np.allclose(res.orientation_residual, dr, rtol=0, atol=1e-12)


def test_batch_residuals_are_those_of_the_models_fk(random_cases):
    _, T, _, batch = random_cases
    for i in range(0, len(T), 7):
        item = batch[i]
        dp, dr = residuals_by_chain(UR10, item.q, T[i])
        assert np.allclose(item.position_residual, dp, rtol=0, atol=1e-13)
        assert np.allclose(item.orientation_residual, dr, rtol=0, atol=1e-12)


def test_angles_and_branches(random_cases):
    _, _, singles, _ = random_cases
    for res in singles:
        assert np.all(res.q > -np.pi) and np.all(res.q <= np.pi)
        assert res.branches.shape == (len(res), 3) and res.within_limits.all()
        # wrist = sign of sin q5, elbow = sign of sin q3
        assert np.all(np.sign(np.sin(res.q[:, 4])) == res.branches[:, 1])
        assert np.all(np.sign(np.sin(res.q[:, 2])) == res.branches[:, 2])
        # sorted by branch, +1 first; no branch twice
        keys = [tuple(-b) for b in res.branches]
        assert keys == sorted(keys) and len(set(keys)) == len(keys)
        assert res.singular == ()


def test_eight_distinct_solutions_in_general(random_cases):
    _, _, singles, _ = random_cases
    eight = [res for res in singles if len(res) == 8]
    assert len(eight) > 0.7 * len(singles)
    for res in eight[:200]:
        gaps = np.abs(wrapped(res.q[:, None, :] - res.q[None, :, :])).max(axis=2)
        assert np.all(gaps[~np.eye(8, dtype=bool)] > 1e-6)
        assert {tuple(b) for b in res.branches} == {(s, w, e) for s in (1, -1) for w in (1, -1) for e in (1, -1)}
    # fewer solutions come in whole elbow pairs: a (shoulder, wrist) branch reaches or not
    for res in singles:
        assert len(res) % 2 == 0


def test_batch_equals_single(random_cases):
    _, T, singles, batch = random_cases
    assert isinstance(batch, URIKBatchResult) and len(batch) == len(T)
    assert batch.q.shape == (len(T), 8, 6) and batch.valid.shape == (len(T), 8)
    assert batch.branches.shape == (8, 3)
    for i, (res, item) in enumerate(zip(singles, batch)):
        assert item.reason == res.reason and item.success == res.success and item.singular == res.singular, i
        assert np.array_equal(item.branches, res.branches), i
        assert np.abs(wrapped(item.q - res.q)).max(initial=0) < 1e-10, i  # near a singular case a few ulp grow
        assert np.allclose(item.position_residual, res.position_residual, rtol=0, atol=1e-14)
        assert np.allclose(item.wrist_centre, res.wrist_centre, rtol=0, atol=1e-15)
    assert np.all(np.isnan(batch.q[~batch.valid])) and np.all(np.isfinite(batch.q[batch.valid]))


def test_nested_lists_and_names_as_input():
    q = np.array([0.3, -1.2, 1.4, -0.5, 1.1, 0.2])
    T = UR10.fk(q)
    res = ur10_ik(T.tolist(), dh=[list(row) for row in UR10_DH])
    assert res.success and len(res) == 8 and gap_to(res.q, q) < 1e-10
    assert np.array_equal(ur10_ik(T, dh="UR10").q, res.q)
    assert np.allclose(ur10_ik_batch([T.tolist()])[0].q, res.q, rtol=0, atol=1e-12)


def test_batch_shapes():
    empty = ur10_ik_batch(np.zeros((0, 4, 4)))
    assert len(empty) == 0 and empty.q.shape == (0, 8, 6) and empty.singular.shape == (0, 3)
    T = UR10.fk(np.array([0.3, -1.2, 1.4, -0.5, 1.1, 0.2]))
    one = ur10_ik_batch(T)
    assert len(one) == 1 and one.q.shape == (1, 8, 6) and one.success.tolist() == [True]
    assert "poses=1" in repr(one) and "solutions=8" in repr(ur10_ik(T))


# ---------------------------------------------------------------- against a dense numerical search
@pytest.mark.parametrize("q", [
    np.array([0.3, -1.2, 1.4, -0.5, 1.1, 0.2]),
    np.array([-2.0, -0.6, -1.9, 2.5, -0.4, 1.3]),
    np.array([1.1, -2.2, 0.7, 0.9, 2.0, -2.8]),
])
def test_solution_set_equals_multistart_search(q):
    """Every numerical solution from 150 random starts is a closed-form one, and every closed-form one is found."""
    from robokin.motion import solve_ik  # layer 4, imported where it is used

    T = UR10.fk(q)
    res = ur10_ik(T)
    rng = np.random.default_rng(11)
    found = []
    for start in rng.uniform(-np.pi, np.pi, (150, 6)):
        num = solve_ik(UR10, T, q0=start, restarts=0, tol=1e-10, record_history=False)
        if num.success:
            found.append(wrapped(num.q))
    assert len(found) > 50
    for qn in found:  # no solution outside the closed form's set
        assert gap_to(res.q, qn) < 1e-6
    for qc in res.q:  # no closed-form solution the search misses
        assert gap_to(found, qc) < 1e-6


# ---------------------------------------------------------------- the tables
def test_default_table_is_robokins_ur10():
    assert np.array_equal(np.array(UR_DH_TABLES["ur10"]), np.array(UR10_DH, dtype=float))
    Q = UR10.random_configurations(200, seed=5)
    for description in ("dh", "mdh", "ets"):
        assert np.abs(ur10(description).fk(Q) - from_dh(UR10_DH).fk(Q)).max() < 1e-12


def test_ur5_table_matches_example_robot_data():
    pytest.importorskip("yourdfpy")
    from robokin.models import from_urdf, robot_description

    try:
        path = robot_description("ur10").parent / "ur5_robot.urdf"
    except ImportError:
        pytest.skip("example-robot-data is not installed")
    urdf = from_urdf(path, "base", "tool0")
    Q = urdf.random_configurations(200, seed=6)
    assert np.abs(urdf.fk(Q) - from_dh(UR5_DH).fk(Q)).max() < 1e-10  # the URDF rounds to 1e-11 m


@pytest.mark.parametrize("name", sorted(UR_DH_TABLES))
def test_every_published_table(name):
    table = UR_DH_TABLES[name]
    arm = from_dh(table)
    Q = arm.random_configurations(200, seed=7)
    for q, T in zip(Q, arm.fk(Q)):
        for dh in (name, table):
            res = ur10_ik(T, dh=dh)
            assert res.success and gap_to(res.q, q) < 1e-8
            assert np.abs(arm.fk(res.q) - T).max() <= 1e-10
    batch = ur10_ik_batch(arm.fk(Q), dh=name)
    assert batch.success.all()


@pytest.mark.parametrize("table", [UR5_DH, UR10E_DH], ids=["UR5", "UR10e"])
def test_ur5_and_ur10e_tables_are_not_the_ur10(table):
    """The table matters: UR5 and UR10e poses solved with their own table, not with the UR10's."""
    arm = from_dh(table)
    q = np.array([0.3, -1.2, 1.4, -0.5, 1.1, 0.2])
    T = arm.fk(q)
    own = ur10_ik(T, dh=table)
    assert own.success and len(own) == 8 and gap_to(own.q, q) < 1e-10
    other = ur10_ik(T)  # the UR10 table: other joint values, none of them the arm's
    assert not other.success or gap_to(other.q, q) > 1e-3


def test_table_with_joint_offsets():
    table = np.array(UR10_DH, dtype=float)
    table[:, 1] = [0.1, -np.pi / 2, 0.0, np.pi / 2, 0.3, -0.2]
    arm = from_dh(table)
    Q = arm.random_configurations(100, seed=8)
    for q, T in zip(Q, arm.fk(Q)):
        res = ur10_ik(T, dh=table)
        assert res.success and gap_to(res.q, q) < 1e-8
        assert np.abs(arm.fk(res.q) - T).max() <= 1e-10


# ---------------------------------------------------------------- singular cases
def test_wrist_singularity():
    q = np.array([0.4, -1.0, 1.2, -0.3, 0.0, 0.7])  # q5 = 0: joints 2, 3, 4 and 6 parallel
    T = UR10.fk(q)
    res = ur10_ik(T)
    assert res.success and "wrist" in res.singular and len(res) < 8
    assert np.abs(UR10.fk(res.q) - T).max() <= 1e-10
    # on the generating shoulder branch one representative of the family: q5 = 0, q6 = 0 (q2, q3, q4 follow)
    branch = np.abs(wrapped(res.q[:, 0] - q[0])) < 1e-9
    assert branch.any() and np.all(res.q[branch, 4] == 0.0) and np.all(res.q[branch, 5] == 0.0)
    assert np.all(res.branches[branch, 1] == 1)  # the two wrist solutions coincide


def test_elbow_stretched():
    q = np.array([0.4, -1.0, 0.0, -0.3, 0.9, 0.7])
    T = UR10.fk(q)
    res = ur10_ik(T)
    assert res.success and "elbow" in res.singular
    assert np.abs(UR10.fk(res.q) - T).max() <= 1e-10 and gap_to(res.q, q) < 1e-6
    assert len(res) < 8  # the two elbow solutions of a stretched branch coincide
    assert len({tuple(b[:2]) for b in res.branches}) == len(res)  # (this pose: one per reached branch)


def test_shoulder_singularity():
    """Wrist centre on the base axis in the arm's plane: a2 c2 + a3 c23 + d5 s234 = 0, r = d4."""
    a2, a3 = -0.612, -0.5723
    q2 = -1.2
    q23 = -math.acos(-a2 * math.cos(q2) / a3)  # a2 c2 + a3 c23 = 0
    q = np.array([0.5, q2, q23 - q2, -q23, 1.0, 0.3])  # q2 + q3 + q4 = 0: s234 = 0
    T = UR10.fk(q)
    res = ur10_ik(T)
    assert np.isclose(np.hypot(*res.wrist_centre[:2]), 0.163941, atol=1e-12)
    assert res.success and "shoulder" in res.singular
    assert np.all(res.branches[:, 0] == 1)  # the two q1 coincide: one shoulder branch
    assert np.abs(UR10.fk(res.q) - T).max() <= 1e-9 and gap_to(res.q, q) < 1e-6


def test_singular_flags_agree_in_batch():
    qs = np.array([[0.4, -1.0, 1.2, -0.3, 0.0, 0.7], [0.4, -1.0, 0.0, -0.3, 0.9, 0.7],
                   [0.3, -1.2, 1.4, -0.5, 1.1, 0.2]])
    batch = ur10_ik_batch(UR10.fk(qs))
    for i, T in enumerate(UR10.fk(qs)):
        assert batch[i].singular == ur10_ik(T).singular
        assert np.abs(wrapped(batch[i].q - ur10_ik(T).q)).max() < 1e-12
    assert batch.singular.tolist() == [[False, True, False], [False, False, True], [False, False, False]]


# ---------------------------------------------------------------- unreachable targets
def _moved(T, dp):
    T = T.copy()
    T[:3, 3] += dp
    return T


def test_too_far():
    T = _moved(UR10.fk(np.zeros(6)), [5.0, 0.0, 0.0])
    res = ur10_ik(T)
    assert not res.success and res.reason == "too_far" and len(res) == 0
    assert res.q.shape == (0, 6) and res.branches.shape == (0, 3)


def test_shoulder_cylinder():
    T = np.eye(4)
    T[:3, 3] = [0.05, 0.0, 0.6]  # z6 up: the wrist centre 5 cm from the base axis, d4 = 16 cm
    res = ur10_ik(T)
    assert not res.success and res.reason == "shoulder_cylinder"


def test_too_close():
    table = np.array(UR10_DH, dtype=float)
    table[2, 2] = -0.3  # a shorter forearm: a hole of radius |a2| - |a3| = 0.312 m about the shoulder axis
    d1, d4, d6 = 0.1273, 0.163941, 0.0922
    T = np.eye(4)
    T[:3, 3] = [0.0, -d4, d1 + d6]  # wrist centre o5 = o1 + d4 z1 at q1 = 0: o4 is d5 = 0.116 m from the shoulder
    res = ur10_ik(T, dh=table)
    assert not res.success and res.reason == "too_close"
    assert ur10_ik_batch(T, dh=table).reason.tolist() == ["too_close"]


def test_unreachable_in_batch():
    T_far = _moved(UR10.fk(np.zeros(6)), [5.0, 0.0, 0.0])
    T_in = np.eye(4)
    T_in[:3, 3] = [0.05, 0.0, 0.6]
    batch = ur10_ik_batch(np.stack([T_far, T_in, UR10.fk(np.ones(6))]))
    assert batch.reason.tolist() == ["too_far", "shoulder_cylinder", "solved"]
    assert batch.success.tolist() == [False, False, True] and not batch.valid[:2].any()


def test_within_limits_option(random_cases):
    _, T, singles, _ = random_cases
    for Tq, res in zip(T[:20], singles[:20]):
        inside = ur10_ik(Tq, within_limits=True)
        assert np.array_equal(inside.q, res.q)  # every angle in (−π, π] is within ±2π
        assert np.all(UR10.within_limits(inside.q))


def test_reasons_and_names():
    assert REASONS[0] == "solved" and set(SINGULARITIES) == {"shoulder", "wrist", "elbow"}
    assert BRANCHES == ("shoulder", "wrist", "elbow")


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("T, error, match", [
    (np.eye(3), ShapeError, r"T_target must have shape \(4, 4\)"),
    (np.stack([np.eye(4)] * 2), ShapeError, r"T_target must have shape \(4, 4\) \(use ur10_ik_batch"),
    (np.full((4, 4), np.nan), DomainError, r"T_target must be finite"),
    (np.diag([1.0, 1.0, -1.0, 1.0]), DomainError, r"T_target\[:3, :3\] is not a rotation"),
    ("pose", TypeError, r"T_target must contain real numbers"),
])
def test_bad_target(T, error, match):
    with pytest.raises(error, match=match):
        ur10_ik(T)


def test_bad_table_and_tolerance():
    T = UR10.fk(np.ones(6))
    with pytest.raises(ShapeError, match=r"dh must have shape \(6, 4\); got shape \(5, 4\)"):
        ur10_ik(T, dh=np.array(UR10_DH)[:5])
    table = np.array(UR10_DH, dtype=float)
    table[4, 3] = np.pi / 2
    with pytest.raises(DomainError, match=r"dh is not a Universal Robots table .* alpha of row 5 must be -1.5708"):
        ur10_ik(T, dh=table)
    table = np.array(UR10_DH, dtype=float)
    table[1, 0] = 0.1
    with pytest.raises(DomainError, match=r"d2 \(row 2, column 1\) must be 0; got 0.1"):
        ur10_ik(T, dh=table)
    with pytest.raises(DomainError, match=r"dh must be a \(6, 4\) DH table or one of .*'ur10e'.*; got 'ur11'"):
        ur10_ik(T, dh="ur11")
    with pytest.raises(TypeError, match=r"dh must be a \(6, 4\) DH table"):
        ur10_ik(T, dh=3.0)
    with pytest.raises(DomainError, match=r"tol must be positive"):
        ur10_ik(T, tol=-1.0)
    with pytest.raises(DomainError, match=r"tol must be a small relative tolerance .* got 0.5"):
        ur10_ik_batch(T, tol=0.5)


def test_bad_pose_in_batch_is_named():
    T = np.stack([np.eye(4), np.eye(4)])
    T[1, :3, 0] *= 2.0
    with pytest.raises(DomainError, match=r"T_targets"):
        ur10_ik_batch(T)


def test_huge_targets_are_unreachable():
    T = np.eye(4)
    for p in ([1e300, 0.0, 0.0], [-1.7e308, 1.7e308, 1e-300], [0.0, 0.0, 1e300]):
        T[:3, 3] = p
        with np.errstate(all="raise"):
            res = ur10_ik(T)
        assert not res.success and res.reason in ("too_far", "shoulder_cylinder")
        assert ur10_ik_batch(T).reason[0] == res.reason


def test_wide_chain_solutions_equal(random_cases):
    """The solutions hold for the chain with the limits of the URDF (elbow ±π): within those limits too."""
    Q, T, singles, _ = random_cases
    narrow = SerialChain(UR10.elements, limits=[[-2 * np.pi, 2 * np.pi]] * 2 + [[-np.pi, np.pi]]
                         + [[-2 * np.pi, 2 * np.pi]] * 3, name="ur10_elbow_pi")
    for res in singles[:100]:
        assert np.all(narrow.within_limits(res.q))
