r"""A serial chain in the product-of-exponentials form (Lynch & Park 2017, ch. 4–5).

A chain's forward kinematics is a product of screw motions about the joints' axes, read
once at the home configuration :math:`\mathbf{q} = 0` (the space form, Lynch & Park 2017,
§4.1.1), and its Jacobians follow column by column (§5.1.1 and §5.1.2; their relation,
§5.1.4). :func:`screw_axes` gives the home pose :math:`M` and the screw axes,
:func:`product_of_exponentials` the pose, :func:`space_jacobian` and :func:`body_jacobian`
the two Jacobians. Chapter 8 of the workbook derives them.

Twists here are Lynch & Park's, **angular part first**, ``[ω; v]``; the geometric Jacobian of
:meth:`~robokin.chains.SerialChain.jacobian` is ``[v; ω]`` with ``v`` the velocity of the
end-effector's origin (``book/conventions.md``). ``tests/test_chains_screws.py`` checks the
pose against ``fk`` and both Jacobians against ``jacobian``, for every model of
:mod:`robokin.models`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.chains.protocol import DrawableChain
from robokin.errors import DomainError
from robokin.transforms.homogeneous import transform_inverse
from robokin.transforms.screws import adjoint, transform_exp
from robokin.validation import as_batch, check_result_finite

__all__ = ["screw_axes", "product_of_exponentials", "space_jacobian", "body_jacobian"]


def screw_axes(chain: DrawableChain) -> tuple[np.ndarray, np.ndarray]:
    r"""The home pose :math:`M` and the space-frame screw axes of a chain's joints.

    At :math:`\mathbf{q} = 0`, joint i turns about (or slides along) a unit axis through a
    point, both read in the base frame from the joint frames of
    :meth:`~robokin.chains.SerialChain.frames`; its screw axis :math:`\mathcal{S}_i` is the
    space twist of the links it carries when it moves at unit rate (Lynch & Park 2017,
    §3.3.2 and §4.1.1).

    Parameters
    ----------
    chain : DrawableChain
        A numeric chain (a :class:`~robokin.chains.SerialChain`, or any object with its
        ``n``, ``joint_types``, ``joint_axes`` and ``frames``).

    Returns
    -------
    M : numpy.ndarray, shape (4, 4)
        The end-effector's pose at :math:`\mathbf{q} = 0` (tool included).
    S : numpy.ndarray, shape (n, 6)
        Row i is :math:`\mathcal{S}_{i+1}`, angular part first.
    """
    frames = chain.frames(np.zeros(chain.n))
    S = np.zeros((chain.n, 6))
    for i, (kind, local_axis) in enumerate(zip(chain.joint_types, chain.joint_axes)):
        joint_frame = frames[i + 1]
        omega = joint_frame[:3, :3] @ local_axis
        point = joint_frame[:3, 3]
        if kind == "revolute":
            S[i] = np.concatenate([omega, -np.cross(omega, point)])
        else:
            S[i, 3:] = omega
    return frames[-1], S


def _configurations(chain: DrawableChain, q: Any) -> tuple[np.ndarray, bool]:
    """``q`` as a batch (N, n) and whether it came as one."""
    configurations, batched = as_batch(q, chain.n, "q")
    return configurations.reshape(-1, chain.n), batched


def _joint_motion(screw: np.ndarray, values: np.ndarray) -> np.ndarray:
    r""":math:`e^{[\mathcal{S}_i]q_i}` for a column of joint values, (N, 4, 4); an overflow names ``q``."""
    try:
        return transform_exp(screw * values[:, None])
    except DomainError:
        largest = float(np.max(np.abs(values), initial=0.0))
        raise DomainError(f"q is too large: computing e^([S] q) overflows float64 (largest |q| = {largest:.3g})") \
            from None


def product_of_exponentials(chain: DrawableChain, q: Any) -> np.ndarray:
    r"""End-effector pose as the product of exponentials of :func:`screw_axes` and :math:`M`.

    Equal to :meth:`~robokin.chains.SerialChain.fk` (Lynch & Park 2017, §4.1.1).

    Parameters
    ----------
    chain : DrawableChain
    q : array_like, shape (n,) or (N, n)
        Joint values (rad or m).

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (N, 4, 4)
    """
    q, batched = _configurations(chain, q)
    M, S = screw_axes(chain)
    T = np.broadcast_to(np.eye(4), (len(q), 4, 4))
    with np.errstate(all="ignore"):
        for i in range(chain.n):
            T = T @ _joint_motion(S[i], q[:, i])
        T = check_result_finite(T @ M, "the product of exponentials", q=q)
    return T if batched else T[0]


def space_jacobian(chain: DrawableChain, q: Any) -> np.ndarray:
    r"""Space Jacobian :math:`J_s(\mathbf{q})`: column i is joint i's screw axis at ``q``.

    :math:`\mathcal{V}_s = J_s \dot{\mathbf{q}}` is the end-effector's space twist ``[ω; v_s]``,
    :math:`[\mathcal{V}_s] = \dot T T^{-1}`: ``v_s`` is the velocity of the body point at the
    base origin (Lynch & Park 2017, §5.1.1).

    Parameters
    ----------
    chain : DrawableChain
    q : array_like, shape (n,) or (N, n)
        Joint values (rad or m).

    Returns
    -------
    numpy.ndarray, shape (6, n) or (N, 6, n)
        Rows ``[ω; v_s]``, in the base frame.
    """
    q, batched = _configurations(chain, q)
    _, S = screw_axes(chain)
    J = np.zeros((len(q), 6, chain.n))
    T = np.broadcast_to(np.eye(4), (len(q), 4, 4))
    with np.errstate(all="ignore"):
        for i in range(chain.n):
            J[:, :, i] = adjoint(T, check=False) @ S[i]
            T = T @ _joint_motion(S[i], q[:, i])
    check_result_finite(J, "the space Jacobian", q=q)
    return J if batched else J[0]


def body_jacobian(chain: DrawableChain, q: Any) -> np.ndarray:
    r"""Body Jacobian :math:`J_b(\mathbf{q})`, the Jacobian of the end-effector's body twist.

    :math:`\mathcal{V}_b = J_b \dot{\mathbf{q}}` is the end-effector's twist ``[ω_b; v_b]`` in its own
    frame, :math:`[\mathcal{V}_b] = T^{-1}\dot T`: ``v_b`` is the velocity of its origin, in the
    end-effector frame (Lynch & Park 2017, §5.1.2; its relation to :math:`J_s`, §5.1.4).

    Parameters
    ----------
    chain : DrawableChain
    q : array_like, shape (n,) or (N, n)
        Joint values (rad or m).

    Returns
    -------
    numpy.ndarray, shape (6, n) or (N, 6, n)
        Rows ``[ω_b; v_b]``, in the end-effector frame.
    """
    q, batched = _configurations(chain, q)
    with np.errstate(all="ignore"):
        J_b = adjoint(transform_inverse(product_of_exponentials(chain, q)), check=False) @ space_jacobian(chain, q)
    check_result_finite(J_b, "the body Jacobian", q=q)
    return J_b if batched else J_b[0]
