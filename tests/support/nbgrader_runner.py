"""nbgrader's command lines, each in a fresh process forked from one that imported nbgrader.

The grading suites run about 40 ``nbgrader`` commands per ``make test``; each new
``nbgrader`` process spends about 1.1 s of CPU importing nbgrader (traitlets,
nbconvert, nbclient, sqlalchemy, ... 1,300 modules) before it does anything. A
*runner* imports the module of nbgrader's command-line application
(``nbgrader.apps.nbgraderapp``, whose ``main`` the ``nbgrader`` console script calls)
once and forks a child for each command: the child takes the command's working
folder, environment and arguments, calls ``main()`` as the console script does and
exits with its exit code. Nothing but imported modules is shared: no application,
configuration, database session or kernel exists before the fork (the runner has
one thread and does nothing else), so each command starts as a new ``nbgrader``
process would, and its output goes to a file of its own.

The runner also applies the suite's *shortcuts* (:func:`apply_shortcuts`) before it
forks: work the suite repeats -- a new gradebook per course, nbgrader's metadata
check of every cell, the same cells highlighted on every feedback page -- done once
per process. Grades and pages are nbgrader's and nbconvert's own; only their CPU time
changes. They live here, not in the grading tools, because only the suite repeats
that work often enough to pay for code that reaches into nbgrader and nbconvert.

:func:`run` is a drop-in for ``subprocess.run([nbgrader, *args], cwd=..., env=...,
capture_output=True, text=True, timeout=...)``. There is one runner per calling thread
(a runner serves one command at a time) and per set of ``PYTHON*`` variables (read
when an interpreter starts: ``sys.path``, hash seed, ...); :func:`close_all` stops
them (``tests/conftest.py`` does, before it looks for processes the tests left
running). A runner ends by itself when the process that started it ends (its
input closes).
"""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import sys
import tempfile
import threading
import time
import traceback
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from nbconvert.filters.highlight import Highlight2HTML


#: The longest a runner may take to start a command or report a killed one's exit (its own
#: start-up, importing nbgrader, included: 1.1 s of CPU, about 5 s at a load of 10 on two
#: cores): a ceiling no load reaches by accident, not a time limit of the command's.
START_CEILING = 300.0


class Runner:
    """One warm process that forks a child per nbgrader command (see the module's docstring)."""

    def __init__(self, env: dict[str, str]) -> None:
        self.process = subprocess.Popen([sys.executable, __file__, "--serve"], stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, env=env, bufsize=0)
        assert self.process.stdin is not None and self.process.stdout is not None  # both piped above
        self._stdin, self._stdout = self.process.stdin, self.process.stdout
        self._unread = b""   # what the runner wrote and no reply has taken yet

    def run(self, args: list[str], cwd: Path, env: dict[str, str], timeout: float) -> subprocess.CompletedProcess:
        command = ["nbgrader", *args]
        with tempfile.TemporaryDirectory(prefix="robokin-nbgrader-") as folder:
            output = Path(folder) / "output.txt"
            request = {"args": args, "cwd": str(cwd), "env": env, "output": str(output)}
            self._stdin.write(json.dumps(request).encode() + b"\n")
            # the time limit is the command's, from its start: a runner still importing
            # nbgrader on a busy machine takes none of it (a limit counted from the request
            # ran out before the command existed, and its output file did not exist)
            started = self._reply(time.monotonic() + START_CEILING)
            if started is None:
                self._abandon()
                raise RuntimeError(f"the nbgrader runner (pid {self.process.pid}) did not start "
                                   f"`{' '.join(command)}` within {START_CEILING:.0f} s")
            ended = self._reply(time.monotonic() + timeout)
            if ended is None:
                os.kill(started["pid"], signal.SIGKILL)
                if self._reply(time.monotonic() + START_CEILING) is None:   # the killed child's exit
                    self._abandon()
                raise subprocess.TimeoutExpired(command, timeout, output.read_text(errors="replace")
                                                if output.exists() else "")
            text = output.read_text(encoding="utf-8", errors="replace")
        return subprocess.CompletedProcess(command, ended["exit"], text, "")

    def _reply(self, deadline: float) -> dict | None:
        """The runner's next line (None at ``deadline``); RuntimeError if the runner died.

        Read from the pipe's file descriptor, not a buffered file: a buffered readline can
        take both of a command's lines at once, and ``select`` would then wait for the
        second one, already read, until the deadline.
        """
        fd = self._stdout.fileno()
        while b"\n" not in self._unread:
            ready, _, _ = select.select([fd], [], [], max(0.0, deadline - time.monotonic()))
            if not ready:
                return None
            chunk = os.read(fd, 65536)
            if not chunk:
                raise RuntimeError(f"the nbgrader runner (pid {self.process.pid}) ended "
                                   f"(exit {self.process.wait()}) in the middle of a command")
            self._unread += chunk
        line, _, self._unread = self._unread.partition(b"\n")
        return json.loads(line)

    def _abandon(self) -> None:
        """Kill a runner that did not answer: a reply it owes would be read as the next command's."""
        self.process.kill()
        self.process.wait()

    def close(self) -> None:
        self._stdin.close()
        self.process.wait(timeout=30)
        self._stdout.close()


