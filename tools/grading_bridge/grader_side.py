"""The grader's kernel side of the bridge: answers imported as data, functions as proxies.

The grader's kernel (started by the autograder; no student code ever runs in it)
imports this module and :func:`connect` s to the student's kernel with a kernel
client of its own. :func:`import_names` asks the student's kernel for the names
an answer cell declares and binds them in the grader's namespace:

* plain data (see :mod:`grading_bridge.codec`) is copied;
* a function becomes a :class:`Proxy`: calling it sends the (data) arguments to
  the student's kernel, runs the student's function there and returns the (data)
  result, within a time limit per call;
* anything else becomes a :class:`codec.Untransferable`, whose use fails with
  "answer `x` is not plain data (a <type>)".

Everything the student's kernel sends back is decoded by :func:`codec.decode`
(whitelist, caps). The test cells then run here, with the real numpy and robokin.
"""

from __future__ import annotations

import json
import queue
import time
import uuid
from pathlib import Path

from jupyter_client import BlockingKernelClient

from . import codec

#: Characters of output accepted from the student's kernel for one request.
MAX_REPLY = 64_000_000

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

    def __init__(self, connection_info: dict, call_timeout: float) -> None:
        self.client = BlockingKernelClient()
        self.client.load_connection_info(connection_info)
        self.client.start_channels(shell=True, iopub=True, stdin=True, hb=False, control=False)
        self.client.wait_for_ready(timeout=60)
        self.call_timeout = call_timeout
        self.stuck = False        # a call timed out: the student's kernel may still be busy
        self.calls = 0
        self.callbacks: dict = {}  # the test's functions passed to the student's functions
        self.in_callback = False
        self.source = (Path(__file__).with_name("codec.py")).read_text(encoding="utf-8")

    def request(self, code: str, nonce: str, timeout: float) -> dict:
        """Run ``code`` in the student's kernel; its reply (the last line marked ``nonce``)."""
        if self.stuck:
            raise AnswerError("the student's kernel is still busy with an earlier call that took too long")
        if self.in_callback:
            raise AnswerError("a function of the test that the student's function calls cannot call the "
                              "student's functions in turn")
        reply = self._run(code, nonce, timeout)
        if reply is None:   # the bridge module is missing there (first use, or deleted): install it
            self._run(f"exec(compile({_BOOT!r}, '<robokin bridge boot>', 'exec'), "
                      f"{{'SOURCE': {self.source!r}}})", None, timeout)
            reply = self._run(code, nonce, timeout)
        if reply is None:
            raise AnswerError("the student's kernel did not answer the grader (its output was redirected "
                              "or the bridge was tampered with)")
        return reply

    def _run(self, code: str, nonce: str | None, timeout: float) -> dict | None:
        client = self.client
        msg_id = client.execute(code, silent=True, store_history=False, allow_stdin=True)
        deadline = time.monotonic() + timeout
        chunks: list[str] = []
        size = 0
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                self.stuck = True
                raise AnswerError(f"the call took longer than {timeout:g} s and was stopped")
            try:
                self._answer_input_requests(msg_id)
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
        if nonce is None:
            return None
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

    def _answer_input_requests(self, msg_id: str) -> None:
        """The student's function calls a function of the test: run it here, send back the result."""
        while True:
            try:
                msg = self.client.get_stdin_msg(timeout=0)
            except queue.Empty:
                return
            if msg.get("msg_type") != "input_request" or msg.get("parent_header", {}).get("msg_id") != msg_id:
                continue
            prompt = str(msg["content"].get("prompt", ""))
            prefix = f"{codec.MARK}callback "
            if not prompt.startswith(prefix) or len(prompt) > MAX_REPLY:
                self.client.input("")      # the student's own input(): no one types here
                continue
            self.client.input(json.dumps(self._callback(prompt[len(prefix):]), allow_nan=False))

    def _callback(self, text: str) -> dict:
        try:
            handle_text, _, payload = text.partition(" ")
            function = self.callbacks[int(handle_text)]
            args, kwargs = codec.decode(json.loads(payload), _make_proxy("an argument"))
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

    def _drain_shell(self) -> None:
        while True:
            try:
                self.client.get_shell_msg(timeout=0.001)
            except queue.Empty:
                return


_LINK: _Link | None = None


def connect(connection_info: dict, call_timeout: float = 30.0) -> None:
    """Open the link to the student's kernel (called once by the autograder)."""
    global _LINK
    _LINK = _Link(connection_info, call_timeout)


def unstick() -> None:
    """The autograder interrupted the student's kernel after a call timed out."""
    if _LINK is not None:
        _LINK.stuck = False


def status() -> dict:
    return {"stuck": bool(_LINK and _LINK.stuck), "calls": _LINK.calls if _LINK else 0}


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
            payload = json.dumps(codec.encode([list(args), dict(kwargs)], link.callbacks), allow_nan=False)
        except codec.BridgeError as exc:
            raise AnswerError(f"the test's arguments for {self._answer} cannot be sent: {exc}") from None
        nonce = uuid.uuid4().hex
        code = (f"__import__('sys').modules['_robokin_bridge'].call({self._handle}, "
                f"{payload!r}, {nonce!r})")
        link.calls += 1
        reply = link.request(code, nonce, link.call_timeout)
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
    code) are bound only when the grader has no such name, and only when they are data.
    """
    summary: dict[str, str] = {}
    extra = [n for n in extra if n not in namespace and n not in names]
    names = list(names) + extra
    link = _LINK
    if link is None:
        raise AnswerError("the grader is not connected to the student's kernel")
    nonce = uuid.uuid4().hex
    code = f"__import__('sys').modules['_robokin_bridge'].export({list(names)!r}, {nonce!r})"
    try:
        reply = link.request(code, nonce, max(link.call_timeout, 60.0))
    except AnswerError as exc:
        reply = {}
        summary["*"] = f"error: {exc}"
    for name in names:
        entry = reply.get(name)
        if name in extra and not (isinstance(entry, dict) and "value" in entry):
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
            else:
                summary[name] = "function" if isinstance(value, Proxy) else "data"
            namespace[name] = value
        else:
            what = str(entry.get("type", "?"))[:200]
            namespace[name] = codec.Untransferable(what, name)
            summary[name] = f"not plain data: {what} ({str(entry.get('error', ''))[:200]})"
    print(marker + json.dumps(summary))
