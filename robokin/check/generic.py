"""Generic checks: a function of some variables, or a value, against a reference.

:func:`matrix_function` and :func:`value` build a :class:`~robokin.check._core.Check`
with the standard diagnoses of a kind of answer (:func:`robokin.check.diagnoses.standard`)
and run it; they sit above both modules, so that neither imports the other.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from robokin.check._core import (
    Check,
    CheckResult,
    Diagnosis,
    RefFn,
    Variable,
    AnswerError,
    as_variables,
    evaluator,
    to_float_array,
)
from robokin.check.diagnoses import standard
from robokin.errors import DomainError
from robokin.validation import check_int

__all__ = ["matrix_function", "value"]


def _reference_fn(reference: Any, variables: list[Variable], groups, name: str) -> RefFn:
    try:
        ev = evaluator(reference, variables, groups, f"the reference of {name}")
    except AnswerError as exc:  # an instructor's mistake: a normal exception naming the argument
        raise TypeError(f"reference must be a sympy expression, a function or numbers: {exc.message}") from None
    return ev.fn


def _check_tolerances(atol: Any, rtol: Any) -> None:
    """Validate the comparison tolerances of the generic checks (the messages name them)."""
    from robokin.validation import check_positive

    check_positive(atol, "atol", allow_zero=True, scalar=True)
    check_positive(rtol, "rtol", allow_zero=True, scalar=True)


def matrix_function(
    student: Any,
    reference: Any,
    variables: Any = None,
    name: str = "answer",
    *,
    kind: str = "matrix",
    diagnoses: Sequence[Diagnosis] | None = None,
    samples: int = 20,
    seed: int = 0,
    atol: float = 1e-8,
    rtol: float = 1e-6,
    raise_on_fail: bool = False,
    quiet: bool = False,
) -> CheckResult:
    """Check a matrix/vector/scalar function of ``variables`` against a reference.

    Parameters
    ----------
    student : sympy Matrix or expression, Python function, or array
        The answer.
    reference : sympy Matrix or expression, Python function (same call style
        as the student's), or array
        The correct answer.
    variables : sequence of sympy symbols, names or :class:`Variable`
        The inputs (angles by default, sampled in [-π, π]).
    name : str
        Shown in the messages.
    kind : {'matrix', 'rotation', 'transform', 'vector', 'jacobian', 'angles'}
        Selects the standard diagnoses (see :func:`robokin.check.diagnoses.standard`).
    diagnoses : list of Diagnosis, optional
        Replaces the standard list.

    Returns
    -------
    CheckResult
    """
    check_int(samples, "samples", 1, 100_000)
    check_int(seed, "seed", 0)
    _check_tolerances(atol, rtol)
    vars_ = as_variables(variables)
    ref = _reference_fn(reference, vars_, [], name)
    check = Check(
        name, ref, vars_, [],
        list(diagnoses) if diagnoses is not None else standard(kind),
        samples=samples, seed=seed, atol=atol, rtol=rtol,
        noun="angles" if all(v.kind == "angle" for v in vars_) else "inputs",
    )
    return check(student, raise_on_fail=raise_on_fail, quiet=quiet)


def value(
    student: Any,
    reference: Any,
    name: str = "answer",
    *,
    kind: str = "matrix",
    atol: float = 1e-3,
    rtol: float = 1e-3,
    raise_on_fail: bool = False,
    quiet: bool = False,
) -> CheckResult:
    """Check a numeric answer (array or number) against a reference value.

    The default tolerances accept answers typed with three or four decimals.

    Parameters
    ----------
    student : float or array_like
        The student's answer.
    reference : float or array_like
        The reference value (same shape), finite.
    name : str, optional
        The answer's name in the messages.
    kind : {"matrix", "rotation", "transform", "vector", "jacobian", "angles"}, optional
        Selects the typical mistakes diagnosed (see :func:`~robokin.check.diagnoses.standard`).
    atol, rtol : float, optional
        Absolute and relative tolerances (units of the answer), non-negative.
    raise_on_fail : bool, optional
        Raise AssertionError (with the message) when the answer is wrong.
    quiet : bool, optional
        Do not print the message.

    Returns
    -------
    CheckResult

    Raises
    ------
    TypeError
        ``reference`` is not numbers.
    DomainError
        ``reference`` holds NaN or infinity, or a tolerance is negative.
    ValueError
        An unknown ``kind``.
    AssertionError
        ``raise_on_fail`` and the answer is wrong.
    """
    _check_tolerances(atol, rtol)
    if reference is None or callable(reference):
        raise TypeError(f"reference must be a number or an array of numbers; got {type(reference).__name__}")
    try:
        ref = to_float_array(reference, "reference")
    except AnswerError as exc:
        raise TypeError(f"reference must be a number or an array of numbers: {exc.message}") from None
    if not np.all(np.isfinite(ref)):
        raise DomainError("reference must be finite; got NaN or infinite entries")
    check = Check(name, lambda x: ref, [], [], standard(kind), atol=atol, rtol=rtol)
    return check(student, raise_on_fail=raise_on_fail, quiet=quiet)
