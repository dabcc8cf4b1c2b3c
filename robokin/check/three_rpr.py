r"""Exercise checks of chapter 3: kinematics of the planar 3-RPR parallel robot.

References come from :func:`robokin.models.three_rpr.three_rpr` (the exercise's robot:
unit equilateral base and platform, pose ``(x, y, φ)`` of the platform vertex
:math:`B_1` and of the side :math:`B_1B_2`), or from the robot passed as ``robot=``.

==========================  ===============================================  ============================
check                       the student's answer                             compared with
==========================  ===============================================  ============================
``inverse_kinematics``      function ``ik(pose)`` or ``ik(x, y, phi)`` ->      ``robot.inverse_kinematics``
                            leg lengths ρ (3,)                               at 20 random poses
``forward_kinematics``      function ``fk(rho)`` -> one pose (3,) or           the assembly modes of
                            several (k, 3)                                   ``robot.forward_kinematics``
``inverse_jacobian``        function ``A(pose)`` -> 3×3 with ρ̇ = A ẋ          ``robot.jacobian``
``twin_pose``               function ``twin_pose(pose)`` -> the pose at −φ   its closed form, at 20
                            with the same leg lengths (3,)                   random poses (φ mod 2π)
``orientation_polynomial``  ``poly_t``, a sympy Poly in t over rho1..rho3     ``robot.orientation_polynomial``
                                                                             (any constant factor)
``orientation_function``    function ``F_of_phi(phi, rho, robot)`` -> F(φ)   its pieces from the subtracted
                                                                             loop equations, on three
                                                                             robots (any constant factor)
==========================  ===============================================  ============================

The graded tests pass the student's functions a :class:`RobotWithoutSolvers`, a robot of their own
whose solvers of the task under test (:data:`WITHHELD`) are missing: a derivation from the anchors
runs on it, a function that hands the task back to robokin raises.

A forward-kinematics answer is accepted when every pose it returns is one of the
assembly modes (a pose whose leg lengths are ρ); any one mode is enough. A function with the
keyword parameter ``F`` (``my_fk(rho, robot=robot, F=F_of_phi)``) is called with robokin's
:func:`reference_orientation_function` in its place, so that the verdict (and the grading
report's) is on the forward kinematics alone, not on a mistake in ``F_of_phi``.

Usage::

    from robokin.check import three_rpr as check_3rpr
    check_3rpr.inverse_kinematics(my_ik)
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import (
    FAIL,
    PASS,
    Check,
    CheckResult,
    FunctionCheck,
    Variable,
    alternatives,
    fmt,
    report,
    with_reference_steps,
)
from robokin.check._registry import exercise
from robokin.errors import DomainError
from robokin.validation import as_scalar, as_vector, check_positive

__all__ = [
    "RobotWithoutSolvers", "WITHHELD", "check_poses", "cramer_parts", "forward_kinematics", "inverse_jacobian",
    "inverse_kinematics", "orientation_function", "orientation_polynomial", "reference_orientation_function",
    "twin_pose",
]

_CHAPTER = "three_rpr"

#: check -> {the robokin method that solves its task: how the grading report names it}: an
#: answer that hands one back is flagged for review by hand (tools/grading/bridge/delegation.py
#: reads this literal table without importing the module; its own table lists the other checks)
DELEGATION = {
    "orientation_function": {"orientation_polynomial": "Planar3RPR.orientation_polynomial",
                             "orientation_harmonics": "Planar3RPR.orientation_harmonics",
                             "forward_kinematics": "Planar3RPR.forward_kinematics",
                             "reference_orientation_function":
                                 "robokin.check.three_rpr.reference_orientation_function"},
    "twin_pose": {"forward_kinematics": "Planar3RPR.forward_kinematics"},
}


@lru_cache(maxsize=1)
def _robot():
    from robokin.models.three_rpr import three_rpr

    return three_rpr()


# Poses of the exercise robot away from its singularities (φ = 0 is singular for the
# congruent platform: all legs parallel) and from zero-length legs.
_POSE = [
    Variable("x", "length", 0.15, 0.6),
    Variable("y", "length", 0.1, 0.55),
    Variable("phi", "angle", 0.3, 1.2, aliases=("φ", "theta")),
]
_GROUP = [("pose", [0, 1, 2])]


def _rot(phi: float) -> np.ndarray:
    c, s = math.cos(phi), math.sin(phi)
    return np.array([[c, -s], [s, c]])


def _legs(x: np.ndarray, *, rotate: Callable[[float], np.ndarray] = _rot, centroid: bool = False):
    """Leg vectors B_i − A_i of the exercise robot with optional mistakes."""
    r = _robot()
    b = r.platform_anchors
    if centroid:                       # the pose is taken as that of the platform centroid
        b = b - b.mean(axis=0)
    B = x[:2] + (rotate(float(x[2])) @ b.T).T
    return B - r.base_anchors, B


# ------------------------------------------------------------------ inverse kinematics
def _inverse_kinematics_reference(x: np.ndarray) -> np.ndarray:
    return _robot().inverse_kinematics(x)


def _inverse_kinematics_mistakes():
    def squared(x):
        return _inverse_kinematics_reference(x) ** 2

    def unrotated(x):
        return np.linalg.norm(_legs(x, rotate=lambda p: np.eye(2))[0], axis=1)

    def transposed(x):
        return np.linalg.norm(_legs(x, rotate=lambda p: _rot(-p))[0], axis=1)

    def centroid(x):
        return np.linalg.norm(_legs(x, centroid=True)[0], axis=1)

    return [
        alternatives("squared", [(squared, (
            "{name} returns the squared leg lengths ρ_i²: take the square root, "
            "ρ_i = ‖B_i − A_i‖."
        ))]),
        alternatives("platform_not_rotated", [(unrotated, (
            "{name} ignores the platform's orientation: the anchors must be rotated, "
            "B_i = p + R(φ) b_i, before the base anchor is subtracted."
        ))]),
        alternatives("rotation_transposed", [(transposed, (
            "{name} rotates the platform by −φ: R(φ) = [[cos φ, −sin φ], [sin φ, cos φ]] "
            "(R(φ)ᵀ turns the other way)."
        ))]),
        alternatives("reference_point", [(centroid, (
            "{name} treats (x, y) as the centre of the platform; in this exercise (x, y) is the "
            "vertex B1 (ρ1 = √(x² + y²))."
        ))]),
        dg.degrees(),
    ]


inverse_kinematics = exercise(_CHAPTER, "inverse_kinematics", Check(
    name="ik(pose)",
    reference=_inverse_kinematics_reference,
    variables=_POSE,
    groups=_GROUP,
    diagnoses=_inverse_kinematics_mistakes(),
    noun="poses",
    hint=("ρ_i is the distance from the base anchor A_i to the platform anchor B_i, with B_i from the "
          "pose as the problem statement's Parameterisation writes it."),
    doc="Check a function ik(pose) (or ik(x, y, phi)) -> leg lengths (ρ1, ρ2, ρ3) of the exercise robot.",
))


# ------------------------------------------------------------------ inverse Jacobian
def _jacobian_reference(x: np.ndarray) -> np.ndarray:
    return _robot().jacobian(x)


def _jacobian_mistakes():
    def unnormalised(x):
        d, B = _legs(x)
        arm = B - x[:2]
        return np.column_stack([d, arm[:, 0] * d[:, 1] - arm[:, 1] * d[:, 0]])

    def arm_from_origin(x):
        d, B = _legs(x)
        n = d / np.linalg.norm(d, axis=1)[:, None]
        return np.column_stack([n, B[:, 0] * n[:, 1] - B[:, 1] * n[:, 0]])

    def arm_from_base_anchor(x):
        A = _jacobian_reference(x).copy()
        A[:, 2] = 0.0      # (B_i − A_i) × n_i = 0: the moment arm taken from the base anchor
        return A

    def direct(x):
        return np.linalg.inv(_jacobian_reference(x))

    def flipped(x):
        A = _jacobian_reference(x).copy()
        A[:, 2] = -A[:, 2]
        return A

    return [
        alternatives("unnormalised", [(unnormalised, (
            "{name} uses the leg vectors B_i − A_i instead of the unit vectors n_i: that matrix "
            "gives ρ_i ρ̇_i, not ρ̇_i. Divide row i by ρ_i."
        ))]),
        alternatives("moment_arm", [
            (arm_from_origin, (
                "the last column of {name} uses the moment arm from the base origin: the moment "
                "must be taken about the point whose velocity (ẋ, ẏ) is, the platform's reference "
                "point P = B1."
            )),
            (arm_from_base_anchor, (
                "the last column of {name} is zero: the moment arm was taken from the base anchor "
                "A_i (B_i − A_i is parallel to n_i); take it from the point whose velocity (ẋ, ẏ) "
                "is, the platform's reference point P = B1."
            )),
        ]),
        alternatives("cross_order", [(flipped, (
            "the last column of {name} has the wrong sign: check the order of the two factors of "
            "the cross product (the moment of n_i about P, with the arm from P to B_i)."
        ))]),
        alternatives("direct_jacobian", [(direct, (
            "{name} is the direct Jacobian A⁻¹ (ẋ = A⁻¹ ρ̇); the question asks for the inverse "
            "Jacobian A with ρ̇ = A ẋ."
        ))]),
        alternatives("transpose", [(lambda x: _jacobian_reference(x).T, (
            "{name} is transposed: row i belongs to leg i, so that ρ̇_i = row_i · [ẋ, ẏ, φ̇]."
        ))]),
        dg.degrees(),
    ]


inverse_jacobian = exercise(_CHAPTER, "inverse_jacobian", Check(
    name="A(pose)",
    reference=_jacobian_reference,
    variables=_POSE,
    groups=_GROUP,
    diagnoses=_jacobian_mistakes(),
    noun="poses",
    hint=("Row i gives ρ̇_i: differentiate ρ_i = ‖B_i − A_i‖ along the platform motion (ẋ, ẏ, φ̇), "
          "with (x, y) the point B1 and the platform turning about it."),
    doc="Check a function A(pose) -> 3×3 inverse Jacobian of the exercise robot (ρ̇ = A ẋ).",
))


# ------------------------------------------------------------------ the twin pose
def _twin_reference(pose: np.ndarray) -> np.ndarray:
    """The pose with the orientation −φ and the leg lengths of ``pose`` (the exercise's robot).

    The platform is congruent to the base, E_i = (z − 1) a_i with z = e^{iφ}; at z̄ the same
    equations hold for w' = −z̄ w: (x', y') = −R(φ)ᵀ(x, y).
    """
    return np.r_[-(_rot(pose[2]).T @ pose[:2]), -pose[2]]


def _twin_mistakes() -> list[tuple[str, Callable[[np.ndarray], np.ndarray], str]]:
    return [
        ("mirror_image", lambda p: np.array([p[0], -p[1], -p[2]]), (
            "{name} returns (x, −y, −φ), the pose mirrored in the x axis: A_1, A_2 and b_1, b_2 "
            "lie on that axis, so ρ1 and ρ2 keep their values, but A_3 and b_3 do not, and ρ3 "
            "changes. Subtract the loop equations at −φ and solve them for the position.")),
        ("orientation_only", lambda p: np.array([p[0], p[1], -p[2]]), (
            "{name} keeps the position (x, y) and negates φ only: with B1 in place, turning the "
            "platform changes ρ2 and ρ3. The position of the twin moves too.")),
        ("rotation_transposed", lambda p: np.r_[-(_rot(p[2]) @ p[:2]), -p[2]], (
            "{name} rotates the position by +φ where the twin needs the opposite turn: R(φ) "
            "and R(φ)ᵀ = R(−φ) differ.")),
        ("sign", lambda p: np.r_[_rot(p[2]).T @ p[:2], -p[2]], (
            "{name} has the position with the wrong sign: its leg lengths differ from the "
            "pose's. Check the sign with a pose of your own and the inverse kinematics.")),
    ]


class _TwinPoseCheck(FunctionCheck):
    """Check a function ``twin_pose(pose)`` -> the pose (3,) at −φ with the same leg lengths."""

    def judge(self, answer: Any) -> CheckResult:
        X = self.sample_points()
        n = len(X)
        got = []
        for x in X:
            out = self.call(answer, (x.copy(),), samples=n)
            try:
                out = np.array(out, dtype=float)
            except (TypeError, ValueError):
                return self.failure("error", f"{self.name} must return numbers (x, y, φ); got "
                                             f"{type(out).__name__}.", n)
            if out.shape != (3,):
                return self.failure("shape", f"{self.name} must return a pose (x, y, φ) of shape "
                                             f"(3,); got shape {out.shape}.", n)
            got.append(out)
        S = np.array(got)
        if not np.all(np.isfinite(S)):
            return self.failure("error", f"{self.name} gives NaN or infinite values.", n)

        def same(P: np.ndarray, Q: np.ndarray) -> bool:
            turn = np.angle(np.exp(1j * (P[:, 2] - Q[:, 2])))
            return bool(np.allclose(P[:, :2], Q[:, :2], atol=1e-8) and np.abs(turn).max() < 1e-8)

        R = np.array([_twin_reference(x) for x in X])
        if same(S, R):
            return self.success(f"{self.name} is correct (checked at {n} random poses).", n)
        for code, mistake, message in _twin_mistakes():
            if same(S, np.array([mistake(x) for x in X])):
                return self.failure(code, message.format(name=self.name), n)
        robot = _robot()
        k = int(np.argmax(np.abs(S - R).max(axis=1)))
        if abs(np.angle(np.exp(1j * (S[k, 2] + X[k, 2])))) > 1e-8:
            return self.failure("mismatch", f"{self.name}({fmt(X[k])}) = {fmt(S[k])} does not have "
                                            f"the orientation −φ = {fmt(-X[k, 2])} rad.", n)
        return self.failure("mismatch", (
            f"{self.name}({fmt(X[k])}) = {fmt(S[k])}: its leg lengths are "
            f"{fmt(robot.inverse_kinematics(S[k]))}, the pose's are "
            f"{fmt(robot.inverse_kinematics(X[k]))}. The twin has the same three leg lengths."), n)


twin_pose = exercise(_CHAPTER, "twin_pose", _TwinPoseCheck(
    name="twin_pose(pose)",
    signature="twin_pose(pose) -> pose",
    variables=_POSE,
    groups=_GROUP,
    noun="poses",
    doc=("Check a function twin_pose(pose) -> the pose (3,) of the exercise robot with the "
         "orientation −φ and the same leg lengths."),
))


# ------------------------------------------------------------------ Cramer's rule for w
def _position_w(robot, phi: float, rho: np.ndarray, *, with_norms: bool = True) -> complex:
    """w = B1 − A1 (a complex number) from the two subtracted loop equations at phi.

    2 e_i · u = ρ_i² − ρ1² − |e_i|², e_i = R(φ)(b_i − b_1) − (A_i − A_1), i = 2, 3, solved as a
    real 2×2 system; ``with_norms=False`` leaves out the |e_i|² (a typical mistake).
    """
    a, b = robot.base_anchors, robot.platform_anchors
    e = (b[1:] - b[0]) @ _rot(phi).T - (a[1:] - a[0])
    r = rho[1:] ** 2 - rho[0] ** 2 - (np.sum(e**2, axis=1) if with_norms else 0.0)
    u = np.linalg.solve(2.0 * e, r)
    return complex(u[0], u[1])


class _CramerCheck(FunctionCheck):
    """Check ``cramer_parts(phi, rho, robot)`` -> (N, Δ) with N/Δ = w = B1 − A1."""

    def cases(self) -> list[tuple[Any, float, np.ndarray]]:
        """(robot, φ, ρ): the classic robot and the exercise's, at seeded random φ and ρ."""
        from robokin.models.three_rpr import CLASSIC_RHO, three_rpr_classic

        rng = np.random.default_rng(self.seed)
        out = []
        for robot, rho in ((three_rpr_classic(), CLASSIC_RHO), (_robot(), np.array([0.5, 0.7, 0.6]))):
            for phi in rng.uniform(0.3, 2.8, self.samples // 2) * rng.choice([-1.0, 1.0], self.samples // 2):
                out.append((robot, float(phi), rho * rng.uniform(0.8, 1.2, 3)))
        return out

    def judge(self, answer: Any) -> CheckResult:
        cases = self.cases()
        n = len(cases)
        got, ref = [], []
        for robot, phi, rho in cases:
            out = self.call(answer, (phi, rho.copy(), robot), samples=n)
            try:
                N, Delta = (complex(v) for v in out)
            except (TypeError, ValueError):
                return self.failure("shape", f"{self.name} must return two complex numbers (N, Δ); got "
                                             f"{type(out).__name__}.", n)
            if Delta == 0 or not np.isfinite(N / Delta):
                return self.failure("error", f"{self.name} at φ = {fmt(phi)} rad gives N/Δ = {N}/{Delta}, "
                                             "not a finite number.", n)
            got.append(N / Delta)
            ref.append(_position_w(robot, phi, rho))
        S, R = np.array(got), np.array(ref)
        scale = max(1.0, float(np.abs(R).max()))

        def same(values: np.ndarray) -> bool:
            return bool(np.abs(S - values).max() <= 1e-9 * scale)

        if same(R):
            return self.success(f"{self.name} is correct: N/Δ is B1 − A1 (checked at {n} random "
                                "orientations and leg lengths, on two robots).", n)
        mistakes = [
            ("conjugate", np.conj(R), (
                "N/Δ of {name} is the conjugate of w: Cramer's rule solved for w̄, not w (the "
                "columns of the pair (w, w̄) exchanged).")),
            ("sign", -R, (
                "N/Δ of {name} is −w: a sign is wrong, in N or in Δ (the order of the two products "
                "of Cramer's rule).")),
            ("reciprocal", 1.0 / R, "{name} returns (Δ, N): N/Δ is 1/w. N is the numerator."),
            ("missing_norms", np.array([_position_w(robot, phi, rho, with_norms=False)
                                        for robot, phi, rho in cases]), (
                "N/Δ of {name} solves the subtracted loop equations without the terms |E_i|² on "
                "their right-hand sides: expand the squares of the loop equations again.")),
        ]
        for code, values, message in mistakes:
            if same(values):
                return self.failure(code, message.format(name=self.name), n)
        k = int(np.argmax(np.abs(S - R)))
        robot, phi, rho = cases[k]
        return self.failure("mismatch", (
            f"N/Δ of {self.name} at φ = {fmt(phi)} rad, ρ = {fmt(rho)} ({robot.name}) is "
            f"{fmt(np.array([S[k].real, S[k].imag]))} as (x, y); the position of B1 − A1 that solves "
            f"the two subtracted loop equations is {fmt(np.array([R[k].real, R[k].imag]))}."), n)


cramer_parts = exercise(_CHAPTER, "cramer_parts", _CramerCheck(
    name="cramer_parts(phi, rho, robot)",
    signature="cramer_parts(phi, rho, robot) -> (N, Delta)",
    samples=20,
    noun="orientations",
    doc=("Check a function cramer_parts(phi, rho, robot) -> (N, Δ), complex, with N/Δ the "
         "position w of B1 relative to A1 that solves the subtracted loop equations."),
))


# ------------------------------------------------------------------ forward kinematics
def check_poses(poses: Any, rho: Any, robot: Any = None, *, name: str = "pose", tol: float = 1e-6,
                quiet: bool = False, raise_on_fail: bool = False) -> CheckResult:
    """Check that each row of ``poses`` (3,) or (k, 3) is an assembly mode for the leg lengths ``rho``.

    A pose is accepted when its leg lengths match ``rho`` within ``tol`` metres.

    Parameters
    ----------
    poses : array_like, shape (3,) or (k, 3)
        Platform poses ``(x [m], y [m], φ [rad])``.
    rho : array_like, shape (3,)
        Leg lengths, m.
    robot : Planar3RPR, optional
        The robot (default the chapter's).
    name : str, optional
        Name of the answer, for the message.
    tol : float, optional
        Allowed leg-length error, m.
    quiet, raise_on_fail : bool, optional
        Print nothing; raise ``AssertionError`` on failure.

    Returns
    -------
    CheckResult
    """
    from robokin.parallel import Planar3RPR

    if robot is None:
        robot = _robot()
    elif not isinstance(robot, Planar3RPR):
        raise TypeError(f"robot must be a robokin.parallel.Planar3RPR (e.g. robokin.models.three_rpr()); "
                        f"got {type(robot).__name__}")
    rho = as_vector(rho, 3, "rho")
    if (rho < 0).any():
        raise DomainError(f"rho must be non-negative leg lengths; got {rho.tolist()}")
    tol = check_positive(tol, "tol", scalar=True)
    return report(_judge(poses, rho, robot, name, tol), raise_on_fail=raise_on_fail, quiet=quiet)


def _subtracted_determinant(robot, phi: float) -> float:
    """Determinant of the two subtracted loop equations in u = B1 − A1 at the orientation phi.

    Subtracting the first loop equation from the others leaves 2 e_i · u = ρ_i² − ρ1² − |e_i|²
    (i = 2, 3) with e_i = R(φ)(b_i − b_1) − (A_i − A_1): linear in u, with the matrix rows
    2 e_i, whatever the leg lengths.
    """
    a, b = robot.base_anchors, robot.platform_anchors
    e = (b[1:] - b[0]) @ _rot(phi).T - (a[1:] - a[0])
    return float(4.0 * (e[0, 0] * e[1, 1] - e[0, 1] * e[1, 0]))


def _spurious_root(P: np.ndarray, robot) -> int | None:
    """The first row of P whose orientation makes the subtracted loop equations singular.

    There Cramer's rule divides by D = 0: a root of the orientation polynomial that
    Cramer's rule, not the robot, produced (for the exercise's robot φ = 0, where D has
    the factor t²). None when no row's φ is such an orientation.
    """
    scale = robot.characteristic_length ** 2
    for k, phi in enumerate(P[:, 2]):
        if np.isfinite(phi) and abs(_subtracted_determinant(robot, float(phi))) <= 1e-6 * scale:
            return k
    return None


def _spurious_message(name: str, P: np.ndarray, k: int) -> str:
    where = f" (row {k + 1})" if P.shape[0] > 1 else ""
    return (f"{name}{where} = {fmt(P[k])} is not an assembly mode: at its orientation φ = "
            f"{fmt(P[k, 2])} rad the two subtracted loop equations cannot be solved for x, y (their "
            "determinant D vanishes): a position from Cramer's rule divides by D ≈ 0 there. Where "
            "D = 0 a root of the orientation equation can come from the elimination, not from the "
            "robot: skip such roots, and check every pose with the inverse kinematics.")


def _judge(poses: Any, rho: np.ndarray, robot, name: str, tol: float, n: int = 1) -> CheckResult:
    def fail(code: str, msg: str) -> CheckResult:
        return CheckResult(name, False, f"{FAIL} {msg}", code, n)
    if poses is None:
        return fail("error", f"{name} is None: did you forget to return it?")
    try:
        P = np.asarray(poses)
        if P.dtype.kind == "c":
            return fail("error", f"{name} has complex entries; expected real numbers (x, y, φ).")
        P = np.array(P, dtype=float)
    except (TypeError, ValueError):
        return fail("error", f"{name} must be numbers (x, y, φ); got {type(poses).__name__}.")
    if P.ndim == 1:
        P = P[None]
    if P.ndim != 2 or P.shape[1] != 3:
        return fail("shape", f"{name} must be a pose (x, y, φ) of shape (3,) or several, (k, 3); "
                             f"got shape {np.shape(poses)}.")
    if P.shape[0] == 0:
        modes = robot.forward_kinematics(rho).poses
        if modes.shape[0] == 0:
            return CheckResult(name, True, f"{PASS} {name}: correct, ρ = {fmt(rho)} has no assembly mode.",
                               None, n)
        return fail("missing", f"{name} is empty, but ρ = {fmt(rho)} has assembly modes.")
    spurious = _spurious_root(P, robot)
    if spurious is not None and not np.all(np.isfinite(P[spurious])):
        return fail("spurious_root", _spurious_message(name, P, spurious))
    if not np.all(np.isfinite(P)):
        return fail("error", f"{name} contains NaN or infinite values.")
    try:
        got = robot.inverse_kinematics(P)
    except DomainError as exc:  # a pose near 1e308 m
        return fail("error", f"{name} cannot be evaluated: {exc}.")
    bad = np.abs(got - rho).max(axis=1) > tol
    if not bad.any():
        what = "it is an assembly mode" if P.shape[0] == 1 else f"all {P.shape[0]} poses are assembly modes"
        return CheckResult(name, True, f"{PASS} {name} is correct: {what} for ρ = {fmt(rho)}.",
                           None, n)
    k = int(np.argmax(bad))
    pose = P[k]
    deg = np.array([pose[0], pose[1], math.radians(pose[2])])
    if np.abs(robot.inverse_kinematics(deg) - rho).max() <= tol:
        return fail("degrees_output", f"{name} has φ in degrees: φ = {fmt(pose[2])}° = "
                                      f"{fmt(deg[2])} rad is an assembly mode. robokin works in radians.")
    b = robot.platform_anchors
    ref_pt = pose.copy()
    ref_pt[:2] = pose[:2] - _rot(pose[2]) @ b.mean(axis=0) + _rot(pose[2]) @ b[0]
    if np.abs(robot.inverse_kinematics(ref_pt) - rho).max() <= tol:
        return fail("reference_point", f"{name} gives the position of the platform centre; the pose "
                                       "of this exercise is that of the vertex B1 (ρ1 = ‖B1 − A1‖).")
    if spurious is not None and bad[spurious]:
        return fail("spurious_root", _spurious_message(name, P, spurious))
    where = f" (row {k + 1})" if P.shape[0] > 1 else ""
    return fail("mismatch", f"{name}{where} = {fmt(pose)} is not an assembly mode: its leg lengths are "
                            f"{fmt(got[k])}, not ρ = {fmt(rho)}. Every pose returned must reproduce ρ "
                            "through the inverse kinematics.")


class _ForwardKinematicsCheck(FunctionCheck):
    """Check a function ``fk(rho)`` -> one assembly mode (3,) or several (k, 3); a function with
    the keyword parameter ``F`` is given robokin's orientation equation there."""

    def evaluate(self, answer: Any) -> CheckResult:
        """:meth:`FunctionCheck.evaluate` of ``answer`` given robokin's
        :func:`reference_orientation_function` as ``F`` (when it takes one)."""
        if callable(answer) and not isinstance(answer, np.ndarray):
            answer = with_reference_steps(answer, {"F": reference_orientation_function})
        return super().evaluate(answer)

    def leg_lengths(self) -> np.ndarray:
        """The leg lengths (N, 3) at which the answer is tested (from seeded random poses)."""
        rng = np.random.default_rng(self.seed)
        lo = np.array([v.low for v in _POSE])
        hi = np.array([v.high for v in _POSE])
        return _robot().inverse_kinematics(lo + (hi - lo) * rng.random((self.samples, 3)))

    def judge(self, answer: Any) -> CheckResult:
        robot = _robot()
        R = self.leg_lengths()
        n = len(R)
        found = 0
        for rho in R:
            out = self.call(answer, (rho.copy(),), samples=n)
            res = _judge(out, rho, robot, self.name, 1e-6, n)
            if not res.passed:
                return CheckResult(self.name, False, res.message + f" (at ρ = {fmt(rho)})", res.diagnosis, n)
            found += np.atleast_2d(np.asarray(out, dtype=float)).shape[0]
        total = sum(robot.forward_kinematics(rho).count for rho in R)
        return self.success(f"{self.name} is correct (checked at {n} random leg lengths; you returned "
                            f"{found} of the {total} assembly modes).", n)


forward_kinematics = exercise(_CHAPTER, "forward_kinematics", _ForwardKinematicsCheck(
    name="fk(rho)",
    signature="fk(rho) -> pose",
    samples=10,
    noun="leg lengths",
    doc=("Check a function fk(rho) -> pose (3,) or poses (k, 3) of the exercise robot: "
         "every pose must reproduce the leg lengths (any assembly mode is accepted)."),
))


# ------------------------------------------------------------------ the robot of the graded tests
@dataclasses.dataclass(frozen=True, eq=False)
class RobotWithoutSolvers:
    """A 3-RPR robot whose solvers of one task are withheld: the robot the graded tests pass.

    A graded test of chapter 3 calls the student's function with ``robot=`` one of these, of
    anchors of its own. Everything of :class:`robokin.parallel.Planar3RPR` is there (the anchors,
    ``platform_points``, ``inverse_kinematics``, ...) except the methods named in ``withheld``,
    the ones that solve the task under test: a function that hands the task back to robokin
    raises, one derived from the anchors runs as on any robot. The bridge of the grading rebuilds
    it in the student's kernel from its three fields.

    Parameters
    ----------
    base_anchors, platform_anchors : array_like, shape (3, 2)
        The anchors A_i in the base frame and b_i in the platform frame, m.
    withheld : tuple of str
        Names of the ``Planar3RPR`` methods the robot does not have.

    Raises
    ------
    DomainError, ShapeError
        Anchors ``Planar3RPR`` refuses.
    """

    base_anchors: Any
    platform_anchors: Any
    withheld: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        from robokin.parallel import Planar3RPR

        model = Planar3RPR(self.base_anchors, self.platform_anchors, name="the test's robot")
        object.__setattr__(self, "base_anchors", model.base_anchors)
        object.__setattr__(self, "platform_anchors", model.platform_anchors)
        object.__setattr__(self, "withheld", tuple(str(name) for name in self.withheld))
        object.__setattr__(self, "_model", model)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        if name in self.withheld:
            raise AttributeError(
                f"the robot this test passes has no {name}: the test grades your own derivation "
                f"(from robot.base_anchors and robot.platform_anchors), not robokin's {name}; "
                "compare with robokin's outside your function")
        return getattr(self._model, name)


#: The methods of Planar3RPR that solve each task: a graded test's robot withholds them.
WITHHELD = {
    "inverse_kinematics": ("inverse_kinematics", "platform_points", "leg_vectors", "leg_angles"),
    "forward_kinematics": ("forward_kinematics", "orientation_polynomial", "orientation_harmonics"),
    "inverse_jacobian": ("jacobian", "direct_jacobian", "condition_number", "is_singular"),
}


# ------------------------------------------------------------------ the orientation polynomial
_T_DEN = np.array([1.0, 0.0, 1.0])   # 1 + t², ascending powers of t
_POLY = np.polynomial.polynomial


def _polynomial_variant(rho: np.ndarray, mistake: str = "") -> np.ndarray:
    """(1 + t²)⁴ F of the exercise's robot at leg lengths rho, ascending coefficients of t.

    Steps 1-2 of the chapter written with cos φ = (1 − t²)/(1 + t²), sin φ = 2t/(1 + t²), every
    quantity a numerator over 1 + t²; ``mistake`` names a typical slip made in them.
    """
    robot = _robot()
    A, b = robot.base_anchors, robot.platform_anchors
    c2, (c3, d3) = A[1, 0] - A[0, 0], A[2] - A[0]
    l2, l3 = np.linalg.norm(b[1] - b[0]), np.linalg.norm(b[2] - b[0])
    theta = math.atan2(*(b[2] - b[0])[::-1]) - math.atan2(*(b[1] - b[0])[::-1])
    den, mul = _T_DEN, _POLY.polymul
    cos_n, sin_n = np.array([1.0, 0.0, -1.0]), np.array([0.0, 2.0])
    if mistake == "swapped_substitution":
        cos_n, sin_n = sin_n, cos_n
    elif mistake == "half_sine":
        sin_n = np.array([0.0, 1.0])
    turn = -1.0 if mistake == "addition_sign" else 1.0
    cos_t = _POLY.polysub(cos_n * math.cos(theta), turn * sin_n * math.sin(theta))
    sin_t = _POLY.polyadd(sin_n * math.cos(theta), turn * cos_n * math.sin(theta))
    law = -1.0 if mistake == "law_of_cosines_sign" else 1.0
    alpha2, beta2 = 2 * _POLY.polysub(l2 * cos_n, c2 * den), 2 * l2 * sin_n
    gamma2 = _POLY.polysub((l2**2 + c2**2) * den, law * 2 * l2 * c2 * cos_n)
    alpha3 = 2 * _POLY.polysub(l3 * cos_t, c3 * den)
    beta3 = 2 * _POLY.polysub(l3 * sin_t, d3 * den)
    gamma3 = _POLY.polysub((l3**2 + c3**2 + d3**2) * den,
                           law * 2 * l3 * _POLY.polyadd(c3 * cos_t, d3 * sin_t))
    first = 0.0 if mistake == "rho1_left_in_a" else rho[0] ** 2
    a2 = _POLY.polysub((rho[1] ** 2 - first) * den, gamma2)
    a3 = _POLY.polysub((rho[2] ** 2 - first) * den, gamma3)
    num_x = _POLY.polysub(mul(beta3, a2), mul(beta2, a3))
    num_y = _POLY.polysub(mul(alpha2, a3), mul(alpha3, a2))
    det = _POLY.polysub(mul(alpha2, beta3), mul(beta2, alpha3))
    squares = _POLY.polyadd(mul(num_x, num_x), mul(num_y, num_y))
    rho1_term = {"": mul(det, det), "rho1_term_sign": -mul(det, det), "rho1_term_missing": np.zeros(1),
                 "determinant_not_squared": mul(det, mul(den, den))}.get(mistake, mul(det, det))
    return _POLY.polysub(squares, rho[0] ** 2 * rho1_term)


def _divided(coefficients: np.ndarray, divisor: np.ndarray) -> np.ndarray | None:
    """coefficients / divisor (ascending) when the division is exact, else None."""
    quotient, remainder = _POLY.polydiv(coefficients, divisor)
    scale = max(float(np.abs(coefficients).max()), 1e-300)
    return quotient if np.abs(remainder).max() <= 1e-9 * scale else None


def _proportional(a: np.ndarray, b: np.ndarray | None) -> bool:
    """True when the coefficient vectors a and b (ascending, any lengths) are parallel."""
    if b is None:
        return False
    n = max(len(a), len(b))
    a, b = np.pad(a, (0, n - len(a))), np.pad(b, (0, n - len(b)))
    na, nb = np.linalg.norm(a), np.linalg.norm(b)
    return bool(na > 0 and nb > 0 and abs(a @ b) >= (1 - 1e-9) * na * nb)


#: typical slips in the orientation polynomial: code -> (the computed variant's mistake, message)
_POLYNOMIAL_MISTAKES = [
    ("addition_sign", "{name} is the polynomial of cos(φ + θ) = cos φ cos θ + sin φ sin θ (and sin(φ + θ) "
                      "with the same sign slip): that is φ − θ. A sign in the addition formulas: "
                      "cos(φ + θ) = cos φ cos θ − sin φ sin θ, sin(φ + θ) = sin φ cos θ + cos φ sin θ."),
    ("law_of_cosines_sign", "{name} has a sign wrong in the cross terms 2 l_i (…) of the constant parts of the "
                            "subtracted equations: expand the squares of the loop equations again."),
    ("rho1_term_sign", "{name} has the sign of its ρ1² term reversed: move every term of the first loop "
                       "equation to one side before you clear the denominators."),
    ("rho1_term_missing", "{name} lacks its ρ1² term: the first loop equation has two sides, and both must "
                          "appear in F."),
    ("determinant_not_squared", "{name} multiplies the ρ1² side of the first loop equation by D where the "
                                "other side holds D²: clear the denominators of both sides by the same "
                                "factor."),
    ("rho1_left_in_a", "{name} forgets ρ1² in the subtracted equations: subtracting the first loop equation "
                       "from loop i removes x² + y² from one side and ρ1² from the other."),
    ("swapped_substitution", "{name} is the polynomial of cos φ = 2t/(1 + t²), sin φ = (1 − t²)/(1 + t²): a wrong "
                             "substitution (cos and sin swapped). With t = tan(φ/2), cos φ = (1 − t²)/(1 + t²) "
                             "and sin φ = 2t/(1 + t²)."),
    ("half_sine", "{name} is the polynomial of sin φ = t/(1 + t²): a wrong substitution (the factor 2 "
                  "missing). With t = tan(φ/2), sin φ = 2t/(1 + t²)."),
]


def _polynomial_coefficients(answer: Any, name: str) -> tuple[Callable[[np.ndarray], np.ndarray] | None, str]:
    """A function rho -> the ascending coefficients of the answer, or None and why not."""
    sympy = __import__("sympy")
    if answer is None:
        return None, f"{name} is None: did you forget to define it?"
    if not isinstance(answer, sympy.Poly):
        return None, (f"{name} must be a sympy Poly in t (sp.Poly(expression, t)); got "
                      f"{type(answer).__name__}.")
    if len(answer.gens) != 1:
        return None, f"{name} must be a polynomial in t alone; its generators are {answer.gens}."
    free = sorted(answer.free_symbols - set(answer.gens), key=lambda s: s.name)
    names = [s.name for s in free]
    if not set(names) <= {"rho1", "rho2", "rho3"}:
        return None, (f"{name} holds the symbols {', '.join(names)}; the leg lengths must be the symbols "
                      "rho1, rho2, rho3 and t the variable of the polynomial.")
    lookup = {s.name: s for s in free}
    symbols = [lookup.get(f"rho{i}", sympy.Symbol(f"rho{i}")) for i in (1, 2, 3)]
    try:
        fn = sympy.lambdify(symbols, answer.all_coeffs()[::-1], "numpy")
    except Exception as exc:  # noqa: BLE001 - a Poly sympy cannot turn into numbers
        return None, f"{name}'s coefficients cannot be evaluated: {type(exc).__name__}: {exc}"

    def coefficients(rho: np.ndarray) -> np.ndarray:
        return np.array([complex(c) for c in fn(*rho)], dtype=complex)

    return coefficients, ""


class _OrientationPolynomialCheck(FunctionCheck):
    """Check ``poly_t``: (1 + t²)³ F of the exercise's robot as a sympy Poly in t over rho1, rho2, rho3."""

    def evaluate(self, answer: Any) -> CheckResult:
        """The verdict on a sympy Poly (not a function: the base class's refusal is not used)."""
        return self.judge(answer)

    def leg_lengths(self) -> np.ndarray:
        """The leg lengths (N, 3) of seeded random poses of the exercise's robot."""
        rng = np.random.default_rng(self.seed)
        lo = np.array([v.low for v in _POSE])
        hi = np.array([v.high for v in _POSE])
        return _robot().inverse_kinematics(lo + (hi - lo) * rng.random((self.samples, 3)))

    def judge(self, answer: Any) -> CheckResult:
        R = self.leg_lengths()
        n = len(R)
        coefficients, why = _polynomial_coefficients(answer, self.name)
        if coefficients is None:
            return self.failure("error", why, n)
        try:
            S = [coefficients(rho) for rho in R]
        except Exception as exc:  # noqa: BLE001 - report the student's error
            return self.failure("error", f"{self.name}'s coefficients cannot be evaluated at leg lengths: "
                                         f"{type(exc).__name__}: {exc}", n)
        if any(not np.all(np.isfinite(s)) or np.abs(s.imag).max(initial=0) > 1e-9 * max(1.0, np.abs(s).max())
               for s in S):
            return self.failure("error", f"{self.name} has coefficients that are not finite real numbers.", n)
        S = [s.real for s in S]
        right = [_POLY.polydiv(_polynomial_variant(rho), _T_DEN)[0] for rho in R]  # exact: (1 + t²)³ F

        def all_match(variants: list) -> bool:
            return all(_proportional(s, v) for s, v in zip(S, variants))

        if all_match(right):
            return self.success(f"{self.name} is correct (checked at {n} random leg lengths).", n)
        degree = max(len(np.trim_zeros(s, "b")) - 1 for s in S)
        for k in (1, 2, 3):
            if all_match([_POLY.polymul(v, _POLY.polypow(_T_DEN, k)) for v in right]):
                return self.failure("degree", (
                    f"{self.name} has degree {degree}: it is (1 + t²)^{3 + k} F. poly_t is (1 + t²)³ F, "
                    "as the statement defines it: multiply by (1 + t²)³."), n)
        if all_match([_divided(v, np.array([0.0, 0.0, 1.0])) for v in right]):
            return self.failure("factor_divided", (
                f"{self.name} is (1 + t²)³ F divided by a factor t²: poly_t keeps every factor of "
                "(1 + t²)³ F (my_fk may skip roots that are no assembly modes, poly_t keeps them)."), n)
        for code, message in _POLYNOMIAL_MISTAKES:
            variants = [_polynomial_variant(rho, code) for rho in R]
            reduced = [_divided(v, _T_DEN) for v in variants]
            if all_match(variants) or all_match(reduced):
                return self.failure(code, message.format(name=self.name), n)
        rho = R[0]
        modes = _robot().forward_kinematics(rho).poses
        roots = np.tan(modes[:, 2] / 2)
        values = np.array([np.polyval(S[0][::-1], r) for r in roots])
        k = int(np.argmax(np.abs(values)))
        return self.failure("mismatch", (
            f"{self.name} at ρ = {fmt(rho)} does not vanish at t = tan(φ/2) = {fmt(roots[k])} of the assembly "
            f"mode {fmt(modes[k])}: (1 + t²)³ F is {fmt(values[k])} there. Derive F again from the "
            "subtracted loop equations; a wrong sign, a missing term or a substitution other than "
            "cos φ = (1 − t²)/(1 + t²), sin φ = 2t/(1 + t²) each change it."), n)


orientation_polynomial = exercise(_CHAPTER, "orientation_polynomial", _OrientationPolynomialCheck(
    name="poly_t",
    signature="poly_t: sympy Poly in t",
    samples=4,
    noun="leg lengths",
    doc=("Check poly_t, (1 + t²)³ F of the exercise's robot as a sympy Poly in t whose coefficients hold "
         "the symbols rho1, rho2, rho3 (any constant factor)."),
))


# ------------------------------------------------------------------ the orientation equation F(φ)
def _equation_pieces(robot, phi: float, rho: np.ndarray) -> np.ndarray:
    """The pieces (D²|u|², ρ1² D², ρ1², ρ1² D) of F at phi: F = D²|u|² − ρ1² D² (Cramer's x, y times D)."""
    D = _subtracted_determinant(robot, phi)
    w = _position_w(robot, phi, rho)
    return np.array([D**2 * abs(w) ** 2, rho[0] ** 2 * D**2, rho[0] ** 2, rho[0] ** 2 * D])


#: how the orientation handed to F may have been read: code -> (φ the answer used, message)
_ANGLE_READINGS = [
    ("degrees", lambda phi: math.radians(phi), (
        "{name} reads φ in degrees: F_of_phi(φ) is F(φ · π/180). φ is in radians.")),
    ("half_angle_variable", lambda phi: 2 * math.atan(phi), (
        "{name} takes t = tan(φ/2) where φ is passed: F_of_phi(φ, …) is F(2 arctan φ). The argument is the "
        "orientation φ itself (rad).")),
    ("half_angle", lambda phi: phi / 2, "{name} evaluates F at φ/2: the loop equations hold φ itself."),
    ("double_angle", lambda phi: 2 * phi, "{name} evaluates F at 2φ: the loop equations hold φ itself."),
]


class _OrientationFunctionCheck(FunctionCheck):
    """Check ``F_of_phi(phi, rho, robot)``: the orientation equation, up to a constant factor."""

    def cases(self) -> list[tuple[Any, np.ndarray, np.ndarray]]:
        """(robot, ρ, orientations): the classic robot, the exercise's (off φ = 0) and a random one."""
        from robokin.models.three_rpr import CLASSIC_RHO, three_rpr_classic

        rng = np.random.default_rng(self.seed)
        withheld = WITHHELD["forward_kinematics"]
        robots = [three_rpr_classic(), _robot(), None]
        out: list[tuple[Any, np.ndarray, np.ndarray]] = []
        for robot in robots:
            if robot is None:
                base, platform = rng.uniform(-1.0, 1.0, (3, 2)), rng.uniform(-0.5, 0.5, (3, 2))
            else:
                base, platform = robot.base_anchors, robot.platform_anchors
            rho = CLASSIC_RHO.copy() if robot is not None and len(out) == 0 else rng.uniform(0.6, 1.3, 3)
            phis = rng.uniform(0.3, 2.8, self.samples) * rng.choice([-1.0, 1.0], self.samples)
            out.append((RobotWithoutSolvers(base, platform, withheld), rho, phis))
        return out

    def judge(self, answer: Any) -> CheckResult:
        cases = self.cases()
        n = sum(len(phis) for _, _, phis in cases)
        got = []
        for robot, rho, phis in cases:
            values = []
            for phi in phis:
                out = self.call(answer, (float(phi), rho.copy(), robot), samples=n)
                try:
                    values.append(float(out))
                except (TypeError, ValueError):
                    return self.failure("shape", f"{self.name} must return one number F(φ); got "
                                                 f"{type(out).__name__}.", n)
            if not np.all(np.isfinite(values)):
                return self.failure("error", f"{self.name} gives NaN or infinite values.", n)
            got.append(np.array(values))

        def fit(reading: Callable[[float], float]) -> list[tuple[np.ndarray, float]]:
            """Per case, the weights of the pieces that make the answer's values, and the misfit."""
            out: list[tuple[np.ndarray, float]] = []
            for (robot, rho, phis), S in zip(cases, got):
                P = np.array([_equation_pieces(robot, reading(float(p)), rho) for p in phis])
                scale = np.linalg.norm(P, axis=0)
                weights, *_ = np.linalg.lstsq(P / scale, S, rcond=None)
                misfit = np.linalg.norm(P / scale @ weights - S) / max(float(np.linalg.norm(S)), 1e-300)
                out.append((weights / scale, float(misfit)))
            return out

        def verdict(fits: list[tuple[np.ndarray, float]]) -> str | None:
            codes = set()
            for weights, misfit in fits:
                if misfit > 1e-7:
                    return None
                c1, c2, c3, c4 = weights
                if abs(c1) <= 1e-300:
                    return None
                tiny = [abs(c) <= 1e-6 * abs(c1) for c in (c2, c3, c4)]
                if tiny[1] and tiny[2] and abs(c2 + c1) <= 1e-6 * abs(c1):
                    codes.add("")
                elif tiny[1] and tiny[2] and abs(c2 - c1) <= 1e-6 * abs(c1):
                    codes.add("rho1_term_sign")
                elif all(tiny):
                    codes.add("rho1_term_missing")
                elif tiny[0] and tiny[1]:
                    codes.add("determinant_not_squared")
                elif tiny[0] and tiny[2]:
                    codes.add("determinant_missing")
                else:
                    return None
            return codes.pop() if len(codes) == 1 else None

        code = verdict(fit(lambda phi: phi))
        if code == "":
            return self.success(f"{self.name} is correct (checked at {n} random orientations, on three "
                                "robots).", n)
        messages = {
            "rho1_term_sign": ("{name} has the sign of its ρ1² term reversed: move every term of the "
                               "first loop equation to one side before you clear the denominators."),
            "rho1_term_missing": ("{name} lacks its ρ1² term: the first loop equation has two sides, and "
                                  "both must appear in F."),
            "determinant_not_squared": ("{name} multiplies the ρ1² side of the first loop equation by D "
                                        "where the other side holds D²: clear the denominators of both "
                                        "sides by the same factor."),
            "determinant_missing": ("{name} leaves the ρ1² side of the first loop equation without the "
                                    "factor that clears the denominators of the other side: multiply both "
                                    "sides by the same factor. Without it F is not a trigonometric "
                                    "polynomial and its roots are not the modes'."),
        }
        if code in messages:
            return self.failure(code, messages[code].format(name=self.name), n)
        for reading_code, reading, message in _ANGLE_READINGS:
            if verdict(fit(reading)) == "":
                return self.failure(reading_code, message.format(name=self.name), n)
        robot, rho, mode, which = _example_mode(cases)
        value = self.call(answer, (float(mode[2]), rho.copy(), robot), samples=n)
        return self.failure("mismatch", (
            f"{self.name} is not the orientation equation F(φ) up to a constant factor (nor a typical "
            f"slip of it): on {which} at ρ = {fmt(rho)}, F_of_phi({fmt(mode[2])}) = "
            f"{fmt(value)}, where the assembly mode {fmt(mode)} makes F vanish. Eliminate x, y from "
            "the loop equations again."), n)


def _example_mode(cases: list[tuple[Any, np.ndarray, np.ndarray]]) -> tuple[Any, np.ndarray, np.ndarray, str]:
    """The example of a wrong F_of_phi: (robot, ρ, an assembly mode, how to name the robot).

    The exercise's robot at the check's own leg lengths first: the classic robot's modes at
    CLASSIC_RHO are an answer of the chapter (``modes6``), so it comes last (it has six modes).
    """
    from robokin.parallel import Planar3RPR

    names = ("the exercise's robot", "a robot of this check's own", "the classic robot")
    for (robot, rho, _), which in zip((cases[1], cases[2], cases[0]), names):
        modes = Planar3RPR(robot.base_anchors, robot.platform_anchors).forward_kinematics(rho).poses
        if len(modes) or which == names[-1]:
            return robot, rho, modes[0], which
    raise AssertionError("unreachable: the classic robot has six modes at CLASSIC_RHO")


orientation_function = exercise(_CHAPTER, "orientation_function", _OrientationFunctionCheck(
    name="F_of_phi(phi, rho, robot)",
    signature="F_of_phi(phi, rho, robot) -> F",
    samples=16,
    noun="orientations",
    doc=("Check a function F_of_phi(phi, rho, robot) -> the orientation equation F(φ) of a 3-RPR robot, "
         "the trigonometric polynomial whose roots are the orientations of the assembly modes (any "
         "constant factor)."),
))


def reference_orientation_function(phi: float, rho: Any, robot: Any = None) -> float:
    """robokin's answer to ``F_of_phi`` of Task 2 (the tests' stand-in).

    The graded test of ``my_fk`` passes it to the student's ``my_fk`` as its argument ``F``, so
    that a mistake in ``F_of_phi`` costs only the test of ``F_of_phi``.

    Parameters
    ----------
    phi : float
        The orientation of the platform, rad.
    rho : array_like, shape (3,)
        Leg lengths, m.
    robot : Planar3RPR or RobotWithoutSolvers, optional
        The robot (default the chapter's).

    Returns
    -------
    float
        F(φ), m⁶ for anchors in m: zero at the orientations of the assembly modes (and where the
        two subtracted loop equations are singular).

    Raises
    ------
    TypeError
        ``robot`` is no 3-RPR robot.
    DomainError, ShapeError
        ``phi`` not a finite number, ``rho`` not three non-negative lengths.
    """
    from robokin.parallel import Planar3RPR

    if robot is None:
        robot = _robot()
    elif not isinstance(robot, (Planar3RPR, RobotWithoutSolvers)):
        raise TypeError(f"robot must be a robokin.parallel.Planar3RPR (e.g. robokin.models.three_rpr()); "
                        f"got {type(robot).__name__}")
    phi = float(as_scalar(phi, "phi"))
    rho = as_vector(rho, 3, "rho")
    if (rho < 0).any():
        raise DomainError(f"rho must be non-negative leg lengths; got {rho.tolist()}")
    a, b = robot.base_anchors, robot.platform_anchors
    e = (b[1:] - b[0]) @ _rot(phi).T - (a[1:] - a[0])
    with np.errstate(over="ignore", invalid="ignore"):
        M, r = 2.0 * e, rho[1:] ** 2 - rho[0] ** 2 - np.sum(e**2, axis=1)
        adjugate_r = np.array([M[1, 1] * r[0] - M[0, 1] * r[1], M[0, 0] * r[1] - M[1, 0] * r[0]])
        det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
        value = float(adjugate_r @ adjugate_r - rho[0] ** 2 * det**2)
    if not math.isfinite(value):
        raise DomainError(f"F overflows at rho = {rho.tolist()} m: the leg lengths are too large")
    return value
