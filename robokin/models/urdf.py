r"""Serial chains from URDF files.

A URDF (Unified Robot Description Format, the XML format of ROS) describes a
robot as a tree of *links* connected by *joints*. Each joint has

* an ``<origin xyz="x y z" rpy="roll pitch yaw"/>``: the pose of the child
  link's frame in the parent link's frame when the joint is at zero,
  :math:`{}^{P}\mathbf{T}_{C}(0) = \mathbf{T}(x, y, z)\,\mathbf{R}_z(\text{yaw})\,
  \mathbf{R}_y(\text{pitch})\,\mathbf{R}_x(\text{roll})` (fixed-axis roll–pitch–yaw,
  the convention of this package);
* an ``<axis xyz="..."/>`` in the child frame (default ``1 0 0``), about which a
  ``revolute``/``continuous`` joint turns and along which a ``prismatic`` joint
  slides: :math:`{}^{P}\mathbf{T}_{C}(q) = {}^{P}\mathbf{T}_{C}(0)\,
  \mathbf{R}(\mathbf{a}, q)` or :math:`{}^{P}\mathbf{T}_{C}(0)\,\mathbf{T}(q\,\mathbf{a})`;
* ``<limit lower upper/>`` in rad or m (required for revolute and prismatic
  joints; a missing ``lower``/``upper`` attribute is 0, as in the URDF
  specification).

:func:`from_urdf` reads the file with `yourdfpy <https://github.com/clemense/yourdfpy>`_
(an optional dependency: ``pip install robokin[robots]``), walks the tree from
the base link to the tip link and writes the path as elementary transforms: one
constant transform (:func:`robokin.chains.Fixed`) per joint origin, with the
origins of ``fixed`` joints multiplied into their neighbours, followed by the
joint's ``Rx``/``Ry``/``Rz`` (or ``Tx``/``Ty``/``Tz``) when its axis is a
coordinate axis, which is the usual case. The result is the same
:class:`~robokin.chains.SerialChain` as every hand-built model.

:func:`robot_description` gives the path of the URDF of a few robots shipped by
the ``example-robot-data`` package (also in ``robokin[robots]``).
"""

from __future__ import annotations

import contextlib
import importlib.metadata
import logging
import math
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from robokin.chains import Element, Fixed, Rx, Ry, Rz, SerialChain, Tx, Ty, Tz
from robokin.errors import DomainError, URDFError, URDFNotFoundError
from robokin.models.robot_library import available_robots
from robokin.models.urdf_tree import chain_path, joint_origin, link_tree, name_list
from robokin.transforms import rotation_exp

__all__ = ["from_urdf", "robot_description", "ROBOT_DESCRIPTIONS", "CONTINUOUS_LIMITS"]

#: Limits (rad) given to ``continuous`` joints, which have none in a URDF: one full turn.
CONTINUOUS_LIMITS = (-math.pi, math.pi)

#: Robots of :func:`robot_description`: name -> (file under example-robot-data's ``robots``
#: directory, suggested base link, suggested tip link).
ROBOT_DESCRIPTIONS = {
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "base", "tool0"),
    "baxter": ("baxter_description/urdf/baxter.urdf", "torso", "left_hand_link"),
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8"),
}

_INSTALL = "pip install 'robokin[robots]'"
_SUPPORTED = ("revolute", "continuous", "prismatic", "fixed")
_KNOWN = _SUPPORTED + ("floating", "planar")
_ROTATIONS = (Rx, Ry, Rz)
_TRANSLATIONS = (Tx, Ty, Tz)


