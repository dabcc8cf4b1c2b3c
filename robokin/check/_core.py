r"""The generic machinery of the exercise checks.

A *check* compares a student's answer with a reference on seeded random inputs
(or at one fixed input, for numeric answers) and, when they differ, tries a list
of *diagnoses*. A diagnosis turns the reference into a typical mistake (the
transpose, a column with its sign flipped, the formula evaluated in degrees,
the factors of a product in another order, ...) together with a message written
for the student. The first mistake that reproduces the student's answer at every
sample explains it.

Accepted answers
----------------
- a sympy ``Matrix`` or expression in the check's variables (lambdified, then
  compared numerically -- never by symbolic equality; symbols are matched by
  name, whatever their assumptions);
- a NumPy array / list of numbers (for a check at a fixed input, or a check
  without variables);
- a Python function: called with one argument per variable
  (``f(alpha, beta, gamma)``) or with one vector per argument group
  (``f(q)``); the call style is detected.

The result is a :class:`CheckResult`; its message is printed (``quiet=False``)
and, with ``raise_on_fail=True``, a wrong answer raises :class:`AssertionError`.
"""

from __future__ import annotations

import functools
import inspect
import math
import sys
import textwrap
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np


#: Width of a printed check message: the book's output column (and a terminal).
MESSAGE_WIDTH = 80


def show(message: str, width: int = MESSAGE_WIDTH) -> None:
    """Print a check's message with its lines wrapped at ``width`` characters.

    Continuation lines are indented by two spaces; ``CheckResult.message`` is unchanged.

    Parameters
    ----------
    message : str
        The message (one or more lines).
    width : int, optional
        Longest printed line, in characters.
    """
    lines = []
    for line in message.splitlines() or [""]:
        if len(line) <= width:
            lines.append(line)
            continue
        indent = line[: len(line) - len(line.lstrip())]
        lines.extend(textwrap.wrap(line, width, subsequent_indent=indent + "  ", break_long_words=False,
                                   break_on_hyphens=False) or [line])
    print("\n".join(lines))

__all__ = [
    "CheckResult",
    "Variable",
    "Mistake",
    "Diagnosis",
    "Check",
    "MatrixArgumentsCheck",
    "LaterStepCheck",
    "with_reference_steps",
    "FunctionCheck",
    "not_a_function",
    "pack_joint_rows",
    "packed_variants",
    "report",
    "mistake",
    "alternatives",
    "PASS",
    "FAIL",
]

PASS = "\u2714"  # ✔
FAIL = "\u2718"  # ✘

RefFn = Callable[[np.ndarray], np.ndarray]


def report(result: CheckResult, *, raise_on_fail: bool, quiet: bool) -> CheckResult:
    """Print a check's message (unless ``quiet``); raise it when the answer failed and ``raise_on_fail``.

    Parameters
    ----------
    result : CheckResult
        The verdict of a check.
    raise_on_fail, quiet : bool
        As for every check.

    Returns
    -------
    CheckResult
        ``result``.

    Raises
    ------
    AssertionError
        ``raise_on_fail`` and the answer failed (the message is the check's).
    """
    if not quiet:
        show(result.message)
    if raise_on_fail and not result.passed:
        raise AssertionError(result.message)
    return result


# ---------------------------------------------------------------- results
@dataclass(frozen=True, eq=False)
class CheckResult:
    """Outcome of one check.

    Attributes
    ----------
    name : str
        What was checked (e.g. ``"R_B1"``).
    passed : bool
        True if the answer matches the reference at every sample.
    message : str
        The one-line (pass) or short (fail) explanation that was printed.
    diagnosis : str or None
        ``None`` when passed; otherwise a code such as ``"transpose"``,
        ``"sign_column"``, ``"degrees_input"``, ``"wrong_axis"``,
        ``"composition_order"``, ``"shape"``, ``"mismatch"`` (no known mistake
        explains the answer), ``"error"`` (the answer could not be evaluated).
    samples : int
        Number of inputs at which the answer was compared.
    """

    name: str
    passed: bool
    message: str
    diagnosis: str | None = None
    samples: int = 0

    def __bool__(self) -> bool:
        return self.passed

    def __repr__(self) -> str:
        return (
            f"CheckResult(name={self.name!r}, passed={self.passed}, "
            f"diagnosis={self.diagnosis!r})"
        )

    def _ipython_display_(self) -> None:
        """Show nothing in a notebook: the check has already printed its message.

        So ``check.leg.rotation_B1(R)`` as the last line of a cell prints one line
        and no ``CheckResult(...)`` echo (with or without a trailing ``;``).
        """


class AnswerError(Exception):
    """The answer cannot be evaluated (wrong type or shape, symbols left, it raised).

    Parameters
    ----------
    code : str
        Diagnosis code reported in :attr:`CheckResult.diagnosis` (``"shape"``,
        ``"symbols"``, ``"error"``, ...).
    message : str
        What a student reads: what was expected and what came in.
    """

    def __init__(self, code: str, message: str):
        super().__init__(message)
        self.code = code
        self.message = message


# ---------------------------------------------------------------- variables
_GREEK = {
    "alpha": "\u03b1", "beta": "\u03b2", "gamma": "\u03b3", "theta": "\u03b8",
    "phi": "\u03c6", "psi": "\u03c8",
}


