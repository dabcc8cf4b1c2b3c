"""Tests of robokin.models: every bundled robot, plus reference values from the exercises."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest
import sympy as sp

from robokin.chains import SerialChain, from_dh, from_modified_dh
from robokin.models import ar601_leg, baxter_left, eth_leg, planar_two_link, ur10
from robokin.models.baxter import BAXTER_LEFT_LIMITS, baxter_left_urdf

N_CONFIGS = 100

# --------------------------------------------------------------------------- helpers


def vee_log_small(R: np.ndarray) -> np.ndarray:
    """Rotation vector of a small rotation (batched): vee((R - R^T)/2), exact to O(θ³)."""
    A = 0.5 * (R - np.swapaxes(R, -1, -2))
    return np.stack([A[..., 2, 1], A[..., 0, 2], A[..., 1, 0]], axis=-1)


def fd_jacobian(pose_fn, Q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Central finite differences of a batched pose function -> (N, 6, n).

    Linear rows: (p(q+h) − p(q−h)) / 2h. Angular rows: the rotation vector of
    R(q+h) R(q−h)ᵀ divided by 2h.
    """
    N, n = Q.shape
    J = np.empty((N, 6, n))
    for i in range(n):
        e = np.zeros(n)
        e[i] = h
        Tp, Tm = pose_fn(Q + e), pose_fn(Q - e)
        J[:, :3, i] = (Tp[:, :3, 3] - Tm[:, :3, 3]) / (2 * h)
        J[:, 3:, i] = vee_log_small(Tp[:, :3, :3] @ np.swapaxes(Tm[:, :3, :3], -1, -2)) / (2 * h)
    return J


MODELS: dict[str, Callable[[], SerialChain]] = {
    "planar_two_link": planar_two_link,
    "eth_leg": eth_leg,
    "ur10": ur10,
    "ur10_mdh": lambda: ur10("mdh"),
    "ur10_ets": lambda: ur10("ets"),
    "baxter_left": baxter_left,
    "baxter_left_shoulder_gripper": lambda: baxter_left(base="shoulder", end="gripper"),
    "ar601_leg": ar601_leg,
}

_CACHE: dict[str, SerialChain] = {}


def model(name: str) -> SerialChain:
    """One instance per model for the whole module (its symbolic results are cached)."""
    if name not in _CACHE:
        _CACHE[name] = MODELS[name]()
    return _CACHE[name]


def configs(chain: SerialChain, seed: int = 0) -> np.ndarray:
    return chain.random_configurations(N_CONFIGS, seed=seed)


# --------------------------------------------------------------------------- all models


@pytest.mark.parametrize("name", list(MODELS))
def test_public_contract(name):
    chain = model(name)
    n = chain.n
    assert chain.limits.shape == (n, 2)
    assert np.all(chain.limits[:, 0] < chain.limits[:, 1])
    q = configs(chain)[0]
    assert chain.fk(q).shape == (4, 4)
    assert chain.jacobian(q).shape == (6, n)
    assert chain.frames(q).shape == (n + 2, 4, 4)
    assert len(chain.frame_names) == n + 2
    assert chain.joint_axes.shape == (n, 3)
    np.testing.assert_allclose(np.linalg.norm(chain.joint_axes, axis=1), 1.0)
    R = chain.fk(q)[:3, :3]
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)


@pytest.mark.parametrize("name", list(MODELS))
def test_jacobian_vs_finite_differences(name):
    chain = model(name)
    Q = configs(chain, seed=1)
    np.testing.assert_allclose(chain.jacobian(Q), fd_jacobian(chain.fk, Q), atol=1e-6)


@pytest.mark.parametrize("name", list(MODELS))
def test_batch_vs_loop(name):
    chain = model(name)
    Q = configs(chain, seed=2)
    np.testing.assert_allclose(chain.fk(Q), [chain.fk(q) for q in Q], atol=1e-12)
    np.testing.assert_allclose(chain.jacobian(Q), [chain.jacobian(q) for q in Q], atol=1e-12)
    np.testing.assert_allclose(chain.frames(Q), [chain.frames(q) for q in Q], atol=1e-12)
    np.testing.assert_allclose(
        chain.manipulability(Q, position_only=True),
        [chain.manipulability(q, position_only=True) for q in Q],
        atol=1e-12,
    )


