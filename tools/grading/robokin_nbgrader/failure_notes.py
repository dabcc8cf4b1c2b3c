"""``FailureNotes``: the note under a failing test (written by autograde's executor, ``BridgedExecute``).

It quotes the failing statement, names the student's answers it depends on (traced through the
read-only cells), the root cause among them, and what ``robokin.check`` (asked in the student's
kernel) says about those answers.
"""

from __future__ import annotations

import functools
import re
import textwrap

from nbgrader import utils
from tools.notebook_analysis import (
    EXPLAINS_TAG_RE,
    Binding,
    defined_names,
    free_names,
    level2_headings,
    statement_at,
    statement_span,
)
from tools.notebook_analysis import trace as cell_trace

from .cells import (
    cell_label,
    failing_line,
    hidden_lines,
    raising_functions,
    robokin_metadata,
    task_of,
    visible_source,
)
from .checks import BUILTIN_NAMES, TYPE_PROBE, called_as, identifier_names


def cell_kinds(nb) -> list[tuple[str, str]]:
    """``(kind, source)`` of every cell for ``notebook_analysis.trace``: the student's answer
    cells are ``"answer"``, other code cells (given, tests, the student's own) ``"code"``."""
    out = []
    for cell in nb.cells:
        if cell.cell_type != "code":
            out.append(("markdown", ""))
        else:
            out.append(("answer" if utils.is_solution(cell) else "code", cell.source))
    return out


def error_outputs(cell) -> list:
    """The error outputs of the code cell ``cell`` (none if it ran through)."""
    return [o for o in cell.get("outputs", []) if o.get("output_type") == "error"]


def failing_reads(cell, error, kinds) -> tuple[int | None, str, dict[str, Binding]]:
    """``(line, statement, reads)`` of the test cell ``cell`` that failed with ``error``, after the
    cells ``kinds`` (:func:`cell_kinds` of the cells before it): the line that raised, its whole
    statement, and the names of the student's that the statement reads (traced through the
    earlier statements of the cell; ``{name: Binding}``, each with the answers it comes from).
    Without a line (a timeout), or when that statement reads nothing of the student's, the
    names the whole cell reads."""
    line = failing_line(cell, error)
    statement = statement_at(cell.source, line) if line else ""
    if line and statement:
        first, _ = statement_span(cell.source, line)
        own = [("code", s) for s in _statements("\n".join(cell.source.splitlines()[: first - 1]))]
        reads = trace(kinds + own + [("code", statement)])[-1]
    else:
        reads = trace(kinds + [("code", cell.source)])[-1]
    student = {n: b for n, b in reads.items() if b.roots}
    if statement and not student:  # the failing line reads nothing of the student's
        reads = trace(kinds + [("code", cell.source)])[-1]
        student = {n: b for n, b in reads.items() if b.roots}
    return line, statement, student


