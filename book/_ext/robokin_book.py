"""Sphinx extension with the workbook's own build settings.

* **MathJax offline.**  Jupyter Book loads MathJax from a CDN by default, which
  fails on machines without internet.  This extension serves MathJax 3 from the
  ``django-static-mathjax`` wheel (pinned in ``requirements.txt``): it copies only
  the components the book needs (core, TeX input with its extensions, CommonHTML
  output and its fonts — about 0.7 MB instead of the 1.2 MB all-in-one bundle)
  into ``_build/html/_static/mathjax/`` and points Sphinx at them.
* **Stored outputs.**  Neither edition executes a notebook (``_config.yml``:
  ``execute_notebooks: "off"``): the pages show the outputs stored in the
  notebooks, which ``make execute`` computes and nbval (``make test``) proves equal
  to a fresh run with the current robokin.
* **Collapsed solutions.**  Code cells tagged ``solution`` are rendered inside a
  closed ``<details>`` block by ``_static/solutions.js`` (shipped from
  ``book/_static``), so a student sees the task first and opens the worked
  solution on purpose.
* **Student edition.**  With ``ROBOKIN_EDITION=student`` (``make book
  EDITION=student``) the solutions are not in the HTML at all: before a chapter
  notebook is parsed, its ``solution`` cells, the text between
  ``{solution-start}`` and ``{solution-end}``, the hidden tests of its test cells
  (``### BEGIN HIDDEN TESTS`` to ``### END HIDDEN TESTS``, taken out by nbgrader's own
  ``ClearHiddenTests``, as in nbgrader's student edition) and the printouts of its
  ``check`` cells are taken out. The notebook a reader downloads from a page
  (``_sources/``, which Sphinx copies from the file on disk) is that same student
  notebook, and the pages have no launch buttons (Binder, Colab and a hub open the
  repository's notebook, the instructor's). Like the instructor edition it uses the stored outputs, so it is built
  from exactly the pages of the instructor edition.
* **Exercises numbered per chapter.**  sphinx-exercise numbers exercises through
  the whole book (Exercise 25 in Chapter 5); the numbers are rewritten as
  *chapter.k* (Exercise 5.2), the chapter taken from the notebook's name
  (``notebooks/05_…``). Titles of solutions and cross-references use the same
  numbers.
"""

from __future__ import annotations

import hashlib
import importlib
import json
import os
import shutil
from pathlib import Path

from sphinx.application import Sphinx
from sphinx.util.nodes import make_refnode

# One rule for what the student edition keeps of a markdown cell, shared with nbgrader's
# edition (tools/grading/robokin_nbgrader/) and its tests: tools/notebook_analysis.py.
from tools.notebook_analysis import clear_solution_text

#: MathJax components copied into the built book (paths relative to ``es5/``).
MATHJAX_PARTS = (
    "startup.js",
    "core.js",
    "input/tex.js",
    "input/tex/extensions",
    "output/chtml.js",
    "output/chtml/fonts/tex.js",
    "output/chtml/fonts/woff-v2",
)

STATIC_DIR = Path(__file__).resolve().parent.parent / "_static"


def mathjax_source() -> Path:
    """Directory ``es5/`` of the MathJax 3 distribution installed with pip."""
    try:
        import mathjax  # provided by the django-static-mathjax wheel
    except ImportError as exc:  # pragma: no cover - install problem
        raise RuntimeError(
            "MathJax is missing: run `make book` (or `pip install -r requirements.txt`), "
            "which installs django-static-mathjax, the offline MathJax the book uses."
        ) from exc
    root = Path(mathjax.__file__).resolve().parent / "static" / "mathjax" / "es5"
    if not (root / "startup.js").is_file():  # pragma: no cover - broken install
        raise RuntimeError(f"MathJax files not found under {root}")
    return root