@pytest.mark.parametrize("name", ["planar_two_link", "eth_leg", "ur10", "baxter_left", "ar601_leg"])
def test_lambdify_vs_direct(name):
    chain = model(name)
    Q = configs(chain, seed=3)
    fk = chain.lambdify_fk()
    jac = chain.lambdify_jacobian()
    np.testing.assert_allclose(fk(Q), chain.fk(Q), atol=1e-12)
    np.testing.assert_allclose(jac(Q), chain.jacobian(Q), atol=1e-12)
    np.testing.assert_allclose(fk(Q[0]), chain.fk(Q[0]), atol=1e-12)
    np.testing.assert_allclose(jac(Q[0]), chain.jacobian(Q[0]), atol=1e-12)


# --------------------------------------------------------------------------- planar arm


def test_planar_two_link_closed_form():
    arm = planar_two_link(0.8, 0.5)
    Q = configs(arm)
    p = arm.fk(Q)[:, :3, 3]
    q1, q2 = Q[:, 0], Q[:, 1]
    np.testing.assert_allclose(p[:, 0], 0.8 * np.cos(q1) + 0.5 * np.cos(q1 + q2), atol=1e-12)
    np.testing.assert_allclose(p[:, 1], 0.8 * np.sin(q1) + 0.5 * np.sin(q1 + q2), atol=1e-12)
    np.testing.assert_allclose(p[:, 2], 0.0, atol=1e-12)


def test_planar_two_link_symbolic_lengths():
    l1, l2 = sp.symbols("l1 l2", positive=True)
    arm = planar_two_link(l1, l2)
    q1, q2 = arm.symbols()
    p = arm.fk([q1, q2])[:3, 3]
    assert sp.simplify(p[1] - (l1 * sp.sin(q1) + l2 * sp.sin(q1 + q2))) == 0


# --------------------------------------------------------------------------- ETH leg


def leg_foot_closed_form(Q: np.ndarray) -> np.ndarray:
    """Foot position of the unit-length leg (exercise 1, eq. 15, re-derived)."""
    a, b, g = Q.T
    k = 1 + np.cos(b) + np.cos(b + g)
    return np.stack([-np.sin(b) - np.sin(b + g), np.sin(a) * k + 1, -np.cos(a) * k], axis=-1)


def test_leg_foot_closed_form():
    leg = model("eth_leg")
    Q = configs(leg, seed=4)
    np.testing.assert_allclose(leg.fk(Q)[:, :3, 3], leg_foot_closed_form(Q), atol=1e-12)
    assert leg.frame_names == ["B", "1", "2", "3", "F"]
    # frame 1 sits at B r_B1 = [0, 1, 0] whatever the configuration
    np.testing.assert_allclose(leg.frames(Q)[:, 1, :3, 3], np.tile([0.0, 1.0, 0.0], (N_CONFIGS, 1)))


def test_leg_lengths_are_parameters():
    leg = eth_leg(l_b=0.5, l_1=0.2, l_2=0.3, l_3=0.4)
    np.testing.assert_allclose(leg.fk([0.0, 0.0, 0.0])[:3, 3], [0.0, 0.5, -0.9], atol=1e-15)


def test_leg_default_limits_and_override():
    np.testing.assert_allclose(
        model("eth_leg").limits,
        [[-math.pi / 2, math.pi / 2], [-3 * math.pi / 4, 3 * math.pi / 4], [-math.pi, math.pi]],
    )
    tight = [[-math.pi / 2, math.pi / 2], [-math.pi / 2, math.pi / 2], [-math.pi, math.pi]]
    leg = eth_leg(limits=tight)
    np.testing.assert_allclose(leg.limits, tight)
    q = np.deg2rad([10.0, -100.0, 120.0])
    assert model("eth_leg").within_limits(q) and not leg.within_limits(q)
    np.testing.assert_allclose(leg.fk(q), model("eth_leg").fk(q), atol=1e-15)   # same kinematics
    with pytest.raises(ValueError, match="limits"):
        eth_leg(limits=tight[:2])


