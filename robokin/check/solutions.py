r"""Ready-made checks for answers that are *a* solution or *the set of* solutions.

Inverse kinematics has many right answers: a redundant arm reaches a target in
infinitely many postures, a six-joint arm in up to sixteen, and a student's
solver may return any of them. These checks accept every right answer:

- :func:`ik_solution`: a configuration ``q`` is right when ``chain.fk(q)``
  reaches the target (position, or full pose) within a tolerance, and lies
  within the joint limits;
- :func:`solution_set`: a set of solutions (rows, any order, angles equal up to
  multiples of 2π when ``angles=True``) is right when it holds every reference
  solution once and nothing else;
- :class:`SolutionSetCheck`: the same for a *function* that returns every solution,
  compared at random inputs -- a chapter check registered with ``exercise(...)``; with a
  reference of one row, it checks an answer whose angles count modulo 2π.

Like :func:`robokin.check.value`, they print one line (``quiet=True`` silences
it), return a :class:`~robokin.check.CheckResult` with a diagnosis code when the
answer is wrong (``"shape"``, ``"not_finite"``, ``"degrees"``, ``"limits"``,
``"misses_target"``, ``"missing"``, ``"extra"``, ``"duplicate"``), and raise an
``AssertionError`` with ``raise_on_fail=True`` -- so that an instructor's
chapter check is one line (see the authoring page of the book).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np

from robokin.check._core import FAIL, PASS, AnswerError, Check, CheckResult, evaluator, report
from robokin.validation import as_float_array, check_chain, check_positive

__all__ = ["ik_solution", "solution_set", "SolutionSetCheck"]


def _as_answer(answer: Any, name: str, width: int) -> tuple[np.ndarray | None, str]:
    """The answer as a float array of rows of ``width``, or None and what is wrong with it."""
    if callable(answer) or isinstance(answer, (str, bytes, dict)) or np.iscomplexobj(answer):
        return None, f"{name} must be an array of real numbers; got {type(answer).__name__}"
    try:
        with np.errstate(all="ignore"):
            a = np.asarray(answer, dtype=float)
    except (TypeError, ValueError, OverflowError):
        return None, f"{name} must be an array of real numbers; got {type(answer).__name__}"
    if a.ndim == 0 or a.shape[-1] != width or a.ndim > 2:
        return None, f"{name} must have shape ({width},) or (k, {width}); got shape {a.shape}"
    if not np.all(np.isfinite(a)):
        return None, f"{name} has NaN or infinite entries"
    return a, ""


def _pose_error(chain: Any, q: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    """(position error in m, orientation error in rad) of ``chain.fk(q)`` against ``target``."""
    T = np.asarray(chain.fk(q), dtype=float)
    if target.shape == (3,):
        return float(np.linalg.norm(T[:3, 3] - target)), 0.0
    R = target[:3, :3].T @ T[:3, :3]
    angle = float(np.arccos(np.clip((np.trace(R) - 1.0) / 2.0, -1.0, 1.0)))
    return float(np.linalg.norm(T[:3, 3] - target[:3, 3])), angle


def ik_solution(q: Any, chain: Any, target: Any, name: str = "q", *, atol: float = 1e-6,
                limits: bool = True, raise_on_fail: bool = False, quiet: bool = False) -> CheckResult:
    """Check that ``q`` is *an* inverse-kinematics solution: ``chain.fk(q)`` reaches ``target``.

    Parameters
    ----------
    q : array_like, shape (n,)
        The student's configuration (rad for revolute, m for prismatic joints).
    chain : SerialChain
        The robot (anything with ``n``, ``limits`` and ``fk(q)``).
    target : array_like, shape (3,) or (4, 4)
        A position (m): only the tool point must reach it; or a pose: position
        and orientation.
    name : str, optional
        The answer's name in the message.
    atol : float, optional
        Tolerance on the position error (m) and on the orientation error (rad).
    limits : bool, optional
        Require ``q`` within the chain's joint limits (default True).
    raise_on_fail, quiet : bool, optional
        As for every check.

    Returns
    -------
    CheckResult
        Diagnoses: ``"shape"``/``"not_finite"`` (not a configuration),
        ``"degrees"`` (``np.deg2rad(q)`` would reach the target), ``"limits"``,
        ``"misses_target"``.
    """
    check_chain(chain, "chain", methods=("fk",))
    atol = check_positive(atol, "atol", scalar=True)
    goal = as_float_array(target, "target")
    if goal.shape not in ((3,), (4, 4)):
        raise TypeError(f"target must be a position (3,) or a pose (4, 4); got shape {goal.shape}")
    n = int(chain.n)
    a, problem = _as_answer(q, name, n)
    if a is None or a.ndim != 1:
        code = "not_finite" if "NaN" in problem else "shape"
        text = problem or f"{name} must be one configuration of shape ({n},); got shape {np.shape(q)}"
        return report(CheckResult(name, False, f"{FAIL} {text}.", code), raise_on_fail=raise_on_fail, quiet=quiet)
    with np.errstate(all="ignore"):
        dp, dr = _pose_error(chain, a, goal)
    if not (np.isfinite(dp) and np.isfinite(dr)):
        text = f"{FAIL} fk({name}) is not finite: {name} holds values too large to be joint values."
        return report(CheckResult(name, False, text, "not_finite", 1), raise_on_fail=raise_on_fail, quiet=quiet)
    if dp <= atol and dr <= atol:
        lim = np.asarray(chain.limits, dtype=float).reshape(n, 2)
        outside = np.flatnonzero((a < lim[:, 0] - 1e-9) | (a > lim[:, 1] + 1e-9))
        if limits and outside.size:
            k = int(outside[0])
            text = (f"{FAIL} {name} reaches the target but joint {k + 1} is outside its limits: "
                    f"{a[k]:.4g} not in [{lim[k, 0]:.4g}, {lim[k, 1]:.4g}].")
            return report(CheckResult(name, False, text, "limits", 1), raise_on_fail=raise_on_fail, quiet=quiet)
        what = "position" if goal.shape == (3,) else "pose"
        return report(CheckResult(name, True, f"{PASS} {name} reaches the target {what} (error "
                                   f"{max(dp, dr):.1e}).", None, 1), raise_on_fail=raise_on_fail, quiet=quiet)
    with np.errstate(all="ignore"):
        dp_deg, dr_deg = _pose_error(chain, np.deg2rad(a), goal)
    if dp_deg <= atol and dr_deg <= atol:
        text = f"{FAIL} {name} is in degrees: np.deg2rad({name}) reaches the target; robokin works in radians."
        return report(CheckResult(name, False, text, "degrees", 1), raise_on_fail=raise_on_fail, quiet=quiet)
    miss = f"{dp:.3g} m" + (f" and {np.degrees(dr):.3g}°" if goal.shape == (4, 4) else "")
    text = f"{FAIL} fk({name}) misses the target by {miss} (tolerance {atol:g})."
    return report(CheckResult(name, False, text, "misses_target", 1), raise_on_fail=raise_on_fail, quiet=quiet)


def solution_set(solutions: Any, reference: Any, name: str = "solutions", *, atol: float = 1e-6,
                 angles: bool = True, raise_on_fail: bool = False, quiet: bool = False) -> CheckResult:
    """Check a set of solutions against the reference set: each one once, in any order.

    Parameters
    ----------
    solutions : array_like, shape (k, m)
        The student's solutions, one per row (a single row may be given as (m,)).
    reference : array_like, shape (r, m)
        All the right solutions.
    name : str, optional
        The answer's name in the message.
    atol : float, optional
        Two rows are the same solution when every entry differs by at most ``atol``.
    angles : bool, optional
        Entries are angles: equal up to a multiple of 2π (default True).
    raise_on_fail, quiet : bool, optional
        As for every check.

    Returns
    -------
    CheckResult
        Diagnoses: ``"shape"``/``"not_finite"``, ``"duplicate"`` (a solution
        twice), ``"extra"`` (a row that is no solution), ``"missing"``.
    """
    atol = check_positive(atol, "atol", scalar=True)
    ref = as_float_array(reference, "reference")
    ref = ref[None] if ref.ndim == 1 else ref
    if ref.ndim != 2:
        raise TypeError(f"reference must have shape (r, m); got shape {ref.shape}")
    a, problem = _as_answer(solutions, name, ref.shape[1])
    if a is None:
        code = "not_finite" if "NaN" in problem else "shape"
        return report(CheckResult(name, False, f"{FAIL} {problem}.", code), raise_on_fail=raise_on_fail, quiet=quiet)
    a = a[None] if a.ndim == 1 else a

    def same(x: np.ndarray, y: np.ndarray) -> bool:
        d = x - y
        if angles:
            d = (d + np.pi) % (2 * np.pi) - np.pi
        return bool(np.all(np.abs(d) <= atol))

    matched = [next((j for j, r in enumerate(ref) if same(row, r)), None) for row in a]
    extra = [i for i, j in enumerate(matched) if j is None]
    found = [j for j in matched if j is not None]
    duplicate = sorted(j for j, count in Counter(found).items() if count > 1)
    missing = [j for j in range(len(ref)) if j not in found]
    if extra:
        text = (f"{FAIL} row {extra[0]} of {name} is not a solution ({len(extra)} such row"
                f"{'s' if len(extra) > 1 else ''}).")
        return report(CheckResult(name, False, text, "extra", len(a)), raise_on_fail=raise_on_fail, quiet=quiet)
    if duplicate:
        text = f"{FAIL} {name} holds the same solution twice (reference solution {duplicate[0]})."
        return report(CheckResult(name, False, text, "duplicate", len(a)), raise_on_fail=raise_on_fail, quiet=quiet)
    if missing:
        text = f"{FAIL} {name} has {len(a)} of the {len(ref)} solutions: {len(missing)} missing."
        return report(CheckResult(name, False, text, "missing", len(a)), raise_on_fail=raise_on_fail, quiet=quiet)
    return report(CheckResult(name, True, f"{PASS} {name}: all {len(ref)} solutions, each once.", None, len(a)),
                  raise_on_fail=raise_on_fail, quiet=quiet)


@dataclass(repr=False)
class SolutionSetCheck(Check):
    r"""A check of a function that returns *every* solution: each once, in any order.

    Use it, registered with ``exercise(chapter, name, check)``, for a task whose
    answer is a function with several right results (all inverse-kinematics solutions of
    a goal), or a function of angles that are right up to multiples of 2π (a reference
    of one row). At each sampled input ``x`` the answer's rows are compared with
    ``reference(x)`` by :func:`solution_set`.

    Parameters
    ----------
    name, variables, groups, samples, seed, noun, doc
        As for :class:`~robokin.check.Check`: the answer is called with the variables
        (one argument per variable, or per group of ``groups``).
    reference : callable
        ``reference(x) -> ndarray (r, m)``: every solution at the input ``x`` of shape
        ``(nvars,)``, one per row (``r`` may be 0, and may change with ``x``).
    atol : float
        Two rows are the same solution when every entry differs by at most ``atol``.
    angles : bool
        Entries are angles (rad): equal up to a multiple of 2π (default True).

    Notes
    -----
    The answer returns an array ``(k, m)`` (one solution may be ``(m,)``, or a number when
    ``m`` is 1; none ``(0, m)`` or ``[]``). Diagnoses: ``"degrees"`` (``np.deg2rad`` of every answer is right), then
    those of :func:`solution_set` at the first input where the answer is wrong
    (``"extra"``, ``"duplicate"``, ``"missing"``, ``"shape"``, ``"not_finite"``), and
    ``"error"`` for an answer that cannot be called.

    Examples
    --------
    >>> import numpy as np
    >>> from robokin.check import SolutionSetCheck, Variable
    >>> both_elbows = SolutionSetCheck(   # q2 of a two-link arm (l1 = l2 = 1) reaching distance d
    ...     name="q2", variables=[Variable("d", kind="length", low=0.2, high=1.9)], noun="distances",
    ...     reference=lambda x: np.array([[1.0], [-1.0]]) * np.arccos(x[0] ** 2 / 2 - 1))
    >>> result = both_elbows(lambda d: [[np.arccos(d**2 / 2 - 1)], [2 * np.pi - np.arccos(d**2 / 2 - 1)]])
    ✔ q2 is correct: every solution, each once (checked at 20 random distances).
    """

    atol: float = 1e-6
    angles: bool = True

    def _sets(self, answer: Any) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray]]:
        """The inputs, the reference sets and the answer's sets (AnswerError if it fails)."""
        X = self.sample_points()
        refs = []
        for x in X:
            ref = np.asarray(self.reference(x), dtype=float)
            refs.append(ref[None] if ref.ndim == 1 else ref)
        ev = evaluator(answer, self.variables, self.groups, self.name)
        got = []
        for x, ref in zip(X, refs):
            values = ev.fn(x)
            values = values.reshape(1) if values.ndim == 0 else values   # one number: one solution of one angle
            got.append(values.reshape(0, ref.shape[-1]) if values.size == 0 else values)
        return X, refs, got

    def evaluate(self, answer: Any) -> CheckResult:
        """Like calling the check, but neither prints nor raises (see :meth:`Check.evaluate`)."""
        try:
            X, refs, got = self._sets(answer)
        except AnswerError as exc:
            return self._fail(exc.code, exc.message, len(self.sample_points()))
        verdicts = [solution_set(S, R, self.name, atol=self.atol, angles=self.angles, quiet=True)
                    for S, R in zip(got, refs)]
        if all(verdicts):
            return CheckResult(self.name, True, f"{PASS} {self.name} is correct: every solution, each once"
                               f"{self._where(X)}.", None, len(X))
        with np.errstate(all="ignore"):
            in_degrees = all(solution_set(np.deg2rad(S), R, self.name, atol=self.atol, angles=self.angles,
                                          quiet=True) for S, R in zip(got, refs))
        if in_degrees and any(len(R) for R in refs):
            return self._fail("degrees", f"{self.name} returns degrees: np.deg2rad of it is right. "
                              "robokin works in radians.", len(X))
        k = next(i for i, verdict in enumerate(verdicts) if not verdict)
        text = verdicts[k].message.removeprefix(f"{FAIL} ").rstrip(".")
        return self._fail(verdicts[k].diagnosis or "mismatch", f"{text} (at {self._point_text(X[k])}).", len(X))
