"""An instructor adds chapters: the scaffold (tools/authoring/new_chapter.py) makes ones that pass the suite.

In a temporary copy of the repository, ``tools/authoring/new_chapter.py`` creates two chapters, one
after the other (the README's example name, ``scara``, and a second one; a name an existing
chapter holds is taken with a suffix, and the numbers are the next free ones: nothing here
names a chapter of the repository). Then the parts of ``make test-all`` that concern a
chapter run on both, untouched: nbval (stored outputs equal a fresh run), the tests of
their check modules, the notebook conventions, the table of contents, the robustness suite's
coverage of their checks, their grading mutations (each graded test rejects the scaffold's
wrong answers), the contracts of
their student edition, nbgrader (student edition, blank = 0, solution = full marks, the
typical mistake diagnosed), the trust suite (correct answers written another way, talkative
answers: full marks) and the tamper suite's delegation check. Every per-chapter registry
those tests read is written by the scaffold or derived from the notebook. They run in ONE
pytest process (:func:`chapter_tests`). The guide, book/authoring.md, names every file the
scaffold wrote or changed, and only ``make`` targets and files that exist.
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
from support import installed

installed.require("nbgrader", "nbgrader is not installed: run `make test` (installs requirements.txt)")

#: the chapters the test makes, in order: (name, title, robot); a taken name gets a suffix
WANTED = (("scara", "The SCARA arm", "a SCARA arm"), ("cable_robot", "A cable robot", "a cable-driven robot"))


def _tracked_files() -> list[str]:
    """The repository's files as the suite sees them: tracked, and new ones git does not ignore."""
    out = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=ROOT,
                         capture_output=True, check=True).stdout
    return [f for f in out.decode().split("\0") if f]


def free_name(wanted: str, taken: list[str]) -> str:
    """``wanted``, or ``wanted_2``, ``wanted_3``, ...: a name no existing chapter contains, so that
    a ``-k`` expression naming it selects the new chapter's tests alone."""
    name, k = wanted, 1
    while any(name in other for other in taken):
        k += 1
        name = f"{wanted}_{k}"
    return name


def _stems(folder: Path) -> set[str]:
    return {p.stem for p in folder.glob("[0-9][0-9]_*.ipynb")}


@pytest.fixture(scope="module")
def new_chapters(tmp_path_factory) -> tuple[Path, list[tuple[str, str]]]:
    """The copy, and ``[(name, notebook stem), ...]`` of the chapters made in it (the files the
    scaffold wrote or changed: :data:`SCAFFOLDED`)."""
    copy = tmp_path_factory.mktemp("repository")
    for name in _tracked_files():
        source = ROOT / name
        if source.is_file():
            target = copy / name
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(source.read_bytes())
    copied = contents(copy)
    env = dict(os.environ, PYTHONPATH=str(copy))
    made: list[tuple[str, str]] = []
    for wanted, title, robot in WANTED:
        taken = [stem.split("_", 1)[1] for stem in _stems(copy / "notebooks")]
        taken += [p.stem for p in (copy / "robokin" / "check").glob("[a-z]*.py")]
        name = free_name(wanted, taken)
        before = _stems(copy / "notebooks")
        proc = subprocess.run([sys.executable, "tools/authoring/new_chapter.py", "--name", name, "--title", title,
                               "--robot", robot, "--topics", "forward kinematics of a planar arm"],
                              cwd=copy, env=env, capture_output=True, text=True, timeout=600)
        assert proc.returncode == 0, proc.stdout + proc.stderr
        new = _stems(copy / "notebooks") - before
        assert len(new) == 1, f"the scaffold made the notebooks {sorted(new)} for {name}"
        made.append((name, new.pop()))
    after = contents(copy)
    SCAFFOLDED[str(copy)] = sorted(name for name in after if copied.get(name) != after[name])
    return copy, made


#: copy -> the files the scaffold wrote or changed in it, read as soon as it ran (the chapter
#: tests run in the copy afterwards and leave files of their own)
SCAFFOLDED: dict[str, list[str]] = {}


def contents(copy: Path) -> dict[str, bytes]:
    """``{file: its bytes}`` of ``copy``, caches left out."""
    return {path.relative_to(copy).as_posix(): path.read_bytes() for path in copy.rglob("*")
            if path.is_file() and "__pycache__" not in path.parts and ".ipynb_checkpoints" not in path.parts}


