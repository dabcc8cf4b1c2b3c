"""The code habits of pyproject.toml's [tool.ruff] hold for the whole tree (``ruff check``)."""

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