@dataclass(frozen=True)
class Variable:
    """One scalar input of a check.

    Parameters
    ----------
    name : str
        Name used for matching sympy symbols and in messages (``"alpha"``).
    kind : {'angle', 'length', 'other'}
        Angles get the degree diagnoses and are printed in radians.
    low, high : float
        Sampling interval.
    aliases : tuple of str
        Other accepted symbol names (e.g. ``("q1", "α")``).
    """

    name: str
    kind: str = "angle"
    low: float = -math.pi
    high: float = math.pi
    aliases: tuple[str, ...] = ()

    @property
    def label(self) -> str:
        """Pretty name for messages (Greek letter if there is one)."""
        return _GREEK.get(self.name, self.name)

    def names(self) -> set[str]:
        """Every name the variable may be called by in an answer.

        Returns
        -------
        set of str
            ``name``, ``label`` and the aliases, each also without underscores.
        """
        out = {self.name, self.label, *self.aliases}
        return out | {n.replace("_", "") for n in out}


def as_variables(variables: Any) -> list[Variable]:
    """The inputs of a check as :class:`Variable` objects.

    Parameters
    ----------
    variables : None, str, Variable, sympy Symbol or an iterable of them
        Names (``"alpha"``), symbols or ready :class:`Variable` objects.

    Returns
    -------
    list of Variable
        In the given order; empty for ``None``.

    Raises
    ------
    TypeError
        An entry is none of the above.
    """
    if variables is None:
        return []
    if isinstance(variables, (str, Variable)) or not isinstance(variables, Iterable):
        variables = [variables]
    out = []
    for v in variables:
        if isinstance(v, Variable):
            out.append(v)
        elif isinstance(v, str):
            out.append(Variable(v))
        elif hasattr(v, "name"):  # sympy Symbol
            out.append(Variable(str(v.name)))
        else:
            raise TypeError(f"variables must be names, sympy symbols or Variable; got {v!r}")
    return out


# ---------------------------------------------------------------- formatting
def fmt(x: Any, precision: int = 3) -> str:
    """Short, stable text of a number or array for messages (no ``-0``).

    Numbers of magnitude 1e16 and above (a wildly wrong answer) are written in
    scientific notation instead of with hundreds of digits.

    Parameters
    ----------
    x : float or array_like
        A number or an array (any shape).
    precision : int, optional
        Decimals kept.

    Returns
    -------
    str
    """
    raw = np.asarray(x, dtype=float)
    with np.errstate(all="ignore"):
        a = np.round(raw, precision) + 0.0
    a = np.where(np.isfinite(a) | ~np.isfinite(raw), a, raw)

    def one(v: float | np.floating) -> str:
        value = float(v)
        if abs(value) >= 1e16 and math.isfinite(value):
            return np.format_float_scientific(value, precision=precision, trim="-")
        return np.format_float_positional(value, precision=precision, trim="-")

    if a.ndim == 0:
        return one(float(a))
    return np.array2string(a, separator=", ", formatter={"float_kind": one})


def _entry(idx: tuple[int, ...]) -> str:
    """1-based entry label: (2, 3) or [2]."""
    if len(idx) == 1:
        return f"[{idx[0] + 1}]"
    return "(" + ", ".join(str(i + 1) for i in idx) + ")"


def _shape_text(shape: tuple[int, ...]) -> str:
    if len(shape) == 0:
        return "a number"
    if len(shape) == 1:
        return f"a vector of length {shape[0]}"
    return "a " + "\u00d7".join(str(s) for s in shape) + " matrix"


# ---------------------------------------------------------------- answers
def _sympy():
    return sys.modules.get("sympy")


def _is_sympy(x: Any) -> bool:
    sp = _sympy()
    if sp is None:
        return False
    if isinstance(x, (sp.Basic, sp.MatrixBase)):
        return True
    if isinstance(x, (list, tuple)):
        return any(_is_sympy(e) for e in x)
    if isinstance(x, np.ndarray) and x.dtype == object:
        return any(_is_sympy(e) for e in x.ravel())
    return False


def to_float_array(out: Any, what: str) -> np.ndarray:
    """A student's value (number, array, nested list, sympy expression or matrix) as floats.

    Parameters
    ----------
    out : object
        The value an answer produced.
    what : str
        Its name, for the message.

    Returns
    -------
    numpy.ndarray
        Float array of the value's shape (0-d for a number).

    Raises
    ------
    AnswerError
        Symbols left after substitution, complex or non-numeric entries; ``None`` (a
        function that ends without ``return``).
    """
    if out is None:
        raise AnswerError("error", f"{what} is None: did you forget `return`?")
    sp = _sympy()
    if sp is not None and _is_sympy(out):
        try:
            if isinstance(out, sp.Basic):
                return np.array(float(out.evalf()))
            return np.array(sp.Matrix(out).evalf().tolist(), dtype=float)
        except (TypeError, ValueError):
            raise AnswerError(
                "symbols", f"{what} still contains symbols after substituting numbers: {out}"
            ) from None
    try:
        a = np.asarray(out)
        if a.dtype.kind == "c":
            raise AnswerError("error", f"{what} has complex entries; expected real numbers.")
        return np.array(a, dtype=float)
    except (TypeError, ValueError):
        raise AnswerError("error", f"{what} is not numeric (got {type(out).__name__}).") from None