class FailureNotes:
    """The note under a failing test: what failed, which of the student's answers it
    depends on, which of those is the root cause, and what ``robokin.check`` says.

    * the whole failing statement is quoted (a multi-line ``assert`` too);
    * the names it reads are traced back (``notebook_analysis.trace``) through the
      read-only cells and the earlier statements of the test cell to the answer
      cells: only names bound by an answer cell are called "your answer"; an answer also uses
      the functions of its cell that it calls, in a function's body too (parsed, never run);
    * among those answers, the ones whose own earlier test failed at a statement that read them
      (a test of the task that read the answer elsewhere and failed at another is no trial of it), whose cell raised,
      or that ``robokin.check`` found wrong are named as the root cause (the first
      in the chain: an answer that is wrong only because it uses another wrong one
      is left out); a function of an answer cell that a test reaches only through a
      function's body or a value computed by calling it (``S_list = ... screw_axis(...)``)
      is no suspect by that test, only by its own tests and ``robokin.check``'s verdict;
      the note says from which values of its cell such a value was computed, which
      functions of the cell it uses, and which answers of earlier cells it uses (the cause line
      may name them: the student sees where they come in);
    * a test tagged ``explains-<answer>`` (one that runs a later answer on robokin's earlier
      steps) asks ``robokin.check`` about the answers its tags name only and blames no other
      (unless that answer's cell raised): not the earlier answers it reads, nor those the named
      ones use through default arguments;
    * an answer cell that raised is the cause as the line that raised (its label, ``In [5], line 7,
      `cond = robot.condition_number(P)```) unless the error passed through the body of the answer
      (a function of the cell): an answer is named only for an error in its own code;
    * ``robokin.check`` is asked about those answers only, and a typical mistake is
      named only for a check run on the student's value of those very names;
    * a test that fails with a wrong type (``AttributeError``, ``TypeError``, ...)
      says what the answer is and what was expected (the stub's docstring, the
      task statement, or the check's signature).

    ``report`` is the run's shared record (``resources["robokin"]``): it collects what
    checks found wrong (``"wrong"``) and the root causes (``"causes"``) for the report.
    """

    max_statement_lines = 12
    type_errors = ("AttributeError", "TypeError", "IndexError", "KeyError", "ValueError")

    def __init__(self, nb, index: int, report: dict):
        self.nb = nb
        self.index = index
        self.cell = nb.cells[index]
        self.report = report
        self.grade_id = self.cell.metadata.get("nbgrader", {}).get("grade_id", "?")
        self.task = task_of(self.cell)
        # the answers the test grades (its tags explains-<answer>): none, every answer it uses
        self.graded = frozenset(m.group(1) for m in map(EXPLAINS_TAG_RE.match, self.cell.metadata.get("tags", []))
                                if m)
        self._analysed = False
        self._failed_reads_memo: dict[int, dict[str, Binding]] = {}

    # -- the static analysis
    def analyse(self, error) -> None:
        if self._analysed:
            return
        self._analysed = True
        kinds = cell_kinds(self.nb)[: self.index]
        self.line, self.statement, student = failing_reads(self.cell, error, kinds)
        self.yours = {n: b for n, b in student.items() if b.answer and b.cell < self.index}
        self.derived = {n: b for n, b in student.items() if n not in self.yours}
        # the answers the whole test reads itself (a test that fails before it reaches its check of
        # J_lift still checks J_lift: the note gives robokin.check's verdict on it)
        whole = trace(kinds + [("code", visible_source(self.cell.source))])[-1]
        self.checked = {n for n, b in whole.items() if b.answer and b.cell < self.index}
        self.roots = set().union(*(b.roots for b in student.values())) if student else set()
        table = _bindings(kinds)
        self.answer_cell = {n: table[n].cell for n in self.roots if n in table}
        self.root_roots = {n: table[n].roots for n in self.roots if n in table}
        self._kinds = kinds
        self.causes = self._causes(kinds)

    def _causes(self, kinds, correct: frozenset[str] = frozenset()) -> dict[str, str]:
        """``{answer name: why it is suspect}`` for the root causes of this failure (the why
        reads after "its" or "their": ``"own test task2_test1 failed"``). An answer that
        ``robokin.check`` finds correct (``correct``) is never a cause, and its own tests are
        the failing tests of its task whose failing statement read it."""
        why: dict[str, str] = {}
        helpers = _helpers(kinds)
        for name in sorted(self.roots - set(correct)):
            cell = self.answer_cell.get(name)
            if cell is not None and error_outputs(self.nb.cells[cell]):
                error = error_outputs(self.nb.cells[cell])[0]
                count = self.nb.cells[cell].get("execution_count")
                where = f" In [{count}]" if count else ""
                why[name] = f"answer cell{where} raised {error.get('ename')}"
                continue
            if self.graded and name not in self.graded:   # graded by tests of its own, not this one
                continue
            failed = []
            task = task_of(self.nb.cells[cell]) if cell is not None else None
            for j in range(cell + 1 if cell is not None else 0, self.index):
                other = self.nb.cells[j]
                if other.cell_type == "code" and utils.is_grade(other) and error_outputs(other) \
                        and task_of(other) == task:   # a test of another task is not its own
                    # only what the statement that failed there read is on trial (a test that reads
                    # fk_table in one line and fails at the check of another answer does not
                    # accuse fk_table); a function the test reaches only through the body of a
                    # function of its cell, or through a value computed by calling it there, is
                    # not on trial either: robokin.check's verdict on it decides
                    if any(name in b.roots and not any(name in helpers.get(root, ()) for root in b.roots)
                           for b in self._failed_reads(j).values()):
                        failed.append(other.metadata["nbgrader"]["grade_id"])
            if failed:
                why[name] = f"own test {failed[0]} failed" if len(failed) == 1 else \
                    f"own tests {', '.join(failed)} failed"
            elif name in self.report.get("wrong", {}):
                why[name] = f"value is wrong for robokin.check ({self.report['wrong'][name]})"
        # the first link of the chain: leave out an answer that uses another suspect one
        return {n: w for n, w in why.items()
                if not any(other != n and other in self.root_roots.get(n, ()) for other in why)}

    def _failed_reads(self, index: int) -> dict[str, Binding]:
        """What the statement that failed in the earlier test cell ``index`` read of the student's
        (:func:`failing_reads`, on that cell's last error, as the note under it does), memoised
        per cell for this note."""
        if index not in self._failed_reads_memo:
            other = self.nb.cells[index]
            self._failed_reads_memo[index] = failing_reads(other, error_outputs(other)[-1],
                                                           cell_kinds(self.nb)[:index])[2]
        return self._failed_reads_memo[index]

    # -- the questions to the kernel
    def pairs(self, error) -> list[tuple[str, str]]:
        """``(check, quantity)`` pairs to evaluate in the kernel: the checks of this test and
        the registered checks, on the student's answers it depends on; type probes."""
        self.analyse(error)
        names = self.roots | set(self.yours)
        if self.graded:   # the answers it grades: the earlier ones it reads have their own tests
            names &= self.graded
        out: list[tuple[str, str]] = []
        own = [tuple(p) for p in robokin_metadata(self.cell).get("explain", [])]
        candidates = [(check, quantity, names | self.checked) for check, quantity in own]
        candidates += [(check, name, names) for _, check, name in self.report.get("pairs", [])]
        for check, quantity, allowed in candidates:
            used = identifier_names(quantity)
            if used and used <= allowed | BUILTIN_NAMES and (check, quantity) not in out:
                out.append((check, quantity))
        if error.get("ename") in self.type_errors:
            for name in sorted(self.yours):
                out.append((TYPE_PROBE, name))
        return out

    # -- the note
    def lines(self, error, verdicts: list[dict]) -> list[str]:
        self.analyse(error)
        out = []
        if error.get("ename") == "CellTimeoutError":
            out.append(f"✘ Task {self.task} ({self.grade_id}) did not finish within the time limit: "
                       "it was stopped.")
        elif self.line and self.line in hidden_lines(self.cell.source):
            # a hidden test: its verdict and diagnosis, never its code (not even the line's number)
            out.append(f"✘ Task {self.task} ({self.grade_id}) failed in its hidden tests "
                       "(tests run when grading, whose code is not shown):")
            message = f"{error.get('ename')}: {error.get('evalue', '')}".strip().rstrip(":")
            out.append(f"  {message}" if error.get("evalue") else f"  ({error.get('ename')})")
        else:
            where = f" at line {self.line}:" if self.line else ""
            out.append(f"✘ Task {self.task} ({self.grade_id}) failed{where}")
            statement = self.statement.splitlines()
            if len(statement) > self.max_statement_lines:
                statement = statement[: self.max_statement_lines] + ["..."]
            out += [f"      {line}" for line in textwrap.dedent("\n".join(statement)).splitlines()]
            message = f"{error.get('ename')}: {error.get('evalue', '')}".strip().rstrip(":")
            out.append(f"  {message}" if error.get("evalue") else f"  ({error.get('ename')})")
        if self.yours:
            out.append(f"  It checks your answer{'s' if len(self.yours) > 1 else ''} "
                       f"{self._named(self.yours)}.")
        out += self._computed_lines()
        derived = {n: b for n, b in self.derived.items() if n not in self._hidden_names()}
        # of a test tagged explains-<answer>, the answers it grades (the others are graded elsewhere)
        named = (lambda roots: roots & self.graded) if self.graded else set
        derived = {n: b for n, b in derived.items() if named(b.roots)}
        if derived:
            upstream = sorted(set().union(*(named(b.roots) for b in derived.values())))
            given = ", ".join(f"`{n}`" for n in sorted(derived))
            here = [b.cell >= self.index for b in derived.values()]
            where = ("earlier in this test cell" if all(here) else "by read-only cells" if not any(here)
                     else "by read-only cells and earlier in this test cell")
            # what it reads of the student's, not that it is "computed from" them: a finite-difference
            # reference at the student's q is robokin's value there, not the student's
            several = len(derived) > 1
            out.append(f"  It also reads {given}, computed {where}; {'they use' if several else 'it uses'} "
                       f"your answer{'s' if len(upstream) > 1 else ''} {self._named(upstream)}.")
        for name in sorted(self.yours):
            missing = f"name '{name}' is not defined"
            if error.get("ename") == "NameError" and missing in str(error.get("evalue", "")):
                cell = self.yours[name].cell
                out.append(f"  `{name}` was never defined: your answer cell of Task "
                           f"{task_of(self.nb.cells[cell])} did not finish (see its error above it).")
        # right for every check that asks about it (another check may find a mistake this one misses)
        correct = frozenset(v["quantity"] for v in verdicts if v.get("status") == "correct") - \
            {v["quantity"] for v in verdicts if v.get("status") in ("wrong", "missing")}
        # robokin.check finds an answer this test depends on wrong: a suspect from this test on
        found_wrong = {v["quantity"]: v.get("diagnosis") or "wrong" for v in verdicts
                       if v.get("status") == "wrong" and v["quantity"] in self.roots - correct}
        fresh = set(found_wrong) - set(self.report.get("wrong", {})) - set(self.causes)
        for name, diagnosis in found_wrong.items():
            self.report.setdefault("wrong", {}).setdefault(name, diagnosis)
        if correct & set(self.causes) or fresh:   # right: not the cause; wrong: a cause
            self.causes = self._causes(self._kinds, correct)
        # the answers this test grades that robokin.check finds wrong: fixing the cause is not enough
        graded = self.graded or set(self.yours)
        own_wrong = frozenset(v["quantity"] for v in verdicts
                              if v.get("status") in ("wrong", "missing") and v["quantity"] in graded)
        out += self._cause_lines(own_wrong)
        checked = {name for v in verdicts if v.get("status") not in ("info", "skipped")
                   for name in identifier_names(v["quantity"])}
        infos: dict[str, list[str]] = {}
        for v in verdicts:
            if v.get("status") == "info" and v["quantity"] not in checked:
                infos.setdefault(v.get("got") or v.get("message", ""), []).append(v["quantity"])
        for got, names in infos.items():
            expected = [_expected_from_notebook(self.nb, self.yours[n].cell, n) for n in names if n in self.yours]
            listed = ", ".join(f"`{n}`" for n in names)
            text = f"  Your {listed} {'is' if len(names) == 1 else 'are'} {got}"
            hints = "; ".join(e for e in expected if e)
            out.append(text + (f"; expected: {hints}" if hints else "."))
        known = self.roots | set(self.yours) | self.checked
        wrong = self.report.setdefault("wrong", {})
        for v in verdicts:
            if v.get("status") in ("skipped", "info"):
                continue
            used = identifier_names(v["quantity"])
            mine = bool(used) and used <= known | BUILTIN_NAMES
            tag = f"  (typical mistake: {v['diagnosis']})" if v.get("typical") and mine else ""
            text = v["message"] if v["status"] in ("correct", "wrong") else f"✘ {v['message']}"
            out.append(f"  robokin.check{called_as(v)}: {text}{tag}")
            if v["status"] in ("wrong", "missing") and v["quantity"].isidentifier():
                wrong.setdefault(v["quantity"], v.get("diagnosis") or v["status"])
        return out

    def _hidden_names(self) -> set[str]:
        """Names bound in this cell's hidden tests only: the note never names them."""
        hidden = hidden_lines(self.cell.source)
        if not hidden:
            return set()
        lines = self.cell.source.split("\n")
        code = "\n".join(line for number, line in enumerate(lines, 1) if number in hidden)
        try:
            return set(defined_names(textwrap.dedent(code))) - set(defined_names(visible_source(self.cell.source)))
        except SyntaxError:
            return set()

    def _computed_lines(self) -> list[str]:
        """A line for each answer this test reads that its answer cell computes from other values
        of that cell or by calling functions of that cell: the student is led to what the value was
        really computed from (``T_ET = transform_from_ypr(TOOL_YPR, TOOL_OFFSET)``: the two values
        and the function, not the function alone), and to the answers of earlier cells it uses
        (:meth:`_earlier_answers`), which the cause line may name."""
        out = []
        for name in sorted(self.yours):
            values, functions = self._computed_from(name)
            listed = ", ".join(f"`{function}`" for function in functions)
            plural = "s" if len(functions) > 1 else ""
            earlier = self._earlier_answers(name)
            also = f"your earlier answer{'s' if len(earlier) > 1 else ''} {self._named(earlier)}" if earlier else ""
            if values:
                read = ", ".join(f"`{value}`" for value in values)
                uses = f"; it uses your function{plural} {listed}" if functions else ""
                uses += f"{' and' if functions else '; it uses'} {also}" if also else ""
                out.append(f"  {self._named([name])} is computed in its answer cell from your {read}{uses}.")
            elif functions:
                uses = f" and uses {also}" if also else ""
                out.append(f"  {self._named([name])} is computed in its answer cell by your function{plural} "
                           f"{listed}{uses}.")
            elif also:
                out.append(f"  {self._named([name])} uses {also}.")
        return out

    def _earlier_answers(self, name: str) -> list[str]:
        """The answers of earlier cells that the student's ``name`` (read by this test) uses, directly
        or through read-only cells: the cause line may name them, and the student is told where they
        come in. None for a test that grades named answers only (``explains-``): it blames no other."""
        binding = self.yours.get(name)
        if binding is None or self.graded:
            return []
        return sorted(root for root in binding.roots - {name}
                      if self.answer_cell.get(root, binding.cell) < binding.cell)

    def _computed_from(self, name: str) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """``(values, functions)`` of its answer cell that the student's value ``name`` (read by this
        test) is computed from: the cell's other values its statements read, in the order the cell
        binds them (:func:`_cell_values_read`), and the functions it uses, directly or through those
        values (:func:`_cell_functions_used`); none for a function."""
        binding = self.yours.get(name)
        if binding is None:
            return (), ()
        modules = _module_names(code for kind, code in self._kinds if kind in ("answer", "code"))
        source = self.nb.cells[binding.cell].source
        functions = next((calls for bound, _, calls in _cell_functions_used(source, modules) if bound == name), ())
        values = next((read for bound, read in _cell_values_read(source, modules) if bound == name), ())
        return values, functions

    def _cause_lines(self, own_wrong: frozenset[str] = frozenset()) -> list[str]:
        """The note's line naming the root causes (none without a cause), recorded in the run's report
        for *Where to start*. It says the test may then pass only when robokin.check finds none of the
        answers the test grades wrong (``own_wrong``) besides the causes to be fixed anyway; to fix a
        cause "first" only when it is not an answer the test checks itself."""
        if not self.causes:
            return []
        groups: dict[tuple, list[str]] = {}
        # an answer cell that raised on a line of its own (not in the body of the answer): that line
        raised: dict[tuple[str, str], int | None] = {}
        for name, why in sorted(self.causes.items()):
            line = self._line_that_raised(name)
            if line:
                raised.setdefault(line, self._task_of_name(name))
            else:
                groups.setdefault((self._task_of_name(name), why), []).append(name)
        items = [f"{self._named(names)}: {'its' if len(names) == 1 else 'their'} {why}"
                 for (_, why), names in groups.items()]
        items += [f"{label}, which {why}" for label, why in raised]
        # a cause named for its own failing test or its value is already to be fixed; one whose
        # answer cell raised may still be wrong itself; one that uses a cause may be wrong through it
        causes = set(self.causes)
        also = sorted(name for name in own_wrong
                      if self.causes.get(name, "answer cell").startswith("answer cell")
                      and not (set(self.root_roots.get(name, ())) - {name}) & causes)
        if also:
            them = "it" if len(also) == 1 else "them"
            advice = (f"Fix that first, and your {self._named(also)} too: robokin.check finds {them} "
                      "wrong (below), so this test fails until both are fixed.")
        elif not raised and set(self.causes) <= set(self.yours):
            # the answers this test checks itself: nothing to fix before them
            advice = f"Fix {'it' if len(self.causes) == 1 else 'them'}: this test may then pass."
        else:
            advice = "Fix that first: this test may then pass."
        out = [f"  This test failed because of {'; '.join(items)}. {advice}"]
        # one entry per answer (or line) and reason: a test depends on the causes of its own note only
        record = self.report.setdefault("causes", {})
        for (task, why), names in groups.items():
            for name in names:
                entry = record.setdefault(f"{task}|{why}|{name}",
                                          {"task": task, "why": why, "names": [name], "tests": []})
                entry["tests"].append(self.grade_id)
        for (label, why), task in raised.items():
            entry = record.setdefault(f"{task}|{why}|{label}",
                                      {"task": task, "why": why, "names": [], "line": label, "tests": []})
            entry["tests"].append(self.grade_id)
        return out

    def _line_that_raised(self, name: str) -> tuple[str, str] | None:
        """``(the line's label, "raised DomainError")`` when the answer cell of the cause ``name``
        raised at a line whose error did not pass through ``name``: a call of robokin's, or of a
        module's, on another line of the cell. That line is the cause, not ``name`` (a function of
        the cell is named only when its body raised). ``None`` when it did, or the traceback gives
        no line of the cell."""
        index = self.answer_cell.get(name)
        errors = error_outputs(self.nb.cells[index]) if index is not None else []
        if not errors:
            return None
        cell, error = self.nb.cells[index], errors[0]
        line = failing_line(cell, error)
        if line is None or name in raising_functions(cell, error):
            return None
        return cell_label(cell, line), f"raised {error.get('ename')}"

    def _task_of_name(self, name: str) -> int | None:
        cell = self.answer_cell.get(name)
        return task_of(self.nb.cells[cell]) if cell is not None else None

    def _named(self, names) -> str:
        """```a`, `b` (Task 2), `c` (Task 3)``: names with their task, grouped by task."""
        by_task: dict[int | None, list[str]] = {}
        for name in sorted(names):
            task = self._task_of_name(name)
            if task is None and name in self.yours:
                task = task_of(self.nb.cells[self.yours[name].cell])
            by_task.setdefault(task, []).append(name)
        parts = []
        for task, group in sorted(by_task.items(), key=lambda kv: (kv[0] is None, kv[0] or 0)):
            listed = ", ".join(f"`{n}`" for n in group)
            parts.append(f"{listed} (Task {task})" if task is not None else listed)
        return ", ".join(parts)