def configure_mathjax(app: Sphinx, config) -> None:
    """Use the local MathJax and load only the components the book needs."""
    config.mathjax_path = "mathjax/startup.js"
    mj = dict(config.mathjax3_config or {})
    loader = dict(mj.get("loader", {}))
    loader["load"] = ["input/tex", "output/chtml", "[tex]/boldsymbol"]
    mj["loader"] = loader
    tex = dict(mj.get("tex", {}))
    tex.setdefault("packages", {"[+]": ["ams", "boldsymbol"]})
    mj["tex"] = tex
    config.mathjax3_config = mj
    # pydata-sphinx-theme logs a console error on a first visit when no default
    # colour mode is set; a clean console is part of the browser check.
    config.html_context = {**(config.html_context or {}), "default_mode": "light"}
    # Ship solutions.js and the book stylesheet.
    if str(STATIC_DIR) not in config.html_static_path:
        config.html_static_path.append(str(STATIC_DIR))


def copy_mathjax(app: Sphinx, exception: Exception | None) -> None:
    """Copy the MathJax components into ``_static/mathjax`` of the HTML output."""
    if exception is not None or app.builder.format != "html":
        return
    source = mathjax_source()
    target = Path(app.outdir) / "_static" / "mathjax"
    for part in MATHJAX_PARTS:
        src, dst = source / part, target / part
        if src.is_dir():
            shutil.copytree(src, dst, dirs_exist_ok=True)
        else:
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dst)
    license_file = source.parent / "LICENSE"
    if license_file.is_file():
        shutil.copy2(license_file, target / "LICENSE")


def deduplicate_scripts(app: Sphinx, pagename, templatename, context, doctree) -> None:
    """Drop repeated ``<script>`` entries (sphinx-thebe adds its inline set-up twice,
    which raises "Identifier 'THEBE_JS_URL' has already been declared" in the browser)."""
    scripts = context.get("script_files")
    if not scripts:
        return
    seen, unique = set(), []
    for script in scripts:
        filename = getattr(script, "filename", str(script)) or ""
        key = (filename, repr(sorted(getattr(script, "attributes", {}).items())))
        if key not in seen:
            seen.add(key)
            unique.append(script)
    scripts[:] = unique  # in place: the template reads this same list


EDITIONS = ("instructor", "student")


def configure_edition(app: Sphinx, config) -> None:
    """The student edition says what it is, and never executes a notebook (whatever ``_config.yml`` says)."""
    if config.robokin_edition not in EDITIONS:
        raise ValueError(f"robokin_edition (ROBOKIN_EDITION) must be one of {EDITIONS}, "
                         f"not {config.robokin_edition!r}")
    if config.robokin_edition == "student":
        config.nb_execution_mode = "off"
        options = dict(config.html_theme_options or {})
        options["announcement"] = "Student edition: the worked solutions are not included."
        # The launch buttons (Binder, Colab, a hub) open the repository's notebook, the instructor's
        # (solutions and hidden tests): the student edition offers the page's own download instead.
        options["launch_buttons"] = {}
        config.html_theme_options = options


def student_notebook(text: str) -> str | None:
    """The notebook ``text`` without its solutions (None if it is not a notebook).

    Removed: code cells tagged ``solution``; every cell from a ``{solution-start}``
    directive to its ``{solution-end}`` (of a markdown cell with ``BEGIN SOLUTION`` /
    ``END SOLUTION`` markers of its own, e.g. in HTML comments, only the text between
    them, as in nbgrader's student edition); the hidden tests of every code cell
    (:func:`without_hidden_tests`); the outputs of ``check`` cells (they print the
    computed answers) and of cells that had hidden tests. Kept: the problem, hints,
    figures, the check cells' visible code, the *Try it yourself* cells.
    """
    try:
        nb = json.loads(text)
    except ValueError:
        return None
    if not isinstance(nb, dict) or "cells" not in nb:
        return None
    cells, in_solution = [], False
    for cell in nb["cells"]:
        source = cell.get("source", "")
        source = "".join(source) if isinstance(source, list) else source
        tags = cell.get("metadata", {}).get("tags", [])
        starts = cell["cell_type"] == "markdown" and "{solution-start}" in source
        ends = cell["cell_type"] == "markdown" and "{solution-end}" in source
        if starts:
            in_solution = True
        if cell["cell_type"] == "markdown" and "BEGIN SOLUTION" in source:
            kept = clear_solution_text(source)  # the text around the cell's own markers
            in_solution = in_solution and not ends
            if kept.strip():
                cells.append(dict(cell, source=kept))
            continue
        drop = in_solution or "solution" in tags
        if ends:
            in_solution = False
        if drop:
            continue
        if cell["cell_type"] == "code":
            visible, removed = without_hidden_tests(source)
            if removed:
                cell = dict(cell, source=visible, outputs=[])
        if ("check" in tags) and cell.get("outputs"):
            cell = dict(cell, outputs=[])
        cells.append(cell)
    nb["cells"] = cells
    return json.dumps(nb, ensure_ascii=False)


