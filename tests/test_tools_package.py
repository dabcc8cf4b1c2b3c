"""``tools/`` is a package imported by name: no import through ``sys.path``, no private name across modules.

The scripts, ``nbgrader_config.py``, the book's extension, the grader kernels and the tests import
the tools as ``tools.<module>`` (the editable install of ``pyproject.toml`` exposes the package);
nothing puts a folder on ``sys.path`` to import a module by its bare name, neither in a file nor
in code a file hands to another interpreter (a kernel's start-up code, ``python -c``). Inside
``tools/``, a module imports only public names of another (as ``tests/test_layers.py`` holds
robokin to).
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Every Python file of the repository outside robokin/ (whose imports tests/test_layers.py reads), but
#: this one (its strings are the examples of what it looks for).
FILES = sorted(path for path in [*ROOT.glob("*.py"), *(ROOT / "tools").rglob("*.py"), *(ROOT / "tests").rglob("*.py"),
                                 *(ROOT / "book" / "_ext").rglob("*.py"), *(ROOT / "benchmarks").rglob("*.py")]
               if path != Path(__file__).resolve())
#: The calls that put a folder on the import path.
PATH_CALLS = ("sys.path.insert(", "sys.path.append(", "sys.path.extend(", "site.addsitedir(")


def _relative(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def _path_calls(tree: ast.AST) -> list[int]:
    """Lines that call ``sys.path.insert``/``append``/``extend`` or ``site.addsitedir``, in code or in a
    string that holds code (``"sys.path.insert(0, ...)"`` run by a kernel or ``python -c``)."""
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            name = ast.unparse(node.func)
            if any(name == call[:-1] or name.endswith("." + call[:-1]) for call in PATH_CALLS):
                lines.append(node.lineno)
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and any(
                call in node.value for call in PATH_CALLS):
            lines.append(node.lineno)
    return lines


def test_nothing_imports_through_sys_path():
    found = [f"{_relative(path)}, line {line}" for path in FILES
             for line in _path_calls(ast.parse(path.read_text(encoding="utf-8"), filename=str(path)))]
    assert not found, (
        f"these put a folder on sys.path: {found}; import the module by its package instead "
        "(`from tools.notebook_analysis import ...`: pyproject.toml's editable install exposes `tools`)")


def test_the_check_finds_a_path_insertion():
    assert _path_calls(ast.parse("import sys\nsys.path.insert(0, 'tools')\n")) == [2]
    assert _path_calls(ast.parse("code = 'import sys; sys.path.append(\"x\")'\n")) == [1]
    assert _path_calls(ast.parse("import sys\nfirst = sys.path[0]\n")) == []


def _private_imports(path: Path) -> list[str]:
    """``line: name from module`` for each private name a ``tools`` module imports from another module."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level == 0 and not (node.module or "").startswith("tools"):
            continue   # another package's private name is that package's business
        for alias in node.names:
            if alias.name.startswith("_") and not alias.name.startswith("__"):
                out.append(f"line {node.lineno}: {alias.name} from {'.' * node.level}{node.module or ''}")
    return out


def test_tools_modules_import_only_public_names_of_each_other():
    found = {_relative(path): _private_imports(path) for path in FILES if _relative(path).startswith("tools/")}
    found = {path: names for path, names in found.items() if names}
    assert not found, f"tools modules that import private names of another module (make them public): {found}"



def _authoring_imports(source: str) -> list[str]:
    """``line: module`` for each import of ``tools.authoring`` (or of a module in it) in the Python
    ``source``, in code or in a string that holds code (a kernel's start-up code, ``python -c``)."""
    out = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and node.level == 0:
            modules = [node.module or ""] + [f"{node.module}.{alias.name}" for alias in node.names]
        elif isinstance(node, ast.Import):
            modules = [alias.name for alias in node.names]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and "tools.authoring" in node.value:
            modules = ["tools.authoring, in a string"]
        else:
            continue
        out += [f"line {node.lineno}: {module}" for module in modules
                if module.startswith("tools.authoring") and module[len("tools.authoring"):][:1] in ("", ".", ",")]
    return out


def test_the_grading_runtime_imports_nothing_of_authoring():
    """``tools/grading/`` runs without ``tools/authoring/`` (the Gradescope zip carries no authoring
    script): what both sides need lives on the grading side (``tools/grading/course.py``)."""
    grading = sorted((ROOT / "tools" / "grading").rglob("*.py"))
    assert grading, "tools/grading/ has no module"
    found = {_relative(path): _authoring_imports(path.read_text(encoding="utf-8")) for path in grading}
    found = {path: lines for path, lines in found.items() if lines}
    assert not found, f"grading modules that import tools.authoring (move what they need to tools/grading/): {found}"


def test_the_authoring_check_finds_an_import():
    assert _authoring_imports("from tools.authoring.student_edition import write_course\n") == [
        "line 1: tools.authoring.student_edition", "line 1: tools.authoring.student_edition.write_course"]
    assert _authoring_imports("import tools.authoring.new_chapter\n") == ["line 1: tools.authoring.new_chapter"]
    assert _authoring_imports("from tools import authoring\n") == ["line 1: tools.authoring"]
    assert _authoring_imports("code = 'from tools.authoring import new_chapter'\n") == [
        "line 1: tools.authoring, in a string"]
    assert _authoring_imports("from tools.grading.course import ROOT\nimport tools.authoring_notes\n") == []
