"""Answers that hand back robokin's own solution of the task (found in the answer cells' code).

An answer that calls -- or simply is -- the robokin function that solves its task
(``ik = robot.inverse_kinematics``) passes every test, since the tests compare with
that very function. Such an answer is flagged for review by hand; its score stands
as tested (the instructor decides). Besides this static look at the answer cells,
the bridge flags at run time a declared answer that *is* a robokin function (its
proxy reports the function's module: :mod:`tools.grading.bridge.execute`).

:data:`REFERENCES` lists, per ``robokin.check`` check, the robokin methods that
solve the task it checks. A task's reference list is that of the checks its test
cells explain (``metadata.robokin.explain``). A declared name of an answer cell of
the task is flagged when its definition -- or a helper it uses that the answer
cells define and do not declare -- mentions one of those methods (an attribute,
a name, or a string as in ``getattr(robot, "inverse_kinematics")``). A task whose
tests explain no check names its answers in :data:`ANSWERS` instead.
"""

from __future__ import annotations

import ast
from collections.abc import Collection, Iterable, Mapping

#: check -> {robokin method or function name: how the report names it}.
#:
#: Only tasks whose point is to write the function robokin already has are listed.
#: Where a chapter asks for robokin's own tools (chapter 4's frames through
#: ``transform_from_rpy``, the end-effector Jacobian ``arm.jacobian`` its tool Jacobian starts
#: from), calling them is the answer, not a delegation. The chapters' check modules add their
#: own tables (``DELEGATION``, read below): chapter 6's ``leg_ik`` and ``unreachable_reason``,
#: chapter 2's ``ik_restarts`` and ``bisect``.
REFERENCES: dict[str, dict[str, str]] = {}

_IK = {"solve_ik": "robokin.motion.solve_ik", "solve_ik_once": "robokin.motion.solve_ik_once",
       "solve_ik_batch": "robokin.motion.solve_ik_batch"}
# chapter 1, the ETH leg: the frames written by hand
for _key in ("rotation_B1", "rotation_12", "rotation_23", "transform_B1", "transform_12", "transform_23",
             "transform_3F", "transform_BF", "foot_position"):
    REFERENCES[f"leg.{_key}"] = {"eth_leg": "robokin.models.eth_leg (its fk/frames)",
                                 "frames": "SerialChain.frames"}
# the whole transform and the foot position: the chapter's own model ``leg`` evaluated
# (``H_BF = leg.fk(q_sym)``); ``fk`` of that object only, as the tests compare with it. Listed
# here, not in robokin/check/leg.py's DELEGATION: a check this table lists keeps this entry
# (the check modules' tables fill in only the checks it does not list)
for _key in ("transform_BF", "foot_position"):
    REFERENCES[f"leg.{_key}"].update({"leg.fk": "leg.fk (SerialChain.fk)"})
# chapter 2, the UR10: the IK loop (its weighted and damped steps, which robokin's step rules
# WeightedPseudoInverse and DampedLeastSquares give, are in robokin/check/ur10.py's DELEGATION)
REFERENCES["ur10.ik_position"] = dict(_IK)
# chapter 3, the 3-RPR
REFERENCES["three_rpr.inverse_kinematics"] = {"inverse_kinematics": "Planar3RPR.inverse_kinematics"}
REFERENCES["three_rpr.forward_kinematics"] = {"forward_kinematics": "Planar3RPR.forward_kinematics",
                                              "orientation_polynomial": "Planar3RPR.orientation_polynomial",
                                              "orientation_harmonics": "Planar3RPR.orientation_harmonics"}
REFERENCES["three_rpr.inverse_jacobian"] = {"jacobian": "Planar3RPR.jacobian",
                                            "direct_jacobian": "Planar3RPR.direct_jacobian"}
# chapter 5, Baxter: one command of the resolved-rate law
REFERENCES["baxter.resolved_rate"] = {"CartesianController": "robokin.motion.CartesianController",
                                      "simulate": "robokin.motion.simulate",
                                      "track_position_batch": "robokin.motion.track_position_batch"}
# chapter 6, the AR-601 leg: the forward kinematics multiplied factor by factor (T_sym), the
# knee angle and the IK solver written by hand
REFERENCES["ar601.foot_transform"] = {"ar601_leg": "robokin.models.ar601_leg (its fk)",
                                      "fk": "SerialChain.fk", "frames": "SerialChain.frames"}
