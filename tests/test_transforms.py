"""Tests for robokin.transforms: elementary rotations, skew, homogeneous transforms."""

import numpy as np
import pytest
import sympy as sp

from robokin.errors import DomainError, ShapeError
from robokin.transforms import (
    compose,
    rotation_of,
    rotx,
    roty,
    rotz,
    skew,
    transform,
    transform_inverse,
    transform_point,
    translation,
    translation_of,
    unskew,
)

RNG_SEED = 20240501


def random_rotations(rng, n):
    """Haar-random rotations via QR of Gaussian matrices (independent of robokin)."""
    A = rng.standard_normal((n, 3, 3))
    Q, Rr = np.linalg.qr(A)
    Q = Q * np.sign(np.diagonal(Rr, axis1=-2, axis2=-1))[:, None, :]
    Q[np.linalg.det(Q) < 0] *= -1
    return Q


def random_transforms(rng, n):
    T = np.zeros((n, 4, 4))
    T[:, :3, :3] = random_rotations(rng, n)
    T[:, :3, 3] = rng.uniform(-2, 2, (n, 3))
    T[:, 3, 3] = 1
    return T


ROT = {"x": rotx, "y": roty, "z": rotz}
AXES = {"x": 0, "y": 1, "z": 2}


# --- elementary rotations -------------------------------------------------------------


@pytest.mark.parametrize(
    "fn, v, expected",
    [
        (rotz, [1, 0, 0], [0, 1, 0]),
        (rotz, [0, 1, 0], [-1, 0, 0]),
        (rotx, [0, 1, 0], [0, 0, 1]),
        (rotx, [0, 0, 1], [0, -1, 0]),
        (roty, [0, 0, 1], [1, 0, 0]),
        (roty, [1, 0, 0], [0, 0, -1]),
    ],
)
def test_quarter_turns(fn, v, expected):
    np.testing.assert_allclose(fn(np.pi / 2) @ v, expected, atol=1e-15)


@pytest.mark.parametrize("axis", "xyz")
def test_elementary_rotation_properties(axis):
    fn = ROT[axis]
    for t in np.random.default_rng(RNG_SEED).uniform(-7, 7, 20):
        R = fn(t)
        assert R.shape == (3, 3)
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(R) == pytest.approx(1.0)
        e = np.zeros(3)
        e[AXES[axis]] = 1
        np.testing.assert_allclose(R @ e, e, atol=1e-15)  # the axis is fixed
        np.testing.assert_allclose(fn(-t), R.T, atol=1e-15)
    np.testing.assert_allclose(fn(0.3) @ fn(0.4), fn(0.7), atol=1e-15)


@pytest.mark.parametrize("axis", "xyz")
def test_elementary_rotation_batch_equals_loop(axis):
    fn = ROT[axis]
    t = np.linspace(-3, 3, 11)
    Rs = fn(t)
    assert Rs.shape == (11, 3, 3)
    np.testing.assert_array_equal(Rs, np.stack([fn(float(x)) for x in t]))
    assert fn(t.reshape(11, 1)).shape == (11, 1, 3, 3)
    assert fn(list(t)).shape == (11, 3, 3)


@pytest.mark.parametrize("axis", "xyz")
@pytest.mark.parametrize("angle", [0.0, -0.0, np.pi, -np.pi / 2, 1e-300, 123.456])
def test_elementary_rotation_of_one_number_is_the_batch_entry_bit_for_bit(axis, angle):
    """One float takes a fast path (no dispatch): the same float64 entries as the batch code's,
    signed zeros included."""
    fn = ROT[axis]
    R, batch = fn(angle), fn(np.array([angle]))[0]
    assert R.dtype == np.float64 and R.shape == (3, 3) and R.flags.writeable
    assert R.tobytes() == batch.tobytes()


@pytest.mark.parametrize("axis", "xyz")
def test_elementary_rotation_accepts_int_and_numpy_scalars(axis):
    fn = ROT[axis]
    np.testing.assert_array_equal(fn(1), fn(1.0))
    np.testing.assert_array_equal(fn(np.float32(0.5)), fn(float(np.float32(0.5))))
    np.testing.assert_array_equal(fn(np.array(0.5)), fn(0.5))


@pytest.mark.parametrize("axis", "xyz")
def test_elementary_rotation_symbolic(axis):
    fn = ROT[axis]
    a = sp.Symbol("alpha")
    R = fn(a)
    assert isinstance(R, sp.MatrixBase) and R.shape == (3, 3)
    assert not R.atoms(sp.Float)  # exact entries, no 1.0
    assert sp.simplify(R * R.T - sp.eye(3)) == sp.zeros(3, 3)
    for t in (0.3, -2.0):
        np.testing.assert_allclose(np.array(R.subs(a, t), dtype=float), fn(t), atol=1e-15)
    assert fn(sp.pi / 2) == sp.Matrix(np.round(fn(np.pi / 2)).astype(int))


