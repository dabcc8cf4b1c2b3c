r"""The visual meshes of the packaged robots, computed once and stored with the package.

Reading a robot's mesh files with trimesh and decimating them
(:func:`robokin.models.visual_meshes`) takes about 3 s of CPU, the same 3 s at
every execution of a notebook that draws the robot. For the robots the book
draws (:data:`STORED_ROBOTS`, at the default budget
:data:`~robokin.models.urdf_meshes.DEFAULT_MESH_BYTES`) the result is stored in
``robokin/models/mesh_data/<robot>-<budget>.npz`` by ``python
tools/authoring/build_meshes.py``, and :func:`~robokin.models.visual_meshes` reads it
instead: no trimesh, no URDF parser, a few milliseconds.

A stored file holds the meshes (float32 vertices and uint32 triangles of every
mesh, its frame, colour, opacity and links), the chain ``from_urdf(file,
base_link, tip_link)`` the frames belong to (its elements, exactly), and the
SHA-256 of the URDF file and of every mesh file the computation read. It is
used only when all those files are unchanged; otherwise :func:`read_record`
raises :class:`StaleMeshData` naming the file, and the caller computes the
meshes afresh (with a :class:`~robokin.errors.MeshWarning`). A test
(``tests/test_meshes_stored.py``) checks that every stored file equals a fresh
computation, bit for bit, so the data cannot drift from the code.

This module reads and writes the files (numpy only, ``allow_pickle=False``);
it does not compute meshes.
"""

from __future__ import annotations

import hashlib
import zipfile
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from robokin.chains import SerialChain
from robokin.chains.elements import Element, Fixed, Rx, Ry, Rz, Tx, Ty, Tz
from robokin.models.mesh_files import known_packages

__all__ = ["STORED_ROBOTS", "DATA_FOLDER", "BUILD_COMMAND", "FORMAT", "StaleMeshData", "MeshRecord",
           "stored_robot", "data_file", "read_record", "write_record", "record_chain", "chain_arrays",
           "file_digest"]

#: Robots whose meshes are stored: name -> (URDF file under example-robot-data's ``robots``
#: folder, base link, tip link). The three of :data:`robokin.models.ROBOT_DESCRIPTIONS` and the
#: Kinova arm of the "your robot" chapter.
STORED_ROBOTS: dict[str, tuple[str, str, str]] = {
    "ur10": ("ur_description/urdf/ur10_robot.urdf", "base", "tool0"),
    "baxter": ("baxter_description/urdf/baxter.urdf", "torso", "left_hand_link"),
    "panda": ("panda_description/urdf/panda.urdf", "panda_link0", "panda_link8"),
    "kinova": ("kinova_description/robots/kinova.urdf", "base", "j2s6s200_end_effector"),
}

#: Where the stored files are (inside the package; ``pyproject.toml`` ships them as package data).
DATA_FOLDER = Path(__file__).resolve().parent / "mesh_data"

#: The command that (re)writes the stored files, from a robokin source tree.
BUILD_COMMAND = "python tools/authoring/build_meshes.py"

#: Version of the file layout (a file of another version is stale).
FORMAT = 1

_ROBOTS_FOLDER = "robots"   # example-robot-data's URDF files are under <package>/robots/
_JOINTS = {("R", 0): Rx, ("R", 1): Ry, ("R", 2): Rz, ("T", 0): Tx, ("T", 1): Ty, ("T", 2): Tz}


class StaleMeshData(Exception):
    """A stored mesh file is missing, of another format, or was computed from other source files."""


@dataclass(frozen=True, eq=False)
class MeshRecord:
    """The content of one stored file (see the module docstring).

    Attributes
    ----------
    robot : str
        Its name in :data:`STORED_ROBOTS`.
    max_bytes : int
        The mesh budget it was computed for.
    frame_names : tuple of str
        The chain's frame names (``n + 2``).
    meshes : tuple of tuple
        ``(frame, vertices (V, 3) float32, faces (F, 3) uint32, color 0xRRGGBB, opacity, links)``
        of each mesh, in the order the computation gives them.
    original_triangles : int
        Triangles before decimation.
    chain : dict of str to numpy.ndarray
        The URDF chain's elements (:func:`chain_arrays`); :func:`record_chain` rebuilds it.
    """

    robot: str
    max_bytes: int
    frame_names: tuple[str, ...]
    meshes: tuple[tuple[int, np.ndarray, np.ndarray, int, float, tuple[str, ...]], ...]
    original_triangles: int
    chain: dict[str, np.ndarray]