REFERENCES["ar601.knee_angle"] = {"ar601_leg_ik": "robokin.models.ar601_leg_ik",
                                  "reference_knee_angle": "robokin.check.ar601.reference_knee_angle"}
REFERENCES["ar601.ik_solver"] = {"ar601_leg_ik": "robokin.models.ar601_leg_ik",
                                 "ar601_leg_ik_batch": "robokin.models.ar601_leg_ik_batch", **_IK}


def declared_references(check_folder: str | None = None) -> dict[str, dict[str, str]]:
    """The ``DELEGATION`` tables of the chapters' check modules, as ``{"<chapter>.<check>": {...}}``.

    A chapter's check module (``robokin/check/<chapter>.py``; tools/authoring/new_chapter.py writes
    one) may state, as a literal dict ``DELEGATION = {check: {method: how the report names
    it}}``, the robokin functions that solve its tasks. The modules are parsed, not
    imported; a module without the table, or whose table is not a literal, adds nothing.
    """
    import importlib.util
    from pathlib import Path

    if check_folder is None:
        spec = importlib.util.find_spec("robokin")
        if spec is None or not spec.submodule_search_locations:
            return {}
        check_folder = str(Path(list(spec.submodule_search_locations)[0]) / "check")
    found: dict[str, dict[str, str]] = {}
    for path in sorted(Path(check_folder).glob("[a-z]*.py")):
        try:
            tree = ast.parse(path.read_text(encoding="utf-8"))
        except (OSError, SyntaxError, ValueError):
            continue
        for stmt in tree.body:
            if isinstance(stmt, ast.Assign):
                targets, value = stmt.targets, stmt.value
            elif isinstance(stmt, ast.AnnAssign) and stmt.value is not None:
                targets, value = [stmt.target], stmt.value
            else:
                continue
            if not any(isinstance(t, ast.Name) and t.id == "DELEGATION" for t in targets):
                continue
            try:
                table = ast.literal_eval(value)
            except (ValueError, SyntaxError, TypeError):
                continue
            if isinstance(table, dict):
                for check, references in table.items():
                    if isinstance(check, str) and isinstance(references, dict):
                        found[f"{path.stem}.{check}"] = {str(k): str(v) for k, v in references.items()}
    return found


# the tables of the check modules, for the checks not listed above
for _check, _references in declared_references().items():
    REFERENCES.setdefault(_check, _references)

#: answer name -> {robokin function: how the report names it}, for a task whose tests explain
#: no check (so :data:`REFERENCES` cannot reach it). The name is looked at wherever an answer cell
#: declares it: keep to names only one chapter declares (tests/test_grading_tamper.py checks it).
#: A key ``"owner.method"`` names a method of one object (``tool_arm.jacobian``, also as
#: ``self.tool_arm.jacobian`` or ``getattr(tool_arm, "jacobian")``) where the method alone
#: (``arm.jacobian``) may be the answer's legitimate start; ``"method.keyword"`` names a call
#: of the method, or function, with that keyword argument (``arm.jacobian(q, point=p)``,
#: ``pose_error(T, T_goal, representation="rpy")``).
ANSWERS: dict[str, dict[str, str]] = {
    # chapter 4, Task 3: the tool's Jacobian transported by hand from the end-effector's
    # (arm.jacobian); the arm with the tool attached has the tool's Jacobian already
    "my_tool_jacobian": {"tool_jacobian": "robokin.motion.tool_jacobian",
                         "rigid_body_jacobian": "robokin.motion.rigid_body_jacobian",
                         "tool_arm.jacobian": "tool_arm.jacobian",
                         "jacobian.point": "SerialChain.jacobian(q, point=...)",
                         "chain_with_tool": "robokin.motion.tool.chain_with_tool"},
    # chapter 4, Task 2: the angle and axis from the entries of R
    "angle_axis": {"angle_axis_from_rotation": "robokin.transforms.angle_axis_from_rotation",
                   "rotation_log": "robokin.transforms.rotation_log"},
    # chapter 4, Task 3: the slide's column from the frames, not taken from a Jacobian
    "slide_column": {"jacobian": "SerialChain.jacobian", "tool_jacobian": "robokin.motion.tool_jacobian",
                     "rigid_body_jacobian": "robokin.motion.rigid_body_jacobian"},
    # chapter 4, Task 5: the wrapped RPY difference written out, not robokin's RPY error
    "rpy_difference": {"pose_error.representation": "robokin.motion.pose_error(..., representation=...)",
                       "reference_rpy_difference": "robokin.check.cartesian.reference_rpy_difference"},
    # chapter 7, Task 5: the conditions under which two branches meet, not ur10_ik's singular flags
    "coinciding_branches": {"ur10_ik": "robokin.models.ur10_ik", "ur10_ik_batch": "robokin.models.ur10_ik_batch"},
    # chapter 2, Task 2 (d): the three step rules written on the parts, not the tests' helper
    "STEPS": {"step_rules": "robokin.check.ur10.step_rules"},
}


