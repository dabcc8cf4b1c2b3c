r"""The link tree of a URDF file: links, joints, the path between two links.

The functions here work on the robot object that yourdfpy parses (its
``links`` and ``joints``), take time linear in the number of links and joints,
and walk the tree iteratively (a chain of 100 000 links is fine: no recursion).
Error messages that would list names list at most :data:`MAX_LISTED_NAMES` of
them and say how many were left out, so that a wrong link name on a large file
gives a message of bounded length.

Used by :func:`robokin.models.from_urdf` (the chain) and
:func:`robokin.models.visual_meshes` (which links move with which chain frame).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from robokin.errors import URDFError

__all__ = [
    "MAX_LISTED_NAMES",
    "ancestors",
    "chain_path",
    "joint_origin",
    "link_tree",
    "name_list",
    "repeated",
    "root_poses",
]

#: At most this many names are listed in an error message; the rest are counted.
MAX_LISTED_NAMES = 20


def name_list(names: Sequence[str], limit: int = MAX_LISTED_NAMES, sep: str = ", ") -> str:
    """``names`` joined by ``sep``, at most ``limit`` of them, then "(and N more)".

    >>> name_list(["a", "b", "c"], limit=2)
    'a, b (and 1 more)'
    """
    shown = sep.join(str(n) for n in names[:limit])
    left = len(names) - limit
    return f"{shown} (and {left:,} more)" if left > 0 else shown


def repeated(names: Iterable[str]) -> list[str]:
    """The names that occur more than once, sorted (linear time)."""
    return sorted(name for name, count in Counter(names).items() if count > 1)


def link_tree(robot: Any, where: str) -> tuple[list[str], dict[str, Any]]:
    """Link names and ``child link -> joint``.

    Parameters
    ----------
    robot : yourdfpy.Robot
        The parsed file (``yourdfpy.URDF.robot``).
    where : str
        How messages name the file (``"URDF file '...'"``).

    Returns
    -------
    links : list of str
        Every link's name, in the order of the file.
    parent_joint : dict
        For every link that is some joint's child: that joint.

    Raises
    ------
    URDFError
        Repeated link or joint names, a joint naming a link that is not in the
        file, a link that is the child of two joints (a closed loop).
    """
    links = [link.name for link in robot.links]
    dup = repeated(links)
    if dup:
        raise URDFError(f"{where}: link names must be unique; repeated: {name_list([repr(x) for x in dup])}")
    dup = repeated(j.name for j in robot.joints)
    if dup:
        raise URDFError(f"{where}: joint names must be unique; repeated: {name_list([repr(x) for x in dup])}")
    known = set(links)
    parent_joint: dict[str, Any] = {}
    for j in robot.joints:
        for role, link in (("parent", j.parent), ("child", j.child)):
            if link not in known:
                raise URDFError(f"{where}: joint {j.name!r} names {role} link {link!r}, which is not a <link> "
                                f"of the file")
        if j.child in parent_joint:
            other = parent_joint[j.child].name
            raise URDFError(
                f"{where}: link {j.child!r} is the child of two joints, {other!r} and {j.name!r}: the links "
                f"form a closed loop, and a URDF (and a serial chain) must be a tree"
            )
        parent_joint[j.child] = j
    return links, parent_joint


def ancestors(link: str, parent_joint: dict[str, Any], where: str) -> list[Any]:
    """The joints from ``link`` up to the root of its tree, nearest first.

    Raises
    ------
    URDFError
        The joints form a cycle (a link is its own ancestor).
    """
    out, seen = [], {link}
    while link in parent_joint:
        j = parent_joint[link]
        out.append(j)
        link = j.parent
        if link in seen:
            cycle = name_list([jj.name for jj in out], sep=" -> ")
            raise URDFError(f"{where}: the joints {cycle} form a closed loop (link {link!r} is its own "
                            f"ancestor); a URDF must be a tree")
        seen.add(link)
    return out


def chain_path(base: str, tip: str, links: list[str], parent_joint: dict[str, Any],
               where: str) -> tuple[list[Any], list[Any]]:
    """The joints from ``base`` up to the common ancestor and from there down to ``tip``.

    Returns
    -------
    up : list
        Joints from ``base_link`` up to the common ancestor (all ``fixed``).
    down : list
        Joints from the common ancestor down to ``tip_link``, in order.

    Raises
    ------
    URDFError
        ``base``/``tip`` is not a link (the message lists at most
        :data:`MAX_LISTED_NAMES` links), they are in different trees, or the
        way up from ``base`` passes a movable joint.
    """
    known = set(links)
    for arg, link in (("base_link", base), ("tip_link", tip)):
        if link not in known:
            raise URDFError(f"{where}: {arg} {link!r} is not a link of the file; its {len(links):,} links "
                            f"are: {name_list(links)}")
    up_tip = ancestors(tip, parent_joint, where)
    above_tip = [tip] + [j.parent for j in up_tip]
    position_above_tip = {link: k for k, link in enumerate(above_tip)}
    up_base = ancestors(base, parent_joint, where)
    above_base = [base] + [j.parent for j in up_base]
    common = next((x for x in above_base if x in position_above_tip), None)
    if common is None:
        raise URDFError(f"{where}: no chain from base_link {base!r} to tip_link {tip!r}: they are in different "
                        f"trees (roots {above_base[-1]!r} and {above_tip[-1]!r})")
    up = up_base[: above_base.index(common)]  # base -> common ancestor
    down = list(reversed(up_tip[: position_above_tip[common]]))  # common ancestor -> tip
    moving = [j for j in up if j.type != "fixed"]
    if moving:
        if common == tip:
            raise URDFError(f"{where}: tip_link {tip!r} is above base_link {base!r} in the tree (their order is "
                            f"swapped?): the chain must run from base_link down to tip_link")
        raise URDFError(
            f"{where}: no chain from base_link {base!r} to tip_link {tip!r}: tip_link is not a descendant of "
            f"base_link (they are on different branches below {common!r}, and the branch to base_link has the "
            f"{moving[0].type} joint {moving[0].name!r}); the links above tip_link are "
            f"{name_list(above_tip, sep=' <- ')}"
        )
    return up, down


def joint_origin(joint: Any, where: str) -> np.ndarray:
    """The joint's ``<origin>`` as a 4×4 transform (identity when absent).

    Raises
    ------
    URDFError
        A non-finite or malformed origin.
    """
    T = np.eye(4) if joint.origin is None else np.asarray(joint.origin, dtype=float)
    if T.shape != (4, 4) or not np.isfinite(T).all():
        raise URDFError(f"{where}: joint {joint.name!r} has a non-finite or malformed <origin>")
    return T


def root_poses(robot: Any, where: str) -> dict[str, np.ndarray]:
    """Pose (4×4) of every link in the root of its tree, all joints at zero.

    Iterative, parents before children, in time linear in the number of links,
    whatever the order of the links and joints in the file.
    """
    links, parent_joint = link_tree(robot, where)
    children: dict[str, list[Any]] = {}
    for j in robot.joints:
        children.setdefault(j.parent, []).append(j)
    poses: dict[str, np.ndarray] = {}
    todo = [link for link in links if link not in parent_joint]  # roots
    for root in todo:
        poses[root] = np.eye(4)
    while todo:
        link = todo.pop()
        for j in children.get(link, ()):
            poses[j.child] = poses[link] @ joint_origin(j, where)
            todo.append(j.child)
    for link in links:  # links on a cycle are never reached from a root
        if link not in poses:
            ancestors(link, parent_joint, where)  # raises, naming the loop
    return poses