def _match_symbols(free: set, variables: list[Variable], name: str) -> list:
    """Return, per variable, the student's symbol standing for it (or None)."""
    by_var: list = [None] * len(variables)
    unmatched = []
    for s in sorted(free, key=lambda s: s.name):
        hit = [i for i, v in enumerate(variables) if s.name in v.names()]
        if hit and by_var[hit[0]] is None:
            by_var[hit[0]] = s
        else:
            unmatched.append(s)
    if unmatched:
        open_vars = [i for i, s in enumerate(by_var) if s is None]
        if len(unmatched) == 1 and len(open_vars) == 1:
            by_var[open_vars[0]] = unmatched[0]  # one unknown symbol, one free slot
        else:
            expected = ", ".join(v.name for v in variables) or "no symbols (a constant)"
            got = ", ".join(sorted(s.name for s in unmatched))
            raise AnswerError(
                "symbols",
                f"{name} contains the symbol(s) {got}; expected an expression in {expected}.",
            )
    return by_var


@dataclass
class _Evaluator:
    """Numeric view of an answer: ``values (nvars,) -> ndarray``."""

    fn: Callable[[np.ndarray], np.ndarray]
    form: str  # 'function', 'sympy', 'constant'


def _sympy_evaluator(expr: Any, variables: list[Variable], name: str) -> _Evaluator:
    sp = _sympy()
    if isinstance(expr, (list, tuple, np.ndarray)):
        expr = sp.Matrix(expr)
    free = set(expr.free_symbols)
    by_var = _match_symbols(free, variables, name)
    used = [(i, s) for i, s in enumerate(by_var) if s is not None]
    if not used:
        const = to_float_array(expr, name)
        return _Evaluator(lambda x: const, "constant")
    f = sp.lambdify([s for _, s in used], expr, modules="numpy")
    idx = [i for i, _ in used]
    shape = expr.shape if isinstance(expr, sp.MatrixBase) else ()

    def fn(x: np.ndarray) -> np.ndarray:
        out = np.array(f(*[float(x[i]) for i in idx]), dtype=float)
        return out.reshape(shape) if shape else out

    return _Evaluator(fn, "sympy")


def _required_positional(f: Callable) -> int | None:
    try:
        sig = inspect.signature(f)
    except (TypeError, ValueError):
        return None
    n = 0
    for p in sig.parameters.values():
        if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD) and p.default is p.empty:
            n += 1
        elif p.kind == p.VAR_POSITIONAL:
            return None
    return n


def _function_evaluator(
    f: Callable, variables: list[Variable], groups: list[tuple[str, list[int]]], name: str
) -> _Evaluator:
    nvar = len(variables)
    grouped = lambda x: tuple(np.asarray(x[idx], dtype=float) for _, idx in groups)  # noqa: E731
    scalars = lambda x: tuple(float(v) for v in x)  # noqa: E731
    single = lambda x: (np.asarray(x, dtype=float),)  # noqa: E731
    k = _required_positional(f)
    if groups and len(groups) != nvar:
        cand = [("groups", grouped), ("scalars", scalars)]
    else:
        cand = [("scalars", scalars), ("single", single)]
    if k is not None:
        ranked = [c for c in cand if len(c[1](np.zeros(nvar))) == k]
        cand = ranked + [c for c in cand if c not in ranked]
    styles = cand
    chosen: list = []

    def fn(x: np.ndarray) -> np.ndarray:
        if chosen:
            try:
                out = f(*chosen[0](x))
            except Exception as exc:  # noqa: BLE001 - report the student's error
                raise AnswerError(
                    "error", f"calling {name} raised {type(exc).__name__}: {exc}"
                ) from None
            return to_float_array(out, f"the value returned by {name}")
        first_error = None
        for _, style in styles:
            try:
                out = f(*style(x))
            except Exception as exc:  # noqa: BLE001 - report the student's error
                first_error = first_error or exc
                continue
            chosen.append(style)
            return to_float_array(out, f"the value returned by {name}")
        raise AnswerError(
            "error",
            f"calling {name} raised {type(first_error).__name__}: {first_error}",
        )

    return _Evaluator(fn, "function")


def evaluator(answer: Any, variables: list[Variable], groups, name: str) -> _Evaluator:
    """A callable ``values (N, len(variables)) -> answers (N, ...)`` for any form of answer.

    Parameters
    ----------
    answer : sympy expression or matrix, function or array_like
        A sympy answer is lambdified in ``variables``; a function is called with
        the variables (as one argument per variable or per group of ``groups``);
        an array is a constant.
    variables : list of Variable
        The check's inputs.
    groups : list of (str, list of int)
        Named groups of variable indices: the arguments of a function answer
        when it takes one argument per group (else one per variable).
    name : str
        Name of the answer, for messages.

    Returns
    -------
    _Evaluator
        The evaluating function and the answer's form (``"sympy"``,
        ``"function"`` or ``"constant"``).

    Raises
    ------
    AnswerError
        ``answer`` is None or cannot be evaluated.
    """
    if answer is None:
        raise AnswerError("error", f"{name} is None: did you forget to return or assign it?")
    if _is_sympy(answer):
        return _sympy_evaluator(answer, variables, name)
    if callable(answer) and not isinstance(answer, np.ndarray):
        return _function_evaluator(answer, variables, groups, name)
    const = to_float_array(answer, name)
    return _Evaluator(lambda x: const, "constant")


# ---------------------------------------------------------------- diagnoses
@dataclass(frozen=True)
class Mistake:
    """One typical mistake: the reference transformed into the mistaken answer.

    Attributes
    ----------
    code : str
        Diagnosis code (e.g. ``"transpose"``).
    transform : callable
        ``transform(reference)`` returns the function ``values (N, nvars) -> array``
        a student making this mistake would have written.
    message : str
        The explanation; ``{name}`` is replaced by the name of the check.
    """

    code: str
    transform: Callable[[RefFn], RefFn]
    message: str


