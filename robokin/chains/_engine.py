r"""Numeric engine of :class:`~robokin.chains.SerialChain` (private).

The elementary-transform sequence is compiled once into constant blocks:

.. math::

    T(q) = C_0\, J_1(q_1)\, C_1\, J_2(q_2) \cdots J_n(q_n)\, C_n\, T_{tool}

with constant 4×4 matrices :math:`C_i` (products of the constant elements
between joints). A joint element about axis k satisfies

.. math::

    C_{i-1} J_i(\theta) = \cos\theta\, P_i + \sin\theta\, Q_i + R_i
    \quad\text{(revolute)},\qquad
    C_{i-1} J_i(d) = d\, P_i + R_i \quad\text{(prismatic)},

with constant :math:`P_i, Q_i, R_i`, so all joint blocks of one configuration
come from one ``cos`` and one ``sin`` call and one small matrix product.

The single-configuration Jacobian uses the same blocks in a 7×7 form that
carries, besides the pose, the *moment* of every joint axis (Lynch & Park
2017, §3.3.2 and §5.1.1): for a pose :math:`T = (R, p)`

.. math::

    X(T) = \begin{bmatrix} R & [p]R & p \\ 0 & R & 0 \\ 0 & 0 & 1 \end{bmatrix},
    \qquad X(T_1 T_2) = X(T_1)\, X(T_2),

whose top-left 6×6 part is the adjoint map :math:`\mathrm{Ad}_T` (rows
``[v; ω]``). :math:`X(C_{i-1}J_i)` is again linear in ``(cos θ, sin θ, 1)``,
so the blocks come from one product, and the running products :math:`X_i =
X(T_i)` of the joint frames give the space Jacobian (Lynch & Park 2017, §5.1.1) as
one column of each: :math:`\mathrm{Ad}_{T_i}[0; e_k] = [p_i \times z_i;\, z_i]`
(revolute about axis k), :math:`\mathrm{Ad}_{T_i}[e_k; 0] = [z_i; 0]`
(prismatic). The geometric Jacobian of the end-effector point :math:`p_E`
follows by moving the reference point, :math:`J_v = J_{s,v} - [p_E] J_ω`, i.e.
:math:`z_i \times (p_E - p_i)` (Siciliano et al. 2009, eq. 3.30), with no
per-joint cross product.

Batches use a column layout ``Tc[j, r, N]`` (column ``j``, row ``r`` of the
top 3×4 part of ``T``): a revolute joint mixes two columns, a prismatic joint
adds to column 3, and a constant block is one BLAS product ``C^T @ Tc``.
The loops run over joints, never over configurations.
"""

from __future__ import annotations

import numpy as np

#: Chains with at most this many joints keep their blocks in one dense matrix (:class:`Engine`).
DENSE_JOINTS = 32


def _block_diagonal(parts: np.ndarray, n: int) -> np.ndarray:
    """(2n + 1, k m): the stacked parts (3, k, m) = (P, Q, R) of k blocks of m entries (k = n, or
    n + 1 with a constant last block) laid out so that ``[u_1..u_n, w_1..w_n, 1] · M`` gives every
    block u_i P_i + w_i Q_i + R_i, each in its own m columns."""
    _, k, m = parts.shape
    M = np.zeros((2 * n + 1, k * m))
    for i in range(n):
        M[i, m * i : m * i + m] = parts[0, i]
        M[n + i, m * i : m * i + m] = parts[1, i]
    M[2 * n] = parts[2].ravel()
    return M


# (a, b) column pair mixed by a rotation about axis k: R[a,a]=R[b,b]=c, R[b,a]=s, R[a,b]=-s
_PAIR = {0: (1, 2), 1: (2, 0), 2: (0, 1)}

