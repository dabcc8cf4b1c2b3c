"""Tests of the chapter-3 exercise checks (robokin.check.three_rpr).

The correct answers are written independently of the package: the exercise's loop
equations written out, the inverse Jacobian by central differences of them, the
forward kinematics by a Newton iteration on the loop equations from a nearby pose.
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest

chk = importlib.import_module("robokin.check.three_rpr")
S3 = math.sqrt(3.0) / 2.0


def ik_by_hand(x, y, phi):
    return np.array([
        math.hypot(x, y),
        math.hypot(x + math.cos(phi) - 1.0, y + math.sin(phi)),
        math.hypot(x + math.cos(phi + math.pi / 3) - 0.5, y + math.sin(phi + math.pi / 3) - S3),
    ])


def jacobian_fd(pose):
    pose = np.asarray(pose, dtype=float)
    h = 1e-7
    return np.column_stack([(ik_by_hand(*(pose + h * e)) - ik_by_hand(*(pose - h * e))) / (2 * h)
                            for e in np.eye(3)])


def fk_newton(rho, start=(0.35, 0.3, 0.7)):
    x = np.array(start, dtype=float)
    for _ in range(50):
        g = ik_by_hand(*x) - rho
        x = x - np.linalg.solve(jacobian_fd(x), g)
    return x


# ---------------------------------------------------------------- correct answers
def test_correct_answers_pass():
    for check, answer in ((chk.inverse_kinematics, ik_by_hand), (chk.inverse_jacobian, jacobian_fd)):
        r = check(answer, quiet=True)
        assert r.passed and r.diagnosis is None, r.message
        assert r.samples == 20
    r = chk.forward_kinematics(fk_newton, quiet=True)
    assert r.passed, r.message


def test_ik_accepts_vector_call_style(capsys):
    chk.inverse_kinematics(lambda pose: ik_by_hand(*pose))
    assert capsys.readouterr().out == "✔ ik(pose) is correct (checked at 20 random poses).\n"


def test_fk_all_modes_are_counted(capsys):
    from robokin.models.three_rpr import three_rpr

    robot = three_rpr()
    chk.forward_kinematics(lambda rho: robot.forward_kinematics(rho).poses)
    out = capsys.readouterr().out
    assert out.startswith("✔ fk(rho) is correct") and "you returned 40 of the 40" in " ".join(out.split())


# ---------------------------------------------------------------- diagnosed mistakes
def _centre_ik(x, y, phi):
    c = np.array([0.5, S3 / 3])                     # pose taken as that of the centroid
    R = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
    b = np.array([[0, 0], [1, 0], [0.5, S3]]) - c
    A = np.array([[0, 0], [1, 0], [0.5, S3]])
    return np.linalg.norm(np.array([x, y]) + b @ R.T - A, axis=1)


WRONG_IK = {
    "squared": lambda x, y, phi: ik_by_hand(x, y, phi) ** 2,
    "rotation_transposed": lambda x, y, phi: ik_by_hand(x, y, -phi),
    "reference_point": _centre_ik,
    "degrees_input": lambda x, y, phi: ik_by_hand(x, y, math.radians(phi)),
    "platform_not_rotated": lambda x, y, phi: ik_by_hand(x, y, 0.0),
}


@pytest.mark.parametrize("code", list(WRONG_IK))
def test_ik_mistakes_are_diagnosed(code):
    r = chk.inverse_kinematics(WRONG_IK[code], quiet=True)
    assert not r.passed
    assert r.diagnosis == code, r.message


def test_ik_unknown_mistake_is_a_mismatch():
    r = chk.inverse_kinematics(lambda x, y, phi: ik_by_hand(x, y, phi) + [0.0, 0.01, 0.0], quiet=True)
    assert not r.passed and r.diagnosis == "mismatch" and "entry [2]" in r.message


def _unnormalised(pose):
    return jacobian_fd(pose) * ik_by_hand(*pose)[:, None]


def _arm_origin(pose):
    x, y, _ = pose
    A = jacobian_fd(pose)
    A[:, 2] += x * A[:, 1] - y * A[:, 0]       # (B − P) × n + P × n = B × n
    return A


WRONG_JAC = {
    "unnormalised": _unnormalised,
    "moment_arm": _arm_origin,
    "cross_order": lambda p: jacobian_fd(p) * [1, 1, -1],
    "direct_jacobian": lambda p: np.linalg.inv(jacobian_fd(p)),
    "transpose": lambda p: jacobian_fd(p).T,
}


@pytest.mark.parametrize("code", list(WRONG_JAC))
def test_jacobian_mistakes_are_diagnosed(code):
    r = chk.inverse_jacobian(WRONG_JAC[code], quiet=True)
    assert not r.passed
    assert r.diagnosis == code, r.message


def test_fk_mistakes_are_diagnosed():
    r = chk.forward_kinematics(lambda rho: fk_newton(rho) * [1, 1, 180 / math.pi], quiet=True)
    assert not r.passed and r.diagnosis == "degrees_output"
    r = chk.forward_kinematics(lambda rho: fk_newton(rho) + [0.0, 0.0, 0.05], quiet=True)
    assert not r.passed and r.diagnosis == "mismatch" and "must reproduce ρ" in r.message
    assert "assembly modes are" not in r.message   # they would answer modes0 at rho0

    def centre(rho):
        x, y, phi = fk_newton(rho)
        R = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
        return np.r_[np.array([x, y]) + R @ [0.5, S3 / 3], phi]

    r = chk.forward_kinematics(centre, quiet=True)
    assert not r.passed and r.diagnosis == "reference_point"


def _with_spurious_root(rho):
    """The modes and the root phi = 0 of the polynomial, its position by Cramer's rule."""
    from robokin.models.three_rpr import three_rpr

    E = np.array([1.0, 0.5 + 1j * S3]) * (np.exp(1e-9j) - 1.0)   # E_i = (z - 1) a_i, z near 1
    r = rho[1:] ** 2 - rho[0] ** 2 - np.abs(E) ** 2
    w = (r[0] * E[1] - r[1] * E[0]) / (np.conj(E[0]) * E[1] - E[0] * np.conj(E[1]))
    return np.vstack([[w.real, w.imag, 1e-9], three_rpr().forward_kinematics(rho).poses])


