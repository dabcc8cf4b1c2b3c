"""nbgrader preprocessors of the robokin course (configured in ``nbgrader_config.py``), one per module.

nbgrader does the work -- ``generate_assignment`` clears the solutions and records
the assignment in its gradebook, ``autograde`` runs the submission and scores
its test cells, ``generate_feedback`` writes the HTML -- and these classes plug
into its pipelines:

========================================  ==========================  =====================================
class (pipeline)                          module                      what it does
========================================  ==========================  =====================================
``RequireGradingMetadata`` (generate)     require_grading_metadata    a chapter without nbgrader metadata
                                                                      is an error naming the notebook
``MarkSolutionRegions`` (generate)        mark_solution_regions       marks what ``ClearSolutions`` empties
``DropSolutionProse`` (generate)          drop_solution_prose         the emptied solution prose goes
``PointsHeader`` (generate)               points_header               points per task, under the title
``RestoreMissingCells`` (autograde)       restore_missing_cells       a deleted test cell is put back
``NotRunNote`` (autograde)                not_run_note                a note above the cells not run
                                                                      (nothing after them is graded)
``AutograderReport`` (autograde)          autograder_report           the report on top: score per task,
                                                                      findings, what went wrong
``GradingIncidents`` (autograde)          grading_incidents           what happened to the kernel
                                                                      (``NOT_RUN``, ``KERNEL_LOST``)
``HideHiddenTests`` (feedback)            hide_hidden_tests           no hidden test in the feedback page
``FeedbackStyle`` (feedback)              feedback_style              the page's own stylesheet
``MystMarkdown`` (feedback)               myst_markdown               MyST task statements as Markdown
``OfflineMathJaxHTMLExporter`` (feedback) offline_mathjax             MathJax inlined: read offline
========================================  ==========================  =====================================

and the modules they share: ``cells`` (a cell's robokin metadata, task, hidden lines and label),
``checks`` (what ``robokin.check`` is asked, ``registered_pairs``), ``failure_notes``
(``FailureNotes``, the note under a failing test) and ``streams`` (a kernel client whose stream
outputs are joined). Autograde's executor, which replaces nbgrader's ``Execute``, is not here:
``BridgedExecute`` (``tools/grading/bridge/execute.py``) runs the submission in a sandboxed
student's kernel and the tests and ``robokin.check``'s verdicts in a grader kernel, using these
modules. Every other preprocessor of the pipelines is nbgrader's own (``nbgrader_config.py``
lists them).

The cell roles come from ``tools/authoring/nbgrader_metadata.py`` (``metadata.robokin``).
"""

from __future__ import annotations

from .autograder_report import AutograderReport
from .cells import hidden_lines, visible_source
from .checks import VERDICT_MARK, registered_pairs
from .drop_solution_prose import DropSolutionProse
from .failure_notes import FailureNotes
from .feedback_style import FeedbackStyle
from .grading_incidents import KERNEL_LOST, NOT_RUN, GradingIncidents
from .hide_hidden_tests import HideHiddenTests
from .mark_solution_regions import MarkSolutionRegions
from .myst_markdown import MystMarkdown
from .not_run_note import NotRunNote
from .offline_mathjax import OfflineMathJaxHTMLExporter, inline_mathjax, mathjax_script
from .points_header import PointsHeader
from .require_grading_metadata import RequireGradingMetadata
from .restore_missing_cells import RestoreMissingCells

__all__ = [
    "AutograderReport", "DropSolutionProse", "FailureNotes", "FeedbackStyle", "GradingIncidents",
    "HideHiddenTests", "KERNEL_LOST", "MarkSolutionRegions", "MystMarkdown", "NOT_RUN", "NotRunNote",
    "OfflineMathJaxHTMLExporter", "PointsHeader", "RequireGradingMetadata", "RestoreMissingCells",
    "VERDICT_MARK", "hidden_lines",
    "inline_mathjax", "mathjax_script", "registered_pairs", "visible_source",
]
