"""Tests of robokin.parallel.planar_3rpr and robokin.models.three_rpr."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robokin.errors import DomainError, ShapeError
from robokin.models.three_rpr import (
    CLASSIC_RHO,
    EXERCISE_BASE,
    three_rpr,
    three_rpr_classic,
)
from robokin.parallel import ForwardKinematicsResult, Planar3RPR

S3 = math.sqrt(3.0) / 2.0


def exercise_ik(x, y, phi):
    """The exercise's loop equations written out (unit equilateral platform, reference B1)."""
    return np.array([
        math.hypot(x, y),
        math.hypot(x + math.cos(phi) - 1.0, y + math.sin(phi)),
        math.hypot(x + math.cos(phi + math.pi / 3) - 0.5, y + math.sin(phi + math.pi / 3) - S3),
    ])


def random_poses(n, seed, box=((0.1, 0.7), (0.05, 0.6), (-1.2, 1.2))):
    rng = np.random.default_rng(seed)
    lo, hi = np.array(box).T
    return lo + (hi - lo) * rng.random((n, 3))


def same_pose(p, q, tol=1e-7):
    return np.abs(p[:2] - q[:2]).max() < tol and abs(math.remainder(p[2] - q[2], 2 * math.pi)) < tol


# ---------------------------------------------------------------- inverse kinematics
@pytest.mark.parametrize("pose", [(0.3, 0.2, 0.4), (0.0, 0.5, 0.0), (0.25, 0.1, -1.0), (-0.2, 0.4, 3.0)])
def test_ik_matches_exercise_formulas(pose):
    robot = three_rpr()
    assert np.allclose(robot.inverse_kinematics(pose), exercise_ik(*pose), atol=1e-14)


def test_ik_batch_and_shapes():
    robot = three_rpr(0.5)
    P = random_poses(7, 1)
    rho = robot.inverse_kinematics(P)
    assert rho.shape == (7, 3)
    assert np.allclose(rho, [robot.inverse_kinematics(p) for p in P])
    assert robot.platform_points(P).shape == (7, 3, 2)
    assert robot.jacobian(P).shape == (7, 3, 3)
    assert np.shape(robot.condition_number(P)) == (7,)
    assert np.shape(robot.within_stroke(rho)) == (7,)


def test_reference_point_is_b1():
    robot = three_rpr()
    B = robot.platform_points([0.3, 0.2, 0.4])
    assert np.allclose(B[0], [0.3, 0.2])
    assert np.allclose(np.linalg.norm(np.diff(B[[0, 1, 2, 0]], axis=0), axis=1), 1.0)
    assert np.allclose(robot.leg_angles([0.3, 0.2, 0.4])[0], math.atan2(0.2, 0.3))


# ---------------------------------------------------------------- forward kinematics
@pytest.mark.parametrize("make,box", [
    (three_rpr_classic, ((-1.5, 1.5), (-1.5, 1.5), (-math.pi, math.pi))),
    (lambda: three_rpr(0.5), ((0.0, 0.8), (0.0, 0.7), (-math.pi, math.pi))),
    (three_rpr, ((0.1, 0.7), (0.05, 0.6), (-1.2, 1.2))),
])
def test_fk_round_trip_random_poses(make, box):
    robot = make()
    for pose in random_poses(40, 7, box):
        rho = robot.inverse_kinematics(pose)
        res = robot.forward_kinematics(rho)
        assert isinstance(res, ForwardKinematicsResult)
        assert res.success and res.reason == "solved"
        assert 1 <= res.count <= 6 and res.poses.shape == (res.count, 3)
        # every root reproduces the leg lengths ...
        assert np.allclose(robot.inverse_kinematics(res.poses), rho, atol=1e-9)
        assert np.all(res.residuals < 1e-9)
        # ... and the true pose is among them
        assert any(same_pose(p, pose) for p in res.poses)
        # sorted, wrapped, distinct
        assert np.all(np.diff(res.poses[:, 2]) > 0)
        assert np.all((res.poses[:, 2] > -math.pi) & (res.poses[:, 2] <= math.pi))


def test_classic_example_has_six_modes():
    robot = three_rpr_classic()
    res = robot.forward_kinematics(CLASSIC_RHO)
    assert res.count == 6 and len(res) == 6
    assert np.allclose(robot.inverse_kinematics(res.poses), CLASSIC_RHO, atol=1e-12)
    # the six orientations (rad), obtained independently by scanning F(φ) for sign changes + brentq
    from scipy.optimize import brentq
    def F(phi):
        return robot._orientation_function(np.array(phi), CLASSIC_RHO)
    grid = np.linspace(-math.pi, math.pi, 4001)
    vals = F(grid)
    roots = [brentq(F, a, b, xtol=1e-14) for a, b, fa, fb in
             zip(grid[:-1], grid[1:], vals[:-1], vals[1:]) if fa * fb < 0]
    assert np.allclose(np.sort(roots), res.poses[:, 2], atol=1e-9)


