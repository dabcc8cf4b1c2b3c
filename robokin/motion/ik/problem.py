"""Argument checking and the per-solve context shared by the IK loops.

Everything here runs once per call of :func:`~robokin.motion.solve_ik` /
:func:`~robokin.motion.solve_ik_batch`; the iteration loops then call the
chain with ``check=False``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from operator import ge, gt, le, lt
from typing import Any, NamedTuple
from weakref import WeakKeyDictionary

import numpy as np

from robokin.chains.chain import SerialChain
from robokin.chains.protocol import Chain
from robokin.errors import DomainError, ShapeError
from robokin.motion._kernels import tool_jacobian, wrap_angles
from robokin.validation import (
    as_float_array,
    check_int,
    check_limits,
    check_positive,
    check_transform,
)

__all__ = ["IKContext", "make_context", "chain_data", "parse_target", "parse_tolerance", "parse_q0"]


@dataclass(eq=False)
class IKContext:
    """What the step rules and objectives may need about the problem.

    Attributes
    ----------
    chain : object
        The kinematic chain.
    n : int
        Number of joints.
    lower, upper : ndarray, shape (n,)
        Joint limits.
    mask : ndarray of bool, shape (6,)
        Task components ``[x, y, z, rx, ry, rz]`` that are controlled.
    tool : ndarray, shape (4, 4) or None
        Extra tool transform applied after the chain's end-effector.
    wrap : ndarray of bool, shape (n,) or None
        Joints whose angle is wrapped into (-pi, pi] after every step.
    shift : ndarray of bool, shape (n,) or None
        Revolute joints allowed to re-enter their range by ``±2 pi``.
    """

    chain: Chain
    n: int
    lower: np.ndarray
    upper: np.ndarray
    mask: np.ndarray
    tool: np.ndarray | None
    wrap: np.ndarray | None
    shift: np.ndarray | None = None

    def __post_init__(self) -> None:
        self.mask_list = self.mask.astype(float).tolist()  # 1.0 / 0.0 per component, for plain-float norms
        self.full_mask = 0.0 not in self.mask_list  # (plain floats: a NumPy reduction costs more for 6 entries)
        self.rows = self.mask.nonzero()[0]
        self.p_tool = None if self.tool is None else self.tool[:3, 3].copy()
        self._fk_and_jacobian = getattr(self.chain, "fk_and_jacobian", None)
        # the limits as plain floats: one configuration is checked in Python (map: no per-joint bytecode)
        self._lower_list = self.lower.tolist()
        self._upper_list = self.upper.tolist()

    def project(self, q: np.ndarray) -> np.ndarray:
        """Bring a configuration (batch) back within the limits: wrap, shift by 2 pi, clamp."""
        if self.wrap is not None:
            q = wrap_angles(q, self.wrap)
        if self.shift is not None:
            two_pi = 2.0 * np.pi
            q = np.where(self.shift & (q > self.upper) & (q - two_pi >= self.lower), q - two_pi, q)
            q = np.where(self.shift & (q < self.lower) & (q + two_pi <= self.upper), q + two_pi, q)
        return np.minimum(np.maximum(q, self.lower), self.upper)

    def touches_limit(self, q: np.ndarray) -> bool:
        """Does configuration ``q`` (n,) rest on one of its joint limits?"""
        x = q.tolist()
        return any(map(le, x, self._lower_list)) or any(map(ge, x, self._upper_list))

    def advance(self, q: np.ndarray, dq: np.ndarray) -> tuple[np.ndarray, bool]:
        """``q + dq`` brought within the limits (:meth:`project`), and whether it rests on a limit.

        One configuration (n,).  A step that stays strictly inside the limits
        (and no wrapping) is returned as is and reported off the limits.
        """
        q_new = q + dq
        x = q_new.tolist()
        if self.wrap is not None or any(map(lt, x, self._lower_list)) or any(map(gt, x, self._upper_list)):
            q_new = self.project(q_new)
            return q_new, self.touches_limit(q_new)
        return q_new, False

    def pose(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Flange pose and tool pose, each (4, 4) or (N, 4, 4)."""
        T_flange = self.chain.fk(q, check=False)
        if self.tool is None:
            return T_flange, T_flange
        return T_flange, T_flange @ self.tool

    def jacobian(self, q: np.ndarray, T_flange: np.ndarray) -> np.ndarray:
        """Geometric Jacobian of the tool frame, (6, n) or (N, 6, n)."""
        J = self.chain.jacobian(q, check=False)
        if self.p_tool is not None:
            J = tool_jacobian(J, T_flange[..., :3, :3], self.p_tool)
        return J

    def pose_and_jacobian(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Flange pose, tool pose (each (4, 4)) and tool Jacobian (6, n) of one configuration (n,).

        One pass over the chain when it offers ``fk_and_jacobian`` (a
        :class:`~robokin.chains.SerialChain` does); else :meth:`pose` and :meth:`jacobian`.
        """
        if self._fk_and_jacobian is None:
            T_flange, T = self.pose(q)
            return T_flange, T, self.jacobian(q, T_flange)
        T_flange, J = self._fk_and_jacobian(q, check=False)
        if self.tool is None or self.p_tool is None:  # both None or neither (__post_init__)
            return T_flange, T_flange, J
        return T_flange, T_flange @ self.tool, tool_jacobian(J, T_flange[:3, :3], self.p_tool)

    def poses_and_jacobians(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """Flange poses, tool poses (each (N, 4, 4)) and tool Jacobians (N, 6, n) of a batch (N, n).

        One pass over the chain when it offers ``fk_and_jacobian`` (a batch's
        poses and Jacobians then equal :meth:`pose`'s and :meth:`jacobian`'s to
        the last bit, row by row); else the Jacobians are None and
        :meth:`jacobian` computes those of the rows that need them.
        """
        if self._fk_and_jacobian is None:
            T_flange, T = self.pose(q)
            return T_flange, T, None
        T_flange, J = self._fk_and_jacobian(q, check=False)
        if self.tool is None or self.p_tool is None:  # both None or neither (__post_init__)
            return T_flange, T_flange, J
        return T_flange, T_flange @ self.tool, tool_jacobian(J, T_flange[..., :3, :3], self.p_tool)

    def task_jacobian(self, q: np.ndarray) -> np.ndarray:
        """Rows of the tool Jacobian selected by the mask."""
        T_flange, _ = self.pose(q)
        J = self.jacobian(q, T_flange)
        return J if self.full_mask else J[..., self.rows, :]


class _ChainData(NamedTuple):
    """What a solve needs to know about a chain besides its kinematics (read-only arrays)."""

    limits: Any  # the chain's limits object these were computed from
    lower: np.ndarray
    upper: np.ndarray
    revolute: np.ndarray
    middle: np.ndarray


#: :class:`_ChainData` of the SerialChains solved so far: their limits are a read-only array and
#: their joints fixed, so limits, joint types and the default initial guess are read once per chain.
_CHAIN_DATA: WeakKeyDictionary[Any, _ChainData] = WeakKeyDictionary()


def chain_data(chain: Chain) -> _ChainData:
    """Joint limits ``(lower, upper)``, revolute joints (n,) and the middle of the limits of ``chain``.

    Computed once per :class:`~robokin.chains.SerialChain` (cached while its
    limits stay the same read-only array); every call for other chains.
    """
    limits = getattr(chain, "limits", None)
    cached = _CHAIN_DATA.get(chain) if isinstance(chain, SerialChain) else None
    if cached is not None and cached.limits is limits:
        return cached
    n = int(chain.n)
    lower, upper = _chain_limits(chain)
    types = getattr(chain, "joint_types", None) or ("revolute",) * n
    revolute = np.array([t == "revolute" for t in types], dtype=bool)
    middle = np.clip(np.where(np.isfinite(lower) & np.isfinite(upper), 0.5 * (lower + upper), 0.0), lower, upper)
    for a in (lower, upper, revolute, middle):
        a.setflags(write=False)
    data = _ChainData(limits, lower, upper, revolute, middle)
    if isinstance(chain, SerialChain) and isinstance(limits, np.ndarray) and not limits.flags.writeable:
        _CHAIN_DATA[chain] = data
    return data


def _chain_limits(chain: Chain) -> tuple[np.ndarray, np.ndarray]:
    n = int(chain.n)
    limits = getattr(chain, "limits", None)
    if limits is None:
        return np.full(n, -np.inf), np.full(n, np.inf)
    lim = limits if isinstance(limits, np.ndarray) and limits.dtype == float else None
    if lim is None or lim.shape != (n, 2) or np.isnan(lim).any():
        lim = check_limits(limits, n, "chain.limits")
    return lim[:, 0].copy(), lim[:, 1].copy()


#: Largest target or tool distance (m) the solvers accept: errors are squared in the
#: iteration, so much larger values would overflow float64 (and reach nothing anyway).
MAX_DISTANCE = 1e100


def _check_distance(p: np.ndarray, name: str) -> None:
    if p.size and float(np.abs(p).max()) > MAX_DISTANCE:
        raise DomainError(f"{name} is too far away: translations must be at most {MAX_DISTANCE:.0e} m; "
                          f"got {float(np.abs(p).max()):.3g} m")


def parse_target(target: Any, batched: bool) -> tuple[np.ndarray, bool]:
    """Target as poses ``(4, 4)``/``(N, 4, 4)``; a position gets an identity rotation.

    Returns ``(T_goal, is_position)``.
    """
    name = "targets" if batched else "target"
    if not batched and type(target) is np.ndarray and target.dtype == np.float64 and target.shape == (4, 4):
        return _check_pose(target, name), False  # the usual call: one float64 pose, checked in plain floats
    a = as_float_array(target, name)
    if not batched and a.shape == (4, 4):
        return _check_pose(a, name), False
    _check_distance(a[..., :3, 3] if a.ndim >= 2 and a.shape[-2:] == (4, 4) else a, name)
    if batched:
        if a.ndim == 2 and a.shape[1] == 3:
            T = np.broadcast_to(np.eye(4), (a.shape[0], 4, 4)).copy()
            T[:, :3, 3] = a
            return T, True
        if a.ndim == 3 and a.shape[1:] == (4, 4):
            return check_transform(a, name=name), False
        raise ShapeError(f"{name} must have shape (N, 3) (positions) or (N, 4, 4) (poses); got shape {a.shape}")
    if a.shape == (3,):
        T = np.eye(4)
        T[:3, 3] = a
        return T, True
    if a.shape == (4, 4):
        return _check_pose(a, name), False
    raise ShapeError(f"{name} must have shape (3,) (a position) or (4, 4) (a pose); got shape {a.shape}")


def _check_pose(T: np.ndarray, name: str, tol: float = 1e-6) -> np.ndarray:
    """Fast check of one float64 (4, 4) transform (plain floats); falls back to the full checks for the message.

    Checks what :func:`~robokin.validation.as_float_array` and
    :func:`~robokin.validation.check_transform` check (finite entries, bottom row
    ``[0, 0, 0, 1]``, :math:`|RR^T - I| \\le` ``tol`` entry by entry, det R > 0)
    and the distance limit :data:`MAX_DISTANCE`: every test below fails for NaN
    or infinite entries.
    """
    (r00, r01, r02, px), (r10, r11, r12, py), (r20, r21, r22, pz), (b0, b1, b2, b3) = T.tolist()
    if not (abs(px) <= MAX_DISTANCE and abs(py) <= MAX_DISTANCE and abs(pz) <= MAX_DISTANCE):
        as_float_array(T, name)  # NaN or infinite: the message names the entry
        _check_distance(T[:3, 3], name)
    det = r00 * (r11 * r22 - r12 * r21) - r01 * (r10 * r22 - r12 * r20) + r02 * (r10 * r21 - r11 * r20)
    ok = (
        abs(b0) <= tol and abs(b1) <= tol and abs(b2) <= tol and abs(b3 - 1.0) <= tol
        and abs(r00 * r00 + r01 * r01 + r02 * r02 - 1.0) <= tol
        and abs(r10 * r10 + r11 * r11 + r12 * r12 - 1.0) <= tol
        and abs(r20 * r20 + r21 * r21 + r22 * r22 - 1.0) <= tol
        and abs(r00 * r10 + r01 * r11 + r02 * r12) <= tol
        and abs(r00 * r20 + r01 * r21 + r02 * r22) <= tol
        and abs(r10 * r20 + r11 * r21 + r12 * r22) <= tol
        and det > 0.0
    )
    if ok:
        return T
    as_float_array(T, name)  # NaN or infinite: the message names the entry
    return check_transform(T, name=name)


#: The default masks (read-only): every component of a pose, the position of a position target.
_POSE_MASK = np.ones(6, dtype=bool)
_POSITION_MASK = np.array([True] * 3 + [False] * 3)
_POSE_MASK.setflags(write=False)
_POSITION_MASK.setflags(write=False)


def parse_mask(mask: Any, is_position: bool) -> np.ndarray:
    if mask is None:
        return _POSITION_MASK if is_position else _POSE_MASK
    m = np.asarray(mask)
    if m.shape != (6,):
        raise ShapeError(f"mask must have shape (6,) (booleans for x, y, z, rx, ry, rz); got shape {m.shape}")
    if m.dtype != bool:
        if not np.all(np.isin(m, (0, 1))):
            raise DomainError(f"mask must contain booleans; got {m!r}")
        m = m.astype(bool)
    if not m.any():
        raise DomainError("mask must select at least one task component; got all False")
    if is_position and m[3:].any():
        raise DomainError("mask selects orientation components but the target is a position (3,); give a (4, 4) pose")
    return m


def parse_tolerance(tol: Any) -> tuple[float, float]:
    """``tol`` as ``(position (m), orientation (rad))``; a scalar sets both."""
    if type(tol) is float and 0.0 < tol < math.inf:  # the usual case, a positive float
        return tol, tol
    if np.ndim(tol) == 0:
        t = check_positive(tol, "tol", scalar=True)
        return t, t
    t = as_float_array(tol, "tol", (2,))
    check_positive(t, "tol")
    return float(t[0]), float(t[1])


def parse_q0(q0: Any, n: int, lower: np.ndarray, upper: np.ndarray, count: int | None,
             middle: np.ndarray | None = None) -> np.ndarray:
    """Initial guess(es): ``None`` -> middle of the limits (0 for unlimited joints; ``middle`` if given)."""
    if q0 is None:
        if middle is None:
            middle = np.clip(np.where(np.isfinite(lower) & np.isfinite(upper), 0.5 * (lower + upper), 0.0),
                             lower, upper)
        return middle.copy() if count is None else np.tile(middle, (count, 1))
    name = "q0"
    a = as_float_array(q0, name)
    if count is None:
        if a.shape != (n,):
            raise ShapeError(f"{name} must have shape ({n},); got shape {a.shape}")
    elif a.shape == (n,):
        a = np.tile(a, (count, 1))
    elif a.shape != (count, n):
        raise ShapeError(f"{name} must have shape ({n},) or ({count}, {n}); got shape {a.shape}")
    return np.clip(a, lower, upper)


def parse_wrap(wrap: Any, chain: Chain, n: int, revolute: np.ndarray | None = None
               ) -> tuple[np.ndarray | None, np.ndarray | None]:
    """``wrap`` -> (joints wrapped every step, revolute joints that may re-enter by 2 pi).

    ``"limits"`` (default): no wrapping, but a revolute joint that would leave
    its range re-enters it by ``±2 pi`` when that lands inside (same pose);
    ``True``: every revolute joint wrapped into (-pi, pi] each step;
    ``False``/``None``: plain clamping; booleans (n,): those joints wrapped.
    ``revolute`` (n,) bool: the chain's revolute joints, if the caller has them
    (default: :func:`chain_data`).
    """
    if revolute is None:  # (n,) bool, the revolute joints
        revolute = chain_data(chain).revolute
    if isinstance(wrap, str):
        if wrap != "limits":
            raise ValueError(f"wrap must be True, False, 'limits' or booleans of shape ({n},); got {wrap!r}")
        return None, (revolute if revolute.any() else None)
    if wrap is None or wrap is False:
        return None, None
    if wrap is True:
        return (revolute if revolute.any() else None), None
    m = np.asarray(wrap)
    if m.shape != (n,):
        raise ShapeError(f"wrap must be a bool, 'limits' or have shape ({n},); got shape {m.shape}")
    m = m.astype(bool)
    return (m if m.any() else None), None


def make_context(chain: Chain, mask: np.ndarray, tool: Any, wrap: Any) -> IKContext:
    """The :class:`IKContext` of a solve: ``chain`` already checked (:func:`~robokin.validation.check_chain`),
    ``mask`` from :func:`parse_mask`; the tool and ``wrap`` are checked here."""
    n = int(chain.n)
    data = chain_data(chain)
    lower, upper = data.lower, data.upper
    T_tool = None
    if tool is not None:
        T_tool = check_transform(tool, name="tool")
        if T_tool.ndim != 2:
            raise ShapeError(f"tool must have shape (4, 4); got shape {T_tool.shape}")
        _check_distance(T_tool[:3, 3], "tool")
        if np.allclose(T_tool, np.eye(4), rtol=0, atol=0):
            T_tool = None
    wrap_mask, shift_mask = parse_wrap(wrap, chain, n, data.revolute)
    return IKContext(chain, n, lower, upper, mask, T_tool, wrap_mask, shift_mask)


def check_nonnegative_int(value: Any, name: str, minimum: int = 0) -> int:
    """An integer >= ``minimum`` (iteration and restart counts; at most 10**7)."""
    return check_int(value, name, minimum, 10**7)


def parse_stall(method: Any, iterations: Any, tolerance: Any) -> tuple[int, float]:
    """Stall-detection parameters, defaulting to the method's ``default_stall``."""
    k, f = method.default_stall
    k = k if iterations is None else check_nonnegative_int(iterations, "stall_iterations", 1)
    f = f if tolerance is None else check_positive(tolerance, "stall_tolerance", allow_zero=True, scalar=True)
    if f >= 1:
        raise DomainError(f"stall_tolerance must be < 1 (a fraction of the error); got {f:g}")
    return k, float(f)
