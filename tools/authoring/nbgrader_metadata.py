#!/usr/bin/env python3
"""Write nbgrader's cell metadata into the chapter notebooks, from the tags authors use.

    .venv/bin/python tools/authoring/nbgrader_metadata.py           # write (idempotent)
    .venv/bin/python tools/authoring/nbgrader_metadata.py --check   # exit 1 if stale, naming notebook and cell
    .venv/bin/python tools/authoring/nbgrader_metadata.py --list    # print every cell's role, task and points

Authors keep tagging cells as before (``solution``, ``check``, the *Try it
yourself* cells, ``## Task k:`` headings, ``{solution-start}``/``{solution-end}``);
this script derives from them (``tools/notebook_analysis.py``) what nbgrader needs:

=============================  ==================================================  ===================
cell                           nbgrader metadata                                    in the student edition
=============================  ==================================================  ===================
``solution`` code              autograded answer ``taskK_answerJ``                  stub: signature kept,
                                                                                    body ``# YOUR CODE HERE``
markdown in a solution block   read-only ``cell-<id>``, ``robokin.role = prose``     removed (empty)
``check`` code in a task that  autograder test ``taskK_testJ``, **1 point** (or N  kept, restored before
reads the student's answer     with the tag ``points-N``), ``robokin.explain`` =    grading
                               checks that explain a failure (with tags
                               ``explains-<answer>``: those of the answers named)
*Try it yourself* code         none (editable, not graded)                          kept
everything else                read-only ``cell-<id>``                               kept, restored before grading
=============================  ==================================================  ===================

A task is worth the sum of its tests' points (1 each, or N for a test cell tagged
``points-N``, so that points reflect the work a task asks); the notebook's
metadata (``metadata.robokin.grading``) and the table between the
``nbgrader-points`` markers in ``book/for-instructors.md`` state the points per
task and per chapter. The script only writes metadata: it verifies that no cell's
source or outputs changed before it saves a notebook, and a second run changes
nothing.
"""

from __future__ import annotations

import argparse
import copy
import json
import sys
from pathlib import Path
from typing import Any

from tools.grading.course import check_names
from tools.notebook_analysis import Chapter, analyse, dump_notebook

ROOT = Path(__file__).resolve().parents[2]
DOC = ROOT / "book" / "for-instructors.md"
TABLE_START = "<!-- nbgrader-points:start (written by tools/authoring/nbgrader_metadata.py; do not edit) -->"
TABLE_END = "<!-- nbgrader-points:end -->"
POINTS_PER_TEST = 1
SCHEMA_VERSION = 3


def chapter_notebooks(root: Path = ROOT, folder: str = "notebooks") -> list[Path]:
    """The exercise notebooks: ``notebooks/NN_*.ipynb`` except the tour (``00_``)."""
    return sorted(p for p in (root / folder).glob("[0-9][0-9]_*.ipynb") if not p.name.startswith("00_"))


# ---------------------------------------------------------------- the metadata
def _nbgrader(grade_id: str, *, grade=False, solution=False, locked=False, points=None) -> dict:
    meta = {"grade": grade, "grade_id": grade_id, "locked": locked, "schema_version": SCHEMA_VERSION,
            "solution": solution, "task": False}
    if points is not None:
        meta["points"] = points
    return meta


def expected(chapter: Chapter) -> tuple[list[tuple[dict | None, dict | None]], dict]:
    """Per cell ``(nbgrader, robokin)`` metadata (None: the key must be absent), and the
    notebook-level ``robokin`` metadata."""
    out: list[tuple[dict | None, dict | None]] = []
    answers: dict[int | None, int] = {}
    tests: dict[int | None, int] = {}
    for cell in chapter.cells:
        prefix = f"task{cell.task}_" if cell.task is not None else ""
        locked_id = f"cell-{cell.cell_id}" if cell.cell_id else f"cell-{cell.index}"
        if cell.role == "answer":
            answers[cell.task] = answers.get(cell.task, 0) + 1
            declare = [n for n in cell.defines if n in cell.interface]
            out.append((
                _nbgrader(f"{prefix}answer{answers[cell.task]}", solution=True),
                {"declare": declare, "role": "answer", "task": cell.task},
            ))
        elif cell.role == "test":
            tests[cell.task] = tests.get(cell.task, 0) + 1
            out.append((
                _nbgrader(f"{prefix}test{tests[cell.task]}", grade=True, locked=True, points=cell.points),
                {"explain": [list(p) for p in cell.explain], "reads": sorted(cell.depends_on),
                 "role": "test", "task": cell.task},
            ))
        elif cell.role == "prose":
            out.append((_nbgrader(locked_id, locked=True), {"role": "prose", "task": cell.task}))
        elif cell.role == "try":
            out.append((None, None))
        else:  # text, given, check
            out.append((_nbgrader(locked_id, locked=True), None))
    task_points: list[dict[str, Any]] = [
        {"points": sum(c.points for c in chapter.tests(k)), "task": k, "tests": len(chapter.tests(k)),
         "title": title}
        for k, title in sorted(chapter.tasks.items())
    ]
    grading = {"points": sum(t["points"] for t in task_points), "points_per_test": POINTS_PER_TEST,
               "tasks": task_points}
    return out, {"grading": grading}


def apply(nb: dict, chapter: Chapter) -> dict:
    """A copy of ``nb`` with the expected metadata (cells' sources and outputs untouched)."""
    new = copy.deepcopy(nb)
    cells_meta, nb_meta = expected(chapter)
    for cell, (nbg, rk) in zip(new["cells"], cells_meta):
        meta = cell.setdefault("metadata", {})
        for key, value in (("nbgrader", nbg), ("robokin", rk)):
            if value is None:
                meta.pop(key, None)
            else:
                meta[key] = value
    new.setdefault("metadata", {})["robokin"] = nb_meta
    return new