def trace(cells: list[tuple[str, str]]) -> list[dict[str, Binding]]:
    """``notebook_analysis.trace`` with every code cell read statement by statement.

    A name's provenance follows the data: the answers its defining statements read, transitively.
    A read-only cell that computes ``H_model = leg.frames(q)`` and, in another statement,
    ``H = R_B1 @ R_12`` gives ``H_model`` no answer of the student's; in an answer cell that
    binds ``closed = ik_closed_form(r_goal)`` and, further down, ``found`` from ``newton_ik``,
    ``closed`` does not use ``newton_ik``. A name an answer cell binds is still the student's
    answer (its own root); a statement that changes a list it reads (``found.append(q)``)
    passes what it reads on to that list. The result is ``trace``'s, for the cells as given
    (a binding's ``cell`` is the index in ``cells``).
    """
    expanded: list[tuple[str, str]] = []
    owner: list[int] = []
    modules = _module_names(code for kind, code in cells if kind in ("answer", "code"))
    for index, (kind, code) in enumerate(cells):
        parts = [(kind, code)]
        statements = _top_level(code) if kind in ("answer", "code") else None
        if statements is not None:   # a cell that does not parse stays whole
            parts = [("code", _with_mutations(statement, modules)) for statement in statements]
            # the names an answer cell binds are the student's answers, each its own root
            parts += [("answer", f"{name} = {name}") for name in defined_names(code) if kind == "answer"]
            # ... and each uses the functions of its cell that it calls or its body calls, however deep
            if kind == "answer":
                parts += [("answer", f"{name} = ({name}, {', '.join(helpers)})")
                          for name, helpers, _ in _cell_functions_used(code, modules)]
        for part in parts or [("code", "")]:
            expanded.append(part)
            owner.append(index)
    reads = cell_trace(expanded)
    out: list[dict[str, Binding]] = [{} for _ in cells]
    for position, found in enumerate(reads):
        index = owner[position]
        for name, binding in found.items():
            cell = owner[binding.cell]
            if cell < index and name not in out[index]:   # a name bound earlier in the cell is its own
                out[index][name] = Binding(cell, binding.answer, binding.roots)
    return out


