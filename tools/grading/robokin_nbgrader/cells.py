"""What the preprocessors read of a notebook's cells, and how a note names a cell.

A cell's robokin metadata (``metadata.robokin``, written by ``tools/authoring/nbgrader_metadata.py``) and
its task, the lines of its hidden tests and the source a student sees, the line at which an
error was raised, and a cell's label in a note (``In [5] `first line` (your answer to Task 2)``).
"""

from __future__ import annotations

import re

from nbformat.notebooknode import from_dict
from nbgrader.preprocessors import ClearHiddenTests
from tools.notebook_analysis import statement_at


#: An ANSI colour code of a traceback.
ANSI = re.compile(r"\x1b\[[0-9;]*[A-Za-z]")


def robokin_metadata(cell) -> dict:
    """The robokin metadata of ``cell`` (``metadata.robokin``; ``{}`` if it has none)."""
    return cell.metadata.get("robokin", {}) or {}


def task_of(cell) -> int | None:
    """The task ``cell`` belongs to: its robokin metadata's, else the number in its grade id (``task2_...``)."""
    task = robokin_metadata(cell).get("task")
    if task is None:
        m = re.match(r"task(\d+)_", cell.metadata.get("nbgrader", {}).get("grade_id", ""))
        task = int(m.group(1)) if m else None
    return task


def first_line(text: str, width: int = 60) -> str:
    """The first line of code of ``text`` (not a comment), cut to ``width`` characters."""
    for line in text.splitlines():
        line = line.strip()
        if line and not line.startswith("#"):
            return line if len(line) <= width else line[: width - 1] + "…"
    return text.strip().splitlines()[0][:width] if text.strip() else ""


def hidden_lines(source: str, begin: str | None = None, end: str | None = None) -> set[int]:
    """The numbers (from 1) of the lines of ``source`` in its hidden tests, delimiters included:
    the lines nbgrader's ``ClearHiddenTests`` removes (its default delimiters unless given)."""
    begin = begin or ClearHiddenTests.begin_test_delimeter.default_value
    end = end or ClearHiddenTests.end_test_delimeter.default_value
    out, inside = set(), False
    for number, line in enumerate(source.split("\n"), 1):
        if begin in line:
            inside = True
        if inside:
            out.add(number)
        if end in line:
            inside = False
    return out


def visible_source(source: str) -> str:
    """``source`` without its hidden tests, as nbgrader's ``ClearHiddenTests`` leaves it for a student."""
    if not hidden_lines(source):
        return source
    cell = from_dict({"cell_type": "code", "metadata": {}, "source": source, "outputs": [], "execution_count": None})
    return ClearHiddenTests(enforce_metadata=False).preprocess_cell(cell, {}, 0)[0].source


def failing_line(cell, error) -> int | None:
    """The line (from 1) of ``cell`` at which its error output ``error`` was raised, if its traceback says:
    the statement of the cell that was running (the traceback's first frame in it), not a line in the
    body of a function of the cell that the statement called."""
    text = ANSI.sub("", "\n".join(error.get("traceback", [])))
    count = cell.get("execution_count")
    found = [int(line) for number, line in re.findall(r"Cell In\[(\d+)\], line (\d+)", text)
             if str(number) == str(count)]
    return found[0] if found and 0 < found[0] <= len(cell.source.splitlines()) else None


def raising_functions(cell, error) -> set[str]:
    """The names of the functions of ``cell`` that its error output ``error`` passed through: the
    traceback's frames in the body of a function defined in the cell (``Cell In[7], line 2, in
    velocity(v)``), not the cell's own statement nor a frame in a module it called."""
    text = ANSI.sub("", "\n".join(error.get("traceback", [])))
    count = cell.get("execution_count")
    # a method or a nested function is shown by its qualified name: ``Robot.jacobian``, ``f.<locals>.g``
    frames = re.findall(r"Cell In\[(\d+)\], line \d+, in ([\w.<>]+)\(", text)
    return {function.split(".")[0] for number, function in frames if str(number) == str(count)}


def cell_label(cell, line: int | None = None) -> str:
    """``In [5] `first line` (your answer to Task 2)``; with ``line``, that line is quoted (where the
    cell raised) instead of the first -- never a line of its hidden tests."""
    count = cell.get("execution_count")
    where = f"In [{count}]" if count else "a cell"
    role = robokin_metadata(cell).get("role", "")
    task = task_of(cell)
    kind = {"answer": f"your answer to Task {task}", "test": f"a test of Task {task}"}.get(role)
    if line is not None and line not in hidden_lines(cell.source):
        statement = " ".join(part.split("#")[0].strip() for part in statement_at(cell.source, line).splitlines())
        statement = re.sub(r"([(\[{]) ", r"\1", re.sub(r" ([)\]}])", r"\1", " ".join(statement.split())))
        first = statement if len(statement) <= 60 else statement[:59] + "…"
        where += f", line {line},"
    else:
        first = first_line(visible_source(cell.source))
    text = f"{where} `{first}`" if first else where
    return f"{text} ({kind})" if kind else text


def markdown_line(text: str) -> str:
    """One line of plain text made safe inside a markdown list item."""
    return " ".join(text.split()).replace("|", "\\|").replace("<", "&lt;")
