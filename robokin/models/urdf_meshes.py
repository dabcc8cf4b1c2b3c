r"""Visual meshes of a URDF chain, for drawing the real robot.

A URDF link may carry ``<visual>`` elements: a geometry (a mesh file --
``.stl``, ``.dae``, ``.obj`` -- or a box, cylinder, sphere) placed by an
``<origin>`` in the link's frame, with an optional ``<material>`` colour.
:func:`visual_meshes` reads them for the chain ``from_urdf(path, base_link,
tip_link)`` and gives, for each frame of that chain (in the order of
``chain.frames(q)``), the triangle meshes rigidly attached to it, with their
vertices in that frame: the visuals of the frame's link and of every link
hanging from it by ``fixed`` joints only (links that move with joints off the
chain -- Baxter's other arm, a gripper's fingers -- are left out).

The meshes are read with `trimesh <https://trimesh.org>`_, merged per frame and
colour, and decimated with quadric edge collapse (`fast-simplification
<https://github.com/pyvista/fast-simplification>`_) to a total of about
``max_bytes`` of float32 vertices and uint32 triangle indices, so that a static
page that shows the robot stays small. Results are cached: a robot's meshes are
read once per process. For the robots the book draws
(:data:`~robokin.models.mesh_store.STORED_ROBOTS`: UR10, Baxter, Panda, Kinova, at the
default budget) the result is stored in the package (``robokin/models/mesh_data``,
written by ``python tools/authoring/build_meshes.py``) and read from there when the installed
URDF and mesh files are the ones it was computed from (:mod:`robokin.models.mesh_store`);
that takes milliseconds instead of seconds and imports neither trimesh nor the URDF
parser. A mesh file that cannot be read is skipped with one
:class:`~robokin.errors.MeshWarning` naming it; the frames it belongs to are
listed in :attr:`RobotMeshes.unreadable` (the views draw them as a stick figure).

All three libraries are optional (``pip install 'robokin[robots]'``) and imported
only when :func:`visual_meshes` is called.
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from collections.abc import Sequence
from typing import Any

import numpy as np

from robokin.errors import DomainError, MeshWarning, URDFNotFoundError
from robokin.chains import SerialChain
from robokin.models.urdf import from_urdf, parse_urdf, quiet_yourdfpy
from robokin.models.mesh_files import MeshRoot, allowed_roots, known_packages, resolve_mesh_file
from robokin.models.mesh_store import (BUILD_COMMAND, STORED_ROBOTS, MeshRecord, StaleMeshData, chain_arrays,
                                       read_record, record_chain, stored_robot)
from robokin.models.urdf_tree import chain_path, link_tree, name_list, root_poses

__all__ = ["visual_meshes", "visual_chain", "VisualMesh", "RobotMeshes", "DEFAULT_MESH_BYTES",
           "DEFAULT_MESH_COLOR", "MAX_MESH_FILE_BYTES", "MAX_SOURCE_TRIANGLES", "packaged_meshes", "record_meshes",
           "mesh_record"]

#: Default budget (bytes of float32 vertices + uint32 indices) of all meshes of one robot.
DEFAULT_MESH_BYTES = 150_000

#: Colour (0xRRGGBB) of visuals with no colour of their own and no URDF ``<material>``.
DEFAULT_MESH_COLOR = 0xA0A0A0

#: Mesh files larger than this (bytes) are not read (a MeshWarning says so): trimesh needs about
#: 1 kB of memory per triangle while it reads a file (a binary STL has 50 bytes per triangle).
MAX_MESH_FILE_BYTES = 16_000_000

#: At most this many triangles are read for one robot (all files together) before decimation;
#: files past it are not read (a MeshWarning says so). Keeps one call under about 500 MB.
MAX_SOURCE_TRIANGLES = 1_000_000

_INSTALL = "pip install 'robokin[robots]'"
_MIN_FACES = 16  # a colour group keeps at least this many triangles (when it has them)
_GRID = 2.0 ** 0.5 * 1e7  # vertices are rounded to 1/_GRID m before decimation (_snap)


# ------------------------------------------------------------------ results
@dataclass(frozen=True, eq=False)
class VisualMesh:
    """One triangle mesh rigidly attached to a chain frame.

    Attributes
    ----------
    vertices : numpy.ndarray
        (V, 3) float32, in metres, in the frame the mesh is attached to.
    faces : numpy.ndarray
        (F, 3) uint32, vertex indices of each triangle (counter-clockwise seen from outside).
    color : int
        0xRRGGBB.
    opacity : float
        In (0, 1].
    links : tuple of str
        The URDF links whose visuals make up this mesh.
    """

    vertices: np.ndarray
    faces: np.ndarray
    color: int
    opacity: float = 1.0
    links: tuple[str, ...] = ()

    @property
    def triangles(self) -> int:
        return int(self.faces.shape[0])

    @property
    def nbytes(self) -> int:
        """Bytes of float32 vertices plus uint32 indices."""
        return int(self.vertices.nbytes + self.faces.nbytes)


@dataclass(frozen=True, eq=False)
class RobotMeshes:
    """The visual meshes of a chain, frame by frame (what :func:`visual_meshes` returns).

    Attributes
    ----------
    frame_names : tuple of str
        The chain's frame names (``n + 2`` of them).
    frames : tuple of tuple of VisualMesh
        ``frames[i]``: the meshes attached to frame ``i``, vertices in frame ``i``.
    unreadable : tuple of tuple of str
        ``unreadable[i]``: mesh files of frame ``i`` that could not be read (empty
        when all were); such a frame is drawn as a stick figure.
    source : str
        The URDF file.
    original_triangles : int
        Triangles before decimation.
    """

    frame_names: tuple[str, ...]
    frames: tuple[tuple[VisualMesh, ...], ...]
    unreadable: tuple[tuple[str, ...], ...]
    source: str = ""
    original_triangles: int = 0

    @property
    def triangles(self) -> int:
        """Triangles of all meshes."""
        return sum(m.triangles for ms in self.frames for m in ms)

    @property
    def nbytes(self) -> int:
        """Bytes of float32 vertices plus uint32 indices of all meshes."""
        return sum(m.nbytes for ms in self.frames for m in ms)

    def __len__(self) -> int:
        return len(self.frames)

    def __repr__(self) -> str:
        bad = sum(1 for u in self.unreadable if u)
        return (f"<RobotMeshes {Path(self.source).name or '?'}: {len(self.frames)} frames, "
                f"{sum(len(ms) for ms in self.frames)} meshes, {self.triangles} triangles, {self.nbytes} bytes"
                f"{f', {bad} frame(s) unreadable' if bad else ''}>")


# ------------------------------------------------------------------ optional imports
def _import_mesh_libraries() -> tuple[Any, Any]:
    try:
        import fast_simplification
        import trimesh
    except ImportError as exc:
        raise ImportError(f"visual meshes need trimesh and fast-simplification, which are not installed ({exc}): "
                          f"{_INSTALL}") from exc
    return trimesh, fast_simplification


# ------------------------------------------------------------------ which links belong to which frame
def _chain_links(urdf: Any, base_link: str, tip_link: str, where: str) -> list[str]:
    """The link of each chain frame: base_link, the child of each movable joint, tip_link."""
    links, parent_joint = link_tree(urdf.robot, where)
    _, down = chain_path(base_link, tip_link, links, parent_joint, where)
    return [base_link] + [j.child for j in down if j.type != "fixed"] + [tip_link]


def _rigid_groups(urdf: Any, frame_links: list[str]) -> list[list[str]]:
    """Links rigidly attached (through fixed joints only) to each frame's link; each link once."""
    neighbours: dict[str, list[str]] = {link.name: [] for link in urdf.robot.links}
    for j in urdf.robot.joints:
        if j.type == "fixed":
            neighbours[j.parent].append(j.child)
            neighbours[j.child].append(j.parent)
    seen: set[str] = set()
    groups = []
    for start in frame_links:
        group, todo = [], [start]
        while todo:
            link = todo.pop(0)
            if link in seen:
                continue
            seen.add(link)
            group.append(link)
            todo += neighbours[link]
        groups.append(group)
    return groups


