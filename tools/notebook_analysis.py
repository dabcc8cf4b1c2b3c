"""Read the exercise structure of a chapter notebook: tasks, solutions, checks.

Shared by ``tools/authoring/nbgrader_metadata.py`` (which writes nbgrader's cell metadata
from it), ``tools/grading/robokin_nbgrader/`` (nbgrader preprocessors) and the tests.
Everything is derived from what authors already write (book/for-instructors.md):

* a **task** is a section whose heading is ``## Task k: ...``; it runs to the
  next level-2 heading;
* a **solution cell** is a code cell tagged ``solution``; **solution prose** is a
  markdown cell between a ``{solution-start}`` and a ``{solution-end}`` directive;
* a **check cell** is a code cell tagged ``check``; it is **graded** when it lies
  in a task and reads a value that the student's solution cells define (directly,
  or through the given code cells in between) -- a check of the problem's data
  would give points for nothing;
* a **try-it cell** is an untagged code cell after a markdown cell that says
  *Try it yourself*: the student's playground, left editable and ungraded.

Nothing here executes a notebook or imports robokin: the analysis is static (the
``ast`` module), so it is fast and deterministic.
"""

from __future__ import annotations

import ast
import functools
import json
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

__all__ = [
    "Cell",
    "Chapter",
    "analyse",
    "load_notebook",
    "dump_notebook",
    "defined_names",
    "free_names",
    "check_calls",
    "stub_plan",
    "GIVEN_MARKER",
    "given_tail_start",
    "solution_part",
]

TASK_RE = re.compile(r"^##\s+Task\s+(\d+)\s*[:.\u2014-]?\s*(.*?)\s*$")
H2_RE = re.compile(r"^##\s+(.+?)\s*$")
FENCE_RE = re.compile(r"^\s*(```+|~~~+)")
POINTS_TAG_RE = re.compile(r"^points-([1-9][0-9]?)$")  # a test cell's weight, e.g. ``points-3``
#: An answer a test cell grades, e.g. ``explains-ik_position``: with one or more, the test's
#: failures are explained by the checks of those answers only (a test that runs a later answer
#: on robokin's earlier steps grades that answer, not the earlier ones it could read).
EXPLAINS_TAG_RE = re.compile(r"^explains-([A-Za-z_][A-Za-z0-9_]*)$")
TRY_RE = re.compile(r"try it yourself", re.IGNORECASE)
SOLUTION_START = "{solution-start}"
SOLUTION_END = "{solution-end}"
_BUILTINS = set(dir(__import__("builtins")))

#: Roles of cells (``Cell.role``).
ROLES = {
    "answer": "solution code: the student writes it (nbgrader autograded answer)",
    "prose": "solution text between solution-start and solution-end (removed from the student edition)",
    "test": "a check cell of a task that tests the student's answer (nbgrader autograder test)",
    "check": "a check cell that tests given data only (read-only, not graded)",
    "given": "code the student runs as given (read-only)",
    "text": "problem statement, questions, hints (read-only)",
    "try": "a Try it yourself cell (editable, not graded)",
}


# ---------------------------------------------------------------- notebooks on disk
def load_notebook(path: Path) -> dict:
    return json.loads(Path(path).read_text(encoding="utf-8"))


def dump_notebook(nb: dict) -> str:
    """The notebook as nbformat writes it (so that unchanged notebooks stay byte-identical)."""
    return json.dumps(nb, sort_keys=True, indent=1, ensure_ascii=False) + "\n"


def source(cell: dict) -> str:
    src = cell.get("source", "")
    return "".join(src) if isinstance(src, list) else src


def tags(cell: dict) -> set[str]:
    return set(cell.get("metadata", {}).get("tags", []))


# ---------------------------------------------------------------- markdown structure
def level2_headings(markdown: str) -> list[str]:
    """Level-2 headings (``## ...``) outside fenced blocks, in order."""
    out, fence = [], None
    for line in markdown.splitlines():
        m = FENCE_RE.match(line)
        if m:
            marker = m.group(1)[0] * 3
            if fence is None:
                fence = marker
            elif line.strip().startswith(fence):
                fence = None
            continue
        if fence is None:
            h = H2_RE.match(line)
            if h and not line.startswith("###"):
                out.append(h.group(1))
    return out


