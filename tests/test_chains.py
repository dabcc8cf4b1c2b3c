"""Tests of robokin.chains: elements, SerialChain, DH / modified DH / link-table builders."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from robokin.chains import (
    Fixed,
    Rx,
    Ry,
    Rz,
    SerialChain,
    Tx,
    Ty,
    Tz,
    from_dh,
    from_link_table,
    from_modified_dh,
)
from robokin.chains import _engine as engine_module
from robokin.errors import DomainError, ShapeError

# --------------------------------------------------------------------------- helpers


def rot(axis: int, a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    T = np.eye(4)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    T[i, i] = T[j, j] = c
    T[j, i] = s
    T[i, j] = -s
    return T


def trans(axis: int, d: float) -> np.ndarray:
    T = np.eye(4)
    T[axis, 3] = d
    return T


def vee_log_small(R: np.ndarray) -> np.ndarray:
    """Rotation vector of a small rotation (batched): vee((R - R^T)/2), exact to O(θ³)."""
    A = 0.5 * (R - np.swapaxes(R, -1, -2))
    return np.stack([A[..., 2, 1], A[..., 0, 2], A[..., 1, 0]], axis=-1)


def fd_jacobian(pose_fn, Q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Central finite-difference geometric Jacobian (N, 6, n) of a batched pose function."""
    N, n = Q.shape
    J = np.empty((N, 6, n))
    for i in range(n):
        e = np.zeros(n)
        e[i] = h
        Tp, Tm = pose_fn(Q + e), pose_fn(Q - e)
        J[:, :3, i] = (Tp[:, :3, 3] - Tm[:, :3, 3]) / (2 * h)
        J[:, 3:, i] = vee_log_small(Tp[:, :3, :3] @ np.swapaxes(Tm[:, :3, :3], -1, -2)) / (2 * h)
    return J


def mixed_chain() -> SerialChain:
    """A chain exercising every feature: x/y/z axes, negative axes, offsets, prismatic joints,
    Fixed transforms and a tool."""
    T = rot(0, 0.3) @ rot(2, -0.7) @ trans(1, 0.2)
    tool = trans(2, 0.15) @ rot(1, 0.4)
    return SerialChain(
        [
            Tz(0.4), Rz("q1"), Tx(0.1), Ry("-q2", offset=0.2), Tz(0.5),
            Tx("d3", offset=0.1, limits=(0, 0.5)), Fixed(T), Rx("q4"), Ty(0.3),
            Rz("-q5"), Tz("-d6"), Ry("q6", offset=-1.0),
        ],
        tool=tool,
        name="mixed",
    )


@pytest.fixture(scope="module")
def mixed() -> SerialChain:
    return mixed_chain()


@pytest.fixture(scope="module")
def leg() -> SerialChain:
    return SerialChain(
        [Ty(1), Rx("alpha"), Tz(-1), Ry("beta"), Tz(-1), Ry("gamma"), Tz(-1)],
        frame_names=["B", "1", "2", "3", "F"],
        limits=[[-1.5, 1.5]] * 3,
    )


# --------------------------------------------------------------------------- elements


def test_elements_constant_and_joint():
    assert not Rx(0.3).is_joint
    j = Rx("alpha")
    assert j.is_joint and j.joint == "alpha" and j.sign == 1 and j.joint_type == "revolute"
    neg = Ry("-q3", offset=0.5, limits=(-1, 1))
    assert neg.sign == -1 and neg.joint == "q3" and neg.offset == 0.5 and neg.limits == (-1.0, 1.0)
    assert Tz("d").joint_type == "prismatic"
    assert "q3" in repr(neg) and "Rx" in repr(Rx(0.1))
    assert Tz(sp.Symbol("l1")).value == sp.Symbol("l1")


@pytest.mark.parametrize(
    "make, exc",
    [
        (lambda: Rx([1, 2]), TypeError),
        (lambda: Tz(float("nan")), DomainError),
        (lambda: Tz(float("inf")), DomainError),
        (lambda: Rz("q", limits=(1, 0)), DomainError),
        (lambda: Rz("q", limits=(1, 2, 3)), ShapeError),
        (lambda: Rz(0.3, offset=0.1), ValueError),
        (lambda: Fixed(np.eye(3)), ShapeError),
        (lambda: Fixed(np.diag([1.0, 1.0, -1.0, 1.0])), DomainError),
    ],
)
def test_element_errors(make, exc):
    with pytest.raises(exc):
        make()


def test_fixed_error_names_argument():
    with pytest.raises(ShapeError, match="T"):
        Fixed(np.eye(3))


# --------------------------------------------------------------------------- construction


