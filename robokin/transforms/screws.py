r"""Twists, screws and the exponential coordinates of rigid-body motions (SE(3)).

This module follows Lynch & Park (2017), chapter 3, and their order of a twist's
coordinates: **angular part first**, :math:`\mathcal{V} = [\omega; v]` (the rest
of robokin writes a twist linear part first, :math:`[v; \omega]`;
``book/conventions.md`` relates the two). A screw motion of angle
:math:`\theta` about the screw axis :math:`\mathcal{S} = [\omega; v]` is the
6-vector :math:`\mathcal{S}\theta`, and the transform it makes is the matrix
exponential :math:`e^{[\mathcal{S}]\theta}` (Lynch & Park 2017, §3.3.3.1, Proposition 3.25,
in closed form; for :math:`\omega = 0` the translation :math:`v\theta`). The functions take the
product :math:`\mathcal{V} = \mathcal{S}\theta = [w; u]` with :math:`w = \omega\theta`,
:math:`u = v\theta`; below ``SERIES_ANGLE`` the closed form's coefficients are their Taylor
series, so that one formula serves screws and pure translations. Chapter 8 of the workbook
derives the closed form.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin._dispatch import is_symbolic, to_sympy
from robokin.errors import ShapeError
from robokin.transforms.angle_axis import rotation_exp, rotation_log
from robokin.transforms.rotations import skew
from robokin.validation import as_batch, check_result_finite, check_transform

__all__ = ["transform_exp", "transform_log", "adjoint"]

#: Below this angle (rad) the coefficients of G(θ) and G(θ)⁻¹ are their Taylor series: the
#: series' first neglected terms are then below 1e-19 and the closed forms' cancellation error
#: (about 1e-16 / θ²) would be larger.
SERIES_ANGLE = 1e-3


def _translation_factor(w: np.ndarray) -> np.ndarray:
    r""":math:`G = I + B[w] + C[w]^2` of each rotation vector ``w`` (N, 3), shape (N, 3, 3).

    Written with the unit axis :math:`\hat w = w/\theta`, :math:`G = I + \theta B [\hat w] +
    \theta^2 C [\hat w]^2`, whose coefficients :math:`(1 - \cos\theta)/\theta` and
    :math:`1 - \sin\theta/\theta` stay bounded for any angle; below ``SERIES_ANGLE`` they are
    their series.
    """
    theta = np.linalg.norm(w, axis=-1)
    t2 = theta * theta
    small = theta < SERIES_ANGLE
    safe = np.where(theta > 0.0, theta, 1.0)
    b = np.where(small, theta * (0.5 - t2 / 24.0 + t2 * t2 / 720.0), 2.0 * np.sin(0.5 * safe) ** 2 / safe)
    c = np.where(small, t2 * (1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0), 1.0 - np.sin(safe) / safe)
    unit = skew(w / safe[:, None])
    return np.eye(3) + b[:, None, None] * unit + c[:, None, None] * (unit @ unit)


def transform_exp(V: Any) -> Any:
    r"""Homogeneous transform :math:`e^{[\mathcal{V}]}` of the exponential coordinates :math:`\mathcal{V}`.

    The matrix exponential of :math:`[\mathcal{V}]`, in closed form (Lynch & Park 2017,
    §3.3.3.1, Proposition 3.25). Below ``SERIES_ANGLE`` the coefficients are their Taylor
    series, so a pure translation (:math:`w = 0`) gives :math:`[I, u; 0, 1]` exactly.

    Parameters
    ----------
    V : array_like, shape (6,) or (N, 6), or a sympy vector of 6 entries
        Exponential coordinates ``[w; u]``, **angular part first** (Lynch & Park's order):
        ``w`` (rad) the rotation vector, ``u`` (m) the linear part (the screw's ``v`` times θ).

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4), or sympy.Matrix (4x4)
        For symbolic input, the closed form with :math:`\theta = \sqrt{w^\mathsf{T}w}`.

    Raises
    ------
    ShapeError, DomainError
        ``V`` not of shape (6,) / (N, 6), or entries not finite.

    See Also
    --------
    transform_log : the inverse.
    adjoint : maps twists between frames, in the same order.
    """
    if is_symbolic(V):
        return _symbolic_exp(V)
    given, batched = as_batch(V, 6, "V")
    a = given.reshape(-1, 6)
    w, u = a[:, :3], a[:, 3:]
    T = np.zeros((len(a), 4, 4))
    T[:, :3, :3] = rotation_exp(w)
    with np.errstate(all="ignore"):
        T[:, :3, 3] = np.einsum("kij,kj->ki", _translation_factor(w), u)
    T[:, 3, 3] = 1.0
    check_result_finite(T, "the transform", V=a)
    return T if batched else T[0]


def _symbolic_exp(V: Any) -> Any:
    import sympy as sp

    m = to_sympy(V)
    if m.shape not in ((6, 1), (1, 6)):
        raise ShapeError(f"V must have 6 entries; got a sympy Matrix of shape {m.shape}")
    m = m.reshape(6, 1)
    w, u = m[:3, 0], m[3:, 0]
    theta = sp.sqrt((w.T * w)[0, 0])
    W = skew(w)
    G = sp.eye(3) + (1 - sp.cos(theta)) / theta**2 * W + (theta - sp.sin(theta)) / theta**3 * W * W
    T = sp.eye(4)
    T[:3, :3] = rotation_exp(w)
    T[:3, 3] = G * u
    return T


def transform_log(T: Any, check: bool = True) -> np.ndarray:
    r"""Exponential coordinates :math:`\mathcal{V} = [w; u]` of a transform (inverse of :func:`transform_exp`).

    ``w`` (rad) is the rotation vector of the rotation block, with the angle
    :math:`\theta = \|w\| \in [0, \pi]` (:func:`robokin.transforms.rotation_log`); ``u`` (m) is
    the linear part for which :func:`transform_exp` of ``[w; u]`` gives back ``T``: with the
    unit axis :math:`\omega = w/\theta`, ``[w; u]`` is :math:`\mathcal{S}\theta` for a screw axis
    :math:`\mathcal{S} = [\omega; v]` (Lynch & Park 2017, §3.3.3.2, the matrix logarithm of a
    rigid-body motion). At both ends of the angle range:

    - :math:`\theta \to 0`: the coefficients are their Taylor series below ``SERIES_ANGLE``;
      a pure translation gives :math:`[0; p]`.
    - :math:`\theta \to \pi`: the rotation vector comes from :func:`robokin.transforms.rotation_log`,
      which takes the axis from the symmetric part of :math:`R` there, and no coefficient divides
      by :math:`\sin\theta`. At exactly :math:`\theta = \pi` both :math:`w` and :math:`-w`
      describe the rotation; the one :func:`rotation_log` returns is used.

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4)
        Homogeneous transform(s).
    check : bool, optional
        Validate that ``T`` is a homogeneous transform (rotation block, last row ``[0, 0, 0, 1]``).

    Returns
    -------
    numpy.ndarray, shape (6,) or (N, 6)
        ``[w; u]``, angular part first: ``transform_exp(transform_log(T))`` equals ``T``.

    Raises
    ------
    ShapeError, DomainError
        ``T`` of another shape, or (with ``check``) not a homogeneous transform.
    """
    a = check_transform(T, name="T") if check else np.asarray(T, dtype=float)
    if a.ndim not in (2, 3) or a.shape[-2:] != (4, 4):
        raise ShapeError(f"T must have shape (4, 4) or (N, 4, 4); got shape {a.shape}")
    single = a.ndim == 2
    stack = a[None] if single else a
    w = np.asarray(rotation_log(stack[:, :3, :3], check=False), dtype=float)
    theta = np.linalg.norm(w, axis=-1)
    t2 = theta * theta
    small = theta < SERIES_ANGLE
    safe = np.where(small, 1.0, theta)
    D = np.where(small, 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0,
                 (1.0 - 0.5 * safe / np.tan(0.5 * safe)) / safe**2)
    W = skew(w)
    G_inverse = np.eye(3) - 0.5 * W + D[:, None, None] * (W @ W)
    with np.errstate(all="ignore"):
        u = np.einsum("kij,kj->ki", G_inverse, stack[:, :3, 3])
    V = check_result_finite(np.concatenate([w, u], axis=-1), "the exponential coordinates", T=a)
    return V[0] if single else V


def adjoint(T: Any, check: bool = True) -> np.ndarray:
    r"""Adjoint representation :math:`[\mathrm{Ad}_T]` of a transform, for twists ``[ω; v]``.

    :math:`\mathcal{V}_a = [\mathrm{Ad}_{T_{ab}}]\, \mathcal{V}_b` changes the frame of a twist,
    angular part first (Lynch & Park 2017, §3.3.2, the adjoint representation); for robokin's
    order ``[v; ω]`` permute the blocks.

    Parameters
    ----------
    T : array_like, shape (4, 4) or (N, 4, 4)
        Homogeneous transform(s) :math:`T_{ab}`.
    check : bool, optional
        Validate ``T``.

    Returns
    -------
    numpy.ndarray, shape (6, 6) or (N, 6, 6)

    Raises
    ------
    ShapeError, DomainError
        ``T`` of another shape, or (with ``check``) not a homogeneous transform.
    """
    a = check_transform(T, name="T") if check else np.asarray(T, dtype=float)
    if a.ndim not in (2, 3) or a.shape[-2:] != (4, 4):
        raise ShapeError(f"T must have shape (4, 4) or (N, 4, 4); got shape {a.shape}")
    R, p = a[..., :3, :3], a[..., :3, 3]
    out = np.zeros(a.shape[:-2] + (6, 6))
    out[..., :3, :3] = R
    out[..., 3:, 3:] = R
    with np.errstate(all="ignore"):
        out[..., 3:, :3] = skew(p) @ R
    return check_result_finite(out, "the adjoint", T=a)
