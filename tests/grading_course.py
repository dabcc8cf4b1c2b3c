"""The graded courses the nbgrader suites share: one ``nbgrader autograde`` run per assignment.

Three test files grade submissions through the course's own pipeline:
``test_nbgrader.py`` (every chapter: blank, solutions, a typical mistake, ...),
``test_grading_tamper.py`` (chapter 3: tampering, delegation, a call that never
returns) and ``test_grading_trust.py`` (every chapter: correct work that is noisy or
written another way, ending with a crash or a hang; chapter 3: an escape from the
sandbox). Instead of a course and an autograde run each, they
share one course per chapter (a gradebook of its own, so that two chapters are
graded at a time), with one student per submission and ONE ``nbgrader autograde``
per assignment: chapter 3's run grades the submissions of all three files, every
other chapter's run those of test_nbgrader.py and test_grading_trust.py -- seven
autograde runs in all (and the walk-through's two), as few as nbgrader allows
(one per assignment and gradebook). Chapter 3's run, the longest (about 20
submissions), starts first; splitting it over two courses would add a course and a
second grading of the solutions for no shorter wall time, since the thread pool's
other worker grades the other chapters meanwhile.

:func:`graded_courses` builds them once per pytest process (session-wide: the
tests that use them are in one pytest-xdist group, :data:`XDIST_GROUP`), for the
files selected in the session: every chapter when ``test_nbgrader.py`` is
selected or a selected file's suite joins a chapter other than 3, chapter 3 alone
otherwise (the walk-through and the chapter without metadata with
``test_nbgrader.py`` only). Each file sees its own submissions only (:func:`view`).

A file that adds submissions to a chapter's run gives a :class:`Suite` per kind
of run it joins (``SUITE``, or a tuple ``SUITES``): the chapters it joins
(chapter 3 unless told), its submissions, the environment and options its
autograde run needs, and what it does before and after the run. The options of the suites hold for every
submission of that run (the solutions and the typical mistake too): a time
limit per cell of ``ROBOKIN_CELL_TIMEOUT`` s (the trust suite's hangs: 10 s in
chapter 3's run, 30 s in the others, whose talkative submissions have longer cells)
and per call of a student's function (the tamper suite's never-returning call).
"""

from __future__ import annotations

import copy
import importlib.util
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pytest

CHAPTER3 = "03_three_rpr"
XDIST_GROUP = "nbgrader"

#: test files that add submissions to the chapters' runs (their ``SUITES``, or ``SUITE``)
SUITES = ("test_grading_tamper", "test_grading_trust")


def xdist_group_mark() -> list:
    """``pytestmark`` of a file that uses the shared courses: one xdist group (no mark without xdist)."""
    if importlib.util.find_spec("xdist") is None:
        return []
    return [pytest.mark.xdist_group(XDIST_GROUP)]


@dataclass
class Suite:
    """What a test file adds to the autograde run of each chapter it joins (chapter 3 unless told)."""

    name: str
    #: (run, correct submission, course) -> {student: notebook}
    submissions: Callable[..., dict[str, dict]]
    environment: dict[str, str] = field(default_factory=dict)
    options: list[str] = field(default_factory=list)
    before: Callable | None = None      # (run, course) -> None, before autograde
    after: Callable | None = None       # (run, course) -> None, right after autograde
    finally_: Callable | None = None    # (run, course, base) -> None, after generate_feedback
    students: list[str] = field(default_factory=list)   # filled when the course is built
    #: chapter -> does this suite join that chapter's run
    joins: Callable[[str], bool] = lambda chapter: chapter == CHAPTER3


def module_suites(name: str) -> tuple[Suite, ...]:
    """The suites of the test module ``name``: its ``SUITES``, or its ``SUITE``."""
    module = importlib.import_module(name)
    return tuple(getattr(module, "SUITES", None) or (module.SUITE,))


_LOCK = threading.Lock()
_RUNS: dict | None = None


def selected_files(request) -> set[str]:
    """The stems of the test files with a test selected in this session."""
    return {Path(str(item.fspath)).stem for item in request.session.items}


def graded_courses(request, tmp_path_factory) -> dict:
    """``{chapter or job: Run}``, built once per process (see the module's docstring)."""
    global _RUNS
    with _LOCK:
        if _RUNS is None:
            import test_nbgrader

            files = selected_files(request)
            suites = [suite for name in SUITES if name in files for suite in module_suites(name)]
            full = "test_nbgrader" in files
            chapters = [c for c in test_nbgrader.CHAPTERS
                        if full or c == CHAPTER3 or any(s.joins(c) for s in suites)]
            _RUNS = test_nbgrader.grade_everything(tmp_path_factory.mktemp("nbgrader"), full=full,
                                                   suites=suites, chapters=chapters)
        return _RUNS


def view(run, students, **replace):
    """A copy of ``run`` whose per-student results hold ``students`` only."""
    out = copy.copy(run)
    keep = set(students)
    for name in ("scores", "feedback", "autograded", "exported"):
        value = getattr(run, name, None)
        if isinstance(value, dict):
            setattr(out, name, {k: v for k, v in value.items() if k in keep})
    for name, value in replace.items():
        setattr(out, name, value)
    return out