# ------------------------------------------------------------------ reading one visual
def _rgba(color: Any) -> tuple[int, int, int, int] | None:
    if color is None:
        return None
    c = np.asarray(getattr(color, "rgba", color), dtype=float).ravel()
    if c.size < 3 or not np.isfinite(c).all():
        return None
    c = np.concatenate([c[:4], [1.0] * (4 - c[:4].size)])
    return tuple(int(round(255 * min(max(v, 0.0), 1.0))) for v in c)  # type: ignore[return-value]


def _visual_color(visual: Any, materials: dict[str, Any]) -> tuple[int, int, int, int] | None:
    mat = visual.material
    if mat is None:
        return None
    rgba = _rgba(mat.color)
    if rgba is None and mat.name in materials:
        rgba = _rgba(materials[mat.name].color)
    return rgba


def _primitive(trimesh: Any, geometry: Any) -> Any:
    if geometry.box is not None:
        return trimesh.creation.box(extents=np.asarray(geometry.box.size, dtype=float))
    if geometry.cylinder is not None:
        return trimesh.creation.cylinder(radius=float(geometry.cylinder.radius),
                                         height=float(geometry.cylinder.length), sections=24)
    if geometry.sphere is not None:
        return trimesh.creation.icosphere(subdivisions=2, radius=float(geometry.sphere.radius))
    return None


