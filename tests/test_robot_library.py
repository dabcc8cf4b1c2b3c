"""Every robot of the installed example-robot-data: listed with its links, loadable by name."""

from __future__ import annotations

import importlib.metadata

import numpy as np
import pytest

from support import installed
from robokin.errors import DomainError
from robokin.models import ROBOT_DESCRIPTIONS, available_robots, from_urdf, robot_description

installed.require("yourdfpy", "yourdfpy is not installed: pip install 'robokin[robots]'")
try:
    importlib.metadata.distribution("example-robot-data")
except importlib.metadata.PackageNotFoundError:
    pytest.skip("example-robot-data is not installed: pip install 'robokin[robots]'", allow_module_level=True)


def test_every_urdf_file_of_the_package_is_listed_once():
    robots = available_robots()
    names = [r.name for r in robots]
    assert len(robots) >= 60 and len(set(names)) == len(names)
    files = {r.path for r in robots}
    assert len(files) == len(robots) and all(p.suffix == ".urdf" and p.is_file() for p in files)
    by_name = {r.name: r for r in robots}
    for name in ("kinova", "xarm7", "ur5_robot", "solo12", "panda", "baxter"):
        assert name in by_name, name
    assert "anymal_b_simple_description/anymal" in by_name       # shared file names keep their package
    assert available_robots() is robots                           # read once


@pytest.mark.parametrize("name, base, tip, joints", [
    ("kinova", "base", "j2s6s200_end_effector", 6),
    ("xarm7", "world", "link_eef", 7),
    ("ur10_robot", "world", "ee_link", 6),
    ("panda", "panda_link0", "panda_hand_tcp", 7),                  # the tool frame, not a finger
    ("z1", "world", "gripperStator", 6),                            # the gripper's body, not its jaw
    ("so100", "base", "gripper", 5),
    ("talos_left_arm", "arm_left_1_link", "gripper_left_base_link", 6),   # the link carrying the gripper
    ("baxter", "base", "left_gripper_base_link", 7),               # not the hand's camera
    ("tiago", "base_footprint", "hand_tool_link", 8),               # the hand's tool frame, not a finger
    ("romeo", "base_link", "l_wrist", 8),                           # the link carrying the hand (LHand)
    ("alexander_v1.lowerBodyOnly", "PELVIS_LINK", "LEFT_FOOT", 6),  # the foot, not its IMU
])
def test_listed_links_give_the_arm(name, base, tip, joints):
    info = {r.name: r for r in available_robots()}[name]
    assert (info.base_link, info.tip_links[0], info.movable_joints) == (base, tip, joints)
    arm = from_urdf(robot_description(name), info.base_link, info.tip_links[0])
    assert arm.n == joints
    q = np.linspace(-0.5, 0.5, arm.n)
    h = 1e-6
    J_fd = np.column_stack([(arm.fk(q + h * e)[:3, 3] - arm.fk(q - h * e)[:3, 3]) / (2 * h) for e in np.eye(arm.n)])
    assert np.allclose(arm.jacobian(q)[:3], J_fd, atol=1e-8)


def test_robot_description_takes_every_listed_name():
    for info in available_robots():
        assert robot_description(info.name) == info.path
    for name, (file, _, _) in ROBOT_DESCRIPTIONS.items():
        assert robot_description(name).as_posix().endswith(file)


def test_unknown_robot_names_some_and_points_to_the_list():
    with pytest.raises(DomainError) as info:
        robot_description("kinova2")
    message = str(info.value)
    assert "'kinova2'" in message and "available_robots()" in message and "more)" in message
    assert len(message) < 600


@pytest.mark.parametrize("name, finger, joints", [
    ("panda", "panda_leftfinger", 8),
    ("talos_left_arm", "gripper_left_motor_double_link", 7),
    ("tiago", "hand_index_link", 9),
])
def test_a_gripper_joint_only_when_asked(name, finger, joints):
    """A gripper's own links come after the end-effectors; a chain to one has the gripper joint."""
    info = available_robots()[name]
    assert finger in info.tip_links and info.tip_links.index(finger) > 0
    assert from_urdf(robot_description(name), info.base_link, finger).n == joints == info.movable_joints + 1


#: Words of a sensor's frame, written here independently of robokin.models.robot_library.
SENSOR_WORDS = {"camera", "cam", "imu", "accelerometer", "range", "sonar", "optical", "depth", "laser", "led"}


def test_no_first_tip_is_a_sensors_frame():
    """An end-effector is a tool frame or what carries a gripper, a hand or a foot: never a camera
    or an IMU, which come after the end-effectors."""
    import re

    sensor = lambda link: bool(set(re.split(r"[^a-z0-9]+", link.lower())) & SENSOR_WORDS)  # noqa: E731
    for info in available_robots():
        if info.tip_links:
            assert not sensor(info.tip_links[0]), (info.name, info.tip_links[:3])
    baxter = available_robots()["baxter"].tip_links
    assert baxter.index("right_gripper_base_link") < baxter.index("right_hand_camera_link")


def test_notes_say_what_a_file_lacks():
    """talos_left_arm starts below the arm's first joint, which talos_full_v2 has."""
    import xml.etree.ElementTree as ElementTree

    robots = available_robots()
    left, full = robots["talos_left_arm"], robots["talos_full_v2"]
    assert "arm_left_1_joint" in left.note and "talos_full_v2" in left.note
    joints = lambda info: {j.get("name") for j in ElementTree.parse(info.path).getroot().findall("joint")}  # noqa: E731
    assert "arm_left_1_joint" not in joints(left) and "arm_left_1_joint" in joints(full)
    assert from_urdf(robot_description("talos_full_v2"), "torso_2_link", left.tip_links[0]).n == left.movable_joints + 1
    assert sum(bool(info.note) for info in robots) == 1


def test_the_list_shows_as_a_short_table_and_prints_whole():
    robots = available_robots()
    short, whole = repr(robots), str(robots)
    assert len(short.splitlines()) <= 12 and f"{len(robots)} robots" in short and ".names()" in short
    assert len(whole.splitlines()) == len(robots) + 2
    assert all(len(line) <= 80 for line in whole.splitlines() + short.splitlines())
    assert robots.names() == [info.name for info in robots] and robots["kinova"].name == "kinova"
    assert isinstance(robots, tuple) and robots[0] is robots[:1][0]
    with pytest.raises(KeyError, match="names"):
        robots["kinova2"]