@dataclass
class Context:
    """What a diagnosis may look at.

    Attributes
    ----------
    check : Check
        The check being run.
    reference : callable
        ``values (N, nvars) -> reference answers (N, ...)``.
    X : numpy.ndarray, shape (N, nvars)
        The sample points.
    R, S : numpy.ndarray, shape (N, ...)
        Reference and student values at ``X``.
    form : str
        Form of the student's answer (``"sympy"``, ``"function"``, ``"constant"``).
    """

    check: Check
    reference: RefFn
    X: np.ndarray  # samples (N, nvars)
    R: np.ndarray  # reference values (N, ...)
    S: np.ndarray  # student values (N, ...)
    form: str  # form of the student's answer


@dataclass(frozen=True)
class Diagnosis:
    """A family of mistakes.

    Attributes
    ----------
    code : str
        Diagnosis code of the family.
    variants : callable
        ``variants(ctx: Context)`` yields the :class:`Mistake` objects to compare
        the student's values with.
    """

    code: str
    variants: Callable[[Context], Iterable[Mistake]]


def mistake(code: str, transform: Callable[[RefFn], RefFn], message: str) -> Diagnosis:
    """A diagnosis with one variant: ``transform`` maps the reference to the mistake.

    Parameters
    ----------
    code : str
        The diagnosis code reported in :attr:`CheckResult.diagnosis` (e.g. ``"transpose"``).
    transform : callable
        Maps the reference function (inputs (nvars,) to an array) to the
        mistaken function.
    message : str
        What the student is told; ``{name}`` is replaced by the answer's name.

    Returns
    -------
    Diagnosis
    """
    m = Mistake(code, transform, message)
    return Diagnosis(code, lambda ctx: [m])


def alternatives(code: str, items: Sequence[tuple[RefFn, str]]) -> Diagnosis:
    """A diagnosis from ready-made mistaken functions ``[(fn, message), ...]``.

    Use it when the mistake is easier to write directly than as a transform of
    the reference (a rotation about another axis, the factors of a product in
    another order, a controller without its feed-forward term).

    Parameters
    ----------
    code : str
        The diagnosis code reported in :attr:`CheckResult.diagnosis`.
    items : sequence of (callable, str)
        Mistaken functions of the check's inputs (nvars,) and the message of each
        (``{name}`` is replaced by the answer's name).

    Returns
    -------
    Diagnosis
    """
    ms = [Mistake(code, (lambda f: (lambda ref: f))(fn), msg) for fn, msg in items]
    return Diagnosis(code, lambda ctx: ms)


def _values(fn: RefFn, X: np.ndarray) -> np.ndarray | None:
    try:
        with np.errstate(all="ignore"):
            return np.stack([np.asarray(fn(x), dtype=float) for x in X])
    except Exception:  # noqa: BLE001 - a mistake that cannot be evaluated does not apply
        return None


# ---------------------------------------------------------------- the check
def _close(a: np.ndarray, b: np.ndarray, atol: float, rtol: float) -> bool:
    if a.shape != b.shape or not bool(np.all(np.isfinite(a))):
        return False
    with np.errstate(all="ignore"):  # answers near 1e308 must not warn
        return bool(np.allclose(a, b, atol=atol, rtol=rtol))


def _normalise_vector(S: np.ndarray, ref_shape: tuple[int, ...]) -> np.ndarray:
    """Treat (n,), (n, 1) and (1, n) as the same vector (S has a leading sample axis)."""
    if len(ref_shape) == 1 and S.ndim == 3 and 1 in S.shape[1:]:
        return S.reshape(S.shape[0], -1)
    if len(ref_shape) == 2 and 1 in ref_shape and S.ndim == 2 and S.shape[1] == max(ref_shape):
        return S.reshape((S.shape[0],) + ref_shape)
    return S


