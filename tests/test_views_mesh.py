"""Robots drawn with their URDF visual meshes (robokin.models.visual_meshes, robokin.views.robot_meshes)."""

from __future__ import annotations

import importlib.metadata
import io
import subprocess
import sys
import warnings
from collections.abc import Callable

import numpy as np
import pytest

from support import installed
from support.browser_waits import WAIT_MS, poll_until
from conftest import watched_page

from robokin import models
from robokin.chains import SerialChain
from robokin.errors import DomainError, MeshWarning, ShapeError
from robokin.models import ROBOT_DESCRIPTIONS, from_urdf, robot_description, visual_meshes
from robokin.views import Scene
from robokin.views.record import ChainItem
from robokin.views.static_html import pack_commands

installed.require("yourdfpy", "yourdfpy is not installed: pip install 'robokin[robots]'")
installed.require("trimesh", "trimesh is not installed: pip install 'robokin[robots]'")
installed.require("fast_simplification", "fast-simplification is not installed: pip install 'robokin[robots]'")
try:
    importlib.metadata.distribution("example-robot-data")
    HAVE_ROBOTS = True
except importlib.metadata.PackageNotFoundError:
    HAVE_ROBOTS = False
needs_robots = pytest.mark.skipif(not HAVE_ROBOTS,
                                  reason="example-robot-data is not installed: pip install 'robokin[robots]'")

ROBOTS = ["ur10", "panda", "baxter"]
HAND_BUILT: dict[str, Callable[[], SerialChain]] = {"ur10": models.ur10, "panda": models.panda,
                                                    "baxter": models.baxter_left}
BUDGET = 150_000
Q = {"ur10": [0.3, -1.2, 1.4, -1.0, -1.57, 0.4], "panda": [0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8],
     "baxter": [0.3, -0.5, 0.0, 1.0, 0.0, 0.5, 0.0]}


def _urdf_chain(name):
    _, base, tip = ROBOT_DESCRIPTIONS[name]
    return from_urdf(robot_description(name), base, tip)


def _mesh_commands(commands):
    return [c for c in commands if c["type"] == "set_object" and "/mesh_" in c["path"]]


def _world_vertices(meshes, F):
    """{frame i: vertices of its meshes in the base frame, placed by the frames F}."""
    out = {}
    for i, ms in enumerate(meshes.frames):
        if ms:
            V = np.vstack([np.asarray(m.vertices, dtype=float) for m in ms])
            out[i] = V @ F[i, :3, :3].T + F[i, :3, 3]
    return out


# ------------------------------------------------------------------ reading and decimating
@needs_robots
@pytest.mark.parametrize("name", ROBOTS)
def test_meshes_of_the_packaged_robots_fit_the_budget(name):
    _, base, tip = ROBOT_DESCRIPTIONS[name]
    meshes = visual_meshes(robot_description(name), base, tip)
    chain = _urdf_chain(name)
    assert len(meshes) == chain.n + 2 and meshes.frame_names == tuple(chain.frame_names)
    assert not any(meshes.unreadable)
    assert 0 < meshes.nbytes <= BUDGET, meshes
    assert 3_000 <= meshes.triangles <= 9_000, meshes            # about 8 000 triangles
    assert meshes.original_triangles > 10 * meshes.triangles      # they were decimated
    assert all(meshes.frames[i] for i in range(chain.n + 1))      # every body has a mesh
    for ms in meshes.frames:
        for m in ms:
            assert m.vertices.dtype == np.float32 and m.faces.dtype == np.uint32
            assert m.faces.max() < len(m.vertices) and np.isfinite(m.vertices).all()
            assert 0 <= m.color <= 0xFFFFFF and 0 < m.opacity <= 1
    # cached: read once per process
    assert visual_meshes(robot_description(name), base, tip) is meshes
    smaller = visual_meshes(robot_description(name), base, tip, max_bytes=40_000)
    assert smaller.nbytes <= 40_000 and smaller.triangles < meshes.triangles


