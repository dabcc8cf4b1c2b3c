"""The graded courses the nbgrader suites share: one ``nbgrader autograde`` run per assignment.

Three test files grade submissions through the course's own pipeline:
``test_nbgrader.py`` (every chapter: blank, solutions, a typical mistake, ...),
``test_grading_tamper.py`` (the everyday chapter: tampering, delegation, a call that never
returns) and ``test_grading_trust.py`` (every chapter but the everyday one: one submission,
correct work written another way and talkative, with a hang and a crash; the everyday chapter:
its own noisy, hanging and escaping submissions). The everyday chapter
(:data:`EVERYDAY_CHAPTER`, tests/support/tiers.py) is chapter 7, the cheapest to grade (about
5 CPU-s per submission, chapter 3's about 16). Instead of a course and an autograde run each, they
share one course per chapter (a gradebook of its own, so that two chapters are
graded at a time), with one student per submission and ONE ``nbgrader autograde``
per assignment: every chapter's run grades the submissions of test_nbgrader.py and,
in the everyday chapter, those of test_grading_trust.py. Two suites wait a time limit on
purpose and are graded so that the wait overlaps work: the tamper suite
(test_grading_tamper.py) grades the everyday chapter in a course of its own
(:attr:`Suite.own_course`: its never-returning call waits the call limit in every
test, so it runs as a part of its own beside the others), and the trust suite's benign
submission of every other chapter, which hangs, is graded in that chapter's job by an
autograde of its own in a copy of the course, while the shared run grades the rest
(:attr:`Suite.apart`) -- twenty autograde runs in all (and the walk-through's two).

:func:`graded_courses` grades them once per pytest process, for the files
selected in the session: only the jobs (a chapter's run, a suite's own course, the
walk-through, the chapter without metadata) that a selected test reads. Each job is a
part of its own, one pytest-xdist group (``nbgrader:<job>``), so that under xdist the
jobs spread over the workers, longest first (tests/support/parallel_plan.py), and a worker
grades only the jobs its tests read (:class:`Courses` grades a job when it is first
read; without xdist, all jobs at once, in one thread pool). Each file sees its own
submissions only (:func:`view`).

A file that adds submissions to a chapter's run gives a :class:`Suite` per kind
of run it joins (``SUITE``, or a tuple ``SUITES``): the chapters it joins
(the everyday chapter unless told), its submissions, the environment and options its
autograde run needs, and what it does before and after the run. The options of the suites hold for every
submission of that run (the solutions and the typical mistake too; a suite graded apart's
for its own only): a time limit per cell of ``ROBOKIN_CELL_TIMEOUT`` s (the trust suite's
hangs: 30 s, a ceiling load does not reach)
and per call of a student's function (the tamper suite's never-returning call).
"""

from __future__ import annotations

import copy
import importlib.util
import os
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import pytest

#: the chapter the grading suites' own submissions are written for (tests/support/tiers.py)
from support.tiers import EVERYDAY_CHAPTER

XDIST_GROUP = "nbgrader"

#: test files that add submissions to the chapters' runs (their ``SUITES``, or ``SUITE``)
SUITES = ("test_grading_tamper", "test_grading_trust")
#: jobs besides the chapters' runs: the walk-through of book/for-instructors.md, the chapter without metadata
EXTRAS = ("walkthrough", "unmarked")


#: Separates a chapter and a suite in the key of a course of the suite's own (see :class:`Suite`).
OWN = "+"


def own_course_key(chapter: str, suite: str) -> str:
    """The job key of the course in which ``suite`` grades ``chapter`` on its own, e.g. "07_ur10_closed_form+tamper"."""
    return f"{chapter}{OWN}{suite}"


def part_of(key: str) -> str:
    """The part (xdist group) in which the job ``key`` (a chapter, "walkthrough", "unmarked", or a
    suite's own course, "<chapter>+<suite>") is graded: every job is a part of its own."""
    return f"{XDIST_GROUP}:{key}"


def part_mark(part: str) -> list:
    """The xdist mark of the part ``part`` (none without xdist)."""
    if importlib.util.find_spec("xdist") is None:
        return []
    return [pytest.mark.xdist_group(part)]


def job_marks(key: str = EVERYDAY_CHAPTER, students: tuple[str, ...] | None = None) -> list:
    """The marks of a test that reads the job ``key``'s run: ``grades(key)``, from which the
    session learns which runs to grade (:class:`Courses`) and the tiers which chapter the test
    checks (tests/support/tiers.py), and its part's xdist group (none without xdist).

    ``students``: the submissions of a suite that the test reads (None: any of them); a suite
    grades only the submissions the session's tests read (:meth:`Suite.chosen`)."""
    grades = pytest.mark.grades(key) if students is None else pytest.mark.grades(key, students=tuple(students))
    return [grades, *part_mark(part_of(key))]


def reads(key: str, students: tuple[str, ...] | None = None):
    """Decorator: the test reads the run of the job ``key`` (its ``students``, or any).

    A test has one group or none: a file whose tests read runs of both parts marks them
    one by one (this, or :func:`chapter_params`), not with a module-wide ``pytestmark``.
    """
    def mark(test):
        for one in job_marks(key, students):
            test = one(test)
        return test
    return mark


def chapter_params(chapters, students: Callable[[str], tuple[str, ...]] | None = None) -> list:
    """``chapters`` as parameters, each marked with the job it reads (:func:`job_marks`) and, with
    ``students``, the submissions of each chapter's run it reads (``students(chapter)``)."""
    return [pytest.param(chapter, marks=job_marks(chapter, students(chapter) if students else None))
            for chapter in chapters]