def test_chain_properties(mixed):
    assert mixed.n == 7
    assert mixed.joint_names == ["q1", "q2", "d3", "q4", "q5", "d6", "q6"]
    assert mixed.joint_types == [
        "revolute", "revolute", "prismatic", "revolute", "revolute", "prismatic", "revolute"
    ]
    assert mixed.limits.shape == (7, 2)
    np.testing.assert_allclose(mixed.limits[0], [-math.pi, math.pi])
    np.testing.assert_allclose(mixed.limits[2], [0.0, 0.5])
    np.testing.assert_allclose(mixed.limits[5], [-1.0, 1.0])
    assert mixed.frame_names == ["base", "q1", "q2", "d3", "q4", "q5", "d6", "q6", "ee"]
    np.testing.assert_array_equal(
        mixed.joint_axes,
        [[0, 0, 1], [0, -1, 0], [1, 0, 0], [1, 0, 0], [0, 0, -1], [0, 0, -1], [0, 1, 0]],
    )
    assert mixed.tool.shape == (4, 4)
    assert "mixed" in repr(mixed)
    with pytest.raises(ValueError):
        mixed.limits[0, 0] = 3.0  # read-only


@pytest.mark.parametrize(
    "kwargs, exc, word",
    [
        ({"limits": [[0, 1], [2, 1]]}, DomainError, "limits"),
        ({"limits": [[0, 1]]}, ShapeError, "limits"),
        ({"limits": [[0, 1], [0, float("nan")]]}, DomainError, "limits"),
        ({"tool": np.eye(3)}, ShapeError, "tool"),
        ({"tool": 2 * np.eye(4)}, DomainError, "tool"),
        ({"frame_names": ["a", "b"]}, ShapeError, "frame_names"),
        ({"base": np.eye(3)}, ShapeError, "base"),
        ({"base": np.diag([1.0, 1.0, -1.0, 1.0])}, DomainError, "base"),
    ],
)
def test_chain_constructor_errors(kwargs, exc, word):
    with pytest.raises(exc, match=word):
        SerialChain([Rz("a"), Tx(1), Rz("b")], **kwargs)


def test_chain_needs_joints_and_unique_names():
    with pytest.raises(ValueError, match="joint"):
        SerialChain([Tx(1), Rz(0.2)])
    with pytest.raises(ValueError, match="unique"):
        SerialChain([Rz("a"), Rz("a")])
    with pytest.raises(TypeError, match="elements"):
        SerialChain([Rz("a"), "Tx(1)"])  # type: ignore[list-item]  # a wrong type on purpose


# --------------------------------------------------------------------------- q validation


@pytest.mark.parametrize("method", ["fk", "frames", "jacobian", "position_jacobian", "manipulability"])
@pytest.mark.parametrize(
    "q, exc, pattern",
    [
        ([0.1, 0.2], ShapeError, r"q must have shape \(3,\) or \(N, 3\); got shape \(2,\)"),
        (np.zeros((2, 4)), ShapeError, r"q must have shape \(3,\) or \(N, 3\); got shape \(2, 4\)"),
        (np.zeros((2, 2, 3)), ShapeError, r"q .*got shape \(2, 2, 3\)"),
        (0.3, ShapeError, r"q .*got shape \(\)"),
        ([0.1, float("nan"), 0.2], DomainError, r"q must be finite"),
        (np.array([[0.1, 0.2, 0.3], [0.0, np.inf, 0.0]]), DomainError, r"q must be finite"),
        (["a", "b", "c"], TypeError, r"q"),
    ],
)
def test_bad_q(leg, method, q, exc, pattern):
    with pytest.raises(exc, match=pattern):
        getattr(leg, method)(q)


def test_bad_symbolic_q(leg):
    a, b = sp.symbols("a b")
    with pytest.raises(ShapeError, match=r"q must have shape \(3,\)"):
        leg.fk([a, b])


def test_check_false_accepts_int_arrays(leg):
    np.testing.assert_allclose(leg.fk(np.array([0, 0, 0]), check=False), leg.fk([0.0, 0.0, 0.0]))


def test_large_but_finite_q_is_accepted(leg):
    leg.fk(np.array([1e200, 0.0, 0.0]))  # q @ q overflows: must not be reported as NaN/inf


@pytest.mark.parametrize(
    "frame, exc",
    [(7, DomainError), (-8, DomainError), ("nope", DomainError), (1.5, TypeError), (True, TypeError)],
)
def test_bad_frame(leg, frame, exc):
    with pytest.raises(exc, match="frame"):
        leg.fk([0.1, 0.2, 0.3], frame=frame)


