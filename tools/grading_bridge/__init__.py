"""The grading bridge: robokin's autograder decides verdicts outside the student's kernel.

``codec``         plain data as JSON, on both sides (untrusted input: whitelist and caps)
``grader_side``   in the grader's kernel: answers imported as data, functions as proxies
``delegation``    answers that hand back robokin's own solution, for review by hand
``preprocessors`` nbgrader's autograde pipeline: ``BridgedExecute``, ``BridgeReport``

This file imports nothing: the grader's kernel imports ``grader_side`` alone.
"""
