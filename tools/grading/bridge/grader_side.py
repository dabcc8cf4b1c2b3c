"""The grader's kernel side of the bridge: answers imported as data, functions as proxies.

The grader's kernel (started by the autograder; no student code ever runs in it)
imports this module and :func:`connect` s to the student's kernel with a kernel
client of its own. :func:`import_names` asks the student's kernel for the names
an answer cell declares and binds them in the grader's namespace:

* plain data (see :mod:`tools.grading.bridge.codec`) is copied;
* a function becomes a :class:`Proxy`: calling it sends the (data) arguments to
  the student's kernel, runs the student's function there and returns the (data)
  result, within a time limit per call. Calls travel over a **call channel**: a
  Unix socket the grader listens on, in a folder the student's kernel can reach
  (inside the bubblewrap sandbox: the kernel's private runtime folder, bound into
  it), which one execute request in the student's kernel connects to
  (:func:`codec.serve`). A call is then one frame each way (a fraction of a
  millisecond) instead of one execute request (~9 ms). The session ends (the
  socket is closed) before the student's kernel runs anything else;
* anything else becomes a :class:`codec.Untransferable`, whose use fails with
  "answer `x` is not plain data (a <type>)".

Everything the student's kernel sends back is decoded by :func:`codec.decode`
(whitelist, caps). The test cells then run here, with the real numpy and robokin.
"""

from __future__ import annotations

import atexit
import json
import os
import queue
import secrets
import shutil
import socket
import tempfile
import time
from pathlib import Path

from jupyter_client import BlockingKernelClient
from jupyter_client.connect import KernelConnectionInfo

from . import codec

#: Characters of output accepted from the student's kernel for one request.
MAX_REPLY = 64_000_000
#: Seconds to wait at most for the student's kernel to open a call session (and at most
#: the time limit per call), and to end one: short, as the waits run in a grader cell,
#: whose own time limit may be as short as 10 s.
SESSION_TIMEOUT = 10.0
RELEASE_TIMEOUT = 3.0
#: Seconds more for a kernel whose session ended normally to go idle (:func:`status`); with
#: RELEASE_TIMEOUT, within the shortest time limit of a grader cell (10 s)
SETTLE_TIMEOUT = 5.0
#: how an answer that was not called begins (the student's kernel still ran a call stopped earlier)
NOT_CALLED = "not called"

_BOOT = """
import sys, types
_module = types.ModuleType("_robokin_bridge")
exec(compile(SOURCE, "<robokin grading bridge>", "exec"), _module.__dict__)
sys.modules["_robokin_bridge"] = _module
"""


class AnswerError(Exception):
    """The student's function raised, returned something that is not data, or took too long."""