def without_hidden_tests(source: str) -> tuple[str, bool]:
    """``source`` without its hidden tests, and whether it had any.

    nbgrader's own ``ClearHiddenTests`` (the preprocessor of ``generate_assignment``, with
    its configured delimiters) does it, so that the book's student edition and nbgrader's
    leave out exactly the same lines.
    """
    if "HIDDEN TESTS" not in source:
        return source, False
    import nbformat
    from nbgrader.preprocessors import ClearHiddenTests

    cell, _ = ClearHiddenTests(enforce_metadata=False).preprocess_cell(nbformat.v4.new_code_cell(source), {}, 0)
    return cell.source, cell.source != source


def remove_solutions(app: Sphinx, docname: str, source: list[str]) -> None:
    if app.config.robokin_edition != "student" or not str(app.env.doc2path(docname)).endswith(".ipynb"):
        return
    text = student_notebook(source[0])
    if text is not None:
        source[0] = text


def student_sources(app: Sphinx, exception: Exception | None) -> None:
    """In the student edition, the notebooks a reader downloads (``_sources/<page>.ipynb``, which
    Sphinx copies from the original file) are the student notebooks the pages were made from."""
    if exception is not None or app.config.robokin_edition != "student" or app.builder.format != "html":
        return
    sources = Path(app.outdir) / "_sources"
    for docname in app.env.found_docs:
        original = Path(app.env.doc2path(docname))
        if original.suffix != ".ipynb":
            continue
        for copied in (sources / f"{docname}.ipynb", sources / f"{docname}.ipynb.txt"):
            if copied.is_file():
                text = student_notebook(original.read_text(encoding="utf-8"))
                copied.write_text(text if text is not None else "", encoding="utf-8")


def chapter_of(docname: str) -> int | None:
    """The chapter number of a chapter notebook (``notebooks/05_baxter_circle`` -> 5)."""
    name = docname.rsplit("/", 1)[-1]
    head = name.split("_", 1)[0]
    return int(head) if docname.startswith("notebooks/") and head.isdigit() and int(head) > 0 else None


def number_exercises_per_chapter(app: Sphinx, env) -> list[str]:
    """Exercise k of chapter c is numbered (c, k), in reading order within the page."""
    for docname, numbers in env.toc_fignumbers.items():
        chapter = chapter_of(docname)
        exercises = numbers.get("exercise")
        if chapter is None or not exercises:
            continue
        ordered = sorted(exercises, key=lambda ident: exercises[ident])
        numbers["exercise"] = {ident: (chapter, k) for k, ident in enumerate(ordered, 1)}
    return []


def one_solution_style(app: Sphinx, doctree, docname: str) -> None:
    """sphinx-exercise solutions lose the ``dropdown`` class (sphinx-togglebutton's
    "Click to show" button); ``solutions.js`` folds them, like the solution code cells,
    into one closed ``<details class="robokin-solution">`` each."""
    from sphinx_exercise.nodes import solution_node

    for node in doctree.findall(solution_node):
        node["classes"] = [c for c in node["classes"] if c not in ("dropdown", "toggle")]


def nitpick_pairs_as_tuples(app: Sphinx, config) -> None:
    """``nitpick_ignore`` from ``_config.yml`` arrives as lists; Sphinx looks pairs up as tuples."""
    config.nitpick_ignore = [tuple(pair) for pair in config.nitpick_ignore]


