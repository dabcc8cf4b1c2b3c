#!/usr/bin/env python3
"""Create a new chapter: its notebook, its check module, its places in the book and the README.

    .venv/bin/python tools/authoring/new_chapter.py --name scara --title "The SCARA arm" --robot "a SCARA arm"
    make chapter NAME=scara TITLE="The SCARA arm" ROBOT="a SCARA arm"      # the same

What it writes (and nothing else; it refuses to overwrite an existing chapter):

* ``notebooks/NN_<name>.ipynb`` (NN = the next free number) with the book's structure:
  title, learning goals, problem statement, one task with its worked solution, its
  graded check cell (asserts against an independent value, and the chapter's
  robokin.check), a pitfall, a *Try it yourself* cell and *Going further*; the
  Colab install cell; formatted, with nbgrader metadata, executed top to bottom;
* ``robokin/check/<name>.py`` with the task's check (``check.<name>.tool_position``),
  registered in ``robokin/check/_registry.py``'s ``CHAPTERS``, and its tests,
  ``tests/test_check_<name>.py``;
* ``tests/grading_mutations/NN_<name>.py``: the wrong answers each graded test must reject
  (``MUTATIONS``) and each answer computed by another method, which must keep full marks
  (``VARIANTS``, read by the trust suite through ``tests/support/benign_variants.py``);
* in the check module, ``DELEGATION``: the robokin functions that solve each task (read
  by ``tools/grading/bridge/delegation.py``, which flags an answer handing one back);
* its line in ``_toc.yml`` (Exercises), and its row in the chapter tables of
  ``book/intro.md`` and ``README.md``; the points table of ``book/for-instructors.md``.

No other file needs an entry for the chapter. The generated chapter passes
``make test-all`` as it is (its task: the tool position of the two-link planar
arm, ``robokin.models.planar_two_link()``): replace the exercise, keep the
structure. ``book/authoring.md`` explains every part and every rule the test
suite enforces on a chapter.
"""

from __future__ import annotations

import argparse
import ast
import json
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TOOLS = Path(__file__).resolve().parent

NAME_RE = re.compile(r"^[a-z][a-z0-9_]{1,30}$")


def md(text: str, **meta) -> dict:
    return {"cell_type": "markdown", "metadata": dict(meta), "source": text.strip("\n")}


def code(text: str, *tags: str) -> dict:
    meta = {"tags": list(tags)} if tags else {}
    return {"cell_type": "code", "execution_count": None, "metadata": meta, "outputs": [],
            "source": text.strip("\n")}