#: Methods that change the object they are called on: ``found.append(q_end)`` makes ``found`` depend on ``q_end``.
MUTATING_METHODS = frozenset({"append", "appendleft", "extend", "insert", "update", "add", "setdefault",
                              "pop", "remove", "discard", "clear", "sort", "reverse", "fill"})


#: Entries of each memo of this module. ``trace`` runs four times or more for every failing test,
#: over the same cells: each cell and statement is parsed once. A memo is keyed by source text alone
#: and holds immutable results of pure functions (as ``notebook_analysis``'s), so one submission's
#: memo serves the next in an autograde process and nothing else of it reaches their notes; a
#: chapter has a few hundred statements.
MEMO_SIZE = 8192


def _module_names(sources) -> frozenset[str]:
    """The names that ``import x`` or ``import x as y`` binds in any of ``sources``: modules."""
    return frozenset().union(*(_imported_modules(code) for code in sources))


@functools.lru_cache(maxsize=MEMO_SIZE)
def _imported_modules(code: str) -> frozenset[str]:
    """:func:`_module_names` of one source, memoised per source string: ``trace`` runs several
    times for every failing test, over the same cells."""
    import ast

    try:
        tree = ast.parse(code)
    except SyntaxError:
        return frozenset()
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names.update(alias.asname or alias.name.split(".")[0] for alias in node.names)
    return frozenset(names)


