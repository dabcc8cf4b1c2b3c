"""Tests of robokin.models.urdf: from_urdf and robot_description.

1. A small hand-written URDF (fixed, revolute, prismatic and continuous joints,
   a joint about a skew axis): forward kinematics against the URDF formula
   multiplied out by hand, the Jacobian against finite differences.
2. Bad input: every kind of broken file or link choice gives a URDFError (or a
   TypeError / ImportError) that names the file and the link or joint.
3. Cross-checks: the hand-built ``ur10()``, ``baxter_left()`` and ``panda()``
   against the same robots read from the URDFs of example-robot-data (skipped,
   with a message, when that package is not installed; CI installs it).
"""

from __future__ import annotations

import importlib.metadata
import importlib.util
import logging
import math
import subprocess
import sys
from pathlib import Path
from collections.abc import Callable

import numpy as np
import pytest

from robokin.chains import SerialChain
from robokin.errors import DomainError, URDFError, URDFNotFoundError
from robokin.models import baxter_left, from_urdf, panda, robot_description, ur10
from robokin.models.baxter import BAXTER_LEFT_LIMITS
from robokin.models.panda import PANDA_LIMITS
from support.finite_differences import pose_jacobian

HAVE_YOURDFPY = importlib.util.find_spec("yourdfpy") is not None
try:
    importlib.metadata.distribution("example-robot-data")
    HAVE_ROBOTS = True
except importlib.metadata.PackageNotFoundError:
    HAVE_ROBOTS = False

needs_yourdfpy = pytest.mark.skipif(not HAVE_YOURDFPY, reason="yourdfpy is not installed: pip install "
                                    "'robokin[robots]' (CI installs it)")
needs_robots = pytest.mark.skipif(not (HAVE_YOURDFPY and HAVE_ROBOTS), reason="example-robot-data (and yourdfpy) "
                                  "not installed: pip install 'robokin[robots]' (CI installs them)")

PI = math.pi


# --------------------------------------------------------------------------- independent helpers
def rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]])


def rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def trans(x, y, z):
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def origin(xyz, rpy):
    """URDF <origin>: Trans(xyz) Rz(yaw) Ry(pitch) Rx(roll)."""
    return trans(*xyz) @ rz(rpy[2]) @ ry(rpy[1]) @ rx(rpy[0])


def rot_axis(axis, a):
    """Rodrigues: rotation by a about the unit vector axis (4×4)."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + math.sin(a) * K + (1 - math.cos(a)) * K @ K
    return T


def rotation_error(Ra, Rb):
    """Angle (rad) of Ra Rbᵀ, batched; accurate for small angles."""
    D = Ra @ np.swapaxes(Rb, -1, -2)
    w = 0.5 * np.stack([D[..., 2, 1] - D[..., 1, 2], D[..., 0, 2] - D[..., 2, 0], D[..., 1, 0] - D[..., 0, 1]], -1)
    return np.linalg.norm(w, axis=-1)




# --------------------------------------------------------------------------- a hand-written URDF
TOY = """<?xml version="1.0"?>
<robot name="toy">
  <link name="world"/>
  <link name="base"/>
  <link name="l1"/>
  <link name="l2"/>
  <link name="l3"/>
  <link name="l4"/>
  <link name="tool"/>
  <link name="camera">
    <visual><geometry><mesh filename="package://nowhere/meshes/camera.stl"/></geometry></visual>
  </link>
  <joint name="mount" type="fixed">
    <parent link="world"/><child link="base"/>
    <origin xyz="0.1 0 0.2" rpy="0 0 1.5707963267948966"/>
  </joint>
  <joint name="camera_mount" type="fixed">
    <parent link="world"/><child link="camera"/>
    <origin xyz="0.5 -0.2 1.0" rpy="0.2 0.4 -0.6"/>
  </joint>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/>
    <limit lower="-2.0" upper="2.0" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="prismatic">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0.4 0 0" rpy="0 1.5707963267948966 0"/>
    <axis xyz="0 -1 0"/>
    <limit lower="0.0" upper="0.5" effort="1" velocity="1"/>
  </joint>
  <joint name="j3" type="continuous">
    <parent link="l2"/><child link="l3"/>
    <origin xyz="0.05 0.02 0.1" rpy="0.3 -0.2 0.5"/>
    <axis xyz="1 0 0"/>
  </joint>
  <joint name="j4" type="revolute">
    <parent link="l3"/><child link="l4"/>
    <origin xyz="0 0 0.2" rpy="0.1 0 0"/>
    <axis xyz="1 1 0"/>
    <limit lower="-1.0" upper="1.5" effort="1" velocity="1"/>
  </joint>
  <joint name="flange" type="fixed">
    <parent link="l4"/><child link="tool"/>
    <origin xyz="0 0 0.05" rpy="0.1 0.2 0.3"/>
  </joint>