def leg_ik_closed_form(p) -> np.ndarray:
    """All solutions of r_BF(q) = p of the unit leg, from its geometry (rows, wrapped to (−π, π]).

    α turns the leg plane through p (foot below or above the hip axis); in that plane β and γ
    form a planar two-link arm whose shoulder (the β joint) sits 1 m from the hip axis.
    """
    d = np.asarray(p, dtype=float) - [0.0, 1.0, 0.0]
    rho = math.hypot(d[1], d[2])
    sols = []
    for a, L in [(math.atan2(d[1], -d[2]), rho), (math.atan2(-d[1], d[2]), -rho)]:
        u, w = d[0], 1.0 - L
        c = (u * u + w * w - 2.0) / 2.0
        if abs(c) <= 1:
            for g in (math.acos(c), -math.acos(c)):
                sols.append(np.angle(np.exp(1j * np.array([a, math.atan2(-u, -w) - g / 2, g]))))
    return np.array(sols)


def test_leg_limits_contain_the_exercise_with_margin():
    """The exercise sets no joint limits: the model's must not forbid what it asks for.

    Configurations of AMR exercise 1 (chapter 1): the lift pose of task 3, the start and both
    knee solutions of the IK goal of task 4 and the closest point to its unreachable goal, and
    the start and the whole circle of task 5 (which needs β ≈ −97°). Each must lie at least 25°
    inside every limit.
    """
    leg = model("eth_leg")
    margin = np.deg2rad(25.0)
    lower, upper = leg.limits[:, 0] + margin, leg.limits[:, 1] - margin
    poses = np.deg2rad([[0, 60, -120], [0, -30, 60], [0, 45, 0], [0, -60, 120]])
    goal = leg_ik_closed_form([0.2, 0.5, -2.0])
    assert len(goal) == 2                                            # the two knees
    q0 = np.deg2rad([0.0, -60.0, 120.0])
    c = leg.fk(q0)[:3, 3]
    wt = np.linspace(0.0, 2 * math.pi, 721)
    ring = c + 0.5 * np.column_stack([np.sin(wt), 0 * wt, np.cos(wt)])
    circle = np.array([next(s for s in leg_ik_closed_form(p) if s[2] > 0) for p in ring])  # knee as q0
    np.testing.assert_allclose(leg.fk(goal)[:, :3, 3], [[0.2, 0.5, -2.0]] * 2, atol=1e-12)
    np.testing.assert_allclose(leg.fk(circle)[:, :3, 3], ring, atol=1e-12)
    assert np.deg2rad(-98) < circle[:, 1].min() < np.deg2rad(-96)     # thigh above horizontal
    for Q in (poses, goal, circle):
        assert np.all((Q >= lower) & (Q <= upper)), np.rad2deg(Q[~np.all((Q >= lower) & (Q <= upper), 1)])


