"""Every notebook follows the book's notebook conventions (book/for-instructors.md).

nbval checks that stored outputs match a fresh run; these tests check the shape
of the notebooks: stored executed top to bottom, exercise structure, and the
`nbval-ignore-output` tag used only where an output cannot be compared.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parent.parent
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))
EXERCISES = [nb for nb in NOTEBOOKS if not nb.name.startswith("00_")]

#: Tags a cell may carry, and what they mean.
ALLOWED_TAGS = {
    "solution",            # a worked solution: rendered collapsed in the book
    "nbval-ignore-output",  # output is a picture or a 3D scene: nbval does not compare it
    "hide-input",          # show only the output (e.g. a figure made by plotting code)
    "hide-output",
    "remove-input",
    "remove-cell",         # set-up cells that the book does not show
    "check",               # asserts the computed values against independent references
}

#: A check cell's weight in points (``points-N``, tools/authoring/nbgrader_metadata.py); only on check cells.
POINTS_TAG = re.compile(r"^points-[1-9][0-9]?$")
#: An answer a test grades (``explains-<answer>``, tools/notebook_analysis.py); only on check cells.
EXPLAINS_TAG = re.compile(r"^explains-[A-Za-z_][A-Za-z0-9_]*$")

#: Output types that may be left out of nbval's comparison.
UNCOMPARABLE_MIME = {"image/png", "image/svg+xml", "text/html", "application/vnd.jupyter.widget-view+json"}


def load(path: Path) -> dict:
    return json.loads(path.read_text())


def test_there_are_notebooks():
    assert NOTEBOOKS, "notebooks/ holds no notebook"
    assert NOTEBOOKS[0].name == "00_tour.ipynb"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_stored_executed_top_to_bottom(path):
    cells = [c for c in load(path)["cells"] if c["cell_type"] == "code"]
    counts = [c.get("execution_count") for c in cells]
    assert None not in counts, f"{path.name}: cells that were never run (execute it: `make execute`)"
    assert counts == list(range(1, len(cells) + 1)), f"{path.name}: not run top to bottom in a fresh kernel"
    for cell in cells:
        for output in cell.get("outputs", []):
            assert output["output_type"] != "error", f"{path.name}: a stored output is an error"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_no_execution_timestamps_in_metadata(path):
    """Stored notebooks carry no run times (`make execute` turns nbclient's record_timing off)."""
    for index, cell in enumerate(load(path)["cells"]):
        assert "execution" not in cell.get("metadata", {}), f"{path.name} cell {index}: execution timestamps stored"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_no_warnings_in_outputs(path):
    """Nothing written to stderr: a warning in a stored output (a NaN, a matplotlib
    complaint) is shown to every reader of the book."""
    for index, cell in enumerate(load(path)["cells"]):
        for output in cell.get("outputs", []):
            assert output.get("name") != "stderr", (
                f"{path.name} cell {index}: stderr output: {''.join(output.get('text', ''))[:200]}"
            )


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_tags(path):
    for index, cell in enumerate(load(path)["cells"]):
        tags = set(cell.get("metadata", {}).get("tags", []))
        unknown = {t for t in tags - ALLOWED_TAGS if not POINTS_TAG.match(t) and not EXPLAINS_TAG.match(t)}
        assert not unknown, f"{path.name} cell {index}: unknown tags {unknown}"
        assert "check" in tags or not any(EXPLAINS_TAG.match(t) for t in tags), (
            f"{path.name} cell {index}: explains-<answer> belongs on a check cell"
        )
        points = {t for t in tags if POINTS_TAG.match(t)}
        assert not points or ("check" in tags and len(points) == 1), (
            f"{path.name} cell {index}: {points} belongs on one check cell"
        )
        if "nbval-ignore-output" in tags:
            mimes = {m for o in cell.get("outputs", []) for m in o.get("data", {})}
            assert mimes & UNCOMPARABLE_MIME, (
                f"{path.name} cell {index}: tagged nbval-ignore-output but has no picture or scene output"
            )


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_no_addresses_or_timestamps_in_outputs(path):
    import re

    pattern = re.compile(r"at 0x[0-9a-f]{6,}|\b20\d\d-\d\d-\d\d[ T]\d\d:\d\d")
    for index, cell in enumerate(load(path)["cells"]):
        for output in cell.get("outputs", []):
            text = "".join(output.get("text", "")) + "".join(output.get("data", {}).get("text/plain", ""))
            assert not pattern.search(text), f"{path.name} cell {index}: output holds an address or a timestamp"


@pytest.mark.parametrize("path", EXERCISES, ids=lambda p: p.name)
def test_exercise_structure(path):
    cells = load(path)["cells"]
    markdown = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "markdown")
    assert cells[0]["cell_type"] == "markdown" and "".join(cells[0]["source"]).lstrip().startswith("# ")
    for heading in ("Learning goals", "Problem statement", "Going further"):
        assert heading in markdown, f"{path.name}: no '{heading}' section"
    assert any("solution" in c.get("metadata", {}).get("tags", []) for c in cells), f"{path.name}: no solution cells"
    code = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
    assert "assert" in code, f"{path.name}: nothing is checked"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_printed_numbers_are_machine_independent(path):
    """Printed arrays go through robokin.formatting, which prints no ``-0.`` on any CPU.

    ``x.round(4)`` and ``np.round(x, 4)`` keep the sign of a tiny negative value
    (``-1e-17`` on one machine, ``+1e-17`` on another) and print ``-0.``.
    """
    import re

    rounding = re.compile(r"\.round\(|np\.round\(")
    for index, cell in enumerate(load(path)["cells"]):
        if cell["cell_type"] != "code":
            continue
        for line in "".join(cell["source"]).splitlines():
            assert not ("print(" in line and rounding.search(line)), (
                f"{path.name} cell {index}: prints a rounded array; use robokin.formatting.rounded "
                f"or format_array (no negative zeros): {line.strip()}"
            )
        for output in cell.get("outputs", []):
            text = "".join(output.get("text", "")) + "".join(output.get("data", {}).get("text/plain", ""))
            assert not re.search(r"(?<![\w.])-0\.0*(?![\d])", text), (
                f"{path.name} cell {index}: a printed negative zero (its sign depends on the machine)"
            )


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_stream_outputs_are_merged(path):
    """One stream output per cell and stream: how a kernel's flushes split the text depends
    on timing, so unmerged streams make every re-execution a diff (`make execute` merges them)."""
    for index, cell in enumerate(load(path)["cells"]):
        outputs = cell.get("outputs", [])
        for first, second in zip(outputs, outputs[1:]):
            assert not (first["output_type"] == second["output_type"] == "stream"
                        and first["name"] == second["name"]), (
                f"{path.name} cell {index}: consecutive {first['name']} outputs; store it with `make execute`"
            )