</robot>
"""

O_MOUNT = origin((0.1, 0, 0.2), (0, 0, PI / 2))
O_CAMERA = origin((0.5, -0.2, 1.0), (0.2, 0.4, -0.6))
O_J1 = origin((0, 0, 0.3), (0, 0, 0))
O_J2 = origin((0.4, 0, 0), (0, PI / 2, 0))
O_J3 = origin((0.05, 0.02, 0.1), (0.3, -0.2, 0.5))
O_J4 = origin((0, 0, 0.2), (0.1, 0, 0))
O_FLANGE = origin((0, 0, 0.05), (0.1, 0.2, 0.3))


def toy_fk(q, upto="tool"):
    """The URDF's forward kinematics multiplied out by hand, world -> ``upto``."""
    q1, q2, q3, q4 = q
    frames = {}
    T = O_MOUNT @ O_J1 @ rz(q1)
    frames["l1"] = T
    T = T @ O_J2 @ trans(0, -q2, 0)  # prismatic along −y of l2
    frames["l2"] = T
    T = T @ O_J3 @ rx(q3)
    frames["l3"] = T
    T = T @ O_J4 @ rot_axis((1, 1, 0), q4)
    frames["l4"] = T
    frames["tool"] = T @ O_FLANGE
    return frames[upto]


@pytest.fixture(scope="module")
def toy_file(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("urdf") / "toy.urdf"
    path.write_text(TOY)
    return path


@pytest.fixture(scope="module")
def toy(toy_file) -> SerialChain:
    if not HAVE_YOURDFPY:
        pytest.skip("yourdfpy is not installed: pip install 'robokin[robots]' (CI installs it)")
    return from_urdf(toy_file, "world", "tool")


@needs_yourdfpy
def test_toy_structure(toy):
    assert isinstance(toy, SerialChain)
    assert toy.name == "toy" and toy.n == 4
    assert toy.joint_names == ["j1", "j2", "j3", "j4"]
    assert toy.joint_types == ["revolute", "prismatic", "revolute", "revolute"]
    # URDF limits; the continuous joint j3 gets one full turn
    np.testing.assert_array_equal(toy.limits, [[-2.0, 2.0], [0.0, 0.5], [-PI, PI], [-1.0, 1.5]])
    # frames: base link, the child links of the axis-aligned joints, j4's axis frame, tip link
    assert toy.frame_names == ["world", "l1", "l2", "l3", "j4_axis", "tool"]
    np.testing.assert_array_equal(toy.joint_axes[:3], [[0, 0, 1], [0, -1, 0], [1, 0, 0]])


@needs_yourdfpy
def test_toy_fk_by_hand_at_a_simple_configuration(toy):
    # q = (π/2, 0.2, 0, 0), worked out by hand: the mount turns 90° about z and j1 another 90°,
    # so l1's x axis points along world −x: j2 sits at (0.1, 0, 0.5) + 0.4·(−x) = (−0.3, 0, 0.5);
    # l2 = Rz(π) Ry(π/2): its y axis is world −y, so sliding 0.2 along −y_l2 moves +0.2 along world y,
    # and its z axis is world −x.
    T = toy.fk([PI / 2, 0.2, 0.0, 0.0], frame="l2")
    np.testing.assert_allclose(T[:3, 3], [-0.3, 0.2, 0.5], atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], [[0, 0, -1], [0, -1, 0], [-1, 0, 0]], atol=1e-12)


