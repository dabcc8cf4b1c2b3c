"""Registry of exercise checks, one module per chapter.

A chapter module (``robokin/check/<chapter>.py``) defines its checks with
:func:`exercise` and lists its chapter in :data:`CHAPTERS`; students reach them
as ``robokin.check.<chapter>.<check>``. Adding a chapter is: a module with a few
``exercise(...)`` lines, and one entry here.
"""

from __future__ import annotations

import importlib
from typing import Any

from robokin.check._core import Check

__all__ = ["CHAPTERS", "exercise", "checks_of", "chapter"]

#: chapter name -> module holding its checks (imported on first use).
CHAPTERS: dict[str, str] = {
    "leg": "robokin.check.leg",
    "ur10": "robokin.check.ur10",
    "three_rpr": "robokin.check.three_rpr",
    "cartesian": "robokin.check.cartesian",
    "baxter": "robokin.check.baxter",
    "ar601": "robokin.check.ar601",
    "ur10_closed_form": "robokin.check.ur10_closed_form",
    "product_of_exponentials": "robokin.check.product_of_exponentials",
    "statics_ellipsoids": "robokin.check.statics_ellipsoids",
    "trajectories": "robokin.check.trajectories",
}

_REGISTRY: dict[str, dict[str, Check]] = {}


def exercise(chapter: str, attr: str, check: Check) -> Check:
    """Register ``check`` as ``robokin.check.<chapter>.<attr>``.

    Parameters
    ----------
    chapter : str
        A chapter of :data:`CHAPTERS`.
    attr : str
        The check's name in the chapter's module.
    check : Check
        The check.

    Returns
    -------
    Check
        ``check``.
    """
    _REGISTRY.setdefault(chapter, {})[attr] = check
    return check


def chapter(name: str) -> Any:
    """Import and return the check module of a chapter.

    Parameters
    ----------
    name : str
        A chapter of :data:`CHAPTERS` (e.g. ``"ur10"``).

    Returns
    -------
    module

    Raises
    ------
    AttributeError
        ``name`` is not a chapter with checks (the message lists them).
    """
    if not isinstance(name, str) or name not in CHAPTERS:
        raise AttributeError(
            f"robokin.check has no chapter {name!r}; available: {', '.join(sorted(CHAPTERS))}"
        )
    return importlib.import_module(CHAPTERS[name])


def checks_of(name: str) -> dict[str, Check]:
    """All checks of a chapter, by attribute name.

    Parameters
    ----------
    name : str
        A chapter of :data:`CHAPTERS`.

    Returns
    -------
    dict of str to Check

    Raises
    ------
    ValueError
        ``name`` is not a chapter with checks (see :data:`CHAPTERS`).
    """
    if not isinstance(name, str) or name not in CHAPTERS:
        raise ValueError(f"name must be one of {', '.join(repr(c) for c in sorted(CHAPTERS))}; got {name!r}")
    chapter(name)
    return dict(_REGISTRY.get(name, {}))
