"""Live MeshCat servers started by robokin.

:class:`LiveViewer` starts ``python -m robokin.views._server`` (a MeshCat
server listening on 127.0.0.1 only, on the first free web port from 7000),
talks to it over a zmq ``ipc://`` socket in a private folder (mode 0700), and
gives the URL the notebook should show in an iframe, which carries a random
secret (``secrets.token_urlsafe``) without which the server answers 404 -- so on
a shared machine (a JupyterHub node) other users can neither read nor change a
student's scene:

- ``http://127.0.0.1:<port>/<secret>/static/`` normally;
- ``{JUPYTERHUB_SERVICE_PREFIX or "/"}proxy/<port>/<secret>/static/`` when
  ``jupyter-server-proxy`` is importable or the kernel runs under JupyterHub/Binder
  (the browser cannot reach the kernel's loopback, the Jupyter server proxies it;
  the proxy may be installed in the server's environment only).

Every server is stopped by :meth:`LiveViewer.close`, when the viewer is garbage
collected, at interpreter exit (``weakref.finalize`` runs at exit), and -- if the
kernel is killed -- by the server itself, which watches its parent process.
"""

from __future__ import annotations

import importlib.util
import os
import secrets
import shutil
import subprocess
import sys
import tempfile
import time
import weakref
from collections.abc import Iterable
from typing import Any

import numpy as np

from robokin.views import optional
from robokin.views.meshcat_draw import set_transform_command
from robokin.views.record import DEFAULT_HEIGHT

__all__ = ["LiveViewer", "MeshcatUnavailable", "proxy_url", "get_viewer", "close_all"]

_SERVERS: weakref.WeakSet[LiveViewer] = weakref.WeakSet()
_SHARED: LiveViewer | None = None


class MeshcatUnavailable(RuntimeError):
    """The MeshCat server could not be started or reached."""


def proxy_url(port: int, secret: str = "") -> str | None:
    """The URL of a local port through jupyter-server-proxy, or None where the browser should use loopback.

    The proxied form is used when ``jupyter-server-proxy`` is importable, and always
    on JupyterHub/Binder (``JUPYTERHUB_SERVICE_PREFIX`` set): there the browser never
    runs on the kernel's machine, so ``127.0.0.1`` cannot work, and the proxy is often
    installed in the server's environment only, not in the kernel's.

    Parameters
    ----------
    port : int
        The server's local web port.
    secret : str, optional
        The server's URL token (a path segment before ``static/``).

    Returns
    -------
    str or None
        ``<prefix>proxy/<port>/<secret>/static/``, or None (use the loopback URL).
    """
    hub_prefix = os.environ.get("JUPYTERHUB_SERVICE_PREFIX")
    if not hub_prefix and importlib.util.find_spec("jupyter_server_proxy") is None:
        return None
    prefix = hub_prefix or "/"
    if not prefix.endswith("/"):
        prefix += "/"
    return f"{prefix}proxy/{int(port)}/{secret + '/' if secret else ''}static/"


def _stop(proc, logfile, folder=None):
    try:
        if proc.poll() is None:
            proc.terminate()
            try:
                proc.wait(timeout=3)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait(timeout=3)
    finally:
        try:
            logfile.close()
        except Exception:  # noqa: BLE001
            pass
        if folder is not None:
            shutil.rmtree(folder, ignore_errors=True)


