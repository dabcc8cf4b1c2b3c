r"""Elementary transforms: the building blocks of a serial chain.

A serial chain is written as a product of *elementary transforms* (ETS, Corke
2017, ch. 7; Haviland & Corke 2021): translations along and rotations about the
x, y, z axes of the current frame, read from left (base) to right (tool)::

    T_BF(q) = Ty(1) Rx(alpha) Tz(-1) Ry(beta) Tz(-1) Ry(gamma) Tz(-1)

Each element is either **constant** or a **joint**:

=========================  ====================================================
``Tz(0.3)``                constant translation by 0.3 m along z
``Tz(l1)``                 constant, ``l1`` a sympy symbol (a link parameter)
``Rx(sympy.pi / 2)``       constant rotation by π/2 about x
``Rx("alpha")``            revolute joint named ``alpha`` about +x
``Rx("-q3")``              revolute joint ``q3`` about −x, i.e. ``Rx(-q3)``
``Rz("q2", offset=pi/2)``  revolute joint, angle ``q2 + π/2``
``Tz("d3")``               prismatic joint ``d3`` along +z
``Fixed(T)``               constant 4×4 homogeneous transform ``T``
=========================  ====================================================

A joint element moves by ``sign * q + offset`` (radians or metres), where ``q``
is the joint variable and ``sign`` is ±1. Joint limits may be attached with
``limits=(lower, upper)``.

The element classes only *describe* the chain; :class:`robokin.chains.SerialChain`
compiles them into fast numeric blocks and into sympy matrices.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from robokin.errors import DomainError, ShapeError
from robokin.transforms import rotx, roty, rotz, transform, translation
from robokin.validation import check_limits

__all__ = ["Element", "Tx", "Ty", "Tz", "Rx", "Ry", "Rz", "Fixed", "AXES"]

#: Axis letter -> index.
AXES = {"x": 0, "y": 1, "z": 2}


def _is_sympy(x: Any) -> bool:
    import sys

    sp = sys.modules.get("sympy")
    return sp is not None and isinstance(x, (sp.Basic, sp.MatrixBase))


def check_parameter_value(value: Any, name: str) -> Any:
    """Accept a real number or a sympy expression (kept as is)."""
    if _is_sympy(value):
        if getattr(value, "is_number", False):
            try:
                f = float(value)
            except TypeError:
                raise TypeError(f"{name} must be real; got {value!r}") from None
            if not math.isfinite(f):
                raise DomainError(f"{name} must be finite; got {value}")
        return value
    if isinstance(value, (bool, np.bool_)) or not isinstance(
        value, (int, float, np.integer, np.floating)
    ):
        raise TypeError(
            f"{name} must be a number, a sympy expression or (for a joint) a string "
            f"naming the joint; got {type(value).__name__} {value!r}"
        )
    f = float(value)
    if not math.isfinite(f):
        raise DomainError(f"{name} must be finite; got {f}")
    return value


_ROTATIONS = (rotx, roty, rotz)


@dataclass(frozen=True, eq=False)
class Element:
    """One elementary transform.

    Attributes
    ----------
    kind : {'T', 'R', 'F'}
        Translation, rotation, or fixed 4×4 transform.
    axis : int
        0, 1, 2 for x, y, z (unused for 'F').
    value : float or sympy.Expr or None
        Constant value (metres / radians); ``None`` for a joint.
    joint : str or None
        Joint name for a joint element.
    sign : int
        +1 or −1: the element moves by ``sign * q + offset``.
    offset : float or sympy.Expr
        Joint offset (value of the element at ``q = 0``).
    limits : tuple or None
        ``(lower, upper)`` of the joint variable ``q``.
    matrix : numpy.ndarray or sympy.Matrix or None
        The 4×4 transform of a 'F' element.
    """

    kind: str
    axis: int = 0
    value: Any = None
    joint: str | None = None
    sign: int = 1
    offset: Any = 0.0
    limits: tuple[float, float] | None = None
    matrix: Any = None

    @property
    def is_joint(self) -> bool:
        """True for a joint element."""
        return self.joint is not None

    @property
    def joint_type(self) -> str:
        """'revolute' for a rotation joint, 'prismatic' for a translation joint."""
        return "revolute" if self.kind == "R" else "prismatic"

    def __repr__(self) -> str:
        if self.kind == "F":
            return "Fixed(...)"
        name = f"{self.kind}{'xyz'[self.axis]}"
        if self.joint is None:
            return f"{name}({self.value!r})"
        s = "-" if self.sign < 0 else ""
        extra = ""
        if self.offset != 0:
            extra += f", offset={self.offset!r}"
        if self.limits is not None:
            extra += f", limits={self.limits!r}"
        return f"{name}('{s}{self.joint}'{extra})"


def elementary_transform(kind: str, axis: int, value: Any) -> Any:
    r"""The 4×4 homogeneous transform of a rotation ``'R'`` or translation ``'T'``
    by ``value`` about / along axis ``axis`` (0, 1, 2 = x, y, z).

    Built from :func:`robokin.transforms.rotx` (``roty``, ``rotz``) and
    :func:`robokin.transforms.translation`, so a float gives a (4, 4) array and a
    sympy expression a ``sympy.Matrix``: the same code serves the numeric engine's
    constants and the symbolic derivation.
    """
    if kind == "T":
        p: list[Any] = [0, 0, 0]
        p[axis] = value
        return translation(p)
    return transform(_ROTATIONS[axis](value), [0, 0, 0])


def _make(kind: str, axis: str, value: Any, offset: Any, limits: Any) -> Element:
    label = f"{kind}{axis}"
    ax = AXES[axis]
    if isinstance(value, str):
        text = value.strip()
        sign = 1
        if text.startswith("-"):
            sign, text = -1, text[1:].strip()
        elif text.startswith("+"):
            text = text[1:].strip()
        if not text:
            raise ValueError(f"{label}: empty joint name {value!r}")
        offset = check_parameter_value(offset, f"{label}('{value}') offset")
        lim = None
        if limits is not None:
            name = f"limits of joint {text!r}"
            try:
                shape = np.shape(limits)
            except ValueError:  # ragged
                shape = None
            if shape != (2,):
                raise ShapeError(f"{name} must be a pair (lower, upper) of shape (2,); got "
                                 + (f"shape {shape}" if shape is not None else f"{limits!r}"))
            arr = check_limits([limits], 1, name)[0]  # numbers, no NaN, lower <= upper
            lim = (float(arr[0]), float(arr[1]))
        return Element(kind, ax, None, text, sign, offset, lim)
    if limits is not None or (offset is not None and offset != 0):
        raise ValueError(f"{label}: offset/limits only apply to joints (give a joint name)")
    return Element(kind, ax, check_parameter_value(value, f"{label} value"))


def Tx(value: Any, *, offset: Any = 0.0, limits: Any = None) -> Element:
    """Translation along x: constant (number / sympy) or prismatic joint (name)."""
    return _make("T", "x", value, offset, limits)


def Ty(value: Any, *, offset: Any = 0.0, limits: Any = None) -> Element:
    """Translation along y: constant (number / sympy) or prismatic joint (name)."""
    return _make("T", "y", value, offset, limits)


def Tz(value: Any, *, offset: Any = 0.0, limits: Any = None) -> Element:
    """Translation along z: constant (number / sympy) or prismatic joint (name)."""
    return _make("T", "z", value, offset, limits)


def Rx(value: Any, *, offset: Any = 0.0, limits: Any = None) -> Element:
    """Rotation about x: constant angle (number / sympy) or revolute joint (name)."""
    return _make("R", "x", value, offset, limits)


def Ry(value: Any, *, offset: Any = 0.0, limits: Any = None) -> Element:
    """Rotation about y: constant angle (number / sympy) or revolute joint (name)."""
    return _make("R", "y", value, offset, limits)


def Rz(value: Any, *, offset: Any = 0.0, limits: Any = None) -> Element:
    """Rotation about z: constant angle (number / sympy) or revolute joint (name)."""
    return _make("R", "z", value, offset, limits)


def Fixed(T: Any) -> Element:
    """A constant 4×4 homogeneous transform (numbers or sympy entries).

    Parameters
    ----------
    T : array_like or sympy.Matrix, shape (4, 4)
        Numeric transforms are checked (rotation part orthonormal, bottom row
        ``[0, 0, 0, 1]``).

    Raises
    ------
    ShapeError
        If ``T`` is not 4×4.
    DomainError
        If a numeric ``T`` is not a homogeneous transform.
    """
    if _is_sympy(T):
        import sympy as sp

        M = sp.Matrix(T)
        if M.shape != (4, 4):
            raise ShapeError(f"Fixed(T): T must have shape (4, 4); got shape {M.shape}")
        if not M.free_symbols:
            from robokin.validation import check_transform

            check_transform(np.array(M.evalf(), dtype=float), tol=1e-6, name="T")
        return Element("F", matrix=M)
    from robokin.validation import check_transform

    a = check_transform(T, tol=1e-6, name="T")
    if a.ndim != 2:
        raise ShapeError(f"Fixed(T): T must have shape (4, 4); got shape {a.shape}")
    return Element("F", matrix=a.copy())
