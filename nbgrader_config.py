# nbgrader configuration of the robokin course.
#
# `make student` (tools/authoring/student_edition.py) writes a course directory, by default
# _build/nbgrader/course/, whose own nbgrader_config.py loads this file and sets
# the course root and the exchange. Run nbgrader's commands in that directory,
# or here (the root below then points at it). The walk-through is in
# book/for-instructors.md, "Assigning chapters with nbgrader".
import os
from pathlib import Path

from nbconvert.preprocessors import ClearMetadataPreprocessor, CSSHTMLHeaderPreprocessor
from nbgrader.preprocessors import (
    AssignLatePenalties,
    CheckCellMetadata,
    ClearHiddenTests,
    ClearMarkScheme,
    ClearOutput,
    ClearSolutions,
    ComputeChecksums,
    DeduplicateIds,
    GetGrades,
    IgnorePattern,
    IncludeHeaderFooter,
    InstantiateTests,
    LimitOutput,
    LockCells,
    OverwriteKernelspec,
    SaveAutoGrades,
    SaveCells,
)

from tools.grading.robokin_nbgrader import (
    AutograderReport,
    GradingIncidents,
    DropSolutionProse,
    FeedbackStyle,
    HideHiddenTests,
    MarkSolutionRegions,
    MystMarkdown,
    NotRunNote,
    OfflineMathJaxHTMLExporter,
    PointsHeader,
    RequireGradingMetadata,
    RestoreMissingCells,
)
# Verdicts decided in a grader kernel, outside the student's, which a submission could tamper
# with: tools/grading/bridge/.
from tools.grading.bridge.bridge_report import BridgeReport
from tools.grading.bridge.execute import BridgedExecute

ROBOKIN = Path(__file__).resolve().parent

c = get_config()  # noqa: F821 - provided by nbgrader's config loader

c.CourseDirectory.course_id = "robokin"
# Overridden by the course directory's own nbgrader_config.py.
c.CourseDirectory.root = str(ROBOKIN / "_build" / "nbgrader" / "course")
c.Exchange.root = str(ROBOKIN / "_build" / "nbgrader" / "exchange")

# -- generate_assignment: the student edition, from the chapter's nbgrader metadata
c.GenerateAssignment.preprocessors = [
    RequireGradingMetadata,   # a chapter without metadata is an error naming it
    IncludeHeaderFooter,
    InstantiateTests,
    PointsHeader,             # points per task, under the title
    MarkSolutionRegions,      # keep signatures and interface names; mark the prose
    LockCells,
    ClearSolutions,
    DropSolutionProse,        # the emptied solution prose is left out
    ClearOutput,
    CheckCellMetadata,
    ComputeChecksums,
    SaveCells,
    ClearHiddenTests,
    ClearMarkScheme,
    ComputeChecksums,
    CheckCellMetadata,
]
# Solution prose is read-only text that is not a graded answer: nbgrader allows
# solution regions there only with enforce_metadata off; they become empty.
c.ClearSolutions.enforce_metadata = False
c.ClearSolutions.text_stub = ""

# -- autograde: restore deleted tests, explain failures, report on top
c.Autograde.sanitize_preprocessors = [
    ClearOutput,
    DeduplicateIds,
    OverwriteKernelspec,
    RestoreMissingCells,
    CheckCellMetadata,
]
c.Autograde.autograde_preprocessors = [
    BridgedExecute,           # the student's kernel (sandboxed) + a grader kernel for the tests
    NotRunNote,               # the cells after the last graded one are not run: a note says so
    IgnorePattern,
    ClearMetadataPreprocessor,
    LimitOutput,
    SaveAutoGrades,
    AssignLatePenalties,
    CheckCellMetadata,
    AutograderReport,
    GradingIncidents,         # a kernel that died or was killed, tests not run, stderr notes
    BridgeReport,             # answers for review by hand, answers that are not plain data
]
c.OverwriteCells.add_missing_cells = True
c.Execute.timeout = int(os.environ.get("ROBOKIN_CELL_TIMEOUT", "120"))   # seconds per cell
# After a cell's reply, the rest of its output is waited for at most this long. nbclient's
# default, 4 s, is a limit load reaches: a cell that printed thousands of lines on a busy
# machine ended in "Timeout waiting for IOPub output", a timed-out cell in the grading. The
# wait ends as soon as the cell's idle status arrives, so it gets the cell's own ceiling.
c.Execute.iopub_timeout = c.Execute.timeout
# The executor's two settings of the student's kernel keep their defaults here, so that the
# course directory's nbgrader_config.py (loaded after this file) decides them; there, an
# older c.RobokinExecute.<setting> still applies, with a warning naming the new one.
# 3D scenes of the graded notebook as pictures: the feedback page is read offline.
# c.BridgedExecute.viewer = "matplotlib"   (the default)
# Each submission's kernel runs in a bubblewrap sandbox (Debian package `bubblewrap`):
# it sees the system and the Python environment read-only and writes only its own
# folder; the course (source/, gradebook.db, other students), the exchange and the
# repository are hidden, and it has no network. Turn it off only where grading
# already runs in a container of its own: ROBOKIN_GRADING_SANDBOX=off, or
# c.BridgedExecute.sandbox = False   (book/for-instructors.md, "What grading guarantees")
# c.BridgedExecute.sandbox = True   (the default)

# -- generate_feedback: MathJax inlined (the page is read offline, and handed out alone)
c.GenerateFeedback.exporter_class = OfflineMathJaxHTMLExporter
# nbgrader's two preprocessors, then the robokin ones (tools/grading/robokin_nbgrader/)
c.GenerateFeedback.preprocessors = [
    GetGrades,
    CSSHTMLHeaderPreprocessor,
    FeedbackStyle,            # notes that wrap at the page's width; tables with a column gap
    HideHiddenTests,          # no hidden test in the page (a student reads it before handing in again)
    MystMarkdown,             # the task statements' MyST as Markdown ({exercise}, {admonition}, {cite})
]
# Every chapter's test cells and robokin.check's verdicts run in a grader kernel, the answers
# handed over as data (book/for-instructors.md, "Where the verdicts are decided"). A call of a
# student's function from a test goes over a socket to a call server in the student's kernel
# (a fraction of a millisecond; tools/grading/bridge/benchmark.py measures it); one that has
# not returned after c.BridgedExecute.call_timeout seconds (30) is stopped.
# Each grader kernel is forked from a process that imported ipykernel, numpy, scipy, sympy,
# matplotlib and robokin once per autograde run (tools/grading/bridge/fork_server.py): 1.7-2.5
# CPU-s saved per submission after the first (book/for-instructors.md has the measurement).
# False: each grader kernel starts as a new process.
c.BridgedExecute.fork_server = True