def is_marker_only(markdown: str) -> bool:
    """True if the cell holds nothing but a solution-start or solution-end directive."""
    text = re.sub(r"```+\{solution-(start|end)\}[^\n]*\n(:[^\n]*\n)*```+", "", markdown + "\n")
    return not text.strip()


# ---------------------------------------------------------------- names in code
class _Names(ast.NodeVisitor):
    """Names a piece of code reads before binding them (free) and names it binds (defined).

    Walks statements in evaluation order, so that ``for q in Q: f(q)`` does not read
    a global ``q``, and keeps the scopes of functions, lambdas and comprehensions
    apart (their parameters and local names are not the notebook's).
    """

    def __init__(self) -> None:
        self.bound: set[str] = set()
        self.free: set[str] = set()
        self.defined: list[str] = []  # module-level bindings, in order

    # -- helpers
    def _bind(self, name: str) -> None:
        self.bound.add(name)
        if name not in self.defined:
            self.defined.append(name)

    def _read(self, name: str) -> None:
        if name not in self.bound:
            self.free.add(name)

    def _targets(self, node: ast.AST) -> None:
        if isinstance(node, ast.Name):
            self._bind(node.id)
        elif isinstance(node, (ast.Tuple, ast.List)):
            for elt in node.elts:
                self._targets(elt)
        elif isinstance(node, ast.Starred):
            self._targets(node.value)
        else:  # attribute or subscript: reads its base
            self.visit(node)

    def _scope(self, params: set[str], body: Sequence[ast.AST]) -> None:
        """Free names of a nested scope: read there, bound neither there nor as parameters."""
        inner = _Names()
        inner.bound = set(params)
        for node in body:
            inner.visit(node)
        local = set(inner.defined) | params
        for name in inner.free:
            if name not in local:
                self._read(name)

    # -- statements
    def visit_Name(self, node: ast.Name) -> None:
        if isinstance(node.ctx, ast.Load):
            self._read(node.id)
        else:
            self._bind(node.id)

    def visit_Assign(self, node: ast.Assign) -> None:
        self.visit(node.value)
        for target in node.targets:
            self._targets(target)

    def visit_AugAssign(self, node: ast.AugAssign) -> None:
        self.visit(node.value)
        if isinstance(node.target, ast.Name):
            self._read(node.target.id)
            self._bind(node.target.id)
        else:
            self.visit(node.target)

    def visit_AnnAssign(self, node: ast.AnnAssign) -> None:
        if node.value is not None:
            self.visit(node.value)
        self._targets(node.target)

    def visit_NamedExpr(self, node: ast.NamedExpr) -> None:
        self.visit(node.value)
        self._targets(node.target)

    def visit_For(self, node: ast.For | ast.AsyncFor) -> None:
        self.visit(node.iter)
        self._targets(node.target)
        for stmt in node.body + node.orelse:
            self.visit(stmt)

    visit_AsyncFor = visit_For

    def visit_With(self, node: ast.With | ast.AsyncWith) -> None:
        for item in node.items:
            self.visit(item.context_expr)
            if item.optional_vars is not None:
                self._targets(item.optional_vars)
        for stmt in node.body:
            self.visit(stmt)

    visit_AsyncWith = visit_With

    def visit_Import(self, node: ast.Import) -> None:
        for alias in node.names:
            self._bind(alias.asname or alias.name.split(".")[0])

    def visit_ImportFrom(self, node: ast.ImportFrom) -> None:
        for alias in node.names:
            if alias.name != "*":
                self._bind(alias.asname or alias.name)

    def visit_ExceptHandler(self, node: ast.ExceptHandler) -> None:
        if node.type is not None:
            self.visit(node.type)
        if node.name:
            self._bind(node.name)
        for stmt in node.body:
            self.visit(stmt)

    def _function(self, node) -> None:
        for deco in node.decorator_list:
            self.visit(deco)
        args = node.args
        for default in args.defaults + [d for d in args.kw_defaults if d is not None]:
            self.visit(default)
        params = {a.arg for a in args.posonlyargs + args.args + args.kwonlyargs}
        params |= {a.arg for a in (args.vararg, args.kwarg) if a is not None}
        self._bind(node.name)  # recursion reads the function itself
        self._scope(params, node.body)

    visit_FunctionDef = visit_AsyncFunctionDef = _function

    def visit_ClassDef(self, node: ast.ClassDef) -> None:
        for base in node.bases + node.decorator_list:
            self.visit(base)
        self._bind(node.name)
        self._scope(set(), node.body)

    def visit_Lambda(self, node: ast.Lambda) -> None:
        args = node.args
        for default in args.defaults + [d for d in args.kw_defaults if d is not None]:
            self.visit(default)
        params = {a.arg for a in args.posonlyargs + args.args + args.kwonlyargs}
        params |= {a.arg for a in (args.vararg, args.kwarg) if a is not None}
        self._scope(params, [node.body])

    def _comprehension(self, node, elements: list[ast.AST]) -> None:
        # the first iterable is evaluated in the enclosing scope
        self.visit(node.generators[0].iter)
        inner = _Names()
        for k, gen in enumerate(node.generators):
            if k:
                inner.visit(gen.iter)
            inner._targets(gen.target)
            for cond in gen.ifs:
                inner.visit(cond)
        for elt in elements:
            inner.visit(elt)
        for name in inner.free:
            self._read(name)

    def visit_ListComp(self, node: ast.ListComp | ast.SetComp | ast.GeneratorExp) -> None:
        self._comprehension(node, [node.elt])

    visit_SetComp = visit_GeneratorExp = visit_ListComp

    def visit_DictComp(self, node: ast.DictComp) -> None:
        self._comprehension(node, [node.key, node.value])

    def visit_Global(self, node: ast.Global) -> None:  # pragma: no cover - not used in chapters
        pass


