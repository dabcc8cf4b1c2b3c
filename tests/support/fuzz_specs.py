"""The public functions covered by the robustness property suite, one :class:`Spec` each.

See ``fuzz_support`` for the argument generators and the oracle. ``batch``
specs are also called with batches of 0, 1 and 3 items and must keep the
documented shapes (an empty batch gives an empty result).
"""

from __future__ import annotations

import atexit
import importlib.metadata
import importlib.util
import math
import shutil
import tempfile
from functools import cache
from pathlib import Path
from typing import Any, NoReturn

import numpy as np
from support.fuzz_support import (
    NONFINITE,
    NONNUMERIC,
    Arg,
    Arr,
    Choice,
    Const,
    Ctx,
    Fn,
    Int,
    Limits,
    Num,
    Obj,
    Rot,
    Spec,
    Tf,
    _rodrigues,
    batch_shape,
)

import robokin.check as check
import robokin.models as models
import robokin.motion as motion
from robokin.models.baxter import baxter_left_urdf
from robokin.models.panda import panda_link_transforms
from robokin.models.ur_ik import UR10E_DH
import robokin.transforms as tr
from robokin.chains import Fixed, Rx, Ry, Rz, SerialChain, Tx, Ty, Tz, from_dh, from_link_table, from_modified_dh
from robokin.check import CheckResult
from robokin.motion import (
    CartesianController,
    ControlOutput,
    DampedLeastSquares,
    GradientObjective,
    IKBatchResult,
    IKResult,
    JacobianTranspose,
    JointLimitDistance,
    LevenbergMarquardt,
    Manipulability,
    NullSpace,
    PseudoInverse,
    SimulationLog,
    WeightedPseudoInverse,
    chain_with_tool,
    circle_trajectory,
    initial_condition_sweep,
    line_trajectory,
    pose_error,
    rigid_body_jacobian,
    simulate,
    solve_ik,
    solve_ik_batch,
    solve_ik_once,
    time_law,
    tool_jacobian,
    track_position_batch,
    via_point_trajectory,
)
from robokin.motion.sweeps import BatchTrackingLog
from robokin.parallel import ForwardKinematicsResult, Planar3RPR

B = batch_shape


# ------------------------------------------------------------------ shared objects
@cache
def chains() -> dict[str, SerialChain]:
    return {
        "planar": models.planar_two_link(),
        "ur10": models.ur10(),
        "leg": models.eth_leg(),
        "prismatic": SerialChain([Rz("q1"), Tz("d2", limits=(-1.0, 1.0)), Tx(0.5), Ry("q3")], name="RPR"),
    }


def pick_chain(ctx: Ctx, names: tuple[str, ...] = ("planar", "ur10", "leg", "prismatic")) -> None:
    ctx.extra["chain"] = chains()[names[int(ctx.rng.integers(len(names)))]]


@cache
def lambdified() -> tuple[Any, Any]:
    c = chains()["planar"]
    return c.lambdify_fk(), c.lambdify_jacobian()


class Q(Arr):
    """Joint configurations of ``ctx.chain``: (n,) or (N, n), within the limits."""

    def __init__(self, name: str = "q", batch: bool = True, **kw: Any) -> None:
        super().__init__(name, (0,), batch=batch, **kw)

    def shape(self, ctx: Ctx) -> tuple[int, ...]:
        n = ctx.chain.n
        return (n,) if (not self.batch or ctx.N is None) else (ctx.N, n)

    def valid(self, ctx: Ctx) -> Any:
        lim = np.clip(ctx.chain.limits, -3.0, 3.0)
        return lim[:, 0] + (lim[:, 1] - lim[:, 0]) * ctx.rng.random(self.shape(ctx))

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        if kind == "shape":
            shape = self.shape(ctx)
            return np.zeros(shape[:-1] + (shape[-1] + 1,))
        return super().corrupt(kind, ctx)


class Frame(Arg):
    """A frame index or name of ``ctx.chain``."""

    def __init__(self) -> None:
        super().__init__("frame", extreme=False, bad=("unknown", "index", "float", "object"))

    def valid(self, ctx: Ctx) -> Any:
        n = ctx.chain.n
        options: list[Any] = [None, -1, 0, n + 1, int(ctx.rng.integers(0, n + 2)), ctx.chain.frame_names[-1]]
        return options[int(ctx.rng.integers(len(options)))]

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        return {"unknown": "nonsense", "index": ctx.chain.n + 5, "float": 1.5, "object": object()}[kind]


class Strings(Arg):
    """A list of strings of a given length (names)."""

    def __init__(self, name: str, length: Any, **kw: Any) -> None:
        super().__init__(name, extreme=False, bad=("short", "int", "none_entry"), **kw)
        self.length = length

    def valid(self, ctx: Ctx) -> Any:
        return [f"f{i}" for i in range(self.length(ctx))]

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        return {"short": ["a"], "int": 3, "none_entry": [None] * self.length(ctx)}[kind]


def rot_check(result: Any, ctx: Ctx, values: dict) -> None:
    R = np.asarray(result)
    assert np.allclose(R @ np.swapaxes(R, -1, -2), np.eye(3), atol=1e-6), "not a rotation"