# ------------------------------------------------------------------ packaged robots
def robot_description(name: str) -> Path:
    """Path of the URDF file of a robot from the ``example-robot-data`` package.

    Parameters
    ----------
    name : str
        The robot: one of the three the chapters use (their files and the links
        to pass to :func:`from_urdf` below), or the name of any URDF file of
        example-robot-data (:func:`available_robots` lists them, about seventy,
        with their base and tip links: ``"kinova"``, ``"xarm7"``, ``"ur5_robot"``,
        ``"solo12"``, ...):

        ==========  ==========================================  ===============  ==================
        name        file (under ``example-robot-data/robots``)  base link        tip link
        ==========  ==========================================  ===============  ==================
        ``ur10``    ``ur_description/urdf/ur10_robot.urdf``     ``base``         ``tool0``
        ``baxter``  ``baxter_description/urdf/baxter.urdf``     ``torso``        ``left_hand_link``
        ``panda``   ``panda_description/urdf/panda.urdf``       ``panda_link0``  ``panda_link8``
        ==========  ==========================================  ===============  ==================

        (also in :data:`ROBOT_DESCRIPTIONS`).

    Returns
    -------
    pathlib.Path
        The URDF file. Its meshes are named ``package://example-robot-data/robots/...``;
        yourdfpy's default file-name handler finds them (it strips the package
        name and searches the directories above the URDF file), so
        ``yourdfpy.URDF.load(path)`` also loads the meshes.

    Raises
    ------
    TypeError
        ``name`` is not a string.
    DomainError
        Unknown ``name`` (the message lists some names and points to
        :func:`available_robots`).
    ImportError
        ``example-robot-data`` is not installed (``pip install 'robokin[robots]'``).

    Examples
    --------
    >>> from robokin.models import from_urdf, robot_description
    >>> arm = from_urdf(robot_description("panda"), "panda_link0", "panda_link8")  # doctest: +SKIP
    """
    if not isinstance(name, str):
        raise TypeError(f"name must be a robot name such as {sorted(ROBOT_DESCRIPTIONS)} (str); got "
                        f"{type(name).__name__} {name!r}"[:200])
    if name not in ROBOT_DESCRIPTIONS:
        robots = {r.name: r for r in available_robots()}
        if name in robots:
            return robots[name].path
        raise DomainError(f"name must be one of {sorted(ROBOT_DESCRIPTIONS)} or a robot of example-robot-data "
                          f"({name_list(sorted(robots), limit=12)}; robokin.models.available_robots() lists "
                          f"them with their links); got {name!r}")
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        raise ImportError(
            f"robot_description({name!r}) needs the URDF files of the example-robot-data package, which is "
            f"not installed: {_INSTALL}"
        ) from None
    path = Path(str(dist.locate_file(f"cmeel.prefix/share/example-robot-data/robots/{ROBOT_DESCRIPTIONS[name][0]}")))
    if not path.is_file():
        raise URDFNotFoundError(
            f"example-robot-data {dist.version} is installed but has no {ROBOT_DESCRIPTIONS[name][0]} "
            f"(looked for {path}); reinstall it: {_INSTALL}"
        )
    return path


# ------------------------------------------------------------------ reading the file
@contextlib.contextmanager
def quiet_yourdfpy() -> Iterator[None]:
    """Silence yourdfpy's logger (it logs, rather than raises, about meshes and XML recovery)."""
    logger = logging.getLogger("yourdfpy.urdf")
    before = logger.disabled
    logger.disabled = True
    try:
        yield
    finally:
        logger.disabled = before


def _import_yourdfpy() -> Any:
    try:
        import yourdfpy
    except ImportError as exc:
        raise ImportError(f"from_urdf needs the URDF parser yourdfpy, which is not installed ({exc}): "
                          f"{_INSTALL}  (or: pip install yourdfpy)") from exc
    return yourdfpy


