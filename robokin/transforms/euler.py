r"""Roll–pitch–yaw (ZYX) and ZYZ Euler angles.

Roll–pitch–yaw (Siciliano et al. 2009, §2.4.2; Lynch & Park 2017, App. B):

.. math::
    R(\phi, \theta, \psi) = R_z(\psi)\, R_y(\theta)\, R_x(\phi)

with roll :math:`\phi`, pitch :math:`\theta`, yaw :math:`\psi`, always passed
and returned in the order ``(roll, pitch, yaw)``.

ZYZ Euler angles (Siciliano §2.4.1):
:math:`R(\varphi, \vartheta, \psi) = R_z(\varphi) R_y(\vartheta) R_z(\psi)`.

Singularities (gimbal lock) and what is returned there
-------------------------------------------------------
- RPY: at pitch = ±π/2 only roll − yaw (pitch = +π/2) or roll + yaw
  (pitch = −π/2) is determined. :func:`rpy_from_rotation` then returns
  **yaw = 0** and puts the whole rotation about the vertical into roll.
- ZYZ: at θ = 0 or θ = π only φ ± ψ is determined. :func:`zyz_from_rotation`
  then returns **φ = 0** and puts everything into ψ.

A matrix is treated as singular when ``cos(pitch)`` (resp. ``sin θ``) is below
``1e-8`` — at that distance from the singularity both branches reproduce ``R``
to about 1e-8.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin._dispatch import is_symbolic, scalar_input, stack_matrix, to_sympy, trig
from robokin.errors import ShapeError
from robokin.transforms.homogeneous import transform
from robokin.validation import as_float_array, as_rotation_matrix

__all__ = ["rotation_from_rpy", "rpy_from_rotation", "transform_from_rpy", "rotation_from_zyz", "zyz_from_rotation"]

_SINGULAR_TOL = 1e-8


def _three_angles(a: Any, b: Any, c: Any, names: tuple[str, str, str], packed: str) -> tuple:
    if b is None and c is None:
        if is_symbolic(a):
            m = to_sympy(a)
            if len(m) != 3:
                raise ShapeError(f"{packed} must have 3 entries; got {len(m)}")
            return tuple(m)
        arr = as_float_array(a, packed)
        if arr.ndim not in (1, 2) or arr.shape[-1] != 3:
            raise ShapeError(
                f"{packed} must have shape (3,) or (N, 3) (or pass {', '.join(names)} "
                f"separately); got shape {arr.shape}"
            )
        return arr[..., 0], arr[..., 1], arr[..., 2]
    if b is None or c is None:
        raise TypeError(f"pass either all three of {', '.join(names)} or one array of 3 angles")
    angles = tuple(scalar_input(x, n) for x, n in zip((a, b, c), names))
    if is_symbolic(*angles):  # keep e.g. a float 0.0 next to a symbol exact
        return tuple(to_sympy(x) for x in angles)
    return angles


def rotation_from_rpy(roll: Any, pitch: Any = None, yaw: Any = None) -> Any:
    r"""Rotation matrix from roll–pitch–yaw angles, :math:`R_z(\psi) R_y(\theta) R_x(\phi)`.

    .. math::
        R = \begin{bmatrix}
        c_\psi c_\theta & c_\psi s_\theta s_\phi - s_\psi c_\phi &
            c_\psi s_\theta c_\phi + s_\psi s_\phi \\
        s_\psi c_\theta & s_\psi s_\theta s_\phi + c_\psi c_\phi &
            s_\psi s_\theta c_\phi - c_\psi s_\phi \\
        -s_\theta & c_\theta s_\phi & c_\theta c_\phi \end{bmatrix}

    (Siciliano et al. 2009, §2.4.2.)

    Parameters
    ----------
    roll, pitch, yaw : float, array_like of shape S, or sympy expression
        Angles in radians (arrays broadcast together).
        Alternatively pass a single array ``rpy`` of shape (3,) or (N, 3) as
        ``roll`` (columns roll, pitch, yaw) and leave ``pitch``/``yaw`` out.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or S + (3, 3), or sympy.Matrix (3x3)

    Examples
    --------
    >>> import numpy as np
    >>> np.allclose(rotation_from_rpy(0.1, 0.2, 0.3), rotation_from_rpy([0.1, 0.2, 0.3]))
    True
    """
    r, p, y = _three_angles(roll, pitch, yaw, ("roll", "pitch", "yaw"), "rpy")
    cr, sr = trig(r)
    cp, sp = trig(p)
    cy, sy = trig(y)
    return stack_matrix(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def transform_from_rpy(rpy: Any, position: Any) -> np.ndarray:
    r"""Homogeneous transform from roll–pitch–yaw angles and a position.

    Parameters
    ----------
    rpy : array_like, shape (3,) or (N, 3)
        ``(roll, pitch, yaw)`` in rad: :math:`\mathbf{R} = \mathbf{R}_z(\psi)\mathbf{R}_y(\vartheta)
        \mathbf{R}_x(\varphi)` (Siciliano et al. 2009, §2.4.2).
    position : array_like, shape (3,) or (N, 3)
        Origin of the new frame in the reference frame (m).

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4)
        :math:`\begin{bmatrix}\mathbf{R} & \mathbf{p}\\ \mathbf{0}^\top & 1\end{bmatrix}`,
        e.g. a tool frame :math:`{}^{E}\mathbf{T}_{T}` or a goal frame
        :math:`{}^{B}\mathbf{T}_{G}`.

    Raises
    ------
    ShapeError
        ``rpy`` or ``position`` not of shape (3,) / (N, 3), or different N.
    DomainError
        NaN or infinite entries.

    Examples
    --------
    >>> import numpy as np
    >>> (transform_from_rpy([0.0, 0.0, np.pi / 2], [0.2, 0.0, 0.0]).round(3) + 0.0)[:3]  # + 0.0: no -0.
    array([[ 0. , -1. ,  0. ,  0.2],
           [ 1. ,  0. ,  0. ,  0. ],
           [ 0. ,  0. ,  1. ,  0. ]])
    """
    a = as_float_array(rpy, "rpy")
    p = as_float_array(position, "position")
    if a.shape[-1:] != (3,) or a.ndim > 2:
        raise ShapeError(f"rpy must have shape (3,) or (N, 3) (roll, pitch, yaw in rad); got shape {a.shape}")
    if p.shape[-1:] != (3,) or p.ndim > 2:
        raise ShapeError(f"position must have shape (3,) or (N, 3) (metres); got shape {p.shape}")
    try:
        lead = np.broadcast_shapes(a.shape[:-1], p.shape[:-1])
    except ValueError:
        raise ShapeError(f"rpy and position must have the same number of rows; got shapes "
                         f"{a.shape} and {p.shape}") from None
    R = rotation_from_rpy(np.broadcast_to(a, lead + (3,)))
    return transform(R, np.broadcast_to(p, lead + (3,)), check=False)


def rpy_from_rotation(R: Any, check: bool = True) -> Any:
    r"""Roll–pitch–yaw angles of a rotation matrix (inverse of :func:`rotation_from_rpy`).

    Regular case, pitch in (−π/2, π/2) (Siciliano et al. 2009, §2.4.2):

    .. math::
        \phi = \operatorname{atan2}(r_{32}, r_{33}),\quad
        \theta = \operatorname{atan2}\!\big(-r_{31}, \sqrt{r_{11}^2 + r_{21}^2}\big),\quad
        \psi = \operatorname{atan2}(r_{21}, r_{11})

    **Gimbal lock** (:math:`\cos\theta < 10^{-8}`, pitch = ±π/2): yaw is set to
    0 and :math:`\phi = \operatorname{atan2}(-r_{31} r_{12},\, r_{22})`, which
    reproduces ``R``.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3), or sympy.Matrix
        Rotation matrix / matrices.
    check : bool, optional
        Validate that ``R`` is a rotation (numeric input).

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3)
        ``(roll, pitch, yaw)``; roll, yaw in (−π, π], pitch in [−π/2, π/2].
        For a sympy Matrix: a 3x1 ``sympy.Matrix`` of the regular-case
        formulas (valid where cos(pitch) > 0).
    """
    if is_symbolic(R):
        import sympy as spy

        M = to_sympy(R)
        return spy.Matrix([
            spy.atan2(M[2, 1], M[2, 2]),
            spy.atan2(-M[2, 0], spy.sqrt(M[0, 0] ** 2 + M[1, 0] ** 2)),
            spy.atan2(M[1, 0], M[0, 0]),
        ])
    a = as_rotation_matrix(R, check)
    r11, r21, r31 = a[..., 0, 0], a[..., 1, 0], a[..., 2, 0]
    cp = np.hypot(r11, r21)
    pitch = np.arctan2(-r31, cp)
    singular = cp < _SINGULAR_TOL
    roll = np.where(singular, np.arctan2(-r31 * a[..., 0, 1], a[..., 1, 1]),
                    np.arctan2(a[..., 2, 1], a[..., 2, 2]))
    yaw = np.where(singular, 0.0, np.arctan2(r21, r11))
    return np.stack([roll, pitch, yaw], axis=-1)


def rotation_from_zyz(phi: Any, theta: Any = None, psi: Any = None) -> Any:
    r"""Rotation matrix from ZYZ Euler angles, :math:`R_z(\varphi) R_y(\vartheta) R_z(\psi)`.

    .. math::
        R = \begin{bmatrix}
        c_\varphi c_\vartheta c_\psi - s_\varphi s_\psi &
            -c_\varphi c_\vartheta s_\psi - s_\varphi c_\psi & c_\varphi s_\vartheta \\
        s_\varphi c_\vartheta c_\psi + c_\varphi s_\psi &
            -s_\varphi c_\vartheta s_\psi + c_\varphi c_\psi & s_\varphi s_\vartheta \\
        -s_\vartheta c_\psi & s_\vartheta s_\psi & c_\vartheta \end{bmatrix}

    (Siciliano et al. 2009, eq. 2.18.)

    Parameters
    ----------
    phi, theta, psi : float, array_like of shape S, or sympy expression
        Angles in radians, or a single array of shape (3,) / (N, 3) as ``phi``.

    Returns
    -------
    numpy.ndarray, shape (3, 3) or S + (3, 3), or sympy.Matrix (3x3)
    """
    f, t, s = _three_angles(phi, theta, psi, ("phi", "theta", "psi"), "zyz")
    cf, sf = trig(f)
    ct, st = trig(t)
    cs, ss = trig(s)
    return stack_matrix(
        [
            [cf * ct * cs - sf * ss, -cf * ct * ss - sf * cs, cf * st],
            [sf * ct * cs + cf * ss, -sf * ct * ss + cf * cs, sf * st],
            [-st * cs, st * ss, ct],
        ]
    )


def zyz_from_rotation(R: Any, check: bool = True) -> Any:
    r"""ZYZ Euler angles of a rotation matrix (inverse of :func:`rotation_from_zyz`).

    Regular case, θ in (0, π) (Siciliano et al. 2009, §2.4.1):

    .. math::
        \varphi = \operatorname{atan2}(r_{23}, r_{13}),\quad
        \vartheta = \operatorname{atan2}\!\big(\sqrt{r_{13}^2 + r_{23}^2}, r_{33}\big),\quad
        \psi = \operatorname{atan2}(r_{32}, -r_{31})

    **Singular** (:math:`\sin\vartheta < 10^{-8}`, θ = 0 or π): φ is set to 0 and
    ψ = atan2(r21, r11) for θ = 0, ψ = atan2(r21, r22) for θ = π.

    Parameters
    ----------
    R : array_like, shape (3, 3) or (N, 3, 3)
        Rotation matrix / matrices.
    check : bool, optional
        Validate that ``R`` is a rotation.

    Returns
    -------
    numpy.ndarray, shape (3,) or (N, 3)
        ``(phi, theta, psi)``; phi, psi in (−π, π], theta in [0, π].
    """
    a = as_rotation_matrix(R, check)
    r13, r23, r33 = a[..., 0, 2], a[..., 1, 2], a[..., 2, 2]
    st = np.hypot(r13, r23)
    theta = np.arctan2(st, r33)
    singular = st < _SINGULAR_TOL
    phi = np.where(singular, 0.0, np.arctan2(r23, r13))
    psi_sing = np.where(r33 > 0, np.arctan2(a[..., 1, 0], a[..., 0, 0]),
                        np.arctan2(a[..., 1, 0], a[..., 1, 1]))
    psi = np.where(singular, psi_sing, np.arctan2(a[..., 2, 1], -a[..., 2, 0]))
    return np.stack([phi, theta, psi], axis=-1)
