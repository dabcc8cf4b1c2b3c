"""The grading bridge: robokin's autograder decides verdicts outside the student's kernel.

``codec``         plain data as JSON, on both sides (untrusted input: whitelist and caps)
``grader_side``   in the grader's kernel: answers imported as data, functions as proxies
``delegation``    answers that hand back robokin's own solution, for review by hand
``execute``       nbgrader's autograde pipeline: ``BridgedExecute``, its executor (the student's kernel in a
                  sandbox, the grader kernel beside it)
``grader_kernel`` ``GraderKernel``: the grader kernel, in which the instructor's cells and the verdicts run
``pictures``      which read-only cells the grader kernel runs (``skip_pictures``; nbgrader not imported)
``bridge_report`` nbgrader's autograde pipeline: ``BridgeReport``, what the bridge adds to the report
``fork_server``   grader kernels forked from a warm process (imports paid once per autograde)
``fork_launcher`` the command jupyter_client runs for a forked grader kernel (standard library only)
``benchmark``     what one call of a student's function costs through the bridge (run by hand)

This file imports nothing: the grader's kernel imports ``grader_side`` alone.
"""