def _check_structure(root: Any, where: str) -> None:
    """Clear messages for what yourdfpy would turn into a KeyError/AttributeError."""
    if root.tag != "robot":
        raise URDFError(f"{where} is not a URDF file: its root element is <{root.tag}>, expected <robot>")
    if not root.get("name"):
        raise URDFError(f"{where}: the <robot> element (line {root.sourceline}) has no name attribute")
    for el in root.findall("link"):
        if not el.get("name"):
            raise URDFError(f"{where}: the <link> on line {el.sourceline} has no name attribute")
    for el in root.findall("joint"):
        label = f"joint {el.get('name')!r} (line {el.sourceline})" if el.get("name") else \
            f"the <joint> on line {el.sourceline}"
        if not el.get("name"):
            raise URDFError(f"{where}: {label} has no name attribute")
        for tag in ("parent", "child"):
            sub = el.find(tag)
            if sub is None or not sub.get("link"):
                raise URDFError(f'{where}: {label} has no <{tag} link="..."/>')
        if el.get("type") is None:
            raise URDFError(f"{where}: {label} has no type attribute (one of {', '.join(_KNOWN)})")


def parse_urdf(path: Path, where: str) -> Any:
    """Parse ``path`` with yourdfpy (no meshes, no scene graph); URDFError if it is not a URDF."""
    yourdfpy = _import_yourdfpy()
    from lxml import etree  # a dependency of yourdfpy

    try:
        root = etree.parse(str(path)).getroot()
    except etree.XMLSyntaxError as exc:
        hint = " (a .xacro file must be expanded first: xacro file.urdf.xacro > file.urdf)" \
            if path.name.endswith(".xacro") else ""
        raise URDFError(f"{where} is not well-formed XML: {exc}{hint}") from None
    except OSError as exc:
        raise URDFError(f"{where} cannot be read: {exc}") from None
    _check_structure(root, where)
    try:
        with quiet_yourdfpy():
            return yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False,
                                      build_collision_scene_graph=False, load_collision_meshes=False)
    except (ValueError, TypeError, KeyError, AttributeError, IndexError) as exc:
        raise URDFError(f"{where} is not a valid URDF: {_bad_number(root) or f'{type(exc).__name__}: {exc}'}") \
            from None


_NUMERIC = {"xyz": 3, "rpy": 3, "lower": 1, "upper": 1, "effort": 1, "velocity": 1, "multiplier": 1, "offset": 1}


def _bad_number(root: Any) -> str | None:
    """Where a numeric attribute of the kinematic elements is not a number (for the message)."""
    for el in root.iter("origin", "axis", "limit", "mimic"):
        for attr, count in _NUMERIC.items():
            text = el.get(attr)
            if text is None:
                continue
            try:
                values = [float(x) for x in text.split()]
            except ValueError:
                values = []
            if len(values) != count:
                owner = el.getparent()
                return (f"<{el.tag} {attr}={text!r}> on line {el.sourceline} (in <{owner.tag} "
                        f"name={owner.get('name')!r}>) must be {count} number{'s' if count > 1 else ''}")
    return None


# ------------------------------------------------------------------ joints -> elements
def _z_to(axis: np.ndarray) -> np.ndarray:
    """A rotation ``R`` with ``R @ [0, 0, 1] = axis`` (unit ``axis``)."""
    z = np.array([0.0, 0.0, 1.0])
    c = float(np.clip(axis @ z, -1.0, 1.0))
    w = np.cross(z, axis)
    s = float(np.linalg.norm(w))
    if s < 1e-15:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    return np.asarray(rotation_exp(w / s * math.atan2(s, c)), dtype=float)


def _joint_limits(j: Any, where: str) -> tuple[float, float]:
    if j.type == "continuous":
        return CONTINUOUS_LIMITS
    if j.limit is None:
        raise URDFError(f"{where}: {j.type} joint {j.name!r} has no <limit lower upper/> (required by the URDF "
                        f"specification for revolute and prismatic joints)")
    lo = 0.0 if j.limit.lower is None else float(j.limit.lower)
    hi = 0.0 if j.limit.upper is None else float(j.limit.upper)
    if not (math.isfinite(lo) and math.isfinite(hi)) or lo > hi:
        raise URDFError(f"{where}: joint {j.name!r} has limits lower={lo}, upper={hi}; expected finite "
                        f"lower <= upper")
    return lo, hi