class _Link:
    """A kernel client of the student's kernel, used only by the bridge."""

    def __init__(self, connection_info: KernelConnectionInfo, call_timeout: float) -> None:
        self.client = BlockingKernelClient()
        self.client.load_connection_info(connection_info)
        self.client.start_channels(shell=True, iopub=True, stdin=True, hb=False, control=False)
        self.client.wait_for_ready(timeout=60)
        self.call_timeout = call_timeout
        self.stuck = False        # a call timed out: the student's kernel may still be busy
        self.stopped: str | None = None   # the answer whose call was stopped at the time limit
        self.calls = 0
        self.callbacks: dict = {}  # the test's functions passed to the student's functions
        self.in_callback = False
        self.source = (Path(__file__).with_name("codec.py")).read_text(encoding="utf-8")
        self._listen(connection_info)
        self.session: socket.socket | None = None   # the call channel, while a session is open
        self.serve_id: str | None = None            # the execute request that serves it

    # ------------------------------------------------------------ the call channel
    def _listen(self, connection_info: KernelConnectionInfo) -> None:
        """A Unix socket for the call channel, in a folder the student's kernel reaches."""
        if connection_info.get("transport") == "ipc":
            # the sandboxed kernel's runtime folder (tools.grading.sandbox), bound into the sandbox
            folder, self._own_folder = os.path.dirname(str(connection_info["ip"])), None
        else:
            folder = self._own_folder = tempfile.mkdtemp(prefix="robokin-bridge-")
            atexit.register(shutil.rmtree, folder, True)
        self.token = secrets.token_hex(16)
        self.path = os.path.join(folder, f"bridge-{secrets.token_hex(6)}.sock")
        self.listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.listener.bind(self.path)
        os.chmod(self.path, 0o600)
        self.listener.listen(1)
        atexit.register(_remove, self.path)

    def _open(self) -> socket.socket:
        """The call channel: a session served by one execute request in the student's kernel."""
        if self.session is not None:
            return self.session
        for attempt in range(2):
            token = f"{self.token}-{secrets.token_hex(4)}"   # this request's: a late one is turned away
            code = f"__import__('sys').modules['_robokin_bridge'].serve({self.path!r}, {token!r})"
            self.serve_id = self.client.execute(code, silent=True, store_history=False, allow_stdin=False)
            session = self._accept(self.serve_id, token)
            if session is not None:
                self.session = session
                return session
            if attempt == 0:   # the bridge module is missing there (first use, restart, deleted)
                self._install()
        raise AnswerError("the student's kernel did not open the call channel (the bridge was tampered "
                          "with, or its kernel is busy)")

    def _accept(self, msg_id: str, token: str) -> socket.socket | None:
        """The student's kernel's connection, or None if its request ended without one."""
        deadline = time.monotonic() + min(self.call_timeout, SESSION_TIMEOUT)
        self.listener.settimeout(0.002)
        while time.monotonic() < deadline:
            try:
                session, _ = self.listener.accept()
            except TimeoutError:
                if self._idle(msg_id, 0):
                    return None
                continue
            except BaseException:
                self.stuck = True
                raise
            session.settimeout(SESSION_TIMEOUT)
            try:
                hello = codec.receive_frame(session)
            except (OSError, codec.BridgeError):
                hello = None
            if isinstance(hello, dict) and hello.get("hello") == token:
                try:
                    codec.send_frame(session, {"welcome": token})
                except OSError:
                    session.close()
                    continue
                return session
            session.close()   # a request the grader gave up on earlier: it ends
        self.stuck = True
        raise AnswerError("the student's kernel did not open the call channel in time (it is busy)")

    def _idle(self, msg_id: str, timeout: float) -> bool:
        """Whether the student's kernel finished request ``msg_id`` within ``timeout`` s.

        Read from the kernel's reply on the shell channel, which carries the replies to
        this client's own requests only. Not from the ``idle`` status on iopub: iopub
        carries every output of every cell of the student's kernel, which this client
        reads only while it waits for a request of its own; past about 2,000 unread
        messages (ZeroMQ's high-water marks of 1,000 at each end) new ones are dropped
        for this client, the ``idle`` of its request among them (a talkative notebook's
        cells print that much between two tests).
        """
        deadline = time.monotonic() + timeout
        while True:
            try:
                msg = self.client.get_shell_msg(timeout=max(0.0, min(deadline - time.monotonic(), 0.05)))
            except queue.Empty:
                if time.monotonic() >= deadline:
                    return False
                continue
            if msg.get("parent_header", {}).get("msg_id") == msg_id and msg["msg_type"] == "execute_reply":
                return True

    def _install(self) -> None:
        self._run(f"exec(compile({_BOOT!r}, '<robokin bridge boot>', 'exec'), "
                  f"{{'SOURCE': {self.source!r}}})", None, max(self.call_timeout, SESSION_TIMEOUT))

    def release(self) -> None:
        """End the call session, so that the student's kernel can run other requests."""
        session, self.session = self.session, None
        if session is None:
            return
        session.close()
        self.stuck = True   # until the student's kernel is seen idle (else the autograder interrupts it)
        if self.serve_id is not None and self._idle(self.serve_id, RELEASE_TIMEOUT):
            self.stuck, self.stopped = False, None

    def _busy(self) -> AnswerError:
        """The error of a request made before the student's kernel is free again.

        After a call stopped at the time limit, the grader does not call the student's
        functions again until the autograder has interrupted that kernel (after the
        test cell or robokin.check's verdicts): the error says which call was stopped.
        """
        if self.stopped is not None:
            return AnswerError(f"{NOT_CALLED}: an earlier call of {self.stopped} took longer than "
                               f"{self.call_timeout:g} s and was stopped")
        return AnswerError(f"{NOT_CALLED}: the student's kernel had not finished an earlier request in time")

    def call(self, handle: int, arguments, answer: str):
        """Call the student's function ``handle`` with encoded arguments; its reply (a dict)."""
        if self.stuck:
            raise self._busy()
        if self.in_callback:
            raise AnswerError("a function of the test that the student's function calls cannot call the "
                              "student's functions in turn")
        session = self._open()
        deadline = time.monotonic() + self.call_timeout
        try:
            codec.send_frame(session, {"call": handle, "args": arguments})
        except codec.BridgeError as exc:   # nothing was sent: the session goes on
            raise AnswerError(f"the test's arguments for {answer} cannot be sent: {exc}") from None
        except OSError as exc:
            self.release()
            raise AnswerError(f"{answer}: the call channel broke ({type(exc).__name__})") from None
        try:
            while True:
                message = self._next_message(session, deadline, f"{answer}: the student's kernel closed the "
                                             "call channel (its kernel died, or the bridge was tampered with)")
                if "callback" not in message:
                    _show_output(message)
                    return message
                codec.send_frame(session, self._callback(message.get("callback"), message.get("args")))
        except BaseException as error:
            if isinstance(error, TimeoutError):
                self.stopped = answer
            failure = self._failure(error, f"{answer}: ",
                                    f"the call took longer than {self.call_timeout:g} s and was stopped")
            if failure is error:
                raise
            raise failure from None

    def _failure(self, error: BaseException, prefix: str, too_long: str) -> BaseException:
        """What ``error``, raised while waiting for the student's kernel, is raised as.

        A time-out becomes ``AnswerError(too_long)``, a malformed reply or a broken channel an
        ``AnswerError`` whose message starts with ``prefix``; an ``AnswerError`` and any other
        error (the test cell stopped at its time limit mid-call) stay as they are. A broken
        channel releases the session; every error but an ``AnswerError`` leaves the link stuck
        (no call until the autograder has interrupted the student's kernel).
        """
        if isinstance(error, TimeoutError):
            self.stuck = True
            return AnswerError(too_long)
        if isinstance(error, codec.BridgeError):
            self.stuck = True
            return AnswerError(f"{prefix}the student's kernel sent a malformed reply ({error})")
        if isinstance(error, OSError):
            self.release()
            return AnswerError(f"{prefix}the call channel broke ({type(error).__name__})")
        if not isinstance(error, AnswerError):
            self.stuck = True
        return error

    def _next_message(self, session, deadline: float, closed: str) -> dict:
        """The next message of the session, waiting until ``deadline`` at most.

        Raises ``TimeoutError`` past the deadline; ``AnswerError(closed)`` (the session
        released) when the student's side closed the channel or sent no dict.
        """
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            raise TimeoutError
        session.settimeout(remaining)
        message = codec.receive_frame(session)
        if not isinstance(message, dict):
            self.release()
            raise AnswerError(closed)
        return message

    def export(self, names: list[str]) -> dict:
        """The student's kernel's encoded answers ``names`` (``{name: entry}``), over the channel."""
        if self.stuck:
            raise self._busy()
        session = self._open()
        deadline = time.monotonic() + max(self.call_timeout, 60.0)
        out: dict = {}
        try:
            codec.send_frame(session, {"export": list(names)})
            while True:
                message = self._next_message(session, deadline, "the student's kernel closed the call channel")
                if message.get("done"):
                    return out
                if message.get("name") in names and isinstance(message.get("entry"), dict):
                    out[message["name"]] = message["entry"]
        except BaseException as error:
            failure = self._failure(error, "", "the student's kernel took too long to hand over the answers")
            if failure is error:
                raise
            raise failure from None

    def unstick(self) -> None:
        """After the autograder interrupted the student's kernel: end the session, forget the call."""
        session, self.session = self.session, None
        if session is not None:
            session.close()
            if self.serve_id is not None:   # set when the session was opened
                self._idle(self.serve_id, RELEASE_TIMEOUT)
        self.stuck, self.stopped = False, None

    # ------------------------------------------------------------ execute requests
    def request(self, code: str, nonce: str, timeout: float) -> dict:
        """Run ``code`` in the student's kernel; its reply (the last line marked ``nonce``).

        One execute request per reply, read from the kernel's stdout: how the bridge
        called the student's functions before the call channel (milliseconds per call);
        kept for ``tools/grading/bridge/benchmark.py``'s comparison.
        """
        if self.stuck:
            raise self._busy()
        if self.in_callback:
            raise AnswerError("a function of the test that the student's function calls cannot call the "
                              "student's functions in turn")
        self.release()
        if self.stuck:
            raise self._busy()
        reply = self._run(code, nonce, timeout)
        if reply is None:   # the bridge module is missing there (first use, or deleted): install it
            self._install()
            reply = self._run(code, nonce, timeout)
        if reply is None:
            raise AnswerError("the student's kernel did not answer the grader (its output was redirected "
                              "or the bridge was tampered with)")
        return reply

    def _run(self, code: str, nonce: str | None, timeout: float) -> dict | None:
        """Run ``code`` in the student's kernel; with a ``nonce``, its reply read from stdout."""
        client = self.client
        self._drain_iopub()   # the student's cells' outputs since the last request (see _idle)
        msg_id = client.execute(code, silent=True, store_history=False, allow_stdin=False)
        if nonce is None:   # installing the bridge: only its end matters
            try:
                ended = self._idle(msg_id, timeout)
            except BaseException:   # the test cell itself was stopped (time limit) meanwhile
                self.stuck = True
                raise
            if not ended:
                self.stuck = True
                raise AnswerError(f"the call took longer than {timeout:g} s and was stopped")
            return None
        deadline = time.monotonic() + timeout
        chunks: list[str] = []
        size = 0
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                self.stuck = True
                raise AnswerError(f"the call took longer than {timeout:g} s and was stopped")
            try:
                msg = client.get_iopub_msg(timeout=min(remaining, 0.02))
            except queue.Empty:
                continue
            except BaseException:   # the test cell itself was stopped (time limit) mid-call
                self.stuck = True
                raise
            if msg.get("parent_header", {}).get("msg_id") != msg_id:
                continue
            kind, content = msg["msg_type"], msg["content"]
            if kind == "stream" and content.get("name") == "stdout":
                text = str(content.get("text", ""))
                size += len(text)
                if size > MAX_REPLY:
                    self.stuck = True
                    raise AnswerError("the student's kernel sent more output than the grader accepts")
                chunks.append(text)
            elif kind == "status" and content.get("execution_state") == "idle":
                break
        self._drain_shell()
        prefix = f"{codec.MARK}{nonce} "
        found = None
        for line in "".join(chunks).split("\n"):
            if line.startswith(prefix):
                found = line[len(prefix):]
        if found is None:
            return None
        try:
            data = json.loads(found)
        except ValueError as exc:
            raise AnswerError("the student's kernel sent a malformed reply") from exc
        if not isinstance(data, dict):
            raise AnswerError("the student's kernel sent a malformed reply")
        return data

    def _callback(self, handle, arguments) -> dict:
        """The student's function calls a function of the test: run it here; the reply."""
        try:
            function = self.callbacks[handle]
            args, kwargs = codec.decode(arguments, _make_proxy("an argument"))
        except Exception as exc:  # noqa: BLE001 - a malformed request from the student's kernel
            return {"error": f"malformed call ({type(exc).__name__})"}
        self.in_callback = True
        try:
            result = function(*args, **kwargs)
        except Exception as exc:  # noqa: BLE001 - reported to the student's function as an error
            return {"error": f"{type(exc).__name__}: {str(exc)[:300]}"}
        finally:
            self.in_callback = False
        try:
            return {"value": codec.encode(result, self.callbacks)}
        except codec.BridgeError as exc:
            return {"error": f"the result cannot be sent: {exc}"}

    def _drain_iopub(self) -> None:
        _drain(self.client.get_iopub_msg, 0)

    def _drain_shell(self) -> None:
        _drain(self.client.get_shell_msg, 0.001)