_RUNNERS: dict[tuple, Runner] = {}
_LOCK = threading.Lock()


def _interpreter_settings(env: dict[str, str]) -> tuple:
    return tuple(sorted((k, v) for k, v in env.items() if k.startswith("PYTHON")))


def run(args: list[str], cwd: Path, env: dict[str, str], timeout: float) -> subprocess.CompletedProcess:
    """``nbgrader <args>`` in ``cwd`` with the environment ``env`` (all of it): its exit code
    and its output (stdout and stderr, in order, as ``stdout``). Raises
    ``subprocess.TimeoutExpired`` when the command runs ``timeout`` seconds (counted from its
    start, the runner's own start-up not included), the command killed; ``RuntimeError`` when
    the runner does not start it within :data:`START_CEILING` seconds."""
    key = (threading.get_ident(), _interpreter_settings(env))
    with _LOCK:
        runner = _RUNNERS.get(key)
        if runner is None or runner.process.poll() is not None:
            runner = _RUNNERS[key] = Runner(env)
    return runner.run(args, cwd, env, timeout)


def runner_pids() -> list[int]:
    """The process ids of this process's runners."""
    with _LOCK:
        return [runner.process.pid for runner in _RUNNERS.values()]


def close_all() -> None:
    """Stop every runner of this process."""
    with _LOCK:
        runners = list(_RUNNERS.values())
        _RUNNERS.clear()
    for runner in runners:
        runner.close()


# ------------------------------------------------------------------ the suite's shortcuts
#: nbgrader's and nbconvert's functions that :func:`apply_shortcuts` replaces, as they were.
_ORIGINAL: dict[str, Any] = {}


def alembic_head() -> str:
    """The revision of nbgrader's gradebook schema that a new gradebook records, read from
    nbgrader's migration scripts in this process (0.08 s of CPU) instead of by ``alembic heads``
    run as a program, as nbgrader's ``get_alembic_version`` does (0.9 s); with other than one head,
    nbgrader's own function answers."""
    from alembic.config import Config
    from alembic.script import ScriptDirectory
    from nbgrader.dbutil import ALEMBIC_DIR

    config = Config()
    config.set_main_option("script_location", ALEMBIC_DIR)
    heads = ScriptDirectory.from_config(config).get_heads()
    return heads[0] if len(heads) == 1 else _ORIGINAL["get_alembic_version"]()


class SchemaCheckedOnce:
    """``jsonschema`` as nbgrader's metadata validator uses it, with ``validate`` checking a
    schema against the JSON meta-schema once per process, not on every call (nine tenths of the
    time of nbgrader's ``CheckCellMetadata``, which validates each cell): the same verdict,
    ``jsonschema.validate``'s best-matching error. Every other name is ``jsonschema``'s."""

    def __init__(self) -> None:
        self._validators: dict[str, Any] = {}   # the schema's JSON -> its validator

    def __getattr__(self, name: str) -> Any:
        import jsonschema

        return getattr(jsonschema, name)

    def validate(self, instance: Any, schema: dict, cls: Any = None, *args: Any, **kwargs: Any) -> None:
        import jsonschema

        key = json.dumps(schema, sort_keys=True)
        validator = self._validators.get(key)
        if validator is None:
            cls = cls or jsonschema.validators.validator_for(schema)
            cls.check_schema(schema)
            validator = self._validators[key] = cls(schema, *args, **kwargs)
        error = jsonschema.exceptions.best_match(validator.iter_errors(instance))
        if error is not None:
            raise error


def memoised_highlight() -> type[Highlight2HTML]:
    """nbconvert's code highlighting (``Highlight2HTML``, pygments) memoised per process:
    ``generate_feedback`` renders the same given and test cells for every student."""
    from nbconvert.filters.highlight import Highlight2HTML

    class MemoisedHighlight(Highlight2HTML):
        _pages: dict[tuple, str] = {}

        def __call__(self, source, language=None, metadata=None):
            key = (source, language or self.pygments_lexer, (metadata or {}).get("magics_language"),
                   json.dumps(self.extra_formatter_options, sort_keys=True, default=repr))
            if key not in self._pages:
                self._pages[key] = super().__call__(source, language, metadata)
            return self._pages[key]

    return MemoisedHighlight