def test_scaffold_writes_every_place_of_a_chapter(new_chapters):
    copy, made = new_chapters
    numbers = [int(stem[:2]) for _, stem in made]
    existing = [int(stem[:2]) for stem in _stems(ROOT / "notebooks")]
    assert numbers == [max(existing, default=0) + 1, max(existing, default=0) + 2], made
    for (name, stem), number, (_, _, robot) in zip(made, numbers, WANTED):
        nb = copy / "notebooks" / f"{stem}.ipynb"
        assert nb.is_file() and (copy / "robokin" / "check" / f"{name}.py").is_file()
        assert (copy / "tests" / f"test_check_{name}.py").is_file()
        assert f"notebooks/{stem}" in (copy / "_toc.yml").read_text()
        assert f"| {number} | {robot} |" in (copy / "book" / "intro.md").read_text()
        assert f"`notebooks/{stem}.ipynb`" in (copy / "README.md").read_text()
        assert f'"{name}": "robokin.check.{name}"' in (copy / "robokin" / "check" / "_registry.py").read_text()
        assert f"`{stem}`" in (copy / "book" / "for-instructors.md").read_text()   # the points table
        mutations = (copy / "tests" / "grading_mutations" / f"{stem}.py").read_text()
        assert "MUTATIONS = {" in mutations and "VARIANTS = {" in mutations
        assert "DELEGATION = {" in (copy / "robokin" / "check" / f"{name}.py").read_text()
        cells = json.loads(nb.read_text())["cells"]
        assert [c["execution_count"] for c in cells if c["cell_type"] == "code"] == [1, 2, 3, 4, 5, 6, 7]
    name = made[0][0]
    again = subprocess.run([sys.executable, "tools/authoring/new_chapter.py", "--name", name, "--title", "x"],
                           cwd=copy, env=dict(os.environ, PYTHONPATH=str(copy)),
                           capture_output=True, text=True)
    assert again.returncode != 0 and "exists already" in again.stderr


AUTHORING = ROOT / "book" / "authoring.md"


def test_the_guide_names_every_file_the_scaffold_writes(new_chapters):
    """book/authoring.md's table names each file the scaffold wrote or changed, as ``NN_scara`` and
    ``scara`` for the chapter's stem and name (a chapter notebook of the repository whose nbgrader
    metadata the scaffold's metadata run refreshed is not the scaffold's own file)."""
    copy, made = new_chapters
    guide = AUTHORING.read_text(encoding="utf-8")
    stems = {stem for _, stem in made}
    named = set()
    for relative in SCAFFOLDED[str(copy)]:
        if relative.startswith("notebooks/") and Path(relative).stem not in stems:
            continue
        for name, stem in made:
            relative = relative.replace(stem, "NN_scara").replace(name, "scara")
        named.add(relative)
    assert "notebooks/NN_scara.ipynb" in named and "robokin/check/scara.py" in named, sorted(named)
    missing = sorted(relative for relative in named if f"`{relative}`" not in guide)
    assert not missing, f"book/authoring.md does not name these files the scaffold changed: {missing}"


def test_the_guide_names_commands_and_files_that_exist():
    """Every ``make`` target book/authoring.md names is one of the Makefile's, and every file it
    names (without a placeholder: ``NN_``, ``<...>``, ``scara``) is in the repository."""
    guide = AUTHORING.read_text(encoding="utf-8")
    targets = set(re.findall(r"^([a-z][a-z-]*):", (ROOT / "Makefile").read_text(encoding="utf-8"), re.M))
    named_targets = set(re.findall(r"(?:`|^\s*)make ([a-z][a-z-]*)", guide, re.M))   # in code
    assert named_targets and named_targets <= targets, sorted(named_targets - targets)
    paths = set(re.findall(r"((?:book|notebooks|robokin|tests|tools)/[\w./<>-]+\.(?:py|md|ipynb|bib))", guide))
    concrete = {path for path in paths if not re.search(r"NN_|<|scara", path)}
    assert concrete, "no file named in book/authoring.md"
    absent = sorted(path for path in concrete if not (ROOT / path).is_file())
    assert not absent, f"book/authoring.md names files that do not exist: {absent}"


def test_free_name_avoids_every_existing_chapter():
    assert free_name("scara", ["leg", "ur10"]) == "scara"
    assert free_name("scara", ["scara"]) == "scara_2"
    assert free_name("scara", ["scara", "scara_2"]) == "scara_3"


