r"""Closed-form inverse kinematics of the AR-601 leg (:func:`robokin.models.ar601_leg`).

The leg is

.. math::

    {}^B\mathbf{T}_F(\mathbf{q}) = \underbrace{R_z(q_1) R_y(q_2) R_x(q_3)}_{\mathbf{R}_H}\,
    T_z(-L_1)\, R_x(q_4)\, T_z(-L_2)\, R_y(q_5) R_x(q_6)\, T_z(-L_3).

The chain satisfies Pieper's criterion (three consecutive axes through one
point), so its inverse kinematics decouples (Siciliano et al. 2009 §2.12.2;
Craig 2005 §4.6; Lynch & Park 2017 §6.1.1). Given the foot pose :math:`(\mathbf{R}, \mathbf{p})`, it takes four
steps: the ankle point, the knee angle :math:`q_4` from the hip–ankle distance,
the two ankle angles :math:`q_5, q_6`, and the three hip angles
:math:`q_1, q_2, q_3` (Kajita et al. 2014, §2.5, for the same construction on the
HRP legs). Chapter 6 of the workbook derives them. Every returned solution is verified
with the model's forward kinematics (``position_residual``,
``orientation_residual``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robokin.chains import SerialChain
from robokin.errors import DomainError, ShapeError
from robokin.models.ar601 import ar601_leg
from robokin.transforms import rotx, roty, rotz
from robokin.validation import check_positive, check_transform

__all__ = ["REASONS", "SINGULARITIES", "AR601IKResult", "ar601_leg_ik", "ar601_leg_ik_batch"]

#: Reasons of :class:`AR601IKResult` (``success`` is True only for ``"solved"``).
REASONS = (
    "solved",          # at least one solution, every returned one verified by FK
    "too_far",         # hip–ankle distance > L1 + L2
    "too_close",       # hip–ankle distance < |L1 − L2|
    "ankle_range",     # the ankle axes cannot turn the foot to this orientation at this distance
    "joint_limits",    # solutions exist, none within the joint limits (within_limits=True)
    "not_verified",    # solutions computed, but none reproduces the target (numerical trouble)
)

#: Singular cases flagged in :attr:`AR601IKResult.singular`.
SINGULARITIES = (
    "stretched_knee",  # q4 = 0: the two knee solutions coincide (workspace boundary)
    "folded_knee",     # q4 = ±π: the other boundary (|L1 − L2|)
    "hip_gimbal",      # q2 = ±π/2: only q1 ∓ q3 is determined (q1 = 0 returned)
    "ankle_axis",      # hip on the q6 axis: q6 free (q6 = 0 returned)
    "ankle_roll",      # L1 cos q4 + L2 = 0: q5 free (q5 = 0 returned)
)


@dataclass(frozen=True, eq=False)
class AR601IKResult:
    """All closed-form solutions of the AR-601 leg for one foot pose.

    Attributes
    ----------
    q : ndarray, shape (k, 6)
        The solutions (rad, each angle in (−π, π]), ``k`` in 0..8; sorted by
        branch (knee, ankle, hip).
    success : bool
        True if ``k ≥ 1`` and every returned solution reproduces the target.
    reason : str
        One of :data:`REASONS`.
    position_residual : ndarray, shape (k,)
        ``‖p_FK(q) − p_target‖`` (m) of each solution.
    orientation_residual : ndarray, shape (k,)
        Rotation angle of ``R_FK(q)ᵀ R_target`` (rad) of each solution.
    branches : ndarray of int, shape (k, 3)
        Signs ``(knee, ankle, hip)`` of each solution: the sign of ``q4``,
        which of the two ankle solutions (``+1`` first) and ``+1`` for
        ``|q2| ≤ π/2``.
    within_limits : ndarray of bool, shape (k,)
        Whether each solution respects the chain's joint limits.
    singular : tuple of str
        Singular cases met (see :data:`SINGULARITIES`); there a family of
        solutions is represented by one member.
    distance : float
        Hip–ankle distance ``d`` (m).
    """

    q: np.ndarray
    success: bool
    reason: str
    position_residual: np.ndarray
    orientation_residual: np.ndarray
    branches: np.ndarray
    within_limits: np.ndarray
    singular: tuple[str, ...] = field(default_factory=tuple)
    distance: float = float("nan")

    def __len__(self) -> int:
        return int(self.q.shape[0])

    def __repr__(self) -> str:
        return (
            f"AR601IKResult(solutions={len(self)}, success={self.success}, "
            f"reason={self.reason!r}, singular={self.singular})"
        )


def _wrap(a: np.ndarray) -> np.ndarray:
    """Angles into (−π, π]."""
    w = np.mod(np.asarray(a) + np.pi, 2.0 * np.pi) - np.pi
    return np.where(w <= -np.pi + 1e-15, w + 2.0 * np.pi, w)


def _clip_cos(c: float, tol: float) -> float | None:
    """``c`` clipped to [−1, 1] if it is at most ``tol`` outside, else None."""
    if c > 1.0 + tol or c < -1.0 - tol:
        return None
    return min(1.0, max(-1.0, c))


def _hip_angles(R_H: np.ndarray, branch: int, tol: float) -> tuple[float, float, float, bool]:
    r"""``(q1, q2, q3, gimbal)`` with ``R_H = Rz(q1) Ry(q2) Rx(q3)``.

    ``q2 = atan2(−r31, ±√(r11² + r21²))`` (Siciliano et al. 2009, §2.4.2);
    q1 from the first column, then q3 from what remains,
    ``Rx(q3) = Ry(q2)ᵀ Rz(q1)ᵀ R_H``, so that the product is reproduced exactly
    even close to the gimbal-lock configuration ``q2 = ±π/2``. At gimbal lock
    (``√(r11² + r21²) < tol``) only ``q1 ∓ q3`` is defined: ``q1 = 0`` is
    returned and ``q3`` takes the whole angle.
    """
    c2 = math.hypot(R_H[0, 0], R_H[1, 0])
    gimbal = c2 < tol
    q2 = math.atan2(-R_H[2, 0], branch * c2)
    if gimbal:
        q1 = 0.0
    else:
        q1 = math.atan2(branch * R_H[1, 0], branch * R_H[0, 0])
    rest = roty(q2).T @ rotz(q1).T @ R_H  # = Rx(q3)
    q3 = math.atan2(rest[2, 1], rest[1, 1])
    return q1, q2, q3, gimbal


def _solve_one(
    T: np.ndarray, l1: float, l2: float, l3: float, tol: float
) -> tuple[list[np.ndarray], list[tuple[int, int, int]], str, set[str], float]:
    """Raw candidate solutions for one target (no verification)."""
    R, p = T[:3, :3], T[:3, 3]
    a = p + l3 * R[:, 2]                      # step 1: ankle point
    d = float(np.linalg.norm(a))
    if not math.isfinite(d):                  # a huge target: |a|² overflows, |a| does not
        d = math.hypot(*a.tolist())
        if not math.isfinite(d):
            raise DomainError(f"T_target is too large: the hip–ankle distance overflows float64 "
                              f"(|p| up to {float(np.abs(p).max()):.3g} m)")
    singular: set[str] = set()
    scale = l1 + l2
    # step 2: knee from the law of cosines (q4 measured from the stretched leg)
    c4 = _clip_cos((d * d - l1 * l1 - l2 * l2) / (2.0 * l1 * l2), tol)
    if c4 is None:
        return [], [], ("too_far" if d > scale else "too_close"), singular, d
    q4_abs = math.acos(c4)
    if q4_abs < math.sqrt(tol):
        singular.add("stretched_knee")
        knees = [(1, 0.0)] if q4_abs == 0.0 else [(1, q4_abs), (-1, -q4_abs)]
    elif math.pi - q4_abs < math.sqrt(tol):
        singular.add("folded_knee")
        knees = [(1, q4_abs), (-1, -q4_abs)]
    else:
        knees = [(1, q4_abs), (-1, -q4_abs)]
    u = R.T @ a                                # hip→ankle vector in foot coordinates
    rho = math.hypot(u[1], u[2])
    k = l1 * c4 + l2
    sols, branches = [], []
    ankle_fail = False
    for s4, q4 in knees:
        target = -l1 * math.sin(q4)            # c6 u_y − s6 u_z = −L1 s4 = ρ cos(q6 + φ)
        if rho < tol * scale:
            if abs(target) > tol * scale:
                ankle_fail = True
                continue
            singular.add("ankle_axis")
            q6s = [(1, 0.0)]
        else:
            phi = math.atan2(u[2], u[1])
            c = _clip_cos(target / rho, tol)
            if c is None:
                ankle_fail = True
                continue
            g = math.acos(c)
            q6s = [(1, g - phi), (-1, -g - phi)]
        for s6, q6 in q6s:
            w = rotx(q6) @ u                    # Ry(q5) w = v: (w_x, w_z) = (k s5, −k c5)
            if abs(k) < tol * scale:
                singular.add("ankle_roll")
                q5 = 0.0
            else:
                q5 = math.atan2(w[0] / k, -w[2] / k)
            R_H = R @ (rotx(q4) @ roty(q5) @ rotx(q6)).T
            for s2 in (1, -1):
                q1, q2, q3, gimbal = _hip_angles(R_H, s2, tol)
                if gimbal:
                    singular.add("hip_gimbal")
                sols.append(np.array([q1, q2, q3, q4, q5, q6]))
                branches.append((s4, s6, s2))
    if not sols:
        return [], [], ("ankle_range" if ankle_fail else "too_far"), singular, d
    return sols, branches, "solved", singular, d


def _residuals(chain: SerialChain, Q: np.ndarray, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    F = chain.fk(Q, check=False).reshape(-1, 4, 4)
    dp = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1)
    Rrel = np.einsum("kji,jl->kil", F[:, :3, :3], T[:3, :3])   # R_FKᵀ R_target
    cos_t = np.clip((np.trace(Rrel, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    # arccos is inaccurate near 0: use the skew part too
    skew = np.stack([Rrel[:, 2, 1] - Rrel[:, 1, 2], Rrel[:, 0, 2] - Rrel[:, 2, 0],
                     Rrel[:, 1, 0] - Rrel[:, 0, 1]], axis=1)
    ang = np.arctan2(np.linalg.norm(skew, axis=1) / 2.0, cos_t)
    return dp, ang


def _unique(Q: np.ndarray, tol: float) -> np.ndarray:
    """Indices of the first occurrence of each distinct row (angles modulo 2π)."""
    keep: list[int] = []
    for i, q in enumerate(Q):
        if not any(np.all(np.abs(_wrap(q - Q[j])) < tol) for j in keep):
            keep.append(i)
    return np.array(keep, dtype=int)


def ar601_leg_ik(
    T_target: Any,
    l1: float = 0.3,
    l2: float = 0.3,
    l3: float = 0.1,
    *,
    within_limits: bool = False,
    tol: float = 1e-9,
    check: bool = True,
) -> AR601IKResult:
    r"""All joint solutions of the AR-601 leg for a foot pose, in closed form.

    Parameters
    ----------
    T_target : array_like, shape (4, 4)
        Goal pose :math:`{}^B\mathbf{T}_F` of the foot frame in the hip/base frame
        (m). For a batch ``(N, 4, 4)`` use :func:`ar601_leg_ik_batch`.
    l1, l2, l3 : float, optional
        Thigh, shank and ankle–sole lengths (m), the same defaults as
        :func:`robokin.models.ar601_leg` (0.3, 0.3, 0.1).
    within_limits : bool, optional
        Return only the solutions within the model's joint limits (±π/2 each);
        ``reason="joint_limits"`` if none is.
    tol : float, optional
        Relative tolerance for boundary cases (a cosine up to ``tol`` outside
        [−1, 1] is clipped; singular cases are detected with it) and, times the
        leg length, the accepted FK residual.
    check : bool, optional
        Validate the inputs (default True).

    Returns
    -------
    AR601IKResult
        ``q`` (k, 6) with k ≤ 8, ``success``, ``reason``, residuals per
        solution, ``branches``, ``within_limits``, ``singular``. Never raises
        for an unreachable target: ``success=False`` and ``reason`` say why.

    Raises
    ------
    ShapeError
        ``T_target`` is not 4×4.
    DomainError
        ``T_target`` is not a homogeneous transform, or a length is not
        positive (or not finite).

    Notes
    -----
    The four steps of the module docstring; Siciliano et al. (2009) §2.12 for the
    kinematic decoupling, Kajita et al. (2014, *Introduction to Humanoid
    Robotics*, §2.5) for the same construction on the HRP legs.

    Examples
    --------
    >>> import numpy as np
    >>> from robokin.models import ar601_leg
    >>> q = np.array([0.1, -0.2, 0.3, 0.8, -0.1, -0.4])
    >>> res = ar601_leg_ik(ar601_leg().fk(q))
    >>> res.success, len(res)
    (True, 8)
    """
    if check:
        T = check_transform(T_target, name="T_target")
        if T.ndim != 2:
            raise ShapeError(
                f"T_target must have shape (4, 4) (use ar601_leg_ik_batch for (N, 4, 4)); got shape {T.shape}"
            )
        l1, l2, l3 = _lengths(l1, l2, l3)
        tol = check_positive(tol, "tol", scalar=True)
    else:
        T = np.asarray(T_target, dtype=float)
    l1, l2, l3 = float(l1), float(l2), float(l3)
    chain = _chain(l1, l2, l3)
    with np.errstate(all="ignore"):
        sols, branches, reason, singular, d = _solve_one(T, l1, l2, l3, tol)
    empty = np.zeros((0, 6))
    if not sols:
        return AR601IKResult(empty, False, reason, np.zeros(0), np.zeros(0),
                             np.zeros((0, 3), dtype=int), np.zeros(0, dtype=bool),
                             tuple(s for s in SINGULARITIES if s in singular), d)
    Q = _wrap(np.array(sols))
    B = np.array(branches, dtype=int)
    keep = _unique(Q, 1e3 * tol + 1e-7)
    Q, B = Q[keep], B[keep]
    dp, dr = _residuals(chain, Q, T)
    good = (dp <= 1e3 * tol * (l1 + l2 + l3) + 1e-12) & (dr <= 1e3 * tol + 1e-12)
    Q, B, dp, dr = Q[good], B[good], dp[good], dr[good]
    inside = np.asarray(chain.within_limits(Q, tol=1e-12), dtype=bool).reshape(-1)
    if within_limits:
        Q, B, dp, dr, inside = Q[inside], B[inside], dp[inside], dr[inside], inside[inside]
    order = np.lexsort((-B[:, 2], -B[:, 1], -B[:, 0])) if len(Q) else np.zeros(0, dtype=int)
    Q, B, dp, dr, inside = Q[order], B[order], dp[order], dr[order], inside[order]
    if len(Q):
        reason = "solved"
    elif not good.any():
        reason = "not_verified"
    else:
        reason = "joint_limits"
    return AR601IKResult(Q, bool(len(Q)), reason, dp, dr, B, inside,
                         tuple(s for s in SINGULARITIES if s in singular), d)


def _lengths(l1: Any, l2: Any, l3: Any) -> tuple[float, float, float]:
    """The three leg lengths as positive finite floats (the messages name them)."""
    out = tuple(check_positive(v, k, scalar=True) for v, k in ((l1, "l1"), (l2, "l2"), (l3, "l3")))
    for v, k in zip(out, ("l1", "l2", "l3")):
        if isinstance(v, np.ndarray):
            raise ShapeError(f"{k} must be a single number (metres); got shape {v.shape}")
    total = out[0] + out[1] + out[2]
    if not math.isfinite(total * total):  # the law of cosines squares the lengths
        raise DomainError(f"l1, l2, l3 are too large: their squares overflow float64 (got {out})")
    return out


def ar601_leg_ik_batch(
    T_targets: Any,
    l1: float = 0.3,
    l2: float = 0.3,
    l3: float = 0.1,
    *,
    within_limits: bool = False,
    tol: float = 1e-9,
) -> list[AR601IKResult]:
    """:func:`ar601_leg_ik` for a batch of foot poses.

    Parameters
    ----------
    T_targets : array_like, shape (N, 4, 4)
        Foot poses (a single (4, 4) pose is treated as N = 1).
    l1, l2, l3, within_limits, tol
        As in :func:`ar601_leg_ik`.

    Returns
    -------
    list of AR601IKResult, length N
        One result per pose (the number of solutions differs between poses).
    """
    Ts = check_transform(T_targets, name="T_targets").reshape(-1, 4, 4)
    l1, l2, l3 = _lengths(l1, l2, l3)  # validated once for all poses
    tol = check_positive(tol, "tol", scalar=True)
    out = []
    for i, T in enumerate(Ts):
        try:
            out.append(ar601_leg_ik(T, l1, l2, l3, within_limits=within_limits, tol=tol, check=False))
        except DomainError as exc:  # a pose near 1e308 m: name it in the batch
            raise DomainError(f"T_targets[{i}]: {exc}") from None
    return out


_CHAINS: dict[tuple[float, float, float], Any] = {}


def _chain(l1: float, l2: float, l3: float) -> Any:
    key = (l1, l2, l3)
    if key not in _CHAINS:
        if len(_CHAINS) > 16:
            _CHAINS.clear()
        _CHAINS[key] = ar601_leg(l1, l2, l3)
    return _CHAINS[key]
