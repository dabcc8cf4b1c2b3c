"""The code habits of pyproject.toml hold for the whole tree: [tool.ruff] (``ruff check``), [tool.mypy] (``mypy``)."""

from __future__ import annotations

import subprocess
import sys

import pytest

from conftest import ROOT


def test_ruff_finds_nothing():
    pytest.importorskip("ruff", reason="ruff is not installed: run `make test` (installs requirements.txt)")
    proc = subprocess.run([sys.executable, "-m", "ruff", "check", "--output-format", "concise", "."], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, (
        f"ruff check (pyproject.toml [tool.ruff]) finds problems; `.venv/bin/python -m ruff check --fix .` fixes "
        f"some:\n{proc.stdout[-4000:]}{proc.stderr[-1000:]}")


def test_mypy_finds_nothing():
    """``python -m mypy`` (pyproject.toml [tool.mypy]: robokin, tools and tests, numpy's own types) reports no
    error, and neither does ``python -m mypy conftest.py``: the repository's conftest.py is a second module
    named ``conftest`` beside tests/conftest.py, which one mypy run cannot hold (pyproject.toml says more).

    mypy keeps its cache in ``.mypy_cache``: the first run takes about 38 s of CPU on the 2-core machine
    (robokin and tools alone about 26 s), later runs under 1 s; the conftest.py run, one after the other
    so that it reads that cache, about 1 s.
    """
    pytest.importorskip("mypy", reason="mypy is not installed: run `make test` (installs requirements.txt)")
    for files in ([], ["conftest.py"]):
        proc = subprocess.run([sys.executable, "-m", "mypy", "--no-color-output", "--no-error-summary", *files],
                              cwd=ROOT, capture_output=True, text=True, timeout=600)
        command = " ".join([".venv/bin/python -m mypy", *files])
        assert proc.returncode == 0, (
            f"mypy (pyproject.toml [tool.mypy]) finds type errors; run `{command}` to see them, and fix the code "
            f"or its annotations (a `# type: ignore[code]` only with a reason):\n"
            f"{proc.stdout[-4000:]}{proc.stderr[-1000:]}")
