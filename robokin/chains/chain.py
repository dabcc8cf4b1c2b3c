r"""Serial kinematic chains described by elementary transforms.

:class:`SerialChain` holds one representation of a serial robot: a sequence of
elementary transforms (see :mod:`robokin.chains.elements`). Denavit–Hartenberg
tables, modified (Craig) DH tables and link-transform tables are translated into
that sequence by :mod:`robokin.chains.tables` (for the builders of
:mod:`robokin.chains.builders` and the alternative constructors of :class:`SerialChain`).

The same object gives

* forward kinematics :math:`{}^B\mathbf{T}_E(\mathbf{q})` (Siciliano et al. 2009,
  §2.8–2.9; Craig 2005, §3; Lynch & Park 2017, §4),
* the frames of every joint (for drawing and for the Jacobian),
* the geometric Jacobian :math:`\mathbf{J} = [\mathbf{J}_v; \mathbf{J}_\omega]`
  expressed in the base frame (Siciliano et al. 2009, §3.1),
* manipulability measures (Yoshikawa 1985; Siciliano et al. 2009, §3.9),

for a single configuration ``q`` of shape ``(n,)``, a batch ``(N, n)``, or sympy
symbols (exact, simplified ``sympy.Matrix`` results).

Frames
------
Index ``0`` is the base frame (identity). Index ``i`` (1..n) is the frame attached
*after* joint ``i`` moves, i.e. the product of all elements up to and including
joint ``i``; joint ``i``'s axis passes through its origin with direction
``joint_axes[i-1]`` in that frame's own coordinates. Index ``n+1`` is the
end-effector (including the tool transform).
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from robokin._dispatch import is_symbolic
from robokin.chains._engine import Engine
from robokin.chains.elements import Element, Fixed, elementary_transform
from robokin.chains.protocol import Chain, DrawableChain, Frame
from robokin.chains.tables import dh_elements, link_table_elements
from robokin.errors import DomainError, ShapeError
from robokin.validation import (
    as_float_array,
    as_vector,
    check_int,
    check_limits,
    check_positive,
    check_result_finite,
    check_transform,
)

__all__ = ["SerialChain"]

_F64 = np.dtype(np.float64)
#: Joint values (m) or link dimensions beyond which results are checked for float64 overflow.
_BIG = 1e100
#: Largest number of entries random_configurations may allocate (N * n floats, 800 MB).
_MAX_SAMPLES = 10**8
_DEFAULT_REVOLUTE_LIMITS = (-math.pi, math.pi)
_DEFAULT_PRISMATIC_LIMITS = (-1.0, 1.0)


def _numeric_element(el: Element) -> np.ndarray:
    """Constant 4×4 float matrix of a constant element."""
    if el.kind == "F":
        M = el.matrix
        try:
            return np.array(M.evalf() if hasattr(M, "evalf") else M, dtype=float)
        except TypeError:
            raise TypeError("Fixed element has free symbols; substitute them first") from None
    T = np.array(elementary_transform(el.kind, el.axis, float(el.value)), dtype=float)
    # exact zeros for multiples of π/2 (cos(π/2) = 6e-17 in floating point)
    T[np.abs(T) < 1e-15] = 0.0
    return T


def _free_symbols(x: Any) -> set:
    fs = getattr(x, "free_symbols", None)
    return set(fs) if fs else set()


def _default_limits(joint: Element) -> tuple[float, float]:
    """A joint's own limits, else (-π, π) for a revolute and (-1, 1) m for a prismatic joint."""
    if joint.limits is not None:
        return joint.limits
    return _DEFAULT_REVOLUTE_LIMITS if joint.kind == "R" else _DEFAULT_PRISMATIC_LIMITS


def _tool_matrix(tool: Any) -> Any:
    """The checked tool transform: identity, a float (4, 4) array or a 4×4 sympy.Matrix."""
    if tool is None:
        return np.eye(4)
    if is_symbolic(tool):
        import sympy as sp

        matrix = sp.Matrix(tool)
        if matrix.shape != (4, 4):
            raise ShapeError(f"tool must have shape (4, 4); got shape {matrix.shape}")
        return matrix
    t = check_transform(tool, name="tool")
    if t.shape != (4, 4):
        raise ShapeError(f"tool must have shape (4, 4); got shape {t.shape}")
    return np.array(t, dtype=float)


def _frame_names(frame_names: Any, n: int) -> tuple[str, ...]:
    """``n + 2`` frame names (strings; integers are accepted and converted)."""
    if isinstance(frame_names, str) or not hasattr(frame_names, "__iter__"):
        raise TypeError(f"frame_names must be a sequence of {n + 2} strings; got {type(frame_names).__name__} "
                        f"{frame_names!r}")
    frame_names = list(frame_names)
    bad = [f for f in frame_names if not isinstance(f, (str, int, np.integer))]
    if bad:
        raise TypeError(f"frame_names must contain strings; got {type(bad[0]).__name__} {bad[0]!r}")
    if len(frame_names) != n + 2:
        raise ShapeError(
            f"frame_names must have {n + 2} entries (base, one per joint, end-effector); "
            f"got {len(frame_names)}"
        )
    return tuple(str(f) for f in frame_names)