def _parse(code: str) -> ast.Module | None:
    # IPython magics and shell escapes are not Python: leave such lines out
    lines = ["" if line.lstrip().startswith(("%", "!")) else line for line in code.splitlines()]
    try:
        return ast.parse("\n".join(lines))
    except SyntaxError:
        return None


def _end_line(node: ast.stmt) -> int:
    """The last line of a statement of a parsed tree (``ast.parse`` sets ``end_lineno`` on every
    statement; the type says ``int | None`` for nodes built by hand)."""
    return node.end_lineno if node.end_lineno is not None else node.lineno


def _indent(line: str) -> str:
    """The leading white space of ``line`` (empty if none)."""
    match = re.match(r"\s*", line)
    return match.group(0) if match else ""


@functools.lru_cache(maxsize=8192)
def _names(code: str) -> _Names:
    """The names ``code`` reads and binds; memoised per source string (autograde traces the same
    cells for every failing test of every submission), so the result is read-only: copy it."""
    visitor = _Names()
    tree = _parse(code)
    if tree is not None:
        for stmt in tree.body:
            visitor.visit(stmt)
    return visitor


def defined_names(code: str) -> list[str]:
    """Module-level names the code binds, in order of first binding."""
    return list(_names(code).defined)


def free_names(code: str) -> set[str]:
    """Names the code reads before binding them: what it takes from earlier cells."""
    return set(_names(code).free)


# ---------------------------------------------------------------- calls of robokin.check
def check_aliases(code: str) -> dict[str, str]:
    """Local names of check modules: ``{"check_ur10": "ur10", "check": "*"}``."""
    return dict(_check_aliases_of(code))


@functools.lru_cache(maxsize=8192)
def _check_aliases_of(code: str) -> dict[str, str]:
    """:func:`check_aliases`, memoised per source string (autograde asks for every cell of every
    submission): read-only."""
    tree = _parse(code)
    out: dict[str, str] = {}
    if tree is None:
        return out
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module == "robokin.check":
            for alias in node.names:
                out[alias.asname or alias.name] = alias.name
        elif isinstance(node, ast.ImportFrom) and node.module == "robokin":
            for alias in node.names:
                if alias.name == "check":
                    out[alias.asname or "check"] = "*"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "robokin.check" and alias.asname:
                    out[alias.asname] = "*"
    return out


