#!/usr/bin/env python3
"""Format the code cells of the notebooks to the book's width (88 characters).

    .venv/bin/python tools/format_notebooks.py            # format notebooks/*.ipynb in place
    .venv/bin/python tools/format_notebooks.py --check    # exit 1 and list the lines that are too long

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

sys.path.insert(0, str(Path(__file__).resolve().parent))

from notebook_analysis import dump_notebook, load_notebook  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
LIMIT = 88


def long_lines(code: str) -> list[str]:
    return [line for line in code.splitlines() if len(line) > LIMIT]


def _wrap_comment(line: str) -> list[str]:
    indent = line[: len(line) - len(line.lstrip())]
    text = line.strip()[1:].strip()
    return textwrap.wrap(text, LIMIT - len(indent) - 2, initial_indent=f"{indent}# ",
                         subsequent_indent=f"{indent}# ", break_on_hyphens=False)


def _comment_lines(code: str) -> set[int]:
    """Line numbers (1-based) holding a comment that is the whole line."""
    out = set()
    try:
        for tok in tokenize.generate_tokens(io.StringIO(code).readline):
            if tok.type == tokenize.COMMENT and not tok.line[: tok.start[1]].strip():
                out.add(tok.start[0])
    except (tokenize.TokenError, IndentationError, SyntaxError):
        pass
    return out


_DOCSTRING = re.compile(r'^(\s*)"""(.*)"""$')
_DOCSTRING_OPEN = re.compile(r'^(\s*)"""(.*\S)$')


def wrap_long_text(code: str) -> str:
    comments = _comment_lines(code)
    out: list[str] = []
    for number, line in enumerate(code.splitlines(), 1):
        if len(line) <= LIMIT:
            out.append(line)
        elif number in comments:
            out.extend(_wrap_comment(line))
        elif m := _DOCSTRING.match(line):             # """One line."""  ->  wrapped, closed on its own line
            indent, text = m.groups()
            body = textwrap.wrap(text, LIMIT - len(indent), initial_indent='"""', break_on_hyphens=False)
            out.extend(indent + b for b in body)
            out.append(f'{indent}"""')
        elif m := _DOCSTRING_OPEN.match(line):        # """First line of a longer docstring
            indent, text = m.groups()
            body = textwrap.wrap(text, LIMIT - len(indent), initial_indent='"""', break_on_hyphens=False)
            out.extend(indent + b for b in body)
        elif line.startswith(" ") and not line.strip().startswith(("'", '"', "f'", 'f"')) and line.strip()[:1].isalpha() \
                and _in_docstring(code, number):
            indent = line[: len(line) - len(line.lstrip())]
            out.extend(textwrap.wrap(line.strip(), LIMIT - len(indent), initial_indent=indent,
                                     subsequent_indent=indent, break_on_hyphens=False))
        else:
            out.append(line)
    return "\n".join(out) + ("\n" if code.endswith("\n") else "")


def _in_docstring(code: str, number: int) -> bool:
    """Whether line ``number`` lies inside a triple-quoted string."""
    try:
        for tok in tokenize.generate_tokens(io.StringIO(code).readline):
            if tok.type == tokenize.STRING and tok.string.startswith('"""') and tok.start[0] < number < tok.end[0]:
                return True
    except (tokenize.TokenError, IndentationError, SyntaxError):
        pass
    return False


def format_code(code: str) -> str:
    import black

    mode = black.Mode(line_length=LIMIT, unstable=True, is_ipynb=True)
    try:
        formatted = black.format_cell(code, fast=False, mode=mode)
    except black.NothingChanged:
        formatted = code
    return wrap_long_text(formatted)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true")
    parser.add_argument("notebooks", nargs="*", type=Path)
    args = parser.parse_args()
    paths = args.notebooks or sorted((ROOT / "notebooks").glob("*.ipynb"))
    bad = 0
    for path in paths:
        nb = load_notebook(path)
        changed = False
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
