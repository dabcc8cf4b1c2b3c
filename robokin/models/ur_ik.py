r"""Closed-form inverse kinematics of the Universal Robots arms (:func:`robokin.models.ur10`).

The UR3, UR5, UR10 (CB3) and UR3e, UR5e, UR10e, UR16e (e-Series) share one
kinematic structure: in robokin's DH layout (rows ``(d, θ_offset, a, α)``,
:func:`robokin.chains.from_dh`, each row
:math:`R_z(\theta_i)\,T_z(d_i)\,T_x(a_i)\,R_x(\alpha_i)`)

====  =====  =====  =====  ========
i     d_i    a_i    α_i    θ_i
====  =====  =====  =====  ========
1     d1     0      π/2    q1
2     0      a2     0      q2
3     0      a3     0      q3
4     d4     0      π/2    q4
5     d5     0      −π/2   q5
6     d6     0      0      q6
====  =====  =====  =====  ========

with the manufacturer's signs (``a2``, ``a3`` < 0; ``d4`` > 0: the wrist is
offset sideways from the plane of the arm). Joints 2, 3 and 4 are parallel
(their axes are :math:`\mathbf{z}_1`); the three wrist axes do not meet in a
point, so Pieper's decoupling of the position from the orientation does not
apply, but the parallel axes give a closed form all the same (Hawkins 2013,
*Analytic inverse kinematics for the Universal Robots UR-5/UR-10 arms*;
Siciliano et al. 2009 §2.12; Lynch & Park 2017 §6.1), checked numerically
(``tests/test_ur_ik.py``). Given the tool flange pose
:math:`(\mathbf{R}, \mathbf{p})` in the base frame, it takes four steps: the
wrist centre (the origin of frame 5) and :math:`q_1`, two *shoulder* solutions;
:math:`q_5`, two *wrist* solutions; :math:`q_6`; and the planar three-link
problem of the parallel joints for :math:`q_2, q_3, q_4`, two *elbow*
solutions. Chapter 7 of the workbook derives them.

Up to :math:`2\times2\times2 = 8` solutions, each angle wrapped into (−π, π].
Each one is verified by the forward kinematics of the table, the product of its
six DH matrices in robokin's convention (what :func:`robokin.chains.from_dh`
builds; for the default table the chain of :func:`robokin.models.ur10`):
``position_residual`` (m) and ``orientation_residual`` (the rotation angle
between the two orientations, rad). The tests check that these residuals are
those of ``ur10().fk`` / ``from_dh(table).fk`` (to 1e-13 m and 1e-12 rad); the
chain's own ``fk`` is not called here because for eight configurations it costs
about three times the whole closed form (numbers in ``benchmarks/bench_ur_ik.py``'s
docstring).

The tables :data:`UR3_DH`, :data:`UR5_DH`, :data:`UR3E_DH`, :data:`UR5E_DH`,
:data:`UR10E_DH` and :data:`UR16E_DH` are the manufacturer's (Universal Robots,
*DH Parameters for calculations of kinematics and dynamics*, support article, last
modified 19 January 2022), copied into robokin's layout; the UR10's is
``robokin.models.ur10.UR10_DH``. Checked: the UR10 table is the chain of
:func:`robokin.models.ur10` (its three descriptions), the UR5 table the
``ur5_robot.urdf`` of example-robot-data (to 1e-10 m, the URDF's rounding).

:func:`ur10_ik` follows the four steps in plain floats, one branch at a time;
:func:`ur10_ik_batch` does the same arithmetic on arrays (branch axes first, the
pose last, in blocks of 1,024 poses) and is tested against it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.models.ur10 import UR10_DH
from robokin.validation import as_float_array, check_positive, check_transform

__all__ = ["REASONS", "SINGULARITIES", "BRANCHES", "UR_DH_TABLES", "UR3_DH", "UR5_DH", "UR10_DH", "UR3E_DH",
           "UR5E_DH", "UR10E_DH", "UR16E_DH", "URIKResult", "URIKBatchResult", "ur10_ik", "ur10_ik_batch"]

_PI = math.pi


def _ur_table(d1: float, a2: float, a3: float, d4: float, d5: float, d6: float) -> list[list[float]]:
    """A UR table in robokin's DH layout, rows (d, θ_offset, a, α)."""
    return [[d1, 0.0, 0.0, _PI / 2], [0.0, 0.0, a2, 0.0], [0.0, 0.0, a3, 0.0],
            [d4, 0.0, 0.0, _PI / 2], [d5, 0.0, 0.0, -_PI / 2], [d6, 0.0, 0.0, 0.0]]


# Universal Robots, "DH Parameters for calculations of kinematics and dynamics" (support article,
# last modified 19 January 2022; CB3 software 3.7.0 and e-Series 5.1.0), metres and radians.
#: UR3 (CB3) in robokin's DH layout, rows ``(d, θ_offset, a, α)`` (Universal Robots' DH article).
UR3_DH = _ur_table(0.1519, -0.24365, -0.21325, 0.11235, 0.08535, 0.0819)
#: UR5 (CB3), the same layout and source.
UR5_DH = _ur_table(0.089159, -0.425, -0.39225, 0.10915, 0.09465, 0.0823)
#: UR3e (e-Series), the same layout and source.
UR3E_DH = _ur_table(0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921)
#: UR5e (e-Series), the same layout and source.
UR5E_DH = _ur_table(0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996)
#: UR10e (e-Series), the same layout and source.
UR10E_DH = _ur_table(0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655)
#: UR16e (e-Series), the same layout and source.
UR16E_DH = _ur_table(0.1807, -0.4784, -0.36, 0.17415, 0.11985, 0.11655)

#: The tables by name: ``dh="ur5e"`` is ``dh=UR5E_DH``. ``"ur10"`` is ``robokin.models.ur10.UR10_DH``.
UR_DH_TABLES: dict[str, list[list[float]]] = {
    "ur3": UR3_DH, "ur5": UR5_DH, "ur10": [list(map(float, row)) for row in UR10_DH],
    "ur3e": UR3E_DH, "ur5e": UR5E_DH, "ur10e": UR10E_DH, "ur16e": UR16E_DH,
}