def _cos_sin(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""cos and sin of a large array via the half-angle tangent.

    NumPy's float64 ``tan`` is vectorised (SIMD) while ``sin``/``cos`` are not,
    so :math:`t = \tan(\theta/2)`, :math:`\cos\theta = (1-t^2)/(1+t^2)`,
    :math:`\sin\theta = 2t/(1+t^2)` is about 3× faster for big batches and
    accurate to a few ulp (at θ = ±π, t ≈ 1.6e16 still gives cos = −1, sin ≈ 1e-16).
    """
    t = np.multiply(theta, 0.5)
    np.tan(t, out=t)
    t2 = t * t
    inv = t2 + 1.0
    np.divide(1.0, inv, out=inv)
    c = np.subtract(1.0, t2, out=t2)
    c *= inv
    t *= inv
    t *= 2.0
    return c, t


def joint_pqr(axis: int, revolute: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Constant matrices with J(θ) = u P + w Q + R, (u, w) = (cos θ, sin θ) or (d, 0)."""
    P = np.zeros((4, 4))
    Q = np.zeros((4, 4))
    R = np.eye(4)
    if revolute:
        a, b = _PAIR[axis]
        P[a, a] = P[b, b] = 1.0
        Q[b, a] = 1.0
        Q[a, b] = -1.0
        R[a, a] = R[b, b] = 0.0
    else:
        P[axis, 3] = 1.0
    return P, Q, R


def _skew(p: np.ndarray) -> np.ndarray:
    """(3, 3) matrix ``[p]`` with ``[p] x = p × x``."""
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def screw_form(B: np.ndarray, R0: np.ndarray, p0: np.ndarray, constant: bool) -> np.ndarray:
    """(7, 7) part of :math:`X(A)` contributed by the (4, 4) part ``B`` of ``A = u P + w Q + R``.

    ``R0``, ``p0``: rotation and translation of the constant part ``R``. A
    revolute block has ``P``, ``Q`` without translation, a prismatic one
    without rotation, so :math:`[p]R` has no product of two variable parts and
    is linear: the part of ``B`` is :math:`[p_B] R_0 + [p_0] R_B` (and
    :math:`[p_0] R_0` for the constant part).
    """
    RB, pB = B[:3, :3], B[:3, 3]
    X = np.zeros((7, 7))
    X[:3, :3] = X[3:6, 3:6] = RB
    X[:3, 6] = pB
    if constant:
        X[:3, 3:6] = _skew(p0) @ R0
        X[6, 6] = 1.0
    else:
        X[:3, 3:6] = _skew(pB) @ R0 + _skew(p0) @ RB
    return X


#: Rows of the constant map p -> [[I, -[p]], [0, I]] (flattened 6×6): the shift of a Jacobian's
#: reference point from the base origin to p (v' = v + ω × p = v - [p] ω).
_SHIFT = np.zeros((3, 36))
for _r, _c, _k, _v in [(0, 4, 2, 1), (0, 5, 1, -1), (1, 3, 2, -1), (1, 5, 0, 1), (2, 3, 1, 1), (2, 4, 0, -1)]:
    _SHIFT[_k, _r * 6 + _c] = _v  # -[p][r, c - 3] = coefficient of p_k
#: The same map applied to a 7×7 form's last column (p, 0, 0, 0, 1): rows 0-2 as _SHIFT, row 6 the identity.
_SHIFT_X = np.zeros((7, 36))
_SHIFT_X[:3] = _SHIFT
_SHIFT_X[6] = np.eye(6).ravel()
#: Flat indices of the pose (4, 4) inside X(T) (7, 7): rows 0-2 of columns 0-2 and 6, then (0, 0, 0, 1).
_POSE_IN_X = np.array([0, 1, 2, 6, 7, 8, 9, 13, 14, 15, 16, 20, 42, 43, 44, 48])
_IDENTITY_FLAT = np.eye(4).ravel()


class Engine:
    """Compiled numeric form of a chain (constant blocks and joint data).

    Parameters
    ----------
    consts : list of (4, 4) arrays
        ``[C_0, ..., C_n]``; ``C_n`` already includes the tool.
    axes : sequence of int
        Joint axis indices (0, 1, 2).
    revolute : sequence of bool
    signs, offsets : sequences of float
    """

    def __init__(self, consts, axes, revolute, signs, offsets):
        n = len(axes)
        self.n = n
        self.consts = [np.array(C, dtype=float) for C in consts]
        self.axes = np.array(axes, dtype=int)
        self.revolute = np.array(revolute, dtype=bool)
        self.all_revolute = bool(self.revolute.all())
        self.prismatic_idx = np.flatnonzero(~self.revolute)
        self.sign = np.array(signs, dtype=float)
        self.offset = np.array(offsets, dtype=float)
        self.unit_sign = bool(np.all(self.sign == 1.0))
        self.trivial_map = self.unit_sign and bool(np.all(self.offset == 0.0))
        self.E = self.consts[-1]
        # Single configuration: the joint blocks A_i = C_{i-1} J_i = u_i P_i + w_i Q_i + R_i
        blocks = [[(self.consts[i] @ M).ravel() for M in joint_pqr(int(axes[i]), bool(revolute[i]))]
                  for i in range(n)]
        # fk: the blocks' P, Q, R parts stacked, (3, n, 16); E folded into the last block
        self.fk_parts = np.array(blocks, dtype=float).reshape(n, 3, 16).transpose(1, 0, 2).copy()
        if n:
            for part in self.fk_parts[:, n - 1]:  # the last block's P, Q and R, each times E
                part[:] = (part.reshape(4, 4) @ self.E).ravel()
        # frames and Jacobian: the same blocks in the 7×7 form X(A) (see the module docstring), with
        # X(E) as an extra constant block, (3, n + 1, 49)
        self.screw_parts = np.zeros((3, n + 1, 49))
        for i, (P, Q, R) in enumerate(blocks):
            R4 = R.reshape(4, 4)
            R0, p0 = R4[:3, :3], R4[:3, 3]
            self.screw_parts[0, i] = screw_form(P.reshape(4, 4), R0, p0, False).ravel()
            self.screw_parts[1, i] = screw_form(Q.reshape(4, 4), R0, p0, False).ravel()
            self.screw_parts[2, i] = screw_form(R4, R0, p0, True).ravel()
        self.screw_parts[2, n] = screw_form(self.E, self.E[:3, :3], self.E[:3, 3], True).ravel()
        # Up to DENSE_JOINTS joints, all blocks of a configuration come out of ONE product
        # [u_1..u_n, w_1..w_n, 1] · M (M: (2n + 1, 16 n), each block's entries in its own columns),
        # because a Python-level call costs more than the arithmetic of a block; M grows as n², so
        # longer chains add the stacked parts instead, u_i P_i + w_i Q_i + R_i (linear in n).
        self.dense = n <= DENSE_JOINTS
        if self.dense:
            self.M_fk = _block_diagonal(self.fk_parts, n)
            self.M_screw = _block_diagonal(self.screw_parts, n)
        # Column of X_i holding joint i's screw [p_i × z_i; z_i] (revolute) or [z_i; 0] (prismatic)
        self.screw_column = np.where(self.revolute, 3 + self.axes, self.axes)
        # every screw in the same column with sign +1: the Jacobian gathers one column by a slice
        self.same_axis = bool(np.all(self.screw_column == self.screw_column[0]) and np.all(self.sign == 1.0))
        self.first_screw_column = int(self.screw_column[0])
        self._ar = np.arange(n)
        self.const_is_identity = [bool(np.array_equal(C, np.eye(4))) for C in self.consts]
        self.consts_T = [np.ascontiguousarray(C.T) for C in self.consts]

    # ------------------------------------------------------------------ single
    def _coefficients(self, q: np.ndarray) -> np.ndarray:
        """(2n + 1,) ``[u_1..u_n, w_1..w_n, 1]``: ``(cos θ, sin θ)`` or ``(d, 0)`` per joint."""
        n = self.n
        if self.trivial_map:
            th = q
        else:
            th = q + self.offset if self.unit_sign else q * self.sign + self.offset
        v = np.empty(2 * n + 1)
        np.cos(th, out=v[:n])
        np.sin(th, out=v[n : 2 * n])
        v[2 * n] = 1.0
        if not self.all_revolute:
            p = self.prismatic_idx
            v[p] = th[p]
            v[n + p] = 0.0
        return v

    def _blocks(self, v: np.ndarray, M: np.ndarray) -> np.ndarray:
        """The joint blocks ``u_i P_i + w_i Q_i + R_i`` (flat) from the coefficients ``v``: one
        product with the dense ``M``, or the stacked parts ``M`` = (P, Q, R) of a long chain."""
        if self.dense:
            return v.dot(M)
        n, (P, Q, R) = self.n, M
        out = R.copy()
        out[:n] += v[:n, None] * P[:n] + v[n : 2 * n, None] * Q[:n]
        return out

    def fk_single(self, q: np.ndarray) -> np.ndarray:
        """(4, 4) end-effector pose: the product ``A_1 A_2 ... A_n`` of the joint blocks."""
        n = self.n
        A = self._blocks(self._coefficients(q), self.M_fk if self.dense else self.fk_parts).reshape(n, 4, 4)
        if n == 1:
            return A[0]
        if n >= 4:  # neighbours in one stacked product, then in order: fewer calls
            pairs = A[0 : n - 1 : 2] @ A[1:n:2]
            T = pairs[0]
            for i in range(1, len(pairs)):
                T = T.dot(pairs[i])  # ndarray.dot: half the call cost of @ for one 4×4 product
            return T.dot(A[n - 1]) if n % 2 else T
        T = A[0]
        for i in range(1, n):
            T = T.dot(A[i])
        return T

    def joint_frames_single(self, q: np.ndarray) -> np.ndarray:
        """(n + 1, 4, 4) poses of the joint frames 1..n and of the end-effector."""
        return self.screw_frames(q).reshape(self.n + 1, 49).take(_POSE_IN_X, axis=1).reshape(self.n + 1, 4, 4)

    def frames_single(self, q: np.ndarray) -> np.ndarray:
        """(n + 2, 4, 4): the base (identity), the joint frames 1..n and the end-effector."""
        n = self.n
        out = np.empty((n + 2, 16))
        out[0] = _IDENTITY_FLAT
        self.screw_frames(q).reshape(n + 1, 49).take(_POSE_IN_X, axis=1, out=out[1:])
        return out.reshape(n + 2, 4, 4)

    def screw_frames(self, q: np.ndarray) -> np.ndarray:
        """(n + 1, 7, 7): :math:`X(T_i)` of the joint frames 1..n and of the end-effector.

        The running products of the blocks ``X(A_1), ..., X(A_n), X(E)``, in order.
        """
        n = self.n
        X = self._blocks(self._coefficients(q), self.M_screw if self.dense else self.screw_parts).reshape(n + 1, 7, 7)
        frames = np.empty((n + 1, 7, 7))
        frames[0] = X[0]
        for i in range(1, n + 1):
            frames[i - 1].dot(X[i], out=frames[i])
        return frames

    def jacobian_from_screws(self, frames: np.ndarray, upto: int | None = None, point=None) -> np.ndarray:
        """Geometric Jacobian (6, n) from :meth:`screw_frames`' (n + 1, 7, 7).

        Column i is joint i's screw in the base frame, ``[p_i × z_i; z_i]``
        (revolute) or ``[z_i; 0]`` (prismatic), with its reference point moved
        from the base origin to the target point p: ``v - [p] ω``.
        """
        n = self.n
        if upto is None or upto == n + 1:
            m, Xt = n, frames[n]
        else:
            m, Xt = upto, frames[upto - 1]
        if point is None:  # p = Xt[:3, 6]
            shift = Xt[:, 6].dot(_SHIFT_X)
        else:
            shift = (Xt[:3, :3] @ point + Xt[:3, 6]).dot(_SHIFT) + _SHIFT_X[6]
        if self.same_axis:
            screws = frames[:n, :6, self.first_screw_column]  # (n, 6)
        else:
            screws = frames[self._ar, :6, self.screw_column] * self.sign[:, None]
        J = shift.reshape(6, 6).dot(screws.T)
        if m < n:
            J[:, m:] = 0.0
        return J

    def jacobian_single(self, q: np.ndarray, upto: int | None = None, point=None) -> np.ndarray:
        """Geometric Jacobian (6, n); ``upto`` = frame index (n+1 = end-effector)."""
        if upto == 0:
            return np.zeros((6, self.n))
        return self.jacobian_from_screws(self.screw_frames(q), upto, point)

    def pose_and_jacobian_single(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """End-effector pose (4, 4) and Jacobian (6, n) from one pass over the chain."""
        frames = self.screw_frames(q)
        return frames[self.n].take(_POSE_IN_X).reshape(4, 4), self.jacobian_from_screws(frames)

    # ------------------------------------------------------------------- batch
    def _batch_pass(self, Q: np.ndarray, record: str | None, upto: int | None = None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Propagate the column layout through the chain.

        record: None (final pose only), 'frames' (all frames), 'jac' (p_i, z_i).
        Returns final Tc (4, 3, N) and the recorded data (frames, P, Z; empty when not recorded).
        """
        N = Q.shape[0]
        n = self.n
        th = Q if self.trivial_map else Q * self.sign + self.offset
        thT = np.ascontiguousarray(th.T)  # (n, N)
        cosT, sinT = _cos_sin(thT)
        C0 = self.consts[0]
        Tc = np.empty((4, 3, N))
        Tc[...] = C0[:3, :].T[:, :, None]
        frames: np.ndarray = np.empty(0)
        P: np.ndarray = np.empty(0)
        Z: np.ndarray = np.empty(0)
        if record == "frames":
            frames = np.empty((N, n + 2, 4, 4))
            frames[:, 0] = np.eye(4)
            frames[:, :, 3, :] = (0.0, 0.0, 0.0, 1.0)
        elif record == "jac":
            P = np.empty((n, 3, N))
            Z = np.empty((n, 3, N))
        stop = n if upto is None else min(upto, n)
        for i in range(stop):
            k = int(self.axes[i])
            if self.revolute[i]:
                a, b = _PAIR[k]
                c = cosT[i]
                s = sinT[i]
                Ta = Tc[a]
                Tb = Tc[b]
                new_a = Ta * c
                new_a += Tb * s
                Tb *= c
                Ta *= s
                Tb -= Ta
                Tc[a] = new_a
            else:
                Tc[3] += Tc[k] * thT[i]
            if record == "frames":
                frames[:, i + 1, :3, :] = Tc.transpose(2, 1, 0)
            elif record == "jac":
                P[i] = Tc[3]
                if self.sign[i] > 0:
                    Z[i] = Tc[k]
                else:
                    np.negative(Tc[k], out=Z[i])
            if i < stop - 1 and not self.const_is_identity[i + 1]:
                Tc = (self.consts_T[i + 1] @ Tc.reshape(4, 3 * N)).reshape(4, 3, N)
        if upto is None or upto == n + 1:
            Tc = (self.consts_T[n] @ Tc.reshape(4, 3 * N)).reshape(4, 3, N)
            if record == "frames":
                frames[:, n + 1, :3, :] = Tc.transpose(2, 1, 0)
        return Tc, frames, P, Z

    #: Configurations per chunk in batched evaluation: the working set (4·3·CHUNK
    #: floats per array) then stays in the CPU cache, about 2× faster than whole arrays.
    CHUNK = 8192

    def fk_batch(self, Q: np.ndarray, upto: int | None = None) -> np.ndarray:
        N = Q.shape[0]
        out = np.empty((N, 4, 4))
        out[:, 3, :] = (0.0, 0.0, 0.0, 1.0)
        if upto == 0:
            out[:, :3, :] = np.eye(4)[:3]
            return out
        for s in range(0, N, self.CHUNK):
            Tc, _, _, _ = self._batch_pass(Q[s : s + self.CHUNK], None, upto)
            out[s : s + self.CHUNK, :3, :] = Tc.transpose(2, 1, 0)
        return out

    def pose_and_jacobian_batch(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """End-effector poses (N, 4, 4) and Jacobians (N, 6, n) from one pass over the chain.

        The same numbers as :meth:`fk_batch` and :meth:`jacobian_batch` (the same operations).
        """
        poses = np.empty((Q.shape[0], 4, 4))
        poses[:, 3, :] = (0.0, 0.0, 0.0, 1.0)
        return poses, self.jacobian_batch(Q, poses=poses)

    def frames_batch(self, Q: np.ndarray) -> np.ndarray:
        N = Q.shape[0]
        out = np.empty((N, self.n + 2, 4, 4))
        for s in range(0, N, self.CHUNK):
            _, frames, _, _ = self._batch_pass(Q[s : s + self.CHUNK], "frames")
            out[s : s + self.CHUNK] = frames
        return out

    def jacobian_batch(self, Q: np.ndarray, upto: int | None = None, point=None,
                       poses: np.ndarray | None = None) -> np.ndarray:
        """Geometric Jacobians (N, 6, n); with ``poses`` (N, 4, 4, end-effector only), also
        the poses of the frame, written there from the same pass (as :meth:`fk_batch` gives them)."""
        N = Q.shape[0]
        n = self.n
        out = np.zeros((N, 6, n))
        if upto == 0:
            return out
        m = n if (upto is None or upto == n + 1) else upto
        for s in range(0, N, self.CHUNK):
            Tc, _, P, Z = self._batch_pass(Q[s : s + self.CHUNK], "jac", upto)
            if poses is not None:
                poses[s : s + self.CHUNK, :3, :] = Tc.transpose(2, 1, 0)
            if point is None:
                pt = Tc[3]  # (3, chunk)
            else:
                pt = Tc[3] + point[0] * Tc[0] + point[1] * Tc[1] + point[2] * Tc[2]
            Jt = np.empty((6, m, Tc.shape[2]))
            Zm = Z[:m]
            d = pt[None] - P[:m]  # (m, 3, chunk)
            Jt[0] = Zm[:, 1] * d[:, 2] - Zm[:, 2] * d[:, 1]
            Jt[1] = Zm[:, 2] * d[:, 0] - Zm[:, 0] * d[:, 2]
            Jt[2] = Zm[:, 0] * d[:, 1] - Zm[:, 1] * d[:, 0]
            Jt[3:] = Zm.transpose(1, 0, 2)
            for j in self.prismatic_idx:
                if j < m:
                    Jt[:3, j] = Z[j]
                    Jt[3:, j] = 0.0
            out[s : s + self.CHUNK, :, :m] = Jt.transpose(2, 0, 1)
        return out
