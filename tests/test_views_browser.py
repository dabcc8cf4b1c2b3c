"""A static scene opened from file:// in headless Chromium renders the robot and its animation controls."""

from __future__ import annotations


import numpy as np
import pytest

from support.browser_waits import WAIT_MS, pixels, poll_until, wait_drawn
from conftest import watched_page

from support.views_doubles import two_link

pytestmark = pytest.mark.browser

# The `browser` fixture (one headless Chromium for the whole session, skipped with a
# message when Chromium is missing, never skipped in CI) comes from conftest.py.


def _robot():
    from robokin.models import ur10

    chain = ur10()
    q0 = np.array([0.3, -1.2, 1.4, -1.0, -1.57, 0.4])
    return chain, q0, np.linspace(q0, q0 + [1.0, 0.5, -0.5, 0.3, 0.2, 0.1], 40)


def test_static_scene_renders_in_chromium(tmp_path, browser):
    from robokin.views import Scene
    from robokin.views.static_html import save_page

    chain, q0, Q = _robot()
    scene = Scene(height=400)
    scene.add_chain(chain, q0, frames=True)
    scene.animate("robot", Q, dt=0.05, play=False)
    empty = Scene(height=400)
    empty.add_points([[0.0, 0.0, 0.0]], radius=1e-4)     # nearly nothing: the background
    page = save_page(tmp_path / "index.html", [scene, empty])
    assert (tmp_path / "_static" / "meshcat" / "main.min.js").exists()
    assert "main.min.js" in page.read_text() and len(page.read_text()) < 200_000

    pg, errors = watched_page(browser, 800, 900)
    pg.goto(page.as_uri())
    pg.wait_for_selector(".robokin-scene canvas", state="attached", timeout=WAIT_MS)
    pg.wait_for_function("document.querySelectorAll('.robokin-scene canvas').length == 2", timeout=WAIT_MS)
    # the viewer script was loaded once for both scenes
    assert pg.evaluate("document.querySelectorAll('script[src$=\"main.min.js\"]').length") == 1
    canvases = pg.query_selector_all(".robokin-scene canvas")

    def links(a):
        return (a[..., 0] > 180) & (a[..., 1] > 100) & (a[..., 1] < 190) & (a[..., 2] < 80)

    def drawn(shots):
        a, b = shots
        return links(a).sum() > 200 and (np.abs(a - b).sum(axis=-1) > 60).sum() > 1000

    wait_drawn(pg)
    # screenshots of both scenes, taken again only while the robot is not drawn yet (at most 20 s)
    a, b = poll_until(lambda: [pixels(c.screenshot()) for c in canvases[:2]], drawn)
    orange = links(a)
    assert orange.sum() > 200, "robot links not drawn"
    assert (np.abs(a - b).sum(axis=-1) > 60).sum() > 1000, "scene looks like the empty background"
    # animation controls (dat.gui): play / pause / reset and the time slider
    names = pg.eval_on_selector_all(".robokin-scene:first-of-type .dg .property-name",
                                    "els => els.map(e => e.textContent)")
    for control in ("play", "pause", "reset", "time"):
        assert control in names, names
    assert not pg.query_selector_all(".robokin-scene-msg")            # loading messages are gone
    assert not errors, errors


def test_missing_viewer_script_shows_message(tmp_path, browser):
    from robokin.views import Scene
    from robokin.views.static_html import save_page

    scene = Scene()
    scene.add_chain(two_link())
    page = save_page(tmp_path / "index.html", [scene], copy_viewer=False)
    pg = browser.new_page()
    pg.goto(page.as_uri())
    pg.wait_for_function("document.querySelector('.robokin-scene-msg').textContent.indexOf('not shown') >= 0",
                         timeout=WAIT_MS)
    assert "cannot load" in pg.text_content(".robokin-scene-msg")


def test_scene_data_moved_beside_the_page_still_renders(tmp_path, browser):
    """The book moves each scene's data to _static/scenes/<key>.js (small pages; a scene
    shown twice stored once); the page, opened from file://, still draws it."""
    from robokin.views import Scene
    from robokin.views.sphinx_extension import externalize_scene_data
    from robokin.views.static_html import save_page

    chain, q0, _ = _robot()
    scene = Scene(height=300)
    scene.add_chain(chain, q0)
    page = save_page(tmp_path / "chapter" / "page.html", [scene, scene], copy_viewer=False)
    save_page(tmp_path / "index.html", [], copy_viewer=True)          # the viewer at the book's root
    html = page.read_text().replace('<html data-content_root="./">', '<html data-content_root="../">')
    page.write_text(html)
    inline = len(html)
    assert externalize_scene_data(tmp_path) == 2
    assert externalize_scene_data(tmp_path) == 0                      # idempotent
    files = list((tmp_path / "_static" / "scenes").glob("*.js"))
    assert len(files) == 1 and len(page.read_text()) < inline - 2000  # stored once, out of the page
    assert 'data-src="../_static/scenes/' in page.read_text()
    # one script for every scene, linked, not a copy in each (about 6 kB a scene)
    assert (tmp_path / "_static" / "robokin-scene.js").exists()
    assert "(function ()" not in page.read_text()
    assert page.read_text().count('<script src="../_static/robokin-scene.js" data-animated="false">') == 2

    pg, errors = watched_page(browser, 800, 800)
    pg.goto(page.as_uri())
    pg.wait_for_function("document.querySelectorAll('.robokin-scene canvas').length >= 1", timeout=WAIT_MS)
    pg.evaluate("document.querySelectorAll('.robokin-scene')[1].scrollIntoView()")   # the lazy second scene
    pg.wait_for_function("document.querySelectorAll('.robokin-scene canvas').length == 2", timeout=WAIT_MS)
    assert not errors, errors
    assert pg.evaluate("document.querySelectorAll('script[src$=\".js\"][src*=\"scenes\"]').length") == 1


