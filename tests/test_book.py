"""The book builds with warnings as errors, and every page works in a real browser.

The browser check opens each built page from disk (file://) in headless
Chromium: no JavaScript errors, maths typeset by MathJax, every image loaded,
every 3D scene drawn (its WebGL canvas is not blank) with animation controls
where the scene is animated, and the page weight budget of pages with a scene.
"""

from __future__ import annotations

import functools
import io
import re
from collections.abc import Callable
from pathlib import Path
from urllib.parse import unquote, urlparse

import pytest
import yaml

from support.browser_waits import DRAW_TIMEOUT, WAIT_MS, next_frames, poll_until
from conftest import EDITION_HTML, KEPT_CONTEXTS, ROOT

pytestmark = pytest.mark.book

#: Bytes a page may transfer on a cold cache with everything it loads (its HTML, images,
#: scene data, the MeshCat viewer, the theme, MathJax and its fonts; each file once),
#: after scrolling through all of its scenes. Measured as a web server sends them:
#: text files (HTML, JS, CSS, SVG) gzip-compressed, fonts and images as they are.
PAGE_WEIGHT_BUDGET = 2_000_000
#: A page's own HTML, uncompressed (scene data lives in _static/scenes/, the scenes' script in
#: _static/robokin-scene.js: about 6 kB a scene when each carried its copy), in either edition.
#: Mostly highlighted code (a span per token, about six times the source). The instructor edition
#: carries the solutions and the hidden tests too (about 145 kB more than the student's): its
#: largest pages, chapters 5 and 2, were 584 and 573 kB at 14868e7 (their student pages 447 and
#: 426 kB), after the long machinery of their graded tests moved into tested functions of
#: robokin.check. A chapter
#: that needs more moves code out of its tests, or its *Going further* cells, the same way.
PAGE_HTML_BUDGET = 600_000
#: Widths the pages are read at: a laptop, and a phone.
WIDTHS = (1280, 390)
#: The laptop's width, at which an 88-character code line must fit its block.
LAPTOP = WIDTHS[0]
SCREENSHOTS = ROOT / "_build" / "screenshots"
COMPRESSED = (".woff2", ".woff", ".png", ".jpg", ".jpeg", ".gif", ".webp")


#: Every typeset formula whose MathML holds an error or an undefined macro (red text).
MATH_ERRORS_JS = """() => Array.from(MathJax.startup.document.math)
  .map(m => MathJax.startup.toMML(m.root))
  .filter(t => t.includes('mathcolor="red"') || t.includes('<merror'))
  .map(t => t.replace(/\\s+/g, ' ').slice(0, 200))"""


def toc_pages() -> list[str]:
    """Every document listed in ``_toc.yml`` (root first), as paths without suffix."""
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text())
    pages = [toc["root"]]

    def walk(entries):
        for entry in entries or []:
            if "file" in entry:
                pages.append(entry["file"])
            walk(entry.get("sections"))
            walk(entry.get("chapters"))

    for part in toc.get("parts", []):
        walk(part.get("chapters"))
    walk(toc.get("chapters"))
    return pages


PAGES = toc_pages()


#: The editions of the book and the fixtures that build them (``make book EDITION=...``).
EDITIONS = {"instructor": "built_book", "student": "built_student_book"}


@pytest.fixture(params=list(EDITIONS))
def edition_book(request) -> Path:
    """The HTML folder of one edition of the book (built once per session)."""
    return request.getfixturevalue(EDITIONS[request.param])


#: Sphinx's count of the pages it reads: "updating environment: [new config] 28 added, 0 changed, 0 removed"
#: when it reads every page (tests/conftest.py, ``build_book``), "0 added, 3 changed" when it reads again
#: only the pages changed since the last build of the checkout (the others print none of their warnings).
READ_PAGES = re.compile(r"updating environment: (\[[^]]*\] )?(\d+) added, (\d+) changed, (\d+) removed")
ANSI_STYLE = re.compile(r"\x1b\[[0-9;]*m")


