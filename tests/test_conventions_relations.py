"""The relations between robokin's geometric Jacobian and Lynch and Park's space and body
Jacobians, which the conventions page (book/conventions.md, "Velocities, twists and Jacobians")
leaves to chapter 8's Tasks 4-5, checked numerically on the UR10.

robokin: J = [J_v; J_ω], v = ṗ the velocity of the end-effector origin, ω the angular
velocity, both in the base frame B.

Lynch and Park (2017, §5.1): space twist V_s = [ω_s; v_s] with [V_s] = Ṫ T⁻¹, so ω_s = ω and
v_s = ṗ − ω × p (the velocity of the body point at B's origin); body twist V_b = [ω_b; v_b]
with [V_b] = T⁻¹ Ṫ, so ω_b = Rᵀ ω and v_b = Rᵀ ṗ. Hence

    [J_v; J_ω] = [[−[p]×, I], [I, 0]] J_s = blkdiag(R, R) S J_b,   S = [[0, I], [I, 0]].

J_s and J_b are built here without robokin's Jacobian: by finite differences of the forward
kinematics (Ṫ T⁻¹ and T⁻¹ Ṫ), and J_s a second time from the screw axes of the product of
exponentials (L&P §5.1.1) with the home screw axes read off the forward kinematics at q = 0.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from robokin import models

I3, Z3 = np.eye(3), np.zeros((3, 3))
SWAP = np.block([[Z3, I3], [I3, Z3]])  # S: [ω; v] <-> [v; ω]
H = 1e-6


def skew(p: np.ndarray) -> np.ndarray:
    """[p]×, the 3×3 matrix with [p]× x = p × x (written out, not robokin's)."""
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def vee(X: np.ndarray) -> np.ndarray:
    """[ω; v] of a 4×4 twist matrix [[ω]×, v; 0, 0] (L&P order)."""
    return np.r_[X[2, 1], X[0, 2], X[1, 0], X[:3, 3]]


def hat(V: np.ndarray) -> np.ndarray:
    """The 4×4 matrix [V] of a twist V = [ω; v] (L&P order)."""
    X = np.zeros((4, 4))
    X[:3, :3], X[:3, 3] = skew(V[:3]), V[3:]
    return X


def adjoint(T: np.ndarray) -> np.ndarray:
    """Ad_T for twists [ω; v] (L&P §3.3.2)."""
    R, p = T[:3, :3], T[:3, 3]
    return np.block([[R, Z3], [skew(p) @ R, R]])


def fk_derivatives(chain, q):
    """∂T/∂q_i by central differences, shape (n, 4, 4)."""
    out = []
    for i in range(len(q)):
        dq = np.zeros(len(q))
        dq[i] = H
        out.append((chain.fk(q + dq) - chain.fk(q - dq)) / (2 * H))
    return np.array(out)


def space_jacobian_fd(chain, q):
    """L&P's space Jacobian J_s (6×n, [ω_s; v_s]) from [V_s] = Ṫ T⁻¹."""
    T_inv = np.linalg.inv(chain.fk(q))
    return np.column_stack([vee(dT @ T_inv) for dT in fk_derivatives(chain, q)])


def body_jacobian_fd(chain, q):
    """L&P's body Jacobian J_b (6×n, [ω_b; v_b]) from [V_b] = T⁻¹ Ṫ."""
    T_inv = np.linalg.inv(chain.fk(q))
    return np.column_stack([vee(T_inv @ dT) for dT in fk_derivatives(chain, q)])


def space_jacobian_poe(home_screws, q):
    """J_s from the product of exponentials: column i = Ad(e^[S_1]q_1 ··· e^[S_(i-1)]q_(i-1)) S_i."""
    T = np.eye(4)
    columns = []
    for S, qi in zip(home_screws.T, q):
        columns.append(adjoint(T) @ S)
        T = T @ expm(hat(S) * qi)
    return np.column_stack(columns)


@pytest.fixture(scope="module")
def ur10():
    return models.ur10()


@pytest.fixture(scope="module")
def configurations(ur10):
    return ur10.random_configurations(10, seed=7)


def test_product_of_exponentials_reproduces_the_forward_kinematics(ur10, configurations):
    home_screws = space_jacobian_fd(ur10, np.zeros(ur10.n))  # J_s(0) = [S_1 ... S_n]
    M = ur10.fk(np.zeros(ur10.n))
    assert np.allclose(np.linalg.norm(home_screws[:3], axis=0), 1.0, atol=1e-8)  # revolute
    for q in configurations:
        T = np.eye(4)
        for S, qi in zip(home_screws.T, q):
            T = T @ expm(hat(S) * qi)
        assert np.allclose(T @ M, ur10.fk(q), atol=1e-8)
        assert np.allclose(space_jacobian_poe(home_screws, q), space_jacobian_fd(ur10, q), atol=1e-7)


def test_space_jacobian_relation(ur10, configurations):
    home_screws = space_jacobian_fd(ur10, np.zeros(ur10.n))
    for q in configurations:
        p = ur10.fk(q)[:3, 3]
        J_s = space_jacobian_poe(home_screws, q)
        to_robokin = np.block([[-skew(p), I3], [I3, Z3]])
        assert np.allclose(ur10.jacobian(q), to_robokin @ J_s, atol=1e-8)
        # the linear rows of J_s are the velocity of the body point at B's origin, not ṗ
        assert np.allclose(J_s[3:], ur10.jacobian(q)[:3] - np.cross(J_s[:3].T, p).T, atol=1e-8)
        assert not np.allclose(J_s[3:], ur10.jacobian(q)[:3], atol=1e-3)
        # and back: J_s = [[0, I], [I, [p]×]] J
        assert np.allclose(np.linalg.inv(to_robokin), np.block([[Z3, I3], [I3, skew(p)]]))


def test_body_jacobian_relation(ur10, configurations):
    for q in configurations:
        R = ur10.fk(q)[:3, :3]
        J_b = body_jacobian_fd(ur10, q)
        assert np.allclose(ur10.jacobian(q), np.block([[R, Z3], [Z3, R]]) @ SWAP @ J_b, atol=1e-7)
        # the swap alone is not enough: J_b is expressed in the end-effector frame
        assert not np.allclose(ur10.jacobian(q), SWAP @ J_b, atol=1e-3)


def test_body_and_space_jacobians_differ_by_the_adjoint(ur10, configurations):
    """L&P §5.1.4, J_s = Ad_T J_b: ties the two finite-difference Jacobians together."""
    for q in configurations:
        assert np.allclose(space_jacobian_fd(ur10, q), adjoint(ur10.fk(q)) @ body_jacobian_fd(ur10, q), atol=1e-7)
