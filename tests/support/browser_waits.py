"""Waiting for a page in headless Chromium by a condition, not by a fixed sleep.

A fixed sleep is either too short on a loaded machine (a flaky test) or too long
everywhere else (a slow suite). These helpers poll until what the test is about to
assert holds, and return at once when it does; on timeout they return what they
saw last, so that the test's own assertion fails with its own message.
"""

from __future__ import annotations

import io
import time
from collections.abc import Callable
from typing import TypeVar

import numpy as np

T = TypeVar("T")

#: Seconds a page may take to load, typeset or draw before the test looks at it for the last
#: time: the ceiling of every wait in the browser tests. A whole page check (load, typeset, every
#: scene drawn, two widths) takes a few seconds on the quiet 2-core machine, so a single wait
#: reaching 20 s means something never happened; a wait ends as soon as its condition holds.
DRAW_TIMEOUT = 20.0
#: The same ceiling in milliseconds, as Playwright takes it.
WAIT_MS = int(DRAW_TIMEOUT * 1000)
#: Seconds between two looks (a screenshot of a canvas takes about 50 ms).
POLL = 0.1


def pixels(png: bytes) -> np.ndarray:
    """RGB pixels of a PNG screenshot, as integers, shape (height, width, 3)."""
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=int)


def poll_until(look: Callable[[], T], done: Callable[[T], bool], timeout: float = DRAW_TIMEOUT) -> T:
    """Call ``look()`` until ``done(result)`` holds or ``timeout`` seconds passed; the last result."""
    deadline = time.monotonic() + timeout
    while True:
        seen = look()
        if done(seen) or time.monotonic() >= deadline:
            return seen
        time.sleep(POLL)


def next_frames(tab, count: int = 2) -> None:
    """Wait until the page has rendered ``count`` more animation frames (layout and paint
    after a change of the viewport are done)."""
    tab.evaluate("""(count) => new Promise(resolve => {
        const step = left => left ? requestAnimationFrame(() => step(left - 1)) : resolve();
        step(count);
    })""", count)


def wait_drawn(tab, timeout: float = DRAW_TIMEOUT) -> None:
    """Wait until every static scene on the page (``robokin.views.static_html``) has its
    MeshCat viewer, fed with all its commands, and that viewer has drawn them.

    A condition in the page instead of screenshots taken again and again; the test's
    screenshot assertions follow (on timeout they report what is missing)."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    try:
        tab.wait_for_function("""() => Array.from(document.querySelectorAll('.robokin-scene'))
            .every(box => box.robokinViewer && !box.robokinViewer.needs_render)""", timeout=timeout * 1000)
    except PlaywrightTimeout:
        pass