def check_calls(code: str, aliases: dict[str, str]) -> list[tuple[str, str]]:
    """Calls of exercise checks on an answer: ``[("leg.rotation_B1", "my_R_B1"), ...]``.

    Each item is the check (``chapter.attribute``) and the source text of its first
    argument. Calls that feed a deliberately wrong answer are left out: those on a
    line that says so (``# deliberately wrong``), those whose outcome is compared
    with a diagnosis, and those whose argument is a lambda that changes the answer.
    """
    tree = _parse(code)
    if tree is None:
        return []
    lines = code.splitlines()
    out: list[tuple[str, str]] = []

    def target(func: ast.AST) -> str | None:
        # check.leg.rotation_B1 / check_ur10.weighted_pinv / robokin.check.leg.x
        parts = []
        while isinstance(func, ast.Attribute):
            parts.append(func.attr)
            func = func.value
        if not isinstance(func, ast.Name):
            return None
        parts.append(func.id)
        parts.reverse()
        base: str | None
        if parts[:2] == ["robokin", "check"]:
            parts = ["check"] + parts[2:]
            base = "*"
        else:
            base = aliases.get(parts[0])
        if base is None:
            return None
        if base == "*":
            return ".".join(parts[1:3]) if len(parts) == 3 else None
        return f"{base}.{parts[1]}" if len(parts) == 2 else None

    def negative(stmt: ast.stmt) -> bool:
        """Whether ``stmt`` feeds a deliberately wrong answer: it says so in a comment directly
        above it (a formatter moves a long trailing ``# deliberately wrong`` there), or it
        compares the outcome with a diagnosis or negates it."""
        first = stmt.lineno
        while first > 1 and lines[first - 2].lstrip().startswith("#"):
            first -= 1
        above = "\n".join(lines[first - 1: stmt.lineno - 1])
        text = "\n".join(lines[stmt.lineno - 1: stmt.end_lineno])
        return "diagnosis" in text or re.search(r"\bnot\b", text) is not None or "wrong" in above.lower()

    owner = _innermost_statements(tree)
    for stmt in tree.body:
        for node in ast.walk(stmt):
            if not (isinstance(node, ast.Call) and node.args):
                continue
            name = target(node.func)
            if name is None:
                continue
            call_text = "\n".join(lines[node.lineno - 1: node.end_lineno])  # a formatter may move the comment
            # judged by the statement that holds the call: inside ``with your_answers(...):``
            # a call is judged by its own line, as at the top level of a cell
            if "wrong" in call_text.lower() or negative(owner[node]):
                continue
            arg = node.args[0]
            if isinstance(arg, ast.Lambda) and not _plain_wrapper(arg):
                continue
            segment = ast.get_source_segment(code, arg)
            if segment:
                out.append((name, segment))
    return out


def _innermost_statements(tree: ast.Module) -> dict[ast.Call, ast.stmt]:
    """The innermost statement that holds each call of ``tree`` (a call in a compound statement's
    header, e.g. ``with check(...):``, belongs to the compound statement)."""
    owner: dict[ast.Call, ast.stmt] = {}

    def visit(node: ast.AST, statement: ast.stmt | None) -> None:
        if isinstance(node, ast.Call) and statement is not None:
            owner[node] = statement
        for child in ast.iter_child_nodes(node):
            visit(child, child if isinstance(child, ast.stmt) else statement)

    visit(tree, None)
    return owner


def _plain_wrapper(node: ast.Lambda) -> bool:
    """``lambda a, b: f(a, b)``: the same function, called with the same arguments."""
    params = [a.arg for a in node.args.args]
    body = node.body
    return (
        isinstance(body, ast.Call)
        and not body.keywords
        and [a.id for a in body.args if isinstance(a, ast.Name)] == params
        and len(body.args) == len(params)
    )


# ---------------------------------------------------------------- stubs
@dataclass
class StubPlan:
    """How a solution cell becomes a stub: regions to clear and names to declare.

    ``regions`` are ``(first_line, last_line, indent, declare)`` (1-based, inclusive):
    nbgrader replaces each with its code stub; ``declare`` are names assigned
    ``None`` just before the region, so that the student sees which variables to
    define.
    """

    regions: list[tuple[int, int, str, list[str]]] = field(default_factory=list)
    kept: list[int] = field(default_factory=list)  # lines kept as they are (signatures, imports)


#: A top-level comment line that starts the *given* tail of an answer cell: from it to the
#: end of the cell the code is the solution's demonstration (it runs the answer, e.g. prints
#: it at the problem's data), which the student edition keeps as it is written.
GIVEN_MARKER = "# Given:"


def given_tail_start(code: str) -> int | None:
    """The line (1-based) of the :data:`GIVEN_MARKER` comment of an answer cell; None without one."""
    for number, line in enumerate(code.splitlines(), 1):
        if line.startswith(GIVEN_MARKER):
            return number
    return None