def test_book_builds_without_warnings(edition_book):
    built_book = edition_book
    log = (built_book.parent / "book-build.log").read_text()
    assert "build succeeded" in log
    read = READ_PAGES.search(ANSI_STYLE.sub("", log))
    assert read and int(read.group(2)) >= len(PAGES), (
        f"the build did not read every page again, so it could not print every page's warnings: "
        f"{read.group(0) if read else 'no updating environment line in the log'}")
    sphinx_warnings = [line for line in log.splitlines() if "WARNING" in line and "[IPKernelApp]" not in line]
    assert not sphinx_warnings, f"the build printed warnings (they are errors here): {sphinx_warnings[:5]}"
    for page in PAGES:
        assert (built_book / f"{page}.html").is_file(), f"{page} is in _toc.yml but was not built"


def test_every_notebook_is_in_the_toc():
    notebooks = sorted(p.relative_to(ROOT).with_suffix("").as_posix() for p in (ROOT / "notebooks").glob("*.ipynb"))
    missing = [nb for nb in notebooks if nb not in PAGES]
    assert not missing, f"notebooks missing from _toc.yml: {missing}"


def _screenshot_pixels(shoot: Callable[[], bytes]) -> tuple[int, int]:
    """``_count_differing_pixels`` of a screenshot taken now by ``shoot``."""
    return _count_differing_pixels(shoot())


def _count_differing_pixels(png: bytes) -> tuple[int, int]:
    """Number of pixels that differ clearly from the most common colour, and the total."""
    import numpy as np
    from PIL import Image

    image = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).reshape(-1, 3).astype(int)
    # each colour as one integer 0xRRGGBB: the same colours in the same (lexicographic) order
    # as np.unique(image, axis=0), ties included, for a twentieth of its time
    packed = (image[:, 0] << 16) | (image[:, 1] << 8) | image[:, 2]
    colours, counts = np.unique(packed, return_counts=True)
    top = colours[np.argmax(counts)]
    background = np.array([top >> 16, (top >> 8) & 0xFF, top & 0xFF])
    differing = np.abs(image - background).sum(axis=1) > 30
    return int(differing.sum()), int(image.shape[0])


@functools.cache
def _file_transfer_size(path: Path, modified_ns: int, size: int) -> int:
    """``_transfer_size`` of one version of a file (its path, modification time and size):
    each file a page loads (MathJax, the theme, the viewer...) is compressed once per session."""
    import gzip

    data = path.read_bytes()
    return len(data) if path.suffix.lower() in COMPRESSED else len(gzip.compress(data, 6))


def _transfer_size(url: str) -> int:
    """Bytes a web server sends for a local file: gzip level 6 for text, images and fonts as they are."""
    parsed = urlparse(url)
    path = Path(unquote(parsed.path))
    if parsed.scheme != "file" or not path.is_file():
        return 0
    stat = path.stat()
    return _file_transfer_size(path, stat.st_mtime_ns, stat.st_size)


#: Elements wider than the viewport (outside the containers that may scroll sideways:
#: code, tables, 3D scenes, display formulas), and text blocks whose text is clipped.
LAYOUT_JS = """() => {
  const width = window.innerWidth;
  const main = document.querySelector('article.bd-article') || document.querySelector('main') || document.body;
  const mayScroll = 'pre, div.highlight, table, .pst-scrollable-table-container, .robokin-scene, '
    + 'mjx-container, div.math, .MathJax, div.cell_input, .dg';
  const name = el => el.tagName.toLowerCase() + (el.className && typeof el.className === 'string'
    ? '.' + el.className.trim().split(/\\s+/).slice(0, 2).join('.') : '');
  const visible = el => el.offsetParent !== null && !el.closest('details:not([open]) > :not(summary)');
  const wide = Array.from(main.querySelectorAll('*')).filter(el => visible(el) && !el.closest(mayScroll)
      && el.getBoundingClientRect().right > width + 1 && el.getBoundingClientRect().width > 0)
    .map(el => name(el) + ' ' + Math.round(el.getBoundingClientRect().right) + 'px: '
      + (el.textContent || '').trim().slice(0, 40));
  const clipped = Array.from(main.querySelectorAll('p, li, div.cell_output pre, div.output pre, dd'))
    .filter(el => visible(el) && el.scrollWidth > el.clientWidth + 1)
    .map(el => name(el) + ': ' + (el.textContent || '').trim().slice(0, 40));
  return {pageWidth: document.documentElement.scrollWidth, width: width, wide: wide.slice(0, 5),
          nWide: wide.length, clipped: clipped.slice(0, 5), nClipped: clipped.length};
}"""