def notebook(number: int, name: str, title: str, robot: str) -> dict:
    """The chapter notebook: one worked, graded task on the two-link arm, to be replaced."""
    label = name.replace("_", "-")
    cells = [
        md(f"""
# Chapter {number}: {title}

This chapter is about {robot}. *(Replace this paragraph: what the robot is, what the
exercise asks and why it matters.)* Its one task so far -- the tool position of the
two-link planar arm -- shows the structure every chapter follows.
"""),
        md("""
## Learning goals

After this chapter you can

- write the forward kinematics of a planar arm as a function of its joint angles;
- check a function against an independent reference at many configurations.
"""),
        md("""
## Problem statement

The two-link planar arm `robokin.models.planar_two_link()` has two revolute joints
about $z$ and links of $l_1 = l_2 = 1$ m along the $x$ axis of their frames. Find the
position of its tool point in the base frame {B} as a function of the joint angles
$\\mathbf{q} = (q_1, q_2)$ in radians.
"""),
        code("""
import numpy as np

from robokin import check, models
from robokin.formatting import format_array

arm = models.planar_two_link()
Q0 = np.array([0.3, 0.2])  # the configuration of Task 1 (rad)
"""),
        md(f"""
## Task 1: The tool position

```{{exercise}}
:label: {label}-fk

Write `tool_position(q)`: for `q` = $(q_1, q_2)$ in radians (an array of shape (2,)),
it returns the tool position $(x, y)$ in metres in {{B}}, a NumPy array of shape (2,).
Evaluate it at `Q0` $= \\mathbf{{q}}_0 = (0.3, 0.2)$ rad.
```
"""),
        md(f"""
```{{solution-start}} {label}-fk
:class: dropdown
```
Each link adds its length along its own direction, $q_1$ for the first link and
$q_1 + q_2$ for the second:
$x = l_1\\cos q_1 + l_2\\cos(q_1 + q_2)$, $y = l_1\\sin q_1 + l_2\\sin(q_1 + q_2)$.
"""),
        code("""
def tool_position(q):
    q1, q2 = q
    return np.array([np.cos(q1) + np.cos(q1 + q2), np.sin(q1) + np.sin(q1 + q2)])


print("tool position at q0:", format_array(tool_position(Q0)), "m")
""", "solution"),
        md("""
```{solution-end}
```
"""),
        md("""
**Check.** The tool position must be the translation of the model's forward
kinematics `arm.fk(q)` (an independent implementation: a product of elementary
transforms) at many configurations, and robokin.check must find it right. (The test
also compares with the closed form at `Q0`, in a hidden part that the student edition
leaves out: it would give the answer away.)
"""),
        code("""
rng = np.random.default_rng(0)
for q in rng.uniform(-np.pi, np.pi, (50, 2)):
    assert np.allclose(tool_position(q), arm.fk(q)[:2, 3], atol=1e-12)
check.{name}.tool_position(tool_position)
### BEGIN HIDDEN TESTS
assert np.allclose(tool_position(Q0), [np.cos(0.3) + np.cos(0.5), np.sin(0.3) + np.sin(0.5)])
### END HIDDEN TESTS
""".replace("{name}", name), "check"),
        md(f"""
## Task 2: The Jacobian

```{{exercise}}
:label: {label}-jacobian

Write `tool_jacobian(q)`: the 2×2 matrix $\\mathbf{{J}}(\\mathbf{{q}}) = \\partial \\mathbf{{p}} / \\partial
\\mathbf{{q}}$ of `tool_position` (rows $x, y$ in m; columns $q_1, q_2$; in m/rad), for `q` of
shape (2,) in radians.
```
"""),
        md(f"""
```{{solution-start}} {label}-jacobian
:class: dropdown
```
Differentiate each coordinate: with $s_1 = \\sin q_1$, $s_{{12}} = \\sin(q_1 + q_2)$ (and $c$ for
the cosines), $\\mathbf{{J}} = \\begin{{bmatrix}} -s_1 - s_{{12}} & -s_{{12}} \\\\ c_1 + c_{{12}} & c_{{12}}
\\end{{bmatrix}}$.
"""),
        code("""
def tool_jacobian(q):
    q1, q2 = q
    s1, s12, c1, c12 = np.sin(q1), np.sin(q1 + q2), np.cos(q1), np.cos(q1 + q2)
    return np.array([[-s1 - s12, -s12], [c1 + c12, c12]])
""", "solution"),
        md("""
```{solution-end}
```
"""),
        md("""
**Check.** Central finite differences of the model's tool position (an independent
value, to the accuracy their step allows; not of your `tool_position`, so that this test
grades the Jacobian alone) and the model's position Jacobian.
"""),
        code("""
for q in rng.uniform(-np.pi, np.pi, (20, 2)):
    h = 1e-6
    J_fd = np.column_stack(
        [(arm.fk(q + h * e)[:2, 3] - arm.fk(q - h * e)[:2, 3]) / (2 * h) for e in np.eye(2)]
    )
    assert np.allclose(tool_jacobian(q), J_fd, atol=1e-8)
    assert np.allclose(tool_jacobian(q), arm.position_jacobian(q)[:2], atol=1e-12)
check.{name}.tool_jacobian(tool_jacobian)
""".replace("{name}", name), "check"),
        md("""
```{admonition} Pitfall: degrees for radians
:class: warning

NumPy's `cos` and `sin` take radians. Typing the angles in degrees gives a wrong
position without any error; convert at the edge with `np.deg2rad`.
```
"""),
        md("""
### Try it yourself

Where is the tool when the arm is stretched out ($\\mathbf{q} = (0, 0)$)? And folded
back ($q_2 = \\pi$)?
"""),
        code("""
print(format_array(tool_position([0.0, 0.0])), format_array(tool_position([0.0, np.pi])))
"""),
        md("""
## Going further

- The same function for a batch of configurations (shape (N, 2)) without a loop.
- The Jacobian $\\partial \\mathbf{p} / \\partial \\mathbf{q}$, checked against finite
  differences.
"""),
    ]
    for k, cell in enumerate(cells):
        cell["id"] = f"{label}-{k}"
    return {"cells": cells, "metadata": {
        "kernelspec": {"display_name": "Python 3 (ipykernel)", "language": "python", "name": "python3"},
        "language_info": {"name": "python"}}, "nbformat": 4, "nbformat_minor": 5}