def test_rotz_symbolic_readable():
    a = sp.Symbol("alpha")
    assert rotz(a) == sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])


@pytest.mark.parametrize("bad", [np.nan, np.inf, [0.1, np.nan]])
def test_rotation_nonfinite(bad):
    with pytest.raises(DomainError, match="angle must be finite"):
        rotz(bad)


def test_rotation_non_numeric():
    with pytest.raises(TypeError, match="angle must contain real numbers"):
        rotx("90deg")


# --- skew / unskew --------------------------------------------------------------------


def test_skew_cross_product():
    rng = np.random.default_rng(RNG_SEED)
    v, u = rng.standard_normal((2, 3))
    S = skew(v)
    np.testing.assert_allclose(S @ u, np.cross(v, u), atol=1e-15)
    np.testing.assert_array_equal(S, -S.T)
    np.testing.assert_array_equal(unskew(S), v)


def test_skew_batch():
    v = np.random.default_rng(1).standard_normal((6, 3))
    S = skew(v)
    assert S.shape == (6, 3, 3)
    np.testing.assert_array_equal(S, np.stack([skew(x) for x in v]))
    np.testing.assert_array_equal(unskew(S), v)


def test_skew_symbolic():
    x, y, z = sp.symbols("x y z")
    S = skew([x, y, z])
    assert S == sp.Matrix([[0, -z, y], [z, 0, -x], [-y, x, 0]])
    assert skew(sp.Matrix([x, y, z])) == S
    assert unskew(S) == sp.Matrix([x, y, z])


def test_skew_errors():
    with pytest.raises(ShapeError, match=r"v must have shape \(3,\) or \(N, 3\); got shape \(2,\)"):
        skew([1, 2])
    with pytest.raises(DomainError, match="S is not skew-symmetric"):
        unskew(np.eye(3))
    unskew(np.eye(3), check=False)  # no error without the check
    with pytest.raises(ShapeError, match=r"S must have shape \(3, 3\)"):
        unskew(np.zeros((4, 4)))


# --- homogeneous transforms -------------------------------------------------------------


def test_transform_and_parts():
    R, p = rotz(0.4), np.array([1.0, 2.0, 3.0])
    T = transform(R, p)
    assert T.shape == (4, 4)
    np.testing.assert_array_equal(T[3], [0, 0, 0, 1])
    np.testing.assert_array_equal(rotation_of(T), R)
    np.testing.assert_array_equal(translation_of(T), p)
    # parts are copies
    rotation_of(T)[0, 0] = 99
    assert T[0, 0] != 99


def test_transform_broadcasting():
    Rs = rotz(np.linspace(0, 1, 4))
    ps = np.arange(12.0).reshape(4, 3)
    assert transform(Rs, [0, 0, 1]).shape == (4, 4, 4)
    assert transform(np.eye(3), ps).shape == (4, 4, 4)
    T = transform(Rs, ps)
    for i in range(4):
        np.testing.assert_array_equal(T[i], transform(Rs[i], ps[i]))
    with pytest.raises(ShapeError, match="R and p have incompatible batch sizes"):
        transform(Rs, np.zeros((3, 3)))


def test_transform_errors():
    with pytest.raises(DomainError, match="R is not a rotation matrix"):
        transform(2 * np.eye(3), [0, 0, 0])
    transform(2 * np.eye(3), [0, 0, 0], check=False)
    with pytest.raises(ShapeError, match=r"p must have shape \(3,\) or \(N, 3\); got shape \(4,\)"):
        transform(np.eye(3), [0, 0, 0, 1])
    with pytest.raises(ShapeError, match=r"R must have shape \(3, 3\) or \(N, 3, 3\)"):
        transform(np.eye(4), [0, 0, 0], check=False)
    with pytest.raises(DomainError, match="p must be finite"):
        transform(np.eye(3), [0, np.nan, 0])


def test_translation():
    T = translation([1, 2, 3])
    np.testing.assert_array_equal(T, [[1, 0, 0, 1], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]])
    assert translation(np.zeros((5, 3))).shape == (5, 4, 4)