def test_fk_spurious_root_is_named():
    """A root where the subtracted loop equations are singular (D = 0, here phi = 0) kept as
    a mode: its position, Cramer's rule at D near 0, is far off or not finite."""
    r = chk.forward_kinematics(_with_spurious_root, quiet=True)
    assert not r.passed and r.diagnosis == "spurious_root", r.message
    assert "D vanishes" in r.message and "(row 1)" in r.message
    r = chk.forward_kinematics(lambda rho: np.vstack([[np.nan, np.nan, 0.0], fk_newton(rho)]), quiet=True)
    assert not r.passed and r.diagnosis == "spurious_root", r.message
    # a pose at phi = 0 that is one (equal legs: B1 anywhere on the circle |p| = rho) passes
    assert chk.check_poses([0.3, 0.4, 0.0], [0.5, 0.5, 0.5], quiet=True).passed
    # NaN in a pose at another orientation stays an error
    r = chk.forward_kinematics(lambda rho: [np.nan, 0.0, 0.5], quiet=True)
    assert r.diagnosis == "error"


def twin_by_hand(pose):
    """The twin from the loop equations written out: B1' = -R(phi)^T B1, orientation -phi."""
    x, y, phi = pose
    return np.array([-(math.cos(phi) * x + math.sin(phi) * y), math.sin(phi) * x - math.cos(phi) * y,
                     -phi])


def test_twin_pose_correct_in_any_angle_range():
    from robokin.models.three_rpr import three_rpr

    robot = three_rpr()
    poses = np.random.default_rng(1).uniform([-0.5, -0.5, -3.0], [1.0, 1.0, 3.0], (30, 3))
    twins = np.array([twin_by_hand(p) for p in poses])
    assert np.allclose(robot.inverse_kinematics(twins), robot.inverse_kinematics(poses), atol=1e-12)
    for answer in (twin_by_hand, lambda p: twin_by_hand(p) + [0.0, 0.0, 2 * math.pi]):
        r = chk.twin_pose(answer, quiet=True)
        assert r.passed and r.diagnosis is None, r.message


WRONG_TWIN = {
    "mirror_image": lambda p: np.array([p[0], -p[1], -p[2]]),
    "orientation_only": lambda p: np.array([p[0], p[1], -p[2]]),
    "rotation_transposed": lambda p: twin_by_hand(np.array([p[0], p[1], -p[2]])) * [1, 1, -1],
    "sign": lambda p: twin_by_hand(p) * [-1, -1, 1],
}