@functools.lru_cache(maxsize=MEMO_SIZE)
def _with_mutations(statement: str, modules: frozenset[str] = frozenset()) -> str:
    """``statement`` and, for every name it reads and changes in place (a method of
    ``MUTATING_METHODS`` called for its effect, an item or attribute assigned), a binding of that name that reads
    everything the statement reads: the trace then sees the change. A function of a module called
    as a statement (``np.sort(x)``, ``modules`` holds ``np``) changes no module. Memoised per
    ``(statement, modules)``: a pure function of the two."""
    import ast

    try:
        tree = ast.parse(statement)
    except SyntaxError:
        return statement
    changed: list[str] = []

    def base(node: ast.AST) -> str | None:
        while isinstance(node, (ast.Subscript, ast.Attribute)):
            node = node.value
        return node.id if isinstance(node, ast.Name) else None

    for node in ast.walk(tree):
        targets: list[ast.AST] = []
        call = node.value if isinstance(node, ast.Expr) else None
        if isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute) \
                and isinstance(call.func.value, ast.Name) and call.func.attr in MUTATING_METHODS \
                and call.func.value.id not in modules:
            targets = [call.func.value]   # found.append(q) on its own, not a value as np.sort(x)
        elif isinstance(node, ast.Assign):
            targets = [t for t in node.targets if isinstance(t, (ast.Subscript, ast.Attribute))]
        elif isinstance(node, (ast.AugAssign, ast.AnnAssign)):
            targets = [node.target] if isinstance(node.target, (ast.Subscript, ast.Attribute)) else []
        for target in targets:
            name = base(target)
            if name and name not in changed:
                changed.append(name)
    free = sorted(free_names(statement))
    changed = [name for name in changed if name in free]   # a name bound inside the statement is its own
    if not changed:
        return statement
    read = ", ".join(free)
    return statement + "\n" + "\n".join(f"{name} = ({read},)" for name in changed)


