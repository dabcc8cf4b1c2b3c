r"""Planar 3-RPR parallel robot: inverse and forward kinematics, Jacobian.

A moving platform is connected to the ground by three legs. Leg :math:`i` turns
about a passive revolute joint at the base anchor :math:`A_i`, has an actuated
prismatic joint of length :math:`\rho_i` and is attached by a passive revolute
joint to the platform at :math:`B_i` (Merlet 2006, ch. 3 and 4;
Gosselin & Merlet 1994).

Parameterisation
----------------
The platform pose is :math:`\mathbf{x} = (x, y, \varphi)`: the position of the
platform frame's origin :math:`P` in the base frame and the platform's
orientation (rad, counterclockwise). The base anchors :math:`\mathbf{A}_i` are
given in the base frame, the platform anchors :math:`{}_P\mathbf{b}_i` in the
platform frame; :math:`\mathbf{B}_i` is the platform anchor in the base frame
(:meth:`Planar3RPR.platform_points`) and :math:`\rho_i` the distance from
:math:`\mathbf{A}_i` to :math:`\mathbf{B}_i`, the length of leg :math:`i`.

Forward kinematics
------------------
:meth:`Planar3RPR.forward_kinematics` returns every assembly mode (platform pose) for
given leg lengths: the real roots of the orientation equation :math:`F(\varphi) = 0`
that is left after the position is eliminated from the three loop equations. With
:math:`t = \tan(\varphi/2)`, :math:`(1 + t^2)^3 F` is a polynomial of degree 6
(:meth:`Planar3RPR.orientation_polynomial`), so there are at most six real assembly
modes (Gosselin & Merlet 1994; Merlet 2006, ch. 4). The solver finds the roots as those of
a polynomial in :math:`z = e^{i\varphi}` (no special case for :math:`\varphi = \pi`,
where :math:`t \to \infty`), then polishes every pose with Newton's method on the three
loop equations. The derivation of the equation and of its degree is chapter 3 of the
workbook (its solution).

Velocities
----------
:meth:`Planar3RPR.jacobian` returns the *inverse Jacobian* :math:`\mathbf{A}(\mathbf{x})`
of the robot, :math:`\dot{\boldsymbol\rho} = \mathbf{A}\,\dot{\mathbf{x}}` with
:math:`\dot{\mathbf{x}} = (\dot x, \dot y, \dot\varphi)`: it maps the platform velocity to the
leg rates (Merlet 2006, ch. 5), the opposite direction to ``jacobian`` of a serial chain
(:meth:`robokin.chains.SerialChain.jacobian`), which maps the joint rates to the twist.
:meth:`Planar3RPR.direct_jacobian` returns :math:`\mathbf{A}^{-1}`. Where
:math:`\det\mathbf{A} = 0` the robot is at a parallel (type-2) singularity
(Gosselin & Angeles 1990).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, overload

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.validation import (
    as_batch,
    as_float_array,
    as_vector,
    check_limits,
    check_positive,
    check_result_finite,
)

__all__ = ["ForwardKinematicsResult", "Planar3RPR"]

_E = np.array([[0.0, -1.0], [1.0, 0.0]])  # rotation by +90°: E v = z × v
#: Largest anchor spread (m): the direct kinematics works with fourth powers of lengths.
_MAX_SIZE = 1e60


def _rot(phi: np.ndarray) -> np.ndarray:
    """Planar rotation matrices, shape phi.shape + (2, 2)."""
    c, s = np.cos(phi), np.sin(phi)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def _cross2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """z component of the cross product of planar vectors (..., 2)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


@overload
def _wrap(phi: float) -> float: ...


@overload
def _wrap(phi: np.ndarray) -> np.ndarray | float: ...


def _wrap(phi: np.ndarray | float) -> np.ndarray | float:
    """Angle wrapped to (−π, π]."""
    w = np.pi - np.mod(np.pi - np.asarray(phi, dtype=float), 2 * np.pi)
    return float(w) if np.ndim(w) == 0 else w


