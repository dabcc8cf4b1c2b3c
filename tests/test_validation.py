"""Tests for robokin.errors and robokin.validation."""

import numpy as np
import pytest

from robokin.errors import DomainError, RobokinError, ShapeError
from robokin.validation import (
    as_batch,
    as_float_array,
    as_rotation_matrix,
    as_vector,
    check_finite,
    check_limits,
    check_positive,
    check_rotation_matrix,
    check_transform,
    format_shape,
)


def test_hierarchy():
    assert issubclass(ShapeError, RobokinError) and issubclass(ShapeError, ValueError)
    assert issubclass(DomainError, RobokinError) and issubclass(DomainError, ValueError)
    assert not issubclass(ShapeError, DomainError)


@pytest.mark.parametrize(
    "spec, text", [((6,), "(6,)"), ((None, 3), "(N, 3)"), ((-1, 4, 4), "(N, 4, 4)")]
)
def test_format_shape(spec, text):
    assert format_shape(spec) == text


# --- as_float_array -----------------------------------------------------------------


def test_as_float_array_converts_lists_and_ints():
    a = as_float_array([[1, 2], [3, 4]], "x")
    assert a.dtype == np.float64 and a.shape == (2, 2)
    assert as_float_array(3, "x").shape == ()


def test_as_float_array_passes_float_arrays_through():
    x = np.zeros((2, 3))
    assert as_float_array(x, "x", (None, 3)) is x


@pytest.mark.parametrize("bad", ["abc", ["a", "b"], [1 + 2j], None, {"a": 1}, [object()]])
def test_as_float_array_rejects_non_numeric(bad):
    with pytest.raises(TypeError, match="x must contain real numbers"):
        as_float_array(bad, "x")


def test_as_float_array_rejects_symbolic_with_typeerror():
    sp = pytest.importorskip("sympy")
    with pytest.raises(TypeError, match="q must contain real numbers"):
        as_float_array([sp.Symbol("a"), 1.0], "q")


@pytest.mark.parametrize("bad", [[1.0, np.nan], [np.inf, 0.0], -np.inf])
def test_as_float_array_rejects_nonfinite(bad):
    with pytest.raises(DomainError, match="x must be finite; got"):
        as_float_array(bad, "x")


def test_as_float_array_nan_message_gives_index():
    with pytest.raises(DomainError, match=r"q must be finite; got nan at index \(1, 0\)"):
        as_float_array([[0.0, 1.0], [np.nan, 2.0]], "q")


def test_as_float_array_shape():
    assert as_float_array(np.zeros((5, 3)), "p", (-1, 3)).shape == (5, 3)
    with pytest.raises(ShapeError, match=r"p must have shape \(N, 3\); got shape \(5, 2\)"):
        as_float_array(np.zeros((5, 2)), "p", (None, 3))
    with pytest.raises(ShapeError, match=r"p must have shape \(3,\); got shape \(\)"):
        as_float_array(1.0, "p", (3,))


def test_as_float_array_ragged():
    with pytest.raises(ShapeError, match="x must be a rectangular array"):
        as_float_array([[1.0, 2.0], [3.0]], "x")


def test_check_finite():
    assert check_finite([1, 2], "v").dtype == np.float64
    with pytest.raises(DomainError, match="v must be finite"):
        check_finite([1, np.nan], "v")


# --- vectors and batches ------------------------------------------------------------


def test_as_vector():
    assert as_vector((1, 2, 3), 3, "p").shape == (3,)
    assert as_vector(np.arange(7), None, "q").shape == (7,)
    with pytest.raises(ShapeError, match=r"p must have shape \(3,\); got shape \(2,\)"):
        as_vector([1, 2], 3, "p")
    with pytest.raises(ShapeError, match=r"p must have shape \(3,\); got shape \(1, 3\)"):
        as_vector([[1, 2, 3]], 3, "p")


def test_as_batch():
    a, batched = as_batch(np.zeros(6), 6, "q")
    assert a.shape == (6,) and batched is False
    a, batched = as_batch(np.zeros((10, 6)), 6, "q")
    assert a.shape == (10, 6) and batched is True
    a, batched = as_batch([[1, 2]], None, "q")
    assert a.shape == (1, 2) and batched


@pytest.mark.parametrize("shape", [(5,), (2, 5), (2, 2, 6), ()])
def test_as_batch_wrong_shape(shape):
    with pytest.raises(
        ShapeError, match=rf"q must have shape \(6,\) or \(N, 6\); got shape {re_shape(shape)}"
    ):
        as_batch(np.zeros(shape), 6, "q")


def re_shape(shape):
    import re

    return re.escape(str(tuple(shape)))


# --- rotations and transforms -------------------------------------------------------


