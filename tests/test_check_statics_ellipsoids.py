"""Tests of the chapter-9 exercise checks (robokin.check.statics_ellipsoids).

The correct answers are written independently of the package: the two-link arm's Jacobian
by central differences of its tool position written out, the ellipses by an eigen-
decomposition of J Jᵀ (NumPy's ``eigh``), the measures from their definitions.
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

chk = importlib.import_module("robokin.check.statics_ellipsoids")
L1, L2 = chk.LINKS


def tool_position(q):
    q1, q2 = q
    return np.array([L1 * math.cos(q1) + L2 * math.cos(q1 + q2), L1 * math.sin(q1) + L2 * math.sin(q1 + q2)])


def jacobian_fd(q):
    q = np.asarray(q, dtype=float)
    h = 1e-7
    return np.column_stack([(tool_position(q + h * e) - tool_position(q - h * e)) / (2 * h) for e in np.eye(2)])


def foot_height(q):
    """z of chapter 1's foot in the body's frame (unit lengths), written out."""
    alpha, beta, gamma = q
    return -math.cos(alpha) * (1 + math.cos(beta) + math.cos(beta + gamma))


def leg_by_energy(q, m):
    """The gradient of the body's potential energy −m g z_F(q), by central differences."""
    q = np.asarray(q, dtype=float)
    h = 1e-7
    return np.array([-m * chk.GRAVITY * (foot_height(q + h * e) - foot_height(q - h * e)) / (2 * h)
                     for e in np.eye(3)])


def velocity_by_eigh(J):
    values, vectors = np.linalg.eigh(J @ J.T)
    return np.sqrt(values[::-1]), vectors[:, ::-1]


def force_by_eigh(J):
    values, vectors = np.linalg.eigh(J @ J.T)
    return 1 / np.sqrt(values), vectors


CORRECT = {
    "tool_jacobian": jacobian_fd,
    "joint_torques": lambda q, F: jacobian_fd(q).T @ F,
    "leg_torques": leg_by_energy,
    "velocity_ellipse": velocity_by_eigh,
    "force_ellipse": force_by_eigh,
    "force_from_velocity": lambda radii_v, axes_v: (1 / radii_v[::-1], axes_v[:, ::-1]),
    "manipulability": lambda J: math.sqrt(np.linalg.det(J @ J.T)),
    "w_formula": lambda q2, l1, l2: abs(l1 * l2 * math.sin(q2)),
    "condition_number": lambda J: np.linalg.cond(J),
    "push_capacity": lambda J, d: 1 / np.linalg.norm(J.T @ d),
    "posture_measures": lambda J: (math.sqrt(np.linalg.det(J @ J.T)), np.linalg.cond(J),
                                   math.sqrt(np.linalg.eigvalsh(J @ J.T)[0])),
}


@pytest.mark.parametrize("name", list(CORRECT))
def test_correct_answers_pass(name):
    r = getattr(chk, name)(CORRECT[name], quiet=True)
    assert r.passed and r.diagnosis is None, r.message
    assert r.samples == 20


def test_ellipse_axes_of_either_sign_pass():
    flipped = lambda J: (velocity_by_eigh(J)[0], -velocity_by_eigh(J)[1])  # noqa: E731
    assert chk.velocity_ellipse(flipped, quiet=True).passed
    svd = lambda J: np.linalg.svd(J)[1::-1]  # noqa: E731 - (sigma, U)
    assert chk.velocity_ellipse(svd, quiet=True).passed


def test_pass_message(capsys):
    chk.velocity_ellipse(velocity_by_eigh)
    assert capsys.readouterr().out == "✔ velocity_ellipse is correct (checked at 20 random Jacobians of the arm).\n"


