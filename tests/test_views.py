"""Tests of robokin.views: scene recording, MeshCat lowering, static export, modes, plots."""

from __future__ import annotations

import base64
import json
import re
import subprocess
import sys
from typing import Any

import numpy as np
import pytest

from support.views_doubles import scara_like, two_link, zero_length

umsgpack = pytest.importorskip("umsgpack")
views = pytest.importorskip("robokin.views")
from robokin.views import Scene  # noqa: E402
from robokin.views.meshcat_draw import chain_layout  # noqa: E402
from robokin.views.record import EllipsoidItem  # noqa: E402


def _decode(html):
    payload = re.search(r'<script type="application/json" class="robokin-scene-data">(.*?)</script>', html, re.S)
    assert payload is not None, "no scene data in the page"
    return [umsgpack.unpackb(base64.b64decode(s)) for s in json.loads(payload.group(1))]


def _demo_scene(chain=None):
    chain = chain or two_link()
    s = Scene()
    s.add_chain(chain, [0.3, 0.5], frames=True)
    s.add_ghost(chain, [0.8, -0.5])
    T = np.eye(4)
    T[:3, 3] = [1.2, 0.6, 0.2]
    s.add_target(T, label="goal")
    s.add_points([[0.5, 0.5, 0.0], [1.0, 1.0, 0.0]])
    s.add_path([[0, -1, 0], [1, -1, 0.5], [1.5, 0, 0]])
    s.animate("robot", np.linspace([0, 0], [1.5, 1.0], 30), dt=0.05)
    return s


