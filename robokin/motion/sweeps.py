r"""Initial-condition sweeps and batched resolved-rate tracking.

Two small pieces for studying how a redundant arm's motion depends on where
it starts:

- :func:`initial_condition_sweep` builds the start configurations of a
  one-joint-at-a-time sweep: every joint at a nominal fraction of its range,
  one joint at a time moved through a list of fractions;
- :func:`track_position_batch` runs the resolved-rate (closed-loop inverse
  kinematics) law for the position of the end-effector from many start
  configurations at once, vectorised over the runs:

.. math::
    \dot{\mathbf q}_k = \mathbf J_v^{+}(\mathbf q_k)\,
        \big(\dot{\mathbf r}_{des}(t_k) + K\,(\mathbf r_{des}(t_k) - \mathbf r(\mathbf q_k))\big),
    \qquad
    \mathbf q_{k+1} = \operatorname{sat}(\mathbf q_k + t_s\,\dot{\mathbf q}_k)

(Siciliano et al. 2009, §3.7.1, with the position Jacobian; ``K = 0``
is the open-loop integration of :math:`\mathbf J_v^+\dot{\mathbf r}_{des}`, which
drifts). For one run it reproduces :func:`robokin.motion.simulate` with a
position-only :class:`~robokin.motion.CartesianController`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robokin.chains.protocol import Chain
from robokin.errors import DomainError, ShapeError, SingularityWarning
from robokin.motion._kernels import generic_rank
from robokin.motion.control import SINGULAR_THRESHOLD
from robokin.motion.simulate import singularity_message
from robokin.validation import (
    as_float_array,
    check_chain,
    check_choice,
    check_limits,
    check_positive,
    check_result_finite,
)

__all__ = ["initial_condition_sweep", "track_position_batch", "BatchTrackingLog"]


def initial_condition_sweep(limits: Any, fractions: Any, nominal: Any = 0.5) -> np.ndarray:
    r"""Start configurations that move one joint at a time through its range.

    Row ``j * N + i`` (joint ``j``, value ``i``) is the nominal configuration
    with joint ``j`` replaced by

    .. math::  q_j = q_{j,\min} + f_i\,(q_{j,\max} - q_{j,\min}),

    so the result is the "AnglesInit" matrix of a sweep, one configuration per
    row.

    Parameters
    ----------
    limits : array_like, shape (n, 2)
        Finite joint limits ``(lower, upper)`` (rad or m).
    fractions : array_like, shape (N,)
        Fractions :math:`f_i` of each joint's range, in [0, 1] (a fraction
        outside [0, 1] would start the joint outside its limits).
    nominal : float or array_like (n,), optional
        Fraction(s) of the range for the joints that are not swept (default
        0.5: the middle of every range), in [0, 1].

    Returns
    -------
    ndarray, shape (n * N, n)
        Start configurations.

    Raises
    ------
    ShapeError
        ``limits`` not (n, 2), ``fractions`` not 1-D and non-empty, ``nominal``
        neither a scalar nor (n,).
    DomainError
        Infinite limits, fractions or nominal outside [0, 1].

    Examples
    --------
    >>> initial_condition_sweep([[-1, 1], [0, 2]], [0.25, 0.75])
    array([[-0.5,  1. ],
           [ 0.5,  1. ],
           [ 0. ,  0.5],
           [ 0. ,  1.5]])
    """
    lim = check_limits(limits, None, "limits")
    if not np.all(np.isfinite(lim)):
        raise DomainError("limits must be finite to sweep a fraction of each range; got an infinite limit")
    n = lim.shape[0]
    f = as_float_array(fractions, "fractions")
    if f.ndim != 1 or f.size == 0:
        raise ShapeError(f"fractions must have shape (N,) with N >= 1; got shape {f.shape}")
    if np.any(f < 0) or np.any(f > 1):
        i = int(np.argmax((f < 0) | (f > 1)))
        raise DomainError(f"fractions must lie in [0, 1] (else the start is outside the joint limits); "
                          f"got fractions[{i}] = {f[i]:g}")
    nom = as_float_array(nominal, "nominal")
    if nom.ndim == 0:
        nom = np.full(n, float(nom))
    elif nom.shape != (n,):
        raise ShapeError(f"nominal must be a scalar or have shape ({n},); got shape {nom.shape}")
    if np.any(nom < 0) or np.any(nom > 1):
        raise DomainError(f"nominal must lie in [0, 1]; got {nom}")
    with np.errstate(all="ignore"):
        lower, span = lim[:, 0], lim[:, 1] - lim[:, 0]
        base = lower + nom * span
        out = np.tile(base, (n * f.size, 1))
        for j in range(n):
            out[j * f.size:(j + 1) * f.size, j] = lower[j] + f * span[j]
    return check_result_finite(out, "the joint ranges", limits=lim)


#: The default of :class:`BatchTrackingLog`'s ``singular`` until ``__post_init__`` replaces it by the
#: steps' flags (a marker, compared by identity, never kept in a log).
_NOT_LOGGED = np.empty(0, dtype=bool)


@dataclass(frozen=True, eq=False)
class BatchTrackingLog:
    """Arrays logged by :func:`track_position_batch` (N runs, K samples each).

    Attributes
    ----------
    t : ndarray, shape (K,)
        Times (s), ``t[k] = k * ts``.
    q : ndarray, shape (N, K, n)
        Configurations.
    qdot : ndarray, shape (N, K, n)
        Commanded joint velocities :math:`\\dot q_k` (before clamping to the limits).
    position : ndarray, shape (N, K, 3)
        End-effector positions :math:`\\mathbf r(\\mathbf q_k)` (m).
    error : ndarray, shape (N, K, 3)
        :math:`\\mathbf r_{des}(t_k) - \\mathbf r(\\mathbf q_k)` (m).
    singular_values : ndarray, shape (N, K, min(3, n))
        Singular values of the position Jacobian, largest first (m/rad);
        ``min(3, n)`` of them.
    at_limit : ndarray of bool, shape (N, K, n)
        Joints resting on a limit.
    singular : ndarray of bool, shape (N, K)
        Samples flagged as (close to) singular: the smallest singular value of
        :math:`J_v` that is non-zero at a generic configuration,
        ``singular_values[..., task_rank - 1]`` (:attr:`sigma_min` for a spatial
        arm), below ``singular_threshold``. There the pseudoinverse commands
        joint rates up to ``|v| / sigma_min``.
    singular_threshold : float
        The threshold used for ``singular`` (m/rad).
    task_rank : int
        Rank of :math:`J_v` at a generic configuration (3 for a spatial arm, 2
        for a planar one, whose z row is always zero).
    """

    t: np.ndarray
    q: np.ndarray
    qdot: np.ndarray
    position: np.ndarray
    error: np.ndarray
    singular_values: np.ndarray
    at_limit: np.ndarray
    singular: np.ndarray = field(default_factory=lambda: _NOT_LOGGED)
    singular_threshold: float = SINGULAR_THRESHOLD
    task_rank: int | None = None

    def __post_init__(self) -> None:
        rank = self.singular_values.shape[-1] if self.task_rank is None else self.task_rank
        if self.task_rank is None:
            object.__setattr__(self, "task_rank", rank)
        if self.singular is _NOT_LOGGED:   # not given: flagged by the threshold
            s = self.singular_values[..., rank - 1]
            object.__setattr__(self, "singular", s < self.singular_threshold)

    @property
    def position_error(self) -> np.ndarray:
        """Norm of the position error (m), shape (N, K)."""
        return np.linalg.norm(self.error, axis=-1)

    @property
    def sigma_min(self) -> np.ndarray:
        """Smallest singular value of the position Jacobian (m/rad), shape (N, K)."""
        return self.singular_values[..., -1]

    @property
    def manipulability(self) -> np.ndarray:
        r"""Yoshikawa manipulability :math:`\sqrt{\det J_v J_v^T} = \sigma_1\sigma_2\sigma_3`, shape (N, K)."""
        return np.prod(self.singular_values, axis=-1)


#: Largest condition number sigma_max / sigma_min of J_v for which a step goes through the
#: eigen-decomposition of J_v J_v^T: its rounding error grows as the condition number
#: squared, so at most about 1e4 * eps relative here; worse-conditioned rows use the SVD.
GRAM_MAX_CONDITION = 100.0


def _rates_and_singular_values(
    J: np.ndarray, v: np.ndarray, rcond: float, damping: float | None, gram: bool
) -> tuple[np.ndarray, np.ndarray]:
    r"""Joint rates :math:`\mathbf J^{\#}\mathbf v` and the singular values of each J.

    ``J`` (N, 3, n), ``v`` (N, 3) -> rates (N, n) and singular values (N, min(3, n)),
    largest first. :math:`\mathbf J^{\#} = \mathbf V\boldsymbol\Sigma^{\#}\mathbf U^T`
    with :math:`\sigma^{\#} = 1/\sigma` (pseudoinverse; 0 for :math:`\sigma` below
    ``rcond`` times the largest) or :math:`\sigma/(\sigma^2 + \lambda^2)` (damped least
    squares, ``damping`` :math:`\lambda`; None for the pseudoinverse).

    With ``gram`` (J of full row rank 3 at a generic configuration), since
    :math:`\mathbf J\mathbf J^T = \mathbf U\boldsymbol\Sigma^2\mathbf U^T` and
    :math:`\mathbf V = \mathbf J^T\mathbf U\boldsymbol\Sigma^{-1}`, the same rates are
    :math:`\mathbf J^T\mathbf U\,g(\boldsymbol\Sigma^2)\,\mathbf U^T\mathbf v` with
    :math:`g = 1/\sigma^2` or :math:`1/(\sigma^2 + \lambda^2)`: from the
    eigen-decomposition of the 3×3 matrix :math:`\mathbf J\mathbf J^T`, about half the
    cost of the SVD of J for a batch. Its rounding error grows as the condition number
    squared, so the runs whose J is worse conditioned than ``GRAM_MAX_CONDITION``
    (near a singularity) take the SVD of J instead.
    """

    def from_svd(J: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        U, s, Vt = np.linalg.svd(J, full_matrices=False)  # (N,3,3), (N,3), (N,3,n)
        if damping is not None:
            inv_s = s / (s**2 + damping * damping)  # σ / (σ² + λ²)
        else:
            inv_s = np.where(s > rcond * s[:, :1], 1.0 / s, 0.0)  # 1/σ, 0 below the cut-off
        y = np.einsum("nji,nj->ni", U, v) * inv_s  # Σ^# Uᵀ v
        return np.einsum("nij,ni->nj", Vt, y), s  # V y

    if not gram:
        return from_svd(J, v)
    Jt = np.swapaxes(J, 1, 2)
    w, U = np.linalg.eigh(J @ Jt)  # σ² in ascending order, U
    w, U = w[:, ::-1], U[:, :, ::-1]  # largest first, as the SVD
    s = np.sqrt(np.maximum(w, 0.0))
    if damping is not None:
        g = 1.0 / (w + damping * damping)  # 1 / (σ² + λ²)
    else:
        g = np.where(s > rcond * s[:, :1], 1.0 / w, 0.0)  # 1/σ², 0 below the cut-off
    y = np.einsum("nji,nj->ni", U, v) * g  # g(Σ²) Uᵀ v
    rates = np.einsum("nij,nj->ni", Jt, np.einsum("nij,nj->ni", U, y))  # Jᵀ U y
    ill = s[:, 2] * GRAM_MAX_CONDITION < s[:, 0]
    if ill.any():
        rates[ill], s[ill] = from_svd(J[ill], v[ill])
    return rates, s


#: Up to this many runs the kinematics are evaluated one configuration at a time: the
#: batch code is built for many rows, and a batch of a few rows costs more than a few
#: single-configuration calls (about 5 of them).
SINGLE_CONFIGURATION_RUNS = 4


def _positions_and_jacobians(chain: Chain, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """End-effector positions (N, 3) and position Jacobians (N, 3, n) at ``Q`` (N, n)."""
    if 0 < Q.shape[0] <= SINGLE_CONFIGURATION_RUNS:  # (no runs: the batch code gives the empty shapes)
        r = np.array([chain.fk(q, check=False)[:3, 3] for q in Q])
        J = np.array([chain.position_jacobian(q, check=False) for q in Q])
        return r, J
    T, J = chain.fk_and_jacobian(Q, check=False)  # one pass: the same numbers as fk and jacobian
    return T[:, :3, 3], J[:, :3, :]


def _per_run(a: np.ndarray, N: int, K: int, name: str) -> np.ndarray:
    if a.shape == (K, 3):
        return np.broadcast_to(a, (N, K, 3))
    if a.shape == (N, K, 3):
        return a
    raise ShapeError(f"{name} must have shape ({K}, 3) or ({N}, {K}, 3); got shape {a.shape}")


def track_position_batch(
    chain: Chain,
    q0: Any,
    ts: float,
    positions: Any,
    velocities: Any,
    *,
    gain: float = 0.0,
    inverse: str = "pinv",
    damping: float = 0.01,
    rcond: float = 1e-8,
    clamp: bool = True,
    singular_threshold: float = SINGULAR_THRESHOLD,
    warn_singular: bool = True,
) -> BatchTrackingLog:
    r"""Resolved-rate position tracking from N start configurations at once.

    For every run and every sample ``k = 0 … K−1``

    .. math::
        \dot{\mathbf q}_k = \mathbf J_v^{\#}(\mathbf q_k)\big(\dot{\mathbf r}_{des,k}
            + K(\mathbf r_{des,k} - \mathbf r(\mathbf q_k))\big),\qquad
        \mathbf q_{k+1} = \operatorname{sat}(\mathbf q_k + t_s\dot{\mathbf q}_k),

    where :math:`\mathbf J_v^{\#}` is the pseudoinverse
    :math:`\mathbf V\boldsymbol\Sigma^{+}\mathbf U^T` (singular values below
    ``rcond`` times the largest set to zero) or the damped least-squares
    inverse :math:`\mathbf J_v^T(\mathbf J_v\mathbf J_v^T + \lambda^2\mathbf I)^{-1}`
    (Siciliano et al. 2009, §3.7.1 and eq. 3.59), both from the singular value
    decomposition :math:`\mathbf J_v = \mathbf U\boldsymbol\Sigma\mathbf V^T`
    (which also gives the singular values that are logged). For a spatial arm
    the step is computed from the eigen-decomposition
    :math:`\mathbf J_v\mathbf J_v^T = \mathbf U\boldsymbol\Sigma^2\mathbf U^T`
    (the same :math:`\mathbf U` and :math:`\boldsymbol\Sigma`, at half the cost), and
    from the SVD of :math:`\mathbf J_v` itself where :math:`\mathbf J_v` is worse
    conditioned than ``sigma_max / sigma_min = 100`` (near a singularity).

    Parameters
    ----------
    chain : SerialChain
        Offers ``n``, ``limits``, ``fk(q, check=False)`` and
        ``position_jacobian(q, check=False)`` for one configuration (n,), and
        ``fk_and_jacobian(Q, check=False)`` for a batch (N, n) (up to 4 runs
        are evaluated one configuration at a time, more as a batch).
    q0 : array_like, shape (n,) or (N, n)
        Start configuration(s), within the joint limits when ``clamp``.
    ts : float
        Time step (s), > 0.
    positions, velocities : array_like, shape (K, 3) or (N, K, 3)
        Reference :math:`\mathbf r_{des}(t_k)` (m) and :math:`\dot{\mathbf r}_{des}(t_k)`
        (m/s), shared by all runs or one per run (e.g. a circle that starts
        where each run's hand is). K >= 1 samples.
    gain : float, optional
        Position gain :math:`K` (1/s), >= 0. 0 (default) integrates
        :math:`\mathbf J_v^+\dot{\mathbf r}_{des}` open loop.
    inverse : {"pinv", "dls"}, optional
        Pseudoinverse (default) or damped least squares.
    damping : float, optional
        :math:`\lambda` (m) for ``"dls"``, >= 0.
    rcond : float, optional
        Relative cut-off of small singular values for ``"pinv"``, > 0.
    clamp : bool, optional
        Clamp each step to the joint limits (as :func:`robokin.motion.simulate`).
    singular_threshold : float, optional
        Flag the samples whose smallest singular value of :math:`\mathbf J_v` is
        below this value (m/rad, default 1e-3, as
        :class:`~robokin.motion.CartesianController`), >= 0; 0 flags nothing.
    warn_singular : bool, optional
        Issue one :class:`~robokin.errors.SingularityWarning` for the whole
        sweep when any sample of any run is flagged (default True); the
        standard ``warnings`` filters silence it too.

    Returns
    -------
    BatchTrackingLog
        ``q``, ``qdot``, ``position``, ``error``, ``singular_values``,
        ``at_limit`` and the flags ``singular`` (N, K) with a leading run axis N
        (1 for a single ``q0``); ``sigma_min`` is the smallest singular value.

    Raises
    ------
    ShapeError
        ``q0``, ``positions`` or ``velocities`` of the wrong shape.
    DomainError
        ``ts`` not positive, negative ``gain``, ``damping`` or
        ``singular_threshold``, ``q0`` outside the limits (with ``clamp``),
        non-finite inputs.
    TypeError
        ``chain`` is not a kinematic chain.

    Warns
    -----
    SingularityWarning
        Once per call, when some run passes within ``singular_threshold`` of a
        singular configuration (how many runs, where, the peak joint speed).
    """
    check_chain(chain, "chain", ("fk", "position_jacobian"))
    n = int(chain.n)
    Q = as_float_array(q0, "q0")
    if Q.shape == (n,):
        Q = Q[None, :]
    elif Q.ndim != 2 or Q.shape[1] != n:
        raise ShapeError(f"q0 must have shape ({n},) or (N, {n}); got shape {Q.shape}")
    Q = Q.copy()
    N = Q.shape[0]
    ts = check_positive(ts, "ts", scalar=True)
    gain = check_positive(gain, "gain", allow_zero=True, scalar=True)
    check_choice(inverse, ("pinv", "dls"), "inverse")
    lam = check_positive(damping, "damping", allow_zero=True, scalar=True)
    rcond = check_positive(rcond, "rcond", scalar=True)
    threshold = check_positive(singular_threshold, "singular_threshold", allow_zero=True, scalar=True)
    P = as_float_array(positions, "positions")
    V = as_float_array(velocities, "velocities")
    if P.ndim not in (2, 3) or P.shape[-1] != 3 or P.shape[-2] < 1:
        raise ShapeError(f"positions must have shape (K, 3) or (N, K, 3) with K >= 1; got shape {P.shape}")
    K = P.shape[-2]
    P = _per_run(P, N, K, "positions")
    V = _per_run(V, N, K, "velocities")
    lim = check_limits(chain.limits, n, "chain.limits")
    lower, upper = lim[:, 0], lim[:, 1]
    if clamp:
        bad = (Q < lower - 1e-12) | (Q > upper + 1e-12)
        if bad.any():
            run, j = (int(i) for i in np.argwhere(bad)[0])
            raise DomainError(f"q0 must lie within the joint limits; q0[{run}, {j}] = {Q[run, j]:g} is outside "
                              f"[{lower[j]:g}, {upper[j]:g}]")

    with np.errstate(all="ignore"):
        t = check_result_finite(np.arange(K) * ts, "the sample times k * ts", ts=ts)
    q_log = np.empty((N, K, n))
    qd_log = np.empty((N, K, n))
    r_log = np.empty((N, K, 3))
    s_log = np.empty((N, K, min(3, n)))
    dls_damping = lam if inverse == "dls" and lam > 0 else None  # None: the pseudoinverse
    rank = generic_rank(lambda Q_: chain.position_jacobian(Q_, check=False), lower, upper)
    gram = rank == 3  # J_v J_v^T invertible at a generic configuration
    # One errstate for the whole loop (entering it costs as much as a small array operation):
    # an overflow (references near 1e308) is caught below, by an error that names the inputs.
    with np.errstate(all="ignore"):
        for k in range(K):
            r, J = _positions_and_jacobians(chain, Q)
            v_cmd = V[:, k] + gain * (P[:, k] - r)
            qdot, s = _rates_and_singular_values(J, v_cmd, rcond, dls_damping, gram)
            q_log[:, k], qd_log[:, k], r_log[:, k], s_log[:, k] = Q, qdot, r, s
            if k < K - 1:
                Q = Q + ts * qdot
                if not np.isfinite(Q).all():  # references near 1e308: the step overflowed
                    check_result_finite(Q, "the joint step ts * qdot", positions=P, velocities=V, gain=gain)
                if clamp:
                    Q = np.minimum(np.maximum(Q, lower), upper)
    check_result_finite(qd_log, "the joint velocities", positions=P, velocities=V, gain=gain)
    at_limit = (q_log <= lower) | (q_log >= upper)
    log = BatchTrackingLog(
        t=t, q=q_log, qdot=qd_log, position=r_log, error=P - r_log,
        singular_values=s_log, at_limit=at_limit, singular_threshold=threshold, task_rank=rank,
    )
    singular = log.singular
    if warn_singular and singular.any():
        hit = int(singular.any(axis=1).sum())
        warnings.warn(SingularityWarning(singularity_message(
            "track_position_batch", log.t, log.singular_values[..., rank - 1], singular, log.qdot, threshold,
            damped=dls_damping is not None, runs=f"{hit} of {N} run{'s' if N > 1 else ''}, ")),
            stacklevel=2)
    return log
