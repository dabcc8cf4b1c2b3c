"""``HideHiddenTests`` (generate_feedback).

The hidden tests of the test cells are not in the feedback page: nbgrader's ``ClearHiddenTests``
takes them out, the tracebacks lose their code, and the verdict and diagnosis stay.
"""

from __future__ import annotations

import re

from nbgrader.preprocessors import ClearHiddenTests
from traitlets import Bool, Unicode

from .cells import ANSI, hidden_lines


CELL_FRAME = re.compile(r"Cell In\[(\d+)\], line (\d+)")
#: A line of code quoted in a traceback's frame: "----> 5 code" or "      6 code".
QUOTED_LINE = re.compile(r"\s*(?:-*>)?\s*\d+ ?(.*)$")
FAILED_AT = re.compile(r"^(✘ Task .*? failed at line )(\d+)(:)", re.M)


class HideHiddenTests(ClearHiddenTests):
    """generate_feedback: a test cell's hidden tests are not in the feedback page.

    The graded notebook holds every test cell as the instructor wrote it (autograde restores the
    hidden tests the student edition lacks), and the feedback page is made from it; a student who
    reads the page before handing in again (``collect --update``) would read them. nbgrader's
    ``ClearHiddenTests`` (the preprocessor of ``generate_assignment``, with its delimiters) takes
    them out of the cell, and a comment says where they were; what the cell printed stays (the
    verdict), and its error output keeps the error and its message (the diagnosis) while the
    traceback's frames in the hidden lines lose their code. Line numbers (the traceback's, the
    robokin note's "failed at line N") are those of the cell as the student sees it.
    """

    enforce_metadata = Bool(False, help="complain about hidden tests outside a test cell").tag(config=True)
    marker = Unicode("# … hidden tests, run when grading (their code is not shown) …",
                     help="the comment in place of each block of hidden tests").tag(config=True)

    def preprocess_cell(self, cell, resources, index):
        if cell.cell_type != "code" or self.begin_test_delimeter not in cell.source:
            return cell, resources
        original = cell.source
        hidden = hidden_lines(original, self.begin_test_delimeter, self.end_test_delimeter)
        cell, resources = super().preprocess_cell(cell, resources, index)   # nbgrader's own checks
        lines, renumber = [], {}
        for number, line in enumerate(original.split("\n"), 1):
            if number not in hidden:
                lines.append(line)
                renumber[number] = len(lines)
            elif number - 1 not in hidden:
                lines.append(self.marker)
        assert [line for line in lines if line != self.marker] == cell.source.split("\n"), "ClearHiddenTests changed"
        cell.source = "\n".join(lines)
        # the hidden lines a traceback could quote (not those that are also visible, nor a lone ")")
        hidden_text = {line.strip() for number, line in enumerate(original.split("\n"), 1)
                       if number in hidden and len(line.strip()) >= 4} - {line.strip() for line in lines}
        for output in cell.get("outputs", []):
            if output.get("output_type") == "stream" and "failed at line" in output.get("text", ""):
                output["text"] = FAILED_AT.sub(lambda m: m.group(1) + str(renumber.get(int(m.group(2)), "?"))
                                               + m.group(3), output["text"])
            elif output.get("output_type") == "error":
                output["traceback"] = [self._frame(entry, cell.get("execution_count"), lines, renumber, hidden_text)
                                       for entry in output.get("traceback", [])]
        return cell, resources

    @staticmethod
    def _frame(entry: str, count, lines: list[str], renumber: dict[int, int], hidden_text: set[str]) -> str:
        """A traceback entry without the cell's hidden lines: a frame in this cell shows its line only
        if it is visible; any other entry that quotes a hidden line is replaced by a sentence."""
        plain = ANSI.sub("", entry)
        frame = CELL_FRAME.match(plain)
        quoted = {m.group(1).strip() for m in map(QUOTED_LINE.match, plain.splitlines()[1:]) if m}
        if frame and (str(frame.group(1)) == str(count) or quoted & hidden_text):
            line = renumber.get(int(frame.group(2)))
            if line is None:
                return f"Cell In[{frame.group(1)}], in the hidden tests (their code is not shown)"
            return f"Cell In[{frame.group(1)}], line {line}\n----> {line} {lines[line - 1]}"
        if quoted & hidden_text or any(text in plain for text in hidden_text if len(text) >= 12):
            return "(a frame in the hidden tests: its code is not shown)"
        return entry