@dataclass(repr=False)
class Check:
    """An exercise check: a reference, its inputs and the mistakes to look for.

    Call it with the student's answer: ``check(answer) -> CheckResult``.

    Parameters
    ----------
    name : str
        Shown in messages, e.g. ``"R_B1"``.
    reference : callable
        ``reference(values) -> ndarray`` with ``values`` of shape ``(nvars,)``.
    variables : list of Variable
        Scalar inputs (empty for a constant).
    groups : list of (name, indices)
        How a Python function of vectors is called, e.g. ``[("q", [0, 1, 2])]``.
    diagnoses : list of Diagnosis
        Tried in order after the shape check.
    at : array_like, optional
        Fixed input: the check compares at this one point only (numeric answers).
    samples, seed : int
        Number of random inputs and the seed of their generator.
    atol, rtol : float
        Tolerances of the comparison.
    noun : str
        Completes "checked at 20 random ..." (``"angles"``, ``"configurations"``).
    at_text : str
        How the fixed input is described in messages (``"q = [0°, 60°, -120°]"``).
    hint : str
        Appended to the message when no diagnosis explains a wrong answer.
    values_shown : bool
        Whether that message gives an example value, what the reference has and what the
        answer has (the default). ``False`` for a check of numbers the statement asks for at
        one input (``at``, or no variables): the reference there is the answer itself, so a
        wrong attempt is told which entries differ, and the ``hint``, never their values.
    """

    name: str
    reference: RefFn
    variables: list[Variable] = field(default_factory=list)
    groups: list[tuple[str, list[int]]] = field(default_factory=list)
    diagnoses: list[Diagnosis] = field(default_factory=list)
    at: Any = None
    samples: int = 20
    seed: int = 0
    atol: float = 1e-8
    rtol: float = 1e-6
    noun: str = "inputs"
    at_text: str = ""
    hint: str = ""
    doc: str = ""
    values_shown: bool = True

    def __post_init__(self) -> None:
        self.variables = as_variables(self.variables)
        if self.doc:
            self.__doc__ = self.doc

    # -- inputs
    def sample_points(self) -> np.ndarray:
        """The inputs used for the comparison.

        Returns
        -------
        numpy.ndarray, shape (N, nvars)
            The given points (``at``), else ``samples`` random points within the
            variables' ranges (seeded: the same on every run).
        """
        if self.at is not None:
            return np.atleast_2d(np.asarray(self.at, dtype=float))
        if not self.variables:
            return np.zeros((1, 0))
        rng = np.random.default_rng(self.seed)
        lo = np.array([v.low for v in self.variables])
        hi = np.array([v.high for v in self.variables])
        return lo + (hi - lo) * rng.random((self.samples, len(self.variables)))

    def _where(self, X: np.ndarray) -> str:
        if self.at is not None or not self.variables:
            return ""
        noun = self.noun if len(X) > 1 else self.noun.rstrip("s")
        return f" (checked at {len(X)} random {noun})"

    def _point_text(self, x: np.ndarray) -> str:
        if self.at is not None and self.at_text:
            return self.at_text
        return ", ".join(f"{v.label} = {fmt(xi)}" for v, xi in zip(self.variables, x))

    # -- the call
    def __repr__(self) -> str:
        """The check's name only, in ``help()`` and under a cell that ends with the check.

        The dataclass repr listed every field, the messages of the typical mistakes among
        them, which hold the answer's formula, before the student had answered.
        """
        return f"<robokin check of {self.name}>"

    def __call__(
        self, answer: Any, *, raise_on_fail: bool = False, quiet: bool = False
    ) -> CheckResult:
        """Compare ``answer`` with the reference; print and return the result."""
        return report(self.evaluate(answer), raise_on_fail=raise_on_fail, quiet=quiet)

    def evaluate(self, answer: Any) -> CheckResult:
        """Like calling the check, but neither prints nor raises.

        Parameters
        ----------
        answer : object
            The student's answer: a function, a sympy expression or matrix, or numbers.

        Returns
        -------
        CheckResult
        """
        X = self.sample_points()
        reference = self.reference
        R = np.stack([np.asarray(reference(x), dtype=float) for x in X])
        if R.ndim == 3 and 1 in R.shape[1:]:  # a column or row vector: treat as (n,)
            R = R.reshape(R.shape[0], -1)
            reference = (lambda f: lambda x: np.asarray(f(x), dtype=float).ravel())(reference)
        try:
            ev = evaluator(answer, self.variables, self.groups, self.name)
            values = [ev.fn(x) for x in X]
            if len({v.shape for v in values}) > 1:
                raise AnswerError(
                    "shape", f"{self.name} returns arrays of different shapes for different inputs."
                )
            S = np.stack(values)
        except AnswerError as exc:
            return self._fail(exc.code, exc.message, len(X))
        S = _normalise_vector(S, R.shape[1:])
        if _close(S, R, self.atol, self.rtol):
            at = f" at {self.at_text}" if self.at is not None and self.at_text else ""
            return CheckResult(
                self.name, True, f"{PASS} {self.name}{at} is correct{self._where(X)}.",
                None, len(X),
            )
        with np.errstate(all="ignore"):
            ref_varies = len(X) > 1 and not np.allclose(R, R[:1], atol=self.atol, rtol=self.rtol)
        if ev.form == "constant" and self.at is None and ref_varies:
            names = ", ".join(v.label for v in self.variables)
            return self._fail(
                "constant",
                f"{self.name} should depend on {names}, but your answer is a constant "
                f"array. Give a sympy expression or a Python function of {names}.",
                len(X),
            )
        if not np.all(np.isfinite(S)):
            return self._fail(
                "error", f"{self.name} gives NaN or infinite values.", len(X)
            )
        ctx = Context(self, reference, X, R, S, ev.form)
        with np.errstate(all="ignore"):  # a wildly wrong answer (1e308) must not make numpy warn
            for diag in self.diagnoses:
                for m in diag.variants(ctx):
                    M = _values(m.transform(reference), X)
                    if M is None or M.shape != S.shape or _close(M, R, self.atol, self.rtol):
                        continue
                    if _close(S, M, self.atol, self.rtol):
                        return self._fail(m.code, m.message.format(name=self.name), len(X))
            if S.shape[1:] != R.shape[1:]:
                return self._fail("shape", self._shape_message(S, R), len(X))
            return self._fail("mismatch", self._mismatch_message(X, S, R), len(X))

    def _fail(self, code: str, text: str, n: int) -> CheckResult:
        first = text[:1]
        if first.isascii() and first.islower() and not text.startswith(self.name):
            text = first.upper() + text[1:]
        return CheckResult(self.name, False, f"{FAIL} {text}", code, n)

    def _shape_message(self, S: np.ndarray, R: np.ndarray) -> str:
        want, got = R.shape[1:], S.shape[1:]
        msg = (
            f"{self.name} should be {_shape_text(want)}; your answer is {_shape_text(got)} "
            f"(shape {got})."
        )
        if len(got) == len(want) and all(g >= w for g, w in zip(got, want)):
            block = S[(slice(None),) + tuple(slice(0, w) for w in want)]
            if _close(block, R, self.atol, self.rtol) and len(want) == 1:
                msg += (
                    f" Its first {want[0]} entries are right: drop the rest (the trailing 1 "
                    "of homogeneous coordinates?)."
                )
            elif _close(block, R, self.atol, self.rtol):
                msg += (
                    f" Its top-left {'×'.join(map(str, want))} block is right: "
                    f"{self.name} is only that block."
                )
        elif want == (4, 4) and got == (3, 3):
            msg += " A homogeneous transform is 4×4: [[R, p], [0, 0, 0, 1]]."
        return msg

    def _mismatch_message(self, X: np.ndarray, S: np.ndarray, R: np.ndarray) -> str:
        with np.errstate(all="ignore"):
            bad = ~np.isclose(S, R, atol=max(self.atol, 1e-9), rtol=self.rtol)
        k = int(np.argmax(bad.reshape(len(X), -1).any(axis=1)))
        where = self._point_text(X[k])
        where = f" at {where}" if where else ""
        if not self.values_shown:
            return self._hidden_values_message(where, bad, R)
        if R.ndim == 1 or R[0].size == 1:   # one number per input: no entries to name
            return (
                f"{self.name} is not correct{where}: expected {fmt(R[k])}, got {fmt(S[k])}."
                + (f" {self.hint}" if self.hint else "")
            )
        wrong = [tuple(int(i) for i in idx) for idx in zip(*np.nonzero(bad.any(axis=0)))]
        if len(wrong) == R[0].size:
            head = f"{self.name} is not correct: every entry differs from the reference."
        else:
            head = f"{self.name} is not correct: {self._entries_text(wrong)} from the reference."
        # the first entry that is wrong at the example's sample k
        i0 = next(i for i in wrong if bad[k][i])
        want, got = fmt(R[k][i0]), fmt(S[k][i0])
        if want == got:  # they differ beyond the digits shown
            want, got = fmt(R[k][i0], 9), fmt(S[k][i0], 9)
        ex = f" For example{where}: {self._entry_text(i0)} should be {want}, yours is {got}."
        return head + ex + (f" {self.hint}" if self.hint else "")

    def _hidden_values_message(self, where: str, bad: np.ndarray, R: np.ndarray) -> str:
        """The mismatch message of a check whose values are the answer (``values_shown=False``):
        the entries that differ (at any sample) and the hint, no value of the reference."""
        hint = f" {self.hint}" if self.hint else ""
        if R.ndim == 1 or R[0].size == 1:
            return f"{self.name} is not correct{where}.{hint}"
        wrong = [tuple(int(i) for i in idx) for idx in zip(*np.nonzero(bad.any(axis=0)))]
        what = "every entry differs" if len(wrong) == R[0].size else self._entries_text(wrong)
        return f"{self.name} is not correct{where}: {what}.{hint}"

    def _entries_text(self, wrong: list[tuple[int, ...]]) -> str:
        """The wrong entries, for the head of a message: ``"entries [1], [3] differ"``."""
        ent = ", ".join(_entry(i) for i in wrong[:6]) + (" ..." if len(wrong) > 6 else "")
        return f"entr{'y' if len(wrong) == 1 else 'ies'} {ent} differ{'s' if len(wrong) == 1 else ''}"

    def _entry_text(self, idx: tuple[int, ...]) -> str:
        """One entry, for the example of a message: ``"entry [2]"``."""
        return f"entry {_entry(idx)}"