def _check_layout(tab, page: str, edition: str) -> None:
    """At a laptop's and a phone's width: no sideways page scroll, nothing wider than the
    viewport except code, tables, scenes and formulas, no clipped prose or output text; at the
    laptop's, on a chapter, no code block that scrolls sideways (:func:`_check_code_width`).
    Screenshots (JPEG) go to _build/screenshots/<edition>/."""
    for width in WIDTHS:
        tab.set_viewport_size({"width": width, "height": 900})
        next_frames(tab)
        folder = SCREENSHOTS / edition
        folder.mkdir(parents=True, exist_ok=True)
        # evidence for a reader, not asserted: JPEG costs half of PNG's encoding
        tab.screenshot(path=str(folder / f"{page.replace('/', '_')}-{width}.jpg"), type="jpeg", quality=85)
        found = tab.evaluate(LAYOUT_JS)
        assert found["pageWidth"] <= width + 1 and not found["nWide"], (
            f"{page} at {width} px: the page is {found['pageWidth']} px wide; "
            f"{found['nWide']} elements stick out: {found['wide']}")
        assert not found["nClipped"], f"{page} at {width} px: clipped text in {found['clipped']}"
        if width == LAPTOP and page.startswith("notebooks/"):
            _check_code_width(tab, page)
    # left at the last width: going back would redraw every scene for nothing (the page
    # loaded each of its files at the first width already)


def _local_size(url: str) -> int:
    parsed = urlparse(url)
    if parsed.scheme != "file":
        return 0
    path = Path(unquote(parsed.path))
    return path.stat().st_size if path.is_file() else 0


def test_student_edition_has_no_solutions(built_student_book):
    """Solutions are absent from the student edition's HTML, not just collapsed."""
    import html
    import json
    import re

    for path in sorted((ROOT / "notebooks").glob("*.ipynb")):
        page = (built_student_book / "notebooks" / f"{path.stem}.html").read_text()
        assert "tag_solution" not in page and 'class="solution' not in page, f"{path.stem}: a solution block"
        text = html.unescape(re.sub(r"<[^>]+>", "", page))
        # whole lines: a solution's "for m, opts in X.items()" (in a comprehension) is no leak
        # when a shown check cell has "for m, opts in X.items():"
        page_lines = {line.strip() for line in text.splitlines()}
        cells = json.loads(path.read_text())["cells"]
        shown = {line.strip() for c in cells if "solution" not in c.get("metadata", {}).get("tags", [])
                 for line in "".join(c["source"]).splitlines()}
        for cell in cells:
            if "solution" in cell.get("metadata", {}).get("tags", []):
                lines = [line.strip() for line in "".join(cell["source"]).splitlines()
                         if len(line.strip()) > 30 and line.strip() not in shown]
                leaked = [line for line in lines if line in page_lines]
                assert not leaked, f"{path.stem}: solution code in the page: {leaked[:2]}"


READING_LAYOUT_JS = """() => {
  const text = el => el.textContent.replace(/\\s+/g, ' ').trim();
  const all = sel => Array.from(document.querySelectorAll(sel));
  return {
    exercises: all('div.exercise > p.admonition-title').map(text),
    solutionTitles: all('details.robokin-solution > summary').map(text),
    looseSolutions: all('div.solution, div.cell.tag_solution')
      .filter(el => !el.closest('details.robokin-solution')).length,
    openSolutions: all('details.robokin-solution[open]').length,
    looseChecks: all('div.cell.tag_check').filter(el => !el.closest('details.robokin-checks')).length,
    checkBlocks: all('details.robokin-checks').length,
    toggleButtons: all('div.solution button.toggle-button').length,
  };
}"""


#: Resolves when the scene's MeshCat viewer has drawn every command it was given (and a
#: playing animation has advanced); resolves anyway after the timeout (ms), so that the
#: screenshot's own assertion reports a scene not drawn. From the first call on, every scene
#: of the page that has drawn and advanced is paused at the next frame: an animation left
#: running redraws its scene on the CPU (SwiftShader) at every frame, and one that comes on
#: screen while the test draws or photographs another would play for all that time.
#: does the scene's viewer hold an animation (MeshCat's Animator has an action per track)
SCENE_ANIMATED_JS = "box => box.robokinViewer.animator.actions.length > 0"