def _content(nb: dict) -> list:
    """Everything but metadata: what the script must never change."""
    keep = ("cell_type", "source", "outputs", "execution_count", "attachments", "id")
    return [{k: c.get(k) for k in keep} for c in nb["cells"]]


def differences(nb: dict, chapter: Chapter) -> list[str]:
    """Human-readable list of stale metadata (empty when the notebook is up to date)."""
    cells_meta, nb_meta = expected(chapter)
    out = []
    if len(nb["cells"]) != len(chapter.cells):  # pragma: no cover - analyse() reads the same cells
        return ["the notebook changed while it was read"]
    for info, cell, (nbg, rk) in zip(chapter.cells, nb["cells"], cells_meta):
        meta = cell.get("metadata", {})
        for key, value in (("nbgrader", nbg), ("robokin", rk)):
            if meta.get(key) == value:
                continue
            state = "missing" if key not in meta else ("stale" if value is not None else "should be removed")
            first = info.source.strip().splitlines()[0][:50] if info.source.strip() else ""
            task = f", task {info.task}" if info.task is not None else ""
            out.append(f"cell {info.index} ({info.role}{task}: `{first}`): {key} metadata {state}")
    if nb.get("metadata", {}).get("robokin") != nb_meta:
        out.append("notebook metadata `robokin.grading` (points per task) missing or stale")
    return out


def points_table(chapters: list[Chapter]) -> str:
    """The markdown table of points per task and chapter (for book/for-instructors.md)."""
    lines = [
        "| chapter | points per task | total |",
        "|---|---|---|",
    ]
    total = 0
    for chapter in chapters:
        _, nb_meta = expected(chapter)
        grading = nb_meta["grading"]
        per_task = ", ".join(f"Task {t['task']}: {t['points']}" for t in grading["tasks"])
        lines.append(f"| `{chapter.name}` | {per_task} | {grading['points']} |")
        total += grading["points"]
    lines.append(f"| all chapters | | {total} |")
    return "\n".join(lines)


def doc_with_table(text: str, table: str) -> str | None:
    """The page with the table between the markers (None if the markers are missing)."""
    start, end = text.find(TABLE_START), text.find(TABLE_END)
    if start < 0 or end < start:
        return None
    return text[: start + len(TABLE_START)] + "\n\n" + table + "\n\n" + text[end:]


# ---------------------------------------------------------------- command line
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("notebooks", nargs="*", type=Path,
                        help="chapter notebooks (default: notebooks/NN_*.ipynb without the tour)")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 and name every notebook and cell whose metadata is stale")
    parser.add_argument("--list", action="store_true", help="print the role, task and points of every cell")
    parser.add_argument("--doc", type=Path, default=DOC,
                        help="page with the points table (default: book/for-instructors.md); 'none' to skip")
    args = parser.parse_args(argv)

    paths = args.notebooks or chapter_notebooks()
    names = check_names()
    status = 0
    chapters = []
    for path in paths:
        text = path.read_text(encoding="utf-8")
        nb = json.loads(text)
        chapter = analyse(path, nb, check_names=names)
        chapters.append(chapter)
        if chapter.problems:
            for problem in chapter.problems:
                print(f"ERROR {path}: {problem}", file=sys.stderr)
            status = 2
            continue
        if args.list:
            cells_meta, nb_meta = expected(chapter)
            print(f"== {path}: {nb_meta['grading']['points']} points")
            for cell, (nbg, _) in zip(chapter.cells, cells_meta):
                first = cell.source.strip().splitlines()[0][:60] if cell.source.strip() else ""
                extra = f"{nbg['grade_id']}" if nbg else "(editable)"
                if nbg and nbg.get("points"):
                    extra += f", {nbg['points']} point"
                print(f"  {cell.index:3d} {cell.role:6s} task {cell.task!s:4s} {extra:28s} {first}")
            continue
        if args.check:
            stale = differences(nb, chapter)
            for line in stale:
                print(f"STALE {path}: {line}")
            if stale:
                status = max(status, 1)
            continue
        new = apply(nb, chapter)
        if _content(new) != _content(nb):  # pragma: no cover - guarded by construction
            raise RuntimeError(f"{path}: refusing to write, a cell's source or outputs would change")
        new_text = dump_notebook(new)
        if new_text != text:
            path.write_text(new_text, encoding="utf-8")
            print(f"wrote nbgrader metadata: {path} ({expected(chapter)[1]['grading']['points']} points)")
        else:
            print(f"up to date: {path}")

    if str(args.doc).lower() != "none" and not args.list and status < 2 and not args.notebooks:
        page = args.doc.read_text(encoding="utf-8")
        new_page = doc_with_table(page, points_table(chapters))
        if new_page is None:
            print(f"ERROR {args.doc}: no nbgrader-points markers", file=sys.stderr)
            status = 2
        elif new_page != page:
            if args.check:
                print(f"STALE {args.doc}: the table of points per task differs from the notebooks")
                status = max(status, 1)
            else:
                args.doc.write_text(new_page, encoding="utf-8")
                print(f"wrote the points table: {args.doc}")
    if args.check and status == 0:
        print("nbgrader metadata up to date")
    elif args.check and status == 1:
        print("Fix: run `.venv/bin/python tools/authoring/nbgrader_metadata.py` (writes metadata only), then commit.")
    return status


if __name__ == "__main__":
    sys.exit(main())
