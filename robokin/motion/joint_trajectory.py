r"""Point-to-point joint motions in minimum time within velocity and acceleration limits.

What an industrial controller's PTP move does: every joint goes from ``q_start`` to ``q_end``
at rest at both ends, no joint exceeds its speed :math:`\dot q_{max,i}` or acceleration
:math:`\ddot q_{max,i}`, and all joints start and arrive together, in the least time that
allows (Siciliano et al. 2009, §4.2.1; Lynch & Park 2017, §9.2.2).
:func:`joint_trajectory_duration` gives that least duration, :func:`joint_trajectory` the
motion, with the trapezoidal velocity profile or a cubic or quintic polynomial law. Chapter 10
of the workbook derives both.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from robokin.errors import ShapeError
from robokin.motion.trajectories import Trajectory, time_law
from robokin.validation import as_float_array, as_vector, check_choice, check_positive, check_result_finite

__all__ = ["joint_trajectory", "joint_trajectory_duration", "JOINT_LAWS"]

#: The polynomial laws' (c_v, c_a): the peak speed and acceleration of a rest-to-rest motion of
#: displacement D in time T are c_v D/T and c_a D/T² (the maxima of time_law's ds/dτ and
#: |d²s/dτ²|).
POLYNOMIAL_PEAKS = {"cubic": (1.5, 6.0), "quintic": (15.0 / 8.0, 10.0 / math.sqrt(3.0))}
#: The laws of :func:`joint_trajectory`.
JOINT_LAWS = ("trapezoidal", *POLYNOMIAL_PEAKS)


def _limits(value: Any, n: int, name: str) -> np.ndarray:
    limit = as_float_array(value, name)
    if limit.ndim == 0:
        limit = np.full(n, float(limit))
    if limit.shape != (n,):
        raise ShapeError(f"{name} must be a number or have shape ({n},) (one per joint); got shape {limit.shape}")
    return check_positive(limit, name)


def _problem(q_start: Any, q_end: Any, v_max: Any, a_max: Any, law: str):
    start = as_vector(q_start, None, "q_start")
    end = as_vector(q_end, None, "q_end")
    if end.shape != start.shape:
        raise ShapeError(f"q_start and q_end must have the same length (one value per joint); "
                         f"got shapes {start.shape} and {end.shape}")
    n = len(start)
    check_choice(law, list(JOINT_LAWS), "law")
    return start, end, _limits(v_max, n, "v_max"), _limits(a_max, n, "a_max")


def _minimum_times(start: np.ndarray, end: np.ndarray, v_max: np.ndarray, a_max: np.ndarray,
                   law: str) -> np.ndarray:
    """Each joint's own minimum time for its displacement (the slowest sets the motion's)."""
    with np.errstate(all="ignore"):
        distance = np.abs(end - start)
        if law == "trapezoidal":
            reaches_speed = distance >= v_max * v_max / a_max
            times = np.where(reaches_speed, distance / v_max + v_max / a_max, 2.0 * np.sqrt(distance / a_max))
        else:
            c_v, c_a = POLYNOMIAL_PEAKS[law]
            times = np.maximum(c_v * distance / v_max, np.sqrt(c_a * distance / a_max))
    return check_result_finite(times, "the joints' minimum times", q_start=start, q_end=end, v_max=v_max, a_max=a_max)


def joint_trajectory_duration(q_start: Any, q_end: Any, *, v_max: Any, a_max: Any,
                              law: str = "trapezoidal") -> float:
    r"""The least duration :math:`T` of a synchronised motion within the limits.

    Parameters
    ----------
    q_start, q_end : array_like, shape (n,)
        Start and end configurations (rad or m).
    v_max, a_max : float or array_like, shape (n,)
        Speed and acceleration limits, positive (rad/s, rad/s²; m/s, m/s² for prismatic joints).
    law : {"trapezoidal", "quintic", "cubic"}

    Returns
    -------
    float
        Seconds; 0 when ``q_start`` equals ``q_end``.
    """
    start, end, v_limit, a_limit = _problem(q_start, q_end, v_max, a_max, law)
    return float(np.max(_minimum_times(start, end, v_limit, a_limit, law), initial=0.0))


def joint_trajectory(t: Any, q_start: Any, q_end: Any, *, v_max: Any, a_max: Any,
                     law: str = "trapezoidal") -> Trajectory:
    r"""A synchronised point-to-point joint motion in minimum time within per-joint limits.

    The joints start at ``t = 0``, arrive together at :math:`T` =
    :func:`joint_trajectory_duration` and rest before and after. Trapezoidal law: joint i
    accelerates at its limit :math:`\ddot q_{max,i}`, cruises at the speed that brings it to
    ``q_end`` at :math:`T` (at most :math:`\dot q_{max,i}`; a triangle for a joint that never
    reaches a cruise), and decelerates alike. Polynomial laws: the cubic or quintic
    :func:`time_law` scaled to :math:`T`, a straight line in joint space (Siciliano et al.
    2009, §4.2.1).

    Parameters
    ----------
    t : float or array_like, shape (T,)
        Time(s) in seconds.
    q_start, q_end : array_like, shape (n,)
        Start and end configurations (rad or m).
    v_max, a_max : float or array_like, shape (n,)
        Speed and acceleration limits, positive.
    law : {"trapezoidal", "quintic", "cubic"}
        Trapezoidal: the fastest, with jumps of acceleration; quintic: zero acceleration at
        both ends (no jerk impulse); cubic: continuous speed only.

    Returns
    -------
    Trajectory
        ``positions``, ``velocities``, ``accelerations``, each (n,) for a scalar ``t`` or (T, n).

    Raises
    ------
    ShapeError, DomainError, ValueError
        Configurations of different lengths, limits not positive or of the wrong length, times not
        finite, an unknown law: the message names the argument.
    """
    start, end, v_limit, a_limit = _problem(q_start, q_end, v_max, a_max, law)
    times = as_float_array(t, "t")
    if times.ndim > 1:
        raise ShapeError(f"t must be a scalar or have shape (T,); got shape {times.shape}")
    tt = np.atleast_1d(times)[:, None]
    duration = float(np.max(_minimum_times(start, end, v_limit, a_limit, law), initial=0.0))
    with np.errstate(all="ignore"):
        displacement = end - start
        if duration == 0.0:
            rest = np.zeros((len(tt), len(start)))
            positions, velocities, accelerations = rest + start, rest, rest.copy()
        elif law == "trapezoidal":
            positions, velocities, accelerations = _trapezoids(tt, start, displacement, a_limit, duration)
        else:
            s, ds, dds = time_law(tt / duration, law)
            positions = start + s * displacement
            velocities = ds / duration * displacement
            accelerations = dds / (duration * duration) * displacement
    for values, what in ((positions, "the positions"), (velocities, "the velocities"),
                         (accelerations, "the accelerations")):
        check_result_finite(values, what, t=times, q_start=start, q_end=end)
    out = Trajectory(positions, velocities, accelerations)
    return Trajectory(*(row[0] for row in out)) if times.ndim == 0 else out


def _trapezoids(tt: np.ndarray, start: np.ndarray, displacement: np.ndarray, a_limit: np.ndarray,
                duration: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every joint's trapezoid of the common ``duration``, at the times ``tt`` (T, 1)."""
    distance = np.abs(displacement)
    direction = np.sign(displacement)
    # a² T² − 4 a D ≥ 0 since T ≥ 2 sqrt(D / a); rounding can take the slowest triangle below 0
    discriminant = np.maximum(a_limit * a_limit * duration * duration - 4.0 * a_limit * distance, 0.0)
    cruise = 0.5 * (a_limit * duration - np.sqrt(discriminant))
    ramp = cruise / a_limit
    time = np.clip(tt, 0.0, duration)
    rising, falling = time < ramp, time > duration - ramp
    to_end = duration - time
    travelled = np.where(rising, 0.5 * a_limit * time**2,
                         np.where(falling, distance - 0.5 * a_limit * to_end**2, cruise * (time - 0.5 * ramp)))
    speed = np.where(rising, a_limit * time, np.where(falling, a_limit * to_end, cruise))
    acceleration = np.where(rising, a_limit, np.where(falling, -a_limit, 0.0))
    moving = (tt > 0.0) & (tt < duration)
    return (start + direction * travelled, np.where(moving, direction * speed, 0.0),
            np.where(moving, direction * acceleration, 0.0))