# Reference cases derived by hand (exercise 1, task 3) at q = [0°, 60°, −120°]:
# with β = 60°, β + γ = −60°:
#   ∂x/∂β = −cos β − cos(β+γ) = −1,   ∂x/∂γ = −cos(β+γ) = −1/2,
#   ∂y/∂α = cos α (1 + cos β + cos(β+γ)) = 2,
#   ∂z/∂γ = cos α sin(β+γ) = −√3/2   (the report prints +0.866 here: a sign slip;
#   its q̇ below was computed with the correct −0.866),
# all other entries 0. v = [0, 0, −1] m/s then needs q̇ = J⁻¹ v = [0, −1/√3, 2/√3] rad/s.
S3 = math.sqrt(3.0)
LEG_REFERENCE = [
    pytest.param(
        [0.0, 60.0, -120.0],
        [0.0, 1.0, -2.0],
        [[0.0, -1.0, -0.5], [2.0, 0.0, 0.0], [0.0, 0.0, -S3 / 2]],
        [0.0, 0.0, -1.0],
        [0.0, -1.0 / S3, 2.0 / S3],
        id="exercise-q0-60-m120",
    ),
    pytest.param(  # stretched sideways: α = 90°, β = γ = 0: foot at [0, 4, 0]
        [90.0, 0.0, 0.0],
        [0.0, 4.0, 0.0],
        # ∂r/∂α = [0, cos α·3, sin α·3] = [0, 0, 3]; ∂r/∂β = [−2, 0, 0] (sin α (−sin β …) = 0,
        # cos α (…) = 0); ∂r/∂γ = [−1, 0, 0]: rank 2 (β and γ columns parallel) -> singular
        [[0.0, -2.0, -1.0], [0.0, 0.0, 0.0], [3.0, 0.0, 0.0]],
        None,
        None,
        id="singular-stretched",
    ),
]


@pytest.mark.parametrize("q_deg, foot, Jv, v, qdot", LEG_REFERENCE)
def test_leg_reference_values(q_deg, foot, Jv, v, qdot):
    leg = model("eth_leg")
    q = np.deg2rad(q_deg)
    np.testing.assert_allclose(leg.fk(q)[:3, 3], foot, atol=1e-12)
    J = leg.position_jacobian(q)
    np.testing.assert_allclose(J, Jv, atol=1e-12)
    if qdot is None:
        assert leg.manipulability(q, position_only=True) == pytest.approx(0.0, abs=1e-12)
    else:
        np.testing.assert_allclose(np.linalg.solve(J, v), qdot, atol=1e-12)
        np.testing.assert_allclose(J @ np.asarray(qdot), v, atol=1e-12)


def test_leg_symbolic_readable():
    leg = model("eth_leg")
    alpha, beta, gamma = leg.symbols()
    T = leg.fk(leg.symbols())
    assert "sin(beta + gamma)" in str(T)
    foot = T[:3, 3]
    expected = sp.Matrix([
        -sp.sin(beta) - sp.sin(beta + gamma),
        sp.sin(alpha) * (1 + sp.cos(beta) + sp.cos(beta + gamma)) + 1,
        -sp.cos(alpha) * (1 + sp.cos(beta) + sp.cos(beta + gamma)),
    ])
    assert sp.simplify(foot - expected) == sp.zeros(3, 1)
    Jv = leg.position_jacobian(leg.symbols())
    assert sp.simplify(Jv - foot.jacobian([alpha, beta, gamma])) == sp.zeros(3, 3)
    assert "sin(beta + gamma)" in str(Jv)


# --------------------------------------------------------------------------- UR10


def test_ur10_descriptions_agree():
    dh, mdh, ets = model("ur10"), model("ur10_mdh"), model("ur10_ets")
    Q = configs(dh, seed=5)
    for other in (mdh, ets):
        np.testing.assert_allclose(other.fk(Q), dh.fk(Q), atol=1e-12)
        np.testing.assert_allclose(other.jacobian(Q), dh.jacobian(Q), atol=1e-12)
    assert dh.joint_names == mdh.joint_names == ets.joint_names


def test_ur10_zero_pose():
    # q = 0: arm stretched along −x: p = [a2 + a3, −(d4 + d6), d1 − d5] (hand-derived)
    T = model("ur10").fk(np.zeros(6))
    np.testing.assert_allclose(T[:3, 3], [-0.612 - 0.5723, -(0.163941 + 0.0922), 0.1273 - 0.1157], atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-15)
    np.testing.assert_allclose(model("ur10").limits, [[-2 * math.pi, 2 * math.pi]] * 6)


def test_ur10_bad_description():
    with pytest.raises(ValueError, match="description"):
        ur10("urdf")


# --------------------------------------------------------------------------- Baxter


