r"""Exercise checks for an autograder: verdicts on a student's answers, as data.

nbgrader grades a chapter by running its check cells (``assert`` statements). A
bare ``AssertionError`` tells a student *that* something is wrong, not *what*.
The autograder of this workbook (``tools/grading/robokin_nbgrader/``) therefore asks
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

__all__ = ["GENERIC", "TYPE_PROBE", "verdict", "verdicts", "require", "print_verdicts", "describe",
           "expected_form"]

#: Diagnosis codes that say *that* an answer is wrong but name no typical mistake.
GENERIC = frozenset({"mismatch", "shape", "constant", "symbols", "error"})

#: Pseudo-check of a ``(check, quantity)`` pair: no verdict, only what the value is
#: (``status`` ``"info"``, ``message`` e.g. ``"res_a is a list of 3 items"``).
TYPE_PROBE = "type"


def describe(value: Any) -> str:
    """What a value is, in a few words: ``"a NumPy array of shape (6, 3)"``, ``"None"``."""
    if value is None:
        return "None"
    shape = getattr(value, "shape", None)
    kind = type(value).__name__
    if callable(value) and shape is None:
        import inspect

        try:
            return f"a function {getattr(value, '__name__', kind)}{inspect.signature(value)}"
        except (TypeError, ValueError):
            return f"a callable {kind}"
    if shape is not None and isinstance(shape, tuple):
        module = type(value).__module__.split(".")[0]
        prefix = {"numpy": "a NumPy", "sympy": "a sympy"}.get(module, "a")
        return f"{prefix} {kind} of shape {shape}"
    if isinstance(value, (list, tuple, dict, set)):
        return f"a {kind} of {len(value)} item{'s' if len(value) != 1 else ''}"
    if isinstance(value, (bool, int, float, complex, str)):
        return f"a {kind} ({value!r})" if len(repr(value)) <= 30 else f"a {kind}"
    return f"a {kind} object"


def expected_form(checker: Any) -> str:
    """What a check expects as the answer, in words, from its declared signature or variables.

    Parameters
    ----------
    checker : Check
        A check of :mod:`robokin.check`.

    Returns
    -------
    str
        E.g. ``"a function ik(T)"`` or ``"an array of shape (3, 3)"``.
    """
    signature = getattr(checker, "signature", "")
    if signature:
        return f"a function {signature}"
    shape = None
    try:
        import numpy as np

        shape = np.shape(np.asarray(checker.reference(checker.sample_points()[0]), dtype=float))
    except Exception:  # noqa: BLE001 - the form is a courtesy, never an error
        pass
    value = f"an array of shape {shape}" if shape else "a number" if shape == () else "a value"
    groups = [g[0] for g in (getattr(checker, "groups", None) or [])]
    names = groups or [v.name for v in (getattr(checker, "variables", None) or [])]
    if names and getattr(checker, "at", None) is None:
        args = ", ".join(names)
        return f"a function of ({args}) returning {value}, or a sympy expression in {args}"
    return value


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
    if check == TYPE_PROBE:
        try:
            value = eval(quantity, dict(namespace))
        except Exception as exc:  # noqa: BLE001 - report, never raise
            out.update(status="info", message=f"{quantity} cannot be evaluated ({type(exc).__name__})")
        else:
            out.update(status="info", message=f"{quantity} is {describe(value)}", got=describe(value))
        return out
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
        expected = expected_form(checker)
        got = _parts_described(quantity, namespace)
        out.update(status="missing", expected=expected, got=got,
                   message=f"{quantity} cannot be evaluated ({type(exc).__name__}: {exc}): "
                   f"{got}; expected {quantity} to be {expected}.")
        return out
    try:
        result = checker(value, quiet=True)
    except Exception as exc:  # noqa: BLE001 - report, never raise
        expected = expected_form(checker)
        out.update(status="wrong", diagnosis="error", expected=expected, got=describe(value),
                   message=f"robokin.check.{check} could not check {quantity}: {type(exc).__name__}: {exc}. "
                   f"{quantity} is {describe(value)}; expected {expected}.")
        return out
    if not result.passed and result.diagnosis in ("error", "shape", "constant"):
        expected = expected_form(checker)
        out.update(expected=expected, got=describe(value))
        message = f"{result.message} ({quantity} is {describe(value)}; expected {expected}.)"
        out.update(status="wrong", diagnosis=result.diagnosis, typical=False, message=message)
        return out
    out.update(
        status="correct" if result.passed else "wrong",
        diagnosis=result.diagnosis,
        typical=bool(result.diagnosis) and result.diagnosis not in GENERIC,
        message=result.message,
    )
    return out


def _parts_described(quantity: str, namespace: Mapping[str, Any]) -> str:
    """``"res_a is None"``: what the names of an expression hold (those that are defined)."""
    import ast

    try:
        names = [n.id for n in ast.walk(ast.parse(quantity, mode="eval")) if isinstance(n, ast.Name)]
    except SyntaxError:
        names = []
    parts = [f"{n} is {describe(namespace[n])}" for n in dict.fromkeys(names) if n in namespace]
    return "; ".join(parts) or f"{quantity} is not available"


def verdicts(namespace: Mapping[str, Any], pairs: Iterable[tuple[str, str]]) -> list[dict[str, Any]]:
    """:func:`verdict` for every ``(check, quantity)`` pair, in order.

    Parameters
    ----------
    namespace : mapping
        The notebook's names (``globals()`` of the kernel running the test).
    pairs : iterable of (str, str)
        ``(check name, quantity expression)``, e.g. ``("leg.rotation_B1", "R_B1")``.

    Returns
    -------
    list of dict
        One verdict per pair (see :func:`verdict`).
    """
    return [verdict(namespace, check, quantity) for check, quantity in pairs]


def print_verdicts(namespace: Mapping[str, Any], pairs: Iterable[tuple[str, str]],
                   marker: str = "ROBOKIN-VERDICTS") -> None:
    """Print the verdicts as one JSON line, framed by ``marker`` (read by the autograder).

    Parameters
    ----------
    namespace : mapping
        The notebook's names.
    pairs : iterable of (str, str)
        ``(check name, quantity expression)`` pairs (see :func:`verdicts`).
    marker : str, optional
        The line's first word.
    """
    data = verdicts(namespace, [(check, quantity) for check, quantity in pairs])
    sys.stdout.write(f"{marker} {json.dumps(data, ensure_ascii=False)}\n")
    sys.stdout.flush()


def require(check: str, answer: Any) -> None:
    """Raise ``AssertionError`` with the check's explanation unless ``answer`` passes.

    ``require("leg.rotation_B1", R_B1)`` in a test cell fails with e.g.
    ``AssertionError: ✘ R_B1 is transposed: ...`` -- the message a student sees in
    nbgrader's feedback.

    Parameters
    ----------
    check : str
        Name of the check, ``"<chapter module>.<check>"``.
    answer : object
        The student's answer, in any form the check accepts.

    Raises
    ------
    AssertionError
        The answer does not pass; the message is the check's.
    """
    result = _resolve(check)(answer, quiet=True)
    if not result.passed:
        raise AssertionError(result.message)