def _drain(get_message, timeout: float) -> None:
    """Read and drop a channel's messages until none comes within ``timeout`` s."""
    while True:
        try:
            get_message(timeout=timeout)
        except queue.Empty:
            return


_LINK: _Link | None = None


def connect(connection_info: KernelConnectionInfo, call_timeout: float = 30.0) -> None:
    """Open the link to the student's kernel (called once by the autograder)."""
    global _LINK
    _LINK = _Link(connection_info, call_timeout)


def disconnect() -> None:
    """Close the link (end the session, stop listening, stop the kernel client's channels)."""
    global _LINK
    link, _LINK = _LINK, None
    if link is None:
        return
    link.release()
    link.listener.close()
    _remove(link.path)
    link.client.stop_channels()


def unstick() -> None:
    """The autograder interrupted the student's kernel after a call timed out."""
    if _LINK is not None:
        _LINK.unstick()


def status(release: bool = True) -> dict:
    """``{"stuck", "calls"}``; first ends the call session (the student's kernel runs on).

    ``stuck`` tells the autograder to interrupt the student's kernel: after a call stopped
    at the time limit, or when that kernel is still busy. A session that ended normally
    may take a while to end there (a student's function that printed thousands of lines):
    the kernel is then given :data:`SETTLE_TIMEOUT` s more to go idle, as an interrupt
    sent to a kernel about to go idle would stop the next cell it runs.
    """
    link = _LINK
    if link is not None and release:
        link.release()
        if link.stuck and link.stopped is None and link.serve_id is not None \
                and link._idle(link.serve_id, SETTLE_TIMEOUT):
            link.stuck = False
    return {"stuck": bool(link and link.stuck), "calls": link.calls if link else 0}


