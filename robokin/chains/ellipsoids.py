r"""Statics and the velocity and force ellipsoids of a serial chain.

:func:`static_torques` gives the joint torques with which the end-effector, at rest, exerts a
wrench :math:`\mathbf{w} = [\mathbf{f}; \boldsymbol{\mu}]` on its environment
(Siciliano et al. 2009, §3.8; Lynch & Park 2017, §5.2); with this book's
:math:`\mathbf{J} = [\mathbf{J}_v; \mathbf{J}_\omega]` the wrench is ``[f; μ]`` in that order,
in the base frame, the force applied at the end-effector's origin.

One part of the Jacobian at a time, :math:`\mathbf{J}_p` (:math:`\mathbf{J}_v` or
:math:`\mathbf{J}_\omega`, 3 × n): :func:`velocity_ellipsoid` gives the principal semi-axes and
axes of the velocities reached with :math:`\|\dot{\mathbf{q}}\| \le 1`, :func:`force_ellipsoid`
those of the forces (or moments) balanced with :math:`\|\boldsymbol\tau\| \le 1`
(Siciliano et al. 2009, §3.9; Yoshikawa 1985). The two parts are kept apart: a radius in m/s
and one in rad/s have no common scale. Chapter 9 of the workbook derives them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.chains.protocol import Chain
from robokin.errors import ShapeError
from robokin.validation import as_float_array, check_choice, check_result_finite

__all__ = ["velocity_ellipsoid", "force_ellipsoid", "static_torques", "PARTS"]

#: The rows of the geometric Jacobian each part of an ellipsoid takes.
PARTS = {"position": slice(0, 3), "orientation": slice(3, 6)}


def _part_jacobian(chain: Chain, q: Any, part: str) -> np.ndarray:
    check_choice(part, list(PARTS), "part")
    return np.asarray(chain.jacobian(q), dtype=float)[..., PARTS[part], :]


def _signed(axes: np.ndarray) -> np.ndarray:
    """The axes (columns) with the sign that makes each one's largest-magnitude entry positive."""
    largest = np.take_along_axis(axes, np.argmax(np.abs(axes), axis=-2)[..., None, :], axis=-2)
    return axes * np.where(largest < 0.0, -1.0, 1.0)


def _rank_tolerance(sigma: np.ndarray, columns: int) -> np.ndarray:
    """numpy's ``matrix_rank`` tolerance: below it a singular value is a zero of the rank."""
    return sigma[..., :1] * max(3, columns) * np.finfo(float).eps


def velocity_ellipsoid(chain: Chain, q: Any, part: str = "position") -> tuple[np.ndarray, np.ndarray]:
    r"""Principal semi-axes and axes of the velocity (manipulability) ellipsoid.

    The image of the unit ball of joint velocities, :math:`\{\mathbf{J}_p\dot{\mathbf{q}} :
    \|\dot{\mathbf{q}}\| \le 1\}` (Siciliano et al. 2009, §3.9). A chain with fewer than three
    joints gives zero radii (a flat ellipsoid).

    Parameters
    ----------
    chain : Chain
        A serial chain (its geometric Jacobian, rows ``[v; ω]``).
    q : array_like, shape (n,) or (N, n)
        Joint values (rad or m).
    part : {"position", "orientation"}
        The rows of the Jacobian: linear velocities (m/s) or angular ones (rad/s).

    Returns
    -------
    radii : numpy.ndarray, shape (3,) or (N, 3)
        Semi-axes, descending and non-negative, in m/s (or rad/s) per unit joint-speed norm.
    axes : numpy.ndarray, shape (3, 3) or (N, 3, 3)
        Unit axes as the columns, in the base frame, in the order of ``radii``; each column's
        largest-magnitude entry is positive.
    """
    U, sigma = _decomposition(chain, q, part)
    return sigma, U


def force_ellipsoid(chain: Chain, q: Any, part: str = "position") -> tuple[np.ndarray, np.ndarray]:
    r"""Principal semi-axes and axes of the force ellipsoid.

    The forces (``part="position"``) or moments (``"orientation"``) balanced by joint torques of
    unit norm, :math:`\{\mathbf{f} : \|\mathbf{J}_p^\mathsf{T}\mathbf{f}\| \le 1\}` (Siciliano et
    al. 2009, §3.9). Where the set is unbounded (a singular value of :math:`\mathbf{J}_p` below
    numpy's rank tolerance, :math:`\sigma_1 \max(3, n)\,\epsilon`) the radius is ``inf``.

    Parameters
    ----------
    chain : Chain
    q : array_like, shape (n,) or (N, n)
        Joint values (rad or m).
    part : {"position", "orientation"}

    Returns
    -------
    radii : numpy.ndarray, shape (3,) or (N, 3)
        Semi-axes, descending (``inf`` first where unbounded), in N (or N·m) per unit torque
        norm.
    axes : numpy.ndarray, shape (3, 3) or (N, 3, 3)
        Unit axes as the columns, in the base frame, in the order of ``radii``; each column's
        largest-magnitude entry is positive.
    """
    U, sigma = _decomposition(chain, q, part)
    singular = sigma <= _rank_tolerance(sigma, chain.n)
    with np.errstate(divide="ignore"):
        radii = np.where(singular, np.inf, 1.0 / np.where(singular, 1.0, sigma))
    return radii[..., ::-1], U[..., :, ::-1]


def _decomposition(chain: Chain, q: Any, part: str) -> tuple[np.ndarray, np.ndarray]:
    """The left singular vectors (signed, as columns) and the three singular values of J_p."""
    J = _part_jacobian(chain, q, part)
    U, sigma, _ = np.linalg.svd(J, full_matrices=True)
    if sigma.shape[-1] < 3:   # fewer joints than rows: the missing singular values are zeros
        pad = np.zeros(sigma.shape[:-1] + (3 - sigma.shape[-1],))
        sigma = np.concatenate([sigma, pad], axis=-1)
    return _signed(U), sigma


def static_torques(chain: Chain, q: Any, wrench: Any) -> np.ndarray:
    r"""Joint torques (forces) with which the end-effector exerts a wrench, at rest.

    The torques the joints must exert to hold the end-effector still while the environment
    pushes on it with :math:`-\mathbf{w}` (equivalently: the torques that make the end-effector
    exert :math:`\mathbf{w}`) (Siciliano et al. 2009, §3.8; Lynch & Park 2017, §5.2).

    Parameters
    ----------
    chain : Chain
    q : array_like, shape (n,) or (N, n)
        Joint values (rad or m).
    wrench : array_like, shape (6,) or (N, 6)
        ``[f; μ]``: force (N) applied at the end-effector's origin and moment (N·m), both in the
        base frame (the order of the book's twist ``[v; ω]``).

    Returns
    -------
    numpy.ndarray, shape (n,) or (N, n)
        N·m for revolute joints, N for prismatic ones.

    Raises
    ------
    ShapeError, DomainError
        ``wrench`` not of shape (6,) or matching the batch of ``q``, or not finite.
    """
    J = np.asarray(chain.jacobian(q), dtype=float)
    w = as_float_array(wrench, "wrench")
    if w.shape[-1:] != (6,) or w.ndim > 2 or (w.ndim == 2 and (J.ndim != 3 or len(w) != len(J))):
        batch = f"(6,) or ({len(J)}, 6)" if J.ndim == 3 else "(6,)"
        raise ShapeError(f"wrench must have shape {batch}; got shape {w.shape}")
    with np.errstate(all="ignore"):
        tau = np.einsum("...in,...i->...n", J, w)
    return check_result_finite(tau, "the joint torques", wrench=w)