class LiveViewer:
    """A MeshCat server process plus a zmq client.

    ``send(cmd)`` sends a command dict, ``send_transforms([(path, T)])`` only
    transforms.

    Parameters
    ----------
    port : int, optional
        The first web port tried (the next free one is used).
    timeout : float, optional
        Seconds to wait for the server to start.

    Raises
    ------
    MeshcatUnavailable
        meshcat is not installed, or the server did not start.
    """

    def __init__(self, *, port: int = 7000, timeout: float = 20.0) -> None:
        try:
            self._umsgpack = optional.umsgpack()
            zmq = optional.zmq()
        except ImportError as exc:
            raise MeshcatUnavailable(f"meshcat is not installed ({exc}); pip install 'robokin[views]'") from exc
        self._log = tempfile.TemporaryFile()
        self.secret = secrets.token_urlsafe(24)
        self._folder = tempfile.mkdtemp(prefix="robokin-meshcat-")   # mode 0700: only this user
        cmd = [sys.executable, "-u", "-m", "robokin.views._server", "--port", str(int(port)),
               "--zmq-url", f"ipc://{self._folder}/commands", "--parent-pid", str(os.getpid())]
        try:
            self.process = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=self._log,
                                            stdin=subprocess.PIPE, start_new_session=True)
            stdin, stdout = self.process.stdin, self.process.stdout
            assert stdin is not None and stdout is not None  # both are pipes (PIPE above)
            stdin.write(f"{self.secret}\n".encode())
            stdin.close()
        except OSError as exc:
            shutil.rmtree(self._folder, ignore_errors=True)
            raise MeshcatUnavailable(f"cannot start the MeshCat server: {exc}") from exc
        self._finalizer = weakref.finalize(self, _stop, self.process, self._log, self._folder)
        info: dict[str, str] = {}
        deadline = time.monotonic() + timeout
        while len(info) < 3:
            line = stdout.readline().decode("utf-8", "replace").strip()
            if not line:
                if self.process.poll() is not None or time.monotonic() > deadline:
                    self._finalizer()
                    raise MeshcatUnavailable(f"the MeshCat server did not start: {self._error_tail()}")
                continue
            key, _, value = line.partition("=")
            info[key] = value
        stdout.close()
        self.zmq_url = info["zmq_url"]
        self.web_url = info["web_url"]
        self.port = int(info["port"])
        self.pid = self.process.pid
        self._zmq = zmq
        self._context = zmq.Context.instance()
        self._socket: Any = None  # the zmq REQ socket, made by _connect
        self._last: dict[str, list[float]] = {}  # path -> last matrix (16 floats) sent by send_transforms
        self._connect()
        _SERVERS.add(self)

    def _error_tail(self):
        try:
            self._log.seek(0)
            text = self._log.read().decode("utf-8", "replace").strip().splitlines()
            return text[-1] if text else f"exit code {self.process.poll()}"
        except Exception:  # noqa: BLE001
            return f"exit code {self.process.poll()}"

    def _connect(self):
        if self._socket is not None:
            self._socket.close(linger=0)
        self._socket = self._context.socket(self._zmq.REQ)
        self._socket.setsockopt(self._zmq.RCVTIMEO, 5000)
        self._socket.setsockopt(self._zmq.SNDTIMEO, 5000)
        self._socket.setsockopt(self._zmq.LINGER, 0)
        self._socket.connect(self.zmq_url)

    # ---- state
    @property
    def alive(self) -> bool:
        """The server process is running."""
        return self.process.poll() is None

    @property
    def url(self) -> str:
        """The URL the browser should open (proxied on JupyterHub/Binder)."""
        return proxy_url(self.port, self.secret) or self.web_url

    # ---- commands
    def send(self, command: dict) -> None:
        """Send one MeshCat command.

        Parameters
        ----------
        command : dict
            A command in MeshCat's wire format (``type``, ``path``, ...).

        Raises
        ------
        MeshcatUnavailable
            The server has stopped or does not answer.
        """
        if not self.alive:
            raise MeshcatUnavailable("the MeshCat server has stopped")
        frames = [command["type"].encode(), command.get("path", "").encode(),
                  self._umsgpack.packb(command, force_float_precision="single")]
        try:
            self._socket.send_multipart(frames)
            self._socket.recv()
        except self._zmq.ZMQError as exc:
            self._connect()
            raise MeshcatUnavailable(f"no answer from the MeshCat server: {exc}") from exc

    def send_all(self, commands: Iterable[dict]) -> None:
        """Send commands in order (e.g. ``scene.commands()``).

        Parameters
        ----------
        commands : iterable of dict
        """
        self._last.clear()
        for c in commands:
            self.send(c)

    def send_transforms(self, transforms: Iterable[tuple[str, np.ndarray]]) -> None:
        """Send ``set_transform`` for each node whose pose changed since the last call: no geometry.

        Parameters
        ----------
        transforms : iterable of (str, array_like of shape (4, 4))
            MeshCat path and pose (m), as :func:`~robokin.views.meshcat_draw.chain_transforms` returns.
        """
        for path, T in transforms:
            command = set_transform_command(path, T)
            if self._last.get(path) != command["matrix"]:
                self.send(command)
                self._last[path] = command["matrix"]

    def delete(self, path: str = "/meshcat") -> None:
        """Delete a node of the scene and everything under it.

        Parameters
        ----------
        path : str, optional
            MeshCat path; default the whole scene.
        """
        self.send({"type": "delete", "path": path})
        self._last.clear()

    def iframe_html(self, height: int = DEFAULT_HEIGHT) -> str:
        """An ``<iframe>`` of the viewer (resizable).

        Parameters
        ----------
        height : int, optional
            CSS pixels.

        Returns
        -------
        str
            HTML.
        """
        return (f'<div style="height:{int(height)}px;width:100%;overflow:hidden;resize:vertical">'
                f'<iframe src="{self.url}" style="width:100%;height:100%;border:none"></iframe></div>')

    # ---- life cycle
    def close(self) -> None:
        """Stop the server process (idempotent)."""
        if self._socket is not None:
            self._socket.close(linger=0)
            self._socket = None
        self._finalizer()
        global _SHARED
        if _SHARED is self:
            _SHARED = None

    def __enter__(self) -> LiveViewer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self):
        state = "running" if self.alive else "stopped"
        return f"<LiveViewer {self.web_url} pid={self.pid} {state}>"


def get_viewer() -> LiveViewer:
    """The kernel's shared live viewer, started on first use.

    Returns
    -------
    LiveViewer

    Raises
    ------
    MeshcatUnavailable
        The server cannot start.
    """
    global _SHARED
    if _SHARED is None or not _SHARED.alive:
        _SHARED = LiveViewer()
    return _SHARED


def close_all() -> None:
    """Stop every server robokin started in this process."""
    for v in list(_SERVERS):
        v.close()