def test_large_command_shared_by_two_scenes_is_stored_once(tmp_path, browser):
    """A large command (a robot's mesh, here a big point cloud) in two different scenes
    goes to one file of its own; both scenes still draw."""
    from robokin.views import Scene
    from robokin.views.sphinx_extension import SHARED_COMMAND_SIZE, externalize_scene_data
    from robokin.views.static_html import pack_commands, save_page

    chain, q0, Q = _robot()
    cloud = np.random.default_rng(0).uniform(-0.5, 0.5, (3000, 3))
    scenes = []
    for q in (q0, Q[-1]):
        scene = Scene(height=300)
        scene.add_chain(chain, q)
        scene.add_path(cloud)
        scenes.append(scene)
    assert max(len(c) for c in pack_commands(scenes[0].commands())) >= SHARED_COMMAND_SIZE
    page = save_page(tmp_path / "index.html", scenes)
    assert externalize_scene_data(tmp_path) == 2
    files = sorted((tmp_path / "_static" / "scenes").glob("*.js"))
    shared = [f for f in files if '"] = "' in f.read_text()]               # one command, not a scene's list
    assert len(files) == 3 and len(shared) == 1, [f.stat().st_size for f in files]

    pg, errors = watched_page(browser, 800, 700)
    pg.goto(page.as_uri())
    pg.evaluate("document.querySelectorAll('.robokin-scene')[1].scrollIntoView()")
    pg.wait_for_function("document.querySelectorAll('.robokin-scene canvas').length == 2", timeout=WAIT_MS)
    assert not errors, errors


def test_linked_scene_script_reads_each_scene_s_animated_flag(tmp_path, browser):
    """The book links one script from every scene; it opens the animation controls of an
    animated scene only, as each scene's own copy did."""
    from robokin.views import Scene
    from robokin.views.sphinx_extension import externalize_scene_data
    from robokin.views.static_html import save_page

    chain, q0, Q = _robot()
    still, animated = Scene(height=300), Scene(height=300)
    for scene in (still, animated):
        scene.add_chain(chain, q0)
    animated.animate("robot", Q[:3], dt=0.05, play=False)
    page = save_page(tmp_path / "index.html", [still, animated])
    assert externalize_scene_data(tmp_path) == 2
    assert 'data-animated="false"' in page.read_text() and 'data-animated="true"' in page.read_text()

    pg, errors = watched_page(browser, 800, 700)
    pg.goto(page.as_uri())
    pg.evaluate("document.querySelectorAll('.robokin-scene')[1].scrollIntoView()")
    pg.wait_for_function("document.querySelectorAll('.robokin-scene canvas').length == 2", timeout=WAIT_MS)
    controls = pg.evaluate("Array.from(document.querySelectorAll('.robokin-scene')).map("
                           "s => Array.from(s.querySelectorAll('.dg .property-name')).map(e => e.textContent))")
    assert "play" not in controls[0] and "play" in controls[1], controls
    assert not errors, errors


def test_point_cloud_renders_in_chromium(tmp_path, browser):
    """More than 500 points are one MeshCat Points object: drawn, and the page stays small."""
    from robokin.views import Scene
    from robokin.views.static_html import save_page

    rng = np.random.default_rng(1)
    cloud = Scene(height=400)
    cloud.add_points(rng.uniform(-0.5, 0.5, (20_000, 3)), radius=0.01, color=0xFF0000)
    empty = Scene(height=400)
    empty.add_points([[0.0, 0.0, 0.0]], radius=1e-4)
    page = save_page(tmp_path / "index.html", [cloud, empty])
    assert len(page.read_text()) < 600_000        # 12 bytes a point, base64: ~320 kB
    pg, errors = watched_page(browser, 800, 900)
    pg.goto(page.as_uri())
    pg.wait_for_function("document.querySelectorAll('.robokin-scene canvas').length == 2", timeout=WAIT_MS)
    canvases = pg.query_selector_all(".robokin-scene canvas")

    def reds(a):
        return (a[..., 0] > 150) & (a[..., 1] < 80) & (a[..., 2] < 80)

    wait_drawn(pg)
    # screenshots taken again only while the cloud is not drawn yet (at most 20 s)
    shots = poll_until(lambda: [pixels(c.screenshot()) for c in canvases], lambda s: reds(s[0]).sum() > 2000)
    red = reds(shots[0])
    assert red.sum() > 2000, "point cloud not drawn"
    assert not errors, errors