def chapter_tests(made: list[tuple[str, str]]) -> dict[str, str | None]:
    """What runs in the copy, per file (or test): the pytest ``-k`` expression of its tests
    there (None: all of them). One pytest process runs them all (``-k`` of the union, each
    part restricted to its own file); ``ROBOKIN_NBGRADER_NOTEBOOKS`` (read by the grading
    and contract tests) names a folder holding the new chapters alone."""
    names = " or ".join(name for name, _ in made)
    return {
        **{f"notebooks/{stem}.ipynb": None for _, stem in made},   # nbval: stored outputs equal a fresh run
        **{f"tests/test_check_{name}.py": None for name, _ in made},   # the tests of the check module
        "tests/test_notebook_conventions.py": f"{names} or solution or set or there_are",
        "tests/test_check_solutions.py": None,
        "tests/test_book.py::test_every_notebook_is_in_the_toc": None,
        "tests/test_robustness_fuzz.py": f"{names} or every_public_entry_point",
        "tests/test_grading_mutations.py": names,
        "tests/test_student_edition_contracts.py": names,
        "tests/test_grading_tamper.py": f"delegation_is_flagged and ({names})",
        "tests/test_grading_trust.py": names,
        # the metadata checks read the copy's chapters; the grading of a chapter without metadata
        # (test_chapter_without_metadata_is_reported_by_name, its own nbgrader job, about 4.5 CPU-s)
        # tests the runner, not a chapter: the suite runs it in the repository already
        NBGRADER_PART: f"{names} or metadata_is_up_to_date or metadata_script",
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
def chapter_suite(new_chapters, tmp_path_factory) -> dict[str, dict[str, str]]:
    """Run the chapters' part of the suite in the copy, in one pytest process.

    Returns ``{selection: {node id: outcome}}`` (``PASSED``, ``FAILED``, ``ERROR``,
    ``SKIPPED``, ...: pytest's ``-rA`` summary) and, under ``"log"``, the end of its output.
    """
    copy, made = new_chapters
    selections = chapter_tests(made)
    only = tmp_path_factory.mktemp("new_chapters_alone") / "notebooks"
    only.mkdir()
    for _, stem in made:
        (only / f"{stem}.ipynb").write_bytes((copy / "notebooks" / f"{stem}.ipynb").read_bytes())
    environ = dict(os.environ, PYTHONPATH=str(copy), ROBOKIN_NBGRADER_NOTEBOOKS=str(only))
    files = list(dict.fromkeys(selection.split("::", 1)[0] for selection in selections))
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-rA", "--color=no", "-p", "no:cacheprovider",
                           *files, "-k", selection_expression(selections)],
                          cwd=copy, env=environ, capture_output=True, text=True, timeout=2400)
    log = proc.stdout[-4000:] + proc.stderr[-2000:]
    assert proc.returncode in (0, 1), f"pytest could not run the chapters' tests (exit {proc.returncode}):\n{log}"
    outcomes: dict[str, dict[str, str]] = {selection: {} for selection in selections}
    for line in proc.stdout.splitlines():
        match = SUMMARY_LINE.match(line) or SKIPPED_LINE.match(line)
        if match is None:
            continue
        outcome, node, detail = match.groups()
        owner = next((s for s in selections if node == s or node.startswith((s + "::", s + "["))), None)
        if owner is None:   # a skipped test's line names its file (and line), so does a collection error
            owner = next((s for s in selections if s.split("::", 1)[0] == node), None)
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


def test_new_chapters_pass_the_chapter_tests(chapter_suite):
    log = chapter_suite["log"][""]
    for selection in chapter_suite:
        if selection in (NBGRADER_PART, "log"):
            continue
        outcomes = chapter_suite[selection]
        assert outcomes, f"no test of {selection} ran on the new chapters:\n{log}"
        problems = _problems(outcomes)
        assert not problems, f"{selection} on the new chapters:\n" + "\n".join(problems) + f"\n{log}"


def test_new_chapters_are_graded_by_nbgrader(chapter_suite):
    outcomes = chapter_suite[NBGRADER_PART]
    log = chapter_suite["log"][""]
    assert any(outcome.startswith("PASSED") for outcome in outcomes.values()), f"no nbgrader test passed:\n{log}"
    problems = _problems(outcomes)
    assert not problems, "nbgrader on the new chapters:\n" + "\n".join(problems) + f"\n{log}"