@functools.lru_cache(maxsize=MEMO_SIZE)
def _cell_functions_used(code: str, modules: frozenset[str] = frozenset()) \
        -> tuple[tuple[str, tuple[str, ...], tuple[str, ...]], ...]:
    """For each name an answer cell binds, the functions of the same cell it uses, transitively,
    and, for a value, those its own statements call: ``my_leg_ik``, whose body calls
    ``ankle_angles`` of its cell, uses ``ankle_angles``; ``Q_mine = my_leg_ik(T)`` is computed by
    ``my_leg_ik`` and uses both (a value of the cell that its statements read passes its functions
    on: ``rows = [screw_axis(w, p) ...]`` then ``S_list = np.array(rows)``; a list changed in place
    too, ``modules`` as in :func:`_with_mutations`; in ``a, b = f(x), y`` each name its own element,
    :func:`_unpacked`). Only names with such functions, in order of binding; parsed, never run.
    Memoised per ``(code, modules)``."""
    import ast

    statements = _top_level(code)
    if statements is None:
        return ()
    functions = set()
    for statement in statements:
        try:
            tree = ast.parse(statement)
        except SyntaxError:   # pragma: no cover - a statement of a parsed cell parses
            continue
        functions |= {node.name for node in tree.body
                      if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))}
    # a function: the functions its body calls; a value: those its statements call, and the
    # functions of the values of the cell bound before them that they read
    direct: dict[str, set[str]] = {}

    def uses(free: set[str]) -> set[str]:
        return (free & functions).union(*(direct.get(name, ()) for name in free - functions))

    for statement in statements:
        read = uses(free_names(statement))
        # a, b = f(x), y: each name its own element
        own = {name: uses(free_names(part)) for name, part in _unpacked(ast.parse(statement)).items()}
        for name in defined_names(_with_mutations(statement, modules)):
            direct.setdefault(name, set()).update(own.get(name, read) - {name})

    def closure(start) -> set[str]:
        used, todo = set(), list(start)
        while todo:
            helper = todo.pop()
            if helper not in used:
                used.add(helper)
                todo += direct.get(helper, ())
        return used

    out = []
    for name, helpers in direct.items():
        used = closure(helpers) - {name}
        if used:
            out.append((name, tuple(sorted(used)), () if name in functions else tuple(sorted(helpers))))
    return tuple(out)


