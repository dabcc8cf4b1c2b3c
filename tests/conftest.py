"""Shared fixtures: the built book, a headless Chromium, and a process-leak guard."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BUILD_DIR = ROOT / "_build"
HTML_DIR = BUILD_DIR / "html"

#: Flags that make headless Chromium work on a machine without GPU or network.
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-quic",
    "--no-first-run",
    "--allow-file-access-from-files",
]


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
    """Build one edition of the book exactly as ``make book EDITION=...`` does.

    Returns the HTML output directory. The build log (``book-build.log`` next to
    it) is attached to the failure message so that a broken notebook or a
    warning is easy to find.
    """
    command = [str(Path(sys.executable).with_name("jupyter-book")), "build", str(ROOT), "-W", "-n", "--keep-going"]
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


@pytest.fixture(scope="session")
def built_book() -> Path:
    """The instructor edition (the default ``make book``), built once per test session."""
    return build_book("instructor")


@pytest.fixture(scope="session")
def built_student_book() -> Path:
    """The student edition (``make book EDITION=student``): no solutions in the HTML."""
    return build_book("student")


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
        try:
            yield instance
        finally:
            instance.close()


def pytest_sessionfinish(session, exitstatus):
    """Fail the run if a kernel, server or browser started by the tests survived them."""
    try:
        import psutil
    except ImportError:  # pragma: no cover
        return
    me = psutil.Process()
    deadline = time.monotonic() + 10.0
    children = me.children(recursive=True)
    while children and time.monotonic() < deadline:
        time.sleep(0.25)
        children = [c for c in me.children(recursive=True) if c.is_running() and c.status() != psutil.STATUS_ZOMBIE]
    if children:
        names = ", ".join(f"{c.pid}:{' '.join(c.cmdline()[:3])}" for c in children)
        session.config.pluginmanager.get_plugin("terminalreporter").write_line(
            f"ERROR: processes started by the tests are still running: {names}", red=True
        )
        for child in children:
            child.kill()
        session.exitstatus = 1


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