def test_baxter_matches_urdf():
    """The modified-DH model reproduces the URDF joint chain (pose of left_hand / left_gripper)."""
    Q = configs(model("baxter_left"), seed=6)
    for end in ("hand", "gripper"):
        ours = baxter_left(end=end).fk(Q)
        urdf = baxter_left_urdf(end=end).fk(Q)
        # the URDF writes the mount yaw as 0.7854 (π/4 + 1.8e-6) and π/2 as 1.57079632679
        np.testing.assert_allclose(ours, urdf, atol=5e-6)


def test_baxter_limits_and_shoulder_base():
    torso, shoulder = model("baxter_left"), baxter_left(base="shoulder")
    np.testing.assert_allclose(torso.limits, BAXTER_LEFT_LIMITS)
    assert torso.joint_names == ["s0", "s1", "e0", "e1", "w0", "w1", "w2"]
    Q = configs(torso, seed=7)
    mount = torso.frames(np.zeros(7))[1] @ np.linalg.inv(shoulder.frames(np.zeros(7))[1])
    np.testing.assert_allclose(torso.fk(Q), mount @ shoulder.fk(Q), atol=1e-12)
    # zero pose (hand-derived): arm stretched horizontally along the mount direction
    # (45° in the torso x–y plane), reach 0.055695 + 0.069 + 0.36442 + 0.37429 + 0.229525
    # from the mount; the elbow (0.069) and wrist (0.010) offsets point down.
    reach = 0.055695 + 0.069 + 0.36442 + 0.37429 + 0.229525
    expected = [0.024645 + reach / math.sqrt(2), 0.219645 + reach / math.sqrt(2),
                0.118588 + 0.011038 + 0.27035 - 0.069 - 0.010]
    np.testing.assert_allclose(torso.fk(np.zeros(7))[:3, 3], expected, atol=1e-12)


def test_baxter_published_dh_tables():
    shoulder = baxter_left(base="shoulder")
    Q = configs(shoulder, seed=8)
    # Ju, Yang & Ma (2014) / Corke's mdl_baxter standard DH: same arm, d3 = 0.36435
    # (URDF: 0.102 + 0.26242 = 0.36442), so positions agree to 7e-5 m.
    pi = math.pi
    std = from_dh([
        [0.27035, 0, 0.069, -pi / 2], [0, pi / 2, 0, pi / 2], [0.36435, 0, 0.069, -pi / 2],
        [0, 0, 0, pi / 2], [0.37429, 0, 0.010, -pi / 2], [0, 0, 0, pi / 2], [0.229525, 0, 0, 0],
    ])
    d = std.fk(Q) - shoulder.fk(Q)
    assert np.abs(d[:, :3, 3]).max() < 1e-4
    assert np.abs(d[:, :3, :3]).max() < 1e-12
    # The Imperial College tutorial's modified-DH table (seed 003) rounds the lengths and
    # α = ±1.571 and omits the θ2 offset π/2: it matches only after q2 -> q2 + π/2.
    seed = from_modified_dh([
        [0.2703, 0, 0, 0], [0, 0, 0.069, -1.571], [0.3644, 0, 0, 1.571], [0, 0, 0.069, -1.571],
        [0.3743, 0, 0, 1.571], [0, 0, 0.01, -1.571], [0.2295, 0, 0, 1.571],
    ])
    shifted = Q + np.array([0, pi / 2, 0, 0, 0, 0, 0])
    assert np.abs(seed.fk(shifted)[:, :3, 3] - shoulder.fk(Q)[:, :3, 3]).max() < 2e-3
    assert np.abs(seed.fk(Q)[:, :3, 3] - shoulder.fk(Q)[:, :3, 3]).max() > 0.1


def test_baxter_bad_options():
    with pytest.raises(ValueError, match="base"):
        baxter_left(base="world")
    with pytest.raises(ValueError, match="end"):
        baxter_left(end="camera")


# --------------------------------------------------------------------------- AR-601 leg