def solution_part(code: str) -> str:
    """An answer cell's code without its given tail (the lines from :data:`GIVEN_MARKER` on)."""
    start = given_tail_start(code)
    return code if start is None else "\n".join(code.splitlines()[: start - 1])


def stub_plan(code: str, interface: set[str] | None = None) -> StubPlan | None:
    """Regions of a solution cell to replace by a stub, keeping signatures and imports.

    * ``import`` statements stay;
    * a function keeps its decorators, signature and docstring; its body is a region;
    * every run of other statements is one region; the names it assigns that later
      cells read (``interface``; all of them when None) are declared ``= None``;
    * the given tail, from a top-level comment line that starts with :data:`GIVEN_MARKER`
      to the end of the cell, stays as it is: a demonstration that runs the answer and
      asks nothing of the student (so the stub asks for nothing there). It must not assign
      a name of ``interface``: that would overwrite the student's answer (ValueError).

    Returns None when the cell is not valid Python (then nbgrader replaces the whole cell).
    """
    tree = _parse(code)
    if tree is None or not tree.body:
        return None
    lines = code.splitlines()
    plan = StubPlan()
    run: list[ast.stmt] = []
    tail = given_tail_start(code)
    if tail is not None:
        inside = [stmt for stmt in tree.body if stmt.lineno < tail < _end_line(stmt)]
        if inside:
            raise ValueError(f"the {GIVEN_MARKER!r} line {tail} is inside a statement (line "
                             f"{inside[0].lineno}): put it at the top level, before the given code")
        given = [stmt for stmt in tree.body if stmt.lineno > tail]
        overwritten = sorted(
            {name for stmt in given for name in _names(ast.unparse(stmt)).defined}
            & (interface or set()))
        if overwritten:
            raise ValueError(f"the given tail (from line {tail}) assigns {', '.join(overwritten)}, "
                             "which the student's answer defines: move it above the "
                             f"{GIVEN_MARKER!r} line")
        plan.kept.extend(range(tail, len(lines) + 1))
        tree.body = [stmt for stmt in tree.body if stmt.lineno < tail]

    def flush() -> None:
        if not run:
            return
        first, last = run[0].lineno, _end_line(run[-1])
        # comments directly above the run belong to it
        while first > 1 and lines[first - 2].lstrip().startswith("#"):
            first -= 1
        names = []
        for stmt in run:
            for name in _names(ast.unparse(stmt)).defined:
                if (interface is None or name in interface) and name not in names:
                    names.append(name)
        plan.regions.append((first, last, "", names))
        run.clear()

    for stmt in tree.body:
        if isinstance(stmt, (ast.Import, ast.ImportFrom)):
            flush()
            plan.kept.extend(range(stmt.lineno, _end_line(stmt) + 1))
        elif isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef)):
            flush()
            body = stmt.body
            start = stmt.decorator_list[0].lineno if stmt.decorator_list else stmt.lineno
            if (
                body
                and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)
            ):
                doc_end = _end_line(body[0])
                body = body[1:]
            else:
                doc_end = body[0].lineno - 1
                # comment lines between the signature and the first statement are body
                while doc_end > stmt.lineno and lines[doc_end - 1].lstrip().startswith("#"):
                    doc_end -= 1
            plan.kept.extend(range(start, doc_end + 1))
            indent = _indent(lines[stmt.body[0].lineno - 1])
            if body or doc_end < _end_line(stmt):
                plan.regions.append((doc_end + 1, _end_line(stmt), indent, []))
        else:
            run.append(stmt)
    flush()
    return plan


def mark_solution(code: str, interface: set[str] | None = None,
                  begin: str = "### BEGIN SOLUTION", end: str = "### END SOLUTION") -> str:
    """The cell with nbgrader's solution delimiters around every region of :func:`stub_plan`."""
    plan = stub_plan(code, interface)
    if plan is None or not plan.regions:
        return code
    return _replace_regions(code, plan, lambda region, indent: [f"{indent}{begin}", *region, f"{indent}{end}"])


