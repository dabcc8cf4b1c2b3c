"""The workbook's tools: authoring scripts, the nbgrader grading runtime, the notebook analyser.

A package, installed with robokin (``pip install -e .``, as ``requirements.txt`` does: see
``pyproject.toml``), so that scripts, ``nbgrader_config.py``, the book's extension, the grader
kernels and the tests import its modules by name (``from tools.notebook_analysis import ...``).
The scripts run as before (``python tools/authoring/student_edition.py``) or as modules
(``python -m tools.authoring.student_edition``).

This file imports nothing: a grader kernel imports ``tools.grading.bridge.grader_side`` alone.
"""