def not_a_function(name: str, signature: str, answer: Any) -> CheckResult:
    """The verdict on an answer that should be a function and is not (diagnosis ``"constant"``).

    Parameters
    ----------
    name : str
        The check's name.
    signature : str
        The expected call, e.g. ``"weighted_pinv(J, W) -> (n, m) array"``.
    answer : object
        What came in instead.

    Returns
    -------
    CheckResult
        ``"✘ <name> should be a Python function <signature>; got <type>."``, 0 samples.
    """
    return CheckResult(name, False, f"{FAIL} {name} should be a Python function {signature}; "
                       f"got {type(answer).__name__}.", "constant", 0)


@dataclass(repr=False)
class MatrixArgumentsCheck(Check):
    """A :class:`Check` whose answer is a function of arrays (matrices, vectors, gains).

    ``arguments(x)`` turns the sampled scalars ``x`` (shape ``(nvars,)``) into the
    arguments of the student's function, e.g. ``(J, W)``; the answer is called as
    ``answer(*arguments(x))``, and its value, passed through ``pack`` when there is one,
    is compared with ``reference(x)``. Anything that is not a function fails with a
    message quoting ``signature``; ``None`` goes to :meth:`Check.evaluate`, which
    explains it. ``groups`` plays no part: the answer's arguments are ``arguments(x)``.

    Parameters
    ----------
    arguments : callable, optional
        ``arguments(x) -> tuple`` of the student's function's arguments.
    signature : str
        The expected call, e.g. ``"weighted_pinv(J, W) -> (6, 3) array"``.
    pack : callable, optional
        ``pack(value) -> array``: what of the answer's value is compared, when it is not
        the value itself: a loop's ``(q, converged, iterations)`` as one vector, its
        iterates flattened, the pose its joint angles reach. The reference returns the
        same packed form; an exception ``pack`` raises (a ``TypeError`` that says what
        the value should be) is reported like one the answer raised.
    describe : callable, optional
        ``describe(x) -> str``: the call at the sample ``x`` in the student's terms
        (``"newton_ik(r_goal = [...], q0 = [...], ...)"``), written in a failure's example
        instead of the sampled scalars.
    entry_label : callable, optional
        ``entry_label(idx) -> str``: what entry ``idx`` of the packed value is, in the
        student's terms (``"the number of steps K"``), instead of its index.
    """

    arguments: Callable[[np.ndarray], tuple] | None = None
    signature: str = ""
    pack: Callable[[Any], Any] | None = None
    describe: Callable[[np.ndarray], str] | None = None
    entry_label: Callable[[tuple[int, ...]], str] | None = None

    def _point_text(self, x: np.ndarray) -> str:
        if self.describe is not None:
            return self.describe(x)
        return super()._point_text(x)

    def _entries_text(self, wrong: list[tuple[int, ...]]) -> str:
        if self.entry_label is None:
            return super()._entries_text(wrong)
        names = list(dict.fromkeys(self.entry_label(i) for i in wrong))  # once each, in order
        shown = ", ".join(names[:6]) + (" ..." if len(names) > 6 else "")
        return f"{shown} differ{'s' if len(wrong) == 1 else ''}"

    def _entry_text(self, idx: tuple[int, ...]) -> str:
        return super()._entry_text(idx) if self.entry_label is None else self.entry_label(idx)

    def evaluate(self, answer: Any) -> CheckResult:
        """Call ``answer(*arguments(x))`` at the sample points and compare (see :meth:`Check.evaluate`)."""
        if callable(answer) and not isinstance(answer, np.ndarray) and self.arguments is not None:
            build, student, pack = self.arguments, answer, self.pack

            def call_with_arguments(x: np.ndarray) -> Any:
                out = student(*build(np.asarray(x, dtype=float)))
                return out if pack is None else pack(out)

            return super().evaluate(call_with_arguments)
        if answer is not None and not callable(answer):
            return not_a_function(self.name, self.signature, answer)
        return super().evaluate(answer)