@needs_yourdfpy
def test_toy_fk_matches_the_urdf_formula(toy):
    Q = toy.random_configurations(200, seed=1)
    ref = np.stack([toy_fk(q) for q in Q])
    np.testing.assert_allclose(toy.fk(Q), ref, atol=1e-12)
    for link in ("l1", "l2", "l3"):  # the frames of axis-aligned joints are the URDF link frames
        np.testing.assert_allclose(toy.fk(Q, frame=link), np.stack([toy_fk(q, link) for q in Q]), atol=1e-12)
    # j4 turns about a skew axis: its chain frame has the l4 origin and z along the axis
    F4 = toy.fk(Q, frame="j4_axis")
    L4 = np.stack([toy_fk(q, "l4") for q in Q])
    np.testing.assert_allclose(F4[:, :3, 3], L4[:, :3, 3], atol=1e-12)
    np.testing.assert_allclose(F4[:, :3, 2], L4[:, :3, :3] @ (np.array([1, 1, 0]) / math.sqrt(2)), atol=1e-12)


@needs_yourdfpy
def test_toy_jacobian_vs_finite_differences(toy):
    for q in toy.random_configurations(20, seed=2):
        np.testing.assert_allclose(toy.jacobian(q), pose_jacobian(toy, q), atol=1e-8)


@needs_yourdfpy
def test_toy_sub_chains_and_name(toy_file, toy):
    # from the link "base" (fixed joints before it are not part of the chain) to l3, no tool transform
    sub = from_urdf(str(toy_file), "base", "l3", name="toy arm")
    assert sub.name == "toy arm" and sub.joint_names == ["j1", "j2", "j3"]
    Q = sub.random_configurations(50, seed=3)
    ref = np.stack([np.linalg.inv(O_MOUNT) @ toy_fk(np.r_[q, 0.0], "l3") for q in Q])
    np.testing.assert_allclose(sub.fk(Q), ref, atol=1e-12)
    np.testing.assert_allclose(sub.tool, np.eye(4))
    # a base link that hangs from the common ancestor by fixed joints only (like the UR's `base`):
    # the chain starts with the inverse of those fixed transforms
    cam = from_urdf(toy_file, "camera", "tool")
    Q = toy.random_configurations(50, seed=4)
    np.testing.assert_allclose(cam.fk(Q), np.linalg.inv(O_CAMERA) @ toy.fk(Q), atol=1e-12)


@needs_yourdfpy
def test_toy_symbolic_fk_agrees_with_numeric(toy_file):
    sub = from_urdf(toy_file, "world", "l2")
    q = [0.7, 0.3]
    T = sub.fk(sub.symbols())
    Tq = np.array(T.subs(dict(zip(sub.symbols(), q))).evalf(), dtype=float)
    np.testing.assert_allclose(Tq, sub.fk(q), atol=1e-12)


@needs_yourdfpy
def test_no_log_noise_about_meshes(toy_file, caplog, capfd):
    # the toy references a mesh that does not exist; reading it for kinematics says nothing
    with caplog.at_level(logging.DEBUG):
        from_urdf(toy_file, "world", "tool")
    assert not [r for r in caplog.records if r.name.startswith(("yourdfpy", "trimesh"))]
    out, err = capfd.readouterr()
    assert out == "" and err == ""


# --------------------------------------------------------------------------- bad input
def urdf(body: str, name: str = "bad") -> str:
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n{body}\n</robot>\n'


def links(*names: str) -> str:
    return "\n".join(f'<link name="{n}"/>' for n in names)


