r"""Cartesian position trajectories: circle, straight line, via points.

Every generator is evaluated at times ``t`` (a scalar or an array of T times)
and returns a :class:`Trajectory` ``(positions, velocities, accelerations)``
with shapes ``(3,)`` for a scalar ``t`` and ``(T, 3)`` for an array, so it can
be unpacked, ``p, v, a = line_trajectory(t, ...)``, or used as the goal and
feed-forward of a :class:`~robokin.motion.CartesianController`::

    goal = lambda t: circle_trajectory(t, centre, 0.1, normal=[0, 0, 1]).positions
    ff = lambda t: np.r_[circle_trajectory(t, centre, 0.1, normal=[0, 0, 1]).velocities, 0, 0, 0]

References: Siciliano et al. 2009, §4.2 (joint-space polynomials, via points)
and §4.3 (operational-space paths: segment and circle, timing laws).
"""

from __future__ import annotations

import functools
from typing import Any, NamedTuple

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.validation import (
    as_float_array,
    as_scalar,
    as_vector,
    check_positive,
    check_result_finite,
)

_LAWS = ("quintic", "cubic", "linear")

__all__ = ["Trajectory", "circle_trajectory", "line_trajectory", "via_point_trajectory", "time_law"]


class Trajectory(NamedTuple):
    """Positions, velocities and accelerations, (d,) or (T, d) each.

    A point's path: d = 3, in m, m/s, m/s²; a joint motion (:func:`~robokin.motion.joint_trajectory`):
    d = n, in rad (m), rad/s (m/s), rad/s² (m/s²).
    """

    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray


def _times(t: Any) -> tuple[np.ndarray, bool]:
    a = as_float_array(t, "t")
    if a.ndim > 1:
        raise ShapeError(f"t must be a scalar or have shape (T,); got shape {a.shape}")
    return np.atleast_1d(a), a.ndim == 0


def _out(p: np.ndarray, v: np.ndarray, a: np.ndarray, scalar: bool, **inputs: Any) -> Trajectory:
    for arr, what in ((p, "the positions"), (v, "the velocities"), (a, "the accelerations")):
        check_result_finite(arr, what, **inputs)
    if scalar:
        return Trajectory(p[0], v[0], a[0])
    return Trajectory(p, v, a)


def _unit(v: np.ndarray) -> tuple[np.ndarray, float]:
    """``v / |v|`` and ``|v|`` without overflow for huge entries (|v| may be inf: then (nan, inf))."""
    with np.errstate(all="ignore"):
        n = float(np.linalg.norm(v))
        if not np.isfinite(n):
            m = float(np.abs(v).max())
            u = v / m
            return u / np.linalg.norm(u), n
    return (v / n if n > 0 else v), n


