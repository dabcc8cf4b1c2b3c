"""The real user path: JupyterLab -> kernel -> live MeshCat iframe + ipywidgets joint sliders.

A JupyterLab server is started on 127.0.0.1 (a port it picks, token, temporary root,
config, data, runtime and settings directories, the virtualenv's own
``jupyter-lab``), a notebook is opened in headless Chromium: its task statement
(MyST directives, as the chapters write them) must be rendered by jupyterlab-myst,
and its two code cells are run:

    views.show(arm, [0.3, 0.6])          # cell 1: live MeshCat scene in an iframe
    s = views.joint_sliders(arm)         # cell 2: one slider per joint + its own scene

The test checks that the iframes point at the kernel's loopback MeshCat server
(or the jupyter-server-proxy URL), that the scenes draw something, that there is
one slider per joint, that moving a slider with the keyboard moves the robot
(and measures that round trip), and that shutting the kernel and the server down
leaves no kernel and no MeshCat server behind.
"""

from __future__ import annotations

import importlib.util
import io
import json
import os
import secrets
import signal
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from support.browser_waits import DRAW_TIMEOUT, WAIT_MS, poll_until
from conftest import _skip_or_fail, chromium_path

pytestmark = pytest.mark.browser

JUPYTER_LAB = Path(sys.executable).with_name("jupyter-lab")

# Time limits: each a ceiling that a loaded machine does not reach when nothing hangs; every wait
# ends as soon as its condition holds, so a high ceiling costs nothing in a passing run.
#: seconds for jupyter-lab to answer its first request: a few seconds on the quiet 2-core machine
#: (imports, extensions), more at a high load; 60 s means it does not start
SERVER_START = 60.0
#: seconds for one REST call to the local server (milliseconds when it is well; a kernel's
#: shutdown waits for the kernel to exit)
API_REPLY = 15.0
#: seconds for a process to exit once told to (the server after /api/shutdown, a kernel, MeshCat)
PROCESS_EXIT = 10.0
#: milliseconds for JupyterLab's own page to be ready, the notebook opened and its kernel session
#: started: the browser waits' ceiling (browser_waits.DRAW_TIMEOUT) and the kernel's start
APP_READY_MS = 30_000
READOUT = ".jp-OutputArea-output .widget-html code"                    # the end-effector pose line
SLIDER_VALUE = ".jp-OutputArea-output .widget-slider .widget-readout"   # the first slider's value
#: Screenshots go to the test's tmp_path, or to this directory (e.g. ROBOKIN_SHOTS=/tmp) to look at them
#: (the whole page as JPEG: evidence for a reader, cheaper to encode; the asserted scenes as PNG).
SHOTS_DIR = os.environ.get("ROBOKIN_SHOTS")

CELLS = [
    ("import numpy as np\n"
     "from robokin import models, views\n"
     "arm = models.planar_two_link()\n"
     "views.show(arm, [0.3, 0.6])"),
    "s = views.joint_sliders(arm)",
]


def _require_jupyterlab():
    if importlib.util.find_spec("jupyterlab") is None or not JUPYTER_LAB.exists():
        message = f"JupyterLab is not installed in this environment ({JUPYTER_LAB} missing): pip install jupyterlab"
        if os.environ.get("CI") and chromium_path() is not None:
            pytest.fail(f"{message} (CI=true and Chromium present: the live check must run)")
        pytest.skip(message)
    for module in ("ipywidgets", "meshcat", "zmq", "psutil"):
        if importlib.util.find_spec(module) is None:
            _skip_or_fail(f"{module} is not installed: pip install 'robokin[views]' psutil")


#: A task statement as the chapters write it (MyST): jupyterlab-myst (requirements.txt) renders it;
#: without it, JupyterLab shows the directives' markup as text.
MYST_CELL = """```{exercise}
:label: live-task

Write `tool_position(q)`.
```

```{admonition} Pitfall: degrees for radians
:class: warning

NumPy's `cos` takes radians.
```"""


def _notebook():
    cells: list[dict[str, Any]] = [{"cell_type": "markdown", "id": "task", "metadata": {}, "source": MYST_CELL}]
    cells += [{"cell_type": "code", "execution_count": None, "id": f"cell{k}", "metadata": {},
               "outputs": [], "source": src} for k, src in enumerate(CELLS)]
    return {"cells": cells, "nbformat": 4, "nbformat_minor": 5,
            "metadata": {"kernelspec": {"display_name": "Python 3 (ipykernel)", "language": "python",
                                        "name": "python3"},
                         "language_info": {"name": "python"}}}