# ------------------------------------------------------------------ import hygiene
def test_import_robokin_does_not_import_viewers():
    code = ("import sys, robokin, robokin.views; "
            "bad = [m for m in ('matplotlib', 'meshcat', 'ipywidgets', 'zmq', 'IPython') if m in sys.modules]; "
            "print(bad)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


# ------------------------------------------------------------------ static export
def test_static_export_contains_every_object_and_the_animation():
    s = _demo_scene()
    html = s.to_html()
    cmds = _decode(html)
    assert [c["type"] for c in cmds] == [c["type"] for c in s.commands()]
    object_paths = {c["path"] for c in cmds if c["type"] == "set_object"}
    # every item has geometry: robot links/joints/ee, ghost, target triad, both points, path, trace
    for stem in ("/meshcat/robot/", "/meshcat/ghost/", "/meshcat/target/", "/meshcat/points/0",
                 "/meshcat/points/1", "/meshcat/path", "/meshcat/robot_trace"):
        assert any(p.startswith(stem) for p in object_paths), stem
    assert "/meshcat/robot/1_link1/joint" in object_paths
    assert "/meshcat/robot/3_tool/marker" in object_paths
    assert "/meshcat/robot/0_base/triad/label" in object_paths  # frame labels
    anim = [c for c in cmds if c["type"] == "set_animation"]
    assert len(anim) == 1
    tracks = {a["path"]: [t["name"] for t in a["clip"]["tracks"]] for a in anim[0]["animations"]}
    assert tracks["/meshcat/robot/1_link1"] == [".position", ".quaternion"]
    assert "/meshcat/robot/0_base" not in tracks          # never moves: no track
    assert "/meshcat/ghost/1_link1" not in tracks
    times = np.frombuffer(anim[0]["animations"][0]["clip"]["tracks"][0]["times"].data, dtype="<f4")
    assert len(times) == 30 and times[-1] == pytest.approx(29 * 0.05)


def test_static_html_references_shared_viewer_and_does_not_inline_it():
    html = _demo_scene().to_html()
    assert "_static/meshcat/main.min.js" in html
    assert "data-content_root" in html
    assert len(html) < 100_000                 # the 850 kB viewer is not in there
    assert "MeshCat.Viewer" in html and "handle_command_bytearray" in html
    assert "window.robokinMeshCat" in html     # loaded once per page
    assert "MeshCat viewer" in html            # visible message until the viewer runs


def test_static_export_is_deterministic():
    a, b = _demo_scene().to_html(), _demo_scene().to_html()
    assert a == b
    s = _demo_scene()
    assert s.to_html() == s.to_html() == s._repr_html_()
    assert not re.search(r"\d{10}", a.split("robokin-scene-data")[0])   # no timestamps in the markup


def test_prismatic_link_is_animated_with_scale():
    s = Scene()
    s.animate(scara_like(), np.linspace([0, 0, 0], [1.0, -1.0, 0.3], 10), dt=0.1)
    anim = [c for c in s.commands() if c["type"] == "set_animation"][0]
    scaled = [a for a in anim["animations"] if any(t["name"] == ".scale" for t in a["clip"]["tracks"])]
    assert [a["path"] for a in scaled] == ["/meshcat/robot/link_2"]
    assert any(c["type"] == "set_object" and c["path"] == "/meshcat/robot/3_link3/joint" and
               c["object"]["geometries"][0]["type"] == "BoxGeometry" for c in s.commands())


def test_layout_skips_zero_length_links_and_sizes_scale_with_reach():
    small = chain_layout(two_link(0.1, 0.08), np.zeros(2))
    big = chain_layout(two_link(1.0, 0.8), np.zeros(2))
    assert big["reach"] == pytest.approx(10 * small["reach"])
    assert [i for i, _, _ in big["segments"]] == [1, 2]     # base -> frame 1 has zero length
    r_small = Scene()
    r_small.add_chain(two_link(0.1, 0.08))
    r_big = Scene()
    r_big.add_chain(two_link(1.0, 0.8))

    def link_radius(scene):
        c = next(c for c in scene.commands() if c["path"].endswith("/link") and c["type"] == "set_object")
        return c["object"]["geometries"][0]["radiusTop"]
    assert link_radius(r_big) == pytest.approx(10 * link_radius(r_small), rel=1e-3)


# ------------------------------------------------------------------ bad input
def test_zero_length_chain_raises_value_error():
    with pytest.raises(ValueError, match="zero length"):
        Scene().add_chain(zero_length())


def test_trajectory_of_wrong_width_names_argument_and_shapes():
    s = Scene()
    with pytest.raises(ValueError, match=r"trajectory must have shape \(T, 2\).*got shape \(5, 3\)"):
        s.animate(two_link(), np.zeros((5, 3)), dt=0.1)
    with pytest.raises(ValueError, match="dt"):
        s.animate(two_link(), np.zeros((5, 2)), dt=0.0)
    with pytest.raises(ValueError, match=r"q must have shape \(2,\)"):
        s.add_chain(two_link(), [0.0, 0.0, 0.0])


def test_duplicate_names_and_bad_points_raise():
    s = Scene()
    s.add_chain(two_link())
    with pytest.raises(ValueError, match="already used"):
        s.add_chain(two_link(), name="robot")
    with pytest.raises(ValueError, match="points"):
        s.add_points(np.zeros((4, 5)))
    with pytest.raises(ValueError, match="T must be"):
        s.add_target(np.eye(3))


# ------------------------------------------------------------------ modes
def test_mode_selection(monkeypatch):
    from robokin.views.display import choose_mode

    monkeypatch.delenv("ROBOKIN_VIEWER", raising=False)
    monkeypatch.delenv("JPY_SESSION_NAME", raising=False)
    assert choose_mode() == "static"                       # not in a browser kernel
    monkeypatch.setenv("JPY_SESSION_NAME", "x.ipynb")
    assert choose_mode() == "static"                       # ... and not in an IPython kernel either
    monkeypatch.setenv("ROBOKIN_VIEWER", "matplotlib")
    assert choose_mode() == "matplotlib"
    assert choose_mode("live") == "live"                   # argument beats the environment
    monkeypatch.setenv("ROBOKIN_VIEWER", "nonsense")
    with pytest.raises(ValueError, match="ROBOKIN_VIEWER"):
        choose_mode()


def test_show_static_and_matplotlib_display(monkeypatch):
    from robokin.views import display as disp

    shown: list[Any] = []
    monkeypatch.setattr(disp, "display", shown.append)
    s = _demo_scene()
    s.show(mode="static")
    assert shown[-1].data == s.to_html()
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    s.show(mode="matplotlib")
    assert type(shown[-1]).__name__ == "Figure"


@pytest.mark.parametrize("mode, shown_type", [("static", "HTML"), ("matplotlib", "Figure")])
def test_joint_sliders_outside_live_mode_show_the_chain_in_that_mode(monkeypatch, mode, shown_type):
    from robokin.views import display as disp
    from robokin.views import sliders

    if mode == "matplotlib":
        matplotlib = pytest.importorskip("matplotlib")
        matplotlib.use("Agg")
    shown: list[Any] = []
    monkeypatch.setattr(disp, "display", shown.append)
    monkeypatch.setattr(sliders, "display", shown.append)
    sliders.joint_sliders(two_link(), [0.3, -0.2], mode=mode)
    assert "running Jupyter kernel" in shown[0].data
    assert type(shown[1]).__name__ == shown_type


def test_live_failure_falls_back_to_static(monkeypatch):
    from robokin.views import display as disp
    from robokin.views import live

    def broken(*a, **k):
        raise live.MeshcatUnavailable("no zmq today")
    monkeypatch.setattr(live, "LiveViewer", broken)
    shown: list[Any] = []
    monkeypatch.setattr(disp, "display", shown.append)
    s = _demo_scene()
    s.show(mode="live")
    assert "no zmq today" in shown[0].data and "static" in shown[0].data
    assert shown[1].data == s.to_html()


# ------------------------------------------------------------------ matplotlib
@pytest.fixture
def mpl():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    yield plt
    plt.close("all")


def test_plot_chain_single_and_batch(mpl):
    ax = views.plot_chain(two_link(), [0.3, 0.4])
    assert ax.name == "3d" and ax.get_xlabel() == "x [m]"
    ax2 = views.plot_chain(two_link(), np.linspace([0, 0], [1, 1], 4))
    assert len(ax2.lines) > len(ax.lines)
    with pytest.raises(ValueError, match="q must have shape"):
        views.plot_chain(two_link(), np.zeros((3, 5)))


def test_plot_planar_and_history(mpl):
    ax = views.plot_planar([[(0, 0), (1, 0)], [(1, 0), (1.5, 0.5)]], points=[(0, 0), (1, 0)], annotate=["A", "B"])
    assert ax.get_ylabel() == "y [m]" and len(ax.texts) == 2
    t = np.linspace(0, 1, 20)
    fig = views.plot_history(t=t, q=np.c_[t, t ** 2], dq=np.c_[np.ones(20), 2 * t],
                             error=np.exp(-5 * t), singular_values=np.c_[1 + t, 1 - t / 2],
                             joint_names=["q1", "q2"])
    labels = [a.get_ylabel() for a in fig.axes]
    assert labels[0] == "joint position q [rad]" and "rad/s" in labels[1]
    assert fig.axes[2].get_yscale() == "log" and fig.axes[-1].get_xlabel() == "time t [s]"
    fig2 = views.plot_history({"q": np.zeros((5, 2)), "errors": np.ones((5, 6))})
    assert fig2.axes[-1].get_xlabel() == "iteration"


def test_scene_plot(mpl):
    ax = _demo_scene().plot()
    assert ax.name == "3d" and len(ax.lines) > 5


# ------------------------------------------------------------------ sphinx extension
def test_sphinx_extension_copies_viewer(tmp_path):
    from types import SimpleNamespace

    from robokin.views import sphinx_extension

    connected = []
    app = SimpleNamespace(connect=lambda ev, fn: connected.append((ev, fn)), outdir=str(tmp_path),
                          builder=SimpleNamespace(format="html"))
    meta = sphinx_extension.setup(app)
    assert meta["parallel_read_safe"] and connected[0][0] == "build-finished"
    connected[0][1](app, None)
    assert (tmp_path / "_static" / "meshcat" / "main.min.js").stat().st_size > 500_000
    assert (tmp_path / "_static" / "meshcat" / "LICENSE").exists()


@pytest.mark.parametrize("animated", [False, True])
def test_stored_scene_gets_the_current_script(animated):
    """A notebook stores its scenes as they were when it was executed: the book gives each
    the current script, its id, viewer source and animated flag kept, its data untouched."""
    from robokin.views.static_html import refresh_scene_scripts, scene_html

    current = scene_html(_demo_scene().commands(), animated=animated, viewer_src="../viewer.js")
    older = current.replace("drawOnlyNear(viewer);\n", "").replace('watch("0px"', 'watch("100px"')
    page = f"<p>before</p>{older}<p>between</p>{older}"
    refreshed, changed = refresh_scene_scripts(page)
    assert changed == 2 and refreshed == f"<p>before</p>{current}<p>between</p>{current}"
    assert refresh_scene_scripts(refreshed) == (refreshed, 0)


def test_slider_update_sends_only_transforms():
    from robokin.views.sliders import JointSliders

    sent = []

    class FakeViewer:
        def send_transforms(self, transforms):
            sent.extend(transforms)

    js = JointSliders(two_link(), [0.0, 0.0], viewer=FakeViewer())  # type: ignore[arg-type]  # a stand-in: send_transforms only
    text = js.update(np.array([np.pi / 2, 0.0]))
    assert "p = (+0.000, +1.800, +0.000) m" in text and "+90.0" in text
    assert {p for p, _ in sent} == {"/meshcat/robot/0_base", "/meshcat/robot/1_link1",
                                    "/meshcat/robot/2_link2", "/meshcat/robot/3_tool"}


@pytest.mark.parametrize("model", ["planar_two_link", "eth_leg", "ur10", "baxter_left"])
def test_book_models_draw_and_animate(model):
    models = pytest.importorskip("robokin.models")
    chain = getattr(models, model)()
    Q = np.linspace(np.zeros(chain.n), np.full(chain.n, 0.5), 20)
    s = Scene()
    s.add_chain(chain, Q[0], frames=True)
    s.add_target(chain.fk(Q[-1]))
    s.animate("robot", Q, dt=0.05)
    html = s.to_html()
    cmds = _decode(html)
    joints = [c for c in cmds if c["type"] == "set_object" and c["path"].endswith("/joint")]
    assert len(joints) == chain.n
    assert len(html) < 150_000


def test_module_show_one_call(monkeypatch):
    from robokin.views import display as disp

    shown: list[Any] = []
    monkeypatch.setattr(disp, "display", shown.append)
    chain = two_link()
    T = np.eye(4)
    T[:3, 3] = [1, 1, 0]
    assert views.show(chain, [0.1, 0.2], targets=T, ghosts=[[0.5, 0.5]], points=[[1, 0, 0]],
                      path=[[0, 0, 0], [1, 1, 0]], trajectory=np.zeros((5, 2)), mode="static") is None
    paths = {c["path"].split("/")[2] for c in _decode(shown[-1].data) if c.get("path", "").startswith("/meshcat/")}
    assert {"robot", "ghost", "target", "points", "path", "robot_trace"} <= paths


def test_grid_is_only_shifted_and_scaled_not_turned():
    # the viewer's own Rx(π/2) sits on "/Grid/<object>"; a turn on "/Grid" would stand the grid up
    cmds = {c["path"]: c for c in _demo_scene().commands() if c["type"] == "set_transform"}
    grid = np.array(cmds["/Grid"]["matrix"]).reshape(4, 4).T        # MeshCat matrices are column-major
    shift = np.array(cmds["/meshcat"]["matrix"]).reshape(4, 4).T
    scale = grid[0, 0]
    assert 0 < scale < 1
    np.testing.assert_allclose(grid[:3, :3], scale * np.eye(3))
    np.testing.assert_allclose(grid[:3, 3], [0.0, 0.0, shift[2, 3]])   # under the scene's centre, at z = 0


@pytest.mark.parametrize("build", ["demo", "hanging", "ur10"])
def test_grid_is_a_floor_in_front_of_the_camera_around_the_robot(build):
    """The floor grid (MeshCat's 20 m grid, scaled) lies in front of the camera -- a renderer
    that drops lines crossing the camera's plane drew only the far part of the 20 m grid,
    above the robot in the picture -- and its square covers what the scene draws."""
    from robokin.models import baxter_left, ur10
    from robokin.views import Scene
    from robokin.views.geometry import scene_points

    if build == "demo":
        scene = _demo_scene()
    else:
        arm = baxter_left(base="shoulder") if build == "hanging" else ur10()
        scene = Scene()
        scene.add_chain(arm, arm.limits.mean(axis=1))
    cmds = scene.commands()
    transforms = {c["path"]: np.array(c["matrix"]).reshape(4, 4).T for c in cmds if c["type"] == "set_transform"}
    grid, shift = transforms["/Grid"], transforms["/meshcat"]
    eye = next(c["value"] for c in cmds if c.get("property") == "position" and c["path"].startswith("/Cameras"))
    eye = np.array([eye[0], -eye[2], eye[1]])            # three.js (y up) -> the scene's z-up frame
    half = 10.0 * grid[0, 0]                              # the grid's half side (m)
    corners = np.array([[x, y, 0.0] for x in (-half, half) for y in (-half, half)]) + grid[:3, 3]
    view = -eye / np.linalg.norm(eye)                     # the camera looks at the origin
    assert np.all((corners - eye) @ view > 0.1 * np.linalg.norm(eye)), "a grid corner is behind the camera"
    drawn = scene_points(scene) + shift[:3, 3]            # what the scene draws, in the viewer's frame
    assert np.all(np.abs(drawn[:, :2]) <= half) and drawn[:, 2].min() >= grid[2, 3] - 1e-5   # 6 decimals sent


def test_animate_without_name_moves_the_robot_not_its_ghost():
    from robokin.models import planar_two_link
    from robokin.views import Scene

    arm = planar_two_link()
    scene = Scene()
    scene.add_ghost(arm, [1.0, 0.5])
    scene.add_chain(arm, [0.0, 0.0])
    assert scene.animate(arm, np.linspace([0.0, 0.0], [0.5, 0.5], 5)) == "robot"


def test_grid_is_a_floor_under_a_hanging_arm():
    # Baxter's arm hangs below its shoulder frame: the grid goes to the lowest point drawn,
    # not through the shoulder (where it reads as a ceiling); a standing robot keeps z = 0.
    from robokin.models import baxter_left
    from robokin.views import Scene

    arm = baxter_left(base="shoulder")
    q = arm.limits.mean(axis=1)
    scene = Scene()
    scene.add_chain(arm, q)
    cmds = {c["path"]: c for c in scene.commands() if c["type"] == "set_transform"}
    grid = np.array(cmds["/Grid"]["matrix"]).reshape(4, 4).T
    shift = np.array(cmds["/meshcat"]["matrix"]).reshape(4, 4).T
    floor = grid[2, 3] - shift[2, 3]                                     # grid height in the robot's frame
    lowest = arm.frames(q)[:, 2, 3].min()
    assert lowest < -0.04 and floor == pytest.approx(lowest, abs=1e-6)
    np.testing.assert_allclose(grid[:3, :3], grid[0, 0] * np.eye(3))
    standing = {c["path"]: c for c in _demo_scene().commands() if c["type"] == "set_transform"}
    assert np.array(standing["/Grid"]["matrix"]).reshape(4, 4).T[2, 3] == pytest.approx(
        np.array(standing["/meshcat"]["matrix"]).reshape(4, 4).T[2, 3])


# ------------------------------------------------------------------ ellipsoids
def _ellipsoid_transform(scene, name="ellipsoid"):
    """The (4, 4) transform MeshCat receives for the ellipsoid item ``name`` (from the scene's commands)."""
    (command,) = [c for c in scene.commands() if c["type"] == "set_transform" and c["path"] == f"/meshcat/{name}"]
    return np.array(command["matrix"]).reshape(4, 4).T     # column-major, as three.js reads it


def _random_axes(rng):
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return Q                                               # det +1 or -1: both are accepted


@pytest.mark.parametrize("seed", range(5))
def test_ellipsoid_is_the_unit_sphere_moved_by_axes_times_radii(seed):
    rng = np.random.default_rng(seed)
    center, radii, axes = rng.uniform(-1, 1, 3), np.sort(rng.uniform(0.05, 0.5, 3))[::-1], _random_axes(rng)
    s = Scene()
    assert s.add_ellipsoid(center, radii, axes, color=0xD62728, opacity=0.5) == "ellipsoid"
    T = _ellipsoid_transform(s)
    assert np.allclose(T[:3, :3], axes @ np.diag(radii), atol=1e-6)
    assert np.allclose(T[:3, 3], center, atol=1e-6) and np.array_equal(T[3], [0, 0, 0, 1])
    (obj,) = [c["object"] for c in s.commands() if c["type"] == "set_object" and c["path"] == "/meshcat/ellipsoid"]
    assert obj["geometries"][0]["type"] == "SphereGeometry" and obj["geometries"][0]["radius"] == 1.0
    assert obj["materials"][0]["color"] == 0xD62728 and obj["materials"][0]["opacity"] == 0.5
    # the static page holds the sphere and the same transform (in float32)
    stored = [c for c in _decode(s.to_html()) if c["path"] == "/meshcat/ellipsoid"]
    assert [c["type"] for c in stored] == ["set_object", "set_transform"]
    assert np.allclose(np.array(stored[1]["matrix"]).reshape(4, 4).T, T, atol=1e-6)
    # the camera frames it: the scene's box holds the ellipsoid's farthest points along every base axis
    from robokin.views.geometry import scene_points
    P = scene_points(s)
    reach = np.linalg.norm(axes * radii, axis=1)
    assert np.allclose(P.max(axis=0), np.maximum(center + reach, 0.0))
    assert np.allclose(P.min(axis=0), np.minimum(center - reach, 0.0))


def test_ellipsoid_of_a_chain_at_its_tool():
    ur10 = pytest.importorskip("robokin.models").ur10()
    q = np.array([0.3, -1.2, 1.0, -0.6, 1.1, 0.4])
    radii, axes = ur10.velocity_ellipsoid(q)
    s = Scene()
    s.add_chain(ur10, q)
    s.add_ellipsoid(ur10.fk(q)[:3, 3], 0.2 * radii, axes, name="velocity")
    T = _ellipsoid_transform(s, "velocity")
    sigma = np.linalg.svd(ur10.position_jacobian(q), compute_uv=False)
    assert np.allclose(np.linalg.norm(T[:3, :3], axis=0), 0.2 * sigma, atol=2e-6)
    assert np.allclose(T[:3, 3], ur10.fk(q)[:3, 3], atol=1e-6)
    assert "ellipsoid 'velocity'" in repr(s)


@pytest.mark.parametrize("radii, drawn", [
    ([0.3, 0.1, 0.0], [0.3, 0.1, 3e-4]),           # a velocity ellipsoid at a singularity: a flat disc
    ([0.2, 0.0, 0.0], [0.2, 2e-4, 2e-4]),          # a needle
    ([1e-7, 0.0, 0.0], [1e-5, 1e-5, 1e-5]),        # shorter than a 6-decimal transform keeps
])
def test_ellipsoid_zero_radius_is_drawn_flat_not_singular(radii, drawn):
    s = Scene()
    s.add_ellipsoid([0.1, 0.2, 0.3], radii, np.eye(3))
    T = _ellipsoid_transform(s)
    assert np.allclose(T[:3, :3], np.diag(drawn), atol=1e-12)
    assert np.all(np.linalg.norm(T[:3, :3], axis=0) > 0)       # three.js decomposes it without NaN
    ellipsoid = s.item("ellipsoid")
    assert isinstance(ellipsoid, EllipsoidItem)
    assert np.array_equal(ellipsoid.radii, radii)               # the record keeps what was given


@pytest.mark.parametrize("arguments, error, match", [
    (([0, 0], [1, 1, 1], np.eye(3)), ValueError, r"center must have shape \(3,\).*got shape \(2,\)"),
    (([0, 0, np.nan], [1, 1, 1], np.eye(3)), ValueError, "center must be finite"),
    (("origin", [1, 1, 1], np.eye(3)), TypeError, "center must be a position"),
    (([0, 0, 0], [1, 1], np.eye(3)), ValueError, r"radii must have shape \(3,\).*got shape \(2,\)"),
    (([0, 0, 0], [1, -1, 1], np.eye(3)), ValueError, r"radii must be non-negative.*-1\.0"),
    (([0, 0, 0], [1, np.nan, 1], np.eye(3)), ValueError, "radii must be non-negative"),
    (([0, 0, 0], [np.inf, 1, 1], np.eye(3)), ValueError, "infinite semi-axis.*np.minimum"),
    (([0, 0, 0], [0, 0, 0], np.eye(3)), ValueError, "at least one positive"),
    (([0, 0, 0], "big", np.eye(3)), TypeError, "radii must be three semi-axes"),
    (([0, 0, 0], [1, 1, 1], np.eye(2)), ValueError, r"axes must have shape \(3, 3\).*got shape \(2, 2\)"),
    (([0, 0, 0], [1, 1, 1], 2 * np.eye(3)), ValueError, "axes must hold orthonormal unit axes.*3"),
    (([0, 0, 0], [1, 1, 1], [[1, 1, 0], [0, 1, 0], [0, 0, 1]]), ValueError, "orthonormal"),
    (([0, 0, 0], [2e6, 1, 1], np.eye(3)), ValueError, "reaches 2e\\+06 m"),
])
def test_ellipsoid_bad_input_names_the_argument(arguments, error, match):
    s = Scene()
    with pytest.raises(error, match=match):
        s.add_ellipsoid(*arguments)
    assert s.items == []


def test_ellipsoid_bad_style_and_name():
    s = Scene()
    s.add_ellipsoid([0, 0, 0], [1, 1, 1], np.eye(3))
    with pytest.raises(ValueError, match="already used"):
        s.add_ellipsoid([0, 0, 0], [1, 1, 1], np.eye(3), name="ellipsoid")
    with pytest.raises(ValueError, match=r"opacity must be in \(0, 1\]"):
        s.add_ellipsoid([0, 0, 0], [1, 1, 1], np.eye(3), opacity=0.0)
    with pytest.raises(TypeError, match="color"):
        s.add_ellipsoid([0, 0, 0], [1, 1, 1], np.eye(3), color="blue")
    assert s.add_ellipsoid([0, 0, 0], [1, 1, 1], np.eye(3)) == "ellipsoid_2"


def test_ellipsoid_in_the_matplotlib_figure(mpl):
    s = Scene()
    s.add_ellipsoid([0.5, 0, 0.2], [0.3, 0.2, 0.0], np.eye(3))
    ax = s.plot()
    assert len(ax.lines) == 3                      # its three principal ellipses, the flat one too
    assert np.isclose(max(line.get_data_3d()[0].max() for line in ax.lines), 0.8)
