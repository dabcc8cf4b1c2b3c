"""An instructor adds a chapter: the scaffold (tools/new_chapter.py) makes one that passes the suite.

In a temporary copy of the repository: ``tools/new_chapter.py`` creates chapter
``scara``; then the parts of ``make test`` that concern a chapter run on it there:
nbval (stored outputs equal a fresh run), the notebook conventions, the table of
contents, the robustness suite's coverage of its new check, its grading mutations
(the graded test rejects the scaffold's wrong answer), the contracts of its
student edition, and nbgrader (student edition, blank = 0, solution = full marks,
the typical mistake diagnosed). They run in ONE pytest process (``CHAPTER_TESTS``).
"""

from __future__ import annotations

import json
import os
import re
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


#: What runs in the copy, per file (or test): the pytest ``-k`` expression of its tests
#: there (None: all of them). One pytest process runs them all (``-k`` of the union,
#: each part restricted to its own file); ``ROBOKIN_NBGRADER_NOTEBOOKS`` (read by the
#: nbgrader and mutation tests only) names a folder holding the new chapter alone.
CHAPTER_TESTS = {
    "notebooks/07_scara.ipynb": None,   # nbval: stored outputs equal a fresh run
    "tests/test_notebook_conventions.py": "scara or solution or set or there_are",
    "tests/test_check_solutions.py": None,
    "tests/test_book.py::test_every_notebook_is_in_the_toc": None,
    "tests/test_robustness_fuzz.py": "scara or every_public_entry_point",
    "tests/test_grading_mutations.py": "scara",
    "tests/test_nbgrader.py": "scara or metadata",
}
NBGRADER_PART = "tests/test_nbgrader.py"


def _keyword(selection: str) -> str:
    """The ``-k`` term that keeps a test of ``selection`` (a file, a file's test) and no other."""
    return selection.rsplit("::", 1)[1] if "::" in selection else selection.rsplit("/", 1)[1]


def selection_expression(selections: dict[str, str | None]) -> str:
    """One ``-k`` expression: per file, the tests its own expression selects."""
    terms = [_keyword(selection) if expression is None else f"({_keyword(selection)} and ({expression}))"
             for selection, expression in selections.items()]
    return " or ".join(terms)


@pytest.fixture(scope="module")
def chapter_suite(new_chapter, tmp_path_factory) -> dict[str, dict[str, str]]:
    """Run the chapter's part of the suite in the copy, in one pytest process.

    Returns ``{selection: {node id: outcome}}`` (``PASSED``, ``FAILED``, ``ERROR``,
    ``SKIPPED``, ...: pytest's ``-rA`` summary) and, under ``"log"``, the end of its output.
    """
    only = tmp_path_factory.mktemp("new_chapter_alone") / "notebooks"
    only.mkdir()
    (only / "07_scara.ipynb").write_bytes((new_chapter / "notebooks" / "07_scara.ipynb").read_bytes())
    environ = dict(os.environ, PYTHONPATH=str(new_chapter), ROBOKIN_NBGRADER_NOTEBOOKS=str(only))
    files = list(dict.fromkeys(selection.split("::", 1)[0] for selection in CHAPTER_TESTS))
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-rA", "--color=no", "-p", "no:cacheprovider",
                           *files, "-k", selection_expression(CHAPTER_TESTS)],
                          cwd=new_chapter, env=environ, capture_output=True, text=True, timeout=1800)
    log = proc.stdout[-4000:] + proc.stderr[-2000:]
    assert proc.returncode in (0, 1), f"pytest could not run the chapter's tests (exit {proc.returncode}):\n{log}"
    outcomes: dict[str, dict[str, str]] = {selection: {} for selection in CHAPTER_TESTS}
    for line in proc.stdout.splitlines():
        match = SUMMARY_LINE.match(line) or SKIPPED_LINE.match(line)
        if match is None:
            continue
        outcome, node, detail = match.groups()
        owner = next((s for s in CHAPTER_TESTS if node == s or node.startswith((s + "::", s + "["))), None)
        if owner is None:   # a skipped test's line names its file (and line), so does a collection error
            owner = next((s for s in CHAPTER_TESTS if s.split("::", 1)[0] == node), None)
            node = line
        if owner is None and outcome == "SKIPPED":   # skipped where a shared fixture decided (conftest.py)
            continue
        assert owner is not None, f"a test ran that no selection asked for: {node}\n{log}"
        if not _problems({node: outcomes[owner].get(node, "")}):   # a failure stays: PASSED, then ERROR
            outcomes[owner][node] = f"{outcome} {detail or ''}".strip()
    assert any(outcomes.values()), f"no test result in the output:\n{log}"
    assert proc.returncode == 0 or any(_problems(found) for found in outcomes.values()), (
        f"pytest failed (exit {proc.returncode}) but no failed test was read from its summary:\n{log}")
    outcomes["log"] = {"": log}
    return outcomes


#: A line of pytest's ``-rA`` summary: outcome, node id (a collection error: the file), message.
SUMMARY_LINE = re.compile(r"^(PASSED|FAILED|ERROR|XFAIL|XPASS) (.+?)(?: - (.*))?$")
#: ``SKIPPED [count] file:line: reason``.
SKIPPED_LINE = re.compile(r"^(SKIPPED) \[\d+\] ([^:]+):\d+: (.*)$")


def _problems(outcomes: dict[str, str]) -> list[str]:
    return [f"{node}: {outcome[:500]}" for node, outcome in outcomes.items()
            if outcome.startswith(("FAILED", "ERROR"))]


def test_new_chapter_passes_the_chapter_tests(chapter_suite):
    log = chapter_suite["log"][""]
    for selection in CHAPTER_TESTS:
        if selection == NBGRADER_PART:
            continue
        outcomes = chapter_suite[selection]
        assert outcomes, f"no test of {selection} ran on the new chapter:\n{log}"
        problems = _problems(outcomes)
        assert not problems, f"{selection} on the new chapter:\n" + "\n".join(problems) + f"\n{log}"


def test_new_chapter_is_graded_by_nbgrader(chapter_suite):
    outcomes = chapter_suite[NBGRADER_PART]
    log = chapter_suite["log"][""]
    assert any(outcome.startswith("PASSED") for outcome in outcomes.values()), f"no nbgrader test passed:\n{log}"
    problems = _problems(outcomes)
    assert not problems, "nbgrader on the new chapter:\n" + "\n".join(problems) + f"\n{log}"