class Lab:
    """A JupyterLab server in its own process group, with a tiny REST client."""

    def __init__(self, tmp: Path):
        self.root = tmp / "root"
        self.root.mkdir()
        (self.root / "live.ipynb").write_text(json.dumps(_notebook(), indent=1))
        dirs = {name: tmp / name for name in ("config", "data", "runtime", "ipython", "settings", "workspaces")}
        for d in dirs.values():
            d.mkdir()
        # no announcement/news toast on top of the notebook
        (dirs["config"] / "labconfig").mkdir()
        # where jupyter-server-proxy is installed (JupyterHub, Binder), serve the scenes through it
        # as there: robokin's kernel side then points the iframes at <prefix>proxy/<port>/static/
        self.proxied = importlib.util.find_spec("jupyter_server_proxy") is not None
        if self.proxied:
            (dirs["config"] / "jupyter_server_config.d").mkdir()
            (dirs["config"] / "jupyter_server_config.d" / "jupyter_server_proxy.json").write_text(json.dumps(
                {"ServerApp": {"jpserver_extensions": {"jupyter_server_proxy": True}}}))
        (dirs["config"] / "labconfig" / "page_config.json").write_text(json.dumps(
            {"disabledExtensions": {"@jupyterlab/apputils-extension:announcements": True}}))
        env = {k: v for k, v in os.environ.items()
               if not k.startswith(("JPY_", "JUPYTER", "ROBOKIN_", "IPYTHON", "PYDEVD"))}
        env.update(JUPYTER_CONFIG_DIR=str(dirs["config"]), JUPYTER_DATA_DIR=str(dirs["data"]),
                   JUPYTER_RUNTIME_DIR=str(dirs["runtime"]), IPYTHONDIR=str(dirs["ipython"]),
                   JUPYTERLAB_SETTINGS_DIR=str(dirs["settings"]),
                   JUPYTERLAB_WORKSPACES_DIR=str(dirs["workspaces"]),
                   PATH=f"{JUPYTER_LAB.parent}{os.pathsep}{env.get('PATH', '')}",
                   PYDEVD_DISABLE_FILE_VALIDATION="1")
        self.runtime = dirs["runtime"]
        self.port: int | None = None   # the server picks a free port (--port=0): wait_ready reads it
        self.base: str | None = None
        self.token = secrets.token_hex(16)
        self.log = (tmp / "jupyter-lab.log").open("wb")
        self.proc = subprocess.Popen(
            [str(JUPYTER_LAB), "--no-browser", "--ip=127.0.0.1", "--port=0", "--port-retries=0",
             f"--ServerApp.root_dir={self.root}", f"--IdentityProvider.token={self.token}",
             "--LabApp.expose_app_in_browser=True", "--ServerApp.terminals_enabled=False",
             "--LabApp.extension_manager=readonly", *(["--allow-root"] if os.geteuid() == 0 else [])],
            cwd=self.root, env=env, stdin=subprocess.DEVNULL, stdout=self.log, stderr=subprocess.STDOUT,
            start_new_session=True)
        self.log_path = tmp / "jupyter-lab.log"

    def api(self, method, path, timeout=API_REPLY):
        req = urllib.request.Request(f"{self.base}{path}", method=method,
                                     headers={"Authorization": f"token {self.token}"},
                                     data=b"" if method == "POST" else None)
        with urllib.request.urlopen(req, timeout=timeout) as r:
            body = r.read()
        return json.loads(body) if body else None

    def wait_ready(self, timeout=SERVER_START):
        """Wait until the server answers, reading its port from its runtime file first.

        The server binds a port the system gives it (``--port=0``) and names it in
        ``jpserver-<pid>.json``: a port chosen by the test and bound by the server
        seconds later could be taken by another process in between.
        """
        deadline = time.monotonic() + timeout
        info = self.runtime / f"jpserver-{self.proc.pid}.json"
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                pytest.fail(f"jupyter-lab exited with {self.proc.returncode}:\n{self.tail()}")
            try:
                if self.base is None:
                    self.port = json.loads(info.read_text())["port"]
                    self.base = f"http://127.0.0.1:{self.port}"
                self.api("GET", "/api/status", timeout=1.0)   # one try; tried again until SERVER_START
                return
            except (OSError, urllib.error.URLError, ValueError, KeyError):   # no (complete) file yet
                time.sleep(0.1)
        pytest.fail(f"jupyter-lab did not answer within {timeout:.0f} s:\n{self.tail()}")

    def tail(self, n=40):
        try:
            return "\n".join(self.log_path.read_text(errors="replace").splitlines()[-n:])
        except OSError:
            return ""

    def processes(self, module):
        """psutil.Process of everything under the server running ``python -m module`` (kernels, MeshCat)."""
        import psutil
        try:
            children = psutil.Process(self.proc.pid).children(recursive=True)
        except psutil.Error:
            return []
        found = []
        for p in children:
            try:
                if module in p.cmdline():
                    found.append(p)
            except psutil.Error:
                pass
        return found

    def shutdown(self):
        """Kernels via the REST API, then the server; kill the process group if that fails."""
        try:
            for kernel in self.api("GET", "/api/kernels"):
                self.api("DELETE", f"/api/kernels/{kernel['id']}")
            self.api("POST", "/api/shutdown")
        except (OSError, urllib.error.URLError, ValueError):
            pass
        try:
            self.proc.wait(timeout=PROCESS_EXIT)
        except subprocess.TimeoutExpired:
            for sig in (signal.SIGTERM, signal.SIGKILL):
                try:
                    os.killpg(self.proc.pid, sig)
                    self.proc.wait(timeout=PROCESS_EXIT)
                    break
                except (ProcessLookupError, subprocess.TimeoutExpired):
                    continue
        self.log.close()


