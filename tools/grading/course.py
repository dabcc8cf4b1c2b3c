"""The nbgrader course directory, the nbgrader command, and the exercise checks robokin registers.

The grading runtime (``grade_submission.py``) and the authoring side (``make student``,
``tools/authoring/student_edition.py``; ``tools/authoring/nbgrader_metadata.py``) share these:
they live on the grading side, so that grading imports nothing of ``tools/authoring/``.
"""

from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

#: The repository.
ROOT = Path(__file__).resolve().parents[2]

CONFIG = '''# Written by tools/grading/course.py: the robokin course's nbgrader settings,
# with this directory as the course root.
c = get_config()  # noqa: F821
load_subconfig({repo_config!r})  # noqa: F821
c.CourseDirectory.root = {root!r}
c.Exchange.root = {exchange!r}
# autograde runs every submission in a bubblewrap sandbox (apt-get install bubblewrap).
# Only where grading already runs in a container of its own (book/for-instructors.md,
# "What grading guarantees"):
# c.BridgedExecute.sandbox = False
# Test cells and robokin.check's verdicts run in a grader kernel of their own for every
# chapter (the student's answers handed over as data, functions called through the bridge;
# "Where the verdicts are decided"): never in the student's kernel.
'''


def nbgrader_command() -> list[str]:
    """nbgrader from the environment that runs this script."""
    exe = Path(sys.executable).with_name("nbgrader")
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "nbgrader"]


def write_course(course: Path, exchange: Path) -> None:
    """The course directory and its nbgrader_config.py."""
    course.mkdir(parents=True, exist_ok=True)
    exchange.mkdir(parents=True, exist_ok=True)
    (course / "nbgrader_config.py").write_text(CONFIG.format(
        repo_config=str(ROOT / "nbgrader_config.py"), root=str(course.resolve()),
        exchange=str(exchange.resolve())))


def add_source(course: Path, notebook: Path) -> None:
    """``notebook`` as the source of its assignment, ``<course>/source/<stem>/<name>`` (replaced)."""
    target = course / "source" / notebook.stem
    if target.exists():
        shutil.rmtree(target)
    target.mkdir(parents=True)
    shutil.copy2(notebook, target / notebook.name)


def environment() -> dict[str, str]:
    """This environment with its ``bin`` first on PATH (nbgrader runs ``alembic`` from PATH)."""
    env = dict(os.environ)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    return env


def check_names() -> dict[str, str]:
    """``{"leg.rotation_B1": "R_B1", ...}``: every exercise check and the quantity it names."""
    from robokin import check

    out = {}
    for chapter in sorted(check.CHAPTERS):
        try:
            found = check.checks_of(chapter)
        except Exception:  # noqa: BLE001 - a chapter module being rewritten must not stop us
            continue
        for attr, checker in found.items():
            name = str(getattr(checker, "name", "")).split("(")[0].strip()
            if name.isidentifier():
                out[f"{chapter}.{attr}"] = name
    return out
