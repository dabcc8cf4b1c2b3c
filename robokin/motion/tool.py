r"""A tool rigidly attached to the end-effector: its pose, its Jacobian, its chain.

A tool frame T fixed to the end-effector frame E is given by the constant
transform :math:`{}^{E}\mathbf{T}_{T}` (an orientation and an offset written in
E). Then (Siciliano et al. 2009, §2.8 for the pose, §3.1.2 for the velocities)

.. math::
    {}^{B}\mathbf{T}_{T} = {}^{B}\mathbf{T}_{E}\,{}^{E}\mathbf{T}_{T}, \qquad
    \mathbf{J}_T = \begin{bmatrix} \mathbf{I} & -[{}_B\mathbf{r}_{ET}]_\times \\
                                   \mathbf{0} & \mathbf{I} \end{bmatrix} \mathbf{J}_E,
    \qquad {}_B\mathbf{r}_{ET} = {}^{B}\mathbf{R}_{E}\;{}_E\mathbf{r}_{ET},

because both frames share one angular velocity and the tool point moves with
:math:`\mathbf{v}_T = \mathbf{v}_E + \boldsymbol\omega \times {}_B\mathbf{r}_{ET}`
(the twist is ``[v; ω]``, linear part first, base frame). Lynch and Park
2017, §3.3.2, write the same transport with the adjoint map (angular part first).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.chains.protocol import Chain
from robokin.errors import ShapeError
from robokin.transforms import skew
from robokin.transforms import transform_from_rpy as transform_from_rpy  # moved; chapter 4 imports it here
from robokin.validation import (
    as_float_array,
    check_chain,
    check_result_finite,
    check_rotation_matrix,
    check_transform,
)

__all__ = ["chain_with_tool", "rigid_body_jacobian", "tool_jacobian"]


def rigid_body_jacobian(r: Any) -> np.ndarray:
    r"""Rigid-body Jacobian: the twist transport from a point E to a point T of one rigid body.

    Parameters
    ----------
    r : array_like, shape (3,) or (N, 3)
        :math:`{}_B\mathbf{r}_{ET}`, the vector from E to T in the frame in which
        the twists are written (usually the base frame), metres.

    Returns
    -------
    numpy.ndarray, shape (6, 6) or (N, 6, 6)
        .. math::
            \mathbf{J}_{\mathrm{rb}}(\mathbf{r}) = \begin{bmatrix} \mathbf{I}_3 & -[\mathbf{r}]_\times \\
            \mathbf{0} & \mathbf{I}_3 \end{bmatrix},
            \qquad \begin{bmatrix}\mathbf{v}_T\\ \boldsymbol\omega\end{bmatrix}
            = \mathbf{J}_{\mathrm{rb}}(\mathbf{r}) \begin{bmatrix}\mathbf{v}_E\\ \boldsymbol\omega\end{bmatrix},

        since :math:`\mathbf{v}_T = \mathbf{v}_E + \boldsymbol\omega\times\mathbf{r}
        = \mathbf{v}_E - \mathbf{r}\times\boldsymbol\omega` (Siciliano et al. 2009,
        §3.1.2), with :math:`[\mathbf{r}]_\times` the skew-symmetric matrix of
        :math:`\mathbf{r}` (``skew``). With the angular part first, ``[ω; v]``, the
        same map reads :math:`\mathbf{S}\,\mathbf{J}_{\mathrm{rb}}\,\mathbf{S} =
        \begin{bmatrix}\mathbf{I} & \mathbf{0}\\ [\mathbf{r}]_\times^\top & \mathbf{I}\end{bmatrix}`,
        :math:`\mathbf{S}` the row swap of ``book/conventions.md``.

    Raises
    ------
    ShapeError
        ``r`` not of shape (3,) or (N, 3).
    DomainError
        NaN or infinite entries.
    """
    v = as_float_array(r, "r")
    if v.shape[-1:] != (3,) or v.ndim > 2:
        raise ShapeError(f"r must have shape (3,) or (N, 3) (vector from E to T, metres); got shape {v.shape}")
    S = np.zeros(v.shape[:-1] + (6, 6))
    S[..., :3, :3] = np.eye(3)
    S[..., 3:, 3:] = np.eye(3)
    S[..., :3, 3:] = -skew(v)
    return S


def tool_jacobian(J_ee: Any, R_be: Any, p_et: Any) -> np.ndarray:
    r"""Geometric Jacobian of a tool point from the end-effector's Jacobian.

    Parameters
    ----------
    J_ee : array_like, shape (6, n) or (N, 6, n)
        Geometric Jacobian of the end-effector E, rows ``[v; ω]``, base frame.
    R_be : array_like, shape (3, 3) or (N, 3, 3)
        :math:`{}^{B}\mathbf{R}_{E}`, orientation of E in the base.
    p_et : array_like, shape (3,)
        :math:`{}_E\mathbf{r}_{ET}`, the tool offset written in E (metres).

    Returns
    -------
    numpy.ndarray, shape (6, n) or (N, 6, n)
        :math:`\mathbf{J}_T = \mathbf{S}({}^{B}\mathbf{R}_{E}\,{}_E\mathbf{r}_{ET})\,\mathbf{J}_E`
        (see :func:`rigid_body_jacobian`). The offset must be rotated into the
        base frame first; using :math:`{}_E\mathbf{r}_{ET}` directly is only right
        while :math:`{}^{B}\mathbf{R}_{E} = \mathbf{I}`.

    Raises
    ------
    ShapeError
        Arguments of the wrong shapes (the message names the argument).
    DomainError
        ``R_be`` not a rotation, or NaN/inf entries.
    """
    J = as_float_array(J_ee, "J_ee")
    if J.ndim not in (2, 3) or J.shape[-2] != 6:
        raise ShapeError(f"J_ee must have shape (6, n) or (N, 6, n); got shape {J.shape}")
    R = check_rotation_matrix(R_be, name="R_be")
    if R.shape[:-2] != J.shape[:-2]:
        raise ShapeError(f"R_be must have shape {J.shape[:-2] + (3, 3)} to match J_ee of shape "
                         f"{J.shape}; got shape {R.shape}")
    p = as_float_array(p_et, "p_et", (3,))
    with np.errstate(all="ignore"):
        r = check_result_finite(R @ p, "the tool offset in the base frame", p_et=p)
        out = rigid_body_jacobian(r) @ J
    return check_result_finite(out, "the tool Jacobian", J_ee=J, p_et=p)


def chain_with_tool(chain: Chain, T_et: Any, *, name: str | None = None) -> Chain:
    r"""The same robot with its end-effector moved to a tool frame.

    Parameters
    ----------
    chain : SerialChain
        The robot; its end-effector frame is E.
    T_et : array_like, shape (4, 4)
        :math:`{}^{E}\mathbf{T}_{T}`, constant pose of the tool in E.
    name : str, optional
        Name of the new chain (default ``<chain.name>+tool``).

    Returns
    -------
    SerialChain
        Same elements, joint names, limits and frame names; its ``fk`` is
        :math:`{}^{B}\mathbf{T}_{T} = {}^{B}\mathbf{T}_{E}\,{}^{E}\mathbf{T}_{T}` and its
        ``jacobian`` the tool Jacobian, so controllers, simulations and scenes
        use the tool frame directly.

    Raises
    ------
    ShapeError, DomainError
        ``T_et`` not a (4, 4) homogeneous transform.
    TypeError
        ``chain`` is not a :class:`~robokin.chains.SerialChain`.
    """
    from robokin.chains import SerialChain

    check_chain(chain, "chain", ("fk",))
    if not isinstance(chain, SerialChain):
        raise TypeError(f"chain must be a robokin SerialChain (e.g. robokin.models.panda()); got "
                        f"{type(chain).__name__}")
    T = check_transform(T_et, name="T_et")
    if T.shape != (4, 4):
        raise ShapeError(f"T_et must have shape (4, 4); got shape {T.shape}")
    tool = np.asarray(chain.tool, dtype=float) @ T
    return SerialChain(chain.elements, limits=chain.limits, tool=tool, frame_names=chain.frame_names,
                       name=name or f"{getattr(chain, 'name', 'chain')}+tool")