def _plane_axes(normal: Any, axes: Any) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal in-plane axes (u, v) with u x v = n."""
    if (normal is None) == (axes is None):
        raise ValueError("give exactly one of normal= (plane normal) and axes= (two in-plane axes)")
    if axes is not None:
        A = as_float_array(axes, "axes", (2, 3))
        nu = np.linalg.norm(A[0]) if np.abs(A).max() < 1e150 else None
        if nu is None:  # huge entries: only the directions matter
            A = np.array([_unit(A[0])[0], _unit(A[1])[0]]) if np.abs(A[0]).max() > 0 else A
            nu = np.linalg.norm(A[0])
        if nu < 1e-12:
            raise DomainError("axes[0] must be a nonzero vector; got length 0")
        u = A[0] / nu
        w = A[1] - (A[1] @ u) * u
        nw = np.linalg.norm(w)
        if nw < 1e-9 * max(1.0, float(np.linalg.norm(A[1]))):
            raise DomainError("axes must span a plane; got parallel (or zero) vectors")
        return u, w / nw
    n = as_vector(normal, 3, "normal")
    return _axes_about(n.tobytes())


@functools.lru_cache(maxsize=64)
def _axes_about(normal_bytes: bytes) -> tuple[np.ndarray, np.ndarray]:
    """In-plane axes (u, v) with u x v = n for the (validated) normal n, given by its bytes.

    Cached: a controller that evaluates a trajectory once per time step asks for the
    same plane at every step. The key is the exact bits of n (so 0.0 and -0.0 differ),
    and the arrays returned are read-only (they are shared between calls).
    """
    n = np.frombuffer(normal_bytes)
    nn = float(np.linalg.norm(n)) if np.abs(n).max() < 1e150 else None
    if nn is None:
        n, nn = _unit(n)[0], 1.0
    if nn < 1e-12:
        raise DomainError("normal must be a nonzero vector; got length 0")
    n = n / nn
    # u: the base axis least aligned with n, made orthogonal to it
    e = np.eye(3)[int(np.argmin(np.abs(n)))]
    u = e - (e @ n) * n
    u /= np.linalg.norm(u)
    (n0, n1, n2), (u0, u1, u2) = n.tolist(), u.tolist()
    v = np.array((n1 * u2 - n2 * u1, n2 * u0 - n0 * u2, n0 * u1 - n1 * u0))  # n × u
    u.flags.writeable = v.flags.writeable = False
    return u, v


def circle_trajectory(
    t: Any,
    centre: Any,
    radius: float,
    *,
    normal: Any = None,
    axes: Any = None,
    angular_speed: float = 1.0,
    phase: float = 0.0,
) -> Trajectory:
    r"""Uniform motion on a circle (Siciliano et al. 2009, §4.3.1).

    .. math::
        p(t) = c + r(\cos\varphi\, u + \sin\varphi\, v),\quad \varphi = \Omega t + \varphi_0

    :math:`\dot p = r\Omega(-\sin\varphi\, u + \cos\varphi\, v)`,
    :math:`\ddot p = -\Omega^2 (p - c)`.

    Parameters
    ----------
    t : float or array_like (T,)
        Times (s).
    centre : array_like (3,)
        Centre (m).
    radius : float
        Radius (m), > 0.
    normal : array_like (3,), optional
        Plane normal; the in-plane axes are then ``u`` (perpendicular to the
        normal, from the base axis least aligned with it) and ``v = n × u``
        (motion counter-clockwise about ``normal``).
    axes : array_like (2, 3), optional
        Two in-plane directions ``(u, v)`` instead (orthonormalised, Gram–Schmidt):
        the motion starts along ``u`` at ``phase = 0`` and turns towards ``v``.
    angular_speed : float, optional
        :math:`\Omega` (rad/s); negative runs clockwise.
    phase : float, optional
        :math:`\varphi_0` (rad).

    Returns
    -------
    Trajectory
        positions, velocities, accelerations, (3,) or (T, 3) each.
    """
    tt, scalar = _times(t)
    c = as_vector(centre, 3, "centre")
    r = check_positive(radius, "radius", scalar=True)
    u, v = _plane_axes(normal, axes)
    om = as_scalar(angular_speed, "angular_speed")
    ph = as_scalar(phase, "phase")
    with np.errstate(all="ignore"):
        phi = om * tt + ph
        cs, sn = np.cos(phi)[:, None], np.sin(phi)[:, None]
        rel = r * (cs * u + sn * v)
        p = c + rel
        vel = r * om * (-sn * u + cs * v)
        acc = -(om * om) * rel
    return _out(p, vel, acc, scalar, t=tt, centre=c, radius=r, angular_speed=om, phase=ph)


def time_law(tau: Any, kind: str = "quintic") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Normalised timing law ``s(tau)`` on ``tau`` in [0, 1] and its first two derivatives.

    All go from :math:`s(0) = 0` to :math:`s(1) = 1`. ``"quintic"``: the polynomial of degree 5
    with zero velocity and acceleration at both ends; ``"cubic"``: the polynomial of degree 3
    with zero velocity at both ends; ``"linear"``: :math:`s = \tau` (Siciliano et al. 2009,
    §4.2.1). ``tau`` outside [0, 1] is clamped (rest before and after).

    Parameters
    ----------
    tau : float or array_like
        Normalised time(s), finite.
    kind : {"quintic", "cubic", "linear"}, optional

    Returns
    -------
    s, ds, dds : numpy.ndarray, each of the shape of ``tau``
        :math:`s`, :math:`ds/d\tau` and :math:`d^2s/d\tau^2` (dimensionless; divide by the
        duration :math:`T` and :math:`T^2` for the rates in time).

    Raises
    ------
    TypeError, DomainError
        ``tau`` not numeric or not finite.
    ValueError
        Unknown ``kind``.
    """
    tau = as_float_array(tau, "tau")
    if not isinstance(kind, str) or kind not in _LAWS:
        raise ValueError(f"time_law: kind must be 'quintic', 'cubic' or 'linear'; got {kind!r}")
    x = np.clip(tau, 0.0, 1.0)
    inside = (tau >= 0.0) & (tau <= 1.0)
    if kind == "quintic":
        s = x**3 * (10 - 15 * x + 6 * x**2)
        ds = 30 * x**2 * (1 - x) ** 2
        dds = 60 * x * (1 - x) * (1 - 2 * x)
    elif kind == "cubic":
        s = x**2 * (3 - 2 * x)
        ds = 6 * x * (1 - x)
        dds = 6 - 12 * x
    else:  # "linear"
        s = x
        ds = np.ones_like(x)
        dds = np.zeros_like(x)
    return s, np.where(inside, ds, 0.0), np.where(inside, dds, 0.0)