def check_module(number: int, name: str, title: str) -> str:
    return f'''r"""Exercise checks of chapter {number}: {title}.

=================  ==========================================  ==========
check              the student's answer                         inputs
=================  ==========================================  ==========
``tool_position``  p(q): tool position (x, y) in m, shape (2,)  q1, q2
``tool_jacobian``  J(q) = ∂p/∂q: 2×2, in m/rad                 q1, q2
=================  ==========================================  ==========

Every reference comes from the chapter's robot model (one model definition); the
diagnoses are the standard ones for a vector (a sign, degrees for radians, swapped
or negated inputs). See the book's page "Adding a chapter" for the pattern.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from robokin.check import diagnoses as dg
from robokin.check._core import Check, Variable
from robokin.check._registry import exercise

__all__ = ["tool_position", "tool_jacobian"]

_CHAPTER = "{name}"

#: check -> {{the robokin function that solves its task: how the grading report names it}}: an
#: answer that hands one back (``tool_position = ...fk``) is flagged for review by hand
#: (tools/grading/bridge/delegation.py reads this literal table without importing the module)
DELEGATION = {{
    "tool_position": {{"fk": "SerialChain.fk", "frames": "SerialChain.frames"}},
    "tool_jacobian": {{"position_jacobian": "SerialChain.position_jacobian", "jacobian": "SerialChain.jacobian"}},
}}


@lru_cache(maxsize=1)
def _arm():
    from robokin.models import planar_two_link

    return planar_two_link()


tool_position = exercise(_CHAPTER, "tool_position", Check(
    name="tool_position",
    reference=lambda x: np.asarray(_arm().fk(x))[:2, 3],
    variables=[Variable("q1"), Variable("q2")],
    groups=[("q", [0, 1])],
    diagnoses=dg.standard("vector"),
    noun="angles",
    doc="Check tool_position(q): the tool position (x, y) in m of the two-link arm, shape (2,).",
))

tool_jacobian = exercise(_CHAPTER, "tool_jacobian", Check(
    name="tool_jacobian",
    reference=lambda x: np.asarray(_arm().position_jacobian(x))[:2],
    variables=[Variable("q1"), Variable("q2")],
    groups=[("q", [0, 1])],
    diagnoses=dg.standard("jacobian"),
    noun="angles",
    doc="Check tool_jacobian(q): the 2x2 Jacobian of the tool position, in m/rad.",
))
'''


def check_tests(number: int, name: str) -> str:
    """``tests/test_check_<name>.py``: the tests of the chapter's check module (one test file per module)."""
    return f'''"""Tests of the chapter-{number} exercise checks (robokin.check.{name}).

A right answer passes, a typical mistake is named, a function that forgets ``return`` is told
so. Written by tools/authoring/new_chapter.py for the chapter's first tasks: change it with the checks.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

checks = importlib.import_module("robokin.check.{name}")


def tool_position(q):
    """The two-link arm's tool position (l1 = l2 = 1 m), written out."""
    q1, q2 = q
    return np.array([np.cos(q1) + np.cos(q1 + q2), np.sin(q1) + np.sin(q1 + q2)])


def tool_jacobian(q):
    """Its Jacobian by central finite differences (independent of the check's reference)."""
    q, h = np.asarray(q, dtype=float), 1e-6
    return np.column_stack([(tool_position(q + h * e) - tool_position(q - h * e)) / (2 * h) for e in np.eye(2)])


def test_right_answers_pass():
    assert checks.tool_position(tool_position, quiet=True).passed
    assert checks.tool_jacobian(tool_jacobian, quiet=True).passed


@pytest.mark.parametrize("check, answer, diagnosis", [
    ("tool_position", lambda q: tool_position(np.rad2deg(q)), "degrees_evaluated"),
    ("tool_jacobian", lambda q: tool_jacobian(q).T, "transpose"),
    ("tool_jacobian", lambda q: -tool_jacobian(q), "sign"),
])
def test_typical_mistakes_are_named(check, answer, diagnosis):
    result = getattr(checks, check)(answer, quiet=True)
    assert not result.passed and result.diagnosis == diagnosis, result.message


def test_a_function_without_return_is_told_to_return():
    def forgot(q):
        tool_position(q)

    result = checks.tool_position(forgot, quiet=True)
    assert not result.passed and "forget `return`" in result.message, result.message
'''