@functools.lru_cache(maxsize=MEMO_SIZE)
def _cell_values_read(code: str, modules: frozenset[str] = frozenset()) -> tuple[tuple[str, tuple[str, ...]], ...]:
    """For each value an answer cell binds, the other values of the same cell it is computed from:
    those its binding statements read, bound earlier in the cell, in the order the cell first binds
    them. ``T_ET = transform_from_ypr(TOOL_YPR, TOOL_OFFSET)`` reads ``TOOL_YPR`` and
    ``TOOL_OFFSET``; ``T_BT0 = tool_arm.fk(Q0)`` reads ``tool_arm`` (which reads ``T_ET``: the
    student follows the chain value by value); ``R_a, R_b = T_a[:3, :3], T_b[:3, :3]`` gives each
    name its own element. Functions, classes and imported names are not values (a function's uses
    are :func:`_cell_functions_used`'s); a list changed in place reads what the change reads
    (``modules`` as in :func:`_with_mutations`). Only values that read others; parsed, never run.
    Memoised per ``(code, modules)``."""
    import ast

    statements = _top_level(code)
    if statements is None:
        return ()
    trees = []
    not_values: set[str] = set()
    for statement in statements:
        try:
            tree = ast.parse(statement)
        except SyntaxError:   # pragma: no cover - a statement of a parsed cell parses
            continue
        trees.append((statement, tree))
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                not_values.add(node.name)
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                not_values.update(alias.asname or alias.name.split(".")[0] for alias in node.names)
    order: list[str] = []   # the cell's values, in the order it first binds them
    reads: dict[str, set[str]] = {}
    for statement, tree in trees:
        earlier = set(order)
        read = free_names(statement) & earlier
        own = _unpacked(tree)
        for name in defined_names(_with_mutations(statement, modules)):
            if name in not_values:
                continue
            mine = free_names(own[name]) & earlier if name in own else read
            reads.setdefault(name, set()).update(mine - {name})
            if name not in order:
                order.append(name)
    return tuple((name, tuple(value for value in order if value in reads[name]))
                 for name in order if reads[name])


