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
come from one ``cos`` and one ``sin`` call and one small matrix product. A joint
whose variable is :math:`\theta = s q + o` (sign and offset) has them folded into its
constants (:func:`folded_pqr`), so that a configuration needs :math:`\cos q` and
:math:`\sin q` of the joint values themselves.

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

One configuration costs a dozen small numpy calls, and at this size the call, not the
arithmetic, is the cost (a 7×7 product takes about 0.3 µs, and so does making the
views it reads and writes): each engine keeps, per thread, a :class:`Workspace` of
the arrays an evaluation writes into and of the views it needs, made once.

Batches use a column layout ``Tc[j, r, N]`` (column ``j``, row ``r`` of the
top 3×4 part of ``T``): a revolute joint mixes two columns, a prismatic joint
adds to column 3, and a constant block is one BLAS product ``C^T @ Tc``.
The loops run over joints, never over configurations.
"""

from __future__ import annotations

import threading
from typing import NamedTuple

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
# (i, j) of the rows k = 0, 1, 2 of a cross product: (z × d)_k = z_i d_j - z_j d_i
_CROSS_PAIRS = ((1, 2), (2, 0), (0, 1))

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


def folded_pqr(axis: int, revolute: bool, sign: float, offset: float
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`joint_pqr` of a joint whose variable is ``sign * q + offset``, in terms of q itself.

    Revolute, θ = s q + o: cos θ P + sin θ Q = cos q P' + sin q Q' with
    P' = cos o P + sin o Q and Q' = s (cos o Q - sin o P). Prismatic, d = s q + o:
    d P + R = q (s P) + (R + o P). A joint with s = 1, o = 0 keeps P, Q, R exactly.
    """
    P, Q, R = joint_pqr(axis, revolute)
    if sign == 1.0 and offset == 0.0:
        return P, Q, R
    if revolute:
        c, s = np.cos(offset), np.sin(offset)
        return c * P + s * Q, sign * (c * Q - s * P), R
    return sign * P, Q, R + offset * P


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
_POSE_IN_X_4X4 = _POSE_IN_X.reshape(4, 4)   # take() with it gives the (4, 4) pose
_IDENTITY_FLAT = np.eye(4).ravel()


class Workspace:
    """The arrays one single-configuration evaluation of an :class:`Engine` writes into.

    With the views of them it reads and writes, made once (per engine and thread:
    :meth:`Engine.workspace`), so that an evaluation is only the numpy calls that
    compute (``out=``). What an engine method returns is never one of these arrays,
    except :meth:`Engine.screw_frames`' frames (valid until the next evaluation).
    """

    def __init__(self, engine: Engine) -> None:
        n = engine.n
        #: [u_1..u_n, w_1..w_n, 1]: (cos q_i, sin q_i) or (q_i, 0) per joint (:meth:`Engine.coefficients`)
        self.coefficients = np.empty(2 * n + 1)
        self.coefficients[2 * n] = 1.0
        self.cos, self.sin = self.coefficients[:n], self.coefficients[n : 2 * n]
        # fk: the blocks A_1..A_n (E folded into A_n); neighbours multiplied in one stacked product
        self.fk_blocks = np.empty((n, 4, 4))
        self.fk_out = self.fk_blocks.reshape(16 * n) if engine.dense else self.fk_blocks.reshape(n, 16)
        pairs = n // 2
        self.fk_pairs = np.empty((pairs, 4, 4))
        self.fk_left, self.fk_right = self.fk_blocks[0 : 2 * pairs : 2], self.fk_blocks[1 : 2 * pairs : 2]
        factors = [*self.fk_pairs, *([self.fk_blocks[n - 1]] if n % 2 else [])]
        self.fk_first, self.fk_rest = factors[0], tuple(factors[1:])
        # frames: the blocks X(A_1)..X(A_n), X(E) and their running products X(T_1)..X(T_n), X(T_E)
        self.screw_blocks = np.empty((n + 1, 7, 7))
        self.screw_out = self.screw_blocks.reshape(49 * (n + 1)) if engine.dense else self.screw_blocks.reshape(
            n + 1, 49)
        self.frames = np.empty((n + 1, 7, 7))
        self.first_frame, self.first_block = self.frames[0], self.screw_blocks[0]
        self.steps = list(zip(self.frames[:-1], self.screw_blocks[1:], self.frames[1:]))
        # Jacobian: the shift of the reference point (from X(T_E)'s last column) and the screws
        self.frames_flat = self.frames.reshape(49 * (n + 1))
        self.end_flat = self.frames[n].reshape(49)
        self.end_column = self.frames[n][:, 6]
        self.shift = np.empty(36)
        self.shift_matrix = self.shift.reshape(6, 6)
        if engine.same_axis:   # every screw in one column of its frame: a view
            self.screws_T = self.frames[:n, :6, engine.first_screw_column].T
        else:                  # gathered into screws (Engine.end_effector_jacobian)
            self.screws = np.empty((n, 6))
            self.screws_T = self.screws.T


