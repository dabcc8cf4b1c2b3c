r"""Exercise checks: compare a student's answer with robokin's reference.

Students write their own answer -- a sympy expression, a NumPy array or a Python
function -- and call a check::

    from robokin import check
    check.leg.rotation_B1(my_R_B1)        # ✔ R_B1 is correct (checked at 20 random angles).

A wrong answer prints a "✘ ..." line that names the likely mistake (transposed
rotation, a column with the wrong sign, degrees for radians, rotation about the
wrong axis, transforms composed in the wrong order, wrong shape, ...). Every
check returns a :class:`CheckResult` (``.passed``, ``.message``, ``.diagnosis``);
``raise_on_fail=True`` turns a wrong answer into an ``AssertionError`` and
``quiet=True`` suppresses the printout (for autograders).

Generic checks: :func:`matrix_function` (a function of some variables: a
matrix, a transform, a Jacobian -- ``kind=`` picks the typical mistakes),
:func:`value` (a number or array), :func:`ik_solution` (any configuration that
reaches a target) and :func:`solution_set` (all solutions, each once, in any
order); :class:`SolutionSetCheck` is a chapter check of a function returning every
solution, or angles that count modulo 2π. Chapter checks live in submodules listed in
:data:`robokin.check.CHAPTERS` and are imported on first access
(``robokin.check.leg``).
"""

from __future__ import annotations

from typing import Any

from robokin.check._core import (
    Check,
    CheckResult,
    Diagnosis,
    Mistake,
    Variable,
    alternatives,
    mistake,
)
from robokin.check.generic import matrix_function, value
from robokin.check._registry import CHAPTERS, checks_of
from robokin.check.solutions import SolutionSetCheck, ik_solution, solution_set

__all__ = [
    "Check",
    "CheckResult",
    "Diagnosis",
    "Mistake",
    "Variable",
    "alternatives",
    "matrix_function",
    "mistake",
    "value",
    "ik_solution",
    "solution_set",
    "SolutionSetCheck",
    "checks_of",
    "CHAPTERS",
]


def __getattr__(name: str) -> Any:
    if name in CHAPTERS:
        from robokin.check._registry import chapter

        return chapter(name)
    raise AttributeError(
        f"module 'robokin.check' has no attribute {name!r}; chapters with checks: "
        f"{', '.join(sorted(CHAPTERS))}"
    )


def __dir__() -> list[str]:
    return sorted(set(__all__) | set(CHAPTERS))