#: Reasons of :class:`URIKResult` (``success`` is True only for ``"solved"``).
REASONS = (
    "solved",             # at least one solution, every returned one verified by FK
    "shoulder_cylinder",  # wrist centre nearer to the base axis than |d4|: no q1
    "too_far",            # in the arm's plane the wrist is beyond |a2| + |a3| (every branch)
    "too_close",          # in the arm's plane the wrist is within ||a2| − |a3|| (every branch)
    "joint_limits",       # none within the joint limits (within_limits=True; not with the UR's ±2π limits)
    "not_verified",       # solutions computed, none reproduces the target (numerical trouble)
)

#: Singular cases flagged in :attr:`URIKResult.singular`.
SINGULARITIES = (
    "shoulder",  # wrist centre on the base axis in the arm's plane (r = |d4|): the two q1 coincide
    "wrist",     # sin q5 = 0: joints 2, 3, 4, 6 parallel, q6 free (q6 = 0 returned)
    "elbow",     # sin q3 = 0: arm stretched or folded, the two elbow solutions coincide
)

#: Names of the three columns of :attr:`URIKResult.branches`.
BRANCHES = ("shoulder", "wrist", "elbow")

_SIGNS = np.array([(s, w, e) for s in (1, -1) for w in (1, -1) for e in (1, -1)], dtype=int)
_SIGNS.setflags(write=False)
_SLOT = {tuple(int(v) for v in signs): j for j, signs in enumerate(_SIGNS)}


@dataclass(frozen=True, eq=False)
class URIKResult:
    """All closed-form solutions of a Universal Robots arm for one flange pose.

    Attributes
    ----------
    q : ndarray, shape (k, 6)
        The solutions (rad, each angle in (−π, π]), ``k`` in 0..8; sorted by
        branch (shoulder, wrist, elbow), ``+1`` first.
    success : bool
        True if ``k ≥ 1`` and every returned solution reproduces the target.
    reason : str
        One of :data:`REASONS`.
    position_residual : ndarray, shape (k,)
        ``‖p_FK(q) − p_target‖`` (m) of each solution.
    orientation_residual : ndarray, shape (k,)
        Rotation angle of ``R_FK(q)ᵀ R_target`` (rad) of each solution.
    branches : ndarray of int, shape (k, 3)
        Signs ``(shoulder, wrist, elbow)`` of each solution (:data:`BRANCHES`):
        the shoulder's ``+1`` where the wrist centre lies on the negative side
        of the x axis of DH frame 1 and ``−1`` where on its positive side, the
        sign of ``sin q5`` and the sign of ``sin q3`` (``+1`` where it is 0).
    within_limits : ndarray of bool, shape (k,)
        Whether each solution respects the joint limits (±2π, the controller's range).
    singular : tuple of str
        Singular cases met (see :data:`SINGULARITIES`); there a family of
        solutions (or two coinciding ones) is represented by one member.
    wrist_centre : ndarray, shape (3,)
        The wrist centre, the origin of DH frame 5 (m, base frame).
    """

    q: np.ndarray
    success: bool
    reason: str
    position_residual: np.ndarray
    orientation_residual: np.ndarray
    branches: np.ndarray
    within_limits: np.ndarray
    singular: tuple[str, ...] = field(default_factory=tuple)
    wrist_centre: np.ndarray = field(default_factory=lambda: np.full(3, np.nan))

    def __len__(self) -> int:
        return int(self.q.shape[0])

    def __repr__(self) -> str:
        return (f"URIKResult(solutions={len(self)}, success={self.success}, "
                f"reason={self.reason!r}, singular={self.singular})")


@dataclass(frozen=True, eq=False)
class URIKBatchResult:
    """All closed-form solutions for N flange poses, eight slots per pose.

    Slot ``j`` of every pose holds the branch ``BRANCH_SIGNS[j]`` =
    ``branches[j]`` (shoulder, wrist, elbow; ``+1`` first); a slot without a
    solution (unreachable branch, a coinciding singular branch, not verified,
    or outside the limits with ``within_limits=True``) has ``valid`` False and
    NaN in ``q`` and the residuals. ``result[i]`` is pose i as a
    :class:`URIKResult` (the valid slots in order), equal to
    ``ur10_ik(T[i], ...)``; ``len(result)`` is N and iterating gives those results.
    ``q``, the residuals, ``valid`` and ``within_limits`` are transposed views of
    slot-major arrays (as the vectorised steps compute them), not C-contiguous.

    Attributes
    ----------
    q : ndarray, shape (N, 8, 6)
        The solutions (rad, in (−π, π]; NaN where not ``valid``).
    valid : ndarray of bool, shape (N, 8)
        Which slots hold a verified solution.
    success : ndarray of bool, shape (N,)
        At least one valid slot.
    reason : ndarray of str, shape (N,)
        One of :data:`REASONS` per pose.
    position_residual, orientation_residual : ndarray, shape (N, 8)
        As in :class:`URIKResult` (m, rad; NaN where not ``valid``).
    branches : ndarray of int, shape (8, 3)
        The signs ``(shoulder, wrist, elbow)`` of the slots (the same for every pose).
    within_limits : ndarray of bool, shape (N, 8)
        Whether each slot's solution respects the joint limits (False where not ``valid``).
    singular : ndarray of bool, shape (N, 3)
        The singular cases met, columns in the order of :data:`SINGULARITIES`.
    wrist_centre : ndarray, shape (N, 3)
        The origin of frame 5 of each pose (m, base frame).
    """

    q: np.ndarray
    valid: np.ndarray
    success: np.ndarray
    reason: np.ndarray
    position_residual: np.ndarray
    orientation_residual: np.ndarray
    branches: np.ndarray
    within_limits: np.ndarray
    singular: np.ndarray
    wrist_centre: np.ndarray

    def __len__(self) -> int:
        return int(self.q.shape[0])

    def __getitem__(self, i: int) -> URIKResult:
        keep = self.valid[i]
        return URIKResult(self.q[i][keep], bool(self.success[i]), str(self.reason[i]),
                          self.position_residual[i][keep], self.orientation_residual[i][keep],
                          self.branches[keep], self.within_limits[i][keep],
                          tuple(s for s, flag in zip(SINGULARITIES, self.singular[i]) if flag),
                          self.wrist_centre[i].copy())

    def __iter__(self) -> Any:
        return (self[i] for i in range(len(self)))

    def __repr__(self) -> str:
        return (f"URIKBatchResult(poses={len(self)}, solved={int(self.success.sum())}, "
                f"solutions={int(self.valid.sum())})")