# ---------------------------------------------------------------- Colab: the install cell
def _install_cell(path: Path) -> dict:
    code = [c for c in load(path)["cells"] if c["cell_type"] == "code"]
    assert code, f"{path.name}: no code cell"
    return code[0]


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_first_code_cell_installs_robokin_where_it_is_missing(path, monkeypatch):
    """Colab opens a notebook without the repository: the first code cell installs robokin
    (with its views, and the extras the notebook needs) from the repository named in _config.yml;
    here it does nothing."""
    import importlib.util
    import subprocess

    import yaml

    from tools.authoring.install_cell import extras_for

    cell = _install_cell(path)
    code = "".join(cell["source"])
    url = yaml.safe_load((ROOT / "_config.yml").read_text())["repository"]["url"]
    assert f"robokin[{extras_for(path)}] @ git+{url}" in code, (
        f"{path.name}: the install cell does not install robokin[{extras_for(path)}] from {url}")
    assert "remove-cell" in cell["metadata"].get("tags", []) and not cell.get("outputs")

    calls = []
    monkeypatch.setattr(subprocess, "run", lambda *a, **k: calls.append(a[0]))
    exec(compile(code, f"{path.name} install cell", "exec"), {})       # robokin is importable here
    assert calls == [], "the install cell ran pip in the repository's environment"

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "robokin" else real(name, *a))
    exec(compile(code, f"{path.name} install cell", "exec"), {})       # as on Colab
    assert len(calls) == 1 and calls[0][1:4] == ["-m", "pip", "install"] and calls[0][-1].endswith(url)


# ---------------------------------------------------------------- the book's width
#: Measured in the built book (Chromium, 1280 px window, chapter 2): a code cell's text is
#: 652 px wide and its 14 px monospace 8.43 px a character, so 77 characters fit; printed
#: output (6.49 px a character) fits 101. Code is formatted to black's 88: a line of 78 to
#: 88 characters scrolls sideways in a code cell at that width (47 of the 63 code blocks of
#: chapter 2 do), until the book's code font or the limit change.
CODE_LINE_LIMIT = 88


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_code_fits_the_book_width(path):
    """Code lines are at most 88 characters (black's width; at a 1280 px window the book
    shows 77 of them without scrolling: see CODE_LINE_LIMIT). Format with
    `.venv/bin/python tools/authoring/format_notebooks.py`."""
    long = [(index, len(line), line.strip()[:50])
            for index, cell in enumerate(load(path)["cells"]) if cell["cell_type"] == "code"
            for line in "".join(cell["source"]).splitlines() if len(line) > CODE_LINE_LIMIT]
    assert not long, (f"{path.name}: {len(long)} code lines longer than {CODE_LINE_LIMIT} characters "
                      f"(run tools/authoring/format_notebooks.py): {long[:3]}")