def mutations(name: str) -> str:
    return '''"""Wrong answers that each autograded test of the chapter must reject (``MUTATIONS``,
tests/test_grading_mutations.py), and correct answers written another way that must keep
full marks (``VARIANTS``, tests/support/benign_variants.py and tests/test_grading_trust.py).

``MUTATIONS``: ``{grade id of a test cell: [(what is wrong, code appended to the answer
cells), ...]}``, at least one per graded test. ``VARIANTS``: ``{grade id of an answer cell:
(how it differs, code appended to that cell)}``: another method, not only other names
(without ``VARIANTS``, the trust suite derives a weaker default: each answer wrapped).
The first line of each variant's code must be ASCII without quotes.
"""

MUTATIONS = {
    "task1_test1": [
        ("degrees for radians", "tool_position = (lambda f: lambda q: f(np.rad2deg(q)))(tool_position)"),
        ("the second link's own angle q2 instead of q1 + q2",
         "def tool_position(q):\\n    q1, q2 = q\\n"
         "    return np.array([np.cos(q1) + np.cos(q2), np.sin(q1) + np.sin(q2)])"),
    ],
    "task2_test1": [
        ("the transposed Jacobian", "tool_jacobian = (lambda f: lambda q: f(q).T)(tool_jacobian)"),
    ],
}

VARIANTS = {
    "task1_answer1": ("the tool as a sum of complex numbers", """

# written another way: the tool point as the complex number e^(i q1) + e^(i (q1 + q2))
def tool_position(q):
    first, second = np.asarray(q, dtype=float)
    tip = np.exp(1j * first) + np.exp(1j * (first + second))
    return np.array([tip.real, tip.imag])
"""),
    "task2_answer1": ("the Jacobian's columns as i times the complex link vectors", """

# written another way: d/dq_k of e^(i q1) + e^(i (q1 + q2)) is i times the links after joint k
def tool_jacobian(q):
    first, second = np.asarray(q, dtype=float)
    elbow, tip = np.exp(1j * first), np.exp(1j * (first + second))
    columns = [1j * (elbow + tip), 1j * tip]
    return np.array([[column.real for column in columns], [column.imag for column in columns]])
"""),
}
'''


def next_number(root: Path) -> int:
    numbers = [int(p.name[:2]) for p in (root / "notebooks").glob("[0-9][0-9]_*.ipynb")]
    return max(numbers, default=0) + 1


def insert_after_last(text: str, pattern: str, line: str, where: str) -> str:
    """``text`` with ``line`` after the last line matching ``pattern`` (SystemExit naming ``where``)."""
    lines = text.splitlines(keepends=True)
    hits = [i for i, row in enumerate(lines) if re.search(pattern, row)]
    if not hits:
        raise SystemExit(f"ERROR {where}: no line matching {pattern!r} to add the chapter after; add it by hand")
    lines.insert(hits[-1] + 1, line if line.endswith("\n") else line + "\n")
    return "".join(lines)


def registered_chapters(root: Path) -> dict[str, str]:
    """``CHAPTERS`` of the tree at ``root`` (``robokin/check/_registry.py``), read from the file, not
    imported: the tree given by ``--root`` may be another than the one Python imports robokin from."""
    path = root / "robokin" / "check" / "_registry.py"
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.AnnAssign | ast.Assign) and node.value is not None:
            targets = [node.target] if isinstance(node, ast.AnnAssign) else node.targets
            if any(isinstance(target, ast.Name) and target.id == "CHAPTERS" for target in targets):
                return ast.literal_eval(node.value)
    raise ValueError(f"{path}: no CHAPTERS = {{...}} (the registry of the chapters' checks)")


def register(root: Path, name: str) -> None:
    path = root / "robokin" / "check" / "_registry.py"
    text = path.read_text()
    if f'"{name}":' in text:
        return
    path.write_text(insert_after_last(text, r'^\s+"\w+": "robokin\.check\.\w+",$',
                                      f'    "{name}": "robokin.check.{name}",', str(path)))


def run(command: list[str], root: Path) -> None:
    print("$", " ".join(command))
    subprocess.run(command, cwd=root, check=True)