def test_bad_point(leg):
    with pytest.raises(ShapeError, match="point"):
        leg.jacobian([0.1, 0.2, 0.3], point=[1.0, 2.0])


# --------------------------------------------------------------------------- kinematics


def reference_fk(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """Product of element matrices, written independently of the engine."""
    T = np.eye(4)
    j = 0
    for el in chain.elements:
        if el.kind == "F":
            M = np.asarray(el.matrix, dtype=float)
        else:
            v = el.sign * q[j] + float(el.offset) if el.is_joint else float(el.value)
            M = rot(el.axis, v) if el.kind == "R" else trans(el.axis, v)
        if el.is_joint:
            j += 1
        T = T @ M
    return T @ chain.tool


def test_fk_matches_element_product(mixed):
    Q = np.random.default_rng(0).uniform(-2, 2, (50, mixed.n))
    for q in Q:
        np.testing.assert_allclose(mixed.fk(q), reference_fk(mixed, q), atol=1e-12)


def test_fk_leg_known_pose(leg):
    np.testing.assert_allclose(leg.fk([0.0, 0.0, 0.0])[:3, 3], [0.0, 1.0, -3.0], atol=1e-15)
    np.testing.assert_allclose(leg.fk([0.0, math.pi / 2, 0.0])[:3, 3], [-2.0, 1.0, -1.0], atol=1e-15)


def test_batch_equals_loop(mixed):
    Q = np.random.default_rng(1).uniform(-2, 2, (40, mixed.n))
    point = np.array([0.1, -0.2, 0.3])
    for k in range(mixed.n + 2):
        np.testing.assert_allclose(mixed.fk(Q, frame=k), [mixed.fk(q, frame=k) for q in Q], atol=1e-12)
        np.testing.assert_allclose(
            mixed.jacobian(Q, frame=k, point=point),
            [mixed.jacobian(q, frame=k, point=point) for q in Q],
            atol=1e-12,
        )
    np.testing.assert_allclose(mixed.frames(Q), [mixed.frames(q) for q in Q], atol=1e-12)
    np.testing.assert_allclose(mixed.jacobian(Q), [mixed.jacobian(q) for q in Q], atol=1e-12)
    assert mixed.fk(Q[:0]).shape == (0, 4, 4)


def test_frames_contract(mixed):
    rng = np.random.default_rng(2)
    q = rng.uniform(-1, 1, mixed.n)
    F = mixed.frames(q)
    assert F.shape == (mixed.n + 2, 4, 4)
    np.testing.assert_allclose(F[0], np.eye(4))
    np.testing.assert_allclose(F[-1], mixed.fk(q), atol=1e-14)
    for i in range(1, mixed.n + 1):
        np.testing.assert_allclose(F[i], mixed.fk(q, frame=i), atol=1e-14)
        np.testing.assert_allclose(F[i], mixed.frame_pose(q, mixed.frame_names[i]), atol=1e-14)
        # Moving joint i alone: the axis (through frame i's origin, along joint_axes[i-1])
        # stays put; for a revolute joint the origin stays put as well.
        dq = np.zeros(mixed.n)
        dq[i - 1] = 0.37
        G = mixed.frames(q + dq)
        a = mixed.joint_axes[i - 1]
        np.testing.assert_allclose(G[i][:3, :3] @ a, F[i][:3, :3] @ a, atol=1e-12)
        moved = G[i][:3, 3] - F[i][:3, 3]
        if mixed.joint_types[i - 1] == "revolute":
            np.testing.assert_allclose(moved, 0.0, atol=1e-12)
        else:
            np.testing.assert_allclose(moved, 0.37 * (F[i][:3, :3] @ a), atol=1e-12)


def test_fk_and_jacobian_is_one_pass_of_fk_and_jacobian(mixed, leg):
    Q = np.random.default_rng(3).uniform(-2, 2, (20, mixed.n))
    for q in Q:
        T, J = mixed.fk_and_jacobian(q)
        np.testing.assert_allclose(T, mixed.fk(q), atol=1e-14)
        np.testing.assert_array_equal(T, mixed.frames(q)[-1])  # the same running products
        np.testing.assert_array_equal(J, mixed.jacobian(q))
    # a batch: the pose the batched Jacobian passes on its way, to the last bit
    T, J = mixed.fk_and_jacobian(Q)
    np.testing.assert_array_equal(T, mixed.fk(Q))
    np.testing.assert_array_equal(J, mixed.jacobian(Q))
    with pytest.raises(ShapeError, match=r"q must have shape \(3,\) or \(N, 3\)"):
        leg.fk_and_jacobian(np.zeros((2, 4)))
    with pytest.raises(ShapeError, match="symbols"):
        leg.fk_and_jacobian(sp.symbols("a b c"))
    with pytest.raises(DomainError, match="q"):
        leg.fk_and_jacobian([0.0, np.nan, 0.0])


def test_frames_batch_shape(leg):
    Q = np.zeros((5, 3))
    assert leg.frames(Q).shape == (5, 5, 4, 4)
    assert leg.frame_names == ["B", "1", "2", "3", "F"]


@pytest.mark.parametrize("k", list(range(9)))
def test_jacobian_finite_differences_all_frames(mixed, k):
    Q = np.random.default_rng(3).uniform(-1.5, 1.5, (100, mixed.n))
    point = np.array([0.2, 0.1, -0.3])
    for pt in (None, point):
        J = mixed.jacobian(Q, frame=k, point=pt)

        def pose(X, k=k, pt=pt):
            T = mixed.fk(X, frame=k)
            if pt is not None:
                T = T.copy()
                T[:, :3, 3] += T[:, :3, :3] @ pt
            return T

        np.testing.assert_allclose(J, fd_jacobian(pose, Q), atol=1e-6)
        # joints beyond an intermediate frame do not move it
        if 1 <= k <= mixed.n:
            np.testing.assert_array_equal(J[:, :, k:], 0.0)


def test_position_jacobian(mixed):
    q = np.linspace(-1, 1, mixed.n)
    np.testing.assert_allclose(mixed.position_jacobian(q), mixed.jacobian(q)[:3])
    Q = np.stack([q, -q])
    assert mixed.position_jacobian(Q).shape == (2, 3, mixed.n)


# --------------------------------------------------------------------------- measures


def test_manipulability_planar_formula():
    l1, l2 = 0.7, 0.4
    arm = SerialChain([Rz("q1"), Tx(l1), Rz("q2"), Tx(l2)])
    Q = np.random.default_rng(4).uniform(-3, 3, (20, 2))
    # position-only Jacobian of a planar arm has a zero z-row: w = 0 for the 3×2 J_v.
    # The planar (x, y) rows give |l1 l2 sin q2| (Siciliano et al. 2009, eq. 3.57).
    Jxy = arm.jacobian(Q)[:, :2, :]
    w = np.sqrt(np.linalg.det(Jxy @ np.swapaxes(Jxy, 1, 2)))
    np.testing.assert_allclose(w, np.abs(l1 * l2 * np.sin(Q[:, 1])), atol=1e-12)
    assert np.all(arm.manipulability(Q, position_only=True) == 0.0)  # n = 2 < 3 rows


def test_manipulability_svd_and_condition(leg):
    q = np.array([0.2, 0.5, -1.0])
    Jv = leg.position_jacobian(q)
    assert leg.manipulability(q, position_only=True) == pytest.approx(abs(np.linalg.det(Jv)))
    assert leg.manipulability(q) == 0.0  # 3 joints, 6 rows
    sv = leg.singular_values(q, position_only=True)
    np.testing.assert_allclose(sv, np.linalg.svd(Jv, compute_uv=False))
    assert leg.condition_number(q, position_only=True) == pytest.approx(sv[0] / sv[-1])
    # stretched leg (beta = gamma = 0) is singular
    assert leg.manipulability([0.0, 0.0, 0.0], position_only=True) == pytest.approx(0.0, abs=1e-12)
    assert leg.condition_number([0.0, 0.0, 0.0], position_only=True) > 1e12
    Q = np.stack([q, q, q])
    assert leg.manipulability(Q, position_only=True).shape == (3,)
    assert leg.condition_number(Q, position_only=True).shape == (3,)
    assert leg.singular_values(Q).shape == (3, 3)


# --------------------------------------------------------------------------- configurations


def test_random_configurations(leg):
    Q = leg.random_configurations(500, seed=7)
    assert Q.shape == (500, 3)
    assert np.all(Q >= leg.limits[:, 0]) and np.all(Q <= leg.limits[:, 1])
    np.testing.assert_array_equal(Q, leg.random_configurations(500, seed=7))
    assert leg.within_limits(Q).all()
    assert not leg.within_limits([2.0, 0.0, 0.0])
    with pytest.raises(DomainError, match="N"):
        leg.random_configurations(-1)
    unlimited = SerialChain([Rz("a")], limits=[[-np.inf, np.inf]])
    with pytest.raises(DomainError, match="finite"):
        unlimited.random_configurations(3)


# --------------------------------------------------------------------------- builders


def dh_row(d, th, a, al):
    return rot(2, th) @ trans(2, d) @ trans(0, a) @ rot(0, al)


def mdh_row(d, th, a, al):
    return rot(0, al) @ trans(0, a) @ rot(2, th) @ trans(2, d)


DH = [[0.3, 0.1, 0.2, math.pi / 2], [0.0, -0.4, 0.5, 0.0], [0.1, 0.0, 0.0, -math.pi / 2]]


def test_from_dh_matches_row_product():
    chain = from_dh(DH)
    assert chain.joint_names == ["q1", "q2", "q3"]
    for q in np.random.default_rng(5).uniform(-3, 3, (20, 3)):
        T = np.eye(4)
        for (d, off, a, al), qi in zip(DH, q):
            T = T @ dh_row(d, qi + off, a, al)
        np.testing.assert_allclose(chain.fk(q), T, atol=1e-12)


def test_from_modified_dh_matches_row_product():
    chain = SerialChain.from_modified_dh(DH)
    for q in np.random.default_rng(6).uniform(-3, 3, (20, 3)):
        T = np.eye(4)
        for (d, off, a, al), qi in zip(DH, q):
            T = T @ mdh_row(d, qi + off, a, al)
        np.testing.assert_allclose(chain.fk(q), T, atol=1e-12)


def test_dh_prismatic_column_and_types():
    table = [[0.3, 0.0, 0.0, 0.0, "R"], [0.2, 0.5, 0.1, 0.0, "P"], [0.0, 0.0, 0.4, 0.3, 0]]
    chain = from_dh(table)
    assert chain.joint_types == ["revolute", "prismatic", "revolute"]
    q = np.array([0.3, 0.25, -0.6])
    T = dh_row(0.3, 0.3, 0.0, 0.0) @ dh_row(0.2 + 0.25, 0.5, 0.1, 0.0) @ dh_row(0.0, -0.6, 0.4, 0.3)
    np.testing.assert_allclose(chain.fk(q), T, atol=1e-12)
    mchain = from_modified_dh(table)
    T = mdh_row(0.3, 0.3, 0.0, 0.0) @ mdh_row(0.45, 0.5, 0.1, 0.0) @ mdh_row(0.0, -0.6, 0.4, 0.3)
    np.testing.assert_allclose(mchain.fk(q), T, atol=1e-12)


@pytest.mark.parametrize("builder", [from_dh, from_modified_dh])
@pytest.mark.parametrize("table", [[[0.1, 0.2, 0.3]], [[0.1, 0.2, 0.3, 0.4, "R", 9]], [[0.1] * 4, [0.2] * 3], []])
def test_dh_wrong_columns(builder, table):
    with pytest.raises(ShapeError, match="table"):
        builder(table)


def test_dh_bad_joint_type_and_names():
    with pytest.raises(DomainError, match="type|R"):
        from_dh([[0.1, 0.0, 0.0, 0.0, "Q"]])
    with pytest.raises(ShapeError, match="joint_names"):
        from_dh(DH, joint_names=["a"])


def test_link_table_matches_dh():
    """A DH chain written as a link table: iT(i+1)(0) = DH row i at q = 0, joint about child z."""
    dh = from_dh(DH)
    # DH row i is Rz(q_i + off_i) M_i with M_i = Tz Tx Rx; as a link table the fixed part
    # in front of joint i is M_{i-1} Rz(off_i) (M_0 = I) and M_n goes to the end-effector.
    M = [trans(2, d) @ trans(0, a) @ rot(0, al) for d, _, a, al in DH]
    offs = [row[1] for row in DH]
    mats = [rot(2, offs[0])] + [M[i - 1] @ rot(2, offs[i]) for i in range(1, 3)] + [M[2]]
    chain = from_link_table(mats, ["R", "revolute", "R"])
    Q = np.random.default_rng(8).uniform(-3, 3, (20, 3))
    np.testing.assert_allclose(chain.fk(Q), dh.fk(Q), atol=1e-12)
    np.testing.assert_allclose(chain.jacobian(Q), dh.jacobian(Q), atol=1e-12)
    # same joint frames, too (both put frame i right after joint i's rotation)
    np.testing.assert_allclose(chain.frames(Q), dh.frames(Q), atol=1e-12)


def test_link_table_prismatic_and_errors():
    A = trans(0, 0.5) @ rot(0, 0.3)
    chain = from_link_table([A, A], ["revolute", "prismatic"])
    q = np.array([0.4, 0.2])
    np.testing.assert_allclose(chain.fk(q), A @ rot(2, 0.4) @ A @ trans(2, 0.2), atol=1e-12)
    with pytest.raises(ShapeError, match="transforms"):
        from_link_table([A], ["R", "R", "R"])
    with pytest.raises(ShapeError, match="transforms"):
        from_link_table([np.eye(3), A], ["R", "R"])
    with pytest.raises(DomainError, match="joint_types"):
        from_link_table([A], ["X"])


def test_base_and_tool():
    base = trans(0, 1.0) @ rot(2, 0.5)
    tool = trans(2, 0.2)
    chain = SerialChain([Rz("a"), Tx(1.0)], base=base, tool=tool)
    q = np.array([0.3])
    np.testing.assert_allclose(chain.fk(q), base @ rot(2, 0.3) @ trans(0, 1.0) @ tool, atol=1e-12)
    np.testing.assert_allclose(chain.tool, tool)


# --------------------------------------------------------------------------- symbolic


def test_symbolic_leg_readable(leg):
    a, b, g = leg.symbols()
    assert all(s.is_real for s in (a, b, g))
    T = leg.fk([a, b, g])
    assert isinstance(T, sp.MatrixBase) and T.shape == (4, 4)
    text = str(T)
    assert "sin(beta + gamma)" in text and "cos(beta + gamma)" in text
    assert sp.simplify(T[0, 3] - (-sp.sin(b) - sp.sin(b + g))) == 0
    J = leg.jacobian([a, b, g])
    assert J.shape == (6, 3)
    assert "sin(beta + gamma)" in str(J)
    assert leg.position_jacobian([a, b, g]).shape == (3, 3)


def test_symbolic_matches_numeric(mixed):
    s = mixed.symbols()
    F = mixed.fk(s)
    J = mixed.jacobian(s)
    frames = mixed.frames(s)
    assert len(frames) == mixed.n + 2
    q = np.array([0.3, -0.2, 0.1, 0.5, -0.7, 0.2, 0.9])
    sub = dict(zip(s, q))
    np.testing.assert_allclose(np.array(F.subs(sub), dtype=float), mixed.fk(q), atol=1e-12)
    np.testing.assert_allclose(np.array(J.subs(sub), dtype=float), mixed.jacobian(q), atol=1e-12)
    np.testing.assert_allclose(
        np.array(mixed.jacobian(s, frame=3, point=[0.1, 0.2, 0.3]).subs(sub), dtype=float),
        mixed.jacobian(q, frame=3, point=[0.1, 0.2, 0.3]),
        atol=1e-12,
    )
    # mixed numbers and symbols
    t = sp.Symbol("t", real=True)
    Fm = mixed.fk([t, 0, 0.1, 0.5, -0.7, 0.2, 0.9])
    assert Fm.free_symbols == {t}


def test_symbolic_cache_returns_same_object(leg):
    s = leg.symbols()
    assert leg.fk(s) is leg.fk(s)


def test_link_parameters_and_subs():
    l1, l2 = sp.symbols("l1 l2", positive=True)
    arm = SerialChain([Rz("q1"), Tx(l1), Rz("q2"), Tx(l2)])
    assert {str(p) for p in arm.parameters} == {"l1", "l2"}
    q1, q2 = arm.symbols()
    p = arm.fk([q1, q2])[:3, 3]
    assert sp.simplify(p[0] - (l1 * sp.cos(q1) + l2 * sp.cos(q1 + q2))) == 0
    with pytest.raises(TypeError, match="subs"):
        arm.fk([0.1, 0.2])
    num = arm.subs({l1: 0.5, "l2": 0.25})
    np.testing.assert_allclose(num.fk([0.0, 0.0])[:3, 3], [0.75, 0.0, 0.0])


def test_lambdify_matches_direct(mixed):
    Q = np.random.default_rng(9).uniform(-2, 2, (30, mixed.n))
    f = mixed.lambdify_fk()
    g = mixed.lambdify_jacobian()
    np.testing.assert_allclose(f(Q), mixed.fk(Q), atol=1e-12)
    np.testing.assert_allclose(g(Q), mixed.jacobian(Q), atol=1e-12)
    np.testing.assert_allclose(f(Q[0]), mixed.fk(Q[0]), atol=1e-12)
    f3 = mixed.lambdify_fk(frame=3)
    np.testing.assert_allclose(f3(Q), mixed.fk(Q, frame=3), atol=1e-12)
    with pytest.raises(ShapeError, match="q"):
        f(np.zeros(2))


# --------------------------------------------------------------------------- properties

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_element_spec = st.tuples(
    st.sampled_from(["T", "R"]),
    st.sampled_from("xyz"),
    st.booleans(),  # joint?
    st.booleans(),  # negative axis?
    st.floats(-1.0, 1.0),  # constant value / joint offset
)


def _build(specs):
    makers = {("T", "x"): Tx, ("T", "y"): Ty, ("T", "z"): Tz, ("R", "x"): Rx, ("R", "y"): Ry, ("R", "z"): Rz}
    els = []
    j = 0
    for kind, axis, is_joint, neg, v in specs:
        mk = makers[(kind, axis)]
        if is_joint:
            els.append(mk(("-" if neg else "") + f"j{j}", offset=v))
            j += 1
        else:
            els.append(mk(v))
    els.append(Rz("last"))
    return SerialChain(els)


@settings(max_examples=40, deadline=None)
@given(st.lists(_element_spec, min_size=0, max_size=8), st.integers(0, 2**31 - 1))
def test_random_chains_jacobian_and_batch(specs, seed):
    chain = _build(specs)
    Q = np.random.default_rng(seed).uniform(-2, 2, (6, chain.n))
    J = chain.jacobian(Q)
    np.testing.assert_allclose(J, fd_jacobian(chain.fk, Q), atol=1e-6)
    np.testing.assert_allclose(J, [chain.jacobian(q) for q in Q], atol=1e-12)
    np.testing.assert_allclose(chain.fk(Q), [reference_fk(chain, q) for q in Q], atol=1e-12)


def test_batches_larger_than_one_chunk(mixed):
    """Batched evaluation works in chunks; force tiny chunks and compare with the loop."""
    chain = mixed_chain()
    chain._engine.CHUNK = 7  # instance attribute: private tuning knob of the numeric engine
    Q = np.random.default_rng(10).uniform(-2, 2, (23, chain.n))
    np.testing.assert_allclose(chain.fk(Q), [chain.fk(q) for q in Q], atol=1e-12)
    np.testing.assert_allclose(chain.frames(Q), [chain.frames(q) for q in Q], atol=1e-12)
    np.testing.assert_allclose(chain.jacobian(Q, frame=4), [chain.jacobian(q, frame=4) for q in Q], atol=1e-12)
    np.testing.assert_allclose(chain.fk(Q, frame=2), [chain.fk(q, frame=2) for q in Q], atol=1e-12)


def test_subs_fixed_and_tool():
    length = sp.Symbol("l", positive=True)
    T = sp.Matrix([[1, 0, 0, length], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    chain = SerialChain([Rz("a"), Fixed(T), Rz("b"), Tx(length)], tool=T)
    assert chain.parameters == {length}
    a, b = chain.symbols()
    p = chain.fk([a, b])[:3, 3]
    assert sp.simplify(p[0] - length * (sp.cos(a) + 2 * sp.cos(a + b))) == 0
    num = chain.subs({length: 2})
    assert num.parameters == set()
    np.testing.assert_allclose(num.fk([0.0, 0.0])[:3, 3], [6.0, 0.0, 0.0])
    np.testing.assert_allclose(num.jacobian([0.3, 0.4]), num.lambdify_jacobian()(np.array([0.3, 0.4])), atol=1e-12)


def test_import_is_light():
    """The core imports neither sympy (lazily loaded) nor matplotlib/meshcat."""
    import subprocess
    import sys

    code = (
        "import sys, robokin.chains, robokin.models; "
        "m = robokin.models.ur10(); m.fk([0.0] * 6); m.jacobian([[0.0] * 6] * 2); "
        "print(sorted(x for x in ('sympy', 'matplotlib', 'meshcat') if x in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_engine_half_angle_cos_sin_accuracy():
    from robokin.chains._engine import _cos_sin

    th = np.concatenate([
        np.random.default_rng(11).uniform(-20, 20, 10_000),
        [0.0, -0.0, math.pi, -math.pi, math.pi / 2, -math.pi / 2, 2 * math.pi, 1e-300, 1e6],
    ])
    c, s = _cos_sin(th)
    np.testing.assert_allclose(c, np.cos(th), atol=1e-14, rtol=0)
    np.testing.assert_allclose(s, np.sin(th), atol=1e-14, rtol=0)
    assert c[-9] == 1.0 and s[-9] == 0.0


# ---------------------------------------------------------------- long chains: memory linear in n
def _long_chain_elements(n: int, seed: int = 0) -> list:
    rng = np.random.default_rng(seed)
    kinds = [Rx, Ry, Rz, Tx]
    out = []
    for i in range(n):
        out += [Tz(0.1 * rng.random()), kinds[i % 4](f"q{i}", offset=0.1 * i if i % 3 else 0.0), Ty(0.05)]
    return out


@pytest.mark.parametrize("n", [engine_module.DENSE_JOINTS + 1, 40])
def test_long_chain_blocks_equal_the_dense_product(n, monkeypatch):
    """Above DENSE_JOINTS joints the engine adds the stacked block parts instead of one product
    with an n² matrix: the same frames, pose and Jacobian as the dense form."""
    elements = _long_chain_elements(n)
    q = np.random.default_rng(n).uniform(-1.0, 1.0, n)
    stacked = SerialChain(elements)
    results = (stacked.fk(q), stacked.jacobian(q), stacked.frames(q), *stacked.fk_and_jacobian(q))
    monkeypatch.setattr(engine_module, "DENSE_JOINTS", 10 * n)
    dense = SerialChain(elements)
    expected = (dense.fk(q), dense.jacobian(q), dense.frames(q), *dense.fk_and_jacobian(q))
    for got, want in zip(results, expected):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_engine_of_a_3000_joint_chain_holds_no_quadratic_array():
    chain = SerialChain(_long_chain_elements(3000))
    q = np.zeros(3000)
    assert chain.fk(q).shape == (4, 4)
    engine = chain._engine  # the compiled chain (private: this tests its memory)
    biggest = max(value.nbytes for value in vars(engine).values() if isinstance(value, np.ndarray))
    assert biggest < 3 * 3001 * 49 * 8 + 1, f"an engine array of {biggest / 1e6:.0f} MB for 3,000 joints"


# ----------------------------------------------------------- the engine's workspaces
def _single_results(chain: SerialChain, q: np.ndarray) -> list[np.ndarray]:
    return [chain.fk(q), chain.jacobian(q), *chain.fk_and_jacobian(q), chain.frames(q),
            *(chain.fk(q, frame=k) for k in range(chain.n + 2)),
            chain.jacobian(q, frame=chain.n, point=[0.1, 0.2, 0.3])]


@pytest.mark.parametrize("n", [1, 2, 3, 7])
def test_single_results_are_never_the_workspace(mixed, n):
    """One configuration is evaluated in arrays the engine keeps (its workspace): what a call
    returns must not change when the next call writes there."""
    chain = mixed if n == 7 else SerialChain(_long_chain_elements(n))
    q1, q2 = chain.random_configurations(2, seed=n)
    first = _single_results(chain, q1)
    kept = [result.copy() for result in first]
    _single_results(chain, q2)
    for result, copy in zip(first, kept):
        assert np.array_equal(result, copy)


def test_threads_evaluate_one_chain_at_once(mixed):
    """Each thread has a workspace of its own: results computed at the same time in four
    threads are those of one thread alone."""
    from concurrent.futures import ThreadPoolExecutor

    Q = mixed.random_configurations(400, seed=3)

    def evaluate(rows):
        return [(mixed.fk(q), mixed.jacobian(q), *mixed.fk_and_jacobian(q)) for q in rows]

    expected = evaluate(Q)
    with ThreadPoolExecutor(max_workers=4) as pool:
        parts = list(pool.map(evaluate, np.array_split(Q, 4)))
    got = [item for part in parts for item in part]
    assert all(np.array_equal(a, b) for want, have in zip(expected, got) for a, b in zip(want, have))


def test_a_chain_pickles_and_copies_after_use(mixed):
    import copy
    import pickle

    q = mixed.random_configurations(1, seed=4)[0]
    before = _single_results(mixed, q)
    for other in (pickle.loads(pickle.dumps(mixed)), copy.deepcopy(mixed)):
        assert all(np.array_equal(a, b) for a, b in zip(before, _single_results(other, q)))


@pytest.mark.parametrize("revolute", [True, False])
def test_offsets_and_signs_are_folded_into_the_blocks(revolute):
    """A joint's variable sign * q + offset is folded into its constant matrices, so that one
    configuration needs cos q and sin q only: u(q) P' + w(q) Q' + R' equals u(θ) P + w(θ) Q + R,
    and a joint without offset and sign keeps P, Q, R exactly."""
    for axis in range(3):
        P, Q, R = engine_module.joint_pqr(axis, revolute)
        assert all(np.array_equal(a, b) for a, b in zip(engine_module.folded_pqr(axis, revolute, 1.0, 0.0),
                                                        (P, Q, R)))
        for sign, offset in [(-1.0, 0.0), (1.0, 0.7), (-1.0, -2.1)]:
            P2, Q2, R2 = engine_module.folded_pqr(axis, revolute, sign, offset)
            for q in (-1.3, 0.0, 0.4, 2.9):
                theta = sign * q + offset
                u, w = (math.cos(theta), math.sin(theta)) if revolute else (theta, 0.0)
                u2, w2 = (math.cos(q), math.sin(q)) if revolute else (q, 0.0)
                np.testing.assert_allclose(u2 * P2 + w2 * Q2 + R2, u * P + w * Q + R, rtol=0, atol=1e-15)