@needs_robots
@pytest.mark.parametrize("name", ROBOTS)
def test_meshes_sit_on_the_links_they_belong_to(name):
    """Placed by FK, each frame's meshes surround that frame's origin, for the URDF chain and for the
    hand-built model alike (same world vertices at the same q)."""
    from robokin.views import robot_meshes

    ref, hand = _urdf_chain(name), HAND_BUILT[name]()
    mesh_ref, mesh_hand = robot_meshes(name, ref), robot_meshes(name, hand)
    rng = np.random.default_rng(5)
    lim = np.asarray(ref.limits)
    for q in [np.asarray(Q[name])] + [lim[:, 0] + (lim[:, 1] - lim[:, 0]) * rng.random(ref.n) for _ in range(3)]:
        F_ref, F_hand = np.asarray(ref.frames(q)), np.asarray(hand.frames(q))
        world_ref, world_hand = _world_vertices(mesh_ref, F_ref), _world_vertices(mesh_hand, F_hand)
        assert world_ref.keys() == world_hand.keys()
        for i, V in world_ref.items():
            np.testing.assert_allclose(world_hand[i], V, atol=2e-5)   # float32 vertices, Baxter's 0.7854
            # the frame origin is within 10 cm of the box around its meshes, a vertex within 15 cm
            lo, hi = V.min(axis=0) - 0.1, V.max(axis=0) + 0.1
            origin = F_ref[i, :3, 3]
            assert np.all((lo <= origin) & (origin <= hi)), (name, i)
            assert np.linalg.norm(V - origin, axis=1).min() < 0.15, (name, i)


# ------------------------------------------------------------------ commands
@needs_robots
def test_mesh_commands_are_deterministic_and_shared_between_scenes():
    from robokin.models import urdf_meshes

    chain = models.ur10()
    q0, q1 = np.asarray(Q["ur10"]), np.zeros(6)

    def build(q):
        scene = Scene()
        scene.add_chain(chain, q, meshes="ur10")
        return scene.commands()

    first = pack_commands(build(q0))
    urdf_meshes._cached.cache_clear()                          # read the meshes again (stored: test_meshes_stored)
    assert pack_commands(build(q0)) == first                   # identical bytes
    a, b = _mesh_commands(build(q0)), _mesh_commands(build(q1))
    assert len(a) >= 7
    assert pack_commands(a) == pack_commands(b)                # same geometry commands at another q
    assert pack_commands(build(q1)) != first                   # (the frame transforms differ)
    for c in a:                                                # indexed BufferGeometry, no scene data
        geometry = c["object"]["geometries"][0]
        assert geometry["type"] == "BufferGeometry" and geometry["data"]["index"]["type"] == "Uint32Array"
        assert c["object"]["materials"][0]["type"] == "MeshPhongMaterial"
        assert "matrix" not in c["object"]["object"]
    # no stick figure left; the end-effector triad stays
    paths = [c["path"] for c in build(q0) if c["type"] == "set_object"]
    assert not [p for p in paths if p.endswith(("/link", "/joint", "/base", "/marker"))]
    assert any("/triad/" in p for p in paths)


@needs_robots
def test_animation_moves_the_meshes():
    chain = models.panda()
    Q0 = np.asarray(Q["panda"])
    scene = Scene()
    scene.add_chain(chain, Q0, meshes="panda")
    scene.animate("robot", np.linspace(Q0, Q0 + 0.5, 20), dt=0.05)
    commands = scene.commands()
    tracks = {entry["path"] for entry in commands[-1]["animations"]}
    moving = [c["path"] for c in _mesh_commands(commands) if not c["path"].split("/")[3].startswith("0_")]
    assert moving and all(p.rsplit("/", 1)[0] in tracks for p in moving)   # each mesh's frame node has a track


