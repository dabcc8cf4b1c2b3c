#!/usr/bin/env python3
"""Format the code cells of the notebooks to the book's width (88 characters).

    .venv/bin/python tools/authoring/format_notebooks.py            # format notebooks/*.ipynb in place
    .venv/bin/python tools/authoring/format_notebooks.py --check    # exit 1 and list the lines that are too long

Every cell without an id gets a stable one (``make execute`` would give it a random
one, after ``tools/authoring/nbgrader_metadata.py`` named its locked cell by its position).
Code is formatted by black (``--line-length 88``, with its string splitting), then
the comments and one-line docstrings black leaves long are wrapped at word
boundaries. Only cell sources change; outputs are kept (re-run ``make execute``
afterwards: execution counts stay, but a changed printout must be stored again).
``tests/test_notebook_conventions.py`` enforces the limit.
"""

from __future__ import annotations

import argparse
import io
import re
import sys
import textwrap
import tokenize
from pathlib import Path

from tools.notebook_analysis import dump_notebook, load_notebook

ROOT = Path(__file__).resolve().parents[2]
LIMIT = 88


def long_lines(code: str) -> list[str]:
    return [line for line in code.splitlines() if len(line) > LIMIT]


def _wrap_comment(line: str) -> list[str]:
    indent = line[: len(line) - len(line.lstrip())]
    text = line.strip()[1:].strip()
    return textwrap.wrap(text, LIMIT - len(indent) - 2, initial_indent=f"{indent}# ",
                         subsequent_indent=f"{indent}# ", break_on_hyphens=False)


def _line_kinds(code: str) -> tuple[set[int], set[int]]:
    """Line numbers (1-based) of whole-line comments, and of lines inside a triple-quoted string."""
    comments: set[int] = set()
    inside: set[int] = set()
    try:
        for tok in tokenize.generate_tokens(io.StringIO(code).readline):
            if tok.type == tokenize.COMMENT and not tok.line[: tok.start[1]].strip():
                comments.add(tok.start[0])
            elif tok.type == tokenize.STRING and tok.string.startswith('"""'):
                inside.update(range(tok.start[0] + 1, tok.end[0]))
    except (tokenize.TokenError, IndentationError, SyntaxError):
        pass
    return comments, inside


_DOCSTRING = re.compile(r'^(\s*)"""(.*)"""$')
_DOCSTRING_OPEN = re.compile(r'^(\s*)"""(.*\S)$')


def _wrap_text(indent: str, text: str, first: str = "") -> list[str]:
    width = LIMIT - len(indent)
    return [indent + line for line in textwrap.wrap(text, width, initial_indent=first, break_on_hyphens=False)]


def wrap_long_text(code: str) -> str:
    """Wrap the whole-line comments and docstring lines longer than LIMIT (code is black's)."""
    comments, inside = _line_kinds(code)
    out: list[str] = []
    for number, line in enumerate(code.splitlines(), 1):
        indent = line[: len(line) - len(line.lstrip())]
        if len(line) <= LIMIT:
            out.append(line)
        elif number in comments:
            out.extend(_wrap_comment(line))
        elif m := _DOCSTRING.match(line):             # """One line."""  ->  wrapped, closed on its own line
            out.extend(_wrap_text(m.group(1), m.group(2), '"""') + [f'{m.group(1)}"""'])
        elif m := _DOCSTRING_OPEN.match(line):        # """First line of a longer docstring
            out.extend(_wrap_text(m.group(1), m.group(2), '"""'))
        elif number in inside and line.strip()[:1].isalpha():   # prose in a docstring's body
            out.extend(_wrap_text(indent, line.strip()))
        else:
            out.append(line)
    return "\n".join(out) + ("\n" if code.endswith("\n") else "")


#: A line of closing brackets with a comment behind it: ``)  # why``, what black leaves when a
#: trailing comment made a statement too long. The comment belongs above the statement.
DANGLING_COMMENT = re.compile(r"^\s*[)\]}]+[,;]?\s+#")