def memoised_markdown(markdown2html: Any) -> Any:
    """nbconvert's markdown filter (``HTMLExporter.markdown2html``) memoised per process; the
    key is all the filter reads: the text, the cell's attachments, the notebook's folder and the
    exporter's options."""
    from jinja2 import pass_context

    pages: dict[tuple, str] = {}

    @pass_context
    def memoised(self, context, source):
        key = (source, json.dumps(context.get("cell", {}).get("attachments", {}), sort_keys=True),
               context.get("resources", {}).get("metadata", {}).get("path", ""), self.embed_images,
               self.anchor_link_text, self.exclude_anchor_links,
               json.dumps(self.lexer_options, sort_keys=True, default=repr))
        if key not in pages:
            pages[key] = markdown2html(self, context, source)
        return pages[key]

    return memoised


def apply_shortcuts() -> None:
    """Make nbgrader cheaper where the suite repeats work, its results unchanged (the runner
    applies them once, before it forks any command; the pages and grades are nbgrader's):

    - a new gradebook's schema revision read in this process (:func:`alembic_head`): the suite
      makes a course per chapter;
    - nbgrader's metadata check with its schema checked once (:class:`SchemaCheckedOnce`):
      0.04 s of CPU per pass over a notebook instead of 0.004, two passes per submission;
    - nbconvert's code highlighting and markdown memoised (:func:`memoised_highlight`,
      :func:`memoised_markdown`): a feedback page about 0.1 s of CPU cheaper.
    """
    if _ORIGINAL:
        return
    import nbconvert.exporters.html as nbconvert_html
    from nbgrader import api as nbgrader_api
    from nbgrader.nbgraderformat import common as nbgrader_metadata

    _ORIGINAL.update(get_alembic_version=nbgrader_api.get_alembic_version, jsonschema=nbgrader_metadata.jsonschema,
                     Highlight2HTML=nbconvert_html.Highlight2HTML,
                     markdown2html=nbconvert_html.HTMLExporter.markdown2html)
    nbgrader_api.get_alembic_version = alembic_head
    nbgrader_metadata.jsonschema = SchemaCheckedOnce()
    # the class HTMLExporter.from_notebook_node makes its highlighting filter of, and its markdown filter
    nbconvert_html.Highlight2HTML = memoised_highlight()  # type: ignore[misc]  # a subclass, by design
    nbconvert_html.HTMLExporter.markdown2html = memoised_markdown(  # type: ignore[method-assign]  # memoised
        _ORIGINAL["markdown2html"])


# ------------------------------------------------------------------ the runner process
def _child(request: dict) -> int:
    """In the forked child (its output already in the command's file): become the command,
    run it, return its exit code."""
    os.chdir(request["cwd"])
    os.environ.clear()
    os.environ.update(request["env"])
    sys.argv = ["nbgrader", *request["args"]]
    from nbgrader.apps.nbgraderapp import main

    try:
        main()
        return 0
    except SystemExit as exit_:
        code = exit_.code
        if code is None or isinstance(code, int):
            return code or 0
        print(code, file=sys.stderr)
        return 1


def _redirect(output: str) -> None:
    """Standard input from /dev/null, standard output and error to the file ``output``."""
    devnull = os.open(os.devnull, os.O_RDONLY)
    out = os.open(output, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    for fd, target in ((0, devnull), (1, out), (2, out)):
        os.dup2(target, fd)
    os.close(devnull)
    os.close(out)


def _command(request: dict) -> None:
    """The forked child: run the command and exit with its exit code (never returns)."""
    try:
        _redirect(request["output"])
    except BaseException:  # noqa: BLE001 - output not redirected: print nothing on the runner's pipe
        os._exit(1)
    code = 1
    try:
        code = _child(request)
    except BaseException:  # noqa: BLE001 - the command's output tells
        traceback.print_exc()
    finally:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code if 0 <= code < 256 else 1)


def serve() -> None:
    """The runner: import nbgrader's application, then fork a child per request line."""
    # as the console script: the folder of the executable first on sys.path, not tests/
    sys.path[0] = str(Path(sys.executable).parent)
    import nbgrader.apps.nbgraderapp  # noqa: F401 - the import this process exists for

    apply_shortcuts()

    assert threading.active_count() == 1, "the nbgrader runner must not fork with threads running"
    for line in sys.stdin:
        request = json.loads(line)
        pid = os.fork()
        if pid == 0:
            _command(request)
        print(json.dumps({"pid": pid}), flush=True)
        _, status = os.waitpid(pid, 0)
        print(json.dumps({"exit": os.waitstatus_to_exitcode(status)}), flush=True)


if __name__ == "__main__":
    serve()