@pytest.mark.parametrize("code", list(WRONG_TWIN))
def test_twin_pose_mistakes_are_diagnosed(code):
    r = chk.twin_pose(WRONG_TWIN[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_twin_pose_other_answers():
    assert chk.twin_pose(lambda p: p, quiet=True).diagnosis == "mismatch"
    assert chk.twin_pose(lambda p: -p, quiet=True).diagnosis == "mismatch"
    assert chk.twin_pose(lambda p: p[:2], quiet=True).diagnosis == "shape"
    assert chk.twin_pose(None, quiet=True).diagnosis == "error"


def cramer_by_hand(phi, rho, robot):
    """(N, Delta) of Cramer's rule for the pair (w, conj w), written out."""
    a = robot.base_anchors @ [1.0, 1j]
    b = robot.platform_anchors @ [1.0, 1j]
    E2, E3 = np.exp(1j * phi) * (b[1:] - b[0]) - (a[1:] - a[0])
    r2, r3 = rho[1:] ** 2 - rho[0] ** 2 - np.abs([E2, E3]) ** 2
    return r2 * E3 - r3 * E2, np.conj(E2) * E3 - E2 * np.conj(E3)


def test_cramer_parts_correct_with_any_common_factor():
    from robokin.models.three_rpr import CLASSIC_RHO, three_rpr_classic

    robot = three_rpr_classic()
    for mode in robot.forward_kinematics(CLASSIC_RHO).poses:   # N / Delta is B1 - A1 at every mode
        N, Delta = cramer_by_hand(mode[2], CLASSIC_RHO, robot)
        u = robot.platform_points(mode)[0] - robot.base_anchors[0]
        assert abs(N / Delta - complex(*u)) < 1e-9
    for answer in (cramer_by_hand,
                   lambda phi, rho, robot: tuple(np.exp(2j * phi) * v for v in cramer_by_hand(phi, rho, robot))):
        r = chk.cramer_parts(answer, quiet=True)
        assert r.passed and r.diagnosis is None, r.message


def _cramer_without_norms(phi, rho, robot):
    a = robot.base_anchors @ [1.0, 1j]
    b = robot.platform_anchors @ [1.0, 1j]
    E2, E3 = np.exp(1j * phi) * (b[1:] - b[0]) - (a[1:] - a[0])
    r2, r3 = rho[1:] ** 2 - rho[0] ** 2
    return r2 * E3 - r3 * E2, np.conj(E2) * E3 - E2 * np.conj(E3)


WRONG_CRAMER = {
    "conjugate": lambda *args: tuple(np.conj(cramer_by_hand(*args))),
    "sign": lambda *args: (-cramer_by_hand(*args)[0], cramer_by_hand(*args)[1]),
    "reciprocal": lambda *args: cramer_by_hand(*args)[::-1],
    "missing_norms": _cramer_without_norms,
}


@pytest.mark.parametrize("code", list(WRONG_CRAMER))
def test_cramer_parts_mistakes_are_diagnosed(code):
    r = chk.cramer_parts(WRONG_CRAMER[code], quiet=True)
    assert not r.passed and r.diagnosis == code, r.message


def test_cramer_parts_other_answers():
    def no_conjugates(phi, rho, robot):
        N, _ = cramer_by_hand(phi, rho, robot)
        a = robot.base_anchors @ [1.0, 1j]
        b = robot.platform_anchors @ [1.0, 1j]
        E2, E3 = np.exp(1j * phi) * (b[1:] - b[0]) - (a[1:] - a[0])
        return N, E2 * E3

    r = chk.cramer_parts(no_conjugates, quiet=True)
    assert r.diagnosis == "mismatch" and "solves the two subtracted loop equations" in r.message
    assert chk.cramer_parts(lambda phi, rho, robot: 3.0, quiet=True).diagnosis == "shape"
    assert chk.cramer_parts(lambda phi, rho, robot: (1.0, 0.0), quiet=True).diagnosis == "error"


def _no_roots(phi, rho, robot=None):
    return 1.0  # a wrong orientation equation: no root anywhere


def fk_through(rho, robot=None, F=_no_roots):
    """One assembly mode when the orientation equation ``F`` has a root, none otherwise."""
    values = [F(phi, rho, robot) for phi in np.linspace(-math.pi, math.pi, 181)]
    return fk_newton(rho) if min(values) < 0 < max(values) else np.zeros((0, 3))


def test_fk_is_judged_with_robokins_orientation_function():
    # my_fk(rho, robot, F=F_of_phi): the check passes robokin's F, so that a wrong F_of_phi (the
    # default) is not blamed on the forward kinematics, in the check or in the grading report
    assert chk.forward_kinematics(fk_through, quiet=True).passed
    assert chk.forward_kinematics(lambda rho: fk_through(rho), quiet=True).diagnosis == "missing"


def test_fk_bad_answers():
    assert chk.forward_kinematics(np.zeros(3), quiet=True).diagnosis == "constant"
    assert chk.forward_kinematics(lambda rho: None, quiet=True).diagnosis == "error"
    assert chk.forward_kinematics(lambda rho: [1.0, 2.0], quiet=True).diagnosis == "shape"
    assert chk.forward_kinematics(lambda rho: 1 / 0, quiet=True).diagnosis == "error"
    assert chk.forward_kinematics(lambda rho: np.zeros((0, 3)), quiet=True).diagnosis == "missing"
    with pytest.raises(AssertionError):
        chk.forward_kinematics(lambda rho: [np.nan, 0, 0], quiet=True, raise_on_fail=True)


def test_check_poses(capsys):
    from robokin.models.three_rpr import three_rpr

    robot = three_rpr()
    rho = np.array([0.5, 0.6, 0.4])
    modes = robot.forward_kinematics(rho).poses
    assert chk.check_poses(modes, rho).passed
    assert chk.check_poses(modes[0], rho).passed
    assert not chk.check_poses(modes[0] + 0.01, rho, quiet=True).passed
    assert chk.check_poses(np.zeros((0, 3)), [0.1, 0.1, 3.0], quiet=True).passed    # no mode exists
    out = capsys.readouterr().out
    assert out.count("✔") == 2


def test_an_unexplained_wrong_jacobian_gets_a_direction_not_the_answer():
    """The hint of an answer that no diagnosis explains says how to derive A, not its rows
    (the Try it yourself cell would otherwise hand out Task 3's closed form)."""
    result = chk.inverse_jacobian(lambda pose: np.eye(3) + pose[0], quiet=True)
    assert result.diagnosis == "mismatch"
    assert "differentiate ρ_i" in result.message
    assert "×" not in result.message and "n_i" not in result.message


# ---------------------------------------------------------------- the robot of the graded tests
def test_robot_without_solvers_withholds_only_its_task():
    from robokin.parallel import Planar3RPR

    base, platform = np.array([[0.0, 0.0], [1.2, 0.1], [0.4, 0.9]]), np.array([[0.0, 0.0], [0.5, 0.0], [0.1, 0.3]])
    robot = chk.RobotWithoutSolvers(base, platform, chk.WITHHELD["forward_kinematics"])
    reference = Planar3RPR(base, platform)
    pose = np.array([0.3, 0.2, 0.5])
    assert np.allclose(robot.inverse_kinematics(pose), reference.inverse_kinematics(pose))
    assert np.allclose(robot.base_anchors, base) and np.allclose(robot.platform_anchors, platform)
    for name in chk.WITHHELD["forward_kinematics"]:
        with pytest.raises(AttributeError, match=f"has no {name}: the test grades your own derivation"):
            getattr(robot, name)
    with pytest.raises(AttributeError):
        assert robot._model_of_another_name is None   # private names are not looked up in the model


def test_robot_without_solvers_crosses_the_bridge():
    """The grading bridge rebuilds it in the student's kernel from its fields, solvers withheld."""
    codec = pytest.importorskip("tools.grading.bridge.codec")
    robot = chk.RobotWithoutSolvers(np.eye(3, 2), np.eye(3, 2)[::-1], chk.WITHHELD["inverse_jacobian"])
    copy = codec.decode(json_round_trip(codec.encode(robot)))
    assert type(copy) is chk.RobotWithoutSolvers and copy.withheld == robot.withheld
    assert np.array_equal(copy.base_anchors, robot.base_anchors)
    with pytest.raises(AttributeError, match="has no jacobian"):
        copy.jacobian(np.zeros(3))


def json_round_trip(data):
    import json

    return json.loads(json.dumps(data))


# ---------------------------------------------------------------- the orientation polynomial
def sextic_by_hand(mistake=""):
    """(1 + t^2)^3 F of the exercise's robot written out with sympy (steps 1-2 of the chapter)."""
    sp = pytest.importorskip("sympy")
    t = sp.symbols("t", real=True)
    r1, r2, r3 = sp.symbols("rho1:4", positive=True)
    c, s = (1 - t**2) / (1 + t**2), 2 * t / (1 + t**2)
    if mistake == "swapped_substitution":
        c, s = s, c
    th = sp.pi / 3
    sign = -1 if mistake == "addition_sign" else 1
    ct, st = c * sp.cos(th) - sign * s * sp.sin(th), s * sp.cos(th) + sign * c * sp.sin(th)
    c3, d3 = sp.Rational(1, 2), sp.sqrt(3) / 2
    al2, be2, ga2 = 2 * (c - 1), 2 * s, 2 - 2 * c
    al3, be3 = 2 * (ct - c3), 2 * (st - d3)
    ga3 = 2 - 2 * (c3 * ct + d3 * st)
    first = 0 if mistake == "rho1_left_in_a" else r1**2
    a2, a3 = r2**2 - first - ga2, r3**2 - first - ga3
    D = al2 * be3 - be2 * al3
    last = {"rho1_term_sign": -1, "rho1_term_missing": 0}.get(mistake, 1)
    F = (be3 * a2 - be2 * a3) ** 2 + (al2 * a3 - al3 * a2) ** 2 - last * r1**2 * D**2
    return sp.Poly(sp.expand(sp.cancel(F * (1 + t**2) ** 3)), t), t


def test_orientation_polynomial_correct_with_any_factor():
    poly, t = sextic_by_hand()
    assert chk.orientation_polynomial(poly, quiet=True).passed
    assert chk.orientation_polynomial(poly * -3, quiet=True).passed


@pytest.mark.parametrize("code", ["addition_sign", "swapped_substitution", "rho1_left_in_a", "rho1_term_sign",
                                  "rho1_term_missing"])
def test_orientation_polynomial_mistakes_are_named(code):
    poly, _ = sextic_by_hand(code)
    result = chk.orientation_polynomial(poly, quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_orientation_polynomial_degree_and_divided_factor():
    sp = pytest.importorskip("sympy")
    poly, t = sextic_by_hand()
    high = chk.orientation_polynomial(sp.Poly(poly.as_expr() * (1 + t**2), t), quiet=True)
    assert high.diagnosis == "degree" and "degree 8" in high.message
    low = chk.orientation_polynomial(sp.Poly(sp.cancel(poly.as_expr() / t**2), t), quiet=True)
    assert low.diagnosis == "factor_divided"
    other = chk.orientation_polynomial(sp.Poly(poly.as_expr() + t**2, t), quiet=True)
    assert other.diagnosis == "mismatch" and "does not vanish" in other.message


def test_orientation_polynomial_other_answers():
    sp = pytest.importorskip("sympy")
    t, x = sp.symbols("t x")
    assert chk.orientation_polynomial(None, quiet=True).diagnosis == "error"
    assert "sympy Poly" in chk.orientation_polynomial(t**2, quiet=True).message
    assert "symbols x" in chk.orientation_polynomial(sp.Poly(x * t**2, t), quiet=True).message


# ---------------------------------------------------------------- the orientation equation
def F_by_hand(phi, rho, robot, mistake=""):
    """(D x)^2 + (D y)^2 - rho1^2 D^2 from the subtracted loop equations, with a typical slip."""
    a, b = robot.base_anchors, robot.platform_anchors
    c, s = math.cos(phi), math.sin(phi)
    e = (b[1:] - b[0]) @ np.array([[c, -s], [s, c]]).T - (a[1:] - a[0])
    M, r = 2 * e, rho[1:] ** 2 - rho[0] ** 2 - np.sum(e**2, axis=1)
    D = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    Dx, Dy = M[1, 1] * r[0] - M[0, 1] * r[1], M[0, 0] * r[1] - M[1, 0] * r[0]
    last = {"rho1_term_sign": -D**2, "determinant_missing": 1.0, "determinant_not_squared": D}.get(mistake, D**2)
    return Dx**2 + Dy**2 - rho[0] ** 2 * last


def test_orientation_function_correct_with_any_factor():
    assert chk.orientation_function(F_by_hand, quiet=True).passed
    assert chk.orientation_function(lambda p, r, robot: -0.25 * F_by_hand(p, r, robot), quiet=True).passed


@pytest.mark.parametrize("code", ["rho1_term_sign", "determinant_missing", "determinant_not_squared"])
def test_orientation_function_mistakes_are_named(code):
    result = chk.orientation_function(lambda p, r, robot: F_by_hand(p, r, robot, code), quiet=True)
    assert not result.passed and result.diagnosis == code, result.message


def test_orientation_function_angle_readings_and_delegation():
    degrees = chk.orientation_function(lambda p, r, robot: F_by_hand(math.radians(p), r, robot), quiet=True)
    assert degrees.diagnosis == "degrees"
    halved = chk.orientation_function(lambda p, r, robot: F_by_hand(p / 2, r, robot), quiet=True)
    assert halved.diagnosis == "half_angle"
    other = chk.orientation_function(lambda p, r, robot: F_by_hand(p, r, robot) + 1.0, quiet=True)
    assert other.diagnosis == "mismatch"

    def delegating(phi, rho, robot):
        t = math.tan(phi / 2)
        return np.polyval(robot.orientation_polynomial(rho)[::-1], t) / (1 + t**2) ** 3

    result = chk.orientation_function(delegating, quiet=True)
    assert result.diagnosis == "error" and "has no orientation_polynomial" in result.message


def test_reference_orientation_function_vanishes_at_the_modes():
    from robokin.models.three_rpr import CLASSIC_RHO, three_rpr_classic

    classic = three_rpr_classic()
    modes = classic.forward_kinematics(CLASSIC_RHO).poses
    values = [chk.reference_orientation_function(phi, CLASSIC_RHO, classic) for phi in modes[:, 2]]
    scale = max(abs(chk.reference_orientation_function(phi, CLASSIC_RHO, classic)) for phi in (-2.0, 0.5, 2.0))
    assert np.abs(values).max() < 1e-12 * scale
    # the same function as one written by hand, up to its factor
    phis = np.linspace(-3.0, 3.0, 7)
    mine = np.array([F_by_hand(phi, CLASSIC_RHO, classic) for phi in phis])
    ref = np.array([chk.reference_orientation_function(phi, CLASSIC_RHO, classic) for phi in phis])
    assert abs(mine @ ref) > (1 - 1e-12) * np.linalg.norm(mine) * np.linalg.norm(ref)
    with pytest.raises(TypeError):
        chk.reference_orientation_function(0.3, CLASSIC_RHO, "robot")


@pytest.mark.parametrize("name, answer", [
    ("inverse_kinematics", lambda pose: np.zeros(3)),
    ("inverse_jacobian", lambda pose: np.eye(3)),
    ("inverse_jacobian", lambda pose: jacobian_fd(pose).T),
    ("inverse_jacobian", lambda pose: np.linalg.inv(jacobian_fd(pose))),
    ("orientation_function", lambda phi, rho, robot: math.cos(phi)),
])
def test_messages_state_no_closed_form(name, answer):
    """A dummy or a typical wrong answer is told the mistake and the principle, not the closed
    form of the task: not the leg-length formula, not the rows of A, not F = (D x)² + (D y)² − ρ1² D²,
    and F's example is no mode of the classic robot at CLASSIC_RHO (those are modes6)."""
    message = getattr(chk, name)(answer, quiet=True).message
    for closed_form in ("‖p + R(φ) b_i", "((B_i − P) × n_i)_z", "[n_iᵀ", "(D x)²", "ρ1² D²",
                        "[1.498, 1.538, 1.2]"):
        assert closed_form not in message, message


def test_check_poses_does_not_list_the_modes_it_was_asked_about():
    """check_poses(wrong, rho0) would otherwise print every mode at rho0: modes0 of Task 2."""
    from robokin.models.three_rpr import three_rpr

    rho0 = three_rpr().inverse_kinematics([0.3, 0.2, 0.4])
    for wrong in ([0.1, 0.1, 0.5], np.zeros((0, 3))):
        r = chk.check_poses(wrong, rho0, quiet=True)
        assert not r.passed and "0.3, 0.2, 0.4" not in r.message and "4 assembly" not in r.message, r.message
