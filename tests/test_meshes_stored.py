"""The stored meshes of the packaged robots (robokin/models/mesh_data, robokin.models.mesh_store).

The meshes of the robots the book draws are computed once by ``tools/authoring/build_meshes.py``
and read by ``visual_meshes``; these tests compute each robot afresh (about 2-3 s
each, once per run: a module fixture) and check that the stored file is the same,
bit for bit, so that the data cannot drift from the code. If one fails after a
change of the mesh pipeline, the budget or example-robot-data, run
``python tools/authoring/build_meshes.py`` and commit the files.
"""

from __future__ import annotations

import importlib.metadata
import json
import os
import platform
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from support import installed
from robokin.models import mesh_store
from robokin.models.mesh_store import (STORED_ROBOTS, StaleMeshData, chain_arrays, data_file, read_record,
                                       record_chain, stored_robot)
from robokin.models.urdf_meshes import (DEFAULT_MESH_BYTES, mesh_record, packaged_meshes, visual_chain, visual_meshes)

installed.require("yourdfpy", "yourdfpy is not installed: pip install 'robokin[robots]'")
installed.require("trimesh", "trimesh is not installed: pip install 'robokin[robots]'")
installed.require("fast_simplification", "fast-simplification is not installed: pip install 'robokin[robots]'")
try:
    importlib.metadata.distribution("example-robot-data")
except importlib.metadata.PackageNotFoundError:
    pytest.skip("example-robot-data is not installed: pip install 'robokin[robots]'", allow_module_level=True)

ROOT = Path(__file__).resolve().parent.parent
REBUILD = ("stored meshes differ from a fresh computation: run `python tools/authoring/build_meshes.py` "
           "and commit the files")


@pytest.fixture(scope="module")
def fresh():
    """{robot: (meshes, chain, files)} computed from the mesh files, once per run."""
    return {robot: packaged_meshes(robot) for robot in STORED_ROBOTS}


def _rows(meshes):
    return [(i, m.vertices, m.faces, m.color, m.opacity, m.links) for i, ms in enumerate(meshes.frames) for m in ms]


@pytest.mark.parametrize("robot", list(STORED_ROBOTS))
def test_stored_meshes_equal_a_fresh_computation(fresh, robot):
    meshes, chain, files = fresh[robot]
    stored = read_record(robot, DEFAULT_MESH_BYTES)
    assert stored.frame_names == meshes.frame_names, REBUILD
    assert stored.original_triangles == meshes.original_triangles, REBUILD
    now, then = _rows(meshes), list(stored.meshes)
    assert len(now) == len(then), REBUILD
    for (i, V, F, color, opacity, links), (j, W, G, c, o, owners) in zip(now, then):
        assert (i, color, opacity, links) == (j, c, o, owners), REBUILD
        assert V.dtype == W.dtype == np.float32 and F.dtype == G.dtype == np.uint32
        assert np.array_equal(V, W) and np.array_equal(F, G), REBUILD          # bit for bit
    # the digests cover exactly the files the computation read
    with np.load(data_file(robot, DEFAULT_MESH_BYTES)) as data:
        names = [str(n) for n in data["source_files"]]
    folder = Path(str(importlib.metadata.distribution("example-robot-data").locate_file(
        "cmeel.prefix/share/example-robot-data"))).resolve()
    assert names == sorted({f.resolve().relative_to(folder).as_posix() for f in files}), REBUILD
    # the record built now is the stored one (same arrays, same chain)
    record = mesh_record(meshes, chain, robot, DEFAULT_MESH_BYTES)
    assert record.chain.keys() == stored.chain.keys()
    for key, value in record.chain.items():
        assert np.array_equal(value, stored.chain[key]), (key, REBUILD)