def _gone(procs, timeout=PROCESS_EXIT):
    """The processes among ``procs`` still running after ``timeout`` seconds."""
    import psutil
    deadline = time.monotonic() + timeout
    def running(p):
        try:
            return p.is_running() and p.status() != psutil.STATUS_ZOMBIE
        except psutil.Error:
            return False

    alive = [p for p in procs if running(p)]
    while alive and time.monotonic() < deadline:
        time.sleep(0.1)
        alive = [p for p in alive if running(p)]
    return alive


def _describe(p):
    try:
        return f"{p.pid}: {' '.join(p.cmdline()[:4])}"
    except Exception:  # noqa: BLE001 - it may just have exited
        return str(p.pid)


def _pixels(png):
    from PIL import Image
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)


def _frame_of(page, iframe_handle, timeout=DRAW_TIMEOUT):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        frame = iframe_handle.content_frame()
        if frame is not None:
            return frame
        page.wait_for_timeout(50)
    pytest.fail("the MeshCat iframe has no content frame")


def _wait_drawn(frame, timeout_ms=WAIT_MS):
    """The MeshCat page inside an iframe has its canvas and has received the scene."""
    frame.wait_for_selector("#meshcat-pane canvas", state="attached", timeout=timeout_ms)
    frame.wait_for_function("typeof viewer !== 'undefined' && viewer.num_messages_received > 0",
                            timeout=timeout_ms)


def _settled(frame, quiet=0.4, timeout=DRAW_TIMEOUT):
    """Wait until the viewer in ``frame`` has received no message for ``quiet`` seconds; returns the count."""
    deadline = time.monotonic() + timeout
    count, since = frame.evaluate("viewer.num_messages_received"), time.monotonic()
    while time.monotonic() < deadline:
        time.sleep(0.1)
        now = frame.evaluate("viewer.num_messages_received")
        if now != count:
            count, since = now, time.monotonic()
        elif time.monotonic() - since >= quiet:
            return count
    pytest.fail(f"the MeshCat viewer kept receiving messages for {timeout:.0f} s")


def _links(a):
    """Pixels of the robot's (orange) links."""
    return (a[..., 0] > 180) & (a[..., 1] > 100) & (a[..., 1] < 190) & (a[..., 2] < 80)


def _shot(locator, path):
    """Screenshot of ``locator`` saved to ``path``; returns the pixels, which must show the robot."""
    a = _pixels(locator.screenshot(path=str(path)))
    orange = _links(a)
    assert orange.sum() > 100, f"no robot links in the live scene (see {path})"
    return a