class _MeshReader:
    """Reads the mesh files of one URDF within the allowed roots and the memory caps.

    Refused and unreadable files are remembered with their reason (for one
    warning), never opened when refused.
    """

    def __init__(self, trimesh: Any, urdf_file: Path, roots: tuple[MeshRoot, ...]) -> None:
        self.trimesh, self.urdf_file, self.roots = trimesh, urdf_file, roots
        self.triangles = 0                     # triangles read so far (all files)
        self.problems: dict[str, str] = {}     # mesh name -> why it was not read
        self.files: list[Path] = []            # the files read (for the digests of stored meshes)

    def read(self, name: str) -> list[Any] | None:
        """The triangle meshes of file ``name``, or None (the reason is in :attr:`problems`)."""
        path, reason = resolve_mesh_file(name, self.urdf_file, self.roots)
        if path is None:
            self.problems[name] = f"not read: {reason}"
            return None
        try:
            size = path.stat().st_size
        except OSError as exc:
            self.problems[name] = f"cannot be read ({exc.strerror or exc})"
            return None
        if size > MAX_MESH_FILE_BYTES:
            self.problems[name] = (f"not read: {size:,} bytes, more than the cap of {MAX_MESH_FILE_BYTES:,} "
                                   f"bytes per mesh file (robokin.models.urdf_meshes.MAX_MESH_FILE_BYTES)")
            return None
        try:
            loaded = self.trimesh.load(str(path), force="scene")
            meshes = [m for m in loaded.dump() if isinstance(m, self.trimesh.Trimesh) and len(m.faces)]
        except Exception as exc:  # noqa: BLE001 - any failure to parse a mesh file: stick figure + warning
            self.problems[name] = f"cannot be read as a mesh ({type(exc).__name__})"
            return None
        if not meshes:
            self.problems[name] = "holds no triangles"
            return None
        count = sum(len(m.faces) for m in meshes)
        if self.triangles + count > MAX_SOURCE_TRIANGLES:
            self.problems[name] = (f"not read: its {count:,} triangles would take the robot past the cap of "
                                   f"{MAX_SOURCE_TRIANGLES:,} triangles before decimation "
                                   f"(robokin.models.urdf_meshes.MAX_SOURCE_TRIANGLES)")
            return None
        self.triangles += count
        self.files.append(path)
        return meshes