def _replace_regions(code: str, plan: StubPlan, replace: Callable[[list[str], str], list[str]]) -> str:
    """``code`` with each region of ``plan`` replaced by its names declared (``name = None``),
    then ``replace(the region's lines, its indent)``; the lines outside the regions as they are."""
    lines = code.splitlines()
    out: list[str] = []
    starts = {first: (last, indent, names) for first, last, indent, names in plan.regions}
    k = 1
    while k <= len(lines):
        if k in starts:
            last, indent, names = starts[k]
            out.extend(f"{indent}{name} = None" for name in names)
            out.extend(replace(lines[k - 1: last], indent))
            k = last + 1
        else:
            out.append(lines[k - 1])
            k += 1
    return "\n".join(out)


# ---------------------------------------------------------------- the chapter
@dataclass
class Cell:
    index: int
    cell_type: str
    role: str
    section: str
    task: int | None
    source: str
    cell_id: str | None = None
    defines: list[str] = field(default_factory=list)
    reads: set[str] = field(default_factory=set)
    depends_on: set[str] = field(default_factory=set)  # names from the student's work it reads
    explain: list[tuple[str, str]] = field(default_factory=list)
    interface: set[str] = field(default_factory=set)  # for answers: names later cells read
    points: int = 1  # for tests: the tag ``points-N`` on the check cell (default 1)
    explains: set[str] = field(default_factory=set)  # for tests: the tags ``explains-<answer>``


@dataclass
class Chapter:
    path: Path
    cells: list[Cell]
    tasks: dict[int, str]  # number -> title
    problems: list[str]

    def tests(self, task: int | None = None) -> list[Cell]:
        return [c for c in self.cells if c.role == "test" and (task is None or c.task == task)]

    def answers(self, task: int | None = None) -> list[Cell]:
        return [c for c in self.cells if c.role == "answer" and (task is None or c.task == task)]

    @property
    def name(self) -> str:
        return self.path.stem


def analyse(path: Path, nb: dict | None = None, check_names: dict[str, str] | None = None) -> Chapter:
    """Roles, tasks and dependencies of every cell of a chapter notebook.

    ``check_names`` maps a check (``"leg.rotation_B1"``) to the name of the
    quantity it checks (``"R_B1"``); with it, a check also explains an answer
    whose variable has that name, even if no cell calls the check on it.
    """
    path = Path(path)
    nb = nb if nb is not None else load_notebook(path)
    cells, tasks, problems = _read_cells(nb["cells"])
    _trace_student_values(cells)
    _mark_interfaces(cells)
    _explain_tests(cells, check_names or {})
    problems += _task_problems(cells, tasks)
    return Chapter(path, cells, tasks, problems)


def _read_cells(raw_cells: list[dict]) -> tuple[list[Cell], dict[int, str], list[str]]:
    """Each cell's role, section and task (headings and solution blocks read in order), the
    tasks ``{number: title}``, and the problems of the notebook's structure."""
    cells: list[Cell] = []
    tasks: dict[int, str] = {}
    problems: list[str] = []
    section, task = "", None
    in_span = False
    after_try = False
    for index, raw in enumerate(raw_cells):
        text = source(raw)
        kind = raw["cell_type"]
        role = ""
        if kind == "markdown":
            starts, ends = SOLUTION_START in text, SOLUTION_END in text
            heads = level2_headings(text)
            if heads and not in_span:
                section = heads[-1]
                task = _task_heading(section, index, tasks, problems)
            if starts:
                if in_span:
                    problems.append(f"cell {index}: solution-start inside an open solution block")
                in_span = True
            role = "prose" if in_span else "text"
            if ends:
                if not in_span:
                    problems.append(f"cell {index}: solution-end without a solution-start")
                in_span = False
            after_try = bool(TRY_RE.search(text)) and not in_span
        elif kind == "code":
            role = _code_role(tags(raw), after_try)
        else:  # raw cells
            role = "text"
        cell = Cell(index, kind, role, section, task, text, raw.get("id"))
        for tag in tags(raw) if kind == "code" else ():
            m = POINTS_TAG_RE.match(tag)
            if m:
                cell.points = int(m.group(1))
            m = EXPLAINS_TAG_RE.match(tag)
            if m:
                cell.explains.add(m.group(1))
        cells.append(cell)
    if in_span:
        problems.append("a solution-start block is never closed (no solution-end)")
    return cells, tasks, problems