SCENE_DRAWN_JS = """(box, timeout) => new Promise(resolve => {
  const deadline = performance.now() + timeout;
  const settled = viewer => !viewer.needs_render && (!viewer.animator.playing || viewer.animator.time > 0);
  if (!window.robokinPauseSettled) {
    window.robokinPauseSettled = true;
    const pause = () => {
      document.querySelectorAll('.robokin-scene').forEach(scene => {
        const viewer = scene.robokinViewer;
        if (viewer && viewer.animator.playing && settled(viewer)) viewer.animator.pause();
      });
      requestAnimationFrame(pause);
    };
    pause();
  }
  const look = () => {
    const viewer = box.robokinViewer;
    if (viewer && settled(viewer)) {
      requestAnimationFrame(() => resolve(true));
    } else if (performance.now() > deadline) {
      resolve(false);
    } else {
      requestAnimationFrame(look);
    }
  };
  look();
})"""


def _check_reading_layout(tab, page: str, chapter: int, student: bool) -> None:
    """Exercises numbered per chapter (5.1, 5.2, ...); every solution in one closed
    'Solution ... (click to show)' block; every check cell folded under 'Checks'."""
    found = tab.evaluate(READING_LAYOUT_JS)
    numbers = [re.fullmatch(r"Exercise (\d+)\.(\d+)", t) for t in found["exercises"]]
    assert found["exercises"] and all(numbers), f"{page}: exercise labels {found['exercises'][:4]}"
    assert [(int(m.group(1)), int(m.group(2))) for m in numbers if m] == [
        (chapter, k) for k in range(1, len(numbers) + 1)], f"{page}: exercise labels {found['exercises']}"
    titles = found["solutionTitles"]
    assert (not titles) if student else titles, f"{page}: solution blocks {titles[:3]}"
    assert all(re.fullmatch(r"Solution( to Exercise \d+\.\d+)?( \(\d+ cells\))? \(click to show\)", t)
                          for t in titles), f"{page}: solution titles {sorted(set(titles))[:4]}"
    referenced = [t for t in titles if "Exercise" in t]
    assert all(f"Exercise {chapter}." in t for t in referenced), f"{page}: {referenced[:3]}"
    assert found["looseSolutions"] == 0 and found["openSolutions"] == 0 and found["toggleButtons"] == 0, (
        f"{page}: solutions not folded in the book's one style: {found}")
    assert found["looseChecks"] == 0, f"{page}: {found['looseChecks']} check cells interrupt the text"


#: Run in every document of the reused tab before its own scripts: the page finds the storage
#: of a first visit (the theme writes its colour mode and sidebar position there).
FRESH_STORAGE_JS = "try { localStorage.clear(); sessionStorage.clear(); } catch (e) {}"


@pytest.fixture(scope="session")
def _reused_page_tab(browser):
    """One tab for every page check of the session, with the browser cache off.

    A new context and tab per page cost Chromium a new renderer process and a cold V8 (every
    script of the theme, MathJax and MeshCat compiled again): reusing one tab costs about a
    fifth less CPU per page. The cache is off (DevTools' "Disable cache"), so that each page
    requests every file it uses as on a cold cache (the page weight check counts those
    requests: the same URLs as in a new context), and the storage is cleared before each page
    (FRESH_STORAGE_JS)."""
    context = browser.new_context(viewport={"width": 1280, "height": 900})
    KEPT_CONTEXTS.append(context)
    context.add_init_script(FRESH_STORAGE_JS)
    holder: dict = {}

    def tab():
        if "tab" not in holder or holder["tab"].is_closed():
            holder["tab"] = context.new_page()
            holder["devtools"] = context.new_cdp_session(holder["tab"])
            holder["devtools"].send("Network.enable")
            holder["devtools"].send("Network.setCacheDisabled", {"cacheDisabled": True})
        return holder["tab"]

    try:
        yield tab
    finally:
        KEPT_CONTEXTS.remove(context)
        context.close()


@pytest.fixture
def page_tab(_reused_page_tab):
    """The reused tab at the laptop's width, left on about:blank after the test: the page
    unloaded (no scene drawing on), the listeners the test added removed."""
    tab = _reused_page_tab()
    tab.set_viewport_size({"width": 1280, "height": 900})
    listeners: list = []

    def listen(event, handler):
        tab.on(event, handler)
        listeners.append((event, handler))

    try:
        yield tab, listen
    finally:
        if not tab.is_closed():
            try:
                tab.goto("about:blank")
            finally:
                for event, handler in listeners:
                    tab.remove_listener(event, handler)