def _joint_elements(j: Any, before: np.ndarray, where: str) -> tuple[list[Element], np.ndarray, bool]:
    """Elements of one movable joint (``before`` = constant transform accumulated up to its origin).

    Returns the elements, the constant transform left over after the joint, and
    whether the chain frame after the joint is the child link's frame.
    """
    if j.mimic is not None:
        raise URDFError(f"{where}: joint {j.name!r} mimics joint {j.mimic.joint!r} (<mimic>); mimic joints are "
                        f"not supported: robokin chains have independent joints. Choose a tip_link before it.")
    if j.type in ("floating", "planar"):
        what = "a free rigid-body motion" if j.type == "floating" else "motion in a plane"
        raise URDFError(f"{where}: joint {j.name!r} is {j.type} ({what}), which is not supported: a chain's "
                        f"joints are revolute, continuous, prismatic or fixed")
    if j.type not in _SUPPORTED:
        raise URDFError(f"{where}: joint {j.name!r} has type {j.type!r}; a URDF joint type is one of "
                        f"{', '.join(_KNOWN)}")
    name = j.name
    if not name or name != name.strip() or name[0] in "+-":
        raise URDFError(f"{where}: joint name {name!r} cannot name a robokin joint (leading sign or spaces)")
    axis = np.asarray(j.axis, dtype=float).ravel()
    if axis.shape != (3,) or not np.isfinite(axis).all() or not np.any(axis):
        raise URDFError(f"{where}: joint {name!r} has axis {axis.tolist()}; expected three finite numbers, "
                        f"not all zero")
    axis = axis / np.linalg.norm(axis)
    limits = _joint_limits(j, where)
    factories = _ROTATIONS if j.type in ("revolute", "continuous") else _TRANSLATIONS
    nonzero = np.flatnonzero(axis)
    els: list[Element] = []
    if len(nonzero) == 1:  # along ±x, ±y or ±z of the child frame
        k = int(nonzero[0])
        if not np.array_equal(before, np.eye(4)):
            els.append(Fixed(before))
        els.append(factories[k](("-" if axis[k] < 0 else "") + name, limits=limits))
        return els, np.eye(4), True
    R = np.eye(4)
    R[:3, :3] = _z_to(axis)
    els += [Fixed(before @ R), factories[2](name, limits=limits)]
    return els, R.T, False