def _unpacked(tree) -> dict[str, str]:
    """``{name: its element's source}`` of a statement ``a, b = x, y`` (as many names as elements, no
    starred one): each name reads its own element only. Empty for any other statement."""
    import ast

    node = tree.body[0] if len(tree.body) == 1 else None
    if not isinstance(node, ast.Assign) or len(node.targets) != 1:
        return {}
    target, value = node.targets[0], node.value
    if not (isinstance(target, (ast.Tuple, ast.List)) and isinstance(value, (ast.Tuple, ast.List))
            and len(target.elts) == len(value.elts)
            and all(isinstance(element, ast.Name) for element in target.elts)
            and not any(isinstance(element, ast.Starred) for element in value.elts)):
        return {}
    return {element.id: ast.unparse(part) for element, part in zip(target.elts, value.elts)
            if isinstance(element, ast.Name)}


def _helpers(kinds: list[tuple[str, str]]) -> dict[str, tuple[str, ...]]:
    """``{answer name: the functions of its answer cell it uses}`` (:func:`_cell_functions_used`)
    for the answer cells of ``kinds``: a test that reads the name reaches them only through a
    function's body or a value's computation. A later cell's binding replaces an earlier one."""
    modules = _module_names(code for kind, code in kinds if kind in ("answer", "code"))
    out: dict[str, tuple[str, ...]] = {}
    for kind, code in kinds:
        if kind == "answer":
            for name in defined_names(code):
                out.pop(name, None)
            out.update((name, used) for name, used, _ in _cell_functions_used(code, modules))
    return out


def _statements(code: str) -> list[str]:
    """The top-level statements of ``code`` (the lines before the failing one), as sources;
    ``[code]`` if it does not parse."""
    statements = _top_level(code)
    return [code] if statements is None else list(statements)


@functools.lru_cache(maxsize=MEMO_SIZE)
def _top_level(code: str) -> tuple[str, ...] | None:
    """The top-level statements of ``code`` as sources, ``None`` if it does not parse;
    memoised per source string (``trace`` splits the same cells for every failing test)."""
    import ast

    try:
        tree = ast.parse(code)
    except SyntaxError:
        return None
    lines = code.splitlines()
    return tuple("\n".join(lines[s.lineno - 1: s.end_lineno]) for s in tree.body)


def _bindings(kinds: list[tuple[str, str]]):
    """The last binding of every name after ``kinds`` (``notebook_analysis.Binding``)."""
    marker = "_robokin_every_name_"
    names = set()
    for kind, code in kinds:
        if kind in ("answer", "code"):
            names |= set(defined_names(code))
    probe = ", ".join(sorted(names)) or "None"
    return trace(kinds + [("code", f"{marker} = ({probe},)")])[-1]


def _expected_from_notebook(nb, cell_index: int, name: str) -> str:
    """What the notebook says ``name`` is: the docstring of the function, or the sentence of
    the task statement above its answer cell that names it in backticks."""
    import ast

    cell = nb.cells[cell_index]
    try:
        tree = ast.parse(cell.source)
    except SyntaxError:
        tree = None
    for node in tree.body if tree else []:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name == name:
            doc = ast.get_docstring(node) or ""
            returns = re.search(r"Returns\n-+\n(.*?)(\n\s*\n|\Z)", doc, re.S)
            text = returns.group(1) if returns else doc.split("\n\n")[0]
            args = ", ".join(a.arg for a in node.args.args)
            text = " ".join(text.split())
            return f"{name}({args})" + (f" returning {text}" if returns else f": {text}" if text else "")
    mention = re.compile(rf"(?<![\w.]){re.escape(name)}\b")
    for line in cell.source.splitlines():
        if "#" in line and mention.search(line[line.index("#"):]) and "YOUR CODE HERE" not in line:
            comment = " ".join(line[line.index("#") + 1:].split())
            return f"the notebook says: “{comment[:240]}”"
    word = re.compile(rf"`[^`]*(?<![\w.]){re.escape(name)}\b[^`]*`")
    for other in reversed(nb.cells[:cell_index]):
        if other.cell_type != "markdown":
            continue
        text = " ".join(other.source.split())
        for sentence in re.split(r"(?<=[.!?])\s+", text):
            if word.search(sentence):
                return f"the task says: “{sentence[:240]}”"
        if level2_headings(other.source):
            break
    return ""