WRONG = [
    ("tool_jacobian", lambda q: jacobian_fd(q).T, "transpose"),
    ("joint_torques", lambda q, F: jacobian_fd(q) @ F, "jacobian_not_transposed"),
    ("joint_torques", lambda q, F: -jacobian_fd(q).T @ F, "sign"),
    ("joint_torques", lambda q, F: jacobian_fd(np.deg2rad(q)).T @ F, "degrees_input"),
    ("leg_torques", lambda q, m: -leg_by_energy(q, m), "sign"),
    ("leg_torques", lambda q, m: leg_by_energy(q, m) / chk.GRAVITY, "no_gravity"),
    ("leg_torques", lambda q, m: leg_by_energy(np.rad2deg(q), m), "degrees_evaluated"),
    ("velocity_ellipse", lambda J: (velocity_by_eigh(J)[0] ** 2, velocity_by_eigh(J)[1]), "squared"),
    ("velocity_ellipse", lambda J: (np.sqrt(np.linalg.eigh(J @ J.T)[0]), np.linalg.eigh(J @ J.T)[1]),
     "ascending"),
    ("velocity_ellipse", lambda J: np.linalg.eigh(J @ J.T), "squared"),
    # eigh's eigenvalues sorted descending, its eigenvectors left in eigh's order
    ("velocity_ellipse", lambda J: (np.sqrt(np.linalg.eigh(J @ J.T)[0])[::-1], np.linalg.eigh(J @ J.T)[1]),
     "axes_not_reordered"),
    ("velocity_ellipse", lambda J: velocity_by_eigh(J.T), "jacobian_not_transposed"),
    ("velocity_ellipse", lambda J: force_by_eigh(J), "inverted"),
    ("force_ellipse", velocity_by_eigh, "not_inverted"),
    ("force_ellipse", lambda J: (velocity_by_eigh(J)[0][::-1], force_by_eigh(J)[1]), "not_inverted"),
    ("force_ellipse", lambda J: (force_by_eigh(J)[0] ** 2, force_by_eigh(J)[1]), "squared"),
    ("force_ellipse", lambda J: (force_by_eigh(J)[0][::-1], force_by_eigh(J)[1][:, ::-1]), "ascending"),
    ("force_ellipse", lambda J: force_by_eigh(J.T), "jacobian_not_transposed"),
    ("force_ellipse", lambda J: (force_by_eigh(J)[0], force_by_eigh(J)[1][:, ::-1]), "axes_not_reordered"),
    ("force_ellipse", lambda J: (force_by_eigh(J)[0][::-1], force_by_eigh(J)[1]), "axes_not_reordered"),
    ("force_from_velocity", lambda r, a: (r, a), "not_inverted"),
    ("force_from_velocity", lambda r, a: (r[::-1], a[:, ::-1]), "not_inverted"),
    ("force_from_velocity", lambda r, a: (1 / r, a), "ascending"),
    ("force_from_velocity", lambda r, a: (1 / r[::-1], a), "axes_not_reordered"),
    ("force_from_velocity", lambda r, a: (1 / r, a[:, ::-1]), "axes_not_reordered"),
    ("force_from_velocity", lambda r, a: (1 / r[::-1] ** 2, a[:, ::-1]), "squared"),
    ("manipulability", lambda J: np.linalg.det(J @ J.T), "squared"),
    ("w_formula", lambda q2, l1, l2: l1 * l2 * math.sin(q2), "absolute_value"),
    ("w_formula", lambda q2, l1, l2: (l1 * l2 * math.sin(q2)) ** 2, "squared"),
    ("w_formula", lambda q2, l1, l2: abs(l1 * l2 * math.sin(math.radians(q2))), "degrees_input"),
    ("condition_number", lambda J: np.linalg.cond(J) ** 2, "squared"),
    ("condition_number", lambda J: 1 / np.linalg.cond(J), "inverted"),
    ("push_capacity", lambda J, d: np.linalg.norm(J.T @ d), "not_inverted"),
    ("push_capacity", lambda J, d: 1 / np.linalg.norm(J @ d), "jacobian_not_transposed"),
    ("push_capacity", lambda J, d: 1 / np.linalg.norm(J.T @ d) ** 2, "squared"),
    ("posture_measures", lambda J: (np.linalg.det(J @ J.T), np.linalg.cond(J) ** 2,
                                    np.linalg.eigvalsh(J @ J.T)[0]), "squared"),
    ("posture_measures", lambda J: (abs(np.linalg.det(J)), 1 / np.linalg.cond(J),
                                    np.linalg.svd(J, compute_uv=False)[-1]), "inverted"),
    ("posture_measures", lambda J: (abs(np.linalg.det(J)), np.linalg.cond(J), np.linalg.norm(J, 2)),
     "sigma_max"),
]


@pytest.mark.parametrize(("name", "answer", "code"), WRONG, ids=[f"{n}-{c}" for n, _, c in WRONG])
def test_mistakes_are_diagnosed(name, answer, code):
    r = getattr(chk, name)(answer, quiet=True)
    assert not r.passed
    assert r.diagnosis == code, r.message


def test_manipulability_sign_is_diagnosed_where_det_is_negative():
    r = chk.manipulability(lambda J: np.linalg.det(J), quiet=True)
    # the sampled elbow angles are positive (det J > 0): the signed determinant is right there
    assert r.passed