def _owner_name(node: ast.AST) -> str | None:
    """The name an ``owner.method`` key uses for the owner: ``tool_arm`` for ``tool_arm`` and
    ``self.tool_arm``, None for anything else (a call, a subscript)."""
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.NamedExpr):   # (robot := tool_arm).jacobian
        return _owner_name(node.value)
    return None


def _aliases(codes: Iterable[str]) -> dict[str, set[str]]:
    """Name -> the names it may stand for, from simple assignments in the answer cells.

    ``robot = tool_arm`` (also inside a function, ``self.robot = tool_arm``, ``robot =
    self.tool_arm``, ``(robot := tool_arm)`` and chains ``a = tool_arm; b = a``) makes
    ``robot.jacobian`` mention ``tool_arm.jacobian``. Scopes are
    not told apart: a name assigned an object anywhere stands for it everywhere (a flag is a
    request to look, not a verdict).
    """
    direct: dict[str, set[str]] = {}
    for code in codes:
        try:
            tree = ast.parse(code)
        except (SyntaxError, ValueError, RecursionError, MemoryError):
            continue
        for sub in ast.walk(tree):
            if isinstance(sub, ast.Assign):
                targets, value = sub.targets, sub.value
            elif isinstance(sub, (ast.AnnAssign, ast.NamedExpr)) and sub.value is not None:
                targets, value = [sub.target], sub.value
            else:
                continue
            source = _owner_name(value)
            if source is None:
                continue
            for target in targets:   # robot = ..., self.robot = ...
                name = _owner_name(target) if isinstance(target, (ast.Name, ast.Attribute)) else None
                if name is not None and name != source:
                    direct.setdefault(name, set()).add(source)
    resolved: dict[str, set[str]] = {}
    for name in direct:   # the transitive closure, cycles included
        seen: set[str] = set()
        stack = list(direct[name])
        while stack:
            other = stack.pop()
            if other in seen or other == name:
                continue
            seen.add(other)
            stack += direct.get(other, ())
        resolved[name] = seen
    return resolved


def _mentions(node: ast.AST, aliases: dict[str, set[str]] | None = None) -> set[str]:
    aliases = aliases or {}

    def owner_and_aliases(owner: ast.AST) -> set[str]:
        name = _owner_name(owner)
        return set() if name is None else {name, *aliases.get(name, ())}

    out: set[str] = set()
    for sub in ast.walk(node):
        if isinstance(sub, ast.Attribute):
            out.add(sub.attr)
            # "owner.attr" too: a method of one named object, under any name it was given
            out.update(f"{owner}.{sub.attr}" for owner in owner_and_aliases(sub.value))
        elif isinstance(sub, ast.Call):
            # "method.keyword" for a method's call and a function's (pose_error(..., representation=...))
            method = (sub.func.attr if isinstance(sub.func, ast.Attribute)
                      else sub.func.id if isinstance(sub.func, ast.Name) else None)
            if (isinstance(sub.func, ast.Name) and sub.func.id == "getattr" and len(sub.args) >= 2
                    and isinstance(sub.args[1], ast.Constant) and isinstance(sub.args[1].value, str)):
                method, target = sub.args[1].value, sub.args[0]
                out.update(f"{owner}.{method}" for owner in owner_and_aliases(target))
            if method is not None:
                out.update(f"{method}.{keyword.arg}" for keyword in sub.keywords if keyword.arg)
        elif isinstance(sub, ast.Name):
            out.add(sub.id)
        elif isinstance(sub, ast.alias):
            out.add(sub.name.rsplit(".", 1)[-1])
            if sub.asname:
                out.add(sub.asname)
        elif isinstance(sub, ast.Constant) and isinstance(sub.value, str) and len(sub.value) < 80:
            out.add(sub.value)
    return out


