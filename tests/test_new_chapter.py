"""An instructor adds a chapter: the scaffold (tools/new_chapter.py) makes one that passes the suite.

In a temporary copy of the repository: ``tools/new_chapter.py`` creates chapter
``scara``; then the parts of ``make test`` that concern a chapter run on it there:
nbval (stored outputs equal a fresh run), the notebook conventions, the table of
contents, the robustness suite's coverage of its new check, the contracts of its
student edition, and nbgrader (student edition, blank = 0, solution = full marks,
the typical mistake diagnosed).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

pytest.importorskip("nbgrader", reason="nbgrader is not installed: run `make test` (installs requirements.txt)")


def _tracked_files() -> list[str]:
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    return [f for f in out.decode().split("\0") if f]


@pytest.fixture(scope="module")
def new_chapter(tmp_path_factory) -> Path:
    copy = tmp_path_factory.mktemp("repository")
    for name in _tracked_files():
        source = ROOT / name
        if source.is_file():
            target = copy / name
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(source.read_bytes())
    env = dict(os.environ, PYTHONPATH=str(copy))
    proc = subprocess.run([sys.executable, "tools/new_chapter.py", "--name", "scara", "--title", "The SCARA arm",
                           "--robot", "a SCARA arm", "--topics", "forward kinematics from a DH table"],
                          cwd=copy, env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return copy


def _pytest(copy: Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    environ = dict(os.environ, PYTHONPATH=str(copy), **(env or {}))
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *args], cwd=copy,
                          env=environ, capture_output=True, text=True, timeout=900)


def test_scaffold_writes_every_place_of_a_chapter(new_chapter):
    nb = new_chapter / "notebooks" / "07_scara.ipynb"
    assert nb.is_file() and (new_chapter / "robokin" / "check" / "scara.py").is_file()
    assert "notebooks/07_scara" in (new_chapter / "_toc.yml").read_text()
    assert "| 7 | a SCARA arm |" in (new_chapter / "book" / "intro.md").read_text()
    assert "`notebooks/07_scara.ipynb`" in (new_chapter / "README.md").read_text()
    assert '"scara": "robokin.check.scara"' in (new_chapter / "robokin" / "check" / "_registry.py").read_text()
    assert (new_chapter / "tests" / "grading_mutations" / "07_scara.py").is_file()
    cells = json.loads(nb.read_text())["cells"]
    assert [c["execution_count"] for c in cells if c["cell_type"] == "code"] == [1, 2, 3, 4, 5, 6, 7]
    again = subprocess.run([sys.executable, "tools/new_chapter.py", "--name", "scara", "--title", "x"],
                           cwd=new_chapter, env=dict(os.environ, PYTHONPATH=str(new_chapter)),
                           capture_output=True, text=True)
    assert again.returncode != 0 and "exists already" in again.stderr


def test_new_chapter_passes_the_chapter_tests(new_chapter):
    proc = _pytest(new_chapter, "notebooks/07_scara.ipynb", "tests/test_notebook_conventions.py",
                   "tests/test_check_solutions.py", "-k", "scara or solution or set or there_are",
                   "tests/test_book.py::test_every_notebook_is_in_the_toc")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-2000:]
    proc = _pytest(new_chapter, "tests/test_robustness_fuzz.py", "-k", "scara or every_public_entry_point")
    assert proc.returncode == 0, proc.stdout[-3000:]


def test_new_chapter_is_graded_by_nbgrader(new_chapter, tmp_path):
    only = tmp_path / "notebooks"
    only.mkdir()
    (only / "07_scara.ipynb").write_bytes((new_chapter / "notebooks" / "07_scara.ipynb").read_bytes())
    proc = _pytest(new_chapter, "tests/test_nbgrader.py", "-k", "scara or metadata",
                   env={"ROBOKIN_NBGRADER_NOTEBOOKS": str(only)})
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert " passed" in proc.stdout and " failed" not in proc.stdout