def line_trajectory(
    t: Any,
    start: Any,
    end: Any,
    duration: float,
    *,
    t_start: float = 0.0,
    law: str = "quintic",
) -> Trajectory:
    r"""Straight segment from ``start`` to ``end`` with a smooth timing law (Siciliano et al. 2009, §4.3.2).

    .. math::
        p(t) = p_0 + s(\tau)(p_1 - p_0), \quad \tau = (t - t_0)/T

    with :func:`time_law` ``s`` (quintic by default: starts and ends at rest
    with zero acceleration).  Before ``t_start`` the point rests at ``start``,
    after ``t_start + duration`` at ``end``.

    Returns
    -------
    Trajectory
        positions, velocities (:math:`\dot s (p_1 - p_0)/T`), accelerations.
    """
    tt, scalar = _times(t)
    a = as_vector(start, 3, "start")
    b = as_vector(end, 3, "end")
    T = check_positive(duration, "duration", scalar=True)
    t0 = as_scalar(t_start, "t_start")
    if not isinstance(law, str) or law not in _LAWS:
        raise ValueError(f"law must be 'quintic', 'cubic' or 'linear'; got {law!r}")
    with np.errstate(all="ignore"):
        tau = (tt - t0) / T
    tau = check_result_finite(tau, "the normalised time (t - t_start) / duration", t=tt, t_start=t0)
    s, ds, dds = time_law(tau, law)
    with np.errstate(all="ignore"):
        d = b - a
        p, v, acc = a + s[:, None] * d, (ds / T)[:, None] * d, (dds / (T * T))[:, None] * d
    return _out(p, v, acc, scalar, start=a, end=b)


def via_point_trajectory(
    t: Any,
    points: Any,
    times: Any,
    velocities: Any = None,
) -> Trajectory:
    r"""Piecewise-cubic path through via points with continuous velocity (Siciliano §4.2.2).

    Between consecutive via points :math:`p_k` at :math:`t_k` each coordinate
    is the cubic (Hermite) polynomial matching positions and velocities at
    both ends, so positions and velocities are continuous (accelerations jump
    at the via points).  Without given ``velocities`` the intermediate ones
    follow Siciliano et al. 2009, §4.2.2: the mean of the adjacent segment slopes, or 0
    where the slope changes sign (per coordinate); first and last are 0.

    Parameters
    ----------
    t : float or array_like (T,)
        Times (s); before ``times[0]`` / after ``times[-1]`` the point rests
        at the first / last via point.
    points : array_like (M, 3)
        Via points, M >= 2.
    times : array_like (M,)
        Strictly increasing times of the via points.
    velocities : array_like (M, 3), optional
        Velocities at the via points.

    Returns
    -------
    Trajectory
    """
    tt, scalar = _times(t)
    P = as_float_array(points, "points")
    if P.ndim != 2 or P.shape[1] != 3 or P.shape[0] < 2:
        raise ShapeError(f"points must have shape (M, 3) with M >= 2; got shape {P.shape}")
    M = P.shape[0]
    tk = as_float_array(times, "times", (M,))
    if velocities is not None:
        velocities = as_float_array(velocities, "velocities", (M, 3))
    with np.errstate(all="ignore"):
        h = np.diff(tk)
        if np.any(h <= 0):
            i = int(np.argmax(h <= 0))
            raise DomainError(f"times must be strictly increasing; got times[{i + 1}] = {tk[i + 1]:g} "
                              f"<= times[{i}] = {tk[i]:g}")
        if velocities is None:
            slope = np.diff(P, axis=0) / h[:, None]
            V = np.zeros_like(P)
            same = np.sign(slope[:-1]) == np.sign(slope[1:])
            V[1:-1] = np.where(same, 0.5 * (slope[:-1] + slope[1:]), 0.0)
        else:
            V = velocities
        k = np.clip(np.searchsorted(tk, tt, side="right") - 1, 0, M - 2)
        T = h[k][:, None]
        x = np.clip((tt - tk[k]) / h[k], 0.0, 1.0)[:, None]
        inside = ((tt >= tk[0]) & (tt <= tk[-1]))[:, None]
        p0, p1, v0, v1 = P[k], P[k + 1], V[k] * T, V[k + 1] * T
        h00 = 2 * x**3 - 3 * x**2 + 1
        h10 = x**3 - 2 * x**2 + x
        h01 = -2 * x**3 + 3 * x**2
        h11 = x**3 - x**2
        pos = h00 * p0 + h10 * v0 + h01 * p1 + h11 * v1
        d00, d10, d01, d11 = 6 * x**2 - 6 * x, 3 * x**2 - 4 * x + 1, -6 * x**2 + 6 * x, 3 * x**2 - 2 * x
        vel = (d00 * p0 + d10 * v0 + d01 * p1 + d11 * v1) / T
        a00, a10, a01, a11 = 12 * x - 6, 6 * x - 4, -12 * x + 6, 6 * x - 2
        acc = (a00 * p0 + a10 * v0 + a01 * p1 + a11 * v1) / T**2
        vel = np.where(inside, vel, 0.0)
        acc = np.where(inside, acc, 0.0)
    inputs = {"t": tt, "points": P, "times": tk}
    if velocities is not None:
        inputs["velocities"] = velocities
    return _out(pos, vel, acc, scalar, **inputs)