def _submeshes(reader: _MeshReader, visual: Any, default: tuple[int, int, int, int] | None
               ) -> tuple[list[tuple[np.ndarray, np.ndarray, tuple[int, ...]]], str | None]:
    """``([(vertices, faces, rgba)], None)`` of one ``<visual>`` in its link's frame, or ``([], file)``
    when its mesh file is not read (the reason is in ``reader.problems``)."""
    g = visual.geometry
    T = np.eye(4) if visual.origin is None else np.asarray(visual.origin, dtype=float)
    color = default or _rgba_int(DEFAULT_MESH_COLOR)
    parts: list[tuple[np.ndarray, np.ndarray, tuple[int, ...]]] = []
    if g is None:
        return [], None
    if g.mesh is None:
        mesh = _primitive(reader.trimesh, g)
        if mesh is None:
            return [], None
        parts.append((np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces), color))
    else:
        name = str(g.mesh.filename)
        meshes = reader.read(name)
        if meshes is None:
            return [], name
        scale = np.ones(3) if g.mesh.scale is None else np.broadcast_to(np.asarray(g.mesh.scale, float), (3,))
        for m in meshes:
            own = None
            if getattr(m.visual, "kind", None) is not None:  # the file has colours: use them
                own = getattr(m.visual, "main_color", None)
                if own is None and getattr(m.visual, "material", None) is not None:
                    own = m.visual.material.main_color
            rgba = tuple(int(v) for v in np.asarray(own).ravel()[:4]) if own is not None else color
            parts.append((np.asarray(m.vertices, dtype=float) * scale, np.asarray(m.faces), rgba))
    out = []
    for V, F, rgba in parts:
        out.append((V @ T[:3, :3].T + T[:3, 3], np.asarray(F, dtype=np.int64), rgba))
    return out, None


def _rgba_int(color: int) -> tuple[int, int, int, int]:
    return ((color >> 16) & 255, (color >> 8) & 255, color & 255, 255)


# ------------------------------------------------------------------ decimation
def _snap(V: np.ndarray) -> np.ndarray:
    """Vertices rounded to a grid of step ``1 / _GRID`` m (71 nm) before merging and decimating.

    The transforms before this point (trimesh's scene graph, the link poses, the
    matrix products) go through BLAS, whose last bits differ between CPU kernels
    (``OPENBLAS_CORETYPE``), and decimation turns a one-ulp difference into another
    triangulation. Rounding to a fixed grid (far below what a picture shows; the
    result is float32 anyway) removes those bits, so that the result is the same on
    every machine and the stored meshes (:mod:`robokin.models.mesh_store`) equal a
    fresh computation anywhere. The step is irrational (``√2·10⁷`` steps per metre)
    so that no float32 (STL) or decimal (URDF) coordinate lies on a rounding
    midpoint, where an ulp decides: with a power-of-two step, half the float32
    coordinates of an STL file do. What is left is a coordinate within an ulp of a
    midpoint by chance, about one in 10⁹.
    """
    return np.round(np.asarray(V, dtype=float) * _GRID) / _GRID


def _merge(trimesh: Any, parts: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    Vs, Fs, offset = [], [], 0
    for V, F in parts:
        Vs.append(V)
        Fs.append(F + offset)
        offset += len(V)
    mesh = trimesh.Trimesh(np.vstack(Vs), np.vstack(Fs), process=True, validate=False)  # merges equal vertices
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


def _area(V: np.ndarray, F: np.ndarray) -> float:
    return float(np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1).sum() / 2)


def _allocate(faces: list[int], weights: list[float], total: int) -> list[int]:
    """Triangles per group: proportional to ``weights``, at most the group's own count, at least _MIN_FACES."""
    alloc = [0] * len(faces)
    free = list(range(len(faces)))
    left = total
    for _ in range(4):
        w = sum(weights[g] for g in free) or 1.0
        capped = []
        for g in free:
            alloc[g] = max(min(_MIN_FACES, faces[g]), int(left * weights[g] / w))
            if alloc[g] >= faces[g]:
                alloc[g] = faces[g]
                capped.append(g)
        if not capped:
            break
        free = [g for g in free if g not in capped]
        left = max(0, total - sum(alloc[g] for g in range(len(faces)) if g not in free))
    return alloc


