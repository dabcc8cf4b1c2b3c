"""MeshCat server process started by :mod:`robokin.views.live` (``python -m robokin.views._server``).

Differences from ``meshcat-server``:

- only the user who started it can reach it. The commands come over a zmq
  ``ipc://`` socket in a folder only that user can open (mode 0700), not a TCP
  port; the web pages and the websocket (which sends the whole scene to whoever
  connects) are served only under ``/<secret>/``, a random token the kernel
  passes on the server's standard input (not its command line, which every user
  of the machine can read) and puts in the iframe's URL. Any other path is 404;
- the web server listens on 127.0.0.1 only (MeshCat's own ``app.listen(port)``
  binds all interfaces);
- ``/<secret>/static/`` serves a page whose websocket URL is relative to the
  page (so it also works behind jupyter-server-proxy at
  ``.../proxy/<port>/<secret>/static/``);
- the process exits by itself when its parent (the Jupyter kernel) is gone, and
  then removes the command socket and its folder (which the kernel, gone, cannot).
"""

from __future__ import annotations

import argparse
import os
import sys

HOST = "127.0.0.1"

INDEX = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>MeshCat (robokin)</title>
<style>body{margin:0}#meshcat-pane{width:100vw;height:100vh;overflow:hidden}</style></head>
<body><div id="meshcat-pane"></div>
<script src="main.min.js"></script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
var base = location.pathname.replace(/static\\/(index\\.html)?$/, "");
var url = (location.protocol === "https:" ? "wss://" : "ws://") + location.host + base;
try { viewer.connect(url); } catch (e) { console.info("Not connected to MeshCat websocket server: ", e); }
</script></body></html>
"""


def main(argv: list[str] | None = None) -> None:
    """Run the server until the parent process exits (``python -m robokin.views._server``).

    Parameters
    ----------
    argv : list of str, optional
        ``--port`` (first web port tried), ``--zmq-url`` (``ipc://`` address of the
        command socket), ``--parent-pid``; default ``sys.argv[1:]``. The URL
        token comes on standard input.
    """
    first_ppid = os.getppid()     # before anything slow: the kernel may be killed right after starting us
    parser = argparse.ArgumentParser()
    parser.add_argument("--port", type=int, default=7000, help="first web port to try")
    parser.add_argument("--zmq-url", required=True, help="ipc:// address of the command socket")
    parser.add_argument("--parent-pid", type=int, default=None)
    args = parser.parse_args(argv)
    secret = sys.stdin.readline().strip()   # the URL token: never on the command line
    if len(secret) < 16 or not secret.replace("-", "").replace("_", "").isalnum():
        raise SystemExit("robokin.views._server: expected a URL token (>= 16 URL-safe characters) on stdin")

    import tornado.ioloop
    import tornado.web
    from meshcat.servers import zmqserver

    class IndexHandler(tornado.web.RequestHandler):
        def get(self):
            self.set_header("Content-Type", "text/html; charset=utf-8")
            self.set_header("Cache-Control", "no-store")
            self.write(INDEX)

    class Bridge(zmqserver.ZMQWebSocketBridge):
        def make_app(self):
            app = tornado.web.Application([
                (rf"/{secret}/static/?", IndexHandler),
                (rf"/{secret}/static/index\.html", IndexHandler),
                (rf"/{secret}/static/(.*)", zmqserver.StaticFileHandlerNoCache,
                 {"path": zmqserver.VIEWER_ROOT, "default_filename": zmqserver.VIEWER_HTML}),
                (rf"/{secret}/", zmqserver.WebSocketHandler, {"bridge": self}),
            ])
            listen = app.listen

            def listen_on_loopback(port, **kwargs):
                return listen(port, address=HOST, **kwargs)

            # MeshCat's bridge calls app.listen(port): bind it to the loopback interface only
            app.listen = listen_on_loopback  # type: ignore[method-assign,assignment]
            return app

    zmqserver.DEFAULT_FILESERVER_PORT = args.port
    bridge = Bridge(zmq_url=args.zmq_url, host=HOST)
    print(f"zmq_url={bridge.zmq_url}", flush=True)
    print(f"web_url={bridge.web_url.replace('/static/', f'/{secret}/static/')}", flush=True)
    print(f"port={bridge.fileserver_port}", flush=True)
    sys.stdout = open(os.devnull, "w")    # nobody reads our stdout any more

    loop = tornado.ioloop.IOLoop.current()
    parent_gone = []
    if args.parent_pid:
        started_by_parent = first_ppid == args.parent_pid

        def check_parent():
            # The kernel is our parent: when it dies we are re-parented at once (to pid 1
            # or to a "child subreaper" such as systemd --user or tini -s), even while it
            # is still an unreaped zombie that os.kill(pid, 0) reports as alive.
            try:
                os.kill(args.parent_pid, 0)
                gone = started_by_parent and os.getppid() != args.parent_pid
            except OSError:
                gone = True
            if gone:
                parent_gone.append(True)
                loop.stop()
        tornado.ioloop.PeriodicCallback(check_parent, 1000).start()
    try:
        bridge.run()
    except KeyboardInterrupt:
        pass
    if parent_gone:
        remove_command_socket(args.zmq_url)


def remove_command_socket(zmq_url: str) -> None:
    """Remove the ``ipc://`` command socket and its folder (left if not empty); nothing for another URL."""
    if not zmq_url.startswith("ipc://"):
        return
    path = zmq_url[len("ipc://"):]
    for remove, target in ((os.unlink, path), (os.rmdir, os.path.dirname(path))):
        try:
            remove(target)
        except OSError:
            pass   # removed already, or the folder holds something else: left as it is


if __name__ == "__main__":
    main()