def _show_output(reply: dict) -> None:
    """What the student's function printed during the call, shown here (under the test)."""
    import sys

    for name in ("stdout", "stderr"):
        text = reply.get(name)
        if isinstance(text, str) and text:
            stream = getattr(sys, name)
            stream.write(text[: codec.MAX_OUTPUT])
            stream.flush()


def _remove(path: str) -> None:
    try:
        os.remove(path)
    except OSError:
        pass


class Proxy:
    """A student's function, called in the student's kernel with data arguments."""

    def __init__(self, handle: int, name: str, answer: str) -> None:
        self._handle, self._name, self._answer = handle, name, answer
        self.__name__ = answer
        self.__qualname__ = answer
        self.__doc__ = f"the student's `{answer}`, run in the student's kernel"

    @property
    def __robokin_handle__(self) -> int:
        """Passed to another of the student's functions, a proxy is handed back as the original."""
        return self._handle

    def __repr__(self) -> str:
        return f"<the student's function {self._answer}>"

    def __call__(self, *args, **kwargs):
        link = _LINK
        if link is None:
            raise AnswerError("the grader is not connected to the student's kernel")
        try:
            arguments = codec.encode([list(args), dict(kwargs)], link.callbacks)
        except codec.BridgeError as exc:
            raise AnswerError(f"the test's arguments for {self._answer} cannot be sent: {exc}") from None
        link.calls += 1
        reply = link.call(self._handle, arguments, self._answer)
        if "value" in reply:
            try:
                return codec.decode(reply["value"], _make_proxy(self._answer))
            except codec.BridgeError as exc:
                raise AnswerError(f"{self._answer} returned something the grader does not accept: "
                                  f"{exc}") from None
        if "raised" in reply:
            raise AnswerError(f"{self._answer} raised {str(reply['raised'])[:100]}: "
                              f"{str(reply.get('message', ''))[:500]}")
        if "not_data" in reply:
            raise AnswerError(f"{self._answer} returned something that is not plain data "
                              f"(a {str(reply.get('type', '?'))[:200]})")
        raise AnswerError(f"{self._answer} could not be called: {str(reply.get('bridge_error', reply))[:300]}")


