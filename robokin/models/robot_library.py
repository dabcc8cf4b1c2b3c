r"""The robots of the installed ``example-robot-data`` package, listed with their base and tip links.

:func:`available_robots` finds every URDF file the package ships (about seventy:
arms, legged robots, humanoids, hands, drones) and reads, without building
anything, its link tree: the root link (the natural ``base_link`` of
:func:`robokin.models.from_urdf`) and its candidate ``tip_link``\ s, the deepest
first -- for an arm, the first one is its flange or tool frame. A gripper's or a
hand's joints (a movable joint named for a finger, a thumb, a gripper or a hand)
are not counted in: where the tool is a gripper or a hand, the link that carries it
is a tip, ahead of the gripper's own links (asking for one of those adds the
gripper joint to the chain). A sensor's frame (a camera, an IMU, a range finder)
is no end-effector: it comes last, and the link it is fixed to is a tip where that
link carries nothing else (a foot with its IMU).
:func:`robokin.models.robot_description` accepts any of their names.

The list shows as a short table (``available_robots()`` in a notebook);
``print(available_robots())`` prints all of it, ``.names()`` the names, and
``available_robots()["kinova"]`` one entry.

The listing reads the files' XML only (``xml.etree``): about 0.2 s for the
whole package, once per process.
"""

from __future__ import annotations

import importlib.metadata
import re
import xml.etree.ElementTree as ElementTree
from collections import Counter
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

__all__ = ["RobotInfo", "RobotList", "available_robots", "robots_folder"]

_INSTALL = "pip install 'robokin[robots]'"

#: What is known to be missing from a file of the package (checked against the package's
#: other files by tests/test_robot_library.py).
NOTES = {
    "talos_left_arm": ("the file starts at arm_left_1_link: the arm's first joint (arm_left_1_joint, "
                       "torso_2_link to arm_left_1_link) is not in it, so its chain has 6 of the arm's 7 "
                       "joints; talos_full_v2 has the whole arm (base torso_2_link)"),
}

#: Words that name a gripper's or a hand's joint or link (a movable joint so named is not an arm
#: joint): anywhere in the name (``LThumb1``, ``r_gripper_l_finger_joint``) ...
_GRIPPER_WORDS = ("finger", "gripper", "thumb")
#: ... or, with the word "hand", as a whole word of it (``hand_index_flex_1_joint``; not the
#: spine's ``middle_lumbar_Z``, not "steering") ...
_FINGER_WORDS = frozenset({"index", "middle", "ring", "little", "pinky", "mrl"})
#: ... or a movable joint whose name ends with "hand": a hand's closing joint (``LHand``).
_HAND_JOINT_END = "hand"
#: Whole words of a sensor's frame (a camera, an IMU, a range finder): such a leaf is no
#: end-effector. It comes after the others; the link it is fixed to is an end-effector when
#: that link carries nothing but sensors (a foot with its IMU).
_SENSOR_WORDS = frozenset({"camera", "cam", "imu", "accelerometer", "range", "sonar", "optical", "depth",
                           "rgb", "laser", "lidar", "led", "stereo", "xtion", "d435", "antenna", "sensor"})


def _words(name: str) -> set[str]:
    """The words of a link or joint name, lower case (``right_hand_camera_link``: right, hand, camera, link)."""
    return set(re.split(r"[^a-z0-9]+", name.lower()))


def _names_a_gripper(name: str, joint: bool) -> bool:
    """Whether a joint's (``joint``) or a link's name is that of a gripper's or a hand's part."""
    lower, words = name.lower(), _words(name)
    return (any(word in lower for word in _GRIPPER_WORDS) or ("hand" in words and bool(words & _FINGER_WORDS))
            or (joint and lower.endswith(_HAND_JOINT_END)))


def _is_sensor(link: str) -> bool:
    """Whether ``link`` names a sensor's frame (a camera, an IMU, ...)."""
    return bool(_words(link) & _SENSOR_WORDS)