class SerialChain:
    r"""A serial kinematic chain built from elementary transforms.

    Parameters
    ----------
    elements : sequence of Element
        Elementary transforms from base to end-effector, e.g.
        ``[Ty(1), Rx("alpha"), Tz(-1), Ry("beta"), Tz(-1), Ry("gamma"), Tz(-1)]``
        (see :mod:`robokin.chains.elements`). Joint elements are given by a joint
        name (a string, optionally prefixed with ``-`` for a negative axis).
    limits : array_like, shape (n, 2), optional
        Joint limits ``[lower, upper]`` in radians (revolute) / metres
        (prismatic). Default: limits attached to the joint elements, else
        ``(-π, π)`` for revolute and ``(-1, 1)`` m for prismatic joints.
    tool : array_like, shape (4, 4), optional
        Constant transform from the last element's frame to the end-effector
        (``T_{n,E}``). Default identity.
    base : array_like, shape (4, 4), optional
        Constant transform prepended to the elements (pose of the first element's
        frame in the world/base frame).
    frame_names : sequence of str, optional
        ``n + 2`` names for the frames returned by :meth:`frames`. Default
        ``["base", <joint names>..., "ee"]``.
    name : str, optional
        Name of the robot, used in ``repr``.

    Raises
    ------
    ValueError
        No joint element, or duplicate joint names.
    ShapeError, DomainError
        Bad ``limits``, ``tool``, ``base`` or ``frame_names``.

    Notes
    -----
    Forward kinematics is the product of the elements (Corke 2017, ch. 7):

    .. math::  {}^B\mathbf{T}_E(\mathbf{q}) = E_1 E_2 \cdots E_m\, \mathbf{T}_{tool}

    where a joint element moves by ``sign * q_i + offset``.

    Examples
    --------
    >>> from robokin.chains import SerialChain, Ty, Tz, Rx, Ry
    >>> leg = SerialChain([Ty(1), Rx("alpha"), Tz(-1), Ry("beta"), Tz(-1),
    ...                    Ry("gamma"), Tz(-1)])
    >>> leg.n
    3
    >>> leg.fk([0.0, 0.0, 0.0])[:3, 3]
    array([ 0.,  1., -3.])
    """

    def __init__(
        self,
        elements: Sequence[Element],
        *,
        limits: Any = None,
        tool: Any = None,
        base: Any = None,
        frame_names: Sequence[str] | None = None,
        name: str = "chain",
    ) -> None:
        if isinstance(elements, (str, Element)) or not hasattr(elements, "__iter__"):
            raise TypeError(f"elements must be a sequence of Element (Tx, Ty, Tz, Rx, Ry, Rz, Fixed); got "
                            f"{type(elements).__name__} {elements!r}"[:200])
        elements = list(elements)
        for i, el in enumerate(elements):
            if not isinstance(el, Element):
                raise TypeError(
                    f"elements[{i}] must be an Element (Tx, Ty, Tz, Rx, Ry, Rz, Fixed); "
                    f"got {type(el).__name__} {el!r}"
                )
        if base is not None:
            if not isinstance(base, Element):
                if not is_symbolic(base):
                    b = check_transform(base, name="base")
                    if b.shape != (4, 4):
                        raise ShapeError(f"base must have shape (4, 4); got shape {b.shape}")
                base = Fixed(base)
            elements.insert(0, base)
        joints = [el for el in elements if el.is_joint]
        if not joints:
            raise ValueError("elements must contain at least one joint element")
        names = [el.joint for el in joints if el.joint is not None]
        dup = sorted(name for name, count in Counter(names).items() if count > 1)
        if dup:
            raise ValueError(f"joint names must be unique; repeated: {dup}")
        self._elements: tuple[Element, ...] = tuple(elements)
        self._joints = tuple(joints)
        self._n = len(joints)
        self.name = str(name)
        n = self._n
        if limits is None:
            limits = [_default_limits(el) for el in joints]
        self._limits = check_limits(limits, n, "limits").copy()
        self._limits.setflags(write=False)
        self._tool = _tool_matrix(tool)
        self._frame_names = _frame_names(["base", *names, "ee"] if frame_names is None else frame_names, n)
        axes = np.zeros((n, 3))
        for i, el in enumerate(joints):
            axes[i, el.axis] = float(el.sign)
        axes.setflags(write=False)
        self._joint_axes = axes
        self._engine_cache: Engine | None = None
        #: the engine once compiled, if no result of it can overflow (revolute joints, links of
        #: ordinary size): a single configuration then goes to it without an overflow check
        self._unchecked_engine: Engine | None = None
        self._zeros = np.zeros(n)
        self._sym_cache: dict = {}

    # ------------------------------------------------------------ properties
    @property
    def n(self) -> int:
        """Number of joints."""
        return self._n

    @property
    def elements(self) -> tuple[Element, ...]:
        """The elementary transforms (base to tool, tool not included)."""
        return self._elements

    @property
    def joint_names(self) -> list[str]:
        """Joint names, in order from base to tool."""
        return [el.joint for el in self._joints if el.joint is not None]

    @property
    def joint_types(self) -> list[str]:
        """``'revolute'`` or ``'prismatic'`` for each joint."""
        return [el.joint_type for el in self._joints]

    @property
    def limits(self) -> np.ndarray:
        """Joint limits, shape (n, 2): ``[lower, upper]`` (rad or m), read-only."""
        return self._limits

    @property
    def tool(self) -> Any:
        """Constant tool transform ``T_{n,E}``, shape (4, 4)."""
        return self._tool.copy()

    @property
    def frame_names(self) -> list[str]:
        """Names of the ``n + 2`` frames returned by :meth:`frames`."""
        return list(self._frame_names)

    @property
    def joint_axes(self) -> np.ndarray:
        """Joint axis directions, shape (n, 3): unit vectors in each joint's own frame."""
        return self._joint_axes

    @property
    def parameters(self) -> set:
        """Free sympy symbols in constant elements (link parameters), if any."""
        out: set = set()
        for el in self._elements:
            if el.is_joint:
                out |= _free_symbols(el.offset)
            elif el.kind == "F":
                out |= _free_symbols(el.matrix)
            else:
                out |= _free_symbols(el.value)
        out |= _free_symbols(self._tool)
        return out

    def __repr__(self) -> str:
        ets = " ".join(repr(e) for e in self._elements)
        return f"SerialChain(name={self.name!r}, n={self.n}, ets='{ets}')"

    # ------------------------------------------------------------ construction
    @classmethod
    def from_dh(cls, table: Any, *, joint_names: Sequence[str] | None = None, **kwargs: Any) -> SerialChain:
        """Build from a standard DH table; see :func:`robokin.chains.from_dh`."""
        return cls(dh_elements(table, joint_names, modified=False), **{"name": "dh_chain", **kwargs})

    @classmethod
    def from_modified_dh(cls, table: Any, *, joint_names: Sequence[str] | None = None, **kwargs: Any) -> SerialChain:
        """Build from a modified (Craig) DH table; see :func:`robokin.chains.from_modified_dh`."""
        return cls(dh_elements(table, joint_names, modified=True), **{"name": "mdh_chain", **kwargs})

    @classmethod
    def from_link_table(
        cls, transforms: Any, joint_types: Any, *, joint_names: Sequence[str] | None = None, **kwargs: Any
    ) -> SerialChain:
        """Build from fixed link transforms at q = 0; see :func:`robokin.chains.from_link_table`."""
        return cls(link_table_elements(transforms, joint_types, joint_names), **{"name": "link_table_chain", **kwargs})

    def subs(self, values: dict) -> SerialChain:
        """Return a copy with link parameters substituted, e.g. ``{l1: 0.5}``.

        Parameters
        ----------
        values : dict
            Mapping from sympy symbols (or their names) to numbers or expressions.

        Returns
        -------
        SerialChain
            Same joints, limits and frame names; numeric once every parameter
            has a number.

        Raises
        ------
        TypeError
            ``values`` is not a dict, or a value is neither a number nor a sympy
            expression.
        DomainError
            A NaN or infinite value.
        """
        import sympy as sp

        if not isinstance(values, dict):
            raise TypeError(f"values must be a dict {{symbol or name: number}}, e.g. {{l1: 0.5}}; got "
                            f"{type(values).__name__} {values!r}"[:200])
        byname = {}
        for k, v in values.items():
            if isinstance(v, (sp.Basic, sp.MatrixBase)):
                pass
            elif isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
                raise TypeError(f"values[{k!r}] must be a number or a sympy expression; got "
                                f"{type(v).__name__} {v!r}")
            elif not math.isfinite(float(v)):
                raise DomainError(f"values[{k!r}] must be finite; got {v}")
            byname[str(k)] = v

        def sub(x: Any) -> Any:
            if not isinstance(x, (sp.Basic, sp.MatrixBase)):
                return x
            y = x.subs({s: byname[str(s)] for s in x.free_symbols if str(s) in byname})
            if y.free_symbols:
                return y
            if isinstance(y, sp.MatrixBase):
                return np.array(y.evalf(), dtype=float)
            return float(y)

        new = []
        for el in self._elements:
            if el.kind == "F":
                new.append(Element("F", matrix=sub(el.matrix)))
            else:
                new.append(Element(el.kind, el.axis, sub(el.value), el.joint, el.sign,
                                   sub(el.offset), el.limits))
        return SerialChain(new, limits=self._limits, tool=sub(self._tool),
                           frame_names=self._frame_names, name=self.name)

    # ------------------------------------------------------------ engine
    @property
    def _engine(self) -> Engine:
        if self._engine_cache is None:
            params = self.parameters
            if params:
                raise TypeError(
                    f"chain {self.name!r} has symbolic link parameters {sorted(map(str, params))}; "
                    f"numeric evaluation needs numbers: use chain.subs({{...}}) first"
                )
            consts = [np.eye(4)]
            axes, rev, signs, offs = [], [], [], []
            for el in self._elements:
                if el.is_joint:
                    consts.append(np.eye(4))
                    axes.append(el.axis)
                    rev.append(el.kind == "R")
                    signs.append(float(el.sign))
                    offs.append(float(el.offset))
                else:
                    consts[-1] = consts[-1] @ _numeric_element(el)
            consts[-1] = consts[-1] @ np.asarray(self._tool, dtype=float)
            self._engine_cache = Engine(consts, axes, rev, signs, offs)
            # results can overflow only with prismatic joints or huge link dimensions
            self._max_constant = max(float(np.abs(C).max()) for C in consts)
            self._huge_links = self._max_constant > _BIG
            self._prismatic = not all(rev)
            if not (self._huge_links or self._prismatic):
                self._unchecked_engine = self._engine_cache
        return self._engine_cache

    # ------------------------------------------------------------ argument parsing
    def _parse_q(self, q: Any, check: bool) -> tuple[str, Any]:
        """Classify ``q``: ('single', (n,) array), ('batch', (N, n) array) or ('sym', list)."""
        n = self._n
        if type(q) is np.ndarray and q.dtype is _F64:
            a = q
        elif not check and isinstance(q, np.ndarray) and q.dtype.kind in "iuf":
            a = q.astype(np.float64)
        elif is_symbolic(q):
            import sympy as sp

            if isinstance(q, sp.MatrixBase):
                items = list(q)
                shape = q.shape
                ok = len(items) == n and 1 in shape
            else:
                arr = np.asarray(q, dtype=object)
                items = list(arr.ravel())
                shape = arr.shape
                ok = arr.ndim == 1 and len(items) == n
            if not ok:
                raise ShapeError(f"q must have shape ({n},) for symbolic input; got shape {shape}")
            return "sym", [sp.sympify(x) for x in items]
        else:
            a = as_float_array(q, "q")
        if a.ndim == 1 and a.shape[0] == n:
            if check:
                total = sum(a.tolist())  # Python floats: inf/NaN propagate without numpy warnings
                if total - total != 0.0:  # NaN unless every entry is finite (or the sum overflowed)
                    as_float_array(a, "q")  # raises DomainError naming q and the entry
            return "single", a
        if a.ndim == 2 and a.shape[1] == n:
            if check and not np.isfinite(a).all():
                as_float_array(a, "q")
            return "batch", a
        raise ShapeError(f"q must have shape ({n},) or (N, {n}); got shape {a.shape}")

    def _overflow_risk(self, a: np.ndarray, point: Any = None) -> bool:
        """True if a result computed from ``a`` (and ``point``) could overflow float64.

        Only chains with prismatic joints and huge joint values, huge link
        dimensions, or a huge ``point`` can; for revolute chains of ordinary
        size this costs one attribute lookup.
        """
        self._engine  # noqa: B018  (compiles the chain; sets _huge_links and _prismatic)
        if self._huge_links:
            return True
        if point is not None and float(np.abs(point).max()) > _BIG:
            return True
        return self._prismatic and a.size > 0 and float(np.abs(a).max()) > _BIG

    def _direct_engine(self, a: np.ndarray, check: bool) -> Engine | None:
        """The engine, if one configuration ``a`` can go to it without an overflow check; else None.

        (The chain's ``_unchecked_engine`` once compiled, when nothing can overflow.)
        """
        return self._engine if not (check and self._overflow_risk(a)) else None

    def _checked(self, out: np.ndarray, what: str, **inputs: Any) -> np.ndarray:
        """``out`` if finite; else a DomainError naming the inputs (or the chain's huge dimensions)."""
        if np.isfinite(out).all():
            return out
        if self._huge_links:
            raise DomainError(f"chain {self.name!r} has dimensions too large for float64: computing {what} "
                              f"overflows (largest constant transform entry {self._max_constant:.3g} m)")
        return check_result_finite(out, what, **inputs)

    def _frame_index(self, frame: Frame | None) -> int:
        n = self._n
        if frame is None:
            return n + 1
        if isinstance(frame, str):
            if frame in self._frame_names:
                return self._frame_names.index(frame)
            names = self.joint_names
            if frame in names:
                return names.index(frame) + 1
            raise DomainError(
                f"frame must be one of {list(self._frame_names)} (or a joint name) or an "
                f"index 0..{n + 1}; got {frame!r}"
            )
        if isinstance(frame, (bool, np.bool_)) or not isinstance(frame, (int, np.integer)):
            raise TypeError(f"frame must be an int index or a frame name; got {type(frame).__name__}")
        k = int(frame)
        if k < 0:
            k += n + 2
        if not 0 <= k <= n + 1:
            raise DomainError(f"frame must be an index in 0..{n + 1} (or -1 for the end-effector); got {frame}")
        return k

    # ------------------------------------------------------------ kinematics
    def fk(self, q: Any, frame: Frame | None = None, *, check: bool = True) -> Any:
        r"""Forward kinematics: pose of the end-effector (or of ``frame``) in the base.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n), or sequence of sympy expressions
            Joint configuration(s) in rad / m.
        frame : int or str, optional
            Frame index (0 base, 1..n joint frames, n+1 or -1 end-effector) or
            name (see :attr:`frame_names`). Default: end-effector.
        check : bool, optional
            Validate ``q`` (shape, finiteness). ``False`` skips it in hot loops.

        Returns
        -------
        numpy.ndarray, shape (4, 4) or (N, 4, 4), or sympy.Matrix (4×4)
            :math:`{}^B\mathbf{T}_E(\mathbf{q}) = \prod_k E_k(\mathbf{q})\,\mathbf{T}_{tool}`
            (Siciliano et al. 2009, §2.8.1).

        Raises
        ------
        ShapeError
            ``q`` not of shape (n,) or (N, n).
        DomainError
            ``q`` has NaN/inf entries, or ``frame`` is out of range.
        """
        kind, a = self._parse_q(q, check)
        if kind == "single" and frame is None:  # the common call, in as few steps as possible
            engine = self._unchecked_engine or self._direct_engine(a, check)
            if engine is not None:
                return engine.fk_single(a)
        k = self._n + 1 if frame is None else self._frame_index(frame)
        if kind == "sym":
            return self._symbolic_subs(self._sym_frames()[k], a)
        if check and self._overflow_risk(a):
            with np.errstate(all="ignore"):
                out = self._fk_numeric(kind, a, k)
            return self._checked(out, "the forward kinematics", q=a)
        return self._fk_numeric(kind, a, k)

    def _fk_numeric(self, kind: str, a: np.ndarray, k: int) -> np.ndarray:
        if kind == "single":
            eng = self._engine
            if k == self._n + 1:
                return eng.fk_single(a)
            if k == 0:
                return np.eye(4)
            return eng.joint_frames_single(a)[k - 1]
        return self._engine.fk_batch(a, upto=k)

    def frame_pose(self, q: Any, frame: Frame, *, check: bool = True) -> Any:
        """Pose of frame ``frame`` (index or name) in the base: ``fk(q, frame=frame)``."""
        return self.fk(q, frame=frame, check=check)

    def frames(self, q: Any, *, check: bool = True) -> Any:
        """Poses of all frames in the base frame.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n), or sympy expressions
        check : bool, optional
            Validate ``q``.

        Returns
        -------
        numpy.ndarray, shape (n+2, 4, 4) or (N, n+2, 4, 4), or list of sympy.Matrix
            Index 0 base (identity), 1..n the joint frames (after joint i moves;
            joint i's axis passes through the origin along ``joint_axes[i-1]``),
            n+1 the end-effector (tool included). Names: :attr:`frame_names`.
        """
        kind, a = self._parse_q(q, check)
        if kind == "sym":
            return [self._symbolic_subs(F, a) for F in self._sym_frames()]
        frames = self._engine.frames_single if kind == "single" else self._engine.frames_batch
        if check and self._overflow_risk(a):
            with np.errstate(all="ignore"):
                out = frames(a)
            return self._checked(out, "the frames", q=a)
        return frames(a)

    def jacobian(self, q: Any, frame: Frame | None = None, point: Any = None, *, check: bool = True) -> Any:
        r"""Geometric Jacobian in the base frame, rows ``[v; ω]``.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n), or sympy expressions
        frame : int or str, optional
            Target frame (default end-effector). Joints beyond a joint frame give
            zero columns.
        point : array_like, shape (3,), optional
            A point fixed in ``frame``, in that frame's coordinates (default its
            origin).
        check : bool, optional
            Validate ``q``.

        Returns
        -------
        numpy.ndarray, shape (6, n) or (N, 6, n), or sympy.Matrix (6×n)
            For joint i with unit axis :math:`\mathbf{z}_i` through
            :math:`\mathbf{p}_i` (base coordinates) and target point
            :math:`\mathbf{p}`  (Siciliano et al. 2009, eq. 3.30):

            .. math::

                \mathbf{J}_i = \begin{bmatrix}\mathbf{z}_i \times (\mathbf{p}-\mathbf{p}_i)\\
                \mathbf{z}_i\end{bmatrix} \text{ (revolute)},\qquad
                \mathbf{J}_i = \begin{bmatrix}\mathbf{z}_i\\ \mathbf{0}\end{bmatrix}
                \text{ (prismatic)}.

            Symbolic input: the linear rows are :math:`\partial\mathbf{p}/\partial\mathbf{q}`
            (identical, and simpler to print).
        """
        kind, a = self._parse_q(q, check)
        if kind == "single" and frame is None and point is None:  # the common call, in as few steps as possible
            engine = self._unchecked_engine or self._direct_engine(a, check)
            if engine is not None:
                return engine.jacobian_single(a)
        k = self._n + 1 if frame is None else self._frame_index(frame)
        if kind == "sym":
            return self._symbolic_subs(self._sym_jacobian(k, point), a)
        pt = None if point is None else as_vector(point, 3, "point")
        jac = self._engine.jacobian_single if kind == "single" else self._engine.jacobian_batch
        if check and self._overflow_risk(a, pt):
            with np.errstate(all="ignore"):
                out = jac(a, upto=k, point=pt)
            inputs = {"q": a} if pt is None else {"q": a, "point": pt}
            return self._checked(out, "the Jacobian", **inputs)
        return jac(a, upto=k, point=pt)

    def fk_and_jacobian(self, q: Any, *, check: bool = True) -> tuple[np.ndarray, np.ndarray]:
        r"""End-effector pose and geometric Jacobian, from one pass over the chain.

        What an inverse-kinematics or control iteration needs: the same results
        as ``(fk(q), jacobian(q))`` for about the cost of :meth:`jacobian` alone.
        For one configuration they are equal to rounding (the pose comes from the
        chain's running products, as :meth:`frames` computes it); for a batch,
        equal to the last bit (the batched code computes the pose on its way to
        the Jacobian).

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Joint configuration(s) in rad / m.
        check : bool, optional
            Validate ``q``. ``False`` skips it in hot loops.

        Returns
        -------
        T : numpy.ndarray, shape (4, 4) or (N, 4, 4)
            :math:`{}^B\mathbf{T}_E(\mathbf{q})`.
        J : numpy.ndarray, shape (6, n) or (N, 6, n)
            Rows ``[v; ω]`` (see :meth:`jacobian`).
        """
        kind, a = self._parse_q(q, check)
        if kind == "single":  # the common call, in as few steps as possible
            engine = self._unchecked_engine or self._direct_engine(a, check)
            if engine is not None:
                return engine.pose_and_jacobian_single(a)
        if kind == "sym":
            raise ShapeError(f"q must have shape ({self._n},) or (N, {self._n}) (numeric configurations); "
                             "got symbols (fk and jacobian take symbols)")
        engine = self._engine
        pose_and_jacobian = engine.pose_and_jacobian_single if kind == "single" else engine.pose_and_jacobian_batch
        if check and self._overflow_risk(a):
            with np.errstate(all="ignore"):
                T, J = pose_and_jacobian(a)
            return self._checked(T, "the forward kinematics", q=a), self._checked(J, "the Jacobian", q=a)
        return pose_and_jacobian(a)

    def position_jacobian(self, q: Any, frame: Frame | None = None, point: Any = None, *, check: bool = True) -> Any:
        r"""Linear-velocity rows of :meth:`jacobian`: :math:`\partial\mathbf{p}/\partial\mathbf{q}`,
        (3, n) or (N, 3, n)."""
        J = self.jacobian(q, frame=frame, point=point, check=check)
        if hasattr(J, "free_symbols") and not isinstance(J, np.ndarray):
            return J[:3, :]
        return J[..., :3, :]

    # ------------------------------------------------------------ measures
    def singular_values(self, q: Any, position_only: bool = False, *, check: bool = True) -> np.ndarray:
        """Singular values of the Jacobian (descending), shape (min(m, n),) or (N, min(m, n)).

        ``m`` = 6, or 3 with ``position_only=True`` (then of :math:`J_v`).
        """
        J = self.jacobian(q, check=check)
        if not isinstance(J, np.ndarray):
            raise TypeError("singular_values needs a numeric q")
        if position_only:
            J = J[..., :3, :]
        return np.linalg.svd(J, compute_uv=False)

    def manipulability(self, q: Any, position_only: bool = False, *, check: bool = True) -> Any:
        r"""Yoshikawa manipulability :math:`w = \sqrt{\det(\mathbf{J}\mathbf{J}^T)}`.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
        position_only : bool, optional
            Use :math:`\mathbf{J}_v` (3×n) instead of the full 6×n Jacobian, the
            useful choice for arms/legs with fewer than 6 joints.

        Returns
        -------
        float or numpy.ndarray, shape (N,)
            The product of the singular values; 0 when the Jacobian has fewer
            columns than rows (Siciliano et al. 2009, eq. 3.56; Yoshikawa 1985).
        """
        sv = self.singular_values(q, position_only=position_only, check=check)
        m = 3 if position_only else 6
        w = np.prod(sv, axis=-1) if self._n >= m else np.zeros(sv.shape[:-1])
        return float(w) if np.ndim(w) == 0 else w

    def condition_number(self, q: Any, position_only: bool = False, *, check: bool = True) -> Any:
        r"""Condition number :math:`\sigma_{max}/\sigma_{min}` of the Jacobian (inf at singularities)."""
        sv = self.singular_values(q, position_only=position_only, check=check)
        with np.errstate(divide="ignore", invalid="ignore"):
            c = np.where(sv[..., -1] > 0, sv[..., 0] / sv[..., -1], np.inf)
        return float(c) if np.ndim(c) == 0 else c

    # ------------------------------------------------------------ product of exponentials
    def screw_axes(self) -> tuple[np.ndarray, np.ndarray]:
        r"""Home pose :math:`M` (4, 4) and space-frame screw axes :math:`\mathcal{S}` (n, 6), rows ``[ω; v]``.

        Their product of exponentials equals :meth:`fk` (Lynch & Park 2017, §4.1.1). See
        :func:`robokin.chains.screws.screw_axes`.
        """
        from robokin.chains.screws import screw_axes

        return screw_axes(self)

    def space_jacobian(self, q: Any) -> np.ndarray:
        r"""Lynch & Park's space Jacobian :math:`J_s`, shape (6, n) or (N, 6, n), rows ``[ω; v_s]``.

        Column i is joint i's screw axis at ``q``, in the base frame (Lynch & Park 2017,
        §5.1.1); ``v_s`` is the velocity of the body point at the base origin, where this
        book's :meth:`jacobian` ``[J_v; J_ω]`` gives that of the end-effector's origin. See
        :func:`robokin.chains.screws.space_jacobian`.
        """
        from robokin.chains.screws import space_jacobian

        return space_jacobian(self, q)

    def body_jacobian(self, q: Any) -> np.ndarray:
        r"""Lynch & Park's body Jacobian :math:`J_b`, shape (6, n) or (N, 6, n), rows ``[ω_b; v_b]``.

        The twist of the end-effector in its own frame (Lynch & Park 2017, §5.1.2; its
        relation to :math:`J_s`, §5.1.4). See :func:`robokin.chains.screws.body_jacobian`.
        """
        from robokin.chains.screws import body_jacobian

        return body_jacobian(self, q)

    # ------------------------------------------------------------ statics and ellipsoids
    def velocity_ellipsoid(self, q: Any, part: str = "position") -> tuple[np.ndarray, np.ndarray]:
        """Semi-axes and unit axes of the velocity ellipsoid of the ``"position"`` or ``"orientation"`` rows.

        Semi-axes (3,) or (N, 3), descending; axes the columns of (3, 3) or (N, 3, 3), base frame.
        See :func:`robokin.chains.ellipsoids.velocity_ellipsoid`.
        """
        from robokin.chains.ellipsoids import velocity_ellipsoid

        return velocity_ellipsoid(self, q, part)

    def force_ellipsoid(self, q: Any, part: str = "position") -> tuple[np.ndarray, np.ndarray]:
        """Semi-axes and unit axes of the force ellipsoid of the ``"position"`` or ``"orientation"`` rows.

        Semi-axes (3,) or (N, 3), descending (``inf`` where unbounded); axes the columns of
        (3, 3) or (N, 3, 3), base frame. See :func:`robokin.chains.ellipsoids.force_ellipsoid`.
        """
        from robokin.chains.ellipsoids import force_ellipsoid

        return force_ellipsoid(self, q, part)

    def static_torques(self, q: Any, wrench: Any) -> np.ndarray:
        r"""Joint torques with which the end-effector exerts a wrench, at rest.

        ``wrench`` is ``[f; μ]`` (base frame, force at the end-effector's origin); the result has
        shape (n,) or (N, n). See :func:`robokin.chains.ellipsoids.static_torques`.
        """
        from robokin.chains.ellipsoids import static_torques

        return static_torques(self, q, wrench)

    # ------------------------------------------------------------ configurations
    def random_configurations(self, N: int, seed: Any = None) -> np.ndarray:
        """``N`` configurations uniformly distributed within the limits, shape (N, n).

        Parameters
        ----------
        N : int
            Number of configurations.
        seed : int or numpy.random.Generator, optional
            Passed to :func:`numpy.random.default_rng` (reproducible samples).

        Raises
        ------
        TypeError
            ``N`` not an integer, or ``seed`` of the wrong type.
        DomainError
            ``N`` negative or too large (``N * n`` above 1e8 samples), or some
            limit infinite.
        """
        N = check_int(N, "N", 0, _MAX_SAMPLES // self._n)
        if not np.isfinite(self._limits).all():
            raise DomainError("random_configurations needs finite limits; got infinite limits")
        if isinstance(seed, (bool, np.bool_, float, str, bytes)):
            raise TypeError(f"seed must be an int, a numpy Generator or None; got {type(seed).__name__} {seed!r}")
        try:
            rng = np.random.default_rng(seed)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"seed must be an int >= 0, a numpy Generator or None; got {type(seed).__name__} "
                            f"({exc})") from None
        lo, hi = self._limits[:, 0], self._limits[:, 1]
        with np.errstate(all="ignore"):
            out = lo + (hi - lo) * rng.random((N, self._n))
        return check_result_finite(out, "the samples", limits=self._limits)

    def within_limits(self, q: Any, tol: float = 0.0) -> Any:
        """True where ``q`` lies within the limits (± ``tol``, >= 0); bool or (N,) bool array."""
        tol = check_positive(tol, "tol", allow_zero=True, scalar=True)
        kind, a = self._parse_q(q, True)
        if kind == "sym":
            raise TypeError("within_limits needs a numeric q")
        ok = np.all((a >= self._limits[:, 0] - tol) & (a <= self._limits[:, 1] + tol), axis=-1)
        return bool(ok) if kind == "single" else ok

    # ------------------------------------------------------------ symbolic
    def symbols(self) -> list:
        """Default sympy joint symbols (real), named after the joints."""
        import sympy as sp

        return [sp.Symbol(nm, real=True) for nm in self.joint_names]

    def _sym_frames(self) -> list:
        """Simplified symbolic frames (cached), in the default joint symbols."""
        if "frames" in self._sym_cache:
            return self._sym_cache["frames"]
        import sympy as sp

        from robokin.chains._symbolic import element_matrix, simplify_matrix

        syms = self.symbols()
        T = sp.eye(4)
        frames = [sp.eye(4)]
        j = 0
        for el in self._elements:
            if el.is_joint:
                T = simplify_matrix(T * element_matrix(el, syms[j]))
                frames.append(T)
                j += 1
            else:
                T = T * element_matrix(el)
        tool = self._tool
        if isinstance(tool, np.ndarray):
            tool = element_matrix(Element("F", matrix=tool))
        frames.append(simplify_matrix(T * tool))
        self._sym_cache["frames"] = frames
        return frames

    def _sym_jacobian(self, k: int, point: Any = None) -> Any:
        import sympy as sp

        from robokin.chains._symbolic import exact_length, simplify_matrix

        key = ("jac", k, None if point is None else tuple(sp.sympify(p) for p in point))
        if key in self._sym_cache:
            return self._sym_cache[key]
        n = self._n
        F = self._sym_frames()
        syms = self.symbols()
        Tk = F[k]
        if point is None:
            p = Tk[:3, 3]
        else:
            pv = sp.Matrix([x if isinstance(x, sp.Basic) else exact_length(x) for x in point])
            if pv.shape != (3, 1):
                raise ShapeError(f"point must have shape (3,); got {len(point)} entries")
            p = Tk[:3, :3] * pv + Tk[:3, 3]
        m = n if k == n + 1 else k
        J = sp.zeros(6, n)
        Jv = simplify_matrix(p.jacobian(syms))
        for i in range(m):
            J[:3, i] = Jv[:, i]
            if self._joints[i].kind == "R":
                J[3:, i] = F[i + 1][:3, :3] * sp.Matrix(self._joint_axes[i].astype(int).tolist())
        self._sym_cache[key] = J
        return J

    def _symbolic_subs(self, M: Any, q: list) -> Any:
        syms = self.symbols()
        mapping = {s: v for s, v in zip(syms, q) if s != v}
        return M.subs(mapping) if mapping else M

    def _lambdify(self, expr: Any, shape: tuple[int, int]) -> Callable[[Any], np.ndarray]:
        import sympy as sp

        if self.parameters:
            raise TypeError(
                f"chain {self.name!r} has symbolic link parameters; substitute them first (subs)"
            )
        syms = self.symbols()
        entries = list(expr)
        raw = sp.lambdify(syms, entries, modules="numpy", cse=True)
        n = self._n
        r, c = shape

        def fn(q: Any) -> np.ndarray:
            a = as_float_array(q, "q")
            if a.shape[-1:] != (n,) or a.ndim > 2:
                raise ShapeError(f"q must have shape ({n},) or (N, {n}); got shape {a.shape}")
            with np.errstate(all="ignore"):  # joint values near 1e308 may overflow in the formulas
                vals = raw(*a.T)
                out = np.empty(a.shape[:-1] + (r, c))
                for idx, v in enumerate(vals):
                    out[..., idx // c, idx % c] = v
            return check_result_finite(out, "the generated formula", q=a)

        fn.__doc__ = f"Generated from the symbolic result: q (n,) or (N, n) -> {shape} or (N, {r}, {c})."
        return fn

    def lambdify_fk(self, frame: Frame | None = None) -> Callable[[Any], np.ndarray]:
        """Fast numeric FK generated from the simplified symbolic FK (sympy lambdify, cse).

        Returns
        -------
        callable
            ``f(q)`` with ``q`` (n,) -> (4, 4) or (N, n) -> (N, 4, 4).
        """
        k = self._frame_index(frame)
        return self._lambdify(self._sym_frames()[k], (4, 4))

    def lambdify_jacobian(self, frame: Frame | None = None) -> Callable[[Any], np.ndarray]:
        """Fast numeric Jacobian generated from the symbolic one: (n,) -> (6, n), (N, n) -> (N, 6, n)."""
        k = self._frame_index(frame)
        return self._lambdify(self._sym_jacobian(k), (6, self._n))


if TYPE_CHECKING:
    def _satisfies_the_protocols(chain: SerialChain) -> tuple[Chain, DrawableChain]:
        """Never called: mypy checks here that a SerialChain is a Chain and a DrawableChain."""
        return chain, chain
