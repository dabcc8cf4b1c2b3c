"""Tests of robokin.chains.ellipsoids: statics (τ = Jᵀ w) and the velocity and force ellipsoids.

Independent references: finite differences of the work a force does (virtual work), the
definitions of the two ellipsoids (the image of the unit ball of joint speeds; the forces held by
unit torques) checked on their boundaries, the planar two-link arm's closed form and the
isotropic design of Salisbury & Craig (1982), l₂ = l₁/√2 at θ₂ = ±135°.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import pytest

from robokin.chains import SerialChain
from robokin.chains.ellipsoids import force_ellipsoid, static_torques, velocity_ellipsoid
from robokin.errors import ShapeError
from robokin.models import baxter_left, eth_leg, planar_two_link, ur10
from support.finite_differences import pose_jacobian

CHAINS: dict[str, Callable[[], SerialChain]] = {"ur10": ur10, "baxter_left": baxter_left, "eth_leg": eth_leg,
                                                "planar_two_link": planar_two_link}
TOLERANCE = 1e-12


@pytest.fixture(scope="module", params=sorted(CHAINS))
def chain(request):
    return CHAINS[request.param]()


@pytest.mark.parametrize("part", ["position", "orientation"])
def test_velocity_ellipsoid_is_the_image_of_the_unit_ball(chain, part):
    """Each semi-axis σᵢuᵢ is reached with a unit joint speed; no unit speed leaves the ellipsoid."""
    rows = slice(0, 3) if part == "position" else slice(3, 6)
    rng = np.random.default_rng(0)
    for q in chain.random_configurations(5, seed=1):
        radii, axes = velocity_ellipsoid(chain, q, part)
        J = chain.jacobian(q)[rows]
        assert np.all(np.diff(radii) <= 0) and np.allclose(axes.T @ axes, np.eye(3), atol=TOLERANCE)
        speeds = rng.normal(size=(200, chain.n))
        speeds /= np.linalg.norm(speeds, axis=1, keepdims=True)
        reached = speeds @ J.T @ axes              # coordinates along the axes
        inside = radii > 1e-9
        assert np.all(np.sum((reached[:, inside] / radii[inside]) ** 2, axis=1) <= 1 + 1e-9)
        assert np.allclose(reached[:, ~inside], 0, atol=1e-9)
        # the largest semi-axis is reached: ‖J_p‖₂ = σ₁
        assert abs(np.linalg.norm(J, 2) - radii[0]) < TOLERANCE


@pytest.mark.parametrize("part", ["position", "orientation"])
def test_force_ellipsoid_is_dual(chain, part):
    """Same axes, inverted radii; a force along an axis with the radius as magnitude needs unit torques."""
    rows = slice(0, 3) if part == "position" else slice(3, 6)
    for q in chain.random_configurations(5, seed=2):
        speed_radii, speed_axes = velocity_ellipsoid(chain, q, part)
        force_radii, force_axes = force_ellipsoid(chain, q, part)
        assert np.array_equal(force_axes, speed_axes[:, ::-1])
        finite = np.isfinite(force_radii)
        assert np.allclose(force_radii[finite] * speed_radii[::-1][finite], 1.0, rtol=1e-12)
        J = chain.jacobian(q)[rows]
        for radius, axis in zip(force_radii[finite], force_axes.T[finite]):
            assert abs(np.linalg.norm(J.T @ (radius * axis)) - 1.0) < 1e-9
        for axis in force_axes.T[~finite]:   # held with no torque at all
            assert np.linalg.norm(J.T @ axis) < 1e-9


def test_planar_arm_in_closed_form():
    """J_v of the planar 2R arm (l₁ = 1, l₂ = 0.7): σ₁², σ₂² are the eigenvalues of J_v J_vᵀ;
    out of the plane it cannot move (radius 0) and holds any force (radius inf)."""
    arm = planar_two_link(1.0, 0.7)
    t1, t2 = 0.4, 1.1
    s1, c1, s12, c12 = math.sin(t1), math.cos(t1), math.sin(t1 + t2), math.cos(t1 + t2)
    J = np.array([[-s1 - 0.7 * s12, -0.7 * s12], [c1 + 0.7 * c12, 0.7 * c12]])
    eigenvalues = np.sort(np.linalg.eigvalsh(J @ J.T))[::-1]
    radii, axes = velocity_ellipsoid(arm, [t1, t2])
    assert np.allclose(radii, [*np.sqrt(eigenvalues), 0.0], atol=TOLERANCE)
    assert np.allclose(np.abs(axes[:, 2]), [0, 0, 1], atol=TOLERANCE)
    force_radii, _ = force_ellipsoid(arm, [t1, t2])
    assert force_radii[0] == math.inf and np.allclose(force_radii[1:], 1 / np.sqrt(eigenvalues)[::-1])


@pytest.mark.parametrize("elbow", [3 * math.pi / 4, -3 * math.pi / 4])
def test_isotropic_two_link_arm(elbow):
    """Salisbury & Craig (1982): with l₂ = l₁/√2 at θ₂ = ±135° the velocity ellipse is a circle."""
    arm = planar_two_link(1.0, 1.0 / math.sqrt(2.0))
    radii, _ = velocity_ellipsoid(arm, [0.3, elbow])
    assert abs(radii[0] - radii[1]) < TOLERANCE
    other, _ = velocity_ellipsoid(arm, [0.3, elbow + 0.2])
    assert other[0] / other[1] > 1.1


def test_at_a_singularity_the_force_radius_is_infinite_not_an_overflow():
    arm = planar_two_link()
    radii, _ = force_ellipsoid(arm, [0.5, 0.0])   # stretched: it cannot move along the arm
    assert radii[0] == math.inf and radii[1] == math.inf and np.isfinite(radii[2])


def test_static_torques_by_virtual_work(chain):
    """τ = Jᵀ[f; μ]: for a force, the derivative of the work f·p(q); with a moment, the columns of
    the finite-difference Jacobian."""
    rng = np.random.default_rng(3)
    for q in chain.random_configurations(4, seed=4):
        force, moment = rng.normal(size=3), rng.normal(size=3)
        h = 1e-6
        work = [(force @ chain.fk(q + h * e)[:3, 3] - force @ chain.fk(q - h * e)[:3, 3]) / (2 * h)
                for e in np.eye(chain.n)]
        assert np.allclose(static_torques(chain, q, np.r_[force, 0, 0, 0]), work, atol=1e-7)
        expected = pose_jacobian(chain, q).T @ np.r_[force, moment]
        assert np.allclose(chain.static_torques(q, np.r_[force, moment]), expected, atol=1e-7)


def test_ur10_holds_a_five_kilogram_tool():
    """The load's weight is held by an upward force: wrench [-m g; 0]; the base joint, about the
    vertical, needs no torque, and the torques equal the work of lifting the tool."""
    arm = ur10()
    q = np.deg2rad([30, -60, 80, -110, -90, 0])
    g = np.array([0.0, 0.0, -9.81])
    tau = arm.static_torques(q, np.r_[-5.0 * g, 0, 0, 0])
    assert abs(tau[0]) < 1e-12
    h = 1e-6
    lift = [(5.0 * 9.81) * (arm.fk(q + h * e)[2, 3] - arm.fk(q - h * e)[2, 3]) / (2 * h) for e in np.eye(6)]
    assert np.allclose(tau, lift, atol=1e-6)


def test_batches_equal_single_calls(chain):
    q = chain.random_configurations(3, seed=5)
    wrenches = np.random.default_rng(6).normal(size=(3, 6))
    radii, axes = velocity_ellipsoid(chain, q)
    force_radii, force_axes = force_ellipsoid(chain, q, "orientation")
    tau = static_torques(chain, q, wrenches)
    assert radii.shape == (3, 3) and axes.shape == (3, 3, 3) and tau.shape == (3, chain.n)
    for k in range(3):
        single_radii, single_axes = velocity_ellipsoid(chain, q[k])
        assert np.allclose(radii[k], single_radii, atol=1e-15) and np.allclose(axes[k], single_axes, atol=1e-15)
        assert np.allclose(force_ellipsoid(chain, q[k], "orientation")[0], force_radii[k], rtol=1e-15)
        assert np.allclose(static_torques(chain, q[k], wrenches[k]), tau[k], atol=1e-15)
    assert static_torques(chain, q, wrenches[0]).shape == (3, chain.n)   # one wrench for every row


def test_bad_arguments_are_named():
    arm = ur10()
    with pytest.raises(ShapeError, match=r"wrench must have shape \(6,\); got shape \(3,\)"):
        arm.static_torques(np.zeros(6), np.zeros(3))
    with pytest.raises(ShapeError, match=r"wrench must have shape \(6,\) or \(2, 6\); got shape \(3, 6\)"):
        arm.static_torques(np.zeros((2, 6)), np.zeros((3, 6)))
    with pytest.raises(ValueError, match="part"):
        arm.velocity_ellipsoid(np.zeros(6), part="translation")