def with_reference_steps(answer: Any, steps: dict[str, Callable[..., Any]]) -> Any:
    """``answer`` with robokin's earlier steps passed for those of its keyword parameters that
    ``steps`` names (the student's own steps are their defaults), so that a check judges this
    step alone (and the grading report blames no later step for an earlier one); ``answer``
    itself when it has none of them or no signature.

    Parameters
    ----------
    answer : callable
        The student's function, e.g. ``poe_fk(screws, M, q, exp6=exp6)``.
    steps : dict
        ``{parameter name: robokin's step}``, e.g. ``{"exp6": reference_exp6}``.
    """
    try:
        parameters = inspect.signature(answer).parameters
    except (TypeError, ValueError):
        return answer
    given = {name: step for name, step in steps.items() if name in parameters}
    return functools.partial(answer, **given) if given else answer


@dataclass(repr=False)
class LaterStepCheck(MatrixArgumentsCheck):
    """A :class:`MatrixArgumentsCheck` of a function that builds on earlier steps: it is called
    with robokin's steps (``steps()``, by the names of its keyword parameters: ``skew=``,
    ``exp6=``, ...; :func:`with_reference_steps`) in place of the student's."""

    steps: Callable[[], dict[str, Callable[..., Any]]] = dict

    def evaluate(self, answer: Any) -> CheckResult:
        """:meth:`MatrixArgumentsCheck.evaluate` of ``answer`` given robokin's earlier steps."""
        if callable(answer) and not isinstance(answer, np.ndarray):
            answer = with_reference_steps(answer, self.steps())
        return super().evaluate(answer)


class _Refused(Exception):
    """Carries the verdict of a :class:`FunctionCheck` out of its ``judge`` (see :meth:`FunctionCheck.call`)."""

    def __init__(self, result: CheckResult):
        super().__init__(result.message)
        self.result = result


def _no_reference(x: np.ndarray) -> np.ndarray:
    """The reference of a check that compares in its own ``judge``: never used for a verdict."""
    return np.zeros(1)