# ------------------------------------------------------------------ the table
class _Geometry(NamedTuple):
    """The six lengths (m) and six joint offsets (rad) of a UR table."""

    d1: float
    a2: float
    a3: float
    d4: float
    d5: float
    d6: float
    offsets: tuple[float, float, float, float, float, float]
    scale: float  # sum of the lengths' magnitudes (m): the tolerances' unit
    basis: np.ndarray  # (18, 96): block i maps (cos θ_i, sin θ_i, 1) to the 16 entries of the DH matrix of row i


def _dh_basis(table: np.ndarray) -> np.ndarray:
    r"""Constant matrices of the DH rows, block-diagonal (18, 96).

    :math:`R_z(\theta)T_z(d)T_x(a)R_x(\alpha) = c_\theta B_0 + s_\theta B_1 + B_2`: the
    row ``(cos θ_1, sin θ_1, 1, …, cos θ_6, sin θ_6, 1)`` times the result gives the six
    DH matrices, flattened.

    From the standard DH matrix (Siciliano et al. 2009, §2.8.2)
    ``[[cθ, −sθ cα, sθ sα, a cθ], [sθ, cθ cα, −cθ sα, a sθ], [0, sα, cα, d], [0, 0, 0, 1]]``
    (θ = q + θ_offset: the offset is added to q before the cosine).
    """
    B = np.zeros((6, 3, 4, 4))
    for i, (d, _offset, a, alpha) in enumerate(table):
        ca, sa = math.cos(alpha), math.sin(alpha)
        B[i, 0, 0, 0], B[i, 0, 1, 1], B[i, 0, 1, 2], B[i, 0, 0, 3] = 1.0, ca, -sa, a
        B[i, 1, 1, 0], B[i, 1, 0, 1], B[i, 1, 0, 2], B[i, 1, 1, 3] = 1.0, -ca, sa, a
        B[i, 2, 2, 1], B[i, 2, 2, 2], B[i, 2, 2, 3], B[i, 2, 3, 3] = sa, ca, d, 1.0
    basis = np.zeros((18, 96))
    for i in range(6):
        basis[3 * i: 3 * i + 3, 16 * i: 16 * i + 16] = B[i].reshape(3, 16)
    basis.setflags(write=False)
    return basis


_ALPHAS = (_PI / 2, 0.0, 0.0, _PI / 2, -_PI / 2, 0.0)
_ZERO_ENTRIES = ((0, 2, "a1"), (1, 0, "d2"), (2, 0, "d3"), (3, 2, "a4"), (4, 2, "a5"), (5, 2, "a6"))
_CACHE: dict[Any, _Geometry] = {}


def _geometry(dh: Any) -> _Geometry:
    """The validated UR geometry of ``dh`` (None, a name of :data:`UR_DH_TABLES` or a (6, 4) table)."""
    if dh is None:
        dh = "ur10"
    if isinstance(dh, str):
        key: Any = dh.lower()
        if key not in UR_DH_TABLES:
            raise DomainError(f"dh must be a (6, 4) DH table or one of {sorted(UR_DH_TABLES)}; got {dh!r}")
        if key in _CACHE:
            return _CACHE[key]
        table = np.array(UR_DH_TABLES[key], dtype=float)
    else:
        if isinstance(dh, (bool, np.bool_, int, float, complex)):
            raise TypeError(f"dh must be a (6, 4) DH table, rows (d, theta_offset, a, alpha), or a name; "
                            f"got {type(dh).__name__} {dh!r}")
        table = np.array(as_float_array(dh, "dh", shape=(6, 4)), dtype=float)
        key = table.tobytes()
        if key in _CACHE:
            return _CACHE[key]
    for i, alpha in enumerate(_ALPHAS):
        if abs(table[i, 3] - alpha) > 1e-9:
            raise DomainError(
                f"dh is not a Universal Robots table in robokin's DH layout (rows (d, theta_offset, a, alpha)): "
                f"alpha of row {i + 1} must be {alpha:.6g} (alphas pi/2, 0, 0, pi/2, -pi/2, 0); got {table[i, 3]:.6g}")
    for i, j, name in _ZERO_ENTRIES:
        if table[i, j] != 0.0:
            raise DomainError(f"dh is not a Universal Robots table: {name} (row {i + 1}, column {j + 1}) "
                              f"must be 0; got {table[i, j]:.6g}")
    d1, a2, a3, d4, d5, d6 = (float(table[0, 0]), float(table[1, 2]), float(table[2, 2]),
                              float(table[3, 0]), float(table[4, 0]), float(table[5, 0]))
    if a2 == 0.0 or a3 == 0.0:
        raise DomainError(f"dh is not a Universal Robots table: a2 and a3 (upper arm and forearm) must be "
                          f"non-zero; got a2 = {a2:.6g}, a3 = {a3:.6g}")
    scale = abs(d1) + abs(a2) + abs(a3) + abs(d4) + abs(d5) + abs(d6)
    if not math.isfinite(scale * scale) or scale * 1e-150 > 1.0 or min(abs(a2), abs(a3)) < 1e-150:
        raise DomainError(f"dh has lengths out of range (their squares must be finite and non-zero in float64); "
                          f"got a2 = {a2:.6g}, a3 = {a3:.6g}, sum of |lengths| {scale:.6g} m")
    o = [float(x) for x in table[:, 1]]
    geometry = _Geometry(d1, a2, a3, d4, d5, d6, (o[0], o[1], o[2], o[3], o[4], o[5]), scale, _dh_basis(table))
    if len(_CACHE) > 32:
        _CACHE.clear()
    _CACHE[key] = geometry
    return geometry