@pytest.mark.browser
@pytest.mark.parametrize("page", PAGES)
def test_page_in_browser(edition_book, page_tab, page, request):
    built_book = edition_book
    url = (built_book / f"{page}.html").as_uri()
    tab, listen = page_tab
    errors: list[str] = []
    external: list[str] = []
    loaded: dict[str, int] = {}
    listen("pageerror", lambda exc: errors.append(f"page error: {exc}"))
    listen("console", lambda msg: errors.append(f"console {msg.type}: {msg.text}") if msg.type == "error" else None)
    listen("requestfailed", lambda req: errors.append(f"failed to load {req.url}: {req.failure}"))

    def on_request(req):
        if req.url.startswith(("http://", "https://")):
            external.append(req.url)
        else:
            loaded[req.url] = _local_size(req.url)

    listen("request", on_request)
    tab.goto(url, wait_until="load")

    # Maths: every math element typeset by MathJax, no MathJax errors.
    n_math = tab.evaluate("document.querySelectorAll('div.math, span.math').length")
    if n_math:
        tab.wait_for_function("window.MathJax && MathJax.startup && MathJax.startup.promise", timeout=WAIT_MS)
        tab.evaluate("MathJax.startup.promise")
        n_typeset = tab.evaluate("document.querySelectorAll('mjx-container').length")
        assert n_typeset >= n_math, f"{page}: {n_math} math elements but only {n_typeset} typeset"
        assert tab.evaluate("document.querySelectorAll('mjx-merror').length") == 0, f"{page}: MathJax errors"
        # An undefined macro (e.g. a TeX package that was not loaded) is no merror
        # element: MathJax prints its name in red. Look for both in the MathML.
        undefined = tab.evaluate(MATH_ERRORS_JS)
        assert not undefined, f"{page}: TeX errors or undefined macros: {undefined[:3]}"

    # Images: every <img> loaded with a non-zero size.
    broken = tab.evaluate(
        "Array.from(document.images).filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.src)"
    )
    assert not broken, f"{page}: images that did not load: {broken}"

    # 3D scenes: each canvas shows something, and animated scenes have controls.
    scenes = tab.locator(".robokin-scene")
    n_scenes = scenes.count()
    animated_scenes = 0
    for index in range(n_scenes):
        scene = scenes.nth(index)
        scene.scroll_into_view_if_needed()
        canvas = scene.locator("canvas").first
        canvas.wait_for(state="visible", timeout=WAIT_MS)
        # the viewer has drawn the scene (and played its animation for a frame), then
        # stops playing: an animation left running redraws the scene on the CPU
        # (SwiftShader) for the rest of the test
        scene.evaluate(SCENE_DRAWN_JS, DRAW_TIMEOUT * 1000)
        # one screenshot, taken again only if the scene is still blank (at most 20 s)
        differing, total = poll_until(functools.partial(_screenshot_pixels, canvas.screenshot),
                                      lambda counts: counts[0] > 0.002 * counts[1])
        assert differing > 0.002 * total, f"{page}: scene {index} looks blank ({differing}/{total} pixels drawn)"
        # an animated scene (its viewer holds an animation) can be played: its controls hold
        # MeshCat's play button, open at 760 px and wider, behind "Open Controls" below
        if scene.evaluate(SCENE_ANIMATED_JS):
            animated_scenes += 1
            assert scene.locator(".dg li", has_text="play").count() > 0, f"{page}: scene {index} has no play control"
            assert scene.get_by_text(re.compile(r"^(Open|Close) Controls$")).count() > 0, (
                f"{page}: scene {index} has no button that shows its controls")
    # as many animated scenes as the page's scenes declare (the check above never idles): each
    # links the shared scene script with its animated flag (robokin.views.sphinx_extension)
    declared = (built_book / f"{page}.html").read_text(encoding="utf-8").count('data-animated="true"')
    assert animated_scenes == declared, f"{page}: {animated_scenes} scenes play an animation, {declared} declare one"

    chapter = re.match(r"notebooks/0*(\d+)_", page)
    if chapter and int(chapter.group(1)) > 0:
        _check_reading_layout(tab, page, int(chapter.group(1)), student=built_book == EDITION_HTML["student"])

    assert not external, f"{page}: the page tried to reach the network: {external[:5]}"
    assert not errors, f"{page}: " + "\n".join(errors)

    edition = "student" if built_book == EDITION_HTML["student"] else "instructor"
    _check_layout(tab, page, edition)

    # Page weight, after every scene has loaded its data (cold cache: each file once).
    html_size = _local_size(url)
    raw = html_size + sum(size for u, size in loaded.items() if u != url)
    weight = _transfer_size(url) + sum(_transfer_size(u) for u in loaded if u != url)
    print(f"[weight] {page}: {weight / 1e6:.2f} MB transferred ({raw / 1e6:.2f} MB uncompressed, "
          f"{len(loaded)} files); own HTML {html_size / 1e3:.0f} kB")
    edition = request.node.callspec.params["edition_book"]   # "instructor" or "student"
    assert html_size <= PAGE_HTML_BUDGET, (
        f"{page} ({edition}): its HTML is {html_size / 1e3:.0f} kB > {PAGE_HTML_BUDGET / 1e3:.0f} kB")
    assert weight <= PAGE_WEIGHT_BUDGET, f"{page}: page weight {weight / 1e6:.2f} MB > 2 MB"