def test_live_scene_and_sliders_in_jupyterlab(tmp_path, browser):
    import psutil
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    _require_jupyterlab()
    shots = Path(SHOTS_DIR) if SHOTS_DIR else tmp_path
    t_start = time.perf_counter()
    timings = {}
    lab = Lab(tmp_path)
    context = None
    meshcat_procs = []
    kernel_procs = []
    srcs = []
    try:
        lab.wait_ready()
        timings["server"] = time.perf_counter() - t_start

        context = browser.new_context(viewport={"width": 1200, "height": 1400})
        page = context.new_page()
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(f"{lab.base}/lab/tree/live.ipynb?token={lab.token}&reset")
        page.wait_for_function("window.jupyterapp && window.jupyterapp.shell.currentWidget"
                               " && window.jupyterapp.shell.currentWidget.sessionContext", timeout=APP_READY_MS)
        page.evaluate("""async () => {
            const panel = window.jupyterapp.shell.currentWidget;
            await panel.context.ready;
            await panel.sessionContext.ready;
        }""")
        timings["lab open, kernel ready"] = time.perf_counter() - t_start

        # ---- the task statement (MyST) rendered, not shown as markup
        assert page.evaluate("window.jupyterapp.hasPlugin('jupyterlab-myst:mime-renderer')"), (
            "jupyterlab-myst is not installed (requirements.txt): task statements show as raw MyST")
        statement = page.locator(".jp-MarkdownCell").first     # its editor is hidden once rendered
        shown = poll_until(statement.inner_text, lambda text: "Pitfall" in text, 20.0)
        statement.screenshot(path=str(shots / "robokin-lab-task-statement.png"))
        assert "{admonition}" not in shown and "{exercise}" not in shown and ":class:" not in shown, shown
        assert "Exercise 1" in shown and "Write tool_position(q)." in shown and "cos takes radians." in shown, shown
        page.evaluate("window.jupyterapp.commands.execute('notebook:run-all-cells')")

        # ---- cell 1: the live scene in an output iframe
        outputs = page.locator(".jp-Cell .jp-OutputArea-output")
        iframes = page.locator(".jp-OutputArea-output iframe")
        try:
            iframes.nth(1).wait_for(state="attached", timeout=APP_READY_MS)
        except PlaywrightTimeout:
            page.screenshot(path=str(shots / "robokin-lab-fail.png"))
            texts = outputs.all_inner_texts()
            pytest.fail(f"no MeshCat iframes in the outputs; outputs: {texts}; page errors: {errors}\n"
                        f"{lab.tail()}")
        timings["cells run, iframes shown"] = time.perf_counter() - t_start
        srcs = [iframes.nth(k).get_attribute("src") for k in range(2)]
        for src in srcs:
            if lab.proxied:
                assert src.startswith("/proxy/") and src.endswith("/static/"), src
            else:
                assert src.startswith("http://127.0.0.1:") and src.endswith("/static/"), src
        assert srcs[0] != srcs[1], "show() and joint_sliders() share one scene server"

        # ---- the kernel and its MeshCat servers, with the environment the kernel really has
        kernel_procs = lab.processes("ipykernel_launcher")
        meshcat_procs = lab.processes("robokin.views._server")
        assert len(kernel_procs) == 1, [_describe(p) for p in kernel_procs]
        assert "JPY_SESSION_NAME" in kernel_procs[0].environ()
        assert len(meshcat_procs) == 2, [_describe(p) for p in meshcat_procs]
        assert all(p.ppid() == kernel_procs[0].pid for p in meshcat_procs)

        frames = [_frame_of(page, iframes.nth(k).element_handle()) for k in range(2)]
        for frame in frames:
            _wait_drawn(frame)
            # the grid lies in the robot's x-y plane: its normal is three.js's "up" (y); the grid
            # is scaled to the scene (its normal's length is the scale)
            normal = np.array(frame.evaluate("""() => {
                const g = viewer.scene_tree.find(['Grid', '<object>']).object;
                g.updateMatrixWorld(true);
                const e = g.matrixWorld.elements; return [e[4], e[5], e[6]]; }"""))
            assert np.allclose(normal / np.linalg.norm(normal), [0, 1, 0], atol=1e-6), (
                f"the grid is not horizontal: normal {normal}")
        # until the scene shows the robot (one more render after the last command)
        poll_until(lambda: _pixels(iframes.nth(0).screenshot()), lambda a: _links(a).sum() > 100)
        _shot(iframes.nth(0), shots / "robokin-lab-show.png")

        # ---- cell 2: one slider per joint under the second scene
        sliders = page.locator(".jp-OutputArea-output .widget-slider")
        sliders.first.wait_for(state="visible", timeout=WAIT_MS)
        assert sliders.count() == 2, f"{sliders.count()} sliders for 2 joints"
        readout = page.locator(READOUT).last
        readout.wait_for(state="visible", timeout=WAIT_MS)
        text_before = readout.inner_text()
        assert text_before.startswith("end-effector: p = ("), text_before
        page.screenshot(path=str(shots / "robokin-lab-page.jpg"), full_page=True, type="jpeg", quality=85)
        before = _shot(iframes.nth(1), shots / "robokin-lab-sliders-before.png")
        timings["scenes drawn"] = time.perf_counter() - t_start

        # ---- move the first joint with the keyboard and time the round trip
        handle = sliders.first.locator(".noUi-handle")
        value_before = sliders.first.locator(".widget-readout").inner_text()
        n_show = _settled(frames[0])
        n_before = _settled(frames[1])
        handle.focus()
        # one key press: browser -> comm -> kernel -> zmq -> MeshCat server -> websocket -> viewer
        t0 = time.perf_counter()
        handle.press("ArrowRight")
        frames[1].wait_for_function(f"viewer.num_messages_received > {n_before}", polling=10, timeout=WAIT_MS)
        t_one = time.perf_counter() - t0
        page.wait_for_function(f"([t]) => {{ const c = document.querySelectorAll({READOUT!r});"
                               " return c.length > 0 && c[c.length - 1].innerText !== t; }",
                               arg=[text_before], polling=10, timeout=WAIT_MS)   # re-rendered: query again
        t_readout = time.perf_counter() - t0
        # then 19 more (0.5 degree each), as a student holding the key down
        t0 = time.perf_counter()
        for _ in range(19):
            handle.press("ArrowRight")
        target = f"{float(value_before) + 10.0:.1f}"
        page.wait_for_function(f"([t]) => {{ const r = document.querySelector({SLIDER_VALUE!r});"
                               " return r !== null && r.innerText.trim() === t; }",
                               arg=[target], polling=10, timeout=WAIT_MS)
        _settled(frames[1], quiet=0.3)
        t_many = time.perf_counter() - t0
        assert sliders.first.locator(".widget-readout").inner_text().strip() == target
        # until the moved robot is drawn
        poll_until(lambda: _pixels(iframes.nth(1).screenshot()),
                   lambda a: (np.abs(a - before).sum(axis=-1) > 60).sum() > 200)
        after = _shot(iframes.nth(1), shots / "robokin-lab-sliders-after.png")
        changed = (np.abs(after - before).sum(axis=-1) > 60).sum()
        assert changed > 200, f"the scene did not move ({changed} pixels changed)"
        # the sliders drive their own scene only
        assert frames[0].evaluate("viewer.num_messages_received") == n_show
        timings["1 key -> scene update"] = t_one
        timings["1 key -> pose readout"] = t_readout
        timings["19 keys -> scene settled (incl. 0.3 s quiet)"] = t_many
        page.screenshot(path=str(shots / "robokin-lab-page-after.jpg"), full_page=True, type="jpeg", quality=85)
        assert not errors, errors
    finally:
        if context is not None:
            context.close()
        t_shutdown = time.perf_counter()
        if not meshcat_procs:
            kernel_procs = lab.processes("ipykernel_launcher")
            meshcat_procs = lab.processes("robokin.views._server")
        lab.shutdown()
        left = _gone([psutil.Process(lab.proc.pid)] if lab.proc.poll() is None else [])
        left += _gone(kernel_procs + meshcat_procs)
        timings["shutdown"] = time.perf_counter() - t_shutdown
        timings["total"] = time.perf_counter() - t_start
        print(f"\n[live-jupyter] iframes {srcs}: " + ", ".join(f"{k}: {v:.2f} s" for k, v in timings.items()))
        survivors = [_describe(p) for p in left]
        for p in left:
            try:
                p.kill()
            except psutil.Error:
                pass
    assert not survivors, f"still running after the kernel and server shut down: {survivors}"
