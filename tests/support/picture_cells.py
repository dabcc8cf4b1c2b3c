"""Skip, under nbval, the pictures that neither show a compared output nor feed a later cell.

A pytest plugin for the notebooks' runs under another OpenBLAS kernel
(``tests/test_notebooks_other_machines.py`` passes ``-p tests.support.picture_cells``);
the main nbval run and the perturbed machine execute every cell. A cell is skipped when

* it is a picture or a 3D scene (tagged ``nbval-ignore-output``, CONTRIBUTING.md's
  "Tests"): nbval compares none of its output;
* it binds no name a later cell of the notebook reads (``tools.notebook_analysis``, the
  rule by which the grader skips pictures); and
* it checks nothing itself: no ``assert``, no ``raise``, no name of ``robokin.check``
  (``your_answers`` aside: it checks nothing, it turns an error into a printed note).

Every cell whose output nbval compares still runs in every environment, after every cell it
could read from. A picture that changed an object a later cell reads (a mutation, not a
name) would make that later cell's output differ from the stored one there: a failure, not a
silent pass.
"""

from __future__ import annotations

import ast

import pytest

from tools.notebook_analysis import defined_names, free_names

#: nbval's tag for a cell whose output it does not compare (pictures and scenes only).
PICTURE_TAG = "nbval-ignore-output"
#: The one module of ``robokin.check`` that checks nothing: its ``your_answers`` block catches what the
#: student's unfinished answer raises in a read-only cell and prints a note instead (so an error in a
#: picture drawn in that block fails no run, skipped or not).
NOT_A_CHECK = "robokin.check.unfinished"
#: The reason pytest reports for a skipped cell.
REASON = "a picture in another numerical environment: nbval compares none of its output and no later cell reads it"


def _parsed(code: str) -> ast.Module | None:
    """The cell's code as Python (IPython magics and shell escapes left out), None if it is not Python."""
    lines = ["" if line.lstrip().startswith(("%", "!")) else line for line in code.splitlines()]
    try:
        return ast.parse("\n".join(lines))
    except SyntaxError:
        return None


def _check_names(sources: list[str]) -> set[str]:
    """Every name under which a cell of the notebook imports ``robokin.check`` or one of its modules."""
    names: set[str] = set()
    for code in sources:
        tree = _parsed(code)
        for node in ast.walk(tree) if tree is not None else ():
            module = (node.module or "") if isinstance(node, ast.ImportFrom) else ""
            if isinstance(node, ast.ImportFrom) and module.startswith("robokin"):
                if module == "robokin":
                    names.update(alias.asname or alias.name for alias in node.names if alias.name == "check")
                elif module.startswith("robokin.check") and module != NOT_A_CHECK:
                    names.update(alias.asname or alias.name for alias in node.names)
            elif isinstance(node, ast.Import):
                names.update(alias.asname for alias in node.names
                             if alias.asname is not None and alias.name.startswith("robokin.check"))
    return names


def _checks_something(code: str, check_names: set[str]) -> bool:
    """Whether the cell asserts, raises or calls ``robokin.check`` (or is not plain Python: kept then)."""
    tree = _parsed(code)
    if tree is None:
        return True
    if any(isinstance(node, (ast.Assert, ast.Raise)) for node in ast.walk(tree)):
        return True
    return bool(free_names(code) & check_names) or "robokin.check" in code


def skipped_cells(cells: list[dict]) -> set[int]:
    """Indices (among the code cells, as nbval numbers them) of the cells this plugin skips."""
    code_cells = [cell for cell in cells if cell.get("cell_type") == "code"]
    sources = ["".join(cell["source"]) if isinstance(cell["source"], list) else cell["source"]
               for cell in code_cells]
    check_names = _check_names(sources)
    skipped = set()
    for index, (cell, code) in enumerate(zip(code_cells, sources)):
        if PICTURE_TAG not in cell.get("metadata", {}).get("tags", []):
            continue
        read_later = set().union(*(free_names(later) for later in sources[index + 1:]))
        if set(defined_names(code)) & read_later or _checks_something(code, check_names):
            continue
        skipped.add(index)
    return skipped


def pytest_collection_modifyitems(items) -> None:
    """Mark nbval's items of the skipped cells with ``skip`` (they start no kernel of their own)."""
    by_notebook: dict[int, set[int]] = {}
    for item in items:
        notebook = getattr(item.parent, "nb", None)
        if notebook is None or not hasattr(item, "cell_num"):
            continue
        key = id(notebook)
        if key not in by_notebook:
            by_notebook[key] = skipped_cells(notebook.cells)
        if item.cell_num in by_notebook[key]:
            item.add_marker(pytest.mark.skip(reason=REASON))