#: Every code block of a page, its folded blocks opened (and folded again after): its font size, its client width and
#: scroll width, its widest line; and the width of 88 characters in its font (a probe).
CODE_WIDTH_JS = """(characters) => {
  const folded = Array.from(document.querySelectorAll('article details')).filter(d => !d.open);
  folded.forEach(d => { d.open = true; });
  const blocks = Array.from(document.querySelectorAll('article div.highlight pre'))
    .filter(pre => pre.offsetParent !== null);
  const probe = document.createElement('span');
  probe.style.cssText = 'position: absolute; visibility: hidden; white-space: pre';
  document.body.appendChild(probe);
  const found = blocks.map(pre => {
    const style = getComputedStyle(pre);
    probe.style.font = style.font;
    probe.textContent = 'm'.repeat(characters);
    const lines = pre.textContent.replace(/\\n$/, '').split('\\n');
    return {fontPx: parseFloat(style.fontSize), client: pre.clientWidth, scroll: pre.scrollWidth,
            room: pre.clientWidth - parseFloat(style.paddingLeft) - parseFloat(style.paddingRight),
            probe: probe.getBoundingClientRect().width, longest: Math.max(...lines.map(l => l.length)),
            line: lines.reduce((a, b) => (b.length > a.length ? b : a), '').slice(0, 60)};
  });
  probe.remove();
  folded.forEach(d => { d.open = false; });   // as the reader found them
  return found;
}"""
#: The longest code line the notebooks may have (ruff's line length; tests/test_notebook_conventions.py).
CODE_LINE_LENGTH = 88


def _check_code_width(tab, page: str) -> None:
    """At the page's width (1280 px) no code block scrolls sideways: each block's widest line
    fits (scrollWidth <= clientWidth), any 88-character line would fit (a probe in the block's
    own font, so the check measures something even where no line is that long), and the code
    font stays readable (at least 12 px)."""
    blocks = tab.evaluate(CODE_WIDTH_JS, CODE_LINE_LENGTH)
    assert blocks, f"{page}: no code blocks"
    small = sorted({block["fontPx"] for block in blocks if block["fontPx"] < 12})
    assert not small, f"{page}: code at {small} px, smaller than 12 px"
    scrolling = [block for block in blocks if block["scroll"] > block["client"]]
    assert not scrolling, (
        f"{page}: {len(scrolling)} code blocks scroll sideways at {LAPTOP} px, e.g. a line of "
        f"{scrolling[0]['longest']} characters in {scrolling[0]['client']} px "
        f"(scroll width {scrolling[0]['scroll']} px): {scrolling[0]['line']!r}")
    narrowest = min(blocks, key=lambda block: block["room"] - block["probe"])
    assert narrowest["probe"] <= narrowest["room"], (
        f"{page}: {CODE_LINE_LENGTH} characters take {narrowest['probe']:.0f} px, but the narrowest "
        f"code block has {narrowest['room']:.0f} px for text")