def _clean(V: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop degenerate and repeated triangles and unused vertices."""
    if len(F):
        F = F[(F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])]
    if len(F):
        _, first = np.unique(np.sort(F, axis=1), axis=0, return_index=True)
        F = F[np.sort(first)]
    used = np.unique(F)
    remap = np.full(len(V), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return V[used], remap[F]


def _cluster(V: np.ndarray, F: np.ndarray, cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Vertex clustering: the vertices in each cube of side ``cell`` merged into their mean."""
    key = np.floor((V - V.min(axis=0)) / cell).astype(np.int64)
    _, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    count = np.bincount(inverse)
    W = np.stack([np.bincount(inverse, weights=V[:, k]) for k in range(3)], axis=1) / count[:, None]
    return _clean(W, inverse[F])


def _decimate(fast_simplification: Any, V: np.ndarray, F: np.ndarray, target: int) -> tuple[np.ndarray, np.ndarray]:
    """About ``target`` triangles: quadric edge collapse, then vertex clustering where that stalls
    (meshes of many small open pieces)."""
    if target < len(F):
        V, F = fast_simplification.simplify(V.astype(np.float64), F.astype(np.int64),
                                            target_reduction=1.0 - target / len(F))
        V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64)
    V, F = _clean(V, F)
    if len(F) > 1.1 * target:
        size = float(np.ptp(V, axis=0).max())
        lo, hi = size * 1e-4, size           # cell sizes: too fine, coarse enough
        best = _cluster(V, F, hi)
        for _ in range(14):                  # bisection (geometric) on the cell size
            mid = float(np.sqrt(lo * hi))
            trial = _cluster(V, F, mid)
            if len(trial[1]) <= target:
                hi, best = mid, trial
            else:
                lo = mid
        V, F = best
    return V, F


# ------------------------------------------------------------------ computing, or reading the stored result
def _compute(file: str, base_link: str, tip_link: str, max_bytes: int, mesh_roots: tuple[str, ...]
             ) -> tuple[RobotMeshes, SerialChain, list[Path]]:
    """The meshes read and decimated, the chain ``from_urdf(file, base_link, tip_link)``, the files read."""
    trimesh, fast_simplification = _import_mesh_libraries()
    chain = from_urdf(file, base_link, tip_link)  # validates the file and the links
    where = f"URDF file {file!r}"
    urdf = parse_urdf(Path(file), where)
    frame_links = _chain_links(urdf, base_link, tip_link, where)
    poses = root_poses(urdf.robot, where)
    G0 = np.asarray(chain.frames(np.zeros(chain.n)), dtype=float)  # chain frames at q = 0, in base_link
    T_root_base = poses[base_link]
    materials = {m.name: m for m in (urdf.robot.materials or []) if m.name}
    link_by_name = {link.name: link for link in urdf.robot.links}
    names = [str(v.geometry.mesh.filename) for link in urdf.robot.links for v in link.visuals
             if v.geometry is not None and v.geometry.mesh is not None]
    reader = _MeshReader(trimesh, Path(file), allowed_roots(Path(file), names, [Path(r) for r in mesh_roots]))

    groups = []        # (frame, rgba, [(V, F)], [links])
    unreadable: list[list[str]] = [[] for _ in frame_links]
    original = 0
    with quiet_yourdfpy():
        for i, links in enumerate(_rigid_groups(urdf, frame_links)):
            # pose of each link in frame i (constant: the link is rigid with the frame)
            T_frame_root = np.linalg.inv(T_root_base @ G0[i])
            by_color: dict[tuple[int, ...], tuple[list, list]] = {}
            for link in links:
                T = T_frame_root @ poses[link]
                for visual in link_by_name[link].visuals:
                    parts, bad = _submeshes(reader, visual, _visual_color(visual, materials))
                    if bad is not None and bad not in unreadable[i]:
                        unreadable[i].append(bad)
                    for V, F, rgba in parts:
                        original += len(F)
                        entry = by_color.setdefault(rgba, ([], []))
                        entry[0].append((_snap(V @ T[:3, :3].T + T[:3, 3]), F))
                        if link not in entry[1]:
                            entry[1].append(link)
            for rgba, (pieces, owners) in by_color.items():
                V, F = _merge(trimesh, pieces)
                if len(F):
                    groups.append((i, rgba, V, F, owners))
    if reader.problems:
        listed = [f"{name!r} {why}" for name, why in sorted(reader.problems.items())]
        warnings.warn(MeshWarning(
            f"{where}: {len(listed)} visual mesh file(s) not drawn: {name_list(listed, limit=5, sep='; ')}. "
            f"The chain frames {name_list([frame_links[i] for i, u in enumerate(unreadable) if u])} are drawn "
            f"as a stick figure."), stacklevel=4)

    faces = [len(F) for _, _, _, F, _ in groups]
    weights = [_area(V, F) ** 0.75 for _, _, V, F, _ in groups]
    target = int(max_bytes / 19.5)      # ~V = 0.6 F after decimation: 12 V + 12 F bytes per triangle
    for _ in range(6):
        alloc = _allocate(faces, weights, target)
        out = [(i, rgba, *_decimate(fast_simplification, V, F, k), owners)
               for (i, rgba, V, F, owners), k in zip(groups, alloc)]
        nbytes = sum(12 * len(V) + 12 * len(F) for _, _, V, F, _ in out)
        if nbytes <= max_bytes or target <= _MIN_FACES * max(1, len(groups)):
            break
        target = int(target * max_bytes / nbytes * 0.97)
    frames: list[list[VisualMesh]] = [[] for _ in frame_links]
    for i, rgba, V, F, owners in out:
        if len(F):
            frames[i].append(VisualMesh(np.ascontiguousarray(V, dtype=np.float32),
                                        np.ascontiguousarray(F, dtype=np.uint32),
                                        (rgba[0] << 16) | (rgba[1] << 8) | rgba[2], rgba[3] / 255 or 1.0,
                                        tuple(owners)))
    for ms in frames:
        for m in ms:
            m.vertices.setflags(write=False)
            m.faces.setflags(write=False)
    meshes = RobotMeshes(tuple(chain.frame_names), tuple(tuple(ms) for ms in frames),
                         tuple(tuple(u) for u in unreadable), file, original)
    return meshes, chain, [Path(file), *reader.files]


