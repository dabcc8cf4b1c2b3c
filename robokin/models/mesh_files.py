r"""Where a URDF's mesh files may be read from: the robot's own package, and no further.

A URDF names its mesh files as ``package://NAME/path``, ``file:///abs/path``, an
absolute path or a path relative to the URDF file. A URDF downloaded from the
internet could name any file of the machine (``../../../home/me/secret.stl``,
``/etc/...``, ``package://x/../../..``), and its geometry would end up in a
scene and in a page a student shares. So :func:`resolve_mesh_file` opens
nothing; it only decides, from the names alone and the resolved real path
(symbolic links followed), whether a mesh file lies inside an *allowed root*:

1. the robot's package: the nearest folder at or above the URDF file's folder
   that holds a ``package.xml`` (the ROS convention); without one, for a
   ``package://NAME/...`` name the nearest folder above the URDF named ``NAME``;
   without either, the URDF file's own folder;
2. the packages robokin knows (:func:`known_packages`: example-robot-data's
   ``robots`` folder when it is installed);
3. folders the caller allows explicitly (``mesh_roots=`` of
   :func:`robokin.models.visual_meshes`).

``package://NAME/...`` is looked up only in an allowed root whose package is
``NAME`` (its ``package.xml`` ``<name>``, or the folder's name); other schemes
(``http://``, ...) are refused. A refused file is never opened.
"""

from __future__ import annotations

import importlib.metadata
import os
import xml.etree.ElementTree as ElementTree
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

__all__ = ["MeshRoot", "allowed_roots", "known_packages", "resolve_mesh_file"]

_PACKAGE = "package://"
_FILE = "file://"


@dataclass(frozen=True)
class MeshRoot:
    """A folder mesh files may be read from, and the package name it answers to."""

    folder: Path
    package: str | None = None

    def holds(self, path: Path) -> bool:
        """Whether ``path`` (already resolved) lies inside this folder."""
        return path == self.folder or self.folder in path.parents


def _package_name(folder: Path) -> str | None:
    """The ``<name>`` of ``folder/package.xml``, or None when absent or unreadable."""
    try:
        root = ElementTree.parse(folder / "package.xml").getroot()
    except (OSError, ElementTree.ParseError):
        return None
    name = root.findtext("name")
    return name.strip() if name else None


@lru_cache(maxsize=1)
def known_packages() -> tuple[MeshRoot, ...]:
    """The packages robokin knows: example-robot-data's robots, when it is installed."""
    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        return ()
    folder = Path(str(dist.locate_file("cmeel.prefix/share/example-robot-data")))
    if not folder.is_dir():
        return ()
    return (MeshRoot(folder.resolve(), "example-robot-data"),)


def _robot_package(urdf_file: Path, names: Sequence[str]) -> MeshRoot:
    """The robot's own package (rule 1 of the module docstring)."""
    folder = urdf_file.parent
    for candidate in (folder, *folder.parents):
        if (candidate / "package.xml").is_file():
            return MeshRoot(candidate, _package_name(candidate) or candidate.name)
    wanted = {n[len(_PACKAGE):].split("/", 1)[0] for n in names if n.startswith(_PACKAGE)}
    for candidate in folder.parents:
        if candidate.name in wanted:
            return MeshRoot(candidate, candidate.name)
    return MeshRoot(folder, None)


def allowed_roots(urdf_file: Path, names: Sequence[str], extra: Sequence[Path] = ()) -> tuple[MeshRoot, ...]:
    """The allowed roots for the mesh ``names`` of ``urdf_file`` (resolved paths).

    Parameters
    ----------
    urdf_file : pathlib.Path
        The URDF file (resolved).
    names : sequence of str
        The mesh file names of the URDF (to find a package folder by name).
    extra : sequence of pathlib.Path
        Folders the caller allows as well (each is also a package named as the
        folder).
    """
    roots = [_robot_package(urdf_file, names), *known_packages()]
    roots += [MeshRoot(Path(f).resolve(), Path(f).resolve().name) for f in extra]
    return tuple(MeshRoot(r.folder.resolve(), r.package) for r in roots)


def resolve_mesh_file(name: str, urdf_file: Path, roots: Sequence[MeshRoot]) -> tuple[Path | None, str]:
    """The file a mesh name stands for, if it lies inside an allowed root.

    Parameters
    ----------
    name : str
        The ``filename`` attribute of a URDF ``<mesh>``.
    urdf_file : pathlib.Path
        The URDF file (resolved); relative names are relative to its folder.
    roots : sequence of MeshRoot
        From :func:`allowed_roots`.

    Returns
    -------
    path : pathlib.Path or None
        The resolved file, or None when it must not be read.
    reason : str
        Empty when ``path`` is given; otherwise why the name was refused (for
        the warning).
    """
    text = name.strip()
    if not text:
        return None, "an empty file name"
    if text.startswith(_PACKAGE):
        package, _, rest = text[len(_PACKAGE):].partition("/")
        matching = [r for r in roots if r.package == package]
        if not matching:
            return None, (f"package {package!r} is neither the robot's package nor one robokin knows "
                          f"({', '.join(sorted({r.package for r in roots if r.package})) or 'none'})")
        for root in matching:
            path = (root.folder / rest).resolve()
            if root.holds(path):
                return path, ""
        return None, f"it leads out of package {package!r} ({matching[0].folder})"
    if text.startswith(_FILE):
        candidate = Path(text[len(_FILE):])
        if not candidate.is_absolute():
            return None, "a file:// name must be an absolute path"
    elif "://" in text:
        return None, f"the scheme {text.split('://', 1)[0]!r}:// is not read (only package:// and files)"
    else:
        candidate = Path(text) if os.path.isabs(text) else urdf_file.parent / text
    path = candidate.resolve()
    if any(root.holds(path) for root in roots):
        return path, ""
    return None, "it lies outside the robot's package (" + ", ".join(str(r.folder) for r in roots) + ")"