def joint(name, parent, child, type_="revolute", axis="0 0 1", limit='<limit lower="-1" upper="1"/>', extra=""):
    ax = f'<axis xyz="{axis}"/>' if axis is not None else ""
    return (f'<joint name="{name}" type="{type_}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="0 0 0.1"/>{ax}{limit}{extra}</joint>')


CHAIN = links("a", "b", "c") + joint("ja", "a", "b") + joint("jb", "b", "c")
TREE = links("a", "b", "c", "d") + joint("ja", "a", "b") + joint("jb", "b", "c") + joint("jc", "b", "d")

BAD_CASES = {
    # id: (file text, base_link, tip_link, words the message must contain)
    "malformed XML": ('<robot name="x"><link name="a"></robot>', "a", "b", ["well-formed XML", "line"]),
    "not a robot": ('<sdf version="1.6"><model name="m"/></sdf>', "a", "b", ["<sdf>", "expected <robot>"]),
    "joint without parent": (urdf(links("a", "b") + '<joint name="j" type="fixed"><child link="b"/></joint>'),
                             "a", "b", ["joint 'j'", "<parent"]),
    "joint without type": (urdf(links("a", "b") + '<joint name="j"><parent link="a"/><child link="b"/></joint>'),
                           "a", "b", ["joint 'j'", "type"]),
    "link without name": (urdf('<link/>'), "a", "b", ["<link>", "name"]),
    "bad number": (urdf(links("a", "b") + joint("j", "a", "b").replace("0 0 0.1", "0 zero 0.1")),
                   "a", "b", ["not a valid URDF", "xyz='0 zero 0.1'", "line 4", "'j'"]),
    "two numbers for three": (urdf(links("a", "b") + joint("j", "a", "b", axis="0 1")), "a", "b",
                              ["'j'", "axis [0.0, 1.0]", "three finite numbers"]),
    "origin with two numbers": (urdf(links("a", "b") + joint("j", "a", "b").replace("0 0 0.1", "0 0.1")),
                                "a", "b", ["not a valid URDF", "<origin xyz='0 0.1'>", "3 numbers"]),
    "unknown link in joint": (urdf(links("a", "b") + joint("j", "a", "ghost")), "a", "b", ["'j'", "'ghost'"]),
    "duplicate link": (urdf(links("a", "b", "b") + joint("j", "a", "b")), "a", "b", ["unique", "'b'"]),
    "base not a link": (urdf(CHAIN), "hand", "c", ["base_link 'hand'", "links are: a, b, c"]),
    "tip not a link": (urdf(CHAIN), "a", "finger", ["tip_link 'finger'", "links are: a, b, c"]),
    "tip on another branch": (urdf(TREE), "c", "d", ["no chain", "not a descendant", "below 'b'", "'jb'",
                                                    "d <- b <- a"]),
    "swapped": (urdf(CHAIN), "c", "a", ["above base_link", "swapped"]),
    "different trees": (urdf(links("a", "b", "x", "y") + joint("ja", "a", "b") + joint("jx", "x", "y")),
                        "a", "y", ["different trees"]),
    "closed loop (two parents)": (urdf(links("a", "b", "c", "d") + joint("ja", "a", "b") + joint("jb", "a", "c")
                                       + joint("jc", "b", "d") + joint("jd", "c", "d")),
                                  "a", "d", ["closed loop", "'d'", "'jc'", "'jd'"]),
    "closed loop (cycle)": (urdf(links("a", "b") + joint("ja", "a", "b") + joint("jb", "b", "a")),
                            "a", "b", ["closed loop", "ja", "jb"]),
    "floating joint": (urdf(links("a", "b", "c") + joint("free", "a", "b", "floating", limit="")
                            + joint("jb", "b", "c")), "a", "c", ["'free'", "floating", "not supported"]),
    "planar joint": (urdf(links("a", "b") + joint("slide", "a", "b", "planar", limit="")),
                     "a", "b", ["'slide'", "planar", "not supported"]),
    "mimic joint": (urdf(links("a", "b", "c") + joint("ja", "a", "b")
                         + joint("jb", "b", "c", extra='<mimic joint="ja" multiplier="-1"/>')),
                    "a", "c", ["'jb' mimics joint 'ja'", "mimic joints are not supported"]),
    "unknown joint type": (urdf(links("a", "b") + joint("j", "a", "b", "hinge")), "a", "b", ["'j'", "'hinge'"]),
    "revolute without limit": (urdf(links("a", "b") + joint("j", "a", "b", limit="")), "a", "b",
                               ["'j'", "<limit"]),
    "lower above upper": (urdf(links("a", "b") + joint("j", "a", "b", limit='<limit lower="1" upper="-1"/>')),
                          "a", "b", ["'j'", "lower=1.0, upper=-1.0"]),
    "zero axis": (urdf(links("a", "b") + joint("j", "a", "b", axis="0 0 0")), "a", "b", ["'j'", "axis"]),
    "only fixed joints": (urdf(links("a", "b", "c") + joint("ja", "a", "b") + joint("f", "b", "c", "fixed")),
                          "b", "c", ["no movable joint", "f (fixed)"]),
    "base is tip": (urdf(CHAIN), "b", "b", ["no movable joint"]),
}


