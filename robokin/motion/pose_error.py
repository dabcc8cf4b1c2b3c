r"""Pose error between a current and a goal pose, in several representations.

The IK solvers and the Cartesian controller use the angle–axis form
(Siciliano et al. 2009, §3.7.3):

.. math::
    e = \begin{bmatrix} e_P \\ e_O \end{bmatrix}
      = \begin{bmatrix} p_{goal} - p \\ \theta h \end{bmatrix},
    \qquad \theta h = \log\!\big(R_{goal} R^T\big),\ \theta \in [0, \pi]

Both parts are expressed in the base frame and stacked like the twist
:math:`[v; \omega]`, so that :math:`\dot e_O \approx \omega_{goal} - \omega` near
the goal and a controller :math:`\omega = K_O e_O` makes the error decay
exponentially.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.errors import ShapeError
from robokin.transforms import (
    quaternion_conjugate,
    quaternion_from_rotation,
    quaternion_multiply,
    rpy_from_rotation,
)
from robokin.transforms.angle_axis import rotation_log_unchecked
from robokin.validation import check_transform

__all__ = ["pose_error", "pose_error_unchecked", "REPRESENTATIONS"]

#: Accepted values of ``representation``.
REPRESENTATIONS = ("angle_axis", "quaternion", "rpy")


def pose_error(T_current: Any, T_goal: Any, representation: str = "angle_axis") -> np.ndarray:
    r"""Error ``[e_P; e_O]`` (6,) between a current and a goal pose, base frame.

    Parameters
    ----------
    T_current : array_like, shape (4, 4) or (N, 4, 4)
        Current pose(s) ``T_base_ee``.
    T_goal : array_like, shape (4, 4) or (N, 4, 4)
        Goal pose(s); broadcasts against ``T_current``.
    representation : {"angle_axis", "quaternion", "rpy"}, optional
        How the orientation error :math:`e_O` is expressed:

        ``"angle_axis"`` (default)
            :math:`e_O = \theta h = \log(R_{goal}R^T)`, the rotation vector of
            the rotation still to do, in the base frame, :math:`\theta\in[0,\pi]`,
            with :math:`\theta = \operatorname{atan2}(\tfrac12\|\operatorname{vee}(R_e
            - R_e^T)\|, \tfrac12(\operatorname{tr}R_e - 1))` for
            :math:`R_e = R_{goal}R^T`, which keeps its digits for any size of
            error, also next to :math:`\pi` (it is
            :func:`robokin.transforms.rotation_log`, unvalidated).  At exactly
            :math:`\theta = \pi` the sign of the axis is undefined (both
            :math:`\pm\pi h` are correct): the one returned has its component of
            largest magnitude positive (the first of equally large ones).
        ``"quaternion"``
            :math:`e_O = 2\,\varepsilon_{err}` with
            :math:`(\eta_{err}, \varepsilon_{err}) = Q_{goal} \otimes Q^{-1}`,
            sign chosen so that :math:`\eta_{err} \ge 0` (shortest way).  Equals
            :math:`2\sin(\theta/2)\,h`: the same direction as the angle–axis
            error and the same to first order (:math:`\approx\theta h` for
            small :math:`\theta`), but its norm saturates at 2 for
            :math:`\theta = \pi`.  Siciliano et al. 2009, §3.7.3 (up to the
            factor 2).
        ``"rpy"``
            :math:`e_O = \phi_{goal} - \phi` with :math:`\phi` = (roll, pitch,
            yaw), each difference wrapped into (−π, π].  Pitfalls: this is
            *not* a vector in the base frame — it must be paired with the
            analytic Jacobian :math:`T(\phi)^{-1} J_\omega`, not the geometric
            one; it is singular at pitch = ±π/2 (gimbal lock), where small
            rotations can give large angle jumps; and equal rotations can have
            different angle triples, so the error is not zero-iff-equal near
            the singularity.  Kept for comparison (Siciliano et al. 2009, §3.7.3).

    Returns
    -------
    numpy.ndarray, shape (6,) or (N, 6)
        ``[p_goal - p, e_O]`` (m, rad).

    Raises
    ------
    ShapeError, DomainError
        Poses of the wrong shape or not homogeneous transforms (messages name
        ``T_current`` / ``T_goal``).
    ValueError
        Unknown ``representation``.

    Examples
    --------
    >>> import numpy as np
    >>> from robokin.transforms import rotz, transform
    >>> pose_error(np.eye(4), transform(rotz(0.5), [1.0, 0.0, 0.0])).round(3)
    array([1. , 0. , 0. , 0. , 0. , 0.5])
    """
    if representation not in REPRESENTATIONS:
        raise ValueError(f"representation must be one of {REPRESENTATIONS}; got {representation!r}")
    T = check_transform(T_current, name="T_current")
    G = check_transform(T_goal, name="T_goal")
    try:
        shape = np.broadcast_shapes(T.shape, G.shape)
    except ValueError:
        raise ShapeError(
            f"T_current and T_goal must broadcast; got shapes {T.shape} and {G.shape}"
        ) from None
    if representation == "angle_axis":
        e = pose_error_unchecked(T, G[..., :3, :3], G[..., :3, 3])
        return np.array(e) if isinstance(e, tuple) else e
    e = np.empty(shape[:-2] + (6,))
    e[..., :3] = G[..., :3, 3] - T[..., :3, 3]
    R, Rg = T[..., :3, :3], G[..., :3, :3]
    if representation == "quaternion":
        qe = quaternion_multiply(
            quaternion_from_rotation(Rg, check=False), quaternion_conjugate(quaternion_from_rotation(R, check=False))
        )
        sign = np.where(qe[..., :1] < 0, -1.0, 1.0)
        e[..., 3:] = 2.0 * sign * qe[..., 1:]
    else:
        d = rpy_from_rotation(Rg, check=False) - rpy_from_rotation(R, check=False)
        e[..., 3:] = np.pi - np.mod(np.pi - d, 2.0 * np.pi)
    return e


def pose_error_unchecked(T: np.ndarray, R_goal: np.ndarray, p_goal: Any) -> Any:
    r"""The angle–axis :func:`pose_error` without validation: the one implementation of it.

    :math:`e = [p_{goal} - p;\ \log(R_{goal} R^T)]` in the base frame, for poses ``T``
    (..., 4, 4) and a goal given by its rotation ``R_goal`` (..., 3, 3) and position ``p_goal``
    (..., 3) (a goal pose ``G`` is ``G[..., :3, :3], G[..., :3, 3]``; the IK loop keeps them
    apart, contiguous, because a product with a slice of a 4×4 costs it a microsecond per
    iteration). One pose and one goal give a tuple of six floats, computed in plain floats
    (every IK iteration calls it, and numpy's per-call cost would dominate; ``p_goal`` may then
    be a list of three floats); stacks broadcast and give an array (..., 6).
    """
    if T.ndim == 2 and R_goal.ndim == 2:
        wx, wy, wz = rotation_log_unchecked(R_goal.dot(T[:3, :3].T))
        p, g = T[:3, 3].tolist(), (p_goal if isinstance(p_goal, list) else p_goal.tolist())
        return g[0] - p[0], g[1] - p[1], g[2] - p[2], wx, wy, wz
    e = np.empty(np.broadcast_shapes(T.shape[:-2], R_goal.shape[:-2], np.shape(p_goal)[:-1]) + (6,))
    e[..., :3] = p_goal - T[..., :3, 3]
    e[..., 3:] = rotation_log_unchecked(R_goal @ np.swapaxes(T[..., :3, :3], -1, -2))
    return e