def _task_heading(section: str, index: int, tasks: dict[int, str], problems: list[str]) -> int | None:
    """The task number of the level-2 heading ``section`` (None if it is no task), recorded in ``tasks``."""
    m = TASK_RE.match("## " + section)
    if not m:
        return None
    number = int(m.group(1))
    if number in tasks:
        problems.append(f"cell {index}: a second heading for Task {number}")
    tasks[number] = m.group(2)
    return number


def _code_role(cell_tags: set[str], after_try: bool) -> str:
    """The role of a code cell from its tags, and whether it follows a *Try it yourself* heading."""
    if "solution" in cell_tags:
        return "answer"
    if "check" in cell_tags:
        return "check"
    return "try" if after_try else "given"


def _trace_student_values(cells: list[Cell]) -> None:
    """Which values come from the student's work: names bound by answers, and by given code
    that reads them (a given cell that recomputes a name cleans it). A check of a task that
    reads such a value is that task's test."""
    student: set[str] = set()
    for cell in cells:
        if cell.cell_type != "code":
            continue
        cell.defines = defined_names(cell.source)
        cell.reads = free_names(cell.source)
        cell.depends_on = {n for n in cell.reads if n in student}
        if cell.role == "answer" or cell.depends_on:
            student.update(cell.defines)
        else:
            student.difference_update(cell.defines)
        if cell.role == "check" and cell.task is not None and cell.depends_on:
            cell.role = "test"


def _mark_interfaces(cells: list[Cell]) -> None:
    """The names of an answer that later cells read: kept in the stub (declared = None)."""
    for k, cell in enumerate(cells):
        if cell.role != "answer":
            continue
        later = set()
        for other in cells[k + 1:]:
            if other.cell_type == "code" and other.role != "answer":
                later |= other.reads
        own = set(defined_names(solution_part(cell.source)))  # the given tail is not the student's
        cell.interface = {n for n in cell.defines if n in later and n in own}


def _explain_tests(cells: list[Cell], check_names: dict[str, str]) -> None:
    """What explains a failing test: checks called on the task's answers, and checks whose
    quantity has the name of an answer's variable; of a test tagged ``explains-<answer>``,
    only those on the answers it names."""
    aliases: dict[str, str] = {}
    for cell in cells:
        if cell.cell_type == "code":
            aliases.update(check_aliases(cell.source))
    calls: list[tuple[str, str]] = []
    for cell in cells:
        if cell.cell_type == "code" and cell.role != "answer":
            for call in check_calls(cell.source, aliases):
                if call not in calls:
                    calls.append(call)
    chapters_used = {name.split(".")[0] for name, _ in calls} | {
        v for v in aliases.values() if v != "*"
    }
    defined_before: set[str] = set()
    task_answers: dict[int | None, set[str]] = {}
    for cell in cells:
        if cell.cell_type != "code":
            continue
        if cell.role == "test":
            # the task's answers computed so far, and checks that can be run on them
            names = task_answers.get(cell.task, set())
            pairs: list[tuple[str, str]] = []
            for check, expr in calls:
                used = free_names(expr)
                if used & names and used <= defined_before | _BUILTINS and (check, expr) not in pairs:
                    pairs.append((check, expr))
            for check, quantity in sorted(check_names.items()):
                if check.split(".")[0] in chapters_used and quantity in names:
                    if not any(c == check for c, _ in pairs):
                        pairs.append((check, quantity))
            if cell.explains:  # the answers the test grades, named by its tags
                pairs = [(check, expr) for check, expr in pairs if free_names(expr) <= cell.explains]
            cell.explain = pairs
        if cell.role == "answer":
            task_answers.setdefault(cell.task, set()).update(cell.defines)
        defined_before.update(cell.defines)


def _task_problems(cells: list[Cell], tasks: dict[int, str]) -> list[str]:
    """Tasks without a solution cell or without a test of it; a notebook without tasks."""
    problems = []
    for number in sorted(tasks):
        if not [c for c in cells if c.task == number and c.role == "answer"]:
            problems.append(f"Task {number} has no solution cell (tag a code cell `solution`)")
        elif not [c for c in cells if c.task == number and c.role == "test"]:
            problems.append(
                f"Task {number} has no check cell that tests its solution (a `check` cell in the "
                "task that reads a value the solution cells define)"
            )
    if not tasks:
        problems.append("no task headings (`## Task k: ...`)")
    return problems


