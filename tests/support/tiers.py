"""The suite's two tiers: what ``make test`` runs every day, what ``make test-all`` adds.

``make test`` (the everyday tier, about 4 minutes on two cores) runs every test except those
marked ``exhaustive``; ``make test-all`` (what CI runs, ``.ci/run``) runs them all. Nothing is
dropped: a check is in the everyday tier, or in ``make test-all`` only, by the rules below.
A test is marked here, at collection, from what it checks, so that a new chapter's tests
fall into the right tier without an entry anywhere:

========================  ==========================================  =============================
what                      everyday (``make test``)                    ``make test-all`` adds
========================  ==========================================  =============================
unit, property, fuzz      all of them                                 --
notebooks                 every notebook once under nbval             every check under other BLAS
                          (stored outputs, strict)                    kernels (``other_machines``: the
                                                                      notebooks, the stored meshes);
                                                                      ``make execute`` changes no
                                                                      byte; a scaffolded chapter
                                                                      through every tier
book                      both editions built; one page of each       every page of both editions
                          kind in Chromium (:data:`EVERYDAY_PAGES`,   (each at 1280 and 390 px)
                          each at 1280 and 390 px)
grading                   :data:`EVERYDAY_CHAPTER` end to end         every other chapter's grading
                          (solutions, blank, mistakes, one kind of    (nbgrader runs, mutations),
                          tampering (:data:`EVERYDAY_SUBMISSIONS`),   every kind of tampering,
                          the sandbox), the grading machinery's own   the instructors' walk-through,
                          unit tests                                  a chapter without metadata, the
                                                                      everyday chapter graded again
                                                                      by run_autograder, make grade
JupyterLab                --                                          a live session in Chromium
========================  ==========================================  =============================

A chapter's checks thus cost the everyday tier its notebook under nbval, its unit tests and its
static checks; its grading, its mutations and its page in the browser are in ``make test-all``
(CONTRIBUTING.md, "The price of a chapter").
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

#: The chapter graded end to end by ``make test``: the chapter of the grading suites' own
#: submissions (the tamper suite, the sandbox escapes, the other engines), so that every grading
#: check has one everyday case. Chapter 7, the cheapest chapter to grade: its cells run in under
#: a second (a submission about 5 CPU-s, chapter 3's about 16: sympy, scipy, three figures).
#: The instructors' walk-through (book/for-instructors.md quotes its commands) grades it too.
EVERYDAY_CHAPTER = "07_ur10_closed_form"

#: One page of each kind, checked in Chromium by ``make test`` (the others in ``make test-all``):
#: a text page with formulas, a notebook page outside the exercises, an exercise chapter (also
#: in the student edition, which differs there), a page of 3D scenes, a page of the API reference.
EVERYDAY_PAGES = {
    ("book/conventions", "instructor"),
    ("notebooks/00_tour", "instructor"),
    (f"notebooks/{EVERYDAY_CHAPTER}", "instructor"),
    (f"notebooks/{EVERYDAY_CHAPTER}", "student"),
    ("book/views", "instructor"),
    ("book/api/motion", "instructor"),
}

#: Test files whose every test is in ``make test-all`` only, and why.
EXHAUSTIVE_FILES = {
    "test_notebooks_other_machines.py": "every notebook again under other BLAS kernels",
    "test_new_chapter.py": "a scaffolded chapter through the suite (its own nbval, grading, book)",
    "test_live_jupyter.py": "a live JupyterLab session in Chromium",
    "test_reexecution.py": "make execute of unchanged notebooks, byte for byte",
}

#: Test files whose tests that grade submissions (those that read a graded run) are in
#: ``make test-all`` only, and why; their other tests stay in both tiers.
EXHAUSTIVE_GRADING_FILES = {
    "test_grading_engines.py": "the everyday chapter graded again through Gradescope's run_autograder "
                               "and make grade (the nbgrader suites grade it every day)",
}

#: Test files whose tests name the submissions they read (``grading_course.reads(job, students)``):
#: the everyday tier keeps the tests that read only these (and the correct one every course
#: grades), so that its course grades one tampering, not every kind; why in words.
EVERYDAY_SUBMISSIONS = {
    "test_grading_tamper.py": ({"blank_forged_check"}, "every other kind of tampering, delegation, a call "
                               "that never returns (make test: one tampering, forged verdicts)"),
    "test_grading_trust.py": ({"escape"}, "correct work that is talkative, crashes or hangs (make test: the "
                              "sandbox escapes)"),
}

#: Marks whose every test is in ``make test-all`` only, and why.
EXHAUSTIVE_MARKS = {
    "other_machines": "a check under other BLAS kernels (make test checks this machine's)",
}

#: Grading jobs that are not a chapter (tests/support/grading_course.py).
EXHAUSTIVE_JOBS = {"walkthrough": "the instructors' walk-through", "unmarked": "a chapter without metadata"}

CHAPTER_STEM = re.compile(r"^\d\d_[a-z0-9_]+$")


def chapter_of(item) -> str | None:
    """The chapter a test checks: the one whose graded run it reads (its ``grades`` mark), or
    its ``chapter``/``path`` parameter; None for a test of no single chapter."""
    for mark in item.iter_markers("grades"):
        job = str(mark.args[0]).split("+", 1)[0]
        return job if CHAPTER_STEM.match(job) else None
    params = getattr(getattr(item, "callspec", None), "params", {})
    for name in ("chapter", "path"):
        value = params.get(name)
        if value is not None:
            stem = Path(str(value)).stem
            if CHAPTER_STEM.match(stem):
                return stem
    return None


def exhaustive_reason(item) -> str | None:
    """Why ``item`` runs in ``make test-all`` only, or None when it runs in both tiers."""
    if item.path.name in EXHAUSTIVE_FILES:
        return EXHAUSTIVE_FILES[item.path.name]
    for name, reason in EXHAUSTIVE_MARKS.items():
        if item.get_closest_marker(name) is not None:
            return reason
    for mark in item.iter_markers("grades"):
        if str(mark.args[0]) in EXHAUSTIVE_JOBS:
            return EXHAUSTIVE_JOBS[str(mark.args[0])]
        if item.path.name in EXHAUSTIVE_GRADING_FILES:
            return EXHAUSTIVE_GRADING_FILES[item.path.name]
        if item.path.name in EVERYDAY_SUBMISSIONS:
            kept, reason = EVERYDAY_SUBMISSIONS[item.path.name]
            if not set(mark.kwargs.get("students", ("any",))) <= kept:
                return reason
    chapter = chapter_of(item)
    grading = item.path.name == "test_grading_mutations.py" or any(item.iter_markers("grades"))
    if grading and chapter is not None and chapter != EVERYDAY_CHAPTER:
        return f"the grading of {chapter} (make test grades {EVERYDAY_CHAPTER})"
    params = getattr(getattr(item, "callspec", None), "params", {})
    if item.name.startswith("test_page_in_browser"):
        edition = params.get("edition_book")
        if (params.get("page"), edition) not in EVERYDAY_PAGES:
            return "a page of the book in Chromium beyond one of each kind"
    return None


def mark(item) -> None:
    """Mark ``item`` ``exhaustive`` when a rule above says so."""
    if exhaustive_reason(item) is not None:
        item.add_marker(pytest.mark.exhaustive)
