"""Views given bad or huge input: a robokin error naming the argument, or a capped, announced subsample.

The cases the robustness review found (each a numpy/struct error or a silent
wrong picture before), and the caps: a million points, path points or animation
steps give a page of a few MB and one ViewWarning with the numbers, in well
under 500 MB of memory.
"""

from __future__ import annotations

import subprocess
import sys
import warnings

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from robokin import models, views
from robokin.errors import DomainError, ShapeError, ViewWarning
from robokin.views import Scene, arguments
from robokin.views.record import PathItem, PointsItem

ARM = models.planar_two_link()
UR10 = models.ur10()

# (call, exception type, words the message must contain)
BAD_CALLS = {
    "empty trajectory": (lambda: views.show(UR10, trajectory=np.zeros((0, 6)), mode="static"),
                         ShapeError, ["trajectory", "(T, 6)", "(0, 6)"]),
    "string trajectory": (lambda: views.show(UR10, trajectory="abc", mode="static"),
                          TypeError, ["trajectory", "str"]),
    "NaN trajectory": (lambda: views.show(UR10, trajectory=np.full((3, 6), np.nan), mode="static"),
                       DomainError, ["trajectory"]),
    "no points": (lambda: Scene().add_points(np.zeros((0, 3))), ShapeError, ["points", "at least 1"]),
    "path too large for float32": (lambda: Scene().add_path([[0, 0, 0], [1e39, 0, 0]]),
                                   DomainError, ["points", "1e+39"]),
    "string points": (lambda: Scene().add_points("abc"), TypeError, ["points", "str"]),
    "string path": (lambda: Scene().add_path("abc"), TypeError, ["points", "str"]),
    "string target": (lambda: Scene().add_target("abc"), TypeError, ["T", "str"]),
    "string q": (lambda: Scene().add_chain(ARM, "abc"), TypeError, ["q", "str"]),
    "string chain": (lambda: Scene().add_chain("ur10"), TypeError, ["chain", "kinematic chain"]),  # type: ignore[arg-type]  # a wrong type on purpose
    "string animation": (lambda: Scene().animate(ARM, "abc"), TypeError, ["trajectory", "str"]),
    "string plot_chain": (lambda: views.plot_chain(ARM, "abc"), TypeError, ["q", "str"]),
    "scaled target": (lambda: Scene().add_target(2 * np.eye(4)), DomainError, ["T", "homogeneous transform"]),
    "target bottom row": (lambda: Scene().add_target(np.vstack([np.eye(4)[:3], [0.5, 0, 0, 1]])),
                          DomainError, ["T", "bottom row"]),
    "empty history": (lambda: views.plot_history(q=np.zeros((0, 2))), ShapeError, ["q", "no samples"]),
    "NaN history": (lambda: views.plot_history(error=np.full(5, np.nan)), DomainError, ["error", "no finite"]),
    "string color": (lambda: Scene().add_points(np.zeros((2, 3)), color="red"), TypeError, ["color"]),
    "unknown chain item": (lambda: Scene().animate("robot", np.zeros((3, 2))), DomainError, ["chain", "robot"]),
    "string height": (lambda: Scene(height="abc"), TypeError, ["height"]),  # type: ignore[arg-type]  # a wrong type on purpose
    "negative height": (lambda: Scene(height=-5), DomainError, ["height"]),
    "html height": (lambda: Scene().to_html(height="x"), TypeError, ["height"]),  # type: ignore[arg-type]  # a wrong type on purpose
    "plot_scene str": (lambda: views.plot_scene("abc"), TypeError, ["scene"]),  # type: ignore[arg-type]  # a wrong type on purpose
    "save_page str": (lambda: views.save_page("x.html", "abc"), TypeError, ["scenes"]),
    "plot_planar str": (lambda: views.plot_planar(segments="abc"), TypeError, ["segments"]),
    "int name": (lambda: Scene().add_points([[0, 0, 0]], name=5), TypeError, ["name"]),  # type: ignore[arg-type]  # a wrong type on purpose
    "endless animation": (lambda: Scene().animate(ARM, np.zeros((3, 2)), dt=1e300), DomainError, ["dt"]),
}


