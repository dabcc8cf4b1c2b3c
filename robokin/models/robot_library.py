r"""The robots of the installed ``example-robot-data`` package, listed with their base and tip links.

:func:`available_robots` finds every URDF file the package ships (about seventy:
arms, legged robots, humanoids, hands, drones) and reads, without building
anything, its link tree: the root link (the natural ``base_link`` of
:func:`robokin.models.from_urdf`) and its leaf links (candidate ``tip_link``\ s),
the deepest first -- for an arm, the first one is its flange or tool frame.
:func:`robokin.models.robot_description` accepts any of their names.

The listing reads the files' XML only (``xml.etree``): about 0.2 s for the
whole package, once per process.
"""

from __future__ import annotations

import importlib.metadata
import xml.etree.ElementTree as ElementTree
from collections import Counter
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

__all__ = ["RobotInfo", "available_robots", "robots_folder"]

_INSTALL = "pip install 'robokin[robots]'"


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
        Its leaf links, the one with the most movable joints above it first.
    movable_joints : int
        Revolute, continuous and prismatic joints from ``base_link`` to ``tip_links[0]``.
    """

    name: str
    path: Path
    base_link: str
    tip_links: tuple[str, ...]
    movable_joints: int


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
    """``(root, leaves deepest first, movable joints to the first leaf)``, or None if unreadable."""
    try:
        root = ElementTree.parse(path).getroot()
    except (OSError, ElementTree.ParseError):
        return None
    links = [name for el in root.findall("link") if (name := el.get("name"))]
    parent: dict[str, tuple[str, bool]] = {}
    children: set[str] = set()
    for joint in root.findall("joint"):
        p, c = joint.find("parent"), joint.find("child")
        parent_link = p.get("link") if p is not None else None
        child_link = c.get("link") if c is not None else None
        if not parent_link or not child_link:
            continue
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
    leaves = sorted((link for link in links if link not in children and link in parent),
                    key=lambda link: (-depth.get(link, 0), links.index(link)))
    return roots[0], tuple(leaves), depth.get(leaves[0], 0) if leaves else 0


@lru_cache(maxsize=1)
def available_robots() -> tuple[RobotInfo, ...]:
    """Every robot of the installed example-robot-data, sorted by name.

    Returns
    -------
    tuple of RobotInfo
        Name, file, base link and tip links of each URDF file.

    Raises
    ------
    ImportError
        example-robot-data is not installed (``pip install 'robokin[robots]'``).

    Examples
    --------
    >>> from robokin.models import available_robots
    >>> [r.name for r in available_robots()][:3]  # doctest: +SKIP
    ['TwoDofs', 'a1', 'alex_nub_hands']
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
        out.append(RobotInfo(name, f, tree[0], tree[1], tree[2]))
    return tuple(sorted(out, key=lambda r: r.name))
