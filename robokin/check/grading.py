r"""Exercise checks for an autograder: verdicts on a student's answers, as data.

nbgrader grades a chapter by running its check cells (``assert`` statements). A
bare ``AssertionError`` tells a student *that* something is wrong, not *what*.
The autograder of this workbook (``tools/robokin_nbgrader.py``) therefore asks
``robokin.check`` about the quantities a failing task defines, in the student's
own kernel, and writes the answers into the feedback::

    from robokin.check import grading
    grading.verdicts(globals(), [("leg.rotation_B1", "R_B1")])
    # [{'check': 'leg.rotation_B1', 'quantity': 'R_B1', 'status': 'wrong',
    #   'diagnosis': 'transpose', 'typical': True, 'message': '✘ R_B1 is transposed: ...'}]

Each pair names a check (``chapter.attribute`` of :mod:`robokin.check`) and a
Python expression evaluated in the student's namespace (a variable name, or e.g.
``H_B1 * H_12``). The checks themselves are unchanged; this module only runs
them quietly and never raises.

:func:`require` is the same for an ``assert``-style test cell: it raises an
``AssertionError`` whose message is the check's explanation.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Iterable, Mapping
from typing import Any

__all__ = ["GENERIC", "verdict", "verdicts", "require", "print_verdicts"]

#: Diagnosis codes that say *that* an answer is wrong but name no typical mistake.
GENERIC = frozenset({"mismatch", "shape", "constant", "symbols", "error"})


def _resolve(check: str):
    """``"leg.rotation_B1"`` -> the check object ``robokin.check.leg.rotation_B1``."""
    from robokin import check as checks

    chapter, _, attr = check.partition(".")
    return getattr(getattr(checks, chapter), attr)


def verdict(namespace: Mapping[str, Any], check: str, quantity: str) -> dict[str, Any]:
    """What ``robokin.check`` says about one quantity of a student's notebook.

    Returns a dict with ``check``, ``quantity``, ``status`` (``"correct"``,
    ``"wrong"``, ``"missing"`` when the expression cannot be evaluated, ``"skipped"``
    when the check itself is unavailable), ``diagnosis`` (the check's code, or None),
    ``typical`` (True when the diagnosis names a typical mistake) and ``message``.
    """
    out: dict[str, Any] = {"check": check, "quantity": quantity, "status": "skipped",
                           "diagnosis": None, "typical": False, "message": ""}
    try:
        checker = _resolve(check)
    except Exception as exc:  # noqa: BLE001 - a renamed check must not break grading
        out["message"] = f"robokin.check.{check} is not available ({type(exc).__name__})"
        return out
    try:
        value = eval(quantity, dict(namespace))
    except NameError as exc:
        out.update(status="missing", message=f"{quantity} is not defined ({exc}): the cell that "
                   "computes it raised, or was not run.")
        return out
    except Exception as exc:  # noqa: BLE001 - report, never raise
        out.update(status="missing", message=f"{quantity} cannot be evaluated: "
                   f"{type(exc).__name__}: {exc}")
        return out
    try:
        result = checker(value, quiet=True)
    except Exception as exc:  # noqa: BLE001 - report, never raise
        out.update(status="wrong", diagnosis="error",
                   message=f"robokin.check.{check} could not check {quantity}: {type(exc).__name__}: {exc}")
        return out
    out.update(
        status="correct" if result.passed else "wrong",
        diagnosis=result.diagnosis,
        typical=bool(result.diagnosis) and result.diagnosis not in GENERIC,
        message=result.message,
    )
    return out


def verdicts(namespace: Mapping[str, Any], pairs: Iterable[tuple[str, str]]) -> list[dict[str, Any]]:
    """:func:`verdict` for every ``(check, quantity)`` pair, in order."""
    return [verdict(namespace, check, quantity) for check, quantity in pairs]


def print_verdicts(namespace: Mapping[str, Any], pairs: Iterable[tuple[str, str]],
                   marker: str = "ROBOKIN-VERDICTS") -> None:
    """Print the verdicts as one JSON line, framed by ``marker`` (read by the autograder)."""
    data = verdicts(namespace, [tuple(p) for p in pairs])
    sys.stdout.write(f"{marker} {json.dumps(data, ensure_ascii=False)}\n")
    sys.stdout.flush()


def require(check: str, answer: Any) -> None:
    """Raise ``AssertionError`` with the check's explanation unless ``answer`` passes.

    ``require("leg.rotation_B1", R_B1)`` in a test cell fails with e.g.
    ``AssertionError: ✘ R_B1 is transposed: ...`` -- the message a student sees in
    nbgrader's feedback.
    """
    result = _resolve(check)(answer, quiet=True)
    if not result.passed:
        raise AssertionError(result.message)