@dataclass(repr=False)
class FunctionCheck(Check):
    """A check whose answer is a Python function that it calls on inputs of its own.

    The design: the base class holds what every such check repeats -- refusing ``None``
    and anything that is not a function (the messages below, quoting ``signature``),
    calling the answer and reporting what it raised, building the ``✔``/``✘`` messages,
    trying a table of typical mistakes -- and a subclass writes only :meth:`judge`: its
    inputs (seeded cases, or :meth:`Check.sample_points`), its comparison and its
    mistakes, with :meth:`call`, :meth:`success`, :meth:`failure` and :meth:`diagnose`.
    :meth:`call` ends ``judge`` by itself when the answer raises (no result to test
    after every call); :meth:`failure` keeps the text as written (no capital added), so
    that a check moved onto this class prints what it printed before.

    Use it where the answer cannot be compared as values of the check's variables:
    a loop whose result has several parts, a function returning every solution or a
    dict of figures, a function that must raise. Where it can (a function of arrays
    whose value, packed into one array, equals a reference), a :class:`MatrixArgumentsCheck`
    with ``pack`` is shorter and brings the generic diagnoses.

    Parameters
    ----------
    name, variables, groups, samples, seed, noun, doc
        As for :class:`Check`; ``variables`` only where :meth:`judge` samples them.
    reference : callable, optional
        Unused by the verdict (``judge`` compares); kept for what reads every check.
    signature : str
        The expected call, e.g. ``"bisect(f, low, high, tol=1e-13) -> x"``, quoted when
        the answer is not a function (and by :func:`robokin.check.grading.expected_form`).

    Notes
    -----
    ``None`` fails with ``"<name> is None: did you forget to define it?"`` (diagnosis
    ``"error"``), another non-function with ``"<name> should be a Python function
    <signature>; got <type>."`` (``"constant"``); neither calls :meth:`judge`.
    """

    reference: RefFn = _no_reference
    signature: str = ""

    def evaluate(self, answer: Any) -> CheckResult:
        """Refuse ``None`` or a non-function, else :meth:`judge` the answer (neither prints nor raises)."""
        if answer is None:
            return self.failure("error", f"{self.name} is None: did you forget to define it?", 0)
        if not callable(answer):
            return not_a_function(self.name, self.signature, answer)
        try:
            return self.judge(answer)
        except _Refused as refused:
            return refused.result

    def judge(self, answer: Callable[..., Any]) -> CheckResult:
        """The verdict on a function ``answer``; written by each subclass.

        Parameters
        ----------
        answer : callable
            The student's function (never ``None``).

        Returns
        -------
        CheckResult
        """
        raise NotImplementedError(f"{type(self).__name__} must define judge(answer)")

    def call(self, answer: Callable[..., Any], arguments: tuple, where: str = "", samples: int = 1) -> Any:
        """``answer(*arguments)``; what it raises ends :meth:`judge` with a failure that says where.

        Parameters
        ----------
        answer : callable
            The student's function.
        arguments : tuple
            Its arguments (pass copies of arrays the check reuses).
        where : str, optional
            Where the call was, after the name: ``"for f(x) = x³ − 2 on [0, 2]"``.
        samples : int, optional
            The failure's :attr:`CheckResult.samples`.

        Returns
        -------
        object
            What the answer returned.
        """
        try:
            return answer(*arguments)
        except Exception as exc:  # noqa: BLE001 - report the student's error
            place = f" {where}" if where else ""
            raise _Refused(self.failure(
                "error", f"calling {self.name}{place} raised {type(exc).__name__}: {exc}", samples)) from None

    def success(self, text: str, samples: int) -> CheckResult:
        """A passed result whose message is ``"✔ " + text``."""
        return CheckResult(self.name, True, f"{PASS} {text}", None, samples)

    def failure(self, code: str, text: str, samples: int) -> CheckResult:
        """A failed result with diagnosis ``code`` whose message is ``"✘ " + text`` (as written)."""
        return CheckResult(self.name, False, f"{FAIL} {text}", code, samples)

    def diagnose(self, mistakes: Iterable[tuple[str, str]], explains: Callable[[str], bool],
                 samples: int) -> CheckResult | None:
        """The failure of the first mistake that ``explains`` the answer, or None.

        Parameters
        ----------
        mistakes : iterable of (str, str)
            ``(code, message)``; ``{name}`` in the message is replaced by the check's name.
        explains : callable
            ``explains(code) -> bool``: the answer equals what the mistake ``code`` gives
            (on every case).
        samples : int
            The failure's :attr:`CheckResult.samples`.

        Returns
        -------
        CheckResult or None
            Test it with ``is not None``: a failed :class:`CheckResult` is falsy.
        """
        for code, text in mistakes:
            if explains(code):
                return self.failure(code, text.format(name=self.name), samples)
        return None


# ---------------------------------------------------------------- loops checked by their packed value
def pack_joint_rows(function: str, samples: int, joints: int) -> Callable[[Any], np.ndarray]:
    """A ``pack`` for a loop that returns the joint angles at its samples, one row a sample.

    Parameters
    ----------
    function : str
        The student's function as the messages name it (``"track"``).
    samples : int
        N, the rows expected: one per sample of the reference ``r_des``.
    joints : int
        n, the joint count: the columns expected.

    Returns
    -------
    callable
        ``pack(value) -> (N n,) array``: the rows flattened; a ``TypeError`` that says what the
        value should be when it is a tuple or not of shape ``(N, n)`` (see
        :class:`MatrixArgumentsCheck`).
    """
    def pack(out: Any) -> np.ndarray:
        if isinstance(out, tuple):
            raise TypeError(f"{function} should return one array of joint angles (N, {joints}), not a tuple of "
                            f"{len(out)} items")
        rows = np.asarray(out, dtype=float)
        if rows.shape != (samples, joints):
            raise TypeError(f"{function} should return the joint angles at the N = {samples} samples of r_des, "
                            f"shape ({samples}, {joints}); got shape {rows.shape}")
        return rows.ravel()

    return pack


def packed_variants(loop: Callable[..., Any], arguments: Callable[[np.ndarray], tuple],
                    pack: Callable[[Any], Any]) -> Callable[..., RefFn]:
    """The reference of a loop check and its typical mistakes, from one written-out loop.

    Parameters
    ----------
    loop : callable
        ``loop(*arguments(x), **mistake)``: the reference loop; its keywords turn it into a mistake.
    arguments : callable
        ``arguments(x) -> tuple``, as the check's (see :class:`MatrixArgumentsCheck`).
    pack : callable
        The check's ``pack``.

    Returns
    -------
    callable
        ``variant(**mistake) -> (x -> pack(loop(*arguments(x), **mistake)))``: ``variant()`` is the
        reference, ``variant(sign=-1.0)`` the loop with that mistake.
    """
    def variant(**mistake: Any) -> RefFn:
        return lambda x: pack(loop(*arguments(x), **mistake))

    return variant


# ---------------------------------------------------------------- generic entry points
