"""robokin.formatting: the same printed digits on every machine."""

from __future__ import annotations

import math

import numpy as np
import pytest

from robokin.formatting import format_array, rounded


@pytest.mark.parametrize("tiny", [-1e-17, -0.0, -4.9e-5])
def test_rounded_drops_the_sign_of_zero(tiny):
    value = rounded(tiny, 4)
    assert value == 0.0 and math.copysign(1.0, value) == 1.0
    array = rounded(np.array([[tiny, 1.0], [2.0, tiny]]), 4)
    assert not np.signbit(array).any()
    assert "-0." not in str(array)


def test_rounded_keeps_values_shape_and_type():
    assert isinstance(rounded(1.23456), float) and rounded(1.23456) == 1.2346
    assert rounded(np.float64(-2.5), 0) == -2.0               # round half to even, as numpy
    out = rounded(np.arange(24.0).reshape(2, 3, 4) / 7, 2)
    assert out.shape == (2, 3, 4) and np.allclose(out, np.round(np.arange(24.0).reshape(2, 3, 4) / 7, 2))
    assert rounded(1234.5, -2) == 1200.0


def test_tiny_values_of_either_sign_print_the_same():
    rng = np.random.default_rng(0)
    base = rng.standard_normal((5, 3)).round(3)
    base[1, 2] = 0.0
    a, b = base.copy(), base.copy()
    a[1, 2], b[1, 2] = 3e-17, -3e-17                          # two machines, one exact zero
    assert str(rounded(a, 4)) == str(rounded(b, 4))
    assert format_array(a, 4) == format_array(b, 4)


def test_format_array():
    assert format_array(0.5) == "0.5000"
    assert format_array(-1e-9, 2) == "0.00"
    assert format_array([0.5, -1e-12, 2.0], 2) == "[0.50, 0.00, 2.00]"
    assert format_array(np.eye(2), 1) == "[[1.0, 0.0],\n [0.0, 1.0]]"
    assert format_array(np.full(50, 1.0), 1).count("1.0") == 50   # never summarised with "..."


@pytest.mark.parametrize("decimals", [1.5, "2", None, True])
def test_decimals_must_be_an_integer(decimals):
    with pytest.raises(TypeError, match="decimals"):
        rounded(1.0, decimals)