# ------------------------------------------------------------------ forward kinematics
def _dh_poses(g: _Geometry, Q: np.ndarray) -> np.ndarray:
    """Flange poses (k, 4, 4) of the rows ``Q`` (k, 6): the product of the table's six DH matrices."""
    k = len(Q)
    th = Q + np.asarray(g.offsets) if any(g.offsets) else Q
    V = _ONES[:k].copy()  # (k, 6, 3): cos θ_i, sin θ_i, 1
    np.cos(th, out=V[:, :, 0])
    np.sin(th, out=V[:, :, 1])
    A = (V.reshape(k, 18) @ g.basis).reshape(k, 6, 4, 4)  # A_i(q_i), i = 1..6 (one product, block-diagonal basis)
    P = A[:, 0::2] @ A[:, 1::2]                            # A1 A2, A3 A4, A5 A6
    return P[:, 0] @ P[:, 1] @ P[:, 2]


def _residuals(g: _Geometry, Q: np.ndarray, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""Position (m) and orientation (rad) residuals of the rows ``Q`` (k, 6) against ``T`` (4, 4).

    The rotation angle of :math:`\mathbf{R}_{FK}^\top\mathbf{R}` from
    :math:`\lVert\mathbf{R}_{FK} - \mathbf{R}\rVert_F = 2\sqrt{2}\,\sin(\theta/2)`
    (accurate for small angles, unlike the arccosine of the trace).
    """
    D = _dh_poses(g, Q)[:, :3, :] - T[:3, :]
    D *= D
    S = D.reshape(-1, 12) @ _SUMS  # (k, 2): ‖ΔR‖²/8 and ‖Δp‖²
    np.sqrt(S, out=S)
    return S[:, 1], 2.0 * np.arcsin(np.minimum(S[:, 0], 1.0))


_INV_SQRT8 = 1.0 / math.sqrt(8.0)
#: Sums of the squared differences of the rows of [R | p] (3, 4), flattened: rotation (over 8), position.
_SUMS = np.zeros((12, 2))
_SUMS[[0, 1, 2, 4, 5, 6, 8, 9, 10], 0] = 1.0 / 8.0
_SUMS[[3, 7, 11], 1] = 1.0
_SUMS.setflags(write=False)
_TRUE = np.ones(8, dtype=bool)
_TRUE.setflags(write=False)
_ONES = np.ones((8, 6, 3))
_ONES.setflags(write=False)


def _wrap(a: np.ndarray) -> np.ndarray:
    """Angles into (−π, π]: ``a − 2π·round(a / 2π)``, then −π to π."""
    w = a - _TWO_PI * np.rint(a * (1.0 / _TWO_PI))
    w += _TWO_PI * (w <= -_PI)
    return w


def _wrapped(angle: float) -> float:
    """One angle into (−π, π] (``math.remainder`` is exact)."""
    w = math.remainder(angle, _TWO_PI)
    return w if w > -_PI else w + _TWO_PI


def _cos_sin(angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(cos, sin)`` of an array from ``t = tan(angle / 2)``: ``(1 − t², 2t) / (1 + t²) = (v − 1, v t)``.

    With ``v = 2 / (1 + t²)``.

    The same values to a few ulp; numpy vectorises ``tan`` but not ``sin`` and
    ``cos`` for float64 (here 1.7 against 14 ns an element each): the batch
    path's cosines and sines cost an eighth.
    """
    t = np.tan(0.5 * angle)
    v = 2.0 / (1.0 + t * t)
    return v - 1.0, v * t


_TWO_PI = 2.0 * _PI


# ------------------------------------------------------------------ one pose, step by step
def _solve_pose(T: list[list[float]], g: _Geometry, tol: float
                ) -> tuple[list[list[float]], list[tuple[int, int, int]], str, set[str], tuple[float, ...]]:
    """Candidate solutions (DH angles θ, unverified) of one pose, in branch order; the steps of the module."""
    (r11, r12, r13, px), (r21, r22, r23, py), (r31, r32, r33, pz) = T[0], T[1], T[2]
    d1, a2, a3, d4, d5, d6 = g.d1, g.a2, g.a3, g.d4, g.d5, g.d6
    singular: set[str] = set()
    flag, collapse = math.sqrt(tol), 1e3 * tol + 1e-7
    # step 1: wrist centre o5 = p - d6 z6, and q1 from  o5 . z1 = d4
    wx, wy, wz = px - d6 * r13, py - d6 * r23, pz - d6 * r33
    centre = (wx, wy, wz)
    r = math.hypot(wx, wy)
    if r <= tol * g.scale and abs(d4) <= tol * g.scale:  # on the base axis and no offset: q1 free
        singular.add("shoulder")
        shoulders = [(1, 0.0)]
    elif not r >= abs(d4) * (1.0 - tol):
        return [], [], "shoulder_cylinder", singular, centre
    else:
        psi = math.atan2(wy, wx)
        gap = math.atan2(math.sqrt(max((r - abs(d4)) * (r + abs(d4)), 0.0)), d4)  # arccos(d4 / r)
        if min(gap, _PI - gap) < flag:
            singular.add("shoulder")
        shoulders = [(1, _wrapped(psi + _PI / 2 + gap))]
        if min(gap, _PI - gap) > collapse:
            shoulders.append((-1, _wrapped(psi + _PI / 2 - gap)))
    solutions, branches, misses = [], [], []
    for s_sign, t1 in shoulders:
        c1, s1 = math.cos(t1), math.sin(t1)
        # step 2: q5 from z1 seen in the flange frame, R^T z1 = (c6 s5, -s6 s5, c5)
        xz, yz, zz = r11 * s1 - r21 * c1, r12 * s1 - r22 * c1, r13 * s1 - r23 * c1
        s5_abs = math.hypot(xz, yz)
        t5_abs = math.atan2(s5_abs, zz) if s5_abs > tol else (0.0 if zz > 0.0 else _PI)  # sin q5 = 0: exactly
        if s5_abs < flag:
            singular.add("wrist")
        wrists = [(1, t5_abs)] if s5_abs <= tol else [(1, t5_abs), (-1, -t5_abs)]
        for w_sign, t5 in wrists:
            # step 3: q6 (free at sin q5 = 0: 0 returned)
            t6 = math.atan2(-w_sign * yz, w_sign * xz) if s5_abs > tol else 0.0
            c5, s5, c6, s6 = math.cos(t5), math.sin(t5), math.cos(t6), math.sin(t6)
            # step 4: the planar three-link problem in frame 1
            ox = wx + d5 * (s6 * r11 + c6 * r12)  # o4 = o5 - d5 z4, z4 = -s6 x6 - c6 y6
            oy = wy + d5 * (s6 * r21 + c6 * r22)
            oz = wz + d5 * (s6 * r31 + c6 * r32)
            x4x = c5 * c6 * r11 - c5 * s6 * r12 - s5 * r13  # x4 = c5 c6 x6 - c5 s6 y6 - s5 z6
            x4y = c5 * c6 * r21 - c5 * s6 * r22 - s5 * r23
            x4z = c5 * c6 * r31 - c5 * s6 * r32 - s5 * r33
            t234 = math.atan2(x4z, c1 * x4x + s1 * x4y)
            X, Y = c1 * ox + s1 * oy, oz - d1
            rho2 = X * X + Y * Y
            c3 = (rho2 - a2 * a2 - a3 * a3) / (2.0 * a2 * a3)
            if not -1.0 - tol <= c3 <= 1.0 + tol:  # also NaN / inf from a huge target
                misses.append("too_far" if not rho2 < (abs(a2) + abs(a3)) ** 2 else "too_close")
                continue
            c3 = min(1.0, max(-1.0, c3))
            s3_abs = math.sqrt((1.0 - c3) * (1.0 + c3))
            t3_abs = math.atan2(s3_abs, c3)
            if min(t3_abs, _PI - t3_abs) < flag:
                singular.add("elbow")
            elbows = [(1, t3_abs)]
            if min(t3_abs, _PI - t3_abs) > collapse:
                elbows.append((-1, -t3_abs))
            phi = math.atan2(Y, X)
            for e_sign, t3 in elbows:
                t2 = phi - math.atan2(a3 * e_sign * s3_abs, a2 + a3 * c3)
                # t1, t3, t5, t6 are in (−π, π] already
                solutions.append([t1, _wrapped(t2), t3, _wrapped(t234 - t2 - t3), t5, t6])
                branches.append((s_sign, w_sign, e_sign))
    if not solutions:
        return [], [], ("too_far" if "too_far" in misses else "too_close"), singular, centre
    return solutions, branches, "solved", singular, centre


def _fast_transform(T: Any) -> np.ndarray | None:
    """A float64 (4, 4) array that is a transform (tolerance 1e-6), checked in plain floats; else None."""
    if type(T) is not np.ndarray or T.dtype != np.float64 or T.shape != (4, 4):
        return None
    rows = T.tolist()
    (a, b, c, x), (d, e, f, y), (g, h, i, z), bottom = rows
    if not all(map(math.isfinite, (a, b, c, x, d, e, f, y, g, h, i, z))) or bottom != [0.0, 0.0, 0.0, 1.0]:
        return None
    err = max(abs(a * a + b * b + c * c - 1.0), abs(d * d + e * e + f * f - 1.0), abs(g * g + h * h + i * i - 1.0),
              abs(a * d + b * e + c * f), abs(a * g + b * h + c * i), abs(d * g + e * h + f * i))
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return T if err <= 1e-6 and abs(det - 1.0) <= 1e-6 else None


def _check_tol(tol: Any) -> float:
    tol = check_positive(tol, "tol", scalar=True)
    if tol > 1e-3:
        raise DomainError(f"tol must be a small relative tolerance (> 0, at most 1e-3); got {tol:g}")
    return float(tol)


def ur10_ik(
    T_target: Any,
    *,
    dh: Any = None,
    within_limits: bool = False,
    tol: float = 1e-9,
    check: bool = True,
) -> URIKResult:
    r"""All joint solutions of a Universal Robots arm for a flange pose, in closed form.

    Parameters
    ----------
    T_target : array_like, shape (4, 4)
        Goal pose :math:`{}^B\mathbf{T}_E` of the tool flange (``tool0``) in the
        base frame (m), as :func:`robokin.models.ur10`'s ``fk`` returns it. For a
        batch ``(N, 4, 4)`` use :func:`ur10_ik_batch`.
    dh : array_like, shape (6, 4), or str, optional
        The arm's table in robokin's DH layout, rows ``(d, θ_offset, a, α)``
        with the UR structure (α = π/2, 0, 0, π/2, −π/2, 0; only d1, a2, a3,
        d4, d5, d6 non-zero; offsets allowed), or a name of
        :data:`UR_DH_TABLES` (``"ur3"``, ``"ur5"``, ``"ur10"``, ``"ur3e"``,
        ``"ur5e"``, ``"ur10e"``, ``"ur16e"``). Default: the UR10 (CB3) table of
        :func:`robokin.models.ur10`.
    within_limits : bool, optional
        Return only the solutions within the joint limits (the signature of
        :func:`robokin.models.ar601_leg_ik`). The UR joints turn through ±2π
        (the controller's range, as :func:`robokin.models.ur10`), so every
        returned angle in (−π, π] is within them and the option removes none.
    tol : float, optional
        Relative tolerance (at most 1e-3): a cosine up to ``tol`` outside
        [−1, 1] is clipped; singular cases are flagged within ``√tol`` rad and
        two branches merged within ``1e3 tol + 1e-7`` rad; times the arm's size
        (sum of the lengths) the accepted position residual, ``1e3 tol`` the
        accepted orientation residual (rad).
    check : bool, optional
        Validate the inputs (default True).

    Returns
    -------
    URIKResult
        ``q`` (k, 6) with k ≤ 8, ``success``, ``reason``, residuals per
        solution, ``branches`` (shoulder, wrist, elbow), ``within_limits``,
        ``singular``, ``wrist_centre``. Never raises for an unreachable target:
        ``success=False`` and ``reason`` say why (:data:`REASONS`).

    Raises
    ------
    ShapeError
        ``T_target`` is not 4×4, or ``dh`` is not 6×4.
    DomainError
        ``T_target`` is not a homogeneous transform; ``dh`` is not a UR table
        (the message names the entry); ``tol`` is not in (0, 1e-3].
    TypeError
        Non-numeric ``T_target``, ``dh`` or ``tol``.

    Notes
    -----
    Four steps (module docstring): the wrist centre and q1, q5, q6, the planar
    three-link problem for q2, q3, q4; Hawkins (2013) for the UR-5/UR-10,
    Siciliano et al. (2009) §2.12 and Lynch & Park (2017) §6.1 for closed-form
    inverse kinematics. Every solution is verified with the
    forward kinematics of the table (``position_residual``,
    ``orientation_residual``). A joint of the arm turns through ±2π, so each
    returned angle ``q_i`` also stands for ``q_i ∓ 2π``.

    Examples
    --------
    >>> import numpy as np
    >>> from robokin.models import ur10
    >>> q = np.array([0.3, -1.2, 1.4, -0.5, 1.1, 0.2])
    >>> res = ur10_ik(ur10().fk(q))
    >>> res.success, len(res)
    (True, 8)
    >>> bool(np.abs(res.q - q).max(axis=1).min() < 1e-9)
    True
    """
    T = _fast_transform(T_target) if check else np.asarray(T_target, dtype=float)
    if T is None:
        T = check_transform(T_target, name="T_target")
        if T.ndim != 2:
            raise ShapeError(f"T_target must have shape (4, 4) (use ur10_ik_batch for (N, 4, 4)); "
                             f"got shape {T.shape}")
    g = _geometry(dh)
    if check and not (type(tol) is float and tol == 1e-9):
        tol = _check_tol(tol)
    sols, branches, reason, singular, centre = _solve_pose(T.tolist(), g, tol)
    flags = tuple(s for s in SINGULARITIES if s in singular) if singular else ()
    if not sols:
        return URIKResult(np.zeros((0, 6)), False, reason, np.zeros(0), np.zeros(0), np.zeros((0, 3), dtype=int),
                          np.zeros(0, dtype=bool), flags, np.array(centre))
    Q = np.array(sols, dtype=float)  # wrapped into (−π, π]
    if any(g.offsets):
        Q = _wrap(Q - np.array(g.offsets))
    B = _SIGNS.copy() if len(branches) == 8 else _SIGNS[[_SLOT[b] for b in branches]]
    dp, dr = _residuals(g, Q, T)
    inside = _TRUE[: len(Q)].copy()  # every angle in (−π, π] is within the limits ±2π
    if max(dp.tolist()) > 1e3 * tol * g.scale + 1e-12 or max(dr.tolist()) > 1e3 * tol + 1e-12:  # keep verified
        good = (dp <= 1e3 * tol * g.scale + 1e-12) & (dr <= 1e3 * tol + 1e-12)
        Q, B, dp, dr, inside = Q[good], B[good], dp[good], dr[good], inside[good]
    reason = "solved" if len(Q) else "not_verified"  # (no joint_limits: the limits hold every solution)
    return URIKResult(Q, bool(len(Q)), reason, dp, dr, B, inside, flags, np.array(centre))


# ------------------------------------------------------------------ many poses at once
def ur10_ik_batch(
    T_targets: Any,
    *,
    dh: Any = None,
    within_limits: bool = False,
    tol: float = 1e-9,
) -> URIKBatchResult:
    """:func:`ur10_ik` for a batch of flange poses, vectorised over the poses.

    The same steps as :func:`ur10_ik` on arrays: per pose the two shoulder
    angles, the 2×2 wrist angles and the 2×2×2 elbow angles, in eight slots.

    Parameters
    ----------
    T_targets : array_like, shape (N, 4, 4)
        Flange poses (a single (4, 4) pose is treated as N = 1).
    dh, within_limits, tol
        As in :func:`ur10_ik`.

    Returns
    -------
    URIKBatchResult
        Arrays with a leading N (``q`` (N, 8, 6), ``valid`` (N, 8), ...);
        ``result[i]`` equals ``ur10_ik(T_targets[i], ...)`` (to rounding: the
        arithmetic is vectorised).

    Raises
    ------
    ShapeError, DomainError, TypeError
        As in :func:`ur10_ik` (``T_targets`` named, with the index of a bad pose).
    """
    Ts = _fast_transforms(T_targets)
    if Ts is None:
        Ts = check_transform(T_targets, name="T_targets").reshape(-1, 4, 4)
    g = _geometry(dh)
    tol = _check_tol(tol)
    N = len(Ts)
    # stored slot-major, (6, 8, N) and (8, N), as the blocks compute them; the result holds transposed views
    out = URIKBatchResult(np.empty((6, 8, N)).T, np.empty((8, N), dtype=bool).T, np.empty(N, dtype=bool),
                          np.empty(N, dtype="<U17"), np.empty((8, N)).T, np.empty((8, N)).T, _SIGNS.copy(),
                          np.empty((8, N), dtype=bool).T, np.empty((N, 3), dtype=bool), np.empty((N, 3)))
    with np.errstate(all="ignore"):
        for start in range(0, N, _CHUNK):
            _solve_batch(Ts[start: start + _CHUNK], g, tol, within_limits, out, start)
    return out


#: Poses solved together: the arrays of a block stay in the processor's cache (here 1.8 µs a pose at
#: 1,000 poses against 2.9 µs at 10,000 in one block).
_CHUNK = 1024


def _fast_transforms(T: Any) -> np.ndarray | None:
    """A float64 (N, 4, 4) array of transforms (tolerance 1e-6), checked on its components; else None."""
    if type(T) is not np.ndarray or T.dtype != np.float64 or T.ndim != 3 or T.shape[1:] != (4, 4):
        return None
    F = T.reshape(-1, 16)
    if not (np.isfinite(F).all() and (F[:, 12:] == (0.0, 0.0, 0.0, 1.0)).all()):
        return None
    a, b, c, d, e, f, g, h, i = (F[:, k] for k in (0, 1, 2, 4, 5, 6, 8, 9, 10))
    err = np.maximum.reduce([abs(a * a + b * b + c * c - 1.0), abs(d * d + e * e + f * f - 1.0),
                             abs(g * g + h * h + i * i - 1.0), abs(a * d + b * e + c * f),
                             abs(a * g + b * h + c * i), abs(d * g + e * h + f * i),
                             abs(a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g) - 1.0)])
    return T if (err <= 1e-6).all() else None