def data_file(robot: str, max_bytes: int) -> Path:
    """The stored file of ``robot`` at budget ``max_bytes``."""
    return DATA_FOLDER / f"{robot}-{max_bytes}.npz"


def _package_folder() -> Path | None:
    roots = known_packages()
    return roots[0].folder if roots else None


def stored_robot(file: Path, base_link: str, tip_link: str) -> str | None:
    """The name in :data:`STORED_ROBOTS` of the chain ``(file, base_link, tip_link)``, or None.

    ``file`` is a resolved path; it names a stored robot only when it is that
    robot's URDF file inside the installed example-robot-data.
    """
    folder = _package_folder()
    if folder is None or folder not in file.parents:
        return None
    relative = file.relative_to(folder / _ROBOTS_FOLDER).as_posix() if (folder / _ROBOTS_FOLDER) in file.parents \
        else None
    for robot, entry in STORED_ROBOTS.items():
        if entry == (relative, base_link, tip_link):
            return robot
    return None


def file_digest(path: Path) -> str:
    """SHA-256 (hex) of a file's bytes."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


# ------------------------------------------------------------------ the chain, as arrays
def chain_arrays(chain: SerialChain) -> dict[str, np.ndarray]:
    """The elements of a chain built by ``from_urdf`` as arrays (``chain_*`` entries of a stored file).

    Raises
    ------
    ValueError
        An element ``from_urdf`` does not build (a constant rotation or
        translation, a joint offset).
    """
    kinds, axes, signs, joints, limits, matrices = [], [], [], [], [], []
    for el in chain.elements:
        if el.kind == "F":
            matrix = np.asarray(el.matrix, dtype=float)
        elif el.is_joint and el.offset == 0 and el.limits is not None:
            matrix = np.eye(4)
        else:
            raise ValueError(f"cannot store the element {el!r}: a URDF chain has fixed transforms and joints "
                             f"without offset only")
        kinds.append(el.kind)
        axes.append(el.axis)
        signs.append(el.sign)
        joints.append(el.joint or "")
        limits.append(el.limits or (0.0, 0.0))
        matrices.append(matrix)
    return {"chain_kinds": np.array(kinds), "chain_axes": np.array(axes, dtype=np.int64),
            "chain_signs": np.array(signs, dtype=np.int64), "chain_joints": np.array(joints),
            "chain_limits": np.array(limits, dtype=float).reshape(-1, 2),
            "chain_matrices": np.array(matrices, dtype=float).reshape(-1, 4, 4),
            "chain_tool": np.asarray(chain.tool, dtype=float), "chain_name": np.array(chain.name)}


def record_chain(record: MeshRecord) -> SerialChain:
    """The chain ``from_urdf(file, base_link, tip_link)`` of a stored file, rebuilt from its elements."""
    c = record.chain
    elements: list[Element] = []
    for kind, axis, sign, joint, lim, matrix in zip(c["chain_kinds"], c["chain_axes"], c["chain_signs"],
                                                    c["chain_joints"], c["chain_limits"], c["chain_matrices"]):
        if str(kind) == "F":
            elements.append(Fixed(matrix))
        else:
            factory = _JOINTS[str(kind), int(axis)]
            elements.append(factory(("-" if sign < 0 else "") + str(joint), limits=(float(lim[0]), float(lim[1]))))
    return SerialChain(elements, tool=c["chain_tool"], frame_names=list(record.frame_names),
                       name=str(c["chain_name"]))


# ------------------------------------------------------------------ writing
def write_record(record: MeshRecord, sources: list[Path]) -> Path:
    """Write ``record`` to :func:`data_file` with the digests of ``sources`` (the URDF and mesh files read).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    folder = _package_folder()
    if folder is None:
        raise ValueError("example-robot-data is not installed: the packaged robots' meshes cannot be stored")
    names = sorted({p.resolve().relative_to(folder).as_posix() for p in sources})
    meshes = record.meshes
    arrays: dict[str, Any] = {
        "format": np.array(FORMAT), "robot": np.array(record.robot), "max_bytes": np.array(record.max_bytes),
        "source_files": np.array(names), "source_sha256": np.array([file_digest(folder / n) for n in names]),
        "frame_names": np.array(record.frame_names),
        "original_triangles": np.array(record.original_triangles),
        "mesh_frames": np.array([m[0] for m in meshes], dtype=np.int64),
        "mesh_vertex_counts": np.array([len(m[1]) for m in meshes], dtype=np.int64),
        "mesh_face_counts": np.array([len(m[2]) for m in meshes], dtype=np.int64),
        "vertices": np.concatenate([m[1] for m in meshes]).astype(np.float32),
        "faces": np.concatenate([m[2] for m in meshes]).astype(np.uint32),
        "mesh_colors": np.array([m[3] for m in meshes], dtype=np.int64),
        "mesh_opacities": np.array([m[4] for m in meshes], dtype=float),
        "mesh_links": np.array(["\n".join(m[5]) for m in meshes]),
        **record.chain,
    }
    path = data_file(record.robot, record.max_bytes)
    path.parent.mkdir(parents=True, exist_ok=True)
    # what np.savez_compressed writes, with a fixed date on every member: the same meshes give
    # the same bytes, so a rebuild that changes nothing shows no change in git
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, value in arrays.items():
            member = zipfile.ZipInfo(f"{name}.npy", date_time=(1980, 1, 1, 0, 0, 0))
            member.compress_type = zipfile.ZIP_DEFLATED
            with archive.open(member, "w", force_zip64=True) as out:
                np.lib.format.write_array(out, np.asanyarray(value), allow_pickle=False)
    return path