def _stored(file: str, base_link: str, tip_link: str, max_bytes: int, mesh_roots: tuple[str, ...]
            ) -> MeshRecord | None:
    """The stored record of a packaged robot's chain at the default budget; None for any other call,
    and (with a MeshWarning) when the stored file is missing or stale."""
    robot = None if mesh_roots or max_bytes != DEFAULT_MESH_BYTES else stored_robot(Path(file), base_link, tip_link)
    if robot is None:
        return None
    try:
        return read_record(robot, max_bytes)
    except StaleMeshData as exc:
        warnings.warn(MeshWarning(
            f"{exc}: computing them from the mesh files instead (a few seconds per process). "
            f"Rebuild the stored meshes with `{BUILD_COMMAND}` (in a robokin source tree)."), stacklevel=4)
        return None


def record_meshes(record: MeshRecord, file: str) -> RobotMeshes:
    """The :class:`RobotMeshes` of a stored record (``file``: the URDF file, for ``source``)."""
    frames: list[list[VisualMesh]] = [[] for _ in record.frame_names]
    for i, V, F, color, opacity, links in record.meshes:
        frames[i].append(VisualMesh(V, F, color, opacity, links))
    return RobotMeshes(record.frame_names, tuple(tuple(ms) for ms in frames),
                       tuple(() for _ in record.frame_names), file, record.original_triangles)


def mesh_record(meshes: RobotMeshes, chain: SerialChain, robot: str, max_bytes: int) -> MeshRecord:
    """The record to store for the computed ``meshes`` of ``robot`` and its URDF ``chain``."""
    if any(meshes.unreadable):
        raise ValueError(f"{robot}: mesh files were not read ({meshes.unreadable}); they cannot be stored")
    rows = tuple((i, m.vertices, m.faces, m.color, m.opacity, m.links)
                 for i, ms in enumerate(meshes.frames) for m in ms)
    return MeshRecord(robot, max_bytes, meshes.frame_names, rows, meshes.original_triangles, chain_arrays(chain))


