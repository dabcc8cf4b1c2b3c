r"""A straight-line motion of a frame: the position on a segment, the orientation by slerp.

.. math::
    \mathbf{p}(t) = \mathbf{p}_0 + s(\tau)(\mathbf{p}_1 - \mathbf{p}_0), \qquad
    \mathbf{R}(t) = \mathbf{R}_0\, e^{[\mathbf{w}]s(\tau)}, \qquad \tau = t/T,

with one timing law :math:`s` for both (Siciliano et al. 2009, §4.3; Lynch & Park 2017,
§9.2.1): :math:`\mathbf{w} = \theta\mathbf{h}` is the rotation vector of
:math:`\mathbf{R}_0^\mathsf{T}\mathbf{R}_1`, the short way (:math:`\theta \le \pi`), and
:math:`\mathbf{R}(t)` is the slerp of the two orientations' quaternions. Interpolating Euler
angles instead would turn about a moving axis, the long way round when an angle wraps.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from robokin.errors import ShapeError
from robokin.motion.trajectories import time_law
from robokin.transforms.quaternions import (
    quaternion_conjugate,
    quaternion_from_rotation,
    quaternion_multiply,
    quaternion_slerp,
    rotation_from_quaternion,
)
from robokin.validation import as_float_array, check_choice, check_positive, check_result_finite, check_transform

__all__ = ["PoseTrajectory", "pose_trajectory"]


class PoseTrajectory(NamedTuple):
    """Poses (4, 4), twists ``[v; ω]`` (6,) and their rates ``[a; α]`` (6,), in the base frame.

    With an array of T times: (T, 4, 4), (T, 6), (T, 6). ``v`` and ``a`` are the velocity and
    acceleration of the frame's origin (m/s, m/s²), ``ω`` and ``α`` its angular velocity and
    acceleration (rad/s, rad/s²): the book's twist order, the feed-forward of a Cartesian
    controller.
    """

    poses: np.ndarray
    twists: np.ndarray
    accelerations: np.ndarray


def _rotation_vector_between(q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """The rotation vector w of R0ᵀR1 that slerp turns through, from the quaternions (the short way)."""
    if q0 @ q1 < 0.0:
        q1 = -q1
    relative = quaternion_multiply(quaternion_conjugate(q0), q1)   # w >= 0: angle <= pi
    sine = float(np.linalg.norm(relative[1:]))
    if sine == 0.0:
        return np.zeros(3)
    return 2.0 * math.atan2(sine, float(relative[0])) * relative[1:] / sine


def pose_trajectory(t: Any, T_start: Any, T_end: Any, duration: Any, *, law: str = "quintic") -> PoseTrajectory:
    r"""A frame moved from ``T_start`` to ``T_end``: straight line, slerped orientation, one timing law.

    The twists are the pose's rates (the velocity of the frame's origin and its angular
    velocity, base frame), the accelerations theirs (Siciliano et al. 2009, §4.3). Before
    ``t = 0`` and after ``duration`` the frame rests at the ends.

    Parameters
    ----------
    t : float or array_like, shape (T,)
        Time(s) in seconds.
    T_start, T_end : array_like, shape (4, 4)
        Start and end poses (homogeneous transforms, base frame).
    duration : float
        Seconds, positive.
    law : {"quintic", "cubic", "linear"}
        The timing law :func:`~robokin.motion.time_law` (quintic: rest with zero acceleration at
        both ends; cubic: rest; linear: constant speed, jumps at the ends).

    Returns
    -------
    PoseTrajectory
        ``poses`` (4, 4) or (T, 4, 4), ``twists`` and ``accelerations`` (6,) or (T, 6), rows
        ``[v; ω]`` and ``[a; α]`` in the base frame.

    Raises
    ------
    ShapeError, DomainError, ValueError
        A pose that is not a homogeneous transform, a duration not positive, times not finite or
        of more than one dimension, an unknown law: the message names the argument.
    """
    start = check_transform(T_start, name="T_start")
    end = check_transform(T_end, name="T_end")
    for pose, name in ((start, "T_start"), (end, "T_end")):
        if pose.shape != (4, 4):
            raise ShapeError(f"{name} must have shape (4, 4); got shape {pose.shape}")
    total = float(check_positive(duration, "duration", scalar=True))
    check_choice(law, ["quintic", "cubic", "linear"], "law")
    times = as_float_array(t, "t")
    if times.ndim > 1:
        raise ShapeError(f"t must be a scalar or have shape (T,); got shape {times.shape}")
    with np.errstate(all="ignore"):
        tau = check_result_finite(np.atleast_1d(times) / total, "the normalised time t / duration",
                                  t=times, duration=total)
    s, ds, dds = time_law(tau, law)
    q0, q1 = quaternion_from_rotation(start[:3, :3]), quaternion_from_rotation(end[:3, :3])
    axis_in_base = start[:3, :3] @ _rotation_vector_between(q0, q1)
    displacement = end[:3, 3] - start[:3, 3]
    poses = np.zeros((len(tau), 4, 4))
    poses[:, :3, :3] = rotation_from_quaternion(quaternion_slerp(q0, q1, s))
    poses[:, :3, 3] = start[:3, 3] + s[:, None] * displacement
    poses[:, 3, 3] = 1.0
    rate, second = ds / total, dds / (total * total)
    twists = np.hstack([rate[:, None] * displacement, rate[:, None] * axis_in_base])
    accelerations = np.hstack([second[:, None] * displacement, second[:, None] * axis_in_base])
    if times.ndim == 0:
        return PoseTrajectory(poses[0], twists[0], accelerations[0])
    return PoseTrajectory(poses, twists, accelerations)