def ar601_report_position(Q: np.ndarray, L1: float, L2: float, L3: float) -> np.ndarray:
    """X, Y, Z as printed in the AR-601 report (seed 004)."""
    s1, s2, s3, s4, s5, s6 = np.sin(Q).T
    c1, c2, c3, c4, c5, c6 = np.cos(Q).T
    X = (-L1 * (s1 * s3 + c1 * c3 * s2)
         - L2 * (c4 * (s1 * s3 + c1 * c3 * s2) + s4 * (c3 * s1 - c1 * s2 * s3))
         - L3 * (s6 * (c4 * (c3 * s1 - c1 * s2 * s3) - s4 * (s1 * s3 + c1 * c3 * s2))
                 + c6 * (c5 * (c4 * (s1 * s3 + c1 * c3 * s2) + s4 * (c3 * s1 - c1 * s2 * s3))
                         + c1 * c2 * s5)))
    Y = (L1 * (c1 * s3 - c3 * s1 * s2)
         + L2 * (c4 * (c1 * s3 - c3 * s1 * s2) + s4 * (c1 * c3 + s1 * s2 * s3))
         + L3 * (s6 * (c4 * (c1 * c3 + s1 * s2 * s3) - s4 * (c1 * s3 - c3 * s1 * s2))
                 + c6 * (c5 * (c4 * (c1 * s3 - c3 * s1 * s2) + s4 * (c1 * c3 + s1 * s2 * s3))
                         - c2 * s1 * s5)))
    Z = (L3 * (c6 * (s2 * s5 - c5 * (c2 * c3 * c4 - c2 * s3 * s4)) + s6 * (c2 * c3 * s4 + c2 * c4 * s3))
         - L2 * (c2 * c3 * c4 - c2 * s3 * s4) - L1 * c2 * c3)
    return np.stack([X, Y, Z], axis=-1)


@pytest.mark.parametrize("lengths", [(0.3, 0.3, 0.1), (10.0, 10.0, 10.0)])
def test_ar601_matches_report_formulas(lengths):
    leg = ar601_leg(*lengths)
    Q = configs(leg, seed=9)
    np.testing.assert_allclose(leg.fk(Q)[:, :3, 3], ar601_report_position(Q, *lengths), atol=1e-12)


def test_ar601_zero_pose_and_frames():
    leg = ar601_leg(10, 10, 10)
    # the report's own check: all lengths 10, all angles 0 -> foot at z = −30
    expected = np.diag([1.0, 1, 1, 1]) + np.r_[0, 0, -30.0, 0][:, None] * np.eye(4)[3]
    np.testing.assert_allclose(leg.fk(np.zeros(6)), expected, atol=1e-12)
    F = leg.frames(np.zeros(6))
    np.testing.assert_allclose(F[1:4, :3, 3], 0.0)  # hip joints intersect at the base origin
    np.testing.assert_allclose(F[4, :3, 3], [0, 0, -10])  # knee
    np.testing.assert_allclose(F[5, :3, 3], [0, 0, -20])  # ankle
    assert "sin(q3 + q4)" in str(leg.fk(leg.symbols())) or "cos(q3 + q4)" in str(leg.fk(leg.symbols()))


def test_ar601_symbolic_foot_position_is_simplified_already():
    """Chapter 6 takes the foot position from the symbolic fk as it is: sp.simplify changes nothing."""
    q = sp.symbols("q1:7", real=True)
    lengths = sp.symbols("L1 L2 L3", positive=True)
    p = ar601_leg(*lengths).fk(list(q))[:3, 3]
    assert sp.Matrix([sp.simplify(e) for e in p]) == p


def test_ur10_symbolic_exact_and_readable():
    ur = model("ur10")
    T = ur.fk(ur.symbols())
    text = str(T)
    assert "e-1" not in text  # float π/2 twists become exact: no 6e-17 residues
    assert "elbow + shoulder_lift + wrist_1" in text  # parallel axes 2, 3, 4 combine
    assert T[3, :] == sp.Matrix([[0, 0, 0, 1]])