def test_ellipse_answers_of_the_wrong_form():
    r = chk.velocity_ellipse(lambda J: velocity_by_eigh(J)[0], quiet=True)
    assert not r.passed and r.diagnosis == "shape" and "pair (radii, axes)" in r.message
    r = chk.force_ellipse(lambda J: (np.ones(3), np.eye(3)), quiet=True)
    assert not r.passed and r.diagnosis == "shape" and "(2,)" in r.message
    r = chk.velocity_ellipse(lambda J: 1 / 0, quiet=True)
    assert not r.passed and r.diagnosis == "error"
    r = chk.velocity_ellipse(None, quiet=True)
    assert not r.passed
    r = chk.force_ellipse(np.eye(2), quiet=True)
    assert not r.passed and "function" in r.message
    r = chk.force_from_velocity(lambda J: force_by_eigh(J), quiet=True)  # given J, not the ellipse
    assert not r.passed and r.diagnosis == "error" and "force_from_velocity" in r.message
    r = chk.force_from_velocity(lambda r, a: r, quiet=True)
    assert not r.passed and r.diagnosis == "shape" and "pair (radii, axes)" in r.message


def test_unknown_mistake_is_a_mismatch():
    r = chk.joint_torques(lambda q, F: jacobian_fd(q).T @ F + [0.0, 0.1], quiet=True)
    assert not r.passed and r.diagnosis == "mismatch"
    r = chk.push_capacity(lambda J, d: 1.1 / np.linalg.norm(J.T @ d), quiet=True)
    assert not r.passed and r.diagnosis == "mismatch"


def test_raise_on_fail():
    with pytest.raises(AssertionError):
        chk.condition_number(lambda J: 1.0, quiet=True, raise_on_fail=True)


def test_delegation_names_robokin_functions():
    from robokin.chains import ellipsoids

    for check, references in chk.DELEGATION.items():
        assert hasattr(chk, check)
        for attribute in references:
            if attribute.startswith("reference_"):  # the steps the later tests pass in
                assert references[attribute] == f"robokin.check.statics_ellipsoids.{attribute}"
                assert callable(getattr(chk, attribute))
            else:
                assert hasattr(ellipsoids, attribute) or attribute in (
                    "position_jacobian", "jacobian", "planar_two_link")


def test_leg_torques_j_instead_of_transpose_is_named():
    from robokin.models import eth_leg

    leg = eth_leg()
    r = chk.leg_torques(lambda q, m: leg.position_jacobian(q) @ [0.0, 0.0, -m * chk.GRAVITY], quiet=True)
    assert not r.passed and r.diagnosis == "jacobian_not_transposed", r.message


def test_leg_torques_mass_arrives_as_a_number():
    seen = []

    def answer(q, m):
        seen.append(m)
        return leg_by_energy(q, m)

    assert chk.leg_torques(answer, quiet=True).passed
    assert all(isinstance(m, float) for m in seen)


def eigh_ellipse(J):
    """The velocity ellipse by NumPy's eigh of J Jᵀ, radii descending."""
    values, vectors = np.linalg.eigh(J @ J.T)
    return np.sqrt(values[::-1]), vectors[:, ::-1]


def test_references_pass_their_checks():
    """robokin's steps that the later tests pass to the student's functions are right."""
    assert chk.tool_jacobian(chk.reference_tool_jacobian, quiet=True).passed
    assert chk.velocity_ellipse(chk.reference_velocity_ellipse, quiet=True).passed
    assert chk.posture_measures(chk.reference_posture_measures, quiet=True).passed


@pytest.mark.parametrize("seed", range(5))
def test_references_agree_with_independent_answers(seed):
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, 2)
    assert np.allclose(chk.reference_tool_jacobian(q), jacobian_fd(q), atol=1e-7)
    J = rng.normal(size=(3, 6))
    radii, axes = chk.reference_velocity_ellipse(J)
    radii_e, axes_e = eigh_ellipse(J)
    assert np.allclose(radii, radii_e) and np.allclose(np.abs(axes.T @ axes_e), np.eye(3), atol=1e-8)
    w, kappa, sigma_min = chk.reference_posture_measures(J)
    assert np.isclose(w, np.sqrt(np.linalg.det(J @ J.T)))
    assert np.isclose(kappa, radii_e[0] / radii_e[-1]) and np.isclose(sigma_min, radii_e[-1])


def test_reference_steps_reject_a_tall_jacobian():
    from robokin.errors import ShapeError

    with pytest.raises(ShapeError):
        chk.reference_velocity_ellipse(np.ones((3, 2)))
    with pytest.raises(ShapeError):
        chk.reference_posture_measures(np.ones(3))
    assert chk.reference_posture_measures(np.diag([2.0, 0.0]))[1] == math.inf