@needs_yourdfpy
@pytest.mark.parametrize("case", list(BAD_CASES), ids=list(BAD_CASES))
def test_bad_urdf(case, tmp_path):
    text, base, tip, words = BAD_CASES[case]
    path = tmp_path / "robot.urdf"
    path.write_text(text)
    with pytest.raises(URDFError) as info:
        from_urdf(path, base, tip)
    msg = str(info.value)
    assert str(path) in msg, msg  # every message names the file
    for w in words:
        assert w in msg, f"{w!r} not in: {msg}"
    assert isinstance(info.value, ValueError)


@needs_yourdfpy
def test_mimic_joint_off_the_chain_is_fine(tmp_path):
    text = urdf(links("a", "b", "c") + joint("ja", "a", "b")
                + joint("jm", "a", "c", extra='<mimic joint="ja"/>'))
    (tmp_path / "m.urdf").write_text(text)
    assert from_urdf(tmp_path / "m.urdf", "a", "b").joint_names == ["ja"]


@needs_yourdfpy
def test_missing_file(tmp_path):
    with pytest.raises(URDFNotFoundError, match=r"path: URDF file '.*nothere\.urdf' does not exist"):
        from_urdf(tmp_path / "nothere.urdf", "a", "b")
    with pytest.raises(FileNotFoundError):  # also the built-in exception
        from_urdf(str(tmp_path / "nothere.urdf"), "a", "b")
    with pytest.raises(URDFNotFoundError, match="is not a file"):
        from_urdf(tmp_path, "a", "b")


@needs_yourdfpy
def test_xacro_hint(tmp_path):
    path = tmp_path / "arm.urdf.xacro"
    path.write_text('<robot name="x" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="m">')
    with pytest.raises(URDFError, match="xacro"):
        from_urdf(path, "a", "b")


@pytest.mark.parametrize("args, kwargs, message", [
    ((3, "a", "b"), {}, "path must be"), ((b"x.urdf", "a", "b"), {}, "path must be"),
    (("x.urdf", None, "b"), {}, "base_link must be"), (("x.urdf", "a", ["b"]), {}, "tip_link must be"),
    (("x.urdf", "a", "b"), {"name": 3}, "name must be"),
])
def test_wrong_types(args, kwargs, message):
    with pytest.raises(TypeError, match=message):
        from_urdf(*args, **kwargs)