#: The book's content column is about 690 px wide at a 1280 px window: 80 characters of
#: printed output fit with room to spare (101 do, measured), or a 6.9 in figure at 100 dpi.
OUTPUT_LINE_LIMIT = 80
BOOK_COLUMN_PX = 690
#: Lines printed by robokin.check itself (one verdict per line, ``✔ ...`` / ``✘ ...``):
#: their width is robokin.check's to keep, not the notebook's.
#: An output shown in the book as one of these is not shown as its text/plain.
RICH_MIME = UNCOMPARABLE_MIME | {"text/latex", "text/markdown", "image/jpeg"}


def _printed_text(cell: dict):
    """The text a reader sees as printed output: stream text, and text/plain results
    that have no richer representation (a picture, HTML, LaTeX)."""
    if "nbval-ignore-output" in cell.get("metadata", {}).get("tags", []):
        return
    for output in cell.get("outputs", []):
        if output["output_type"] == "stream":
            yield "".join(output["text"])
        elif output["output_type"] in ("execute_result", "display_data"):
            data = output.get("data", {})
            if "text/plain" in data and not set(data) & RICH_MIME:
                yield "".join(data["text/plain"])


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_printed_output_fits_the_book_width(path):
    """Printed lines are at most 80 characters: a longer line is cut off in the book.
    Print fewer fields per line, break between fields, or set NumPy's linewidth."""
    long = [(index, len(line), line[:60])
            for index, cell in enumerate(load(path)["cells"]) if cell["cell_type"] == "code"
            for text in _printed_text(cell) for line in text.splitlines()
            if len(line) > OUTPUT_LINE_LIMIT]
    assert not long, (f"{path.name}: {len(long)} printed lines longer than {OUTPUT_LINE_LIMIT} "
                      f"characters: {long[:3]}")


def _png_size_and_dpi(data: str) -> tuple[int, int, float | None]:
    import base64
    import struct

    png = base64.b64decode(data)
    width, height = struct.unpack(">II", png[16:24])
    chunk = png.find(b"pHYs")
    dpi = None
    if chunk > 0:
        per_x, _, unit = struct.unpack(">IIB", png[chunk + 4:chunk + 13])
        dpi = per_x * 0.0254 if unit == 1 else None
    return width, height, dpi


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_figures_are_shown_at_full_size(path):
    """A figure wider than the column (690 px) is scaled down and its labels shrink
    with it: a 10 pt tick label of a 1,000 px figure is shown at 7 pt. Stored
    figures are at most 690 px wide and rendered at 100 dpi (matplotlib's inline
    default, so that a font's size in pt is what the reader sees)."""
    for index, cell in enumerate(load(path)["cells"]):
        for output in cell.get("outputs", []):
            if "image/png" not in output.get("data", {}):
                continue
            width, _, dpi = _png_size_and_dpi(output["data"]["image/png"])
            assert width <= BOOK_COLUMN_PX, (
                f"{path.name} cell {index}: a figure {width} px wide is shown at "
                f"{BOOK_COLUMN_PX / width:.0%}; make it at most {BOOK_COLUMN_PX / 100:.1f} in wide "
                "(fewer panels per row) so that its labels keep their size")
            assert dpi is None or dpi >= 99, f"{path.name} cell {index}: a figure at {dpi:.0f} dpi"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_figure_fonts_are_at_least_9pt(path):
    """No text in a figure is set below 9 pt (with figures shown at full size, see
    above, that is the size the reader sees). Matplotlib's defaults are 10 pt
    (labels, ticks, legends) and 12 pt (titles). A scan of the code: sizes given as
    numbers or 'small' in fontsize=, labelsize=, title_fontsize= and font rcParams."""
    import re

    size = r"""\s*=\s*(?:(\d+(?:\.\d+)?)\b|["'](xx-small|x-small|small)["'])"""
    small = re.compile(r"""\b(?:fontsize|labelsize|title_fontsize)""" + size
                       + r"""|rcParams\[["'](?:font\.size|[\w.]*(?:labelsize|fontsize|titlesize))["']\]""" + size)
    for index, cell in enumerate(load(path)["cells"]):
        if cell["cell_type"] != "code":
            continue
        for line in "".join(cell["source"]).splitlines():
            for match in small.finditer(line):
                points = match.group(1) or match.group(3)
                assert points is not None and float(points) >= 9, (
                    f"{path.name} cell {index}: a font below 9 pt: {line.strip()}")


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_no_comments_behind_closing_brackets(path):
    """``)  # why`` reads as a comment about a bracket: a comment that does not fit behind
    its statement goes above it (tools/authoring/format_notebooks.py moves it there)."""
    import re

    dangling = re.compile(r"^\s*[)\]}]+[,;]?\s+#")
    found = [(index, line.strip()[:60]) for index, cell in enumerate(load(path)["cells"])
             if cell["cell_type"] == "code"
             for line in "".join(cell["source"]).splitlines() if dangling.match(line)]
    assert not found, (f"{path.name}: {len(found)} comments behind closing brackets (run "
                       f"tools/authoring/format_notebooks.py): {found[:3]}")