def _definitions(code: str) -> dict[str, tuple[ast.stmt | ast.Module, bool]]:
    """Top-level name -> (its defining statement, True when it is bound to an attribute or name)."""
    try:
        tree = ast.parse(code)
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return {}
    out: dict[str, tuple[ast.stmt | ast.Module, bool]] = {}
    for stmt in tree.body:
        if isinstance(stmt, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            out[stmt.name] = (stmt, False)
        elif isinstance(stmt, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = stmt.targets if isinstance(stmt, ast.Assign) else [stmt.target]
            value = stmt.value
            bound = isinstance(value, (ast.Attribute, ast.Name)) or (
                isinstance(value, ast.Call) and isinstance(value.func, ast.Name)
                and value.func.id == "partial")
            for target in targets:
                for sub in ast.walk(target):
                    if isinstance(sub, ast.Name):
                        previous = out.get(sub.id)
                        # a name assigned twice: all its statements count
                        if previous is None:
                            node: ast.stmt | ast.Module = stmt
                        else:
                            earlier = previous[0].body if isinstance(previous[0], ast.Module) else [previous[0]]
                            node = ast.Module(body=[*earlier, stmt], type_ignores=[])
                        out[sub.id] = (node, bound)
        elif isinstance(stmt, (ast.Import, ast.ImportFrom)):
            for alias in stmt.names:
                out[(alias.asname or alias.name).split(".")[0]] = (stmt, True)
    return out


def _names(expression: str) -> set[str] | None:
    """The names an explained expression reads (None if it cannot be parsed)."""
    try:
        tree = ast.parse(expression, mode="eval")
    except (SyntaxError, ValueError, RecursionError, MemoryError):
        return None
    return {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)}


def find(answers: Iterable[tuple[int | None, str, list[str]]],
         task_checks: Mapping[int | None, Collection[str] | Mapping[str, Collection[str]]]) -> list[dict]:
    """Delegating answers.

    Parameters
    ----------
    answers : iterable of (task, code, declared names)
        The answer cells of the submission, in order.
    task_checks : mapping
        Task -> the checks its test cells explain: a collection of check names, or a
        mapping check -> the expressions it checks (``metadata.robokin.explain``); then only
        the names those expressions read are looked at (the answers the check tests).

    Returns
    -------
    list of dict
        ``{"task", "name", "reference", "how", "through"}`` per flagged name.
    """
    cells = list(answers)
    defined: dict[str, tuple[ast.stmt | ast.Module, bool]] = {}
    for _, code, _ in cells:
        defined.update(_definitions(code))
    aliases = _aliases(code for _, code, _ in cells)
    declared = {name for _, _, names in cells for name in names}
    found: list[dict] = []
    seen: set[str] = set()
    for task, code, names in cells:
        references: dict[str, str] = {}
        tested: set[str] | None = set()
        checks = task_checks.get(task, set())
        for check in checks:
            if check not in REFERENCES:
                continue
            references.update(REFERENCES[check])
            for expression in (checks[check] if isinstance(checks, Mapping) else [None]):
                read = None if expression is None else _names(expression)
                tested = None if tested is None or read is None else tested | read
        if not references and not set(names) & set(ANSWERS):
            continue
        local = _definitions(code)
        for name in names:
            own = ANSWERS.get(name, {})
            if name in seen or name not in local or (not own and (
                    not references or (tested is not None and name not in tested))):
                continue
            node, bound = local[name]
            name_references = {**references, **own}
            direct = _mentions(node, aliases) & set(name_references)
            through = None
            if not direct:   # helpers the answers define and do not declare
                stack, visited = [n for n in _mentions(node, aliases) if n in defined and n not in declared], set()
                while stack and not direct:
                    helper = stack.pop()
                    if helper in visited or helper == name:
                        continue
                    visited.add(helper)
                    mentions = _mentions(defined[helper][0], aliases)
                    hit = mentions & set(name_references)
                    if hit:
                        direct, through = hit, helper
                    stack += [n for n in mentions if n in defined and n not in declared]
            if direct:
                seen.add(name)
                attr = sorted(direct)[0]
                found.append({"task": task, "name": name, "reference": name_references[attr],
                              "how": "is" if bound and through is None else "calls", "through": through})
    return found


def describe(item: dict) -> str:
    """The report's line for one flagged answer."""
    if item["how"] == "runtime":
        text = f"`{item['name']}` is robokin's `{item['reference']}` (seen when the grader took the answer)"
    elif item["how"] == "is":
        text = f"`{item['name']}` returns robokin's `{item['reference']}` (it is bound to it)"
    else:
        text = f"`{item['name']}` calls robokin's `{item['reference']}`"
        if item.get("through"):
            text += f" (through `{item['through']}`)"
    return f"review by hand: {text}"