# ---------------------------------------------------------------- where a value comes from
@dataclass(frozen=True)
class Binding:
    """The last binding of a name before some cell.

    ``cell`` is the index of the code cell that bound it, ``answer`` whether that
    cell is an answer cell (the student wrote it), and ``roots`` the names bound
    by answer cells that the value depends on -- through given cells and other
    answers, the name itself included when an answer cell bound it.
    """

    cell: int
    answer: bool
    roots: frozenset[str]


def trace(cells: list[tuple[str, str]]) -> list[dict[str, Binding]]:
    """For every cell, the names it reads that an earlier code cell bound, with that binding.

    ``cells`` are ``(kind, source)`` pairs in notebook order, ``kind`` being
    ``"answer"`` for the student's cells, ``"code"`` for any other code cell and
    anything else (``"markdown"``) for cells that are not run. A given cell that
    reads an answer passes the answer on (``J = jacobian(q_answer)`` depends on
    ``q_answer``); a given cell that reads none makes a clean value.
    """
    table: dict[str, Binding] = {}
    out: list[dict[str, Binding]] = []
    for index, (kind, code) in enumerate(cells):
        if kind not in ("answer", "code"):
            out.append({})
            continue
        names = _names(code)
        reads = {name: table[name] for name in names.free if name in table}
        out.append(reads)
        inherited = frozenset().union(*(b.roots for b in reads.values())) if reads else frozenset()
        answer = kind == "answer"
        for name in names.defined:
            table[name] = Binding(index, answer, inherited | {name} if answer else inherited)
    return out


def statement_span(code: str, line: int) -> tuple[int, int]:
    """First and last line (1-based) of the top-level statement of ``code`` that contains ``line``."""
    tree = _parse(code)
    if tree is not None:
        for stmt in tree.body:
            if stmt.lineno <= line <= _end_line(stmt):
                decorators = getattr(stmt, "decorator_list", None)
                return (decorators[0].lineno if decorators else stmt.lineno), _end_line(stmt)
    return line, line


def statement_at(code: str, line: int) -> str:
    """The whole top-level statement of ``code`` that contains ``line`` (1-based); the line if none."""
    first, last = statement_span(code, line)
    return "\n".join(code.splitlines()[first - 1: last])


# ---------------------------------------------------------------- the student edition, statically
#: What nbgrader's ``ClearSolutions`` writes for a solution region of Python code.
CODE_STUB = "# YOUR CODE HERE\nraise NotImplementedError()"


def stub_source(code: str, declare: set[str] | None) -> str:
    """An answer cell as the student edition shows it (``MarkSolutionRegions`` + ``ClearSolutions``)."""
    plan = stub_plan(code, declare)
    if plan is None:
        return CODE_STUB
    if not plan.regions:
        return code
    return _replace_regions(code, plan, lambda region, indent: [f"{indent}{line}" for line in CODE_STUB.splitlines()])


def clear_solution_text(text: str, stub: str = "") -> str:
    """``text`` with every ``BEGIN SOLUTION`` ... ``END SOLUTION`` region (the marker lines
    included) replaced by ``stub``, as nbgrader's ``ClearSolutions`` does in markdown."""
    out: list[str] = []
    inside = False
    for line in text.split("\n"):
        if "BEGIN SOLUTION" in line:
            inside = True
            indent = _indent(line)
            out.extend(indent + s for s in stub.split("\n"))
        elif "END SOLUTION" in line:
            inside = False
        elif not inside:
            out.append(line)
    return "\n".join(out)


def student_markdown(cell: Cell) -> str | None:
    """The text of a markdown cell in the student edition; None when the cell is left out.

    Solution prose is removed (``MarkSolutionRegions`` marks a whole prose cell, unless it
    has ``BEGIN SOLUTION``/``END SOLUTION`` markers of its own, e.g. in HTML comments,
    which then keep the text around them); a cell left empty is left out
    (``DropSolutionProse``).
    """
    if cell.role != "prose":
        return cell.source
    text = clear_solution_text(cell.source) if "BEGIN SOLUTION" in cell.source else ""
    return text if text.strip() else None


def removed_in_student_edition(cell: Cell) -> bool:
    """Cells the student edition leaves out: solution prose with nothing else in it."""
    return cell.cell_type == "markdown" and student_markdown(cell) is None