def _rot(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def test_check_rotation_matrix_accepts():
    R = _rot(0.3)
    assert np.array_equal(check_rotation_matrix(R), R)
    Rs = np.stack([_rot(t) for t in np.linspace(0, 3, 5)])
    assert check_rotation_matrix(Rs).shape == (5, 3, 3)
    assert check_rotation_matrix(R.tolist()).dtype == np.float64


def test_as_rotation_matrix_checks_a_rotation_or_only_the_shape():
    reflection = np.diag([1.0, 1.0, -1.0])
    with pytest.raises(DomainError, match=r"R is not a rotation matrix"):
        as_rotation_matrix(reflection)
    assert np.array_equal(as_rotation_matrix(reflection, check=False), reflection)
    for check in (True, False):
        with pytest.raises(ShapeError, match=r"^R_AB must have shape \(3, 3\) or \(N, 3, 3\); got shape \(3, 4\)$"):
            as_rotation_matrix(np.zeros((3, 4)), check, name="R_AB")
        with pytest.raises(DomainError, match=r"R must be finite"):
            as_rotation_matrix(np.full((3, 3), np.nan), check)


def test_check_rotation_matrix_reflection():
    with pytest.raises(
        DomainError,
        match=r"R is not a rotation matrix: R Rᵀ − I has max \|entry\| 0 \(tolerance 1e-06\), "
        r"det\(R\) = -1",
    ):
        check_rotation_matrix(np.diag([1.0, 1.0, -1.0]))


def test_check_rotation_matrix_not_orthonormal():
    R = _rot(0.3)
    R[0, 0] += 0.1
    with pytest.raises(DomainError, match=r"R_AB is not a rotation matrix: R_AB R_ABᵀ − I has max"):
        check_rotation_matrix(R, name="R_AB")
    # but a loose tolerance accepts it
    check_rotation_matrix(R, tol=0.5)


def test_check_rotation_matrix_batch_names_index():
    Rs = np.stack([_rot(0.1), _rot(0.2), 2 * _rot(0.3)])
    with pytest.raises(DomainError, match=r"R\[2\] is not a rotation matrix"):
        check_rotation_matrix(Rs)


@pytest.mark.parametrize("shape", [(3,), (3, 4), (2, 2, 2), (4, 4)])
def test_check_rotation_matrix_shape(shape):
    with pytest.raises(ShapeError, match=r"R must have shape \(3, 3\) or \(N, 3, 3\); got shape"):
        check_rotation_matrix(np.zeros(shape))


def test_check_rotation_matrix_nan():
    R = np.eye(3)
    R[1, 1] = np.nan
    with pytest.raises(DomainError, match="R must be finite"):
        check_rotation_matrix(R)


def test_check_transform():
    T = np.eye(4)
    T[:3, :3] = _rot(1.0)
    T[:3, 3] = [1, 2, 3]
    assert np.array_equal(check_transform(T), T)
    assert check_transform(np.stack([T, T])).shape == (2, 4, 4)
    bad = T.copy()
    bad[3, 0] = 0.5
    with pytest.raises(DomainError, match=r"T is not a homogeneous transform: bottom row"):
        check_transform(bad)
    with pytest.raises(DomainError, match=r"T_WB\[1\] is not a homogeneous transform"):
        check_transform(np.stack([T, bad]), name="T_WB")
    bad = T.copy()
    bad[:3, :3] *= 2
    with pytest.raises(DomainError, match=r"T\[:3, :3\] is not a rotation matrix"):
        check_transform(bad)
    with pytest.raises(ShapeError, match=r"T must have shape \(4, 4\) or \(N, 4, 4\)"):
        check_transform(np.eye(3))


# --- limits and positive numbers ----------------------------------------------------


def test_check_limits():
    lim = check_limits([[-1, 1], [0, 0], [-np.inf, np.inf]], 3)
    assert lim.shape == (3, 2) and lim.dtype == np.float64
    assert check_limits(np.zeros((4, 2)), None).shape == (4, 2)


def test_check_limits_errors():
    with pytest.raises(DomainError, match=r"limits must have lower <= upper.*row 1 has lower = 2"):
        check_limits([[-1, 1], [2, 1]], 2)
    with pytest.raises(ShapeError, match=r"joint_limits must have shape \(3, 2\); got shape \(2, 2\)"):
        check_limits([[-1, 1], [2, 3]], 3, name="joint_limits")
    with pytest.raises(DomainError, match="limits must not contain NaN"):
        check_limits([[np.nan, 1]], 1)
    with pytest.raises(TypeError, match="limits must contain real numbers"):
        check_limits([["a", "b"]], 1)


def test_check_positive():
    assert check_positive(2, "dt") == 2.0 and isinstance(check_positive(2, "dt"), float)
    assert check_positive(0.0, "damping", allow_zero=True) == 0.0
    assert check_positive(np.float64(1.5), "dt") == 1.5
    np.testing.assert_array_equal(check_positive([1, 2], "w"), [1.0, 2.0])
    with pytest.raises(DomainError, match=r"dt must be positive \(> 0\); got 0"):
        check_positive(0.0, "dt")
    with pytest.raises(DomainError, match=r"damping must be non-negative \(>= 0\); got -1"):
        check_positive(-1, "damping", allow_zero=True)
    with pytest.raises(DomainError, match="dt must be finite"):
        check_positive(float("nan"), "dt")
    with pytest.raises(DomainError, match=r"w must be positive \(> 0\); got -2 at index \(1,\)"):
        check_positive([1, -2], "w")
    with pytest.raises(TypeError, match="dt must contain real numbers"):
        check_positive("fast", "dt")