def _make_proxy(answer: str):
    def make(handle: int, name: str) -> Proxy:
        return Proxy(handle, name, f"{answer} (a function it returned)" if name else answer)
    return make


def import_names(namespace: dict, names: list[str], marker: str, extra: tuple = ()) -> None:
    """Bind the student's ``names`` in ``namespace``; print what happened as one JSON line.

    ``extra`` names (read by a test, declared by no answer: a side effect of the student's
    code) are bound only when the grader has no such name, and only when they can be
    handed over (data, or a function as a proxy).
    """
    summary: dict[str, str] = {}
    extras = [n for n in extra if n not in namespace and n not in names]
    names = list(names) + extras
    link = _LINK
    if link is None:
        raise AnswerError("the grader is not connected to the student's kernel")
    try:
        reply = link.export(names)
    except AnswerError as exc:
        reply = {}
        summary["*"] = f"error: {exc}"
    for name in names:
        entry = reply.get(name)
        if name in extras and not (isinstance(entry, dict) and "value" in entry):
            continue
        namespace.pop(name, None)
        if not isinstance(entry, dict) or entry.get("missing"):
            summary.setdefault(name, "missing")
            continue
        if "value" in entry:
            try:
                value = codec.decode(entry["value"], lambda handle, _n, a=name: Proxy(handle, _n, a))
            except codec.BridgeError as exc:
                namespace[name] = codec.Untransferable(f"value the grader does not accept: {exc}", name)
                summary[name] = f"refused: {exc}"
                continue
            if isinstance(value, codec.Untransferable):
                object.__setattr__(value, "_name", name)
                summary[name] = f"not plain data: {value._what}"
            elif isinstance(value, Proxy):
                module = str(getattr(value, "__robokin_module__", ""))
                robokin = module == "robokin" or module.startswith("robokin.")
                summary[name] = f"function of {module}.{value._name}" if robokin else "function"
            else:
                summary[name] = "data"
            namespace[name] = value
        else:
            what = str(entry.get("type", "?"))[:200]
            namespace[name] = codec.Untransferable(what, name)
            summary[name] = f"not plain data: {what} ({str(entry.get('error', ''))[:200]})"
    print(marker + json.dumps(summary))