@lru_cache(maxsize=32)
def _cached(file: str, stamp: tuple[int, int], base_link: str, tip_link: str, max_bytes: int,
            mesh_roots: tuple[str, ...]) -> RobotMeshes:
    record = _stored(file, base_link, tip_link, max_bytes, mesh_roots)
    if record is not None:
        return record_meshes(record, file)
    return _compute(file, base_link, tip_link, max_bytes, mesh_roots)[0]


def packaged_meshes(robot: str, max_bytes: int = DEFAULT_MESH_BYTES
                    ) -> tuple[RobotMeshes, SerialChain, list[Path]]:
    """The meshes of a robot of :data:`~robokin.models.mesh_store.STORED_ROBOTS`, computed afresh.

    What ``python tools/authoring/build_meshes.py`` stores, and what the test of the stored
    files compares them with. The stored files are not read.

    Parameters
    ----------
    robot : str
        A name of :data:`~robokin.models.mesh_store.STORED_ROBOTS`.
    max_bytes : int, optional
        The budget (default :data:`DEFAULT_MESH_BYTES`, the one stored).

    Returns
    -------
    meshes : RobotMeshes
        As :func:`visual_meshes` computes them.
    chain : SerialChain
        ``from_urdf(file, base_link, tip_link)``.
    files : list of pathlib.Path
        The URDF file and the mesh files read (their digests are stored).
    """
    if robot not in STORED_ROBOTS:
        raise DomainError(f"robot must be one of {sorted(STORED_ROBOTS)}; got {robot!r}")
    relative, base_link, tip_link = STORED_ROBOTS[robot]
    roots = known_packages()
    if not roots:
        raise ImportError(f"the meshes of {robot!r} need example-robot-data, which is not installed: {_INSTALL}")
    file = (roots[0].folder / "robots" / relative).resolve()
    return _compute(str(file), base_link, tip_link, max_bytes, ())