def execute(path: Path, root: Path) -> None:
    """What ``make execute NB=path`` does: run in a fresh kernel, store outputs, merge streams."""
    import os

    env = dict(os.environ, ROBOKIN_VIEWER="static")
    base = [sys.executable, "-m", "nbconvert", "--to", "notebook", "--inplace", "--log-level=WARN"]
    manager = "--ExecutePreprocessor.kernel_manager_class=tools.kernel_sockets.AsyncPrivateSocketsKernelManager"
    for extra in (["--execute", "--ExecutePreprocessor.timeout=300", "--ExecutePreprocessor.record_timing=False",
                   manager],
                  ["--CoalesceStreamsPreprocessor.enabled=True"]):
        print("$", " ".join(base[2:] + extra), path.name)
        subprocess.run(base + extra + [str(path)], cwd=root, env=env, check=True)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="book/authoring.md ('Adding a chapter') explains the result.")
    parser.add_argument("--name", required=True, help="the chapter's short name: lower case, digits, _ "
                                                       "(names the notebook and robokin.check.<name>)")
    parser.add_argument("--title", required=True, help='the chapter title, e.g. "The SCARA arm"')
    parser.add_argument("--robot", default="a robot", help='the robot, for the intro table, e.g. "a SCARA arm"')
    parser.add_argument("--topics", default="to be written", help="what the chapter teaches, for the tables")
    parser.add_argument("--root", type=Path, default=ROOT, help="the repository (default: this one)")
    parser.add_argument("--no-execute", action="store_true", help="do not execute the new notebook")
    args = parser.parse_args(argv)

    root = args.root.resolve()
    if not NAME_RE.match(args.name):
        parser.error(f"--name must be lower case letters, digits and _ (2-31 characters); got {args.name!r}")
    if (args.name in registered_chapters(root) or (root / "robokin" / "check" / f"{args.name}.py").exists()
            or (root / "tests" / f"test_check_{args.name}.py").exists()):
        parser.error(f"a chapter with checks named {args.name!r} exists already")
    number = next_number(root)
    stem = f"{number:02d}_{args.name}"
    nb_path = root / "notebooks" / f"{stem}.ipynb"

    nb_path.write_text(json.dumps(notebook(number, args.name, args.title, args.robot), indent=1,
                                  ensure_ascii=False) + "\n")
    (root / "robokin" / "check" / f"{args.name}.py").write_text(check_module(number, args.name, args.title))
    (root / "tests" / f"test_check_{args.name}.py").write_text(check_tests(number, args.name))
    register(root, args.name)
    mutation_dir = root / "tests" / "grading_mutations"
    mutation_dir.mkdir(exist_ok=True)
    (mutation_dir / "__init__.py").touch()
    (mutation_dir / f"{stem}.py").write_text(mutations(args.name))

    toc = root / "_toc.yml"
    toc.write_text(insert_after_last(toc.read_text(), r"^\s+- file: notebooks/[0-9][0-9]_",
                                     f"      - file: notebooks/{stem}", str(toc)))
    intro = root / "book" / "intro.md"
    intro.write_text(insert_after_last(intro.read_text(), r"^\| \d+ \|",
                                       f"| {number} | {args.robot} | {args.topics} |", str(intro)))
    readme = root / "README.md"
    readme.write_text(insert_after_last(readme.read_text(), r"^\| \d+ \| `notebooks/",
                                        f"| {number} | `notebooks/{stem}.ipynb` | {args.robot}: {args.topics} |",
                                        str(readme)))

    python = sys.executable
    run([python, str(TOOLS / "install_cell.py"), str(nb_path.relative_to(root))], root)
    run([python, str(TOOLS / "format_notebooks.py"), str(nb_path.relative_to(root))], root)
    run([python, str(TOOLS / "nbgrader_metadata.py")], root)
    if not args.no_execute:
        execute(nb_path, root)
    print(f"\nNew chapter {number}: {nb_path.relative_to(root)}, robokin/check/{args.name}.py, "
          f"tests/test_check_{args.name}.py, tests/grading_mutations/{stem}.py; listed in _toc.yml, "
          f"book/intro.md and README.md.")
    print(f"Next: write the exercise (book/authoring.md), tidy it (format, metadata, make execute), "
          f"then `make test-chapter CH={stem}`.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