def _python_object(dotted: str):
    """The object called ``dotted`` (a module, or attributes of one), or None."""
    parts = dotted.split(".")
    for split in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        for attribute in parts[split:]:
            obj = getattr(obj, attribute, None)
            if obj is None:
                return None
        return obj
    return None


def _same_object(documented: str, target: str) -> bool:
    """True if the names ``documented`` and ``target`` are the same Python object (a re-export)."""
    obj = _python_object(target)
    return obj is not None and obj is _python_object(documented)


def _docstring_owner(node) -> str:
    """The dotted name of the object whose docstring holds ``node`` (autodoc), or ''."""
    source = str(node.source or "")
    return source.rsplit("docstring of ", 1)[1].strip() if "docstring of " in source else ""


def resolve_short_python_names(app: Sphinx, env, node, contnode):
    """Resolve a Python name of the API reference that Sphinx did not find to its one documented object.

    Two cases: a docstring refers to a name of its own module by its short name
    (``:data:`REASONS```), documented under its full name; or it uses a full name
    under which a re-exported object is not documented (``robokin.motion.ik.NullSpace``
    is documented as ``robokin.motion.NullSpace``). Among the documented objects
    whose name ends with ``.<name>`` (of a type the role accepts), a re-export of
    the very same object wins; else the one sharing the longest module prefix with
    the docstring's owner. A tie or no candidate leaves the reference unresolved
    (a nitpicky warning).
    """
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip(".~")
    domain = env.get_domain("py")
    if node["reftype"] == "mod":
        entries = {name: (entry.docname, entry.node_id) for name, entry in domain.modules.items()}
    else:
        objtypes = set(domain.objtypes_for_role(node["reftype"]) or ())
        entries = {name: (entry.docname, entry.node_id) for name, entry in domain.objects.items()
                   if entry.objtype in objtypes and not entry.aliased}
    winners = [name for name in entries if name.endswith("." + target)]
    if not winners and "." in target and node["reftype"] != "mod":
        last = target.rsplit(".", 1)[1]
        winners = [name for name in entries if name.endswith("." + last) and _same_object(name, target)]
    elif len(winners) > 1:
        owner = _docstring_owner(node).split(".")

        def shared(name: str) -> int:
            count = 0
            for a, b in zip(name.split("."), owner):
                if a != b:
                    break
                count += 1
            return count

        best = max(shared(name) for name in winners)
        winners = [name for name in winners if shared(name) == best]
    if len(winners) != 1:
        return None
    docname, node_id = entries[winners[0]]
    return make_refnode(app.builder, node["refdoc"], docname, node_id, contnode, winners[0])


def setup(app: Sphinx) -> dict:
    app.add_config_value("robokin_edition", os.environ.get("ROBOKIN_EDITION", "instructor") or "instructor",
                         "env", [str])
    # A change of this extension (e.g. of what the student edition removes) changes how every
    # page is read: as a config value ("env"), its digest makes Sphinx read every page again.
    app.add_config_value("robokin_extension_digest", hashlib.sha256(Path(__file__).read_bytes()).hexdigest(),
                         "env", [str])
    app.connect("config-inited", configure_edition, priority=50)
    app.connect("missing-reference", resolve_short_python_names)
    app.connect("config-inited", nitpick_pairs_as_tuples)
    app.connect("source-read", remove_solutions)
    # Run after myst-parser has added its own MathJax options.
    app.connect("config-inited", configure_mathjax, priority=900)
    app.connect("build-finished", copy_mathjax)
    app.connect("build-finished", student_sources)
    app.connect("html-page-context", deduplicate_scripts, priority=900)
    # After Sphinx has assigned the book-wide figure numbers (priority 500).
    app.connect("env-get-updated", number_exercises_per_chapter, priority=900)
    app.connect("doctree-resolved", one_solution_style)
    app.add_js_file("solutions.js")
    app.add_css_file("robokin-book.css")
    return {"version": "0.1", "parallel_read_safe": True, "parallel_write_safe": True}
