"""Tests for robokin._dispatch (float / NumPy / sympy helpers)."""

import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from robokin import _dispatch as d
from robokin.errors import DomainError


def test_is_symbolic():
    a = sp.Symbol("a")
    assert not d.is_symbolic(1.0, 2, np.zeros(3), [1.0, 2.0], None)
    assert d.is_symbolic(a) and d.is_symbolic(sp.pi) and d.is_symbolic(sp.Matrix([1, 2]))
    assert d.is_symbolic([1.0, a]) and d.is_symbolic(np.array([1, a], dtype=object))
    assert d.is_symbolic(1.0, a)


def test_trig():
    assert d.trig(0.0) == (1.0, 0.0)
    c, s = d.trig(np.array([0.0, np.pi / 2]))
    np.testing.assert_allclose(c, [1, 0], atol=1e-16)
    a = sp.Symbol("a")
    assert d.trig(a) == (sp.cos(a), sp.sin(a))


def test_stack_matrix():
    M = d.stack_matrix([[1, 0], [0, 2.0]])
    assert M.shape == (2, 2) and M.dtype == np.float64
    t = np.arange(5.0)
    M = d.stack_matrix([[t, 0], [1, -t]])
    assert M.shape == (5, 2, 2)
    np.testing.assert_array_equal(M[:, 1, 1], -t)
    a = sp.Symbol("a")
    S = d.stack_matrix([[a, 1.0], [0, 2]])
    assert S == sp.Matrix([[a, 1], [0, 2]]) and not S.atoms(sp.Float)
    assert isinstance(d.stack_matrix([[1, 0], [0, 1]], like=a), sp.MatrixBase)


def test_stack_vector_matmul_transpose():
    assert d.stack_vector([1, 2, 3]).shape == (3,)
    assert d.stack_vector([np.zeros(4), 1, 2]).shape == (4, 3)
    a = sp.Symbol("a")
    assert d.stack_vector([a, 1.0]) == sp.Matrix([a, 1])
    assert d.matmul(np.eye(2), sp.Matrix([[a, 0], [0, 1]])) == sp.Matrix([[a, 0], [0, 1]])
    np.testing.assert_array_equal(d.matmul(np.eye(2), np.ones((3, 2, 2))), np.ones((3, 2, 2)))
    assert d.transpose(np.zeros((4, 2, 3))).shape == (4, 3, 2)
    assert d.transpose(sp.Matrix([[a, 1]])) == sp.Matrix([a, 1])
    assert d.sqrt(4.0) == 2.0 and d.sqrt(a) == sp.sqrt(a)
    assert d.atan2(a, 1) == sp.atan2(a, 1) and d.atan2(1.0, 0.0) == pytest.approx(np.pi / 2)


def test_scalar_input():
    assert d.scalar_input(1, "x") == 1.0 and isinstance(d.scalar_input(1, "x"), float)
    assert d.scalar_input([1, 2], "x").shape == (2,)
    a = sp.Symbol("a")
    assert d.scalar_input(a, "x") is a
    with pytest.raises(DomainError, match="theta must be finite"):
        d.scalar_input(float("nan"), "theta")
    with pytest.raises(TypeError, match="theta must be a scalar expression"):
        d.scalar_input(sp.Matrix([a]), "theta")
    with pytest.raises(TypeError, match="theta must be one number.*batches of symbolic"):
        d.scalar_input([a, 1.0], "theta")


def test_to_sympy_exact():
    assert d.to_sympy(2.0) == sp.Integer(2) and isinstance(d.to_sympy(2.0), sp.Integer)
    assert isinstance(d.to_sympy(0.5), sp.Float)
    assert d.to_sympy(np.eye(2)) == sp.eye(2)
    assert d.to_sympy([1, 2]) == sp.Matrix([1, 2])


def test_transforms_do_not_import_sympy_matplotlib_or_meshcat():
    code = (
        "import sys, robokin.transforms, robokin.validation; "
        "import robokin.transforms as t; t.rotz(0.1); t.rotation_log(t.rotx(0.2)); "
        "bad = [m for m in ('sympy', 'matplotlib', 'meshcat') if m in sys.modules]; "
        "print(','.join(bad))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""