def _solve_batch(Ts: np.ndarray, g: _Geometry, tol: float, within_limits: bool, out: URIKBatchResult,
                 start: int) -> None:
    """The steps of :func:`_solve_pose` on arrays whose last axis is the pose; into ``out[start:]``.

    Branch axes come first: shoulder (2, N), shoulder × wrist (2, 2, N),
    shoulder × wrist × elbow (2, 2, 2, N); flattened, slot j of the result.
    """
    N = Ts.shape[0]
    flag, collapse = math.sqrt(tol), 1e3 * tol + 1e-7
    r11, r12, r13, px, r21, r22, r23, py, r31, r32, r33, pz = np.ascontiguousarray(Ts[:, :3, :].reshape(N, 12).T)
    # step 1: wrist centre and the two q1 (index 0: +, 1: −)
    wx, wy, wz = px - g.d6 * r13, py - g.d6 * r23, pz - g.d6 * r33
    r = np.hypot(wx, wy)
    d4 = abs(g.d4)
    gap = np.arctan2(np.sqrt(np.maximum((r - d4) * (r + d4), 0.0)), g.d4)
    gap_min = np.minimum(gap, _PI - gap)
    reach1 = r >= d4 * (1.0 - tol)
    base = np.arctan2(wy, wx) + _PI / 2
    if d4 <= tol * g.scale:  # no offset: on the base axis q1 is free (0 returned)
        free = r <= tol * g.scale
        reach1 |= free
        base[free], gap[free] = 0.0, 0.0
    else:
        free = np.zeros(N, dtype=bool)
    t1 = np.stack([base + gap, base - gap])                                     # (2, N)
    ok1 = np.stack([reach1, reach1 & ~free & (gap_min > collapse)])
    sing_shoulder = free | (reach1 & (gap_min < flag))
    c1, s1 = _cos_sin(t1)
    # step 2: q5 = ±atan2(|s5|, c5) from R^T z1 = (c6 s5, −s6 s5, c5)
    xz, yz, zz = r11 * s1 - r21 * c1, r12 * s1 - r22 * c1, r13 * s1 - r23 * c1  # (2, N)
    s5_abs = np.hypot(xz, yz)
    t5_abs = np.arctan2(s5_abs, zz)
    regular5 = s5_abs > tol
    if not regular5.all():  # sin q5 = 0: exactly 0 or π
        t5_abs[~regular5] = np.where(zz[~regular5] > 0.0, 0.0, _PI)
    t5 = np.stack([t5_abs, -t5_abs], axis=1)                                    # (2, 2, N)
    ok2 = np.stack([ok1, ok1 & regular5], axis=1)
    sing_wrist = (ok1 & (s5_abs < flag)).any(axis=0)
    # step 3: q6 (0 where sin q5 = 0)
    t6 = np.stack([np.arctan2(-yz, xz), np.arctan2(yz, -xz)], axis=1)
    if not regular5.all():
        t6[~np.broadcast_to(regular5[:, None], t6.shape)] = 0.0
    (c5, s5), (c6, s6) = _cos_sin(t5), _cos_sin(t6)
    # step 4: the planar three-link problem in frame 1 (arrays (2, 2, N))
    C1, S1 = c1[:, None], s1[:, None]
    ox = wx + g.d5 * (s6 * r11 + c6 * r12)
    oy = wy + g.d5 * (s6 * r21 + c6 * r22)
    oz = wz + g.d5 * (s6 * r31 + c6 * r32)
    c5c6, c5s6 = c5 * c6, c5 * s6
    x4x = c5c6 * r11 - c5s6 * r12 - s5 * r13
    x4y = c5c6 * r21 - c5s6 * r22 - s5 * r23
    x4z = c5c6 * r31 - c5s6 * r32 - s5 * r33
    t234 = np.arctan2(x4z, C1 * x4x + S1 * x4y)
    X, Y = C1 * ox + S1 * oy, oz - g.d1
    rho2 = X * X + Y * Y
    c3 = (rho2 - g.a2 * g.a2 - g.a3 * g.a3) / (2.0 * g.a2 * g.a3)
    reach3 = (c3 >= -1.0 - tol) & (c3 <= 1.0 + tol)
    np.clip(c3, -1.0, 1.0, out=c3)
    s3_abs = np.sqrt((1.0 - c3) * (1.0 + c3))
    t3_abs = np.arctan2(s3_abs, c3)
    t3_min = np.minimum(t3_abs, _PI - t3_abs)
    ok2r = ok2 & reach3
    sing_elbow = (ok2r & (t3_min < flag)).any(axis=(0, 1))
    ok = np.stack([ok2r, ok2r & (t3_min > collapse)], axis=2)                    # (2, 2, 2, N)
    t3 = np.stack([t3_abs, -t3_abs], axis=2)
    phi, beta = np.arctan2(Y, X), np.arctan2(g.a3 * s3_abs, g.a2 + g.a3 * c3)  # atan2 is odd in its first argument
    t2 = np.stack([phi - beta, phi + beta], axis=2)
    t4 = t234[:, :, None] - t2 - t3
    # the joint values, each at its own branch shape, wrapped into (−π, π]
    o = g.offsets
    if any(o):
        q1, q5, q6 = _wrap(t1 - o[0]), _wrap(t5 - o[4]), _wrap(t6 - o[5])
        q2, q3, q4 = _wrap(t2 - o[1]), _wrap(t3 - o[2]), _wrap(t4 - o[3])
    else:  # t3, t5, t6 are in (−π, π] already (atan2, and −π only in a slot that is left out)
        q1, q2, q3, q4, q5, q6 = _wrap(t1), _wrap(t2), t3, _wrap(t4), t5, t6
    dp, dr = _slot_residuals(g, (q1, q2, q3, q4, q5, q6), r11, r12, r13, px, r21, r22, r23, py, r31, r32, r33, pz)
    good = ok & (dp <= 1e3 * tol * g.scale + 1e-12) & (dr <= 1e3 * tol + 1e-12)
    slots = np.empty((6, 2, 2, 2, N))
    slots[0], slots[1], slots[2], slots[3] = q1[:, None, None], q2, q3, q4
    slots[4], slots[5] = q5[:, :, None], q6[:, :, None]
    good = good.reshape(8, N)  # slot-major, as the result stores it
    inside = good  # every angle in (−π, π] is within the limits ±2π
    valid = inside if within_limits else good
    rows = slice(start, start + N)
    solved = out.success[rows]
    np.any(valid, axis=0, out=solved)
    reason = out.reason[rows]
    reason[:] = "solved"
    if not solved.all():
        computed = ok.reshape(8, N).any(axis=0)
        far = (ok2 & ~reach3 & ~(rho2 < (abs(g.a2) + abs(g.a3)) ** 2)).any(axis=(0, 1))
        why = np.where(~reach1, "shoulder_cylinder",
                       np.where(computed, np.where(good.any(axis=0), "joint_limits", "not_verified"),
                                np.where(far, "too_far", "too_close")))
        reason[~solved] = why[~solved]
    blank = np.where(valid, 0.0, np.nan)
    np.add(slots.reshape(6, 8, N), blank, out=out.q[rows].T)
    np.add(dp.reshape(8, N), blank, out=out.position_residual[rows].T)
    np.add(dr.reshape(8, N), blank, out=out.orientation_residual[rows].T)
    out.valid[rows].T[:], out.within_limits[rows].T[:] = valid, inside
    out.singular[rows, 0], out.singular[rows, 1], out.singular[rows, 2] = sing_shoulder, sing_wrist, sing_elbow
    out.wrist_centre[rows, 0], out.wrist_centre[rows, 1], out.wrist_centre[rows, 2] = wx, wy, wz


