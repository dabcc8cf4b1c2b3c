#!/usr/bin/env python3
"""Write the first code cell of every notebook: install robokin where it is missing.

    .venv/bin/python tools/install_cell.py           # write (idempotent)

Colab's launch button opens a notebook without the rest of the repository, so the
notebook has to install robokin itself. The cell does that only when robokin is not
importable: in the repository's environment (``make lab``, Binder, a JupyterHub
with ``requirements.txt``) it does nothing. It is tagged ``remove-cell``: the book
does not show it. The repository URL comes from ``_config.yml`` (``repository.url``,
the one place it is written): after the repository moves, change it there, run this
script and ``make execute``; ``tests/test_notebook_conventions.py`` fails until then.
"""

from __future__ import annotations

import sys
from pathlib import Path

import yaml

sys.path.insert(0, str(Path(__file__).resolve().parent))

from notebook_analysis import dump_notebook, load_notebook  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
MARK = 'importlib.util.find_spec("robokin")'
TEMPLATE = '''# Colab, or any Python without robokin: install it first (in the repository's
# environment robokin is installed, and this cell does nothing).
import importlib.util
import subprocess
import sys

if importlib.util.find_spec("robokin") is None:
    subprocess.run([sys.executable, "-m", "pip", "install", "--quiet",
                    "robokin[views] @ git+{url}"], check=True)'''


def install_code(root: Path = ROOT) -> str:
    url = yaml.safe_load((root / "_config.yml").read_text())["repository"]["url"]
    return TEMPLATE.format(url=url)


def write(path: Path, code: str) -> bool:
    """Put the install cell before the first code cell (or update it); True if changed."""
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
    cell["source"] = code.splitlines(keepends=True)
    path.write_text(dump_notebook(nb), encoding="utf-8")
    return True


def main() -> int:
    code = install_code()
    for path in sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")):
        if write(path, code):
            print(f"install cell written: {path.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