def skews(ctx: Ctx, shape: tuple[int, ...]) -> np.ndarray:
    v = ctx.rng.uniform(-2, 2, shape[:-2] + (3,))
    S = np.zeros(shape)
    S[..., 0, 1], S[..., 0, 2], S[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    return S - np.swapaxes(S, -1, -2)


class Skew(Arr):
    def __init__(self) -> None:
        super().__init__("S", (3, 3), extra_bad={"nonskew": lambda ctx: np.ones(self.shape(ctx)[:-2] + (3, 3))
                                                 if ctx.N != 0 else np.ones((3, 3))})

    def valid(self, ctx: Ctx) -> Any:
        return skews(ctx, self.shape(ctx))


def zero_vector(length: int) -> Any:
    return lambda ctx: np.zeros(length)


# ------------------------------------------------------------------ transforms
def transform_specs() -> list[Spec]:
    angle = lambda name="angle": Arr(name, (), shape_bad=False)  # noqa: E731  (any shape S)
    S: list[Spec] = []
    for f in (tr.rotx, tr.roty, tr.rotz):
        S.append(Spec(f"transforms.{f.__name__}", f, [angle()], shape=lambda c, v: B(c, 3, 3), batch=True,
                      check=rot_check))
    S += [
        Spec("transforms.skew", tr.skew, [Arr("v", (3,))], shape=lambda c, v: B(c, 3, 3), batch=True),
        Spec("transforms.unskew", tr.unskew, [Skew()], shape=lambda c, v: B(c, 3), batch=True),
        Spec("transforms.transform", tr.transform, [Rot("R"), Arr("p", (3,))], shape=lambda c, v: B(c, 4, 4),
             batch=True),
        Spec("transforms.translation", tr.translation, [Arr("p", (3,))], shape=lambda c, v: B(c, 4, 4),
             batch=True),
        Spec("transforms.transform_inverse", tr.transform_inverse, [Tf("T")], shape=lambda c, v: B(c, 4, 4),
             batch=True),
        Spec("transforms.compose", tr.compose, [Tf("T1", labels=("Ts[0]",)), Tf("T2", labels=("Ts[1]",))],
             shape=lambda c, v: B(c, 4, 4), batch=True),
        Spec("transforms.rotation_of", tr.rotation_of, [Tf("T")], shape=lambda c, v: B(c, 3, 3), batch=True),
        Spec("transforms.translation_of", tr.translation_of, [Tf("T")], shape=lambda c, v: B(c, 3), batch=True),
        Spec("transforms.transform_point", tr.transform_point, [Tf("T"), Arr("p", (3,))],
             shape=lambda c, v: B(c, 3), batch=True),
        Spec("transforms.rotation_from_rpy", tr.rotation_from_rpy, [Arr("rpy", (3,), lo=-4, hi=4)],
             shape=lambda c, v: B(c, 3, 3), batch=True, check=rot_check),
        Spec("transforms.rotation_from_rpy(roll, pitch, yaw)", tr.rotation_from_rpy,
             [angle("roll"), angle("pitch"), angle("yaw")], shape=lambda c, v: B(c, 3, 3), batch=True,
             check=rot_check, covers=()),
        Spec("transforms.rpy_from_rotation", tr.rpy_from_rotation, [Rot("R")], shape=lambda c, v: B(c, 3),
             batch=True),
        Spec("transforms.rotation_from_zyz", tr.rotation_from_zyz, [Arr("zyz", (3,), lo=-4, hi=4)],
             shape=lambda c, v: B(c, 3, 3), batch=True, check=rot_check),
        Spec("transforms.zyz_from_rotation", tr.zyz_from_rotation, [Rot("R")], shape=lambda c, v: B(c, 3),
             batch=True),
        Spec("transforms.rotation_exp", tr.rotation_exp, [Arr("w", (3,), lo=-4, hi=4)],
             shape=lambda c, v: B(c, 3, 3), batch=True, check=rot_check),
        Spec("transforms.rotation_log", tr.rotation_log, [Rot("R")], shape=lambda c, v: B(c, 3), batch=True),
        Spec("transforms.rotation_from_angle_axis", tr.rotation_from_angle_axis,
             [Arr("axis", (3,), extra_bad={"zero": zero_vector(3)}), Arr("angle", (), shape_bad=False)],
             shape=lambda c, v: B(c, 3, 3), batch=True, check=rot_check),
        Spec("transforms.angle_axis_from_rotation", tr.angle_axis_from_rotation, [Rot("R")],
             shape=lambda c, v: (B(c, 3), B(c)), batch=True),
        Spec("transforms.quaternion_from_rotation", tr.quaternion_from_rotation, [Rot("R")],
             shape=lambda c, v: B(c, 4), batch=True),
        Spec("transforms.rotation_from_quaternion", tr.rotation_from_quaternion,
             [Arr("q", (4,), extra_bad={"zero": zero_vector(4)})], shape=lambda c, v: B(c, 3, 3), batch=True,
             check=rot_check),
        Spec("transforms.quaternion_multiply", tr.quaternion_multiply, [Arr("p", (4,)), Arr("q", (4,))],
             shape=lambda c, v: B(c, 4), batch=True),
        Spec("transforms.quaternion_conjugate", tr.quaternion_conjugate, [Arr("q", (4,))],
             shape=lambda c, v: B(c, 4), batch=True),
        Spec("transforms.quaternion_slerp", tr.quaternion_slerp,
             [Arr("q0", (4,), batch=False, extra_bad={"zero": zero_vector(4)}),
              Arr("q1", (4,), batch=False, extra_bad={"zero": zero_vector(4)}),
              Arr("s", (), shape_bad=False, lo=-0.5, hi=1.5)],
             shape=lambda c, v: B(c, 4), batch=True),
        Spec("transforms.transform_exp", tr.transform_exp, [Arr("V", (6,), lo=-4, hi=4)],
             shape=lambda c, v: B(c, 4, 4), batch=True),
        Spec("transforms.transform_log", tr.transform_log, [Tf("T")], shape=lambda c, v: B(c, 6), batch=True),
        Spec("transforms.adjoint", tr.adjoint, [Tf("T")], shape=lambda c, v: B(c, 6, 6), batch=True),
    ]
    return S


# ------------------------------------------------------------------ chains
def _method(name: str):
    return lambda *a, **k: getattr(a[0], name)(*a[1:], **k)


def chain_method_specs() -> list[Spec]:
    def self_arg() -> Const:
        return Const("self", lambda ctx: ctx.chain)

    n = lambda c: c.chain.n  # noqa: E731
    S = [
        Spec("SerialChain.fk", _method("fk"), [self_arg(), Q()], {"frame": Frame()},
             shape=lambda c, v: B(c, 4, 4), batch=True, setup=pick_chain),
        Spec("SerialChain.frame_pose", _method("frame_pose"), [self_arg(), Q(), Frame()],
             shape=lambda c, v: B(c, 4, 4), batch=True, setup=pick_chain),
        Spec("SerialChain.frames", _method("frames"), [self_arg(), Q()],
             shape=lambda c, v: B(c, n(c) + 2, 4, 4), batch=True, setup=pick_chain),
        Spec("SerialChain.jacobian", _method("jacobian"), [self_arg(), Q()],
             {"frame": Frame(), "point": Arr("point", (3,), batch=False, optional=True)},
             shape=lambda c, v: B(c, 6, n(c)), batch=True, setup=pick_chain),
        Spec("SerialChain.fk_and_jacobian", _method("fk_and_jacobian"), [self_arg(), Q()],
             shape=lambda c, v: (B(c, 4, 4), B(c, 6, n(c))), batch=True, setup=pick_chain),
        Spec("SerialChain.position_jacobian", _method("position_jacobian"), [self_arg(), Q()],
             {"point": Arr("point", (3,), batch=False, optional=True)}, shape=lambda c, v: B(c, 3, n(c)), batch=True,
             setup=pick_chain),
        Spec("SerialChain.singular_values", _method("singular_values"), [self_arg(), Q()],
             {"position_only": Choice("position_only", [True, False], bad=())},
             shape=lambda c, v: B(c, min(3 if v["position_only"] else 6, n(c))), batch=True, setup=pick_chain),
        Spec("SerialChain.manipulability", _method("manipulability"), [self_arg(), Q()],
             {"position_only": Choice("position_only", [True, False], bad=())},
             shape=lambda c, v: B(c), batch=True, setup=pick_chain),
        Spec("SerialChain.screw_axes", _method("screw_axes"), [self_arg()],
             shape=lambda c, v: ((4, 4), (n(c), 6)), setup=pick_chain),
        Spec("SerialChain.space_jacobian", _method("space_jacobian"), [self_arg(), Q()],
             shape=lambda c, v: B(c, 6, n(c)), batch=True, setup=pick_chain),
        Spec("SerialChain.body_jacobian", _method("body_jacobian"), [self_arg(), Q()],
             shape=lambda c, v: B(c, 6, n(c)), batch=True, setup=pick_chain),
        Spec("SerialChain.velocity_ellipsoid", _method("velocity_ellipsoid"), [self_arg(), Q()],
             {"part": Choice("part", ["position", "orientation"])},
             shape=lambda c, v: (B(c, 3), B(c, 3, 3)), batch=True, setup=pick_chain),
        Spec("SerialChain.force_ellipsoid", _method("force_ellipsoid"), [self_arg(), Q()],
             {"part": Choice("part", ["position", "orientation"])},
             shape=lambda c, v: (B(c, 3), B(c, 3, 3)), batch=True, setup=pick_chain, finite=False),
        Spec("SerialChain.static_torques", _method("static_torques"), [self_arg(), Q(), Arr("wrench", (6,))],
             shape=lambda c, v: B(c, n(c)), batch=True, setup=pick_chain),
        Spec("SerialChain.condition_number", _method("condition_number"), [self_arg(), Q()],
             shape=lambda c, v: B(c), batch=True, setup=pick_chain, finite=False),
        Spec("SerialChain.random_configurations", _method("random_configurations"),
             [self_arg(), Int("N", 0, 5, minimum=0, huge=10**15)],
             {"seed": Int("seed", 0, 10, bad=("str", "float", "object"))},
             shape=lambda c, v: (v[1], n(c)), setup=pick_chain),
        Spec("SerialChain.within_limits", _method("within_limits"), [self_arg(), Q()],
             {"tol": Num("tol", 0.0, 0.1, positive=True, allow_zero=True)}, shape=lambda c, v: B(c),
             batch=True, setup=pick_chain),
        Spec("SerialChain.lambdify_fk", _method("lambdify_fk"), [Const("self", lambda c: chains()["planar"])],
             {"frame": Frame()}, setup=lambda c: c.extra.update(chain=chains()["planar"]), weight=0.2),
        Spec("SerialChain.lambdify_jacobian", _method("lambdify_jacobian"),
             [Const("self", lambda c: chains()["planar"])], {"frame": Frame()},
             setup=lambda c: c.extra.update(chain=chains()["planar"]), weight=0.2),
        Spec("SerialChain.lambdify_fk(...)(q)", lambda q: lambdified()[0](q), [Q()],
             shape=lambda c, v: B(c, 4, 4), batch=True, setup=lambda c: c.extra.update(chain=chains()["planar"]),
             covers=()),
        Spec("SerialChain.lambdify_jacobian(...)(q)", lambda q: lambdified()[1](q), [Q()],
             shape=lambda c, v: B(c, 6, 2), batch=True,
             setup=lambda c: c.extra.update(chain=chains()["planar"]), covers=()),
        Spec("SerialChain.symbols", _method("symbols"), [self_arg()], setup=pick_chain, weight=0.1),
        Spec("SerialChain.subs", _method("subs"), [Const("self", lambda c: _symbolic_planar()),
                                                   Obj("values", lambda c: {"l1": float(c.rng.uniform(0.5, 2))},
                                                       bad=("none", "str", "int", "list"),
                                                       extra_bad={"nan": lambda c: {"l1": math.nan},
                                                                  "text": lambda c: {"l1": "abc"}})],
             check=lambda r, c, v: np.testing.assert_allclose(r.fk([0.0, 0.0])[0, 3], v[1]["l1"] + 1.0),
             weight=0.3),
    ]
    return S


@cache
def _symbolic_planar() -> SerialChain:
    import sympy as sp

    return models.planar_two_link(sp.Symbol("l1"), 1.0)


def _elements(ctx: Ctx) -> list:
    return [Rz("q1"), Tx(0.5), Ry("q2"), Tz(0.3)]


def construction_specs() -> list[Spec]:
    S = [
        Spec("SerialChain", SerialChain, [Obj("elements", _elements, extra_bad={"number": lambda c: [Rz("q1"), 3.0],
                                                                               "empty": lambda c: [Tx(1.0)]})],
             {"limits": Limits("limits", 2, optional=True), "tool": Tf("tool", batch=False, optional=True),
              "base": Tf("base", batch=False, optional=True),
              "frame_names": Strings("frame_names", lambda c: 4, optional=True)}, weight=0.5),
        Spec("chains.Fixed", Fixed, [Tf("T", batch=False)]),
        Spec("chains.from_dh", from_dh, [Arr("table", (3, 4), batch=False, extra_bad={
            "type": lambda c: [[0.1, 0.0, 0.2, 0.0, "X"]] * 3})],
             {"limits": Limits("limits", 3, optional=True), "tool": Tf("tool", batch=False, optional=True),
              "joint_names": Strings("joint_names", lambda c: 3, optional=True)}, weight=0.5,
             check=lambda r, c, v: isinstance(r, SerialChain) and r.n == 3 or _fail(r)),
        Spec("chains.from_modified_dh", from_modified_dh, [Arr("table", (3, 4), batch=False)],
             {"base": Tf("base", batch=False, optional=True)}, weight=0.5),
        Spec("chains.from_link_table", from_link_table,
             [Obj("transforms", lambda c: [_tf(c), _tf(c)], extra_bad={
                 "nonortho": lambda c: [_tf(c) * 1.5, _tf(c)], "nan": lambda c: [np.full((4, 4), np.nan), _tf(c)],
                 "shape": lambda c: [np.eye(3), np.eye(4)], "strings": lambda c: [["a"] * 4] * 4}),
              Obj("joint_types", lambda c: ["R", "P"], extra_bad={"unknown": lambda c: ["R", "X"]})],
             weight=0.5),
    ]
    for E in (Tx, Ty, Tz, Rx, Ry, Rz):
        # a string value names a joint: not a corruption here
        S.append(Spec(f"chains.{E.__name__}", E, [Arr("value", (), batch=False, bad=NONFINITE + (
            "none", "strlist", "object", "complex", "shape"))]))
        S.append(Spec(f"chains.{E.__name__} (joint)", E, [Const("value", "q1")],
                      {"offset": Num("offset", -1.0, 1.0),
                       "limits": _Pair("limits", optional=True, extra_bad={"reversed": lambda c: (1.0, -1.0)})},
                      covers=()))
    return S


class _Pair(Arr):
    """A (lower, upper) pair."""

    def __init__(self, name: str, **kw: Any) -> None:
        kw.setdefault("bad", NONNUMERIC + ("nan", "complex", "shape", "ragged"))  # inf: an open end, valid
        super().__init__(name, (2,), batch=False, **kw)

    def valid(self, ctx: Ctx) -> Any:
        return np.sort(super().valid(ctx))

    def extreme(self, ctx: Ctx) -> Any:
        return np.sort(super().extreme(ctx))


def _tf(ctx: Ctx) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = _rodrigues(ctx.rng.uniform(-2, 2, 3))
    T[:3, 3] = ctx.rng.uniform(-1, 1, 3)
    return T


# ------------------------------------------------------------------ URDF
_TOY_URDF = """<robot name="toy">
  <link name="world"/><link name="base"/><link name="l1"/><link name="l2"/><link name="tool"/>
  <joint name="mount" type="fixed"><parent link="world"/><child link="base"/>
    <origin xyz="0.1 0 0.2" rpy="0 0 0.5"/></joint>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2"/></joint>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0" rpy="0 1.2 0"/>
    <axis xyz="0 1 1"/><limit lower="0" upper="0.5"/></joint>
  <joint name="flange" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0 0 0.05"/></joint>
</robot>
"""


@cache
def toy_urdf() -> str:
    """A small URDF file (fixed, revolute, prismatic joints), written once per session."""
    folder = tempfile.mkdtemp(prefix="robokin-fuzz-urdf-")
    atexit.register(shutil.rmtree, folder, True)
    path = Path(folder) / "toy.urdf"
    path.write_text(_TOY_URDF)
    return str(path)


class _UrdfFile(Arg):
    """The path of :func:`toy_urdf`; corrupted: a missing file, None, an int, an object."""

    def __init__(self, name: str) -> None:
        super().__init__(name, extreme=False)

    def valid(self, ctx: Ctx) -> Any:
        return toy_urdf() if ctx.rng.random() < 0.5 else Path(toy_urdf())

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return ("missing", "none", "int", "object")

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        return {"missing": toy_urdf() + ".gone", "none": None, "int": 3, "object": object()}[kind]


def _optional(fn: Any, module: str | None = None, distribution: str | None = None) -> Any:
    """``fn``, skipping the test when its optional dependency is not installed (CI installs it)."""
    import pytest

    def call(*args: Any, **kwargs: Any) -> Any:
        if module is not None and importlib.util.find_spec(module) is None:
            pytest.skip(f"{module} is not installed: pip install 'robokin[robots]'")
        if distribution is not None:
            try:
                importlib.metadata.distribution(distribution)
            except importlib.metadata.PackageNotFoundError:
                pytest.skip(f"{distribution} is not installed: pip install 'robokin[robots]'")
        return fn(*args, **kwargs)

    return call


def urdf_specs() -> list[Spec]:
    is_chain = lambda r, c, v: isinstance(r, SerialChain) and r.n == 2 or _fail(r)  # noqa: E731
    is_file = lambda r, c, v: Path(r).is_file() or _fail(r)  # noqa: E731
    is_meshes = lambda r, c, v: len(r.frames) == 4 and r.triangles == 0 or _fail(r)  # noqa: E731 (no visuals)
    return [
        Spec("models.from_urdf", _optional(models.from_urdf, module="yourdfpy"),
             [_UrdfFile("path"), Choice("base_link", ["world", "base"]), Choice("tip_link", ["l2", "tool"])],
             {"name": Choice("name", ["arm", None], bad=("int", "object"))}, check=is_chain, weight=0.3),
        Spec("models.robot_description", _optional(models.robot_description, distribution="example-robot-data"),
             [Choice("name", ["ur10", "baxter", "panda", "kinova", "xarm7"])], check=is_file, weight=0.2),
        Spec("models.available_robots", _optional(models.available_robots, distribution="example-robot-data"),
             [], check=lambda r, c, v: None if len(r) > 0 else (_ for _ in ()).throw(AssertionError(r)),
             weight=0.05),
        Spec("models.visual_meshes", _optional(_optional(models.visual_meshes, module="trimesh"),
                                               module="fast_simplification"),
             [_UrdfFile("path"), Choice("base_link", ["world", "base"]), Choice("tip_link", ["l2", "tool"])],
             {"max_bytes": Int("max_bytes", 1_000, 200_000, minimum=1)}, check=is_meshes, weight=0.2),
    ]


# ------------------------------------------------------------------ models
def length(name: str) -> Num:
    return Num(name, 0.2, 1.5, positive=True)


def model_specs() -> list[Spec]:
    is_chain = lambda r, c, v: isinstance(r, SerialChain) or _fail(r)  # noqa: E731
    S = [
        Spec("models.planar_two_link", models.planar_two_link, [length("l1"), length("l2")], check=is_chain),
        Spec("models.eth_leg", models.eth_leg, [Num("l_b", -1.0, 1.0), length("l_1"), length("l_2"), length("l_3")],
             {"limits": Limits("limits", 3, optional=True)}, check=is_chain),
        Spec("models.ur10", models.ur10, [Choice("description", ["dh", "mdh", "ets"])], weight=0.3),
        Spec("models.baxter_left", models.baxter_left, [Choice("base", ["torso", "shoulder"]),
                                                        Choice("end", ["hand", "gripper"])], weight=0.3),
        Spec("models.baxter.baxter_left_urdf", baxter_left_urdf, [Choice("end", ["hand", "gripper"])],
             weight=0.3),
        Spec("models.ar601_leg", models.ar601_leg, [length("l1"), length("l2"), length("l3")], check=is_chain),
        Spec("models.panda", models.panda, [Choice("description", ["link_table", "mdh", "urdf"])], weight=0.3),
        Spec("models.panda.panda_link_transforms", panda_link_transforms, [], weight=0.05),
        Spec("models.genova_arm", models.genova_arm, [], {"limits": Limits("limits", 7, optional=True)},
             weight=0.3),
        Spec("models.three_rpr", models.three_rpr, [length("platform_side"),
                                                     _Pair("stroke", lo=0.0, hi=3.0, sign=1,
                                                           extra_bad={"reversed": lambda c: (2.0, 1.0)})],
             weight=0.5),
        Spec("models.three_rpr_classic", models.three_rpr_classic,
             [_Pair("stroke", lo=0.0, hi=3.0, sign=1, extra_bad={"reversed": lambda c: (2.0, 1.0)})],
             weight=0.5),
        Spec("models.ar601_leg_ik", models.ar601_leg_ik, [Tf("T_target", batch=False, scale=0.3)],
             {"l1": length("l1"), "within_limits": Choice("within_limits", [True, False], bad=()),
              "tol": Num("tol", 1e-10, 1e-8, positive=True)},
             check=lambda r, c, v: np.testing.assert_equal(r.q.shape[1:], (6,))),
        Spec("models.ar601_leg_ik_batch", models.ar601_leg_ik_batch, [Tf("T_targets", scale=0.3)],
             {"l2": length("l2")}, batch=True,
             check=lambda r, c, v: np.testing.assert_equal(len(r), 1 if c.N is None else c.N)),
        Spec("models.ur10_ik", models.ur10_ik, [Tf("T_target", batch=False, scale=1.3)],
             {"dh": _ur_table(), "within_limits": Choice("within_limits", [True, False], bad=()),
              "tol": Num("tol", 1e-10, 1e-8, positive=True)},
             check=lambda r, c, v: np.testing.assert_equal(r.q.shape[1:], (6,))),
        Spec("models.ur10_ik_batch", models.ur10_ik_batch, [Tf("T_targets", scale=1.3)],
             {"dh": _ur_table()}, batch=True, finite=False, check=_ur_batch_check),
    ]
    return S


def _ur_table() -> Choice:
    """The ``dh`` of the UR inverse kinematics: a name or a table; bad: a wrong shape or not a UR table."""
    twisted = [list(row) for row in UR10E_DH]
    twisted[4][3] = math.pi / 2
    return Choice("dh", ["ur10", "ur5", "ur3e", "ur16e", UR10E_DH, None],
                  extra_bad={"not_ur": lambda c: twisted, "rows": lambda c: UR10E_DH[:5]})


def _ur_batch_check(r: Any, ctx: Ctx, values: dict) -> None:
    """N results of eight slots; the valid slots finite, the others NaN."""
    n = 1 if ctx.N is None else ctx.N
    np.testing.assert_equal((len(r), r.q.shape, r.valid.shape), (n, (n, 8, 6), (n, 8)))
    assert np.all(np.isfinite(r.q[r.valid])) and np.all(np.isnan(r.q[~r.valid]))


# ------------------------------------------------------------------ motion
def _controller(ctx: Ctx) -> CartesianController:
    chain = ctx.chain
    return CartesianController(chain, chain.fk(np.zeros(chain.n))[:3, 3] + 0.05, position_gain=1.0)


def pick_small(ctx: Ctx) -> None:
    pick_chain(ctx, ("planar", "ur10", "prismatic"))


def _goal(ctx: Ctx) -> Any:
    T = ctx.chain.fk(Q().valid(ctx))
    return T if ctx.rng.random() < 0.5 else T[:3, 3]


class Goal(Arg):
    """A goal for the controller: a pose (4, 4) or a position (3,) near the chain's workspace."""

    def __init__(self) -> None:
        super().__init__("goal", extreme=False)

    def valid(self, ctx: Ctx) -> Any:
        return _goal(ctx)

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return NONNUMERIC + NONFINITE + ("shape", "nonortho", "fn_nan", "fn_shape")

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        if kind == "shape":
            return np.zeros(5)
        if kind == "nonortho":
            return np.eye(4) * 1.5
        if kind == "fn_nan":
            return lambda t: np.full(3, np.nan)
        if kind == "fn_shape":
            return lambda t: np.zeros(5)
        return super().corrupt(kind, ctx)


def motion_specs() -> list[Spec]:
    ctrl_self = Const("self", _controller)
    S = [
        Spec("motion.pose_error", pose_error, [Tf("T_current"), Tf("T_goal"),
                                               Choice("representation", ["angle_axis", "quaternion", "rpy"])],
             shape=lambda c, v: B(c, 6), batch=True),
        Spec("CartesianController", CartesianController, [Obj("chain", lambda c: c.chain), Goal()],
             {"position_gain": Num("position_gain", 0.0, 5.0, positive=True, allow_zero=True),
              "orientation_gain": Num("orientation_gain", 0.0, 5.0, positive=True, allow_zero=True),
              "inverse": Choice("inverse", ["pinv", "dls"]),
              "damping": Num("damping", 0.0, 0.1, positive=True, allow_zero=True),
              "singular_threshold": Num("singular_threshold", 0.0, 0.1, positive=True, allow_zero=True),
              "tool": Tf("tool", batch=False, optional=True)}, setup=pick_small),
        Spec("CartesianController.__call__", lambda s, t, q: s(t, q), [ctrl_self, Num("t", 0.0, 2.0), Q(batch=False)],
             check=lambda r, c, v: (isinstance(r, ControlOutput) and r.qdot.shape == (c.chain.n,)
                                    and r.twist.shape == (6,) and r.error.shape == (6,)) or _fail(r),
             setup=pick_small),
        Spec("CartesianController.error", _method("error"), [ctrl_self, Q(batch=False), Num("t", 0.0, 2.0)],
             shape=lambda c, v: (6,), setup=pick_small),
        Spec("CartesianController.goal", _method("goal"), [ctrl_self, Num("t", 0.0, 2.0)], setup=pick_small),
        Spec("CartesianController.pose", _method("pose"), [ctrl_self, Q(batch=False)], shape=lambda c, v: (4, 4),
             setup=pick_small),
        Spec("CartesianController.jacobian", _method("jacobian"), [ctrl_self, Q(batch=False)],
             shape=lambda c, v: (6, c.chain.n), setup=pick_small),
        Spec("motion.simulate", simulate, [Obj("chain", lambda c: c.chain), Obj("controller", _controller,
                                                                                 bad=("none", "str", "int")),
                                           Const("q0", lambda c: np.zeros(c.chain.n)),
                                           Num("ts", 0.01, 0.1, positive=True), Num("t_end", 0.05, 0.3, positive=True)],
             {"qdot_limits": Num("qdot_limits", 0.5, 5.0, positive=True, optional=True),
              "singular_threshold": Num("singular_threshold", 0.0, 0.1, positive=True, allow_zero=True,
                                        optional=True)},
             setup=pick_small, finite=False, check=lambda r, c, v: _log_ok(r, c), weight=0.5),
        Spec("motion.simulate (q0)", simulate, [Obj("chain", lambda c: c.chain), Const("controller", _controller),
                                                Q("q0", batch=False), Const("ts", 0.05), Const("t_end", 0.1)],
             {"tol": _tol(optional=True)}, setup=pick_small, finite=False,
             check=lambda r, c, v: _log_ok(r, c), weight=0.5, covers=()),
        Spec("motion.circle_trajectory", circle_trajectory,
             [Arr("t", (), shape_bad=False), Arr("centre", (3,), batch=False), Num("radius", 0.1, 1.0, positive=True)],
             {"normal": Arr("normal", (3,), batch=False, extra_bad={"zero": zero_vector(3)}),
              "angular_speed": Num("angular_speed", -3, 3), "phase": Num("phase", -3, 3)},
             shape=lambda c, v: (B(c, 3),) * 3, batch=True),
        Spec("motion.circle_trajectory (axes)", lambda t, axes: circle_trajectory(t, [0, 0, 0], 0.5, axes=axes),
             [Arr("t", (), shape_bad=False), Arr("axes", (2, 3), batch=False, extra_bad={
                 "parallel": lambda c: [[1, 0, 0], [2, 0, 0]]})],
             shape=lambda c, v: (B(c, 3),) * 3, batch=True, covers=()),
        Spec("motion.line_trajectory", line_trajectory,
             [Arr("t", (), shape_bad=False), Arr("start", (3,), batch=False), Arr("end", (3,), batch=False),
              Num("duration", 0.1, 3.0, positive=True)],
             {"t_start": Num("t_start", -1, 1), "law": Choice("law", ["quintic", "cubic", "linear"])},
             shape=lambda c, v: (B(c, 3),) * 3, batch=True),
        Spec("motion.via_point_trajectory", via_point_trajectory,
             [Arr("t", (), shape_bad=False), Arr("points", (3, 3), batch=False),
              Const("times", [0.0, 1.0, 2.5])],
             {"velocities": Arr("velocities", (3, 3), batch=False, optional=True)},
             shape=lambda c, v: (B(c, 3),) * 3, batch=True),
        Spec("motion.via_point_trajectory (times)", via_point_trajectory,
             [Arr("t", (), shape_bad=False), Const("points", np.eye(3)),
              _Times()],
             shape=None, batch=True, covers=()),
        Spec("motion.time_law", time_law, [Arr("tau", (), shape_bad=False, lo=-0.5, hi=1.5),
                                           Choice("kind", ["quintic", "cubic", "linear"])],
             shape=lambda c, v: (B(c),) * 3, batch=True),
        Spec("motion.joint_trajectory", motion.joint_trajectory,
             [Arr("t", (), shape_bad=False), Arr("q_start", (4,), batch=False), Arr("q_end", (4,), batch=False)],
             {"v_max": Num("v_max", 0.1, 3.0, positive=True), "a_max": Num("a_max", 0.1, 3.0, positive=True),
              "law": Choice("law", ["trapezoidal", "quintic", "cubic"])},
             shape=lambda c, v: (B(c, 4),) * 3, batch=True),
        Spec("motion.joint_trajectory_duration", motion.joint_trajectory_duration,
             [Arr("q_start", (4,), batch=False), Arr("q_end", (4,), batch=False)],
             {"v_max": Num("v_max", 0.1, 3.0, positive=True), "a_max": Num("a_max", 0.1, 3.0, positive=True),
              "law": Choice("law", ["trapezoidal", "quintic", "cubic"])}, shape=lambda c, v: ()),
        Spec("motion.pose_trajectory", motion.pose_trajectory,
             [Arr("t", (), shape_bad=False), Tf("T_start", batch=False), Tf("T_end", batch=False),
              Num("duration", 0.1, 3.0, positive=True)],
             {"law": Choice("law", ["quintic", "cubic", "linear"])},
             shape=lambda c, v: (B(c, 4, 4), B(c, 6), B(c, 6)), batch=True),
        Spec("motion.chain_with_tool", chain_with_tool, [Obj("chain", lambda c: c.chain), Tf("T_et", batch=False)],
             setup=pick_small, check=lambda r, c, v: isinstance(r, SerialChain) or _fail(r)),
        Spec("motion.rigid_body_jacobian", rigid_body_jacobian, [Arr("r", (3,))], shape=lambda c, v: B(c, 6, 6),
             batch=True),
        Spec("motion.tool_jacobian", tool_jacobian, [Arr("J_ee", (6, 4), bad=NONNUMERIC + NONFINITE + ("complex",),
                                                         extra_bad={"rows": lambda c: np.zeros((5, 4))}),
                                                     Rot("R_be"), Arr("p_et", (3,), batch=False)],
             shape=lambda c, v: B(c, 6, 4), batch=True),
        Spec("transforms.transform_from_rpy", tr.transform_from_rpy, [Arr("rpy", (3,)), Arr("position", (3,))],
             shape=lambda c, v: B(c, 4, 4), batch=True),
        Spec("motion.initial_condition_sweep", initial_condition_sweep,
             [Limits("limits", 3, extra_bad={"reversed": lambda c: [[1.0, -1.0]] * 3,
                                             "infinite": lambda c: [[-np.inf, 1.0]] * 3}),
              Arr("fractions", (4,), batch=False, lo=0.0, hi=1.0, bad=NONNUMERIC + NONFINITE + ("complex",),
                  extra_bad={"outside": lambda c: [0.5, 1.5], "matrix": lambda c: [[0.5]], "empty": lambda c: []}),
              Num("nominal", 0.0, 1.0, extra_bad={"outside": lambda c: 1.5})],
             shape=lambda c, v: (12, 3)),
        Spec("motion.track_position_batch", track_position_batch,
             [Obj("chain", lambda c: c.chain), Q("q0"), Num("ts", 0.01, 0.05, positive=True),
              Arr("positions", (4, 3), batch=False, lo=-0.5, hi=0.5), Arr("velocities", (4, 3), batch=False)],
             {"gain": Num("gain", 0.0, 5.0, positive=True, allow_zero=True),
              "inverse": Choice("inverse", ["pinv", "dls"]),
              "damping": Num("damping", 0.0, 0.1, positive=True, allow_zero=True),
              "singular_threshold": Num("singular_threshold", 0.0, 0.1, positive=True, allow_zero=True)},
             setup=pick_small, batch=True, check=lambda r, c, v: _batch_log_ok(r, c), weight=0.5),
        Spec("motion.solve_ik", solve_ik, [Obj("chain", lambda c: c.chain), Arr("target", (3,), batch=False,
                                                                                 lo=-1.5, hi=1.5)],
             {"q0": Q("q0", batch=False, optional=True), "method": Choice("method", ["lm", "pinv", "dls"]),
              "tol": _tol(), "restarts": Int("restarts", 0, 2),
              "max_iterations": Int("max_iterations", 5, 30, minimum=1, optional=True)},
             setup=pick_small, check=lambda r, c, v: _ik_ok(r, c), weight=0.6),
        Spec("motion.solve_ik_once", solve_ik_once, [Obj("chain", lambda c: c.chain),
                                                     Arr("target", (3,), batch=False, lo=-1.5, hi=1.5)],
             {"q0": Q("q0", batch=False, optional=True), "method": Choice("method", ["lm", "pinv", "dls"]),
              "tol": _tol(), "max_iterations": Int("max_iterations", 5, 30, minimum=1, optional=True)},
             setup=pick_small, check=lambda r, c, v: _ik_ok(r, c), weight=0.4),
        Spec("motion.solve_ik (pose)", solve_ik, [Obj("chain", lambda c: c.chain), Tf("target", batch=False)],
             {"restarts": Const("restarts", 1), "tool": Tf("tool", batch=False, optional=True)},
             setup=pick_small, check=lambda r, c, v: _ik_ok(r, c), weight=0.4, covers=()),
        Spec("motion.solve_ik_batch", solve_ik_batch, [Obj("chain", lambda c: c.chain),
                                                       Arr("targets", (3,), lo=-1.5, hi=1.5)],
             {"restarts": Int("restarts", 0, 2), "method": Choice("method", ["lm", "pinv", "dls"]),
              "max_iterations": Int("max_iterations", 5, 30, minimum=1, optional=True)},
             setup=pick_small, batch=True, sizes=(1, 3, 0), check=lambda r, c, v: _ik_batch_ok(r, c), weight=0.6),
        Spec("motion.PseudoInverse", PseudoInverse, [Num("gain", positive=True), Num("rcond", 1e-10, 1e-6,
                                                                                       positive=True)]),
        Spec("motion.JacobianTranspose", JacobianTranspose, [Num("gain", positive=True, optional=True)]),
        Spec("motion.WeightedPseudoInverse", WeightedPseudoInverse,
             [Arr("weights", (3,), batch=False, lo=0.5, hi=2.0, sign=1, bad=NONNUMERIC + NONFINITE + ("complex",),
                  extra_bad={"negative": lambda c: [1, -1, 1], "nonsquare": lambda c: np.ones((2, 3)),
                             "asymmetric": lambda c: [[1.0, 0.5], [0.0, 1.0]]}),
              Num("gain", positive=True)]),
        Spec("motion.DampedLeastSquares", DampedLeastSquares,
             [Num("damping", 0.0, 0.1, positive=True, allow_zero=True),
              Choice("adaptive", [None, "manipulability", "singular_value", "error"])],
             {"threshold": Num("threshold", 0.01, 0.1, positive=True, optional=True),
              "gain": Num("gain", positive=True)}),
        Spec("motion.NullSpace", NullSpace, [Choice("objective", ["joint_limits", "manipulability"])],
             {"gain": Num("gain", positive=True, optional=True),
              "rcond": Num("rcond", 1e-10, 1e-6, positive=True)}),
        Spec("motion.LevenbergMarquardt", LevenbergMarquardt, [Num("bias", 1e-9, 1e-6, positive=True)],
             {"error_weights": Arr("error_weights", (6,), batch=False, lo=0.5, hi=2, sign=1, optional=True),
              "error_damping": Num("error_damping", 0.0, 0.5, positive=True, allow_zero=True)}),
        Spec("motion.Manipulability", Manipulability, [Num("h", 1e-8, 1e-5, positive=True)]),
        Spec("motion.JointLimitDistance", JointLimitDistance, [], weight=0.05),
        Spec("motion.GradientObjective", GradientObjective, [Fn("gradient", lambda c: (lambda q: -q))]),
    ]
    return S


def _tol(**kw: Any) -> Num:
    """A tolerance: one positive number, or a (position, orientation) pair -- so a 3-vector is bad."""
    return Num("tol", 1e-8, 1e-4, positive=True, bad=NONNUMERIC + NONFINITE + ("complex", "negative", "zero"),
               extra_bad={"three": lambda c: [1e-6] * 3, "matrix": lambda c: np.full((2, 2), 1e-6)}, **kw)


class _Times(Arr):
    """Strictly increasing via-point times."""

    def __init__(self) -> None:
        super().__init__("times", (3,), batch=False, extra_bad={"decreasing": lambda c: [0.0, 2.0, 1.0]})

    def valid(self, ctx: Ctx) -> Any:
        return np.cumsum(ctx.rng.uniform(0.1, 1.0, 3))

    def extreme(self, ctx: Ctx) -> Any:
        return np.sort(super().extreme(ctx))


def _fail(r: Any) -> NoReturn:
    raise AssertionError(f"unexpected result {r!r}")


def _log_ok(log: SimulationLog, ctx: Ctx) -> None:
    assert isinstance(log, SimulationLog)
    K, n = len(log), ctx.chain.n
    assert log.q.shape == (K, n) and log.qdot.shape == (K, n) and log.pose.shape == (K, 4, 4)
    assert np.all(np.isfinite(log.q)) and np.all(np.isfinite(log.pose))
    assert log.sigma_min.shape == (K,) and log.singular.shape == (K,) and log.singular.dtype == bool


def _batch_log_ok(log: BatchTrackingLog, ctx: Ctx) -> None:
    N = 1 if ctx.N is None else ctx.N
    assert log.q.shape == (N, 4, ctx.chain.n) and log.singular.shape == (N, 4)


def _ik_ok(r: IKResult, ctx: Ctx) -> None:
    assert isinstance(r, IKResult) and r.q.shape == (ctx.chain.n,)
    assert np.all(ctx.chain.within_limits(r.q, tol=1e-9))


def _ik_batch_ok(r: IKBatchResult, ctx: Ctx) -> None:
    N = 1 if ctx.N is None else ctx.N
    assert r.q.shape == (N, ctx.chain.n) and r.success.shape == (N,)


# ------------------------------------------------------------------ parallel
@cache
def robot_3rpr() -> Planar3RPR:
    return models.three_rpr()


def parallel_specs() -> list[Spec]:
    robot = Const("self", lambda c: robot_3rpr())
    pose = lambda: Arr("pose", (3,), lo=-0.5, hi=1.0)  # noqa: E731
    rho = lambda batch=True: Arr("rho", (3,), batch=batch, lo=0.5, hi=1.2, extra_bad={  # noqa: E731
        "negative": lambda c: [-1.0, 1.0, 1.0]})
    S = [
        Spec("Planar3RPR", Planar3RPR, [Arr("base_anchors", (3, 2), batch=False, extra_bad={
            "collinear": lambda c: [[0, 0], [1, 0], [2, 0]]}), Arr("platform_anchors", (3, 2), batch=False)],
             {"stroke": _Pair("stroke", lo=0.0, hi=3.0, sign=1, extra_bad={"reversed": lambda c: (2.0, 1.0)})}),
        Spec("Planar3RPR.platform_points", _method("platform_points"), [robot, pose()],
             shape=lambda c, v: B(c, 3, 2), batch=True),
        Spec("Planar3RPR.leg_vectors", _method("leg_vectors"), [robot, pose()], shape=lambda c, v: B(c, 3, 2),
             batch=True),
        Spec("Planar3RPR.leg_angles", _method("leg_angles"), [robot, pose()], shape=lambda c, v: B(c, 3),
             batch=True),
        Spec("Planar3RPR.inverse_kinematics", _method("inverse_kinematics"), [robot, pose()],
             shape=lambda c, v: B(c, 3), batch=True),
        Spec("Planar3RPR.within_stroke", _method("within_stroke"),
             [robot, Arr("rho", (3,), lo=0.5, hi=1.2)], shape=lambda c, v: B(c),
             batch=True),
        Spec("Planar3RPR.jacobian", _method("jacobian"), [robot, pose()], shape=lambda c, v: B(c, 3, 3),
             batch=True),
        Spec("Planar3RPR.direct_jacobian", _method("direct_jacobian"), [robot, Arr("pose", (3,), batch=False,
                                                                                   lo=0.1, hi=0.6)],
             shape=lambda c, v: (3, 3)),
        Spec("Planar3RPR.condition_number", _method("condition_number"), [robot, pose()],
             shape=lambda c, v: B(c), batch=True, finite=False),
        Spec("Planar3RPR.is_singular", _method("is_singular"), [robot, pose()],
             {"tol": Num("tol", 1e-10, 1e-6, positive=True)}, shape=lambda c, v: B(c), batch=True),
        Spec("Planar3RPR.orientation_harmonics", _method("orientation_harmonics"), [robot, rho(False)],
             shape=lambda c, v: (7,)),
        Spec("Planar3RPR.orientation_polynomial", _method("orientation_polynomial"), [robot, rho(False)],
             shape=lambda c, v: (7,)),
        Spec("Planar3RPR.forward_kinematics", _method("forward_kinematics"), [robot, rho(False)],
             {"tol": Num("tol", 1e-10, 1e-7, positive=True)},
             check=lambda r, c, v: isinstance(r, ForwardKinematicsResult) and r.poses.shape[1:] == (3,) or _fail(r)),
    ]
    return S


# ------------------------------------------------------------------ exercise checks
class Answer(Arg):
    """A student's answer: garbage of every kind must give a failed CheckResult."""

    def __init__(self, name: str = "answer") -> None:
        super().__init__(name, extreme=False, bad=(
            "none", "str", "strlist", "nan", "inf", "huge", "empty", "shape", "object", "raises",
            "returns_none", "returns_nan", "returns_str", "returns_huge", "complex", "dict"))

    def valid(self, ctx: Ctx) -> Any:
        return np.zeros((3, 3)) if ctx.rng.random() < 0.5 else (lambda *a: np.zeros(3))

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        def raises(*a: Any) -> Any:
            raise RuntimeError("student bug")

        return {
            "none": None, "str": "abc", "strlist": ["a", "b"], "nan": np.full((3, 3), np.nan),
            "inf": np.full((4, 4), np.inf), "huge": np.full((4, 4), 1e308), "empty": np.zeros((0, 3)),
            "shape": np.zeros((2, 5, 7)), "object": object(), "raises": raises,
            "returns_none": lambda *a: None, "returns_nan": lambda *a: np.full(6, np.nan),
            "returns_str": lambda *a: "x", "returns_huge": lambda *a: np.full((3, 3), 1.7e308),
            "complex": np.ones(3) + 1j, "dict": {"q": 1},
        }[kind]


class _Configuration(Answer):
    """A student's configuration for the UR10 (valid: any (6,) array)."""

    def valid(self, ctx: Ctx) -> Any:
        return ctx.rng.uniform(-2.0, 2.0, 6)


class _SolutionRows(Answer):
    """A student's set of AR-601 solutions (valid: any (k, 6) array)."""

    def valid(self, ctx: Ctx) -> Any:
        return ctx.rng.uniform(-2.0, 2.0, (int(ctx.rng.integers(1, 9)), 6))


def _is_result(r: Any, c: Ctx, v: dict) -> None:
    assert isinstance(r, CheckResult) and isinstance(r.message, str) and r.message, r


def _rows_of(*shapes: tuple[int, ...]) -> Any:
    """A check that the result is an array of one of ``shapes``."""
    def check(r: Any, c: Ctx, v: dict) -> None:
        assert isinstance(r, np.ndarray) and r.shape in shapes, (type(r), getattr(r, "shape", None))

    return check


def _poe_step_specs() -> list[Spec]:
    """robokin's steps of chapter 8 (the stand-ins the graded tests pass to the student's functions)."""
    steps = check.product_of_exponentials

    def angles(name: str) -> Arr:
        return Arr(name, (6,), batch=False, lo=-3.0, hi=3.0, extreme=False)

    def screws() -> Arr:
        return Arr("S_list", (6, 6), batch=False, lo=-1.0, hi=1.0, extreme=False)

    return [
        Spec("check.product_of_exponentials.reference_skew", steps.reference_skew,
             [Arr("w", (3,), batch=False)], shape=lambda c, v: (3, 3), weight=0.3),
        Spec("check.product_of_exponentials.reference_rodrigues", steps.reference_rodrigues,
             [Arr("omega", (3,), batch=False, lo=-1.0, hi=1.0, extreme=False), Num("theta", -3.0, 3.0, extreme=False)],
             shape=lambda c, v: (3, 3), weight=0.3),
        Spec("check.product_of_exponentials.reference_screw_axis", steps.reference_screw_axis,
             [Arr("omega", (3,), batch=False, lo=-1.0, hi=1.0, extreme=False), Arr("point", (3,), batch=False)],
             shape=lambda c, v: (6,), weight=0.3),
        Spec("check.product_of_exponentials.reference_exp6", steps.reference_exp6,
             [Arr("S", (6,), batch=False, lo=-1.0, hi=1.0, extreme=False), Num("theta", -3.0, 3.0, extreme=False)],
             shape=lambda c, v: (4, 4), weight=0.3),
        Spec("check.product_of_exponentials.reference_poe_fk", steps.reference_poe_fk,
             [Tf("M", batch=False, extreme=False), screws(), angles("theta")], shape=lambda c, v: (4, 4), weight=0.3),
        Spec("check.product_of_exponentials.reference_adjoint_matrix", steps.reference_adjoint_matrix,
             [Tf("T", batch=False)], shape=lambda c, v: (6, 6), weight=0.3),
        Spec("check.product_of_exponentials.reference_jacobian_in_space", steps.reference_jacobian_in_space,
             [screws(), angles("theta")], shape=lambda c, v: (6, 6), weight=0.3),
        Spec("check.product_of_exponentials.reference_jacobian_in_body", steps.reference_jacobian_in_body,
             [Tf("M", batch=False, extreme=False), screws(), angles("theta")], shape=lambda c, v: (6, 6), weight=0.3),
    ]


def _ur10_closed_form_step_specs() -> list[Spec]:
    """robokin's steps of chapter 7 (the stand-ins the graded tests pass to the student's functions)."""
    steps = check.ur10_closed_form
    return [
        Spec("check.ur10_closed_form.reference_wrist_centre", steps.reference_wrist_centre, [Tf("T", batch=False)],
             shape=lambda c, v: (3,), weight=0.3),
        Spec("check.ur10_closed_form.reference_shoulder_angles", steps.reference_shoulder_angles,
             [Tf("T", batch=False)], check=_rows_of((2,), (0,)), weight=0.3),
        Spec("check.ur10_closed_form.reference_wrist_angles", steps.reference_wrist_angles,
             [Tf("T", batch=False), Num("q1", -3.0, 3.0)], shape=lambda c, v: (2, 2), weight=0.3),
        Spec("check.ur10_closed_form.reference_arm_angles", steps.reference_arm_angles,
             [Tf("T", batch=False), *(Num(name, -3.0, 3.0) for name in ("q1", "q5", "q6"))],
             check=_rows_of((2, 3), (0, 3)), weight=0.3),
    ]


def _ur10_step_specs() -> list[Spec]:
    """robokin's steps of chapter 2 (the stand-ins the graded tests pass to the student's functions)."""
    steps = check.ur10
    jacobian = lambda name="J": Arr(name, (3, 6), batch=False, extreme=False)  # noqa: E731
    return [
        Spec("check.ur10.reference_weighted_pinv", steps.reference_weighted_pinv,
             [jacobian(), Const("W", np.diag([2.0, 2.0, 2.0, 1.0, 1.0, 1.0]))], shape=lambda c, v: (6, 3),
             weight=0.3),
        Spec("check.ur10.reference_dls_step", steps.reference_dls_step,
             [jacobian(), Arr("e", (3,), batch=False, extreme=False), Num("damping", 0.01, 0.5, extreme=False)],
             shape=lambda c, v: (6,), weight=0.3),
        Spec("check.ur10.reference_nullspace_projector", steps.reference_nullspace_projector, [jacobian()],
             shape=lambda c, v: (6, 6), weight=0.3),
        Spec("check.ur10.reference_joint_limit_objective", steps.reference_joint_limit_objective,
             [Arr("q", (6,), extreme=False)], {"limits": Limits("limits", 6, optional=True)},
             shape=lambda c, v: batch_shape(c), batch=True, weight=0.3),
        Spec("check.ur10.reference_joint_limit_gradient", steps.reference_joint_limit_gradient,
             [Arr("q", (6,), batch=False, extreme=False)], {"limits": Limits("limits", 6, optional=True)},
             shape=lambda c, v: (6,), weight=0.3),
        Spec("check.ur10.reference_ik_position", steps.reference_ik_position,
             [Obj("chain", lambda c: models.ur10()), Arr("p_goal", (3,), batch=False, lo=-0.8, hi=0.8, extreme=False),
              Arr("q0", (6,), batch=False, extreme=False), Fn("step", lambda c: steps.PseudoinverseStep())],
             {"max_step": Num("max_step", 0.1, 1.0, positive=True, extreme=False),
              "tol": Num("tol", 1e-9, 1e-3, positive=True, allow_zero=True, extreme=False),
              "max_iterations": Int("max_iterations", 0, 5)},
             check=lambda r, c, v: _ik_position_result(r), weight=0.3),
    ]


def _ik_position_result(result: Any) -> None:
    """A loop's result: (q (6,) finite, converged, iterations)."""
    q, converged, iterations = result
    assert np.shape(q) == (6,) and np.all(np.isfinite(q)) and isinstance(converged, bool)
    assert isinstance(iterations, int) and 0 <= iterations <= 5


def check_specs() -> list[Spec]:
    from robokin.check._registry import CHAPTERS, checks_of

    S = [
        *_poe_step_specs(),
        Spec("check.matrix_function", check.matrix_function,
             [Answer("student"), Fn("reference", lambda c: (lambda alpha: tr.rotx(alpha)), bad=("none", "str"))],
             {"variables": Const("variables", ["alpha"]), "quiet": Const("quiet", True),
              "samples": Int("samples", 1, 5, minimum=1)},
             student=("student",), check=_is_result, weight=0.5),
        Spec("check.value", check.value, [Answer("student"), Arr("reference", (3,), batch=False, shape_bad=False)],
             {"quiet": Const("quiet", True), "atol": Num("atol", 1e-6, 1e-2, positive=True, allow_zero=True),
              "rtol": Num("rtol", 1e-6, 1e-2, positive=True, allow_zero=True)},
             student=("student",), check=_is_result, weight=0.5),
        Spec("check.checks_of", check.checks_of, [Choice("name", sorted(CHAPTERS))], weight=0.1),
        Spec("check.leg.ik_solution", check.leg.ik_solution, [Answer("q")],
             {"goal": Arr("goal", (3,), batch=False, optional=True), "tol": Num("tol", 1e-4, 1e-2, positive=True),
              "quiet": Const("quiet", True)}, student=("q",), check=_is_result, weight=0.5),
        Spec("check.three_rpr.check_poses", check.three_rpr.check_poses,
             [Answer("poses"), Arr("rho", (3,), batch=False, lo=0.5, hi=1.2, sign=1)],
             {"tol": Num("tol", 1e-7, 1e-4, positive=True), "quiet": Const("quiet", True),
              "robot": Obj("robot", lambda c: robot_3rpr(), bad=("str", "int", "list"), optional=True)},
             student=("poses",), check=_is_result, weight=0.5),
        Spec("check.three_rpr.reference_orientation_function", check.three_rpr.reference_orientation_function,
             [Num("phi", -3.0, 3.0), Arr("rho", (3,), batch=False, lo=0.5, hi=1.2, sign=1)],
             {"robot": Obj("robot", lambda c: robot_3rpr(), bad=("str", "int", "list"), optional=True)},
             weight=0.5),
        Spec("check.ar601.ik_solution", check.ar601.ik_solution, [Answer("q")],
             {"T_target": Tf("T_target", batch=False, scale=0.3, optional=True), "quiet": Const("quiet", True)},
             student=("q",), check=_is_result, weight=0.5),
        Spec("check.ar601.ik_solver", check.ar601.ik_solver, [Answer("f")],
             {"samples": Int("samples", 1, 3, minimum=1, huge=None), "seed": Int("seed", 0, 5, optional=True),
              "quiet": Const("quiet", True)}, student=("f",), check=_is_result, weight=0.5),
        *_ur10_closed_form_step_specs(),
        *_ur10_step_specs(),
        # chapter 5's stand-in for the student's law in the test of the loop
        Spec("check.baxter.reference_resolved_rate", check.baxter.reference_resolved_rate,
             [Arr("q", (7,), batch=False, extreme=False), Arr("r_des", (3,), batch=False, extreme=False),
              Arr("v_des", (3,), batch=False, extreme=False)],
             {"kp": Num("kp", 0.0, 20.0, allow_zero=True, extreme=False)}, shape=lambda c, v: (7,), weight=0.3),
        # chapter 10's stand-ins for the student's earlier steps in the later tests
        Spec("check.trajectories.reference_cubic_scaling", check.trajectories.reference_cubic_scaling,
             [Num("t", 0.0, 2.0, allow_zero=True), Num("T", 0.5, 3.0, positive=True)], shape=lambda c, v: (3,)),
        Spec("check.trajectories.reference_quintic_scaling", check.trajectories.reference_quintic_scaling,
             [Num("t", 0.0, 2.0, allow_zero=True), Num("T", 0.5, 3.0, positive=True)], shape=lambda c, v: (3,)),
        Spec("check.trajectories.reference_trapezoid_time", check.trajectories.reference_trapezoid_time,
             [Num("distance", 0.0, 3.0, positive=True, allow_zero=True), Num("v_max", 0.1, 3.0, positive=True),
              Num("a_max", 0.1, 5.0, positive=True)], shape=lambda c, v: ()),
        Spec("check.trajectories.reference_least_duration", check.trajectories.reference_least_duration,
             [Arr("q_start", (4,), batch=False), Arr("q_end", (4,), batch=False),
              Arr("v_max", (4,), batch=False, lo=0.1, hi=3.0, sign=1),
              Arr("a_max", (4,), batch=False, lo=0.1, hi=5.0, sign=1)], shape=lambda c, v: ()),
        Spec("check.trajectories.reference_slerp", check.trajectories.reference_slerp,
             [Arr("q0", (4,), batch=False, extra_bad={"zero": zero_vector(4)}),
              Arr("q1", (4,), batch=False, extra_bad={"zero": zero_vector(4)}), Num("s", 0.0, 1.0, allow_zero=True)],
             shape=lambda c, v: (4,)),
    ]
    seen = set()
    for chapter in sorted(CHAPTERS):
        for attr, chk in sorted(checks_of(chapter).items()):
            if id(chk) in seen:
                continue
            seen.add(id(chk))
            S.append(Spec(f"check.{chapter}.{attr}", lambda answer, quiet, _c=chk: _c(answer, quiet=quiet),
                          [Answer("answer")], {"quiet": Const("quiet", True)}, student=("answer",),
                          check=_is_result, weight=0.3))
    # chapter 4's stand-in for the student's orientation error in the later tests
    S.append(Spec("check.cartesian.reference_orientation_error", check.cartesian.reference_orientation_error,
                  [Rot("R", batch=False), Rot("R_goal", batch=False)], shape=lambda c, v: (3,), weight=0.3))
    # and for its RPY difference in the test of analytic_twist
    S.append(Spec("check.cartesian.reference_rpy_difference", check.cartesian.reference_rpy_difference,
                  [Rot("R", batch=False), Rot("R_goal", batch=False)], shape=lambda c, v: (3,), weight=0.3))
    return S


# ------------------------------------------------------------------ views
class _Points(Arr):
    """Points (N, 3) with N >= 1 (a batch of at least one point)."""

    def valid(self, ctx: Ctx) -> Any:
        return ctx.rng.uniform(-1.0, 1.0, (int(ctx.rng.integers(1, 5)) + (1 if self.name == "path" else 0), 3))

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return NONNUMERIC + NONFINITE + ("complex", "shape", "ragged", "empty", "huge")

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        if kind == "empty":
            return np.zeros((0, 3))
        if kind == "huge":
            return np.array([[0.0, 0.0, 0.0], [1e39, 0.0, 0.0]])
        if kind == "shape":
            return ctx.rng.uniform(-1.0, 1.0, (3, 4))
        return super().corrupt(kind, ctx)


class _Pose(Tf):
    """One rigid transform; also corrupted into a scaled one (2 I)."""

    def __init__(self, name: str) -> None:
        super().__init__(name, batch=False)

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return super().default_bad(ctx) + ("scaled",)

    def corrupt(self, kind: str, ctx: Ctx) -> Any:
        if kind == "scaled":
            return 2.0 * np.eye(4)
        return super().corrupt(kind, ctx)


class _Axes(Rot):
    """Unit axes as columns (3, 3): a rotation, or a reflection (singular vectors come as either)."""

    def __init__(self, name: str) -> None:
        super().__init__(name, batch=False)

    def default_bad(self, ctx: Ctx) -> tuple[str, ...]:
        return tuple(kind for kind in super().default_bad(ctx) if kind != "reflect")


def _view_chain(ctx: Ctx) -> Any:
    return models.planar_two_link()


class _Steps(Arr):
    def valid(self, ctx: Ctx) -> Any:
        return ctx.rng.uniform(-1.0, 1.0, (4, 2))


def _close_figures(result: Any, ctx: Ctx, values: dict) -> None:
    import matplotlib.pyplot as plt

    plt.close("all")


def view_specs() -> list[Spec]:
    """Every public function of robokin.views that draws what it is given (static and matplotlib)."""
    import matplotlib

    matplotlib.use("Agg")
    from robokin import views

    def scene_call(method: str) -> Any:
        def call(*args: Any, **kwargs: Any) -> Any:
            scene = views.Scene()
            getattr(scene, method)(*args, **kwargs)
            return scene.to_html() and None  # the page is made: nothing reached the packer unchecked

        call.__name__ = method
        return call

    chain = Obj("chain", _view_chain)
    q = Arr("q", (2,), batch=False, optional=True)
    steps = _Steps("trajectory", (4, 2), batch=False, extra_bad={"empty": lambda c: np.zeros((0, 2))})
    return [
        Spec("views.Scene.add_chain", scene_call("add_chain"), [chain, q], finite=False, weight=0.3),
        Spec("views.Scene.add_ghost", scene_call("add_ghost"), [chain, q], finite=False, weight=0.2),
        Spec("views.Scene.add_target", scene_call("add_target"), [_Pose("T")], finite=False, weight=0.3),
        Spec("views.Scene.add_points", scene_call("add_points"), [_Points("points", (3,))],
             {"radius": Num("radius", positive=True, optional=True)}, finite=False, weight=0.3),
        Spec("views.Scene.add_path", scene_call("add_path"), [_Points("path", (3,), labels=("points",))],
             finite=False, weight=0.3),
        Spec("views.Scene.add_ellipsoid", scene_call("add_ellipsoid"),
             [Arr("center", (3,), batch=False), Arr("radii", (3,), batch=False, lo=0.0, hi=1.0, sign=1),
              _Axes("axes")], finite=False, weight=0.2),
        Spec("views.Scene.animate", scene_call("animate"), [chain, steps],
             {"dt": Num("dt", 0.01, 0.5, positive=True)}, finite=False, weight=0.3),
        Spec("views.show", views.show, [chain, q],
             {"trajectory": _Steps("trajectory", (4, 2), batch=False, optional=True,
                                   extra_bad={"empty": lambda c: np.zeros((0, 2))}),
              "mode": Const("mode", "static")}, finite=False, weight=0.3),
        Spec("views.plot_chain", views.plot_chain, [chain, q], check=_close_figures, finite=False, weight=0.2),
        Spec("views.plot_history", lambda q: views.plot_history(q=q), [_Steps("q", (4, 2), batch=False,
             extra_bad={"empty": lambda c: np.zeros((0, 2))}, bad=("none", "str", "strlist", "object"))],
             check=_close_figures, finite=False, weight=0.2),
    ]


def solution_check_specs() -> list[Spec]:
    """The ready-made checks of robokin.check.solutions: student garbage -> a failed CheckResult."""
    arm = models.ur10()
    goal = arm.fk(np.array([0.3, -1.2, 1.4, -1.0, -1.57, 0.4]))
    chain = Obj("chain", lambda c: arm)
    ref = models.ar601_leg_ik(models.ar601_leg().fk(np.array([0.1, 0.05, -0.3, 0.6, -0.3, -0.05]))).q
    return [
        Spec("check.ik_solution", lambda q, chain, target, atol: check.ik_solution(q, chain, target, atol=atol,
                                                                                   quiet=True),
             [_Configuration("q"), chain, Const("target", goal), Num("atol", 1e-8, 1e-3, positive=True)],
             student=("q",), check=_is_result, weight=0.3),
        Spec("check.solution_set", lambda solutions, reference, atol: check.solution_set(
             solutions, reference, atol=atol, quiet=True),
             [_SolutionRows("solutions"), Const("reference", ref), Num("atol", 1e-8, 1e-3, positive=True)],
             student=("solutions",), check=_is_result, weight=0.3),
        Spec("check.SolutionSetCheck", lambda answer: _ELBOW_ANGLES(answer, quiet=True), [Answer("answer")],
             student=("answer",), check=_is_result, weight=0.3),
    ]


#: a SolutionSetCheck: both elbow angles q2 of a two-link arm (l1 = l2 = 1 m) at a distance d
_ELBOW_ANGLES = check.SolutionSetCheck(
    name="q2", variables=[check.Variable("d", kind="length", low=0.2, high=1.9)], samples=5,
    reference=lambda x: np.array([[1.0], [-1.0]]) * np.arccos(x[0] ** 2 / 2 - 1))


def _pairs_of(size: int) -> Any:
    """A check that the result is a list of tuples of ``size`` floats."""
    def check(r: Any, c: Ctx, v: dict) -> None:
        assert isinstance(r, list) and all(isinstance(t, tuple) and len(t) == size for t in r), r

    return check


def _knee_angle_result(r: Any, c: Ctx, v: dict) -> None:
    assert isinstance(r, float) and (math.isnan(r) or 0.0 <= r <= math.pi), r


def ar601_step_specs() -> list[Spec]:
    """robokin's steps of chapter 6 (the stand-ins the graded tests pass to the student's my_leg_ik)."""
    steps = check.ar601
    return [
        Spec("check.ar601.reference_ankle_point", steps.reference_ankle_point, [Tf("T", batch=False, scale=0.3)],
             {"L3_": Num("L3_", 0.05, 0.2, extreme=False)}, shape=lambda c, v: (3,), weight=0.3),
        # nan for a distance out of reach (the lengths are drawn too)
        Spec("check.ar601.reference_knee_angle", steps.reference_knee_angle, [Num("d", 0.0, 0.6, allow_zero=True)],
             {"l1_": Num("l1_", 0.1, 0.5, positive=True), "l2_": Num("l2_", 0.1, 0.5, positive=True)},
             check=_knee_angle_result, finite=False, weight=0.3),
        Spec("check.ar601.reference_ankle_angles", steps.reference_ankle_angles,
             [Arr("u", (3,), batch=False, lo=-0.6, hi=0.6, extreme=False), Num("q4", -2.5, 2.5, extreme=False)],
             check=_pairs_of(2), weight=0.3),
        Spec("check.ar601.reference_hip_angles", steps.reference_hip_angles, [Rot("R_H", batch=False)],
             check=_pairs_of(3), weight=0.3),
    ]


def statics_step_specs() -> list[Spec]:
    """robokin's steps of chapter 9 (the stand-ins the graded tests pass to the student's functions)."""
    steps = check.statics_ellipsoids

    def pair(r: Any, c: Ctx, v: dict) -> None:
        radii, axes = r
        assert np.shape(radii) == (2,) and np.shape(axes) == (2, 2), r

    def triple(r: Any, c: Ctx, v: dict) -> None:
        assert isinstance(r, tuple) and len(r) == 3 and all(isinstance(x, float) for x in r), r

    # any (m, n) with m <= n is valid: no corrupted shape
    wide = lambda: Arr("J", (2, 3), batch=False, extreme=False, shape_bad=False)  # noqa: E731
    return [
        Spec("check.statics_ellipsoids.reference_tool_jacobian", steps.reference_tool_jacobian,
             [Arr("q", (2,), batch=False)], shape=lambda c, v: (2, 2), weight=0.3),
        Spec("check.statics_ellipsoids.reference_velocity_ellipse", steps.reference_velocity_ellipse,
             [wide()], check=pair, weight=0.3),
        Spec("check.statics_ellipsoids.reference_posture_measures", steps.reference_posture_measures,
             [wide()], check=triple, finite=False, weight=0.3),
    ]


def all_specs() -> list[Spec]:
    return (transform_specs() + chain_method_specs() + construction_specs() + model_specs() + urdf_specs()
            + motion_specs() + parallel_specs() + check_specs() + solution_check_specs() + view_specs()
            + ar601_step_specs() + statics_step_specs())