# ------------------------------------------------------------------ reading
def read_record(robot: str, max_bytes: int) -> MeshRecord:
    """The stored meshes of ``robot`` at budget ``max_bytes``, after checking their source files.

    Raises
    ------
    StaleMeshData
        The file is missing or of another format, or the installed URDF or a
        mesh file it was computed from is missing or differs (the message names
        it).
    """
    path = data_file(robot, max_bytes)
    return _read(robot, max_bytes, str(path), _stamp(path))


def _stamp(path: Path) -> tuple[int, int]:
    try:
        st = path.stat()
    except OSError:
        return (0, 0)
    return (st.st_mtime_ns, st.st_size)


@lru_cache(maxsize=16)
def _read(robot: str, max_bytes: int, file: str, stamp: tuple[int, int]) -> MeshRecord:
    path = Path(file)
    what = f"the stored meshes of {robot!r} ({path.name})"
    if stamp == (0, 0):
        raise StaleMeshData(f"{what} are missing")
    folder = _package_folder()
    if folder is None:
        raise StaleMeshData(f"{what} cannot be checked: example-robot-data is not installed")
    with np.load(path, allow_pickle=False) as data:
        d = {k: data[k] for k in data.files}
    if int(d.get("format", -1)) != FORMAT or str(d.get("robot", "")) != robot:
        raise StaleMeshData(f"{what} are of another format (format {d.get('format')}, this robokin reads {FORMAT})")
    for name, digest in zip(d["source_files"], d["source_sha256"]):
        try:
            now = file_digest(folder / str(name))
        except OSError:
            raise StaleMeshData(f"{what} were computed from {name}, which the installed example-robot-data "
                                f"({folder}) does not have") from None
        if now != str(digest):
            raise StaleMeshData(f"{what} were computed from another version of {name} than the installed "
                                f"one ({folder})")
    vertex_ends = np.cumsum(d["mesh_vertex_counts"])
    face_ends = np.cumsum(d["mesh_face_counts"])
    meshes = []
    for k, frame in enumerate(d["mesh_frames"]):
        V = d["vertices"][vertex_ends[k] - d["mesh_vertex_counts"][k]:vertex_ends[k]]
        F = d["faces"][face_ends[k] - d["mesh_face_counts"][k]:face_ends[k]]
        for a in (V, F):
            a.setflags(write=False)
        links = str(d["mesh_links"][k])
        meshes.append((int(frame), V, F, int(d["mesh_colors"][k]), float(d["mesh_opacities"][k]),
                       tuple(links.split("\n")) if links else ()))
    return MeshRecord(robot, int(d["max_bytes"]), tuple(str(n) for n in d["frame_names"]), tuple(meshes),
                      int(d["original_triangles"]), {k: v for k, v in d.items() if k.startswith("chain_")})