@pytest.mark.parametrize("robot", list(STORED_ROBOTS))
def test_stored_chain_is_from_urdf_s(fresh, robot):
    _, chain, _ = fresh[robot]
    rebuilt = record_chain(read_record(robot, DEFAULT_MESH_BYTES))
    assert repr(rebuilt.elements) == repr(chain.elements) and rebuilt.name == chain.name
    assert rebuilt.frame_names == chain.frame_names and rebuilt.joint_names == chain.joint_names
    assert np.array_equal(rebuilt.tool, chain.tool) and np.array_equal(rebuilt.limits, chain.limits)
    for a, b in zip(rebuilt.elements, chain.elements):
        assert (a.kind, a.axis, a.sign, a.joint, a.limits) == (b.kind, b.axis, b.sign, b.joint, b.limits)
        if a.kind == "F":
            assert np.array_equal(a.matrix, b.matrix)
    rng = np.random.default_rng(3)
    lim = np.asarray(chain.limits)
    for q in lim[:, 0] + (lim[:, 1] - lim[:, 0]) * rng.random((5, chain.n)):
        assert np.array_equal(np.asarray(rebuilt.frames(q)), np.asarray(chain.frames(q)))
    assert chain_arrays(rebuilt).keys() == chain_arrays(chain).keys()


@pytest.mark.parametrize("robot", list(STORED_ROBOTS))
def test_visual_meshes_reads_the_stored_files(fresh, robot):
    meshes, chain, files = fresh[robot]
    relative, base, tip = STORED_ROBOTS[robot]
    urdf = files[0]
    assert stored_robot(urdf, base, tip) == robot
    got = visual_meshes(urdf, base, tip)
    assert got.source == meshes.source and got.unreadable == meshes.unreadable
    assert [(i, V.tobytes(), F.tobytes(), c, o, li) for i, V, F, c, o, li in _rows(got)] == \
           [(i, V.tobytes(), F.tobytes(), c, o, li) for i, V, F, c, o, li in _rows(meshes)]
    assert repr(visual_chain(urdf, base, tip).elements) == repr(chain.elements)
    # another chain of the same file, another budget: not stored
    assert stored_robot(urdf, base, chain.frame_names[-2]) is None


def test_stored_files_are_small():
    sizes = {robot: data_file(robot, DEFAULT_MESH_BYTES).stat().st_size for robot in STORED_ROBOTS}
    assert sum(sizes.values()) < 500_000, sizes
    for robot in STORED_ROBOTS:
        record = read_record(robot, DEFAULT_MESH_BYTES)
        assert sum(V.nbytes + F.nbytes for _, V, F, *_ in record.meshes) <= DEFAULT_MESH_BYTES


def _tampered(tmp_path, robot, change):
    """A copy of the stored files in tmp_path, with ``change(arrays)`` applied to ``robot``'s."""
    folder = tmp_path / "mesh_data"
    shutil.copytree(mesh_store.DATA_FOLDER, folder)
    path = folder / data_file(robot, DEFAULT_MESH_BYTES).name
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    change(arrays)
    with open(path, "wb") as out:
        np.savez_compressed(out, **arrays)
    return folder


def _other_digest(arrays):
    arrays["source_sha256"] = np.array(["0" * 64] + list(arrays["source_sha256"][1:]))


@pytest.mark.parametrize("change, message", [
    (_other_digest, "computed from another version of robots/"),
    (lambda a: a.update(source_files=np.array(["robots/nowhere.stl"]), source_sha256=np.array(["0" * 64])),
     "robots/nowhere.stl, which the installed example-robot-data"),
    (lambda a: a.update(format=np.array(0)), "are of another format"),
])
def test_stale_or_missing_stored_files_are_named(tmp_path, monkeypatch, change, message):
    monkeypatch.setattr(mesh_store, "DATA_FOLDER", _tampered(tmp_path, "kinova", change))
    with pytest.raises(StaleMeshData, match="the stored meshes of 'kinova'") as info:
        read_record("kinova", DEFAULT_MESH_BYTES)
    assert message in str(info.value)
    monkeypatch.setattr(mesh_store, "DATA_FOLDER", tmp_path / "empty")
    with pytest.raises(StaleMeshData, match=r"the stored meshes of 'kinova' \(kinova-150000.npz\) are missing"):
        read_record("kinova", DEFAULT_MESH_BYTES)