def test_inverse_identities():
    rng = np.random.default_rng(RNG_SEED)
    Ts = random_transforms(rng, 50)
    Tinv = transform_inverse(Ts)
    np.testing.assert_allclose(Ts @ Tinv, np.broadcast_to(np.eye(4), Ts.shape), atol=1e-14)
    np.testing.assert_allclose(Tinv, np.linalg.inv(Ts), atol=1e-13)
    for i in range(3):
        np.testing.assert_allclose(transform_inverse(Ts[i]), Tinv[i], atol=0)
    np.testing.assert_allclose(transform_inverse(Tinv), Ts, atol=1e-14)


def test_inverse_rejects_non_transform():
    with pytest.raises(DomainError, match="T is not a homogeneous transform"):
        transform_inverse(np.ones((4, 4)))
    with pytest.raises(ShapeError, match=r"T must have shape \(4, 4\) or \(N, 4, 4\); got shape \(3, 3\)"):
        transform_inverse(np.eye(3))


def test_compose():
    rng = np.random.default_rng(RNG_SEED + 1)
    A, B, C = random_transforms(rng, 3)
    np.testing.assert_allclose(compose(A, B, C), A @ B @ C, atol=1e-14)
    np.testing.assert_array_equal(compose(A), A)
    np.testing.assert_array_equal(compose(), np.eye(4))
    np.testing.assert_allclose(compose(A, transform_inverse(A)), np.eye(4), atol=1e-14)
    batch = random_transforms(rng, 5)
    np.testing.assert_allclose(compose(A, batch), A @ batch, atol=1e-14)
    with pytest.raises(DomainError, match=r"Ts\[1\] is not a homogeneous transform"):
        compose(A, 2 * B)
    with pytest.raises(ShapeError, match="incompatible batch sizes"):
        compose(batch, random_transforms(rng, 4))


def test_compose_matches_frames_convention():
    # T_AB: B is A rotated 90 deg about z and shifted by x = 1.
    T_AB = transform(rotz(np.pi / 2), [1, 0, 0])
    T_BC = translation([1, 0, 0])
    T_AC = compose(T_AB, T_BC)
    # C's origin is 1 along B's x axis, which is A's y axis.
    np.testing.assert_allclose(translation_of(T_AC), [1, 1, 0], atol=1e-15)
    np.testing.assert_allclose(transform_point(T_AB, [1, 0, 0]), [1, 1, 0], atol=1e-15)


def test_transform_point_shapes():
    rng = np.random.default_rng(RNG_SEED + 2)
    Ts = random_transforms(rng, 4)
    pts = rng.standard_normal((4, 3))
    T = Ts[0]
    np.testing.assert_allclose(transform_point(T, pts[0]), (T @ np.append(pts[0], 1))[:3])
    out = transform_point(T, pts)
    assert out.shape == (4, 3)
    np.testing.assert_allclose(out, np.stack([transform_point(T, p) for p in pts]))
    assert transform_point(Ts, pts[0]).shape == (4, 3)
    pair = transform_point(Ts, pts)
    np.testing.assert_allclose(pair, np.stack([transform_point(Ts[i], pts[i]) for i in range(4)]))
    back = transform_point(transform_inverse(Ts), pair)
    np.testing.assert_allclose(back, pts, atol=1e-13)
    with pytest.raises(ShapeError, match="T and p have incompatible batch sizes"):
        transform_point(Ts, np.zeros((3, 3)))
    with pytest.raises(ShapeError, match=r"p must have shape \(3,\) or \(N, 3\)"):
        transform_point(T, [1, 2])


def test_homogeneous_symbolic():
    a, d = sp.symbols("alpha d")
    T = transform(rotx(a), [0, 0, d])
    assert isinstance(T, sp.MatrixBase) and T.shape == (4, 4)
    assert T[3, :] == sp.Matrix([[0, 0, 0, 1]])
    assert not T.atoms(sp.Float)
    Ti = transform_inverse(T)
    assert sp.simplify(T * Ti) == sp.eye(4)
    assert translation([0, 0, d]) == sp.Matrix([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, d], [0, 0, 0, 1]])
    C = compose(T, translation([1, 0, 0]))
    subs = {a: 0.7, d: 0.2}
    num = compose(transform(rotx(0.7), [0, 0, 0.2]), translation([1, 0, 0]))
    np.testing.assert_allclose(np.array(C.subs(subs), dtype=float), num, atol=1e-15)
    # mixing a numeric array with a symbolic matrix gives exact integers
    assert not compose(np.eye(4), T).atoms(sp.Float)
    assert rotation_of(T) == rotx(a)
    assert translation_of(T) == sp.Matrix([0, 0, d])
    x = sp.Symbol("x")
    assert transform_point(T, [x, 0, 0]) == sp.Matrix([x, 0, d])