@dataclass(frozen=True, eq=False)
class ForwardKinematicsResult:
    """All assembly modes of a 3-RPR robot for given leg lengths.

    Attributes
    ----------
    poses : numpy.ndarray, shape (k, 3)
        The real solutions ``(x, y, φ)`` (φ in (−π, π]), sorted by φ; ``k`` in 0..6
        (``k = 0`` when the legs cannot be assembled).
    success : bool
        True if at least one assembly mode was found and the solution set is finite
        (a continuum of modes gives ``False``; ``poses`` then holds the isolated modes).
    reason : str
        ``"solved"``, ``"no real assembly mode"`` or a description of a degenerate case.
    residuals : numpy.ndarray, shape (k,)
        ``max_i |ρ_i(pose) − ρ_i|`` of each pose, metres.
    rho : numpy.ndarray, shape (3,)
        The leg lengths that were solved for.
    """

    poses: np.ndarray
    success: bool
    reason: str
    residuals: np.ndarray
    rho: np.ndarray = field(repr=False)

    @property
    def count(self) -> int:
        """Number of assembly modes found."""
        return int(self.poses.shape[0])

    def __len__(self) -> int:
        return self.count


class Planar3RPR:
    r"""A planar 3-RPR parallel robot.

    Parameters
    ----------
    base_anchors : array_like, shape (3, 2)
        Base joint centres :math:`\mathbf{A}_i` in the base frame, metres.
    platform_anchors : array_like, shape (3, 2)
        Platform joint centres :math:`{}_P\mathbf{b}_i` in the platform frame, metres.
        The pose ``(x, y, φ)`` is that of the platform frame, so with
        ``platform_anchors[0] = (0, 0)`` the position ``(x, y)`` is the point :math:`B_1`.
    stroke : array_like, shape (2,) or (3, 2), optional
        Leg length limits ``(ρ_min, ρ_max)`` per leg (one row for all legs),
        metres. Default ``(0, inf)``.
    name : str, optional

    Raises
    ------
    ShapeError
        Wrong array shapes.
    DomainError
        Non-finite anchors, collinear or coincident anchors, invalid stroke.

    Notes
    -----
    Geometry follows Merlet (2006), *Parallel Robots*, 2nd ed., ch. 3 (inverse
    kinematics) and ch. 4 (direct kinematics), and Gosselin & Merlet (1994).
    """

    def __init__(self, base_anchors: Any, platform_anchors: Any, stroke: Any = (0.0, np.inf),
                 name: str = "3-RPR") -> None:
        A = as_float_array(base_anchors, "base_anchors", (3, 2)).copy()
        b = as_float_array(platform_anchors, "platform_anchors", (3, 2)).copy()
        for arr, what in ((A, "base_anchors"), (b, "platform_anchors")):
            with np.errstate(all="ignore"):
                size = float(np.ptp(arr, axis=0).max())
                area2 = float(_cross2((arr[1] - arr[0]) / size, (arr[2] - arr[0]) / size)) if size > 0 else 0.0
            if not (np.isfinite(size) and size < _MAX_SIZE):
                raise DomainError(f"{what} are too large: coordinates span {size:.3g} m (at most "
                                  f"{_MAX_SIZE:.0e} m)")
            if not abs(area2) > 1e-9:
                raise DomainError(
                    f"{what} must be the corners of a proper triangle; got collinear or "
                    f"coincident points {np.array2string(arr, precision=6, separator=', ')}"
                )
        try:
            shape = np.shape(stroke)
        except ValueError:  # ragged
            shape = None
        if shape == (2,):
            stroke = [stroke] * 3
        elif shape != (3, 2):
            raise ShapeError("stroke must have shape (2,) or (3, 2); got "
                             + (f"shape {shape}" if shape is not None else repr(stroke)))
        s = check_limits(stroke, 3, "stroke")  # numbers, no NaN, rho_min <= rho_max
        if (s[:, 0] < 0).any() or np.isinf(s[:, 0]).any():
            raise DomainError(
                f"stroke rows must be 0 <= rho_min <= rho_max (rho_max may be inf); got {s.tolist()}"
            )
        self.base_anchors = A
        self.platform_anchors = b
        self.stroke = s
        self.name = str(name)
        self._scale = float(max(np.ptp(A, axis=0).max(), np.ptp(b, axis=0).max()))

    def __repr__(self) -> str:
        return (f"Planar3RPR(name={self.name!r}, base_anchors={np.round(self.base_anchors, 4).tolist()}, "
                f"platform_anchors={np.round(self.platform_anchors, 4).tolist()})")

    # ------------------------------------------------------------------ geometry
    def platform_points(self, pose: Any) -> np.ndarray:
        r"""Platform anchors :math:`\mathbf{B}_i` in the base frame.

        Parameters
        ----------
        pose : array_like, shape (3,) or (N, 3)
            ``(x, y, φ)``, metres and radians.

        Returns
        -------
        numpy.ndarray, shape (3, 2) or (N, 3, 2)
        """
        X, batched = as_batch(pose, 3, "pose")
        B = self._points(X.reshape(-1, 3))
        return B if batched else B[0]

    def _points(self, X2: np.ndarray) -> np.ndarray:
        """Platform anchors in the base frame for poses (N, 3) -> (N, 3, 2); checks for overflow."""
        R = _rot(X2[:, 2])                                    # (N, 2, 2)
        with np.errstate(all="ignore"):
            B = X2[:, None, :2] + np.einsum("nij,kj->nki", R, self.platform_anchors)
        return check_result_finite(B, "the platform points", pose=X2)

    def _lengths(self, d: np.ndarray, X2: Any) -> np.ndarray:
        """Norms of leg vectors d (..., 2), checked for overflow (a pose near 1e154 m)."""
        with np.errstate(over="ignore"):
            rho = np.linalg.norm(d, axis=-1)
            if not np.isfinite(rho).all():  # |d|² overflowed: hypot scales instead
                rho = np.where(np.isfinite(rho), rho, np.hypot(d[..., 0], d[..., 1]))
        return check_result_finite(rho, "the leg lengths", pose=X2)

    def leg_vectors(self, pose: Any) -> np.ndarray:
        r"""Leg vectors :math:`\mathbf{B}_i - \mathbf{A}_i`, shape (3, 2) or (N, 3, 2)."""
        return self.platform_points(pose) - self.base_anchors

    def leg_angles(self, pose: Any) -> np.ndarray:
        r"""Directions of the legs :math:`\theta_i = \operatorname{atan2}` of :math:`\mathbf{B}_i - \mathbf{A}_i`,
        shape (3,) or (N, 3) (the passive base joint angles)."""
        d = self.leg_vectors(pose)
        return np.arctan2(d[..., 1], d[..., 0])

    # ------------------------------------------------------------------ inverse kinematics
    def inverse_kinematics(self, pose: Any) -> np.ndarray:
        r"""Leg lengths :math:`\rho_i`, the distances from :math:`A_i` to :math:`B_i` (Merlet 2006, ch. 3).

        Parameters
        ----------
        pose : array_like, shape (3,) or (N, 3)
            ``(x, y, φ)`` of the platform frame.

        Returns
        -------
        numpy.ndarray, shape (3,) or (N, 3)
            Leg lengths in metres (stroke limits are not applied; see
            :meth:`within_stroke`).

        Raises
        ------
        ShapeError, DomainError
            ``pose`` not of shape (3,) / (N, 3), non-finite, or so large that
            the leg lengths overflow float64.
        """
        return self._lengths(self.leg_vectors(pose), pose)

    def within_stroke(self, rho: Any) -> np.ndarray | bool:
        """True where all leg lengths ``rho`` (3,) or (N, 3) lie within the stroke limits."""
        R, batched = as_batch(rho, 3, "rho")
        ok = np.all((R >= self.stroke[:, 0]) & (R <= self.stroke[:, 1]), axis=-1)
        return ok if batched else bool(ok)

    # ------------------------------------------------------------------ Jacobian
    def jacobian(self, pose: Any) -> np.ndarray:
        r"""Inverse Jacobian :math:`\mathbf{A}`:
        :math:`\dot{\boldsymbol\rho} = \mathbf{A}\,[\dot x, \dot y, \dot\varphi]^\top`.

        Note the direction: for this parallel robot ``jacobian`` maps the platform velocity
        to the leg rates (row :math:`i` gives :math:`\dot\rho_i`; columns :math:`\dot x`,
        :math:`\dot y` in m/s and :math:`\dot\varphi` in rad/s), while ``jacobian`` of a
        serial chain maps the joint rates to the twist. :meth:`direct_jacobian` is
        :math:`\mathbf{A}^{-1}`, the map from leg rates to platform velocity
        (Merlet 2006, ch. 5).

        Parameters
        ----------
        pose : array_like, shape (3,) or (N, 3)
            ``(x, y, φ)`` of the platform frame, metres and radians.

        Returns
        -------
        numpy.ndarray, shape (3, 3) or (N, 3, 3)
            Rows: legs; columns: :math:`\dot x, \dot y` (dimensionless) and
            :math:`\dot\varphi` (m/rad).

        Raises
        ------
        DomainError
            If a pose puts a platform anchor on its base anchor (a leg of length 0,
            whose direction is undefined); the message names the pose and the leg.
        """
        X, batched = as_batch(pose, 3, "pose")
        X2 = X.reshape(-1, 3)
        B = self._points(X2)
        d = B - self.base_anchors
        rho = self._lengths(d, X2)
        zero = rho <= 1e-12 * self._scale
        if zero.any():
            k, leg = (int(i) for i in np.argwhere(zero)[0])
            where = f"pose[{k}] = " if batched else "pose "
            raise DomainError(
                f"{where}{[float(f'{v:.6g}') for v in X2[k]]} puts platform anchor B{leg + 1} on base "
                f"anchor A{leg + 1} (leg {leg + 1} has length 0): its direction and the Jacobian are "
                "undefined there; leave such poses out (e.g. a grid of positions through a base anchor)")
        n = d / rho[..., None]
        arm = B - X2[:, None, :2]
        J = np.concatenate([n, _cross2(arm, n)[..., None]], axis=-1)
        return J if batched else J[0]

    def direct_jacobian(self, pose: Any) -> np.ndarray:
        r"""Direct Jacobian :math:`\mathbf{A}^{-1}`:
        :math:`[\dot x, \dot y, \dot\varphi]^\top = \mathbf{A}^{-1}\dot{\boldsymbol\rho}`.

        Parameters
        ----------
        pose : array_like, shape (3,)

        Returns
        -------
        numpy.ndarray, shape (3, 3)

        Raises
        ------
        DomainError
            At a parallel singularity (``condition_number`` above 1e12), where the
            platform can move with the legs locked and no inverse exists.
        """
        p = as_vector(pose, 3, "pose")
        A = self.jacobian(p)
        if self.condition_number(p) > 1e12:
            raise DomainError(f"pose {[float(f'{x:.6g}') for x in p]} is a parallel singularity: "
                              "the inverse Jacobian A is singular and has no inverse")
        return np.linalg.inv(A)

    def condition_number(self, pose: Any) -> np.ndarray | float:
        r"""2-norm condition number of :math:`\mathbf{A}` after scaling its last column by a length.

        The last column (m/rad) is divided by the characteristic length
        :attr:`characteristic_length` so that all columns are dimensionless.
        Returns ``inf`` at singular poses; shape () or (N,).
        """
        A = np.array(self.jacobian(pose), dtype=float)
        A[..., 2] /= self.characteristic_length
        s = np.linalg.svd(A, compute_uv=False)
        with np.errstate(divide="ignore"):
            k = np.where(s[..., -1] > 0, s[..., 0] / s[..., -1], np.inf)
        return float(k) if np.ndim(k) == 0 else k

    @property
    def characteristic_length(self) -> float:
        """RMS distance of the platform anchors from their centroid, metres."""
        b = self.platform_anchors
        return float(np.sqrt(np.mean(np.sum((b - b.mean(axis=0)) ** 2, axis=1))))

    def is_singular(self, pose: Any, tol: float = 1e-9) -> np.ndarray | bool:
        r"""True where :math:`|\det\mathbf{A}| \le` ``tol`` · (characteristic length): a parallel singularity."""
        tol = check_positive(tol, "tol", scalar=True)
        A = self.jacobian(pose)
        with np.errstate(all="ignore"):  # an exactly singular A: LAPACK's LU divides by zero, det = 0
            d = np.abs(np.linalg.det(A)) <= tol * self.characteristic_length
        return bool(d) if np.ndim(d) == 0 else d

    # ------------------------------------------------------------------ forward kinematics
    def _linear_system(self, phi: np.ndarray, rho: np.ndarray):
        """M (…,2,2), r (…,2) of the subtracted loop equations M u = r, u = B1 − A1."""
        a, b = self.base_anchors, self.platform_anchors
        R = _rot(np.asarray(phi, dtype=float))
        e = np.einsum("...ij,kj->...ki", R, b[1:] - b[0]) - (a[1:] - a[0])   # (…, 2, 2)
        M = 2.0 * e
        r = rho[1:] ** 2 - rho[0] ** 2 - np.sum(e**2, axis=-1)
        return M, r

    def _orientation_function(self, phi: np.ndarray, rho: np.ndarray) -> np.ndarray:
        """F(φ) = |adj(M) r|² − ρ1² det(M)²."""
        M, r = self._linear_system(phi, rho)
        D = M[..., 0, 0] * M[..., 1, 1] - M[..., 0, 1] * M[..., 1, 0]
        Nx = M[..., 1, 1] * r[..., 0] - M[..., 0, 1] * r[..., 1]
        Ny = -M[..., 1, 0] * r[..., 0] + M[..., 0, 0] * r[..., 1]
        return Nx**2 + Ny**2 - rho[0] ** 2 * D**2

    def orientation_harmonics(self, rho: Any) -> np.ndarray:
        r"""Fourier coefficients of the orientation equation :math:`F(\varphi)`.

        Returns
        -------
        numpy.ndarray, shape (7,), complex
            :math:`c_{-3}, \dots, c_3` with :math:`F(\varphi) = \sum_k c_k e^{ik\varphi}`
            (:math:`c_{-k} = \bar c_k`), in the units of :math:`F` (m⁶), for the leg
            lengths ``rho`` (3,) in m; :math:`F` is the orientation equation of the
            module docstring (Merlet 2006, ch. 4).
        """
        rho = self._check_rho(rho)
        phi = 2 * np.pi * np.arange(16) / 16
        with np.errstate(all="ignore"):
            c = np.fft.fft(self._orientation_function(phi, rho)) / 16
        check_result_finite(c, "the orientation equation (fourth powers of the lengths)", rho=rho)
        return np.concatenate([c[-3:], c[:4]])

    def orientation_polynomial(self, rho: Any) -> np.ndarray:
        r"""Coefficients :math:`C_0, \dots, C_6` of the orientation polynomial in :math:`t = \tan(\varphi/2)`.

        :math:`(1 + t^2)^3 F(\varphi) = \sum_{j=0}^{6} C_j t^j`, lowest degree first
        (the notation of the exercise; Gosselin & Merlet 1994, Merlet 2006, ch. 4),
        for the leg lengths ``rho`` (3,) in m.

        Returns
        -------
        numpy.ndarray, shape (7,)
            :math:`C_0, \dots, C_6`, real, in the units of :math:`F` (m⁶).
        """
        c = self.orientation_harmonics(rho)
        out = np.zeros(7, dtype=complex)
        P = np.polynomial.polynomial
        one_plus_t2 = np.array([1.0, 0.0, 1.0])
        for k in range(-3, 4):
            base = np.array([1.0, 1j]) if k >= 0 else np.array([1.0, -1j])
            term: np.ndarray = P.polymul(P.polypow(base, 2 * abs(k)), P.polypow(one_plus_t2, 3 - abs(k)))
            out[: len(term)] += c[k + 3] * term
        return out.real

    def _check_rho(self, rho: Any) -> np.ndarray:
        r = as_vector(rho, 3, "rho")
        if (r < 0).any():
            raise DomainError(f"rho must be non-negative leg lengths; got {r.tolist()}")
        return r

    def _residual(self, pose: np.ndarray, rho: np.ndarray) -> np.ndarray:
        d = self.leg_vectors(pose)
        return np.sum(d**2, axis=-1) - rho**2

    def _newton(self, pose: np.ndarray, rho: np.ndarray, iterations: int = 8) -> np.ndarray:
        """Polish a pose on the loop equations |B_i − A_i|² = ρ_i² (Newton's method)."""
        x = pose.copy()
        for _ in range(iterations):
            g = self._residual(x, rho)
            if np.abs(g).max() <= 1e-15 * self._scale**2:
                break
            d = self.leg_vectors(x)
            arm = self.platform_points(x) - x[:2]
            G = 2.0 * np.concatenate([d, _cross2(arm, d)[:, None]], axis=1)
            try:
                step = np.linalg.solve(G, -g)
            except np.linalg.LinAlgError:
                break
            if not np.all(np.isfinite(step)) or np.linalg.cond(G) > 1e14:
                break
            x = x + step
        return x

    def _positions(self, phi: float, rho: np.ndarray) -> tuple[list[np.ndarray], bool]:
        """Solve M u = r with |u| = ρ1 at a fixed φ; returns candidate u's and a 'continuum' flag."""
        M, r = self._linear_system(np.array(phi), rho)
        U, s, Vt = np.linalg.svd(M)
        tol = 1e-6 * self._scale          # φ from a double root is accurate to ~1e-8 only
        if s[1] > tol:
            return [np.linalg.solve(M, r)], False
        if s[0] <= tol:                              # M = 0: any u on the circle |u| = ρ1
            return [], bool(np.abs(r).max() <= 1e-6 * self._scale**2)
        # rank 1: line v·u = c intersected with the circle |u| = ρ1
        v, c = Vt[0], (U[:, 0] @ r) / s[0]
        if abs(U[:, 1] @ r) > 1e-7 * self._scale**2:
            return [], False
        h2 = rho[0] ** 2 - c**2
        if h2 < -1e-12 * self._scale**2:
            return [], False
        h = np.sqrt(max(h2, 0.0))
        w = np.array([-v[1], v[0]])
        return [c * v + h * w, c * v - h * w], False

    def forward_kinematics(self, rho: Any, tol: float = 1e-9) -> ForwardKinematicsResult:
        r"""All real assembly modes (platform poses) for the leg lengths ``rho``.

        Method: the orientation equation :math:`F(\varphi) = 0` (module docstring) as a
        degree-6 polynomial in :math:`z = e^{i\varphi}` (companion-matrix roots), keep the
        roots close to the unit circle, solve the linear equations for the position,
        polish each pose with Newton's method on the three loop equations, keep poses
        whose leg lengths match to ``tol`` (relative to the robot's size), remove duplicates.
        Gosselin & Merlet (1994); Merlet (2006), ch. 4.

        Parameters
        ----------
        rho : array_like, shape (3,)
            Leg lengths, metres (non-negative).
        tol : float, optional
            Accepted leg-length residual, relative to the robot's size.

        Returns
        -------
        ForwardKinematicsResult
            ``poses`` (k, 3) with k in 0..6, ``success``, ``reason``, ``residuals``.
            Never raises for valid ``rho``: no solution gives ``success=False``.

        Raises
        ------
        ShapeError, DomainError
            ``rho`` not three finite non-negative numbers (or so large that the
            orientation equation overflows float64), ``tol`` not positive.
        """
        rho = self._check_rho(rho)
        tol = check_positive(tol, "tol", scalar=True)
        scale = self._scale + float(rho.max())
        c = self.orientation_harmonics(rho)
        if np.abs(c).max() <= 1e-12 * scale**4:  # finite: the harmonics (with rho**4) are
            return self._fail(rho, "degenerate: the orientation equation vanishes for every "
                                   "angle (the platform can move with locked legs)")
        coeffs = c[::-1]                           # z^6 ... z^0 of z^3 F
        lead = np.abs(coeffs).max()
        first = int(np.argmax(np.abs(coeffs) > 1e-14 * lead))
        z = np.roots(coeffs[first:]) if first < 6 else np.array([])
        candidates = [float(np.angle(zk)) for zk in z if abs(abs(zk) - 1.0) < 1e-3]
        # a k-fold root is computed with an error ~ eps^(1/k); the mean of its cluster is accurate
        for zk in z:
            cluster = z[np.abs(z - zk) < 1e-3]
            if len(cluster) > 1 and abs(abs(cluster.mean()) - 1.0) < 1e-6:
                candidates.append(float(np.angle(cluster.mean())))
        poses, continuum = [], False
        for phi in candidates:
            us, cont = self._positions(float(phi), rho)
            continuum |= cont
            for u in us:
                p = self.base_anchors[0] + u - _rot(np.array(phi)) @ self.platform_anchors[0]
                pose = self._newton(np.array([p[0], p[1], phi]), rho)
                poses.append(pose)
        kept: list[np.ndarray] = []
        res: list[float] = []
        for pose in poses:
            pose = np.array([pose[0], pose[1], _wrap(pose[2])])
            r = float(np.abs(self.inverse_kinematics(pose) - rho).max())
            if not r <= tol * scale:
                continue
            if any(np.abs(pose[:2] - q[:2]).max() <= 1e-6 * scale and
                   abs(_wrap(pose[2] - q[2])) <= 1e-6 for q in kept):
                continue
            kept.append(pose)
            res.append(r)
        if not kept and not continuum:
            return self._fail(rho, "no real assembly mode: the legs cannot be connected to the platform")
        order = np.argsort([q[2] for q in kept])
        P = np.array(kept, dtype=float).reshape(-1, 3)[order]
        P[np.abs(P) < 1e-15] = 0.0
        if continuum:
            return ForwardKinematicsResult(
                P, False, "degenerate: a continuum of assembly modes (the platform can move with "
                "locked legs); poses holds the isolated modes only", np.array(res)[order], rho)
        return ForwardKinematicsResult(P, True, "solved", np.array(res)[order], rho)

    def _fail(self, rho: np.ndarray, reason: str) -> ForwardKinematicsResult:
        return ForwardKinematicsResult(np.zeros((0, 3)), False, reason, np.zeros(0), rho)