def test_missing_yourdfpy(monkeypatch, tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(urdf(CHAIN))
    monkeypatch.setitem(sys.modules, "yourdfpy", None)  # import yourdfpy -> ImportError
    with pytest.raises(ImportError, match=r"yourdfpy.*pip install 'robokin\[robots\]'"):
        from_urdf(path, "a", "c")


def test_import_robokin_does_not_import_yourdfpy():
    code = "import robokin, robokin.models, sys; print('yourdfpy' in sys.modules, 'trimesh' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_robot_description_bad_names():
    with pytest.raises(DomainError, match=r"name must be one of \['baxter', 'panda', 'ur10'\] or a robot of "
                                          r"example-robot-data .*available_robots\(\).*; got 'ur5'"):
        robot_description("ur5")
    with pytest.raises(TypeError, match="name must be"):
        robot_description(10)  # type: ignore[arg-type]  # a wrong type on purpose


def test_robot_description_without_the_package(monkeypatch):
    def missing(name):
        raise importlib.metadata.PackageNotFoundError(name)

    monkeypatch.setattr(importlib.metadata, "distribution", missing)
    with pytest.raises(ImportError, match=r"example-robot-data.*pip install 'robokin\[robots\]'"):
        robot_description("panda")


# --------------------------------------------------------------------------- cross-checks with example-robot-data
#: The base transform T_{URDF base, model base} and tool transform T_{model tip, URDF tip} with
#:     fk_URDF(q) = BASE @ fk_model(q) @ TOOL      (same q: both have the same joint zeros)
#: derived from the URDF's fixed joints (see the docstrings of the models):
#:  * UR10: the model's base is the URDF link `base` and its end-effector `tool0`: identity. From the
#:    URDF's kinematic root `base_link` to `ee_link`: `base` is `base_link` turned by π about z
#:    (joint base_link-base_fixed_joint, rpy 0 0 −π), `ee_link` is `tool0` turned by
#:    Rx(π/2) Rz(π/2) (tool0: rpy −π/2 0 0, ee_link: rpy 0 0 π/2, same origin).
#:  * Panda: base `panda_link0`, flange `panda_link8`: identity.
#:  * Baxter: base `torso`, hand `left_hand_link`. The URDF writes the arm-mount yaw as 0.7854, the model
#:    uses π/4 exactly: the torso frames differ by Rz(0.7854 − π/4) = Rz(1.8366e-6 rad) about the
#:    vertical through the mount point p_m = (0.024645, 0.219645, 0.118588) -- a rounding in the URDF,
#:    1.96e-6 m at the hand, not a convention. With base='shoulder' (the s0 frame at the mount) the
#:    base transform is the s0 offset Trans(0.055695, 0, 0.011038) from `left_arm_mount`.
I4 = np.eye(4)
UR10_BASE_LINK_TO_BASE = rz(PI)
UR10_TOOL0_TO_EE_LINK = rx(PI / 2) @ rz(PI / 2)
BAXTER_MOUNT = np.array([0.024645, 0.219645, 0.118588])
BAXTER_TORSO = trans(*BAXTER_MOUNT) @ rz(0.7854 - PI / 4) @ trans(*-BAXTER_MOUNT)
BAXTER_S0_OFFSET = trans(0.055695, 0.0, 0.011038)

CROSS: dict[str, tuple[str, Callable[[], SerialChain], str, str, np.ndarray, np.ndarray]] = {
    # id: (robot_description name, hand-built model, base link, tip link, BASE, TOOL)
    "ur10 base-tool0": ("ur10", ur10, "base", "tool0", I4, I4),
    "ur10 base_link-ee_link": ("ur10", ur10, "base_link", "ee_link", UR10_BASE_LINK_TO_BASE, UR10_TOOL0_TO_EE_LINK),
    "panda link0-link8": ("panda", panda, "panda_link0", "panda_link8", I4, I4),
    "baxter torso-hand": ("baxter", baxter_left, "torso", "left_hand_link", BAXTER_TORSO, I4),
    "baxter shoulder-hand": ("baxter", lambda: baxter_left(base="shoulder"), "left_arm_mount", "left_hand_link",
                             BAXTER_S0_OFFSET, I4),
}
N_CROSS = 1000
_CHAINS: dict[str, tuple[SerialChain, SerialChain]] = {}


def pair(case: str) -> tuple[SerialChain, SerialChain]:
    if case not in _CHAINS:
        robot, model, base, tip, _, _ = CROSS[case]
        _CHAINS[case] = (model(), from_urdf(robot_description(robot), base, tip))
    return _CHAINS[case]


def common_configurations(a: SerialChain, b: SerialChain, N: int, seed: int) -> np.ndarray:
    lo = np.maximum(a.limits[:, 0], b.limits[:, 0])
    hi = np.minimum(a.limits[:, 1], b.limits[:, 1])
    return lo + (hi - lo) * np.random.default_rng(seed).random((N, a.n))


@needs_robots
@pytest.mark.parametrize("case", list(CROSS), ids=list(CROSS))
def test_hand_built_model_matches_the_urdf(case):
    model, loaded = pair(case)
    BASE, TOOL = CROSS[case][4], CROSS[case][5]
    assert loaded.n == model.n
    Q = common_configurations(model, loaded, N_CROSS, seed=sum(map(ord, case)))
    expected = BASE @ model.fk(Q) @ TOOL
    got = loaded.fk(Q)
    assert np.abs(got[:, :3, 3] - expected[:, :3, 3]).max() < 1e-9  # m
    assert rotation_error(got[:, :3, :3], expected[:, :3, :3]).max() < 1e-9  # rad
    # Jacobians: base rotation on both blocks, the tool's origin as the point
    R = np.kron(np.eye(2), BASE[:3, :3])
    np.testing.assert_allclose(loaded.jacobian(Q), R @ model.jacobian(Q, point=TOOL[:3, 3]), atol=1e-9)


@needs_robots
def test_baxter_torso_frames_differ_by_the_rounded_mount_yaw():
    """Without BAXTER_TORSO the hand positions differ by up to 2e-6 m: the URDF's 0.7854 is not π/4."""
    model, loaded = pair("baxter torso-hand")
    Q = common_configurations(model, loaded, 200, seed=9)
    d = np.abs(loaded.fk(Q)[:, :3, 3] - model.fk(Q)[:, :3, 3]).max()
    assert 1e-7 < d < 3e-6
    np.testing.assert_allclose(rotation_error(loaded.fk(Q)[:, :3, :3], model.fk(Q)[:, :3, :3]), 0.7854 - PI / 4,
                               rtol=1e-4)


@needs_robots
@pytest.mark.parametrize("case", ["ur10 base-tool0", "panda link0-link8", "baxter torso-hand"])
def test_joint_names_and_limits_match(case):
    model, loaded = pair(case)
    prefix, suffix = {"ur10": ("", "_joint"), "panda": ("panda_", ""), "baxter": ("left_", "")}[CROSS[case][0]]
    assert loaded.joint_names == [prefix + nm + suffix for nm in model.joint_names]
    assert loaded.joint_types == model.joint_types
    expected = np.array(model.limits)
    if case.startswith("ur10"):
        # On purpose: the model gives every joint the controller's ±2π (UR10 CB3: ±360° on all joints);
        # ur_description's ur10_robot.urdf limits the elbow to ±π, where the arm would hit itself.
        assert np.allclose(model.limits[2], [-2 * PI, 2 * PI])
        expected[2] = [-PI, PI]
    # the URDF prints 2π as 6.28318530718, π/2 as 1.57079632679
    np.testing.assert_allclose(loaded.limits, expected, atol=1e-10, rtol=0)
    np.testing.assert_allclose(model.limits, {"panda": PANDA_LIMITS, "baxter": BAXTER_LEFT_LIMITS,
                                              "ur10": [[-2 * PI, 2 * PI]] * 6}[CROSS[case][0]])


@needs_robots
def test_robot_description_files():
    for name in ("ur10", "baxter", "panda"):
        path = robot_description(name)
        assert path.is_file() and path.suffix == ".urdf"
    assert from_urdf(robot_description("ur10"), "base", "tool0").frame_names == [
        "base", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link", "wrist_3_link",
        "tool0"]