def test_stale_stored_file_is_recomputed_with_a_warning(fresh, tmp_path):
    """Not a silent wrong mesh: a MeshWarning names the file and the tool, and the meshes are computed."""
    folder = _tampered(tmp_path, "kinova", _other_digest)
    script = f"""
import json, warnings, numpy as np
from robokin.models import mesh_store, robot_description
mesh_store.DATA_FOLDER = mesh_store.Path({str(folder)!r})
from robokin.models import visual_meshes
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    m = visual_meshes(robot_description("kinova"), "base", "j2s6s200_end_effector")
print(json.dumps({{"warnings": [str(w.message) for w in caught], "category": [w.category.__name__ for w in caught],
    "file": [w.filename for w in caught],
    "meshes": [[i, V.tolist(), F.tolist()] for i, ms in enumerate(m.frames) for V, F in
               [(x.vertices, x.faces) for x in ms]]}}))
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True, cwd=ROOT)
    result = json.loads(out.stdout)
    assert result["category"] == ["MeshWarning"], result["warnings"]
    assert "python tools/authoring/build_meshes.py" in result["warnings"][0]
    assert "computed from another version of robots/kinova_description/" in result["warnings"][0]
    assert result["file"] == ["<string>"]                          # points at the caller
    meshes = fresh["kinova"][0]
    assert result["meshes"] == [[i, V.tolist(), F.tolist()] for i, V, F, *_ in _rows(meshes)]


def test_packaged_robot_scene_imports_neither_trimesh_nor_the_urdf_parser():
    script = """
import sys, numpy as np
from robokin import models, views
scene = views.Scene()
scene.add_chain(models.baxter_left(), np.zeros(7), meshes="baxter")
scene.add_chain(models.ur10(), np.zeros(6), meshes="ur10", name="ur10")
html = scene.commands()
print(sorted(m for m in ("trimesh", "yourdfpy", "fast_simplification", "lxml") if m in sys.modules))
"""
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]", out.stdout + out.stderr


def test_package_data_ships_the_stored_files():
    text = (ROOT / "pyproject.toml").read_text()
    assert '"models/mesh_data/*.npz"' in text
    for robot in STORED_ROBOTS:
        assert zipfile.is_zipfile(data_file(robot, DEFAULT_MESH_BYTES))


def test_a_copy_of_a_packaged_urdf_is_not_stored(fresh, tmp_path):
    """Another file (the "your robot" path) goes through from_urdf and the full pipeline, never the store."""
    _, chain, files = fresh["ur10"]
    copy = tmp_path / "ur10_robot.urdf"
    shutil.copyfile(files[0], copy)
    _, base, tip = STORED_ROBOTS["ur10"]
    assert stored_robot(copy.resolve(), base, tip) is None
    assert repr(visual_chain(copy, base, tip).elements) == repr(chain.elements)


@pytest.mark.other_machines
@pytest.mark.skipif(platform.machine().lower() not in ("x86_64", "amd64"), reason="OpenBLAS kernel names of x86-64")
def test_stored_meshes_equal_a_computation_with_another_blas_kernel(tmp_path):
    """The pipeline rounds the vertices to a grid before decimating (urdf_meshes._snap), so a CPU whose
    BLAS rounds the transforms differently (here OpenBLAS's baseline Prescott kernel) gives the same
    meshes: the stored files are right on every machine, not only on the one that wrote them."""
    script = """
import numpy as np
from robokin.models.mesh_store import STORED_ROBOTS, read_record
from robokin.models.urdf_meshes import DEFAULT_MESH_BYTES, packaged_meshes
for robot in STORED_ROBOTS:
    meshes = packaged_meshes(robot)[0]
    now = [(i, m.vertices, m.faces) for i, ms in enumerate(meshes.frames) for m in ms]
    then = read_record(robot, DEFAULT_MESH_BYTES).meshes
    same = len(now) == len(then) and all(a[0] == b[0] and np.array_equal(a[1], b[1]) and np.array_equal(a[2], b[2])
                                         for a, b in zip(now, then))
    print(robot, same)
"""
    env = {**os.environ, "OPENBLAS_CORETYPE": "Prescott", "OPENBLAS_NUM_THREADS": "1"}
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True, cwd=ROOT,
                         env=env)
    assert out.stdout.split() == [w for robot in STORED_ROBOTS for w in (robot, "True")], out.stdout + out.stderr
