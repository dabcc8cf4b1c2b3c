"""Skipping a test module whose requirement is not installed, without importing it.

``pytest.importorskip("nbgrader")`` imports nbgrader to learn whether it is there: 1.3 s of
CPU (nbconvert, jupyter_server, sqlalchemy, ...) in every pytest process that collects the
module, although most of those processes never run an nbgrader command in process (the
grading suites run them in forked runners, ``support.nbgrader_runner``). :func:`require`
looks the package up instead; the modules that need it import it where they use it.
"""

from __future__ import annotations

import importlib.util

import pytest


def require(name: str, reason: str) -> None:
    """Skip the calling test module when the package ``name`` is not installed.

    Parameters
    ----------
    name : str
        The package's import name, e.g. ``"nbgrader"``.
    reason : str
        The skip's message: what to install, and how.
    """
    if importlib.util.find_spec(name) is None:
        pytest.skip(reason, allow_module_level=True)
