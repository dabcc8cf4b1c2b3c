"""Live MeshCat server management: loopback only, free port, no leftover process."""

from __future__ import annotations

import os
import socket
import sys
import time

import numpy as np
import pytest

from support.views_doubles import two_link

pytest.importorskip("meshcat")
pytest.importorskip("zmq")
from robokin.views.live import LiveViewer, proxy_url

# Time limits: ceilings a loaded machine does not reach when nothing hangs; each wait ends as soon
# as its condition holds, so a high ceiling costs nothing in a passing run.
#: seconds for the server to exit after its owner is gone: it looks at its parent every second
#: (robokin/views/_server.py) and is gone about 1.5 s after the owner on the quiet machine
SERVER_EXIT = 30.0
#: seconds for one HTTP request to the server on the loopback (milliseconds when it is well)
REPLY = 15.0
#: seconds for a Python that starts a server and returns (imports and the server's start: a few
#: seconds on the quiet machine)
OWNER_RUN = 120


def _listening(pid):
    """(address, port) pairs pid listens on, via psutil or /proc."""
    try:
        import psutil
        return {(c.laddr.ip, c.laddr.port) for c in psutil.Process(pid).net_connections(kind="inet")
                if c.status == psutil.CONN_LISTEN}
    except ImportError:
        pass
    inodes = set()
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            link = os.readlink(f"/proc/{pid}/fd/{fd}")
        except OSError:
            continue
        if link.startswith("socket:["):
            inodes.add(link[8:-1])
    out = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        with open(table) as f:
            for line in f.readlines()[1:]:
                parts = line.split()
                if parts[3] == "0A" and parts[9] in inodes:      # LISTEN
                    host, port = parts[1].split(":")
                    ip = ".".join(str(int(host[i:i + 2], 16)) for i in (6, 4, 2, 0)) if len(host) == 8 else host
                    out.add((ip, int(port, 16)))
    return out


def _gone(pid, timeout=SERVER_EXIT):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            with open(f"/proc/{pid}/stat") as f:
                if f.read().split()[2] == "Z":
                    return True
        except FileNotFoundError:
            return True
        time.sleep(0.05)
    return False


def test_server_on_loopback_free_port_and_cleaned_up():
    blocker = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    blocker.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        try:
            blocker.bind(("127.0.0.1", 7000))
            blocker.listen(1)
        except OSError:
            pass            # 7000 already taken by something else: just as good
        viewer = LiveViewer(port=7000)
        try:
            assert viewer.alive
            assert viewer.port != 7000
            assert viewer.web_url == f"http://127.0.0.1:{viewer.port}/{viewer.secret}/static/"
            listening = _listening(viewer.pid)
            assert listening == {("127.0.0.1", viewer.port)}, listening   # commands come over ipc, not TCP
            # drawing and transform-only updates work
            from robokin.views import Scene
            from robokin.views.meshcat_draw import chain_transforms
            s = Scene()
            s.add_chain(two_link(), [0.1, 0.2])
            viewer.send_all(s.commands())
            viewer.send_transforms(chain_transforms("robot", two_link(), np.array([0.5, 0.5])))
            # the page served at /static/ connects its websocket relative to its own URL (proxy-safe)
            import urllib.request
            page = urllib.request.urlopen(viewer.web_url, timeout=REPLY).read().decode()
            assert "location.pathname" in page and "main.min.js" in page
        finally:
            pid = viewer.pid
            viewer.close()
        assert not viewer.alive
        assert _gone(pid), "server process still running after close()"
    finally:
        blocker.close()


def test_server_exits_with_its_owner():
    import subprocess
    import sys

    code = ("from robokin.views.live import LiveViewer; v = LiveViewer(); print(v.pid, flush=True)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=OWNER_RUN,
                         cwd=os.path.dirname(os.path.dirname(__file__)))
    pid = int(out.stdout.split()[-1])
    assert _gone(pid), "server survived the interpreter that started it"



