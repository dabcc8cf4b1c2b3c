"""The MeshCat commands and static HTML of representative scenes, byte for byte.

The book stores scenes by the hash of their data (``_static/scenes/<key>.js``),
so a refactoring of :mod:`robokin.views` must not change a single byte of
``Scene.commands()`` (as packed for a page) or ``Scene.to_html()``. The hashes
below were recorded before the views were split into layers; a change to
the drawing itself updates them deliberately, in the same commit.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest

from support.views_doubles import scara_like

pytest.importorskip("umsgpack")
from robokin import models, views
from robokin.views.static_html import pack_commands

Q_UR10 = np.array([0.1, -1.2, 1.5, -0.4, 1.2, 0.3])


def _ur10_frames_target():
    ur, scene = models.ur10(), views.Scene()
    scene.add_chain(ur, Q_UR10, frames=True)
    scene.add_target(ur.fk(Q_UR10), label="goal")
    return scene


def _ur10_ghost_points_path():
    ur, scene = models.ur10(), views.Scene(height=300, grid=False)
    scene.add_chain(ur, Q_UR10)
    scene.add_ghost(ur, -Q_UR10)
    scene.add_points(np.random.default_rng(0).random((20, 3)), radius=0.02)
    scene.add_path(np.random.default_rng(1).random((30, 3)))
    return scene


def _cloud():
    scene = views.Scene()
    scene.add_points(np.random.default_rng(2).random((800, 3)))
    return scene


def _ur10_animation():
    scene = views.Scene()
    scene.animate(models.ur10(), np.linspace(Q_UR10, -Q_UR10, 25), dt=0.1, loop=True)
    return scene


def _targets():
    scene = views.Scene()
    scene.add_target(np.eye(4))
    scene.add_target(np.array([0.3, 0.2, 0.1]), size=0.1)
    return scene


def _ar601_leg():
    chain, scene = models.ar601_leg(), views.Scene()
    q = np.linspace(0.1, 0.5, int(chain.n))
    scene.add_chain(chain, q, frames=True)
    scene.animate(chain, np.linspace(q, -q, 7), dt=0.2)
    return scene


def _scara():
    chain, scene = scara_like(), views.Scene()
    q = np.linspace(0.1, 0.3, int(chain.n))
    scene.add_chain(chain, q, frames=True)
    scene.animate(chain, np.linspace(q, 2 * q, 9), dt=0.1)
    return scene


#: name: (scene builder, sha256[:16] of the packed commands, sha256[:16] of to_html()).
SCENES = {
    "ur10 with frames and a target": (_ur10_frames_target, "3b3fce98759c15d9", "717664b259d222b3"),
    "ur10, ghost, points, path, no grid": (_ur10_ghost_points_path, "32b3889180d2890b", "772c91207d5ffa2d"),
    "point cloud (800 points)": (_cloud, "bce8275f9b230421", "36ba42d425958373"),
    "ur10 animation, looped": (_ur10_animation, "324a7714e05bf358", "6f726058e1006f4e"),
    "targets alone": (_targets, "66ac7a56517e0fe7", "4b945c8adab12bed"),
    "ar601 leg, frames, animation": (_ar601_leg, "ccd36afefa7e98e4", "c79ae0e7d73037ca"),
    "prismatic joint, animation (scale tracks)": (_scara, "32f73bc420175732", "b5ce021f85b02d3b"),
}


@pytest.mark.parametrize("name", list(SCENES))
def test_scene_bytes_are_unchanged(name):
    build, commands_hash, html_hash = SCENES[name]
    scene = build()
    packed = json.dumps(pack_commands(scene.commands())).encode()
    assert hashlib.sha256(packed).hexdigest()[:16] == commands_hash, f"{name}: MeshCat commands changed"
    assert hashlib.sha256(scene.to_html().encode()).hexdigest()[:16] == html_hash, f"{name}: to_html() changed"