@dataclass(frozen=True)
class RobotInfo:
    """One URDF file of example-robot-data.

    Attributes
    ----------
    name : str
        What :func:`robokin.models.robot_description` accepts: the file's name
        without ``.urdf`` (``"kinova"``, ``"ur5_robot"``, ``"xarm7"``), prefixed by
        its package folder where two files share a name
        (``"anymal_b_simple_description/anymal"``).
    path : pathlib.Path
        The URDF file.
    base_link : str
        The root of its link tree (the first root if the file holds several trees).
    tip_links : tuple of str
        Its end-effector links, the one with the most movable joints above it first: the
        leaf links reached without a gripper joint, and the links that carry a gripper;
        then sensors' frames, and the gripper's own leaf links (a chain to one of those has
        a gripper joint).
    movable_joints : int
        Revolute, continuous and prismatic joints from ``base_link`` to ``tip_links[0]``.
    note : str
        What is known to be wrong or missing in the file ("" if nothing).
    """

    name: str
    path: Path
    base_link: str
    tip_links: tuple[str, ...]
    movable_joints: int
    note: str = ""


class RobotList(tuple):
    """The robots of :func:`available_robots`: a tuple of :class:`RobotInfo` shown as a table.

    ``repr`` (what a notebook shows) is a short table of the first rows; ``str`` (what
    ``print`` shows) has every row; ``names()`` lists the names; indexing by a name
    (``robots["kinova"]``) gives that robot's entry.
    """

    SHOWN = 8

    def names(self) -> list[str]:
        """The robots' names, as :func:`robokin.models.robot_description` takes them."""
        return [info.name for info in self]

    def __getitem__(self, key):
        if isinstance(key, str):
            for info in self:
                if info.name == key:
                    return info
            raise KeyError(f"no robot named {key!r} in example-robot-data; .names() lists them")
        return super().__getitem__(key)

    def _rows(self, infos) -> list[str]:
        width = max((len(info.name) for info in self), default=4)
        width = min(width, 28)
        rows = [f"{'name':<{width}}  joints  base link -> first tip link"]
        for info in infos:
            name = info.name if len(info.name) <= width else info.name[: width - 1] + "…"
            tip = info.tip_links[0] if info.tip_links else "-"
            line = f"{name:<{width}}  {info.movable_joints:>6}  {info.base_link} -> {tip}"
            rows.append(line if len(line) <= 80 else line[:79] + "…")
        return rows

    def __repr__(self) -> str:
        head = f"{len(self)} robots of example-robot-data"
        if len(self) <= self.SHOWN:
            return "\n".join([head + ":", *self._rows(self)])
        rest = len(self) - self.SHOWN
        return "\n".join([head + f" (the first {self.SHOWN}):", *self._rows(self[: self.SHOWN]),
                          f"… and {rest} more: print(available_robots()) shows them all,",
                          "available_robots().names() lists the names."])

    def __str__(self) -> str:
        return "\n".join([f"{len(self)} robots of example-robot-data:", *self._rows(self)])

    def __getnewargs__(self):
        return (tuple(self),)


def robots_folder() -> Path:
    """The ``robots`` folder of the installed example-robot-data.

    Raises
    ------
    ImportError
        example-robot-data is not installed.
    """
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        raise ImportError(f"the robots of example-robot-data are not installed: {_INSTALL}") from None
    return Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data/robots")))