@needs_robots
def test_mesh_scene_bounds_include_the_meshes():
    """Baxter's pedestal reaches the floor below the torso: the grid goes there, not through it."""
    from robokin.views.meshcat_draw import scene_floor

    stick, mesh = Scene(), Scene()
    stick.add_chain(models.baxter_left(), Q["baxter"])
    mesh.add_chain(models.baxter_left(), Q["baxter"], style="mesh")
    assert scene_floor(mesh) < scene_floor(stick) - 0.3


@needs_robots
def test_style_and_meshes_arguments():
    from robokin.views import robot_meshes

    scene = Scene()
    with pytest.raises(DomainError, match="style must be one of"):
        scene.add_chain(models.ur10(), style="wire")
    with pytest.raises(DomainError, match="style='stick'"):
        scene.add_chain(models.ur10(), style="stick", meshes="ur10")
    with pytest.raises(DomainError, match="needs meshes="):
        scene.add_chain(models.planar_two_link(), style="mesh")
    with pytest.raises(ShapeError, match="one entry per frame"):
        scene.add_chain(models.panda(), meshes=robot_meshes("ur10", models.ur10()))
    with pytest.raises(DomainError, match="chain has 7 joints but the URDF chain"):
        robot_meshes("ur10", models.panda())
    with pytest.raises(TypeError, match="meshes must be"):
        scene.add_chain(models.ur10(), meshes=3)  # type: ignore[arg-type]  # a wrong type on purpose
    assert scene.items == []
    scene.add_chain(models.ur10(), style="mesh")                 # the name picks the robot
    scene.add_ghost(models.ur10(), np.ones(6), meshes="ur10")    # translucent meshes
    ghost = [c for c in _mesh_commands(scene.commands()) if c["path"].startswith("/meshcat/ghost/")]
    assert ghost and all(c["object"]["materials"][0]["opacity"] < 1 for c in ghost)


# ------------------------------------------------------------------ failures
_BROKEN = """<?xml version="1.0"?>
<robot name="broken">
  <material name="blue"><color rgba="0 0 0.8 1"/></material>
  <link name="base"><visual><geometry><box size="0.1 0.1 0.05"/></geometry><material name="blue"/></visual></link>
  <link name="l1"><visual><geometry><mesh filename="missing.stl"/></geometry></visual></link>
  <link name="l2"><visual><geometry><mesh filename="garbage.stl"/></geometry></visual></link>
  <link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j3" type="fixed"><parent link="l2"/><child link="tip"/><origin xyz="0.3 0 0"/></joint>
</robot>
"""


def test_unreadable_mesh_files_fall_back_to_the_stick_figure(tmp_path):
    path = tmp_path / "broken.urdf"
    path.write_text(_BROKEN)
    (tmp_path / "garbage.stl").write_bytes(b"solid nothing here\x00\x01\x02")
    chain = from_urdf(path, "base", "tip")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = Scene()
        scene.add_chain(chain, [0.2, 0.3], meshes=path)
        commands = scene.commands()
    mesh_warnings = [w for w in caught if issubclass(w.category, MeshWarning)]
    assert len(mesh_warnings) == 1, [str(w.message) for w in caught]
    message = str(mesh_warnings[0].message)
    assert "missing.stl" in message and "garbage.stl" in message and "stick figure" in message
    robot = scene.item("robot")
    assert isinstance(robot, ChainItem)
    meshes = robot.meshes
    assert meshes.unreadable[0] == () and meshes.unreadable[1] and meshes.unreadable[2]
    assert len(meshes.frames[0]) == 1 and meshes.frames[0][0].color == 0x0000CC   # the box, URDF colour
    paths = [c["path"] for c in commands if c["type"] == "set_object"]
    assert "/meshcat/robot/0_base/mesh_0" in paths and "/meshcat/robot/0_base/base" not in paths
    assert "/meshcat/robot/1_l1/link" in paths and "/meshcat/robot/1_l1/joint" in paths   # sticks
    assert "/meshcat/robot/2_l2/link" in paths and "/meshcat/robot/3_tip/marker" in paths