def _slot_residuals(g: _Geometry, q: tuple[np.ndarray, ...], *T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""Residuals (2, 2, 2, N) of the wrapped joint values against the poses' components ``T`` (12 × (N,)).

    The forward kinematics of the table written out (the product of its DH
    matrices, grouped as the derivation reads it): the flange frame in frame 4,
    :math:`\mathbf{x}_6 = [c_5c_6,\ s_5c_6,\ -s_6]`, :math:`\mathbf{y}_6 = [-c_5s_6,\ -s_5s_6,\ -c_6]`,
    :math:`\mathbf{z}_6 = [-s_5,\ c_5,\ 0]`, :math:`\mathbf{o}_6 = [-d_6s_5,\ d_6c_5,\ d_5]`;
    frame 4 in frame 1 turned by :math:`\theta_{234}` about :math:`\mathbf{z}_1` with origin
    :math:`[a_2c_2 + a_3c_{23},\ a_2s_2 + a_3s_{23},\ d_4]`. It is compared with the target
    seen from frame 1, :math:`\mathbf{A}_1(q_1)^{-1}\,\mathbf{T}` (a rigid motion keeps the
    distances; the per-pose work is done once per shoulder): :math:`\lVert\mathbf{p}_{FK} - \mathbf{p}\rVert`
    and the angle of :math:`\mathbf{R}_{FK}^\top\mathbf{R}` from the Frobenius distance.
    """
    o = g.offsets
    q1, q2, q3, q4, q5, q6 = q
    if any(o):
        q1, q2, q3, q4, q5, q6 = (qi + oi for qi, oi in zip(q, o))
    t23 = q2 + q3
    t234 = t23 + q4
    c1, s1 = _cos_sin(q1)                                                        # (2, N)
    (c5, s5), (c6, s6) = _cos_sin(q5[:, :, None]), _cos_sin(q6[:, :, None])      # (2, 2, 1, N)
    (c2, s2), (c23, s23), (c234, s234) = _cos_sin(q2), _cos_sin(t23), _cos_sin(t234)  # (2, 2, 2, N)

    def seen_from_frame1(k: int, height: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Column k of the target in frame 1: (x1·v, y1·v − height, z1·v); x1 = (c1, s1, 0), z1 = (s1, −c1, 0)."""
        x, y, z = T[k], T[4 + k], T[8 + k]
        return (c1 * x + s1 * y)[:, None, None], z - height, (s1 * x - c1 * y)[:, None, None]

    # column (u, v, w) of frame 4 in frame 1: (u c234 + w s234, u s234 − w c234, v)
    rot2 = np.zeros(t234.shape)
    for k, (u, v, w) in enumerate(((c5 * c6, s5 * c6, -s6), (-c5 * s6, -s5 * s6, -c6), (-s5, c5, None))):
        tx, ty, tz = seen_from_frame1(k, 0.0)
        ex, ey = u * c234, u * s234  # (in place from here: fewer temporaries)
        if w is not None:
            ex += w * s234
            ey -= w * c234
        ex -= tx
        ey -= ty
        ez = v - tz
        rot2 += np.square(ex, out=ex)
        rot2 += np.square(ey, out=ey)
        rot2 += np.square(ez, out=ez)
    tx, ty, tz = seen_from_frame1(3, g.d1)
    ex = g.a2 * c2 + g.a3 * c23 - g.d6 * s5 * c234 + g.d5 * s234 - tx
    ey = g.a2 * s2 + g.a3 * s23 - g.d6 * s5 * s234 - g.d5 * c234 - ty
    ez = g.d6 * c5 + g.d4 - tz
    pos2 = ex * ex
    pos2 += ey * ey
    pos2 += ez * ez
    return np.sqrt(pos2), 2.0 * np.arcsin(np.minimum(np.sqrt(rot2) * _INV_SQRT8, 1.0))