def _tree(path: Path) -> tuple[str, tuple[str, ...], int] | None:
    """``(root, tip links deepest first, movable joints to the first tip)``, or None if unreadable.

    The tips: the leaves reached without a gripper joint and the links that carry a gripper
    (by their movable joints, gripper joints not counted; sensors' frames last), then the
    gripper's own leaves.
    """
    try:
        root = ElementTree.parse(path).getroot()
    except (OSError, ElementTree.ParseError):
        return None
    links = [name for el in root.findall("link") if (name := el.get("name"))]
    parent: dict[str, tuple[str, bool]] = {}
    children: set[str] = set()
    joint_names: dict[str, str] = {}   # child link -> the name of the joint above it
    for joint in root.findall("joint"):
        p, c = joint.find("parent"), joint.find("child")
        parent_link = p.get("link") if p is not None else None
        child_link = c.get("link") if c is not None else None
        if not parent_link or not child_link:
            continue
        joint_names[child_link] = joint.get("name") or ""
        parent[child_link] = (parent_link, joint.get("type") in ("revolute", "continuous", "prismatic"))
        children.add(parent_link)
    roots = [link for link in links if link not in parent]
    if not roots:
        return None
    depth: dict[str, int] = {}  # movable joints from the root, memoised; iterative walks up
    for link in links:
        walk: list[str] = []
        up = link
        while up not in depth:
            if up not in parent or len(walk) > len(links):  # a root (or a loop: stop)
                depth[up] = 0
                break
            walk.append(up)
            up = parent[up][0]
        count = depth[up]
        for below in reversed(walk):
            count += parent[below][1]
            depth[below] = count
    leaves = [link for link in links if link not in children and link in parent]

    def named(link: str, joint_only: bool = False) -> bool:   # named for a gripper, a finger or a hand
        return (_names_a_gripper(joint_names.get(link, ""), joint=True)
                or (not joint_only and _names_a_gripper(link, joint=False)))

    child_links: dict[str, list[str]] = {}   # link -> its child links
    for child, (holder, _) in parent.items():
        child_links.setdefault(holder, []).append(child)

    ends: dict[str, int] = {}      # end-effector link -> movable joints above it (gripper joints not counted)
    gripped: dict[str, int] = {}   # a gripper's own leaf -> movable joints above it
    carriers: set[str] = set()     # links that carry a gripper
    for leaf in leaves:
        up_to_root = [leaf]   # the leaf, its parent link, ..., the root
        while up_to_root[-1] in parent and len(up_to_root) <= len(links):
            up_to_root.append(parent[up_to_root[-1]][0])
        # the first movable joint from the base that is named for a gripper: its parent link carries it
        first = next((k for k in range(len(up_to_root) - 2, -1, -1)
                      if parent[up_to_root[k]][1] and named(up_to_root[k], joint_only=True)), None)
        if first is None:
            ends.setdefault(leaf, depth.get(leaf, 0))
            holder = parent[leaf][0]   # a link that carries nothing but sensors is an end-effector
            if (_is_sensor(leaf) and holder in parent and not _is_sensor(holder)
                    and all(_is_sensor(child) for child in child_links[holder])):
                ends.setdefault(holder, depth.get(holder, 0))
        else:
            ends.setdefault(up_to_root[first + 1], depth.get(up_to_root[first + 1], 0))
            carriers.add(up_to_root[first + 1])
            gripped[leaf] = depth.get(leaf, 0)
    # deepest first, sensors' frames last; at equal depth a leaf of the arm (a tool frame), then a
    # link carrying a gripper, then a leaf named for a finger or gripper fixed to it
    order = lambda item: (_is_sensor(item[0]), -item[1],  # noqa: E731
                          item[0] not in carriers and named(item[0]), item[0] in carriers, links.index(item[0]))
    tips = [link for link, _ in sorted(ends.items(), key=order)]
    tips += [link for link, _ in sorted(gripped.items(), key=order) if link not in ends]
    return roots[0], tuple(tips), ends[tips[0]] if tips else 0


@lru_cache(maxsize=1)
def available_robots() -> RobotList:
    """Every robot of the installed example-robot-data, sorted by name.

    Returns
    -------
    RobotList
        A tuple of :class:`RobotInfo` (name, file, base link, tip links, movable joints,
        notes), shown as a short table; ``print(...)`` shows every row, ``.names()``
        lists the names, ``[name]`` gives one entry.

    Raises
    ------
    ImportError
        example-robot-data is not installed (``pip install 'robokin[robots]'``).

    Examples
    --------
    >>> from robokin.models import available_robots
    >>> available_robots().names()[:3]  # doctest: +SKIP
    ['TwoDofs', 'a1', 'alex_nub_hands']
    >>> available_robots()["panda"].tip_links[0]  # doctest: +SKIP
    'panda_hand_tcp'
    """
    folder = robots_folder()
    files = sorted(folder.glob("*/**/*.urdf"))
    stems = Counter(f.stem for f in files)
    out = []
    for f in files:
        tree = _tree(f)
        if tree is None:
            continue
        package = f.relative_to(folder).parts[0]
        name = f.stem if stems[f.stem] == 1 else f"{package}/{f.stem}"
        out.append(RobotInfo(name, f, tree[0], tree[1], tree[2], NOTES.get(name, "")))
    return RobotList(sorted(out, key=lambda r: r.name))