class _BatchJoint(NamedTuple):
    """One joint as the batched pass reads it (:meth:`Engine._batch_pass`)."""

    joint: int  # its index in the chain
    revolute: bool
    axis: int
    a: int  # the column pair a revolute joint mixes (_PAIR)
    b: int
    positive: bool  # sign > 0
    next_const_T: np.ndarray | None  # C_{i+1}^T, None when it is the identity or i is the last joint


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
        blocks = [[(self.consts[i] @ M).ravel()
                   for M in folded_pqr(int(axes[i]), bool(revolute[i]), float(signs[i]), float(offsets[i]))]
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
        #: flat indices of the screws in the frames (n + 1, 7, 7): joint i's rows 0-5 of its column
        self.screw_index = (49 * np.arange(n)[:, None] + 7 * np.arange(6) + self.screw_column[:, None])
        self.sign_column = self.sign[:, None]
        self._local = threading.local()   # this engine's workspaces, one per thread
        self.const_is_identity = [bool(np.array_equal(C, np.eye(4))) for C in self.consts]
        self.consts_T = [np.ascontiguousarray(C.T) for C in self.consts]
        # Batched evaluation: each joint's data as plain Python values, read once per joint and pass
        # (indexing the arrays above costs about as much as one operation on a small batch)
        self.batch_plan = [
            _BatchJoint(i, bool(self.revolute[i]), int(self.axes[i]), *_PAIR[int(self.axes[i])],
                        bool(self.sign[i] > 0),
                        None if i == n - 1 or self.const_is_identity[i + 1] else self.consts_T[i + 1])
            for i in range(n)]

    # ------------------------------------------------------------------ single
    def __getstate__(self) -> dict:
        state = dict(self.__dict__)
        del state["_local"]   # the workspaces: made again where needed
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._local = threading.local()

    def workspace(self) -> Workspace:
        """This thread's :class:`Workspace` of this engine (made on first use)."""
        try:
            return self._local.workspace
        except AttributeError:
            self._local.workspace = Workspace(self)
            return self._local.workspace

    def coefficients(self, q: np.ndarray, w: Workspace) -> None:
        """``w.coefficients`` = ``[u_1..u_n, w_1..w_n, 1]``: ``(cos q_i, sin q_i)`` (revolute) or
        ``(q_i, 0)`` (prismatic) per joint, the blocks holding offsets and signs (:func:`folded_pqr`)."""
        np.cos(q, out=w.cos)   # offsets and signs are folded into the blocks (folded_pqr)
        np.sin(q, out=w.sin)
        if not self.all_revolute:
            p = self.prismatic_idx
            w.coefficients[p] = q[p]
            w.coefficients[self.n + p] = 0.0

    def _blocks(self, v: np.ndarray, M, out: np.ndarray) -> None:
        """The joint blocks ``u_i P_i + w_i Q_i + R_i`` (flat, into ``out``) from the coefficients
        ``v``: one product with the dense ``M``, or the stacked parts ``M`` = (P, Q, R) of a long chain."""
        if self.dense:
            v.dot(M, out=out)
            return
        n, (P, Q, R) = self.n, M
        np.copyto(out, R)
        out[:n] += v[:n, None] * P[:n] + v[n : 2 * n, None] * Q[:n]

    def fk_single(self, q: np.ndarray) -> np.ndarray:
        """(4, 4) end-effector pose: the product ``A_1 A_2 ... A_n`` of the joint blocks
        (neighbours first, in one stacked product, then in order)."""
        w = self.workspace()
        self.coefficients(q, w)
        self._blocks(w.coefficients, self.M_fk if self.dense else self.fk_parts, w.fk_out)
        if len(w.fk_pairs):
            np.matmul(w.fk_left, w.fk_right, out=w.fk_pairs)
        T = w.fk_first
        for factor in w.fk_rest:
            T = T.dot(factor)  # ndarray.dot: half the call cost of @ for one 4×4 product
        return T if w.fk_rest else T.copy()   # never an array of the workspace

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

    def evaluate_frames(self, q: np.ndarray) -> Workspace:
        """This thread's workspace, with ``frames`` (n + 1, 7, 7) = :math:`X(T_i)` of the joint
        frames 1..n and of the end-effector at ``q``: the running products of the blocks
        ``X(A_1), ..., X(A_n), X(E)``, in order."""
        w = self.workspace()
        self.coefficients(q, w)
        self._blocks(w.coefficients, self.M_screw if self.dense else self.screw_parts, w.screw_out)
        np.copyto(w.first_frame, w.first_block)
        for previous, block, frame in w.steps:
            previous.dot(block, out=frame)
        return w

    def screw_frames(self, q: np.ndarray) -> np.ndarray:
        """(n + 1, 7, 7): :math:`X(T_i)` of the joint frames 1..n and of the end-effector
        (:meth:`evaluate_frames`; the workspace's array, valid until its next evaluation)."""
        return self.evaluate_frames(q).frames

    def end_effector_jacobian(self, w: Workspace) -> np.ndarray:
        """Geometric Jacobian (6, n) of the end-effector from the frames in ``w``
        (:meth:`evaluate_frames`): :meth:`jacobian_from_screws` without its options."""
        w.end_column.dot(_SHIFT_X, out=w.shift)
        if not self.same_axis:
            w.frames_flat.take(self.screw_index, out=w.screws, mode="clip")  # clip: no buffer
            if not self.unit_sign:
                w.screws *= self.sign_column
        return w.shift_matrix.dot(w.screws_T)

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
        screws = frames.reshape(-1).take(self.screw_index) * self.sign_column
        J = shift.reshape(6, 6).dot(screws.T)
        if m < n:
            J[:, m:] = 0.0
        return J

    def jacobian_single(self, q: np.ndarray, upto: int | None = None, point=None) -> np.ndarray:
        """Geometric Jacobian (6, n); ``upto`` = frame index (n+1 = end-effector)."""
        if upto == 0:
            return np.zeros((6, self.n))
        w = self.evaluate_frames(q)
        if point is None and (upto is None or upto == self.n + 1):
            return self.end_effector_jacobian(w)
        return self.jacobian_from_screws(w.frames, upto, point)

    def pose_and_jacobian_single(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """End-effector pose (4, 4) and Jacobian (6, n) from one pass over the chain."""
        w = self.evaluate_frames(q)
        return w.end_flat.take(_POSE_IN_X_4X4), self.end_effector_jacobian(w)

    # ------------------------------------------------------------------- batch
    def _batch_pass(self, Q: np.ndarray, record: str | None, upto: int | None = None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Propagate the column layout through the chain.

        record: None (final pose only), 'frames' (all frames), 'jac' (p_i, z_i).
        Returns final Tc (4, 3, N) and the recorded data (frames, P, Z; empty when not recorded).

        A revolute joint about axis k mixes the columns (a, b) of the running pose:
        ``T_a <- c T_a + s T_b``, ``T_b <- c T_b - s T_a`` (old ``T_a``), written into two
        scratch arrays made once per pass (the same operations, in the same order, as with
        temporaries: the same numbers to the last bit).
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
        record_frames, record_jac = record == "frames", record == "jac"
        if record_frames:
            frames = np.empty((N, n + 2, 4, 4))
            frames[:, 0] = np.eye(4)
            frames[:, :, 3, :] = (0.0, 0.0, 0.0, 1.0)
        elif record_jac:
            P = np.empty((n, 3, N))
            Z = np.empty((n, 3, N))
        stop = n if upto is None else min(upto, n)
        mixed = np.empty((3, N))    # c T_a + s T_b
        scratch = np.empty((3, N))  # s T_b
        multiply, add, subtract = np.multiply, np.add, np.subtract
        for i, revolute, k, a, b, positive, next_const_T in self.batch_plan[:stop]:
            if revolute:
                c = cosT[i]
                s = sinT[i]
                Ta = Tc[a]
                Tb = Tc[b]
                multiply(Ta, c, out=mixed)
                multiply(Tb, s, out=scratch)
                add(mixed, scratch, out=mixed)
                multiply(Tb, c, out=Tb)
                multiply(Ta, s, out=Ta)
                subtract(Tb, Ta, out=Tb)
                Ta[...] = mixed
            else:
                Tc[3] += Tc[k] * thT[i]
            if record_frames:
                frames[:, i + 1, :3, :] = Tc.transpose(2, 1, 0)
            elif record_jac:
                P[i] = Tc[3]
                if positive:
                    Z[i] = Tc[k]
                else:
                    np.negative(Tc[k], out=Z[i])
            if i < stop - 1 and next_const_T is not None:
                Tc = (next_const_T @ Tc.reshape(4, 3 * N)).reshape(4, 3, N)
        if upto is None or upto == n + 1:
            Tc = (self.consts_T[n] @ Tc.reshape(4, 3 * N)).reshape(4, 3, N)
            if record_frames:
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
            scratch = np.empty((m, Tc.shape[2]))
            for row, (first, second) in enumerate(_CROSS_PAIRS):  # row k of z × d, in place
                np.multiply(Zm[:, first], d[:, second], out=Jt[row])
                np.multiply(Zm[:, second], d[:, first], out=scratch)
                np.subtract(Jt[row], scratch, out=Jt[row])
            Jt[3:] = Zm.transpose(1, 0, 2)
            for j in self.prismatic_idx:
                if j < m:
                    Jt[:3, j] = Z[j]
                    Jt[3:, j] = 0.0
            out[s : s + self.CHUNK, :, :m] = Jt.transpose(2, 0, 1)
        return out
