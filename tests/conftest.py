"""Shared fixtures: the built book, a headless Chromium, and a process-leak guard.

The suite runs on two workers (pytest-xdist, ``--dist loadgroup``) unless ``-n`` says
otherwise; ``tests/support/parallel_plan.py`` sets that up, keeps what must share one process
together (the cells of a notebook under nbval, a module's expensive fixtures) and
starts the longest parts first.
"""

from __future__ import annotations

import fcntl
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from support import nbgrader_runner

ROOT = Path(__file__).resolve().parent.parent
BUILD_DIR = ROOT / "_build"
HTML_DIR = BUILD_DIR / "html"

#: Flags that make headless Chromium work on a machine without GPU or network.
#: WebGL runs on SwiftShader (the CPU); the page itself is composited in software:
#: compositing through SwiftShader as well doubles the CPU a page load costs and checks
#: nothing more (layout and the pixels of a drawn scene are the same). WebGL without
#: multisampling: 4x MSAA on the CPU costs about 6 % of a page check and only smooths
#: edges (the scene checks count drawn pixels, with thresholds far from an edge's width).
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--disable-gpu-compositing",
    "--webgl-antialiasing-mode=none",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-quic",
    "--no-first-run",
    "--allow-file-access-from-files",
]


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--other-machines-notebook", action="append", default=[], metavar="PATH",
        help="run tests/test_notebooks_other_machines.py on this notebook only (repeatable; "
             "default: every notebook) -- the check to run after editing one notebook")


def chromium_path() -> str | None:
    """Path of the system Chromium (Debian's ``chromium`` package), or None."""
    for name in ("chromium", "chromium-browser", "google-chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


def _skip_or_fail(message: str) -> None:
    # CI must never skip the browser check: there a missing browser is an error.
    if os.environ.get("CI"):
        pytest.fail(f"{message} (CI=true: the browser check must run)")
    pytest.skip(message)


#: Where each edition of the book is built (``make book EDITION=...``).
EDITION_HTML = {"instructor": HTML_DIR, "student": BUILD_DIR / "student" / "_build" / "html"}


def build_book(edition: str = "instructor") -> Path:
    """Build one edition of the book as ``make book EDITION=...`` does, every page read again.

    ``--all``: Sphinx reads only the pages that changed since the last build of a checkout,
    and a page that is not read prints none of its warnings: a page with a warning would pass
    from the second build on. Reading every page costs what a fresh clone's build costs
    (benchmarks/README.md, "The suite's start, end and book builds").

    Returns the HTML output directory. The build log (``book-build.log`` next to
    it) is attached to the failure message so that a broken notebook or a
    warning is easy to find.
    """
    command = [str(Path(sys.executable).with_name("jupyter-book")), "build", str(ROOT), "--all", "-W", "-n",
               "--keep-going"]
    if edition != "instructor":
        command += ["--path-output", str(EDITION_HTML[edition].parent.parent)]
    env = dict(os.environ, ROBOKIN_VIEWER="static", PYDEVD_DISABLE_FILE_VALIDATION="1", ROBOKIN_EDITION=edition)
    started = time.perf_counter()
    proc = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, timeout=1200)
    elapsed = time.perf_counter() - started
    log = proc.stdout + proc.stderr
    log_file = EDITION_HTML[edition].parent / "book-build.log"
    log_file.parent.mkdir(parents=True, exist_ok=True)
    log_file.write_text(log)
    if proc.returncode != 0 or "build succeeded" not in log:
        tail = "\n".join(log.splitlines()[-60:])
        pytest.fail(f"jupyter-book build ({edition} edition) failed (exit {proc.returncode}) after "
                    f"{elapsed:.0f} s:\n{tail}")
    print(f"\n[book] {edition} edition built in {elapsed:.1f} s")
    return EDITION_HTML[edition]