def test_orientation_polynomial_degree_and_roots():
    robot = three_rpr_classic()
    C = robot.orientation_polynomial(CLASSIC_RHO)
    assert C.shape == (7,) and abs(C[6]) > 1e-6 * np.abs(C).max()
    t = np.roots(C[::-1])
    t_real = np.sort(t[np.abs(t.imag) < 1e-9].real)
    assert np.allclose(t_real, np.tan(robot.forward_kinematics(CLASSIC_RHO).poses[:, 2] / 2), atol=1e-8)
    # F is a trigonometric polynomial of order 3: harmonics 4..8 vanish
    phi = 2 * np.pi * np.arange(16) / 16
    c = np.fft.fft(robot._orientation_function(phi, CLASSIC_RHO)) / 16
    assert np.abs(c[4:13]).max() < 1e-9 * np.abs(c).max()


def test_exercise_geometry_even_polynomial_at_most_four_modes():
    robot = three_rpr()
    rng = np.random.default_rng(3)
    counts = set()
    for rho in rng.uniform(0.1, 1.5, (300, 3)):
        C = robot.orientation_polynomial(rho)
        scale = np.abs(C).max()
        assert abs(C[0]) < 1e-9 * scale and np.abs(C[1::2]).max() < 1e-9 * scale   # t^2 * even
        counts.add(robot.forward_kinematics(rho).count)
    assert counts <= {0, 2, 4} and 4 in counts


def test_phi_equal_pi_is_found():
    robot = three_rpr_classic()
    pose = np.array([0.4, 0.9, math.pi])
    rho = robot.inverse_kinematics(pose)
    C = robot.orientation_polynomial(rho)
    assert abs(C[6]) < 1e-9 * np.abs(C).max()      # t = tan(π/2) = ∞: the degree drops
    res = robot.forward_kinematics(rho)
    assert any(same_pose(p, pose) for p in res.poses)
    assert np.any(np.abs(np.abs(res.poses[:, 2]) - math.pi) < 1e-9)


def test_no_assembly_mode():
    robot = three_rpr()
    res = robot.forward_kinematics([0.1, 0.1, 3.0])     # legs cannot reach a unit platform
    assert not res.success and res.count == 0 and res.poses.shape == (0, 3)
    assert "no real assembly mode" in res.reason


def test_continuum_of_modes_congruent_translation():
    robot = three_rpr()          # congruent base and platform, all legs equal: a circle of poses
    res = robot.forward_kinematics([0.4, 0.4, 0.4])
    assert not res.success and "continuum" in res.reason
    assert res.count == 2 and np.allclose(robot.inverse_kinematics(res.poses), 0.4)   # isolated modes kept


# ---------------------------------------------------------------- Jacobian
@pytest.mark.parametrize("make", [three_rpr, three_rpr_classic, lambda: three_rpr(0.4)])
def test_jacobian_vs_finite_differences(make):
    robot = make()
    for pose in random_poses(15, 11):
        A = robot.jacobian(pose)
        h = 1e-6
        A_fd = np.column_stack([(robot.inverse_kinematics(pose + h * e) - robot.inverse_kinematics(pose - h * e))
                                / (2 * h) for e in np.eye(3)])
        assert np.allclose(A, A_fd, atol=1e-7)


def test_direct_jacobian_is_inverse_and_matches_fk_differences():
    robot = three_rpr_classic()
    res = robot.forward_kinematics(CLASSIC_RHO)
    for pose in res.poses:
        Jd = robot.direct_jacobian(pose)
        assert np.allclose(Jd @ robot.jacobian(pose), np.eye(3))
        # finite differences of the forward kinematics on the same branch
        cols = []
        for e in np.eye(3):
            plus = robot.forward_kinematics(CLASSIC_RHO + 1e-6 * e).poses
            minus = robot.forward_kinematics(CLASSIC_RHO - 1e-6 * e).poses
            pp = plus[np.argmin(np.linalg.norm(plus - pose, axis=1))]
            pm = minus[np.argmin(np.linalg.norm(minus - pose, axis=1))]
            cols.append((pp - pm) / 2e-6)
        assert np.allclose(np.column_stack(cols), Jd, rtol=1e-4, atol=1e-4)