def jobs_read(items) -> dict[str, set[str]]:
    """``{job: stems of the test files whose tests read it}`` for the tests ``items``."""
    out: dict[str, set[str]] = {}
    for item in items:
        for mark in item.iter_markers("grades"):
            out.setdefault(str(mark.args[0]), set()).add(Path(str(item.fspath)).stem)
    return out


def students_read(items) -> dict[str, set[str] | None]:
    """``{job: the suite submissions the tests ``items`` read}``, None for a job some test reads
    whole (a ``grades`` mark without ``students``)."""
    out: dict[str, set[str] | None] = {}
    for item in items:
        for mark in item.iter_markers("grades"):
            job, students = str(mark.args[0]), mark.kwargs.get("students")
            known = out.get(job, set())
            out[job] = None if students is None or known is None else known | set(students)
    return out


@dataclass
class Suite:
    """What a test file adds to the autograde run of each chapter it joins (the everyday chapter unless told)."""

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
    joins: Callable[[str], bool] = lambda chapter: chapter == EVERYDAY_CHAPTER
    #: graded in a course of its own (job "<chapter>+<name>", an xdist part of its own) with the
    #: chapter's correct submission, instead of in the chapter's shared run: for a
    #: suite whose waits (time limits reached on purpose) would make the shared run the suite's
    #: longest unit; its options and environment then hold for its own submissions only
    own_course: bool = False
    #: graded in the chapter's job but by an autograde of its own, in a copy of the chapter's
    #: course made after generate_assignment, while the shared run grades the other
    #: submissions: for a suite whose submissions wait a time limit on purpose, so that the
    #: wait overlaps the shared run's work instead of adding to it (the jobs of one wave of
    #: parts reached their waits together: 108 of the 171 core-seconds a quiet ``make
    #: test-all`` left idle came in three such windows of 20-25 s). Its environment and options
    #: hold for its own submissions only; it has no hooks (they see the shared course).
    apart: bool = False
    #: job -> the submissions the session's tests read (None: all), set by :class:`Courses`
    wanted: dict[str, set[str] | None] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.apart and (self.own_course or self.before or self.after or self.finally_):
            raise ValueError(f"suite {self.name!r}: a suite graded apart has no course of its own and no hooks")

    def key(self, chapter: str) -> str:
        """The job whose run holds this suite's submissions of ``chapter``."""
        return own_course_key(chapter, self.name) if self.own_course else chapter

    def chosen(self, job: str, submissions: dict[str, dict]) -> dict[str, dict]:
        """Of ``submissions`` (the suite's, for the run of ``job``), those a selected test reads."""
        wanted = self.wanted.get(job)
        return dict(submissions) if wanted is None else {k: v for k, v in submissions.items() if k in wanted}


def module_suites(name: str) -> tuple[Suite, ...]:
    """The suites of the test module ``name``: its ``SUITES``, or its ``SUITE``."""
    module = importlib.import_module(name)
    return tuple(getattr(module, "SUITES", None) or (module.SUITE,))


_LOCK = threading.Lock()
_RUNS: dict = {}                 # job -> Run, for the parts built in this process
_BUILT: set[str] = set()         # the parts built in this process


class Courses(Mapping):
    """``{chapter or job: Run}`` for the jobs of this session; a part is graded when one of its
    jobs is first read (all parts at once outside pytest-xdist, where one pool grades them all).

    The jobs are those the selected tests read (their ``grades`` marks, :func:`job_marks`):
    ``make test``, which selects the everyday chapter's grading tests only (tests/support/tiers.py),
    grades that chapter only; a suite adds its submissions to the runs of the chapters it joins when a selected
    test of its file reads a run."""

    def __init__(self, request, tmp_path_factory) -> None:
        from support import nbgrader_course

        read = jobs_read(request.session.items)
        files = set().union(*read.values()) if read else set()
        self.suites = [suite for name in SUITES if name in files for suite in module_suites(name)]
        self.chapters = [c for c in nbgrader_course.CHAPTERS if c in read]
        own = [suite.key(c) for suite in self.suites if suite.own_course
               for c in nbgrader_course.CHAPTERS if suite.key(c) in read]
        for name in files & set(SUITES):   # a suite's submissions: those its own file's tests read
            wanted = students_read(item for item in request.session.items if Path(str(item.fspath)).stem == name)
            for suite in module_suites(name):
                suite.wanted = wanted
        self.extras = [job for job in EXTRAS if job in read]
        self.jobs = [*self.chapters, *own, *self.extras]
        self.factory = tmp_path_factory

    def _build(self, parts: set[str]) -> None:
        from support import nbgrader_course

        with _LOCK:
            parts -= _BUILT
            if not parts:
                return
            chapters = [c for c in self.chapters if part_of(c) in parts]
            own = [key for key in self.jobs if OWN in key and part_of(key) in parts]
            extras = [job for job in self.extras if part_of(job) in parts]
            _RUNS.update(nbgrader_course.grade_everything(self.factory.mktemp("nbgrader"), suites=self.suites,
                                                        chapters=chapters, own=own, extras=extras))
            _BUILT.update(parts)

    def __getitem__(self, key: str):
        if key not in self.jobs:
            raise KeyError(key)
        if key not in _RUNS:
            under_xdist = bool(os.environ.get("PYTEST_XDIST_WORKER"))
            self._build({part_of(key)} if under_xdist else {part_of(job) for job in self.jobs})
        return _RUNS[key]

    def __iter__(self):
        return iter(self.jobs)

    def __len__(self) -> int:
        return len(self.jobs)


def graded_courses(request, tmp_path_factory) -> Courses:
    """The graded courses of this session (see the module's docstring and :class:`Courses`)."""
    return Courses(request, tmp_path_factory)


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
