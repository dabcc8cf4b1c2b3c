#!/usr/bin/env python3
"""Write the first code cell of every notebook: install robokin where it is missing.

    .venv/bin/python tools/authoring/install_cell.py                     # every chapter (idempotent)
    .venv/bin/python tools/authoring/install_cell.py notebooks/07_x.ipynb # one notebook
    .venv/bin/python tools/authoring/install_cell.py --check              # exit 1 if a cell is missing or stale

Run it before ``tools/authoring/format_notebooks.py`` and ``tools/authoring/nbgrader_metadata.py`` (it
writes the cell already formatted; the metadata script then gives it its nbgrader
metadata).

Colab's launch button opens a notebook without the rest of the repository, so the
notebook has to install robokin itself. The cell does that only when robokin is not
importable: in the repository's environment (``make lab``, Binder, a JupyterHub
with ``requirements.txt``) it does nothing. It is tagged ``remove-cell``: the book
does not show it. The repository URL comes from ``_config.yml`` (``repository.url``,
the one place it is written): after the repository moves, change it there, run this
script and ``make execute``; ``tests/test_notebook_conventions.py`` fails until then.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import yaml

from tools.notebook_analysis import dump_notebook, load_notebook

ROOT = Path(__file__).resolve().parents[2]
MARK = 'importlib.util.find_spec("robokin")'
TEMPLATE = '''# Colab, or any Python without robokin: install it first (in the repository's
# environment robokin is installed, and this cell does nothing).
import importlib.util
import subprocess
import sys

if importlib.util.find_spec("robokin") is None:
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "--quiet",
            "robokin[{extras}] @ git+{url}",
        ],
        check=True,
    )'''  # as tools/authoring/format_notebooks.py (black) writes it


# The extras a notebook needs beyond robokin[views] (pyproject.toml's optional dependencies), by
# notebook stem: Colab has numpy, scipy, sympy and matplotlib, not the URDF parser and the robots.
EXTRAS = {"00_your_robot": "views,robots"}


def extras_for(path: Path) -> str:
    """The extras of robokin that the notebook at ``path`` installs: ``"views"`` unless EXTRAS names more."""
    return EXTRAS.get(Path(path).stem, "views")


def install_code(root: Path = ROOT, extras: str = "views") -> str:
    url = yaml.safe_load((root / "_config.yml").read_text())["repository"]["url"]
    return TEMPLATE.format(url=url, extras=extras)


def write(path: Path, code: str, dry_run: bool = False) -> bool:
    """Put the install cell before the first code cell (or update it); True if changed
    (with ``dry_run``: True if it would change, and nothing is written)."""
    nb = load_notebook(path)
    cells = nb["cells"]
    cell = next((c for c in cells if c["cell_type"] == "code" and MARK in "".join(c["source"])), None)
    if cell is None:
        cell = {"cell_type": "code", "execution_count": None, "id": "install-robokin",
                "metadata": {"tags": ["remove-cell"]}, "outputs": [], "source": []}
        if cells and "id" not in cells[0]:
            del cell["id"]
        cells.insert(next(i for i, c in enumerate(cells) if c["cell_type"] == "code"), cell)
    elif "".join(cell["source"]) == code:
        return False
    if dry_run:
        return True
    cell["source"] = code.splitlines(keepends=True)
    path.write_text(dump_notebook(nb), encoding="utf-8")
    return True


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("notebooks", nargs="*", type=Path,
                        help="notebooks to write (default: every notebooks/NN_*.ipynb)")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 naming stale notebooks")
    args = parser.parse_args(argv)
    paths = args.notebooks or sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
    stale = []
    for path in paths:
        if not path.is_file():
            parser.error(f"{path}: no such notebook")
        if write(path, install_code(extras=extras_for(path)), dry_run=args.check):
            stale.append(path)
            if not args.check:
                print(f"install cell written: {path}")
    if args.check and stale:
        print("STALE install cell (run tools/authoring/install_cell.py, then tools/authoring/format_notebooks.py and "
              "tools/authoring/nbgrader_metadata.py): " + ", ".join(map(str, stale)), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