def _trailing_comments(code: str) -> list[tuple[int, int, int]]:
    """``(comment line, column, first line of its statement)`` of every comment after code."""
    out, start = [], None
    try:
        for tok in tokenize.generate_tokens(io.StringIO(code).readline):
            if tok.type in (tokenize.NEWLINE, tokenize.NL) and start is not None and tok.type == tokenize.NEWLINE:
                start = None
            elif tok.type == tokenize.COMMENT:
                if tok.line[: tok.start[1]].strip():
                    out.append((tok.start[0], tok.start[1], start or tok.start[0]))
            elif tok.type not in (tokenize.NL, tokenize.INDENT, tokenize.DEDENT, tokenize.ENCODING) and start is None:
                start = tok.start[0]
    except (tokenize.TokenError, IndentationError, SyntaxError):
        return []
    return out


def hoist_comments(code: str, only_dangling: bool) -> str:
    """Move trailing comments above their statement: those on lines longer than LIMIT (before
    black, so that a comment does not split a statement), or those left behind closing brackets
    (``)  # ...``, after black)."""
    lines = code.splitlines()
    moves: dict[int, list[str]] = {}
    for number, column, first in reversed(_trailing_comments(code)):
        line = lines[number - 1]
        if only_dangling and not DANGLING_COMMENT.match(line):
            continue
        if not only_dangling and len(line) <= LIMIT:
            continue
        head = lines[first - 1]
        indent = head[: len(head) - len(head.lstrip())]
        moves.setdefault(first, []).insert(0, indent + line[column:].strip())
        lines[number - 1] = line[:column].rstrip()
    if not moves:
        return code
    out = []
    for number, line in enumerate(lines, 1):
        out.extend(moves.get(number, []))
        out.append(line)
    return "\n".join(out) + ("\n" if code.endswith("\n") else "")


def _black(code: str) -> str:
    import black

    mode = black.Mode(line_length=LIMIT, unstable=True, is_ipynb=True)
    try:
        return black.format_cell(code, fast=False, mode=mode)
    except black.NothingChanged:
        return code


def format_code(code: str) -> str:
    """black at LIMIT columns, with trailing comments that do not fit moved above their statement,
    then long comments and docstrings wrapped."""
    formatted = _black(hoist_comments(code, only_dangling=False))
    hoisted = hoist_comments(formatted, only_dangling=True)
    if hoisted != formatted:
        formatted = _black(hoisted)
    return wrap_long_text(formatted)


def give_cells_ids(nb: dict) -> bool:
    """Give every cell without an ``id`` a stable one (and the notebook format 4.5 that has them).

    A cell written without an id (by a script, or by an editor of format 4.4) would otherwise
    get a random one from the next ``make execute`` (nbformat fills missing ids), after
    ``tools/authoring/nbgrader_metadata.py`` had named its locked cell ``cell-<index>``: the metadata
    would then be stale. The id is derived from the cell's position and source, so that a
    second run changes nothing. Returns whether a cell changed.
    """
    import hashlib

    taken = {cell["id"] for cell in nb["cells"] if cell.get("id")}
    changed = False
    for index, cell in enumerate(nb["cells"]):
        if cell.get("id"):
            continue
        digest = hashlib.sha1(f"{index}\0{''.join(cell.get('source', ''))}".encode()).hexdigest()
        length = 8
        while f"cell-{digest[:length]}" in taken:
            length += 1
        cell["id"] = f"cell-{digest[:length]}"
        taken.add(cell["id"])
        changed = True
    if changed and (nb.get("nbformat"), nb.get("nbformat_minor", 0)) < (4, 5):
        nb["nbformat"], nb["nbformat_minor"] = 4, 5
    return changed


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true")
    parser.add_argument("notebooks", nargs="*", type=Path)
    args = parser.parse_args()
    paths = args.notebooks or sorted((ROOT / "notebooks").glob("*.ipynb"))
    bad = 0
    for path in paths:
        nb = load_notebook(path)
        changed = False if args.check else give_cells_ids(nb)
        for index, cell in enumerate(nb["cells"]):
            if cell["cell_type"] != "code":
                continue
            code = "".join(cell["source"])
            if args.check:
                for line in long_lines(code):
                    print(f"{path.name} cell {index}: {len(line)} > {LIMIT}: {line.strip()[:60]}")
                    bad += 1
                continue
            new = format_code(code)
            if new != code:
                cell["source"] = new.splitlines(keepends=True)
                changed = True
        if changed:
            path.write_text(dump_notebook(nb), encoding="utf-8")
            print(f"formatted {path.name}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
