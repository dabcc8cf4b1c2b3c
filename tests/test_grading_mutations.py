"""Every graded test catches the mistakes it is there for (mutation testing of the tests).

Per chapter, ``tests/grading_mutations/<notebook stem>.py`` defines::

    MUTATIONS = {
        "task2_test1": [
            ("W used where W^-1 belongs", "def weighted_pinv(J, W):\\n    return ..."),
            ...
        ],
        ...
    }

keyed by the nbgrader ``grade_id`` of a test cell (``tools/authoring/nbgrader_metadata.py --list``
shows them). The chapter's instructor notebook runs from the top to its last graded test in ONE kernel
(``ROBOKIN_VIEWER=static``, working directory ``notebooks/``; with three chapters or more, forked
from a warm server, as nbval's kernels are: :func:`kernel_manager`), without the cells the grader
kernel leaves out (:func:`cells_not_run`: what follows the last test, and the pictures no later
cell that runs reads; nbval runs them all and compares their outputs, in both tiers); just
before the test cell of a ``grade_id``, for each mutation:

1. the names the mutation binds at top level (assignments, ``def``, ``import``) are
   saved in the kernel (or noted as absent);
2. the mutation's code runs, then the test cell: it **must raise** -- a test that
   passes a wrong answer gives points for it;
3. the saved names are restored.

Then the test cell runs as written (it must pass) and the notebook goes on. The
test also fails when a graded test has no mutation, when a mutation names a
``grade_id`` that is not a graded test, and when a chapter has no mutation file.

``ROBOKIN_NBGRADER_NOTEBOOKS=<folder>`` runs the notebooks of another folder and
``ROBOKIN_GRADING_MUTATIONS=<folder>`` reads the mutation files from another folder.
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
from pathlib import Path

import pytest

from conftest import ROOT
from support import forked_kernels
from tools.grading.bridge.pictures import skip_pictures
from tools.kernel_sockets import AsyncPrivateSocketsKernelManager
from tools.authoring.nbgrader_metadata import chapter_notebooks
from tools.notebook_analysis import defined_names

NOTEBOOKS = Path(os.environ.get("ROBOKIN_NBGRADER_NOTEBOOKS", ROOT / "notebooks")).resolve()
MUTATIONS_DIR = Path(os.environ.get("ROBOKIN_GRADING_MUTATIONS", ROOT / "tests" / "grading_mutations")).resolve()
CHAPTERS = chapter_notebooks(NOTEBOOKS.parent, NOTEBOOKS.name)
CELL_TIMEOUT = 300  # seconds, as `make execute`
SAVED = "_robokin_mutation_saved"
ABSENT = "_robokin_mutation_absent"


def load_mutations(chapter: str) -> dict[str, list[tuple[str, str]]]:
    path = MUTATIONS_DIR / f"{chapter}.py"
    if not path.is_file():
        pytest.fail(
            f"{chapter}: no mutation file {path.relative_to(ROOT) if path.is_relative_to(ROOT) else path}. "
            f"Write it: MUTATIONS = {{grade_id: [(description, code), ...]}} with at least one wrong "
            "answer per graded test (grade ids: "
            f"`tools/authoring/nbgrader_metadata.py --list notebooks/{chapter}.ipynb`)."
        )
    spec = importlib.util.spec_from_file_location(f"grading_mutations_{chapter}", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    mutations = getattr(module, "MUTATIONS", None)
    if not isinstance(mutations, dict):
        pytest.fail(f"{chapter}: {path} defines no dict MUTATIONS = {{grade_id: [(description, code), ...]}}")
    for grade_id, items in mutations.items():
        for item in items:
            if not (isinstance(item, tuple) and len(item) == 2 and all(isinstance(x, str) for x in item)):
                pytest.fail(f"{chapter}: MUTATIONS[{grade_id!r}] holds {item!r}; expected (description, code)")
    return mutations


def graded_tests(nb: dict) -> dict[str, int]:
    """``{grade_id: cell index}`` of the autograded test cells."""
    out = {}
    for index, cell in enumerate(nb["cells"]):
        meta = cell.get("metadata", {}).get("nbgrader", {})
        if cell["cell_type"] == "code" and meta.get("grade"):
            out[meta["grade_id"]] = index
    return out


def cells_not_run(nb: dict) -> set[int]:
    """Indices of the cells the mutation run leaves out, by the grader's own rule
    (``tools.grading.bridge.pictures.skip_pictures``), applied to every code cell of the
    instructor's notebook: the cells after the last graded test (nothing is graded there;
    nbval runs them and compares their outputs, in both tiers), and the pictures and 3D scenes
    that define nothing a later cell that runs reads (the grader kernel does not run them either)."""
    indices = [index for index, cell in enumerate(nb["cells"]) if cell["cell_type"] == "code"]
    cells = [{"grade_id": str(index), "source": _source(nb["cells"][index]),
              "test": bool(nb["cells"][index].get("metadata", {}).get("nbgrader", {}).get("grade"))}
             for index in indices]
    tags = {str(index): nb["cells"][index].get("metadata", {}).get("tags", []) for index in indices}
    skip_pictures(cells, tags)
    return {index for index, item in zip(indices, cells) if item.get("skip")}


def coverage_problems(chapter: str, tests: dict[str, int], mutations: dict) -> list[str]:
    problems = [
        f"{chapter}: MUTATIONS names {grade_id!r}, which is not a graded test of the notebook "
        f"(graded tests: {', '.join(tests)})"
        for grade_id in mutations if grade_id not in tests
    ]
    problems += [
        f"{chapter}: the graded test {grade_id} (cell {index}) has no mutation: add "
        f"MUTATIONS[{grade_id!r}] = [(description, code of a wrong answer that the test must reject)]"
        for grade_id, index in tests.items() if not mutations.get(grade_id)
    ]
    return problems


def _source(cell: dict) -> str:
    s = cell.get("source", "")
    return "".join(s) if isinstance(s, list) else s


def _error_text(exc: Exception) -> str:
    text = re.sub(r"\x1b\[[0-9;]*[A-Za-z]", "", str(exc)).strip().splitlines()
    return text[-1] if text else type(exc).__name__


def run_with_mutations(chapter: str, nb: dict, mutations: dict,
                       manager: type = AsyncPrivateSocketsKernelManager) -> list[str]:
    """Run the notebook once in one kernel (started by ``manager``, an nbclient kernel manager class),
    trying every mutation before its test; the problems found."""
    import nbformat
    from nbclient import NotebookClient
    from nbclient.exceptions import CellExecutionError

    notebook = nbformat.reads(json.dumps(nb), as_version=4)   # sources as strings
    client = NotebookClient(notebook, timeout=CELL_TIMEOUT, kernel_name="python3",
                            kernel_manager_class=manager,   # its sockets are files: no TCP port race
                            resources={"metadata": {"path": str(NOTEBOOKS)}})
    problems: list[str] = []

    def run(code: str, index: int) -> None:
        cell = nbformat.v4.new_code_cell(code)
        client.execute_cell(cell, index, store_history=False)

    skipped = cells_not_run(nb)
    with client.setup_kernel():
        run(f"{ABSENT} = object()", 0)
        for index, cell in enumerate(notebook.cells):
            if cell.cell_type != "code" or index in skipped:
                continue
            grade_id = cell.get("metadata", {}).get("nbgrader", {}).get("grade_id")
            if cell.get("metadata", {}).get("nbgrader", {}).get("grade"):
                for description, code in mutations.get(grade_id, []):
                    names = defined_names(code)
                    run(f"{SAVED} = {{n: globals().get(n, {ABSENT}) for n in {names!r}}}", index)
                    try:
                        try:
                            run(code, index)
                        except CellExecutionError as exc:
                            problems.append(f"{chapter} {grade_id} (cell {index}), mutation {description!r}: "
                                            f"its code raised before the test ran: {_error_text(exc)}")
                            continue
                        try:
                            run(_source(cell), index)
                        except CellExecutionError:
                            pass   # the test rejects the wrong answer
                        else:
                            problems.append(
                                f"{chapter} {grade_id} (cell {index}): the test passes the wrong answer "
                                f"{description!r}; make the test cell reject it (an assert on the quantity "
                                "it changes), or fix the mutation")
                    finally:
                        run(f"for _n, _v in {SAVED}.items():\n"
                            f"    globals().pop(_n, None) if _v is {ABSENT} else globals().__setitem__(_n, _v)\n"
                            f"del {SAVED}", index)
            try:
                client.execute_cell(cell, index)
            except CellExecutionError as exc:
                first = next((line for line in _source(cell).splitlines() if line.strip()), "")
                what = f"the test {grade_id}" if grade_id and grade_id.startswith("task") else "the cell"
                problems.append(f"{chapter} cell {index} ({what}, `{first[:60]}`) raised in the instructor's "
                                f"notebook after the mutations were undone: {_error_text(exc)}")
                break
    return problems


@pytest.fixture(scope="module")
def kernel_manager(request):
    """The kernel manager of the chapters' runs: with three chapters or more in the session (the
    ten of ``make test-all``), their kernels forked from one server (its environment has
    ``ROBOKIN_VIEWER=static``; stopped after the module), a kernel's start and imports costing a
    fork instead; with fewer (``make test``'s one, a scaffolded copy's two), each kernel starts
    anew: the server's own start, its preloaded imports, costs about two kernels'. Module-scoped,
    so the chapters run in one pytest-xdist worker (tests/support/parallel_plan.py) and share it
    (benchmarks/README.md, "The grading mutations' kernels forked, and the suite's order by CPU")."""
    chapters = sum(1 for item in request.session.items if getattr(item, "module", None) is request.module)
    if chapters < 3:
        yield AsyncPrivateSocketsKernelManager
        return
    try:
        yield forked_kernels.ForkedAsyncKernelManager
    finally:
        forked_kernels.stop_server()


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_every_graded_test_rejects_its_mutations(path, monkeypatch, kernel_manager):
    chapter = path.stem
    mutations = load_mutations(chapter)
    nb = json.loads(path.read_text(encoding="utf-8"))
    tests = graded_tests(nb)
    assert tests, f"{chapter}: no graded test cells (run tools/authoring/nbgrader_metadata.py)"
    problems = coverage_problems(chapter, tests, mutations)
    monkeypatch.setenv("ROBOKIN_VIEWER", "static")   # inherited by the kernel
    monkeypatch.setenv("PYDEVD_DISABLE_FILE_VALIDATION", "1")
    problems += run_with_mutations(chapter, nb, mutations, kernel_manager)
    assert not problems, f"{len(problems)} problem(s):\n" + "\n".join(f"- {p}" for p in problems)