def build_book_once(edition: str, run_id: str) -> Path:
    """``build_book(edition)`` once per test run, whichever worker asks first.

    The workers of one run (pytest-xdist) share the built book: the first to ask
    builds it while holding a lock, the others wait for the lock and use its result
    (or fail with its failure). ``run_id`` names the run; a book built by an earlier
    run is built again.
    """
    BUILD_DIR.mkdir(parents=True, exist_ok=True)
    record = BUILD_DIR / f".book-{edition}.test-run"
    with open(BUILD_DIR / f".book-{edition}.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            recorded = record.read_text().split("\n", 2) if record.is_file() else []
            if recorded[:1] == [run_id]:
                if recorded[1:2] != ["built"]:
                    pytest.fail(f"jupyter-book build ({edition} edition) failed in another worker of this run:\n"
                                + (recorded[2] if len(recorded) > 2 else ""))
                return EDITION_HTML[edition]
            record.unlink(missing_ok=True)
            try:
                html = build_book(edition)
            except BaseException as failure:
                record.write_text(f"{run_id}\nfailed\n{failure}")
                raise
            record.write_text(f"{run_id}\nbuilt\n")
            return html
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


@pytest.fixture(scope="session")
def suite_run_id(pytestconfig) -> str:
    """One name for this test run, the same in every pytest-xdist worker (tests/support/parallel_plan.py)."""
    return pytestconfig.robokin_run_id


@pytest.fixture(scope="session")
def built_book(suite_run_id) -> Path:
    """The instructor edition (the default ``make book``), built once per test run."""
    return build_book_once("instructor", suite_run_id)


@pytest.fixture(scope="session")
def built_student_book(suite_run_id) -> Path:
    """The student edition (``make book EDITION=student``): no solutions in the HTML."""
    return build_book_once("student", suite_run_id)


@pytest.fixture(scope="session")
def browser():
    """A headless Chromium driven by Playwright, closed at the end of the session."""
    executable = chromium_path()
    if executable is None:
        _skip_or_fail(
            "Chromium not found: install it to run the browser checks, e.g. "
            "`sudo apt-get install chromium` on Debian/Ubuntu"
        )
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:  # pragma: no cover - requirements not installed
        _skip_or_fail("playwright is not installed: run `make test`, which installs requirements.txt")
    with sync_playwright() as playwright:
        instance = playwright.chromium.launch(executable_path=executable, headless=True, args=CHROMIUM_ARGS)
        _BROWSERS.append(instance)
        try:
            yield instance
        finally:
            _BROWSERS.remove(instance)
            instance.close()


#: The Chromium instances the ``browser`` fixture launched in this process (one per worker).
_BROWSERS: list = []
#: Browser contexts that live for the whole session (the book's page checks reuse one tab,
#: tests/test_book.py); their owner leaves them on about:blank after each test.
KEPT_CONTEXTS: list = []


@pytest.fixture(autouse=True)
def _close_browser_pages():
    """Close every tab a test opened in the session's Chromium when the test ends
    (except the contexts in ``KEPT_CONTEXTS``).

    A tab left open with a live WebGL scene keeps Chromium's GPU process drawing
    (about 40 % of a core) for the rest of the run.
    """
    yield
    for instance in _BROWSERS:
        for context in list(instance.contexts):
            if context not in KEPT_CONTEXTS:
                context.close()


def _stop_survivors() -> list[str]:
    """The processes this one started that still run 10 s later, killed; their descriptions."""
    try:
        import psutil
    except ImportError:  # pragma: no cover
        return []
    me = psutil.Process()
    deadline = time.monotonic() + 10.0
    children = me.children(recursive=True)
    while children and time.monotonic() < deadline:
        time.sleep(0.25)
        children = [c for c in me.children(recursive=True) if c.is_running() and c.status() != psutil.STATUS_ZOMBIE]
    names = [f"{c.pid}:{' '.join(c.cmdline()[:3])}" for c in children]
    for child in children:
        child.kill()
    return names


def pytest_sessionfinish(session, exitstatus):
    """Fail the run if a kernel, server or browser started by the tests survived them.

    Under pytest-xdist each worker looks at the processes it started and hands the
    survivors to the controller (tests/support/parallel_plan.py), which reports them here.
    """
    config = session.config
    nbgrader_runner.close_all()   # the warm nbgrader processes of this one (tests/support/nbgrader_runner.py)
    if hasattr(config, "workerinput"):
        config.workeroutput["robokin_survivors"] = _stop_survivors()
        return
    if config.pluginmanager.hasplugin("dsession"):   # the controller: its children are the workers
        survivors = list(getattr(config, "robokin_worker_survivors", []))
    else:
        survivors = _stop_survivors()
    if survivors:
        session.config.pluginmanager.get_plugin("terminalreporter").write_line(
            f"ERROR: processes started by the tests are still running: {', '.join(survivors)}", red=True
        )
        session.exitstatus = 1


#: the CPU-seconds of each test with ROBOKIN_CPU_REPORT=FILE (tests/support/cpu_accounting.py)
pytest_plugins = ("support.cpu_accounting", "support.chapter_keywords")

from support.parallel_plan import (  # noqa: E402,F401 - pytest hooks and a fixture of the parallel run
    pytest_cmdline_main,
    pytest_collection,
    pytest_collection_modifyitems,
    pytest_configure,
    pytest_configure_node,
    pytest_testnodedown,
)

# Hypothesis profiles. The default one (100 examples per property) is the CI budget;
# `pytest --hypothesis-profile=long` runs ten times as many, with fresh random examples
# (used for the robustness suite, tests/test_robustness_fuzz.py, before a release).
from hypothesis import settings as _hypothesis_settings  # noqa: E402

_hypothesis_settings.register_profile("long", max_examples=1000, deadline=None)


def watched_page(browser, width: int = 800, height: int = 900):
    """A new tab of the session's Chromium and the list its console errors and page errors go to."""
    errors: list[str] = []
    tab = browser.new_page(viewport={"width": width, "height": height})
    tab.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    tab.on("pageerror", lambda e: errors.append(str(e)))
    return tab, errors