# ---------------------------------------------------------------- what a graded test may read
def _trusted_names_problems(path: Path) -> list[str]:
    """Names a graded test cell reads that the grader kernel does not have.

    The grader kernel (``tools/grading/bridge/``) runs only read-only cells (locked, not
    solution: given, check and test cells) and imports from the student's kernel only the
    names answer cells declare (``metadata.robokin.declare``). So a graded test may read
    only names declared by an earlier answer cell, names defined by an earlier locked
    non-solution cell, and builtins; anything else (an import in a *Try it yourself* cell,
    a function defined there) would be taken from the student's kernel, where the
    student can change it.
    """
    import builtins

    from tools.notebook_analysis import defined_names, free_names

    declared: set[str] = set()
    read_only: set[str] = set()
    problems = []
    for index, cell in enumerate(load(path)["cells"]):
        if cell["cell_type"] != "code":
            continue
        meta = cell.get("metadata", {})
        nbgrader = meta.get("nbgrader") or {}
        code = "".join(cell["source"])
        if nbgrader.get("grade") and nbgrader.get("locked") and not nbgrader.get("solution"):
            missing = free_names(code) - declared - read_only - set(dir(builtins))
            if missing:
                problems.append(f"cell {index} ({nbgrader.get('grade_id')}) reads {sorted(missing)}")
        if nbgrader.get("solution"):
            declared |= set((meta.get("robokin") or {}).get("declare", []))
        elif nbgrader.get("locked"):
            read_only |= set(defined_names(code))
    return problems


@pytest.mark.parametrize("path", EXERCISES, ids=lambda p: p.stem)
def test_graded_tests_read_only_declared_answers_and_read_only_cells(path):
    """A graded test's free names are declared answers of earlier answer cells, names
    defined by earlier read-only cells (locked, not solution), or builtins: what the
    grader kernel has. Fix: import in a given cell (or in the test), or make the name an
    answer (define it in the answer cell; tools/authoring/nbgrader_metadata.py then declares it)."""
    problems = _trusted_names_problems(path)
    assert not problems, f"{path.name}: graded tests read names the grader kernel lacks: {problems}"


def test_trusted_names_rule_finds_a_name_from_a_try_cell(tmp_path):
    def code(source, nbgrader=None, robokin=None):
        meta = {}
        if nbgrader is not None:
            meta["nbgrader"] = nbgrader
        if robokin is not None:
            meta["robokin"] = robokin
        return {"cell_type": "code", "metadata": meta, "source": source, "outputs": [], "execution_count": 1}

    cells = [
        code("import numpy as np", {"locked": True, "solution": False, "grade": False}),
        code("total = 1\nhidden = 2", {"locked": False, "solution": True, "grade": False},
             {"declare": ["total"], "role": "answer"}),
        code("from robokin.check import leg"),  # a Try it yourself cell: no nbgrader metadata
        code("assert np.isclose(total, 1) and leg and hidden and len([])",
             {"locked": True, "solution": False, "grade": True, "grade_id": "task1_test1"}),
    ]
    path = tmp_path / "01_x.ipynb"
    path.write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}))
    assert _trusted_names_problems(path) == ["cell 3 (task1_test1) reads ['hidden', 'leg']"]


def test_formatter_gives_a_cell_without_an_id_a_stable_one():
    """tools/authoring/format_notebooks.py gives a cell written without an id (by a script, or an editor of
    format 4.4) a stable id, so that ``make execute`` does not give it a random one after
    tools/authoring/nbgrader_metadata.py named its locked cell by position (the metadata went stale)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("format_notebooks",
                                                  ROOT / "tools" / "authoring" / "format_notebooks.py")
    assert spec is not None and spec.loader is not None
    formatter = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(formatter)
    nb: dict[str, Any] = {"nbformat": 4, "nbformat_minor": 4,
          "cells": [{"cell_type": "markdown", "metadata": {}, "source": "kept", "id": "kept"},
                    {"cell_type": "markdown", "metadata": {}, "source": "new"},
                    {"cell_type": "markdown", "metadata": {}, "source": "new"}]}
    assert formatter.give_cells_ids(nb)
    ids = [cell["id"] for cell in nb["cells"]]
    assert ids[0] == "kept" and len(set(ids)) == 3 and all(re.fullmatch(r"[a-zA-Z0-9_-]{1,64}", i) for i in ids)
    assert nb["nbformat_minor"] == 5
    again = json.loads(json.dumps(nb))
    assert not formatter.give_cells_ids(again) and again == nb