def visual_meshes(path: str | os.PathLike, base_link: str, tip_link: str, *,
                  max_bytes: int = DEFAULT_MESH_BYTES,
                  mesh_roots: Sequence[str | os.PathLike] = ()) -> RobotMeshes:
    """The visual meshes of the chain ``from_urdf(path, base_link, tip_link)``, frame by frame.

    Parameters
    ----------
    path : str or os.PathLike
        The URDF file (:func:`robokin.models.robot_description` gives a few).
        Its mesh files (``package://...``, ``file://...``, relative or absolute
        names) are read only inside the robot's own package -- the nearest folder
        above the file with a ``package.xml``, else the folder named as the
        ``package://`` name, else the file's folder -- and the packages robokin
        knows (example-robot-data), symbolic links followed
        (:mod:`robokin.models.mesh_files`). Any other file is never opened: its
        frame is drawn as a stick figure and the warning names file and rule.
    base_link, tip_link : str
        As for :func:`robokin.models.from_urdf`.
    max_bytes : int, optional
        Budget of all meshes together, in bytes of float32 vertex coordinates and
        uint32 triangle indices (default 150 000, about 8 000 triangles).
        Meshes are decimated to it; triangles are shared out between the
        (frame, colour) groups in proportion to their area to the power 0.75.
    mesh_roots : sequence of str or os.PathLike, optional
        More folders mesh files may be read from (for a URDF whose meshes live
        in another package: each folder also answers to ``package://<its
        name>/...``).

    Returns
    -------
    RobotMeshes
        ``result.frames[i]`` holds the meshes (:class:`VisualMesh`: vertices in
        chain frame ``i``, triangles, colour) rigidly attached to frame ``i`` of
        the chain -- the frames of ``chain.frames(q)``: visuals of the frame's
        link and of the links fixed to it, one mesh per colour. Colours: the
        mesh file's own (a ``.dae`` material), else the URDF ``<material>``,
        else grey. Cached per file, links and budget; for the robots of
        ``robokin.models.mesh_store.STORED_ROBOTS`` at the default budget and
        without ``mesh_roots``, read from the files stored in the package (the
        same arrays, a test checks).

    Raises
    ------
    TypeError, URDFError
        As :func:`robokin.models.from_urdf` (bad path or links).
    TypeError, DomainError
        ``max_bytes`` is not a positive integer.
    ImportError
        yourdfpy, trimesh or fast-simplification is missing (``pip install 'robokin[robots]'``).

    Warns
    -----
    MeshWarning
        Once per call that reads the file, when mesh files are not read: outside
        the allowed folders, missing, not a mesh, larger than
        :data:`MAX_MESH_FILE_BYTES` (16 MB), or past :data:`MAX_SOURCE_TRIANGLES`
        (10⁶ triangles for the whole robot, before decimation). They are skipped,
        named with the reason, and their frames listed in ``result.unreadable``.
        Also when the stored meshes of a packaged robot are missing or were
        computed from other files than the installed example-robot-data's: the
        warning names the file and ``python tools/authoring/build_meshes.py``, and the
        meshes are computed from the mesh files instead (never a stale mesh).

    Notes
    -----
    Caps: at most 16 MB per mesh file and 10⁶ triangles per robot are read, so
    that one call stays under about 500 MB of memory; the result is decimated to
    ``max_bytes``.

    Examples
    --------
    >>> from robokin.models import robot_description, visual_meshes
    >>> meshes = visual_meshes(robot_description("ur10"), "base", "tool0")  # doctest: +SKIP
    >>> meshes.triangles <= 8_000  # doctest: +SKIP
    True
    """
    if isinstance(max_bytes, bool) or not isinstance(max_bytes, (int, np.integer)):
        raise TypeError(f"max_bytes must be an int (bytes); got {type(max_bytes).__name__} {max_bytes!r}"[:200])
    if max_bytes <= 0:
        raise DomainError(f"max_bytes must be positive; got {max_bytes}")
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a str or os.PathLike naming a URDF file; got {type(path).__name__} "
                        f"{path!r}"[:200])
    file = Path(os.fsdecode(os.fspath(path))).resolve()
    if not file.is_file():
        from_urdf(file, base_link, tip_link)  # raises the usual type errors / URDFNotFoundError
        raise URDFNotFoundError(f"path: URDF file {str(file)!r} is not a file")
    for arg, value in (("base_link", base_link), ("tip_link", tip_link)):
        if not isinstance(value, str):
            raise TypeError(f"{arg} must be a link name (str); got {type(value).__name__} {value!r}"[:200])
    if isinstance(mesh_roots, (str, bytes, os.PathLike)) or not all(
            isinstance(r, (str, os.PathLike)) and not isinstance(r, bytes) for r in mesh_roots):
        raise TypeError(f"mesh_roots must be a sequence of folders (str or os.PathLike); got "
                        f"{type(mesh_roots).__name__} {mesh_roots!r}"[:200])
    roots = tuple(str(Path(os.fsdecode(os.fspath(r))).resolve()) for r in mesh_roots)
    for r in roots:
        if not Path(r).is_dir():
            raise DomainError(f"mesh_roots: {r!r} is not a folder")
    st = file.stat()
    return _cached(str(file), (st.st_mtime_ns, st.st_size), base_link, tip_link, int(max_bytes), roots)


def visual_chain(path: str | os.PathLike, base_link: str, tip_link: str) -> SerialChain:
    """The chain ``from_urdf(path, base_link, tip_link)`` whose frames :func:`visual_meshes` uses.

    For a robot whose meshes are stored in the package
    (:data:`~robokin.models.mesh_store.STORED_ROBOTS`, unchanged source files) it
    is rebuilt from the stored elements (identical to ``from_urdf``'s, a test
    checks) without importing the URDF parser; otherwise it is ``from_urdf``'s.

    Parameters
    ----------
    path, base_link, tip_link
        As for :func:`visual_meshes` (call that first: it checks them).

    Returns
    -------
    SerialChain
    """
    file = Path(os.fsdecode(os.fspath(path))).resolve()
    robot = stored_robot(file, base_link, tip_link) if file.is_file() else None
    record = None
    if robot is not None:
        try:
            record = read_record(robot, DEFAULT_MESH_BYTES)
        except StaleMeshData:
            record = None  # visual_meshes warned (MeshWarning) and read the mesh files; read the URDF too
    return from_urdf(path, base_link, tip_link) if record is None else record_chain(record)