@pytest.mark.parametrize("case", sorted(BAD_CALLS))
def test_bad_view_input_names_the_argument(case):
    call, kind, words = BAD_CALLS[case]
    with pytest.raises(kind) as info:
        call()
    message = str(info.value)
    for word in words:
        assert word in message, f"{case}: {word!r} not in {message!r}"


@pytest.mark.parametrize("method, cap, what", [("add_points", "MAX_POINTS", "points"),
                                               ("add_path", "MAX_PATH_POINTS", "points")])
def test_points_past_the_cap_are_subsampled_with_a_warning(monkeypatch, method, cap, what):
    monkeypatch.setattr(arguments, cap, 100)
    points = np.column_stack([np.linspace(0, 1, 1_000), np.zeros(1_000), np.zeros(1_000)])
    scene = Scene()
    with pytest.warns(ViewWarning, match=r"1,000 points are more than a scene keeps \(100\); drawing 100"):
        getattr(scene, method)(points) if method == "add_points" else scene.add_path(points)
    item = scene.items[0]
    assert isinstance(item, (PointsItem, PathItem))
    kept = item.points
    assert len(kept) == 100 and np.array_equal(kept[0], points[0]) and np.array_equal(kept[-1], points[-1])


def test_animation_past_the_cap_is_subsampled_in_time(monkeypatch):
    monkeypatch.setattr(arguments, "MAX_ANIMATION_STEPS", 50)
    Q = np.column_stack([np.linspace(0, 1, 500), np.zeros(500)])
    scene = Scene()
    with pytest.warns(ViewWarning, match=r"500 steps are more than a scene keeps \(50\)"):
        scene.animate(ARM, Q, dt=0.01)
    animation = scene.animations[0]
    assert len(animation.times) == 50 and animation.times[-1] == pytest.approx(4.99)
    assert np.array_equal(animation.trajectory[-1], Q[-1])


def test_a_million_items_stay_under_500_mb():
    """10⁶ points, 10⁶ path points and 10⁶ animation steps: pages of a few MB, peak memory < 500 MB."""
    code = """
import warnings
import numpy as np
from robokin import models
from robokin.views import Scene
warnings.simplefilter("ignore")
N = 1_000_000
rng = np.random.default_rng(0)
sizes = []
for kind in ("points", "path", "animation"):
    scene = Scene()
    if kind == "points":
        scene.add_points(rng.uniform(-1, 1, (N, 3)))
    elif kind == "path":
        scene.add_path(rng.uniform(-1, 1, (N, 3)))
    else:
        scene.animate(models.planar_two_link(), rng.uniform(-1, 1, (N, 2)), dt=0.001)
    sizes.append(len(scene.to_html()))
# peak resident memory of this process alone (ru_maxrss would include the parent's at fork)
peak = int(next(line.split()[1] for line in open("/proc/self/status") if line.startswith("VmHWM")))
print(peak, *sizes)
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    peak_kb, sizes = int(out[0]), [int(s) for s in out[1:]]
    assert peak_kb < 500_000, f"peak {peak_kb / 1000:.0f} MB"
    assert max(sizes) < 20_000_000, sizes


def test_caps_are_stated_in_the_docstrings():
    assert "100 000" in (Scene.add_points.__doc__ or "") and "100 000" in (Scene.add_path.__doc__ or "")
    assert "20 000" in (Scene.animate.__doc__ or "")
    assert arguments.MAX_POINTS == 100_000 and arguments.MAX_ANIMATION_STEPS == 20_000


def test_valid_input_still_draws_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        scene = Scene()
        scene.add_chain(ARM, [0.1, 0.2])
        scene.add_target(np.eye(4), size=0.2)
        scene.add_target([0.5, 0.0, 0.0])
        scene.add_points(np.zeros((3, 2)), radius=0.02)
        scene.add_path(np.eye(3))
        scene.animate("robot", np.zeros((4, 2)), times=[0.0, 0.1, 0.3, 0.35])
        assert "<div" in scene.to_html()
