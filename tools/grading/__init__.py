"""What runs when a submission is graded: nbgrader's pipeline, the grader kernels, the sandbox, the drivers.

``robokin_nbgrader/``  the nbgrader preprocessors and the feedback exporter (``nbgrader_config.py``)
``bridge/``            verdicts decided in a grader kernel, the answers handed over as data
``sandbox``            the student's kernel in a bubblewrap sandbox
``process_cap``        a cap on the processes a submission's kernel can start
``course``             the nbgrader course directory and command, the checks robokin registers
``grade_submission``   grades one notebook without a course directory to keep
``grade_many``         grades a folder of submissions (``make grade``)
``gradescope``         the Gradescope autograder zip of a chapter (``make gradescope``)
``deploy/``            grading at scale: the container image and the Kubernetes Job

Nothing here imports ``tools/authoring/`` (``tests/test_tools_package.py`` checks it): the
Gradescope zip and the grading image carry this folder and the shared modules of ``tools/``.
This file imports nothing: a grader kernel imports ``tools.grading.bridge.grader_side`` alone.
"""
