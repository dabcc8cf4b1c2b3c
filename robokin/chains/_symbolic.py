"""Symbolic (sympy) helpers for serial chains (private).

Numbers are converted exactly: integral floats become Integers and angles that
are multiples of π/12 (up to 1e-12) become exact multiples of ``pi``, so that
``cos(pi/2)`` is exactly 0 and printed kinematics stay readable.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import sympy as sp
from sympy.simplify.fu import TR10i

from robokin.chains.elements import Element, elementary_transform

__all__ = ["exact_length", "exact_angle", "element_matrix", "simplify_matrix", "simplify_expr"]


def exact_length(x: Any) -> sp.Expr:
    """Exact sympy number for a length (integral floats -> Integer)."""
    if isinstance(x, sp.Basic):
        return x
    f = float(x)
    if f.is_integer():
        return sp.Integer(int(f))
    return sp.Float(f)


def exact_angle(x: Any) -> sp.Expr:
    """Exact sympy angle; floats close to k·π/12 become ``k*pi/12``."""
    if isinstance(x, sp.Basic):
        return x
    f = float(x)
    if f.is_integer():
        return sp.Integer(int(f))
    k = f / (math.pi / 12)
    if abs(k - round(k)) < 1e-9:
        return sp.Rational(int(round(k)), 12) * sp.pi
    return sp.Float(f)


def element_matrix(el: Element, q: Any = None) -> sp.Matrix:
    """4×4 sympy matrix of an element; ``q`` is the joint symbol for joints."""
    if el.kind == "F":
        M = el.matrix
        if isinstance(M, sp.MatrixBase):
            return sp.Matrix(M)
        A = np.asarray(M, dtype=float)
        out = sp.eye(4)
        for i in range(3):
            for j in range(4):
                out[i, j] = exact_length(A[i, j]) if j == 3 else _exact_unit(A[i, j])
        return out
    if el.is_joint:
        conv = exact_angle if el.kind == "R" else exact_length
        value = el.sign * q + conv(el.offset)
    else:
        value = exact_angle(el.value) if el.kind == "R" else exact_length(el.value)
    return elementary_transform(el.kind, el.axis, value)


def _exact_unit(x: float) -> sp.Expr:
    """Exact form of a rotation-matrix entry when it is a common value."""
    for v in (0, 1, -1):
        if abs(x - v) < 1e-12:
            return sp.Integer(v)
    for cand in (sp.sqrt(2) / 2, sp.sqrt(3) / 2, sp.Rational(1, 2)):
        fv = float(cand)
        if abs(x - fv) < 1e-12:
            return cand
        if abs(x + fv) < 1e-12:
            return -cand
    return sp.Float(x)


def simplify_expr(e: sp.Expr) -> sp.Expr:
    """Readable form of one entry of a kinematics matrix.

    Expands products (cheap; collects numeric factors), recombines products of
    sines and cosines into sums of angles with Fu's rule TR10i
    (``cos a cos b − sin a sin b → cos(a + b)``: the identity produced by
    consecutive parallel joint axes, e.g. ``sin(beta + gamma)``), then pulls
    common factors out of the non-constant terms. Full ``trigsimp`` gives the
    same results on the bundled models but is 10–30× slower.
    """
    if e.is_number or e.is_Symbol:
        return e
    r = TR10i(sp.expand(e))
    if r.is_Add:
        const, rest = r.as_coeff_Add()
        r = const + sp.factor_terms(rest)
    else:
        r = sp.factor_terms(r)
    return r


def simplify_matrix(M: sp.Matrix) -> sp.Matrix:
    """Apply :func:`simplify_expr` to every entry."""
    return M.applyfunc(simplify_expr)