# ------------------------------------------------------------------ public builder
def from_urdf(path: str | os.PathLike, base_link: str, tip_link: str, *, name: str | None = None) -> SerialChain:
    r"""Serial chain from a URDF file, from ``base_link`` to ``tip_link``.

    Parameters
    ----------
    path : str or os.PathLike
        The URDF file (plain URDF; expand a ``.xacro`` file with ``xacro`` first).
        :func:`robot_description` gives the files of a few robots.
    base_link : str
        Link whose frame is the chain's base frame.
    tip_link : str
        Link whose frame is the end-effector frame; it must be a descendant of
        ``base_link``, or of a link that ``base_link`` hangs from by ``fixed``
        joints only (as the UR's ``base`` frame hangs from ``base_link``).
    name : str, optional
        Name of the chain (default: the ``<robot name>`` of the file).

    Returns
    -------
    SerialChain
        One joint per ``revolute``, ``continuous`` or ``prismatic`` joint on the
        path, in order from the base, named as in the file. Limits: the URDF's
        ``<limit lower upper>``; ``continuous`` joints get ``(-π, π)`` (one full
        turn, :data:`CONTINUOUS_LIMITS`). ``fixed`` joints are folded into the
        neighbouring constant transforms: those before the first movable joint
        into the base, those after the last one into ``tool``.
        Frames (:attr:`~SerialChain.frame_names`): ``base_link``, then the child
        link of each movable joint, then ``tip_link``. Frame i is exactly the
        URDF frame of joint i's child link when the joint axis is along a
        coordinate axis (``±x``, ``±y``, ``±z``, the usual case); for another
        axis it is that frame turned so that its z axis is the joint axis (the
        chain turns joints about coordinate axes only), and ``fk`` of the tip is
        exact either way.

    Raises
    ------
    TypeError
        ``path`` not a string or path, ``base_link``/``tip_link``/``name`` not
        strings.
    ImportError
        yourdfpy is not installed (``pip install 'robokin[robots]'``).
    URDFError
        The file does not exist (:class:`~robokin.errors.URDFNotFoundError`),
        is not well-formed XML or not a URDF; ``base_link`` or ``tip_link`` is
        not a link of the file (the message lists the links); ``tip_link`` is
        not a descendant of ``base_link``; the links form a closed loop; a joint
        on the path is ``floating``, ``planar``, a ``<mimic>`` joint, has no
        ``<limit>`` or a zero axis; there is no movable joint between the two
        links. Messages name the file and the link or joint.

    Notes
    -----
    The joint transform is
    :math:`{}^{P}\mathbf{T}_{C}(q) = \mathbf{T}(\mathbf{p})\,\mathbf{R}_z(y)\,\mathbf{R}_y(p)\,
    \mathbf{R}_x(r)\;\mathbf{R}(\mathbf{a}, q)` for a revolute joint with
    ``<origin xyz="p" rpy="r p y"/>`` and ``<axis xyz="a"/>``
    (ROS REP 103 / the URDF specification; Siciliano et al. 2009, §2.4.2 for
    roll–pitch–yaw). The file is parsed by yourdfpy without meshes, so nothing
    is logged about mesh files that cannot be found.

    Examples
    --------
    >>> from robokin.models import from_urdf, robot_description
    >>> ur = from_urdf(robot_description("ur10"), "base", "tool0")  # doctest: +SKIP
    >>> ur.joint_names  # doctest: +SKIP
    ['shoulder_pan_joint', 'shoulder_lift_joint', 'elbow_joint', 'wrist_1_joint', 'wrist_2_joint', 'wrist_3_joint']
    """
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a str or os.PathLike naming a URDF file; got {type(path).__name__} "
                        f"{path!r}"[:200])
    for arg, value in (("base_link", base_link), ("tip_link", tip_link)):
        if not isinstance(value, str):
            raise TypeError(f"{arg} must be a link name (str); got {type(value).__name__} {value!r}"[:200])
    if name is not None and not isinstance(name, str):
        raise TypeError(f"name must be a str or None; got {type(name).__name__} {name!r}"[:200])
    file = Path(os.fsdecode(os.fspath(path)))
    where = f"URDF file {str(file)!r}"
    if not file.exists():
        raise URDFNotFoundError(f"path: {where} does not exist")
    if not file.is_file():
        raise URDFNotFoundError(f"path: {where} is not a file")
    urdf = parse_urdf(file, where)
    robot = urdf.robot
    links, parent_joint = link_tree(robot, where)
    up, joints = chain_path(base_link, tip_link, links, parent_joint, where)

    elements: list[Element] = []
    frame_names = [base_link]
    T = np.eye(4)  # constant transform not yet written out
    for j in up:  # base_link hangs below the common ancestor by fixed joints: start with their inverse
        T = T @ np.linalg.inv(joint_origin(j, where))
    for j in joints:
        if j.type == "fixed":
            T = T @ joint_origin(j, where)
            continue
        els, T, exact = _joint_elements(j, T @ joint_origin(j, where), where)
        elements += els
        frame_names.append(j.child if exact else f"{j.name}_axis")
    if not elements or not any(el.is_joint for el in elements):
        kinds = ", ".join(f"{j.name} ({j.type})" for j in joints) or "none, base_link is tip_link"
        raise URDFError(f"{where}: no movable joint between base_link {base_link!r} and tip_link {tip_link!r} "
                        f"(joints on the path: {kinds}); a chain needs at least one")
    frame_names.append(tip_link)
    try:
        return SerialChain(elements, tool=T, frame_names=frame_names, name=robot.name if name is None else name)
    except (ValueError, TypeError) as exc:  # e.g. a transform that is not a rigid motion
        raise URDFError(f"{where}: cannot build the chain from {base_link!r} to {tip_link!r}: {exc}") from None