def test_singularity_concurrent_legs():
    robot = three_rpr()
    # platform turned by π about... choose a pose whose three leg lines meet in one point:
    # with φ = 0 and the congruent platform all legs are parallel (A_i B_i = p for every i)
    pose = np.array([0.2, 0.3, 0.0])
    assert robot.is_singular(pose)
    assert robot.condition_number(pose) > 1e12
    with pytest.raises(DomainError, match="singular"):
        robot.direct_jacobian(pose)
    assert not robot.is_singular([0.2, 0.3, 0.5])
    # concurrent legs: all three leg lines through the centroid of the base triangle
    small = three_rpr(0.3)
    g = EXERCISE_BASE.mean(axis=0)
    # platform centred on g, turned by 0: B_i - A_i point towards g for the similar triangle
    c_b = small.platform_anchors.mean(axis=0)
    pose_c = np.array([g[0] - c_b[0], g[1] - c_b[1], 0.0])
    assert small.is_singular(pose_c)
    # the null vector is a rotation about the concurrency point g
    _, s, Vt = np.linalg.svd(small.jacobian(pose_c))
    v = Vt[-1]
    assert s[-1] < 1e-12 and abs(v[2]) > 0.1


def test_singular_poses_are_detected_by_fk_double_roots():
    robot = three_rpr_classic()
    # det A changes sign between two assembly modes of the same leg lengths separated by a singularity
    dets = np.linalg.det(robot.jacobian(robot.forward_kinematics(CLASSIC_RHO).poses))
    assert np.all(np.abs(dets) > 1e-3) and (dets > 0).any() and (dets < 0).any()


# ---------------------------------------------------------------- bad input
def test_bad_input():
    robot = three_rpr()
    with pytest.raises(ShapeError, match="pose"):
        robot.inverse_kinematics([0.1, 0.2])
    with pytest.raises(DomainError, match="pose"):
        robot.inverse_kinematics([0.1, np.nan, 0.0])
    with pytest.raises(TypeError):
        robot.inverse_kinematics(["a", "b", "c"])
    with pytest.raises(ShapeError, match="rho"):
        robot.forward_kinematics([1.0, 1.0])
    with pytest.raises(DomainError, match="rho"):
        robot.forward_kinematics([1.0, -1.0, 1.0])
    with pytest.raises(DomainError, match="rho"):
        robot.forward_kinematics([1.0, np.inf, 1.0])
    with pytest.raises(ShapeError, match="base_anchors"):
        Planar3RPR([[0, 0], [1, 0]], EXERCISE_BASE)
    with pytest.raises(DomainError, match="platform_anchors"):
        Planar3RPR(EXERCISE_BASE, [[0, 0], [1, 0], [2, 0]])
    with pytest.raises(ShapeError, match="stroke"):
        Planar3RPR(EXERCISE_BASE, EXERCISE_BASE, stroke=[1, 2, 3])
    with pytest.raises(DomainError, match="stroke"):
        Planar3RPR(EXERCISE_BASE, EXERCISE_BASE, stroke=(2.0, 1.0))
    with pytest.raises(DomainError, match="platform_side"):
        three_rpr(-1.0)
    with pytest.raises(DomainError, match="length 0"):
        robot.jacobian([0.0, 0.0, 0.3])           # B1 on A1


def test_within_stroke():
    robot = three_rpr(stroke=(0.2, 1.0))
    assert robot.within_stroke([0.5, 0.5, 0.5]) and not robot.within_stroke([0.1, 0.5, 0.5])
    assert np.asarray(robot.within_stroke([[0.5, 0.5, 0.5], [0.5, 1.5, 0.5]])).tolist() == [True, False]


@pytest.mark.parametrize("pose, leg, where", [
    ([0.0, 0.0, 0.3], 1, r"pose \[0.0, 0.0, 0.3\]"),                     # B1 on A1
    ([[0.2, 0.1, 0.4], [0.0, 0.0, 0.4]], 1, r"pose\[1\] = \[0.0, 0.0, 0.4\]"),
    ([1.0 - np.cos(0.7), -np.sin(0.7), 0.7], 2, r"pose \["),               # B2 on A2
])
def test_jacobian_at_a_zero_length_leg_names_the_pose_and_the_leg(pose, leg, where):
    """A grid of positions through a base anchor: the error says which pose and which leg."""
    with pytest.raises(DomainError, match=rf"{where}.*B{leg} on base anchor A{leg} \(leg {leg} has length 0\)"):
        three_rpr().jacobian(pose)
    with pytest.raises(DomainError, match=f"leg {leg} has length 0"):
        three_rpr().condition_number(pose)


def test_jacobian_maps_platform_velocity_to_leg_rates():
    """jacobian is the inverse Jacobian A (rho_dot = A x_dot), direct_jacobian its inverse."""
    robot = three_rpr()
    pose, x_dot, h = np.array([0.3, 0.2, 0.4]), np.array([0.05, -0.02, 0.3]), 1e-6
    rho_dot = (robot.inverse_kinematics(pose + h * x_dot) - robot.inverse_kinematics(pose - h * x_dot)) / (2 * h)
    assert np.allclose(robot.jacobian(pose) @ x_dot, rho_dot, atol=1e-9)
    assert np.allclose(robot.direct_jacobian(pose) @ rho_dot, x_dot, atol=1e-9)
    doc = Planar3RPR.jacobian.__doc__ or ""
    assert "leg rates" in doc and "serial chain" in doc
