"""What ``robokin.check`` is asked about a submission, and how its verdicts name an answer.

``registered_pairs`` lists the exercise checks registered in ``robokin.check`` that apply to the
answers of a notebook; ``called_as`` says when a check names an answer otherwise than the
notebook does. The verdicts are printed in the kernel after ``VERDICT_MARK``
(``robokin.check.grading.print_verdicts``).
"""

from __future__ import annotations

import functools
import re

from nbgrader import utils
from tools.notebook_analysis import check_aliases, defined_names, free_names

from .cells import robokin_metadata, task_of


TYPE_PROBE = "type"  # robokin.check.grading.TYPE_PROBE: what a value is, no verdict
#: The start of the line on which ``robokin.check.grading.print_verdicts`` prints its verdicts (JSON).
VERDICT_MARK = "ROBOKIN-VERDICTS"
#: The names of Python's builtins: a quantity made of them and an answer's names is the answer's.
BUILTIN_NAMES = set(dir(__import__("builtins")))


def identifier_names(expression: str) -> set[str]:
    """The free names of the Python expression ``expression`` (none if it is empty)."""
    return free_names(expression) if expression.strip() else set()


@functools.cache
def check_names() -> dict[str, str]:
    """``tools.grading.course.check_names()``, read once per process (robokin.check's registry does
    not change while a command runs; autograde asks for it for every submission): read-only."""
    from tools.grading.course import check_names as registered_check_names

    return registered_check_names()


def registered_pairs(nb) -> list[tuple[int | None, str, str]]:
    """``(task, check, name)`` for every exercise check registered in ``robokin.check`` whose
    quantity has the name of a variable or function that an answer cell binds, in the
    chapters of checks the notebook uses (imports, or names in its test cells' metadata),
    unless a test cell's metadata already explains with that check."""
    try:
        names = check_names()
    except Exception:  # noqa: BLE001 - feedback is a bonus; grading goes on
        return []
    chapters, explained = set(), set()
    for cell in nb.cells:
        if cell.cell_type == "code":
            chapters |= {v for v in check_aliases(cell.source).values() if v != "*"}
            explained |= {p[0] for p in robokin_metadata(cell).get("explain", [])}
    chapters |= {check.split(".")[0] for check in explained}
    bound: dict[str, int | None] = {}
    for cell in nb.cells:
        if cell.cell_type == "code" and utils.is_solution(cell):
            for name in defined_names(cell.source):
                bound[name] = task_of(cell)
    # a check the chapter already calls on an answer is asked as the chapter calls it (e.g.
    # through a lambda that fixes default arguments), not on the bare name
    return [(bound[name], check, name) for check, name in sorted(names.items())
            if check.split(".")[0] in chapters and name in bound and check not in explained]


def called_as(verdict: dict) -> str:
    """`` (on your `found[0]`, which it calls `q_goal`)`` when the check names the answer otherwise
    than the notebook does (its message uses its own name), else ``""``."""
    try:
        own = check_names().get(verdict.get("check", ""))
    except Exception:  # noqa: BLE001 - feedback is a bonus
        return ""
    quantity = verdict.get("quantity", "")
    if not own or not quantity or own == quantity or not re.search(rf"(?<![\w.]){re.escape(own)}\b",
                                                                    verdict.get("message", "")):
        return ""
    return f" (on your `{quantity}`, which it calls `{own}`)"