def test_core_and_views_do_not_import_the_mesh_libraries():
    code = ("import sys, robokin, robokin.views, robokin.models; from robokin.views import Scene; "
            "print(sorted(m for m in ('trimesh', 'yourdfpy', 'fast_simplification') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_missing_mesh_library_names_the_extra(tmp_path, monkeypatch):
    path = tmp_path / "broken.urdf"
    path.write_text(_BROKEN)
    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.raises(ImportError, match=r"pip install 'robokin\[robots\]'"):
        visual_meshes(path, "base", "tip", max_bytes=1234)
    with pytest.raises(TypeError, match="max_bytes"):
        visual_meshes(path, "base", "tip", max_bytes=1.5)  # type: ignore[arg-type]  # a wrong type on purpose
    with pytest.raises(DomainError, match="max_bytes"):
        visual_meshes(path, "base", "tip", max_bytes=0)


# ------------------------------------------------------------------ in a browser
def _rgb(png):
    from PIL import Image
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)


@needs_robots
@pytest.mark.browser
def test_static_mesh_scene_renders_in_chromium(tmp_path, browser):
    from robokin.views.static_html import save_page

    chain = models.panda()
    scene = Scene(height=400)
    scene.add_chain(chain, Q["panda"], meshes="panda")
    empty = Scene(height=400)
    empty.add_points([[0.0, 0.0, 0.0]], radius=1e-4)
    page = save_page(tmp_path / "index.html", [scene, empty])

    pg, errors = watched_page(browser, 800, 900)
    pg.goto(page.as_uri())
    pg.wait_for_function("document.querySelectorAll('.robokin-scene canvas').length == 2", timeout=WAIT_MS)
    # both viewers have been fed every command and have drawn them (not a fixed sleep)
    pg.wait_for_function("""() => Array.from(document.querySelectorAll('.robokin-scene'))
        .every(box => box.robokinViewer && !box.robokinViewer.needs_render)""", timeout=WAIT_MS)
    # the meshes arrived as indexed geometry (uint32 indices decoded by the viewer)
    indexed = pg.evaluate("""() => { var n = 0;
        document.querySelector('.robokin-scene').robokinViewer.scene.traverse(function (o) {
          if (o.isMesh && o.geometry.index && o.geometry.index.array instanceof Uint32Array) n++; });
        return n; }""")
    robot = scene.item("robot")
    assert isinstance(robot, ChainItem) and robot.meshes is not None
    assert indexed == sum(len(ms) for ms in robot.meshes.frames)
    canvases = pg.query_selector_all(".robokin-scene canvas")

    def robot_pixels(a):
        return (a.min(axis=-1) > 200) & (np.ptp(a, axis=-1) < 30)     # the Panda is white

    # screenshots taken again only while the robot is not drawn yet (at most 20 s)
    a, b = poll_until(lambda: [_rgb(c.screenshot()) for c in canvases[:2]], lambda s: robot_pixels(s[0]).sum() > 2000)
    white = robot_pixels(a)
    assert white.sum() > 2000, "no robot drawn"
    assert (np.abs(a - b).sum(axis=-1) > 60).sum() > 5000, "scene looks like the empty background"
    assert not errors, errors


@needs_robots
@pytest.mark.browser
def test_live_mesh_scene_reaches_the_browser(browser):
    pytest.importorskip("zmq")
    from robokin.views.live import LiveViewer

    scene = Scene()
    scene.add_chain(models.ur10(), Q["ur10"], meshes="ur10")
    with LiveViewer() as viewer:
        viewer.send_all(scene.commands())
        pg = browser.new_page(viewport={"width": 640, "height": 480})
        pg.goto(viewer.web_url)
        pg.wait_for_function("""() => { var n = 0; if (!window.viewer) return false;
            window.viewer.scene.traverse(function (o) { if (o.isMesh && o.geometry.index) n++; });
            return n >= 15; }""", timeout=WAIT_MS)
        pg.close()