_KILLED_OWNER = """
import ctypes, os, signal, subprocess, sys, time
ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0)      # PR_SET_CHILD_SUBREAPER, like systemd --user / tini -s
code = ("from robokin.views.live import LiveViewer; v = LiveViewer(); print(v.pid, v.zmq_url, flush=True); "
        "import time; time.sleep(60)")
owner = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
pid, zmq_url = owner.stdout.readline().split()
pid, folder = int(pid), os.path.dirname(zmq_url.removeprefix("ipc://"))
assert os.path.isdir(folder), folder
owner.kill()                      # the kernel dies hard and is not reaped yet: a zombie
deadline, gone = time.monotonic() + SERVER_EXIT, False
while not gone and time.monotonic() < deadline:
    try:
        with open(f"/proc/{pid}/stat") as f:
            gone = f.read().split()[2] == "Z"
    except FileNotFoundError:
        gone = True
    time.sleep(0.05)
if not gone:
    try:
        with open(f"/proc/{pid}/stat") as f:
            print("server", f.read().split()[:4], "owner", owner.pid, "me", os.getpid(), flush=True)
        with open(f"/proc/{pid}/status") as f:
            print([l for l in f.read().splitlines() if l.startswith(("State", "Threads", "SigBlk", "SigIgn"))])
        print(open(f"/proc/{pid}/wchan").read(), flush=True)
    except OSError as exc:
        print(exc)
print("folder left" if os.path.exists(folder) else "folder removed", flush=True)
print("gone" if gone else "alive", flush=True)
owner.wait()
if not gone:
    os.kill(pid, signal.SIGKILL)
try:
    os.waitpid(pid, 0)            # we are its subreaper now: reap it either way
except ChildProcessError:
    pass
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_CHILD_SUBREAPER is Linux only")
def test_server_exits_when_its_kernel_is_killed_under_a_subreaper():
    # re-parented to a subreaper (not pid 1) while the killed kernel is an unreaped zombie:
    # the server must notice that its parent changed, not wait for the zombie to be reaped;
    # it removes its command socket's folder, which the killed kernel could not
    import subprocess

    out = subprocess.run([sys.executable, "-c", f"SERVER_EXIT = {SERVER_EXIT}\n" + _KILLED_OWNER], capture_output=True,
                         text=True, timeout=OWNER_RUN + SERVER_EXIT, check=False,
                         cwd=os.path.dirname(os.path.dirname(__file__)))
    assert out.stdout.strip().splitlines()[-2:] == ["folder removed", "gone"], out.stdout + out.stderr


def test_proxy_url(monkeypatch):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: object() if name == "jupyter_server_proxy" else real(name, *a))
    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", "/user/ada/")
    assert proxy_url(7001) == "/user/ada/proxy/7001/static/"
    assert proxy_url(7001, "s3cret") == "/user/ada/proxy/7001/s3cret/static/"
    monkeypatch.delenv("JUPYTERHUB_SERVICE_PREFIX")
    assert proxy_url(7001) == "/proxy/7001/static/"


def test_proxy_url_on_a_hub_even_if_the_kernel_lacks_the_proxy(monkeypatch):
    # JupyterHub/Binder: the browser is never on the kernel's machine, and the proxy is often
    # installed in the server's environment only
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "jupyter_server_proxy" else real(name, *a))
    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", "/user/ada")
    assert proxy_url(7002) == "/user/ada/proxy/7002/static/"
    monkeypatch.delenv("JUPYTERHUB_SERVICE_PREFIX")
    assert proxy_url(7002) is None


def test_only_the_owner_reaches_the_server():
    """Another user of the machine knows the port but not the secret: 404 for pages and websocket;
    the command socket is in a folder only the owner can open; the secret is not on the command line."""
    import stat
    import urllib.error
    import urllib.request

    with LiveViewer() as viewer:
        base = f"http://127.0.0.1:{viewer.port}"
        for path in ("/static/", "/static/main.min.js", "/", "/wrong-secret-0123456789/static/",
                     f"/{viewer.secret[:-1]}/static/"):
            with pytest.raises(urllib.error.HTTPError) as info:
                urllib.request.urlopen(base + path, timeout=REPLY)
            assert info.value.code == 404, path
        assert urllib.request.urlopen(viewer.web_url, timeout=REPLY).status == 200
        assert urllib.request.urlopen(viewer.web_url + "main.min.js", timeout=REPLY).status == 200
        assert viewer.zmq_url.startswith("ipc://")
        folder = os.path.dirname(viewer.zmq_url[len("ipc://"):])
        mode = os.stat(folder)
        assert stat.S_IMODE(mode.st_mode) == 0o700 and mode.st_uid == os.getuid()
        with open(f"/proc/{viewer.pid}/cmdline", "rb") as f:
            assert viewer.secret.encode() not in f.read()
        assert viewer.secret in viewer.url
    assert not os.path.exists(folder), "the private folder outlived the server"
