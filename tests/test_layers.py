"""The layer rule of CONTRIBUTING.md, enforced: every import of every robokin module, read with ``ast``.

Layers (a module imports only modules of its own layer or of layers before it)::

    1. robokin.errors, robokin.validation, robokin._dispatch, robokin.formatting
    2. robokin.transforms
    3. robokin.chains, robokin.models, robokin.parallel
    4. robokin.motion
    5. robokin.views, robokin.check
    (6. notebooks/)

Three tests read the same import graph (imports inside functions included):

- no module imports a module of a later layer;
- no import cycle between modules (a cycle held together by imports inside
  functions is still a cycle);
- no private name (``_x``) is imported from another module, apart from the
  exceptions listed in ``PRIVATE_EXCEPTIONS`` with their reason.

A fourth keeps the views free of imports inside functions: only
``robokin/views/optional.py`` imports the optional libraries (lazily, one
function each), and the MeshCat server process imports tornado/MeshCat in its
``main`` (after recording its parent's pid, which must come first).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "robokin"

#: Layer of each top-level part of robokin (the first dotted component after ``robokin``).
LAYERS = {
    "errors": 1, "validation": 1, "_dispatch": 1, "formatting": 1,
    "transforms": 2,
    "chains": 3, "models": 3, "parallel": 3,
    "motion": 4,
    "views": 5, "check": 5,
}
LAYER_NAMES = {1: "errors/validation/_dispatch/formatting", 2: "transforms", 3: "chains/models/parallel",
               4: "motion", 5: "views/check"}

#: ``(importing module, imported module, private name)``: reason. Keep it short; each entry is a debt.
PRIVATE_EXCEPTIONS: dict[tuple[str, str, str], str] = {
}

#: Import cycles known when this test was written, each held by imports inside functions: reason.
#: A cycle not listed here fails; a listed cycle that is gone fails too (remove it from the list).
KNOWN_CYCLES: dict[frozenset, str] = {}

#: The modules of robokin.views, bottom up: each imports only views modules listed before it
#: (the layers of the robokin.views docstring). ``_server`` runs in its own process and imports none.
VIEWS_ORDER = ["optional", "record", "arguments", "geometry", "ellipsoids", "meshcat_draw", "static_html", "plots",
               "ellipse_plots", "meshes", "live", "sphinx_extension", "display", "scene", "sliders", "_server", ""]

#: Modules allowed to import inside functions (all other views modules import at the top).
FUNCTION_IMPORTS_ALLOWED = {
    "robokin.views.optional": "the one place that imports each optional library, on first use",
    "robokin.views._server": "the server process records its parent's pid before the slow tornado/MeshCat imports",
}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _is_package(name: str) -> bool:
    return MODULES[name].name == "__init__.py"


def _resolve(module: str, node: ast.ImportFrom) -> str:
    """The absolute module name of a ``from ... import`` (relative imports resolved)."""
    if not node.level:
        return node.module or ""
    base = module.split(".") if _is_package(module) else module.split(".")[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports(module: str):
    """``(line, target module, imported name or None, inside a function)`` of every robokin import."""
    tree = ast.parse(MODULES[module].read_text(encoding="utf-8"))
    functions = {id(n) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
                 for n in ast.walk(f) if n is not f}
    for node in ast.walk(tree):
        inside = id(node) in functions
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "robokin":
                    yield node.lineno, alias.name, None, inside
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, node)
            if target.split(".")[0] != "robokin":
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in MODULES:
                    yield node.lineno, sub, None, inside
                else:
                    yield node.lineno, target, alias.name, inside


def _layer(module: str) -> int | None:
    parts = module.split(".")
    return LAYERS.get(parts[1]) if len(parts) > 1 else None   # the package robokin itself: no layer


def _where(module: str, line: int) -> str:
    return f"{MODULES[module].relative_to(ROOT)}:{line} ({module})"


def test_every_part_of_robokin_has_a_layer():
    parts = {m.split(".")[1] for m in MODULES if m != "robokin"}
    assert parts <= set(LAYERS), f"parts of robokin without a layer in tests/test_layers.py: {parts - set(LAYERS)}"


def test_no_module_imports_a_later_layer():
    problems = []
    for module in MODULES:
        mine = _layer(module)
        if mine is None:
            continue
        for line, target, name, inside in _imports(module):
            theirs = _layer(target)
            if theirs is not None and theirs > mine:
                what = f"from {target} import {name}" if name else f"import {target}"
                problems.append(f"{_where(module, line)}: `{what}`{' (inside a function)' if inside else ''} -- "
                                f"layer {mine} ({LAYER_NAMES[mine]}) must not import layer {theirs} "
                                f"({LAYER_NAMES[theirs]}); see CONTRIBUTING.md, Layers")
    assert not problems, "\n".join(problems)


def _graph():
    return {m: {target for _, target, _, _ in _imports(m) if target in MODULES and target != m} for m in MODULES}


def _cycles(graph):
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index, low, stack, on_stack, out, counter = {}, {}, [], set(), [], [0]
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(sorted(graph[start])))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            for child in children:
                if child not in index:
                    index[child] = low[child] = counter[0]
                    counter[0] += 1
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                    break
                if child in on_stack:
                    low[node] = min(low[node], index[child])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1:
                        out.append(sorted(component))
    return out


def _cycle_path(graph, component):
    """One cycle through the component, as ``a -> b -> ... -> a``."""
    members = set(component)
    start = component[0]
    path, seen = [start], {start}
    while True:
        nxt = sorted(t for t in graph[path[-1]] if t in members)
        back = [t for t in nxt if t == start]
        if back and len(path) > 1:
            return " -> ".join(path + [start])
        fresh = [t for t in nxt if t not in seen]
        if not fresh:
            loop_start = next(t for t in nxt if t in seen)
            return " -> ".join(path[path.index(loop_start):] + [loop_start])
        path.append(fresh[0])
        seen.add(fresh[0])


def test_no_import_cycles():
    graph = _graph()
    cycles = _cycles(graph)
    problems = []
    for component in cycles:
        if frozenset(component) in KNOWN_CYCLES:
            continue
        lines: list[str] = []
        for module in component:
            for line, target, _name, inside in _imports(module):
                if target in component and target != module and not any(f":{line} " in x for x in lines
                                                                          if module in x):
                    lines.append(f"  {_where(module, line)} imports {target}{' inside a function' if inside else ''}")
        problems.append(f"import cycle {_cycle_path(graph, component)} -- modules must not import each other "
                        f"in a ring (CONTRIBUTING.md, Layers):\n" + "\n".join(lines))
    assert not problems, "\n".join(problems)


def test_known_cycles_are_still_there():
    cycles = {frozenset(c) for c in _cycles(_graph())}
    gone = [sorted(c) for c in KNOWN_CYCLES if c not in cycles]
    assert not gone, f"remove these from KNOWN_CYCLES in tests/test_layers.py (the cycle is gone): {gone}"


def test_no_private_names_across_modules():
    problems = []
    for module in MODULES:
        for line, target, name, _ in _imports(module):
            if name is None or not name.startswith("_") or name.startswith("__"):
                continue
            if (module, target, name) in PRIVATE_EXCEPTIONS:
                continue
            problems.append(f"{_where(module, line)}: `from {target} import {name}` -- a private name is used "
                            f"only in its own module: make it public (and documented) or move the code")
    assert not problems, "\n".join(problems)


def test_private_exceptions_are_still_needed():
    used = {(m, t, n) for m in MODULES for _, t, n, _ in _imports(m)}
    stale = [key for key in PRIVATE_EXCEPTIONS if key not in used]
    assert not stale, f"remove these from PRIVATE_EXCEPTIONS (no longer imported): {stale}"


def test_views_modules_import_only_those_below_them():
    rank = {("robokin.views." + name).rstrip("."): k for k, name in enumerate(VIEWS_ORDER)}
    views = [m for m in MODULES if m.startswith("robokin.views")]
    assert set(views) == set(rank), (f"add/remove modules in VIEWS_ORDER of tests/test_layers.py: "
                                     f"{set(views) ^ set(rank)}")
    problems = []
    for module in views:
        for line, target, _name, _ in _imports(module):
            if target in rank and target != module and rank[target] >= rank[module]:
                problems.append(f"{_where(module, line)}: imports {target}, which comes after it in the views' layers "
                                f"(VIEWS_ORDER in tests/test_layers.py, the robokin.views docstring)")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith("robokin.views")))
def test_views_import_at_the_top(module):
    if module in FUNCTION_IMPORTS_ALLOWED:
        return
    tree = ast.parse(MODULES[module].read_text(encoding="utf-8"))
    problems = []
    for function in ast.walk(tree):
        if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for node in ast.walk(function):
                if isinstance(node, (ast.Import, ast.ImportFrom)):
                    problems.append(f"{_where(module, node.lineno)}: import inside {function.name}() -- views "
                                    f"import at the top; optional libraries come from robokin.views.optional")
    assert not problems, "\n".join(problems)
