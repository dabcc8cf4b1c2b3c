"""The optional libraries of the views, each imported here and only here, when first needed.

``import robokin.views`` imports none of them (a headless machine without
matplotlib or MeshCat can still build and export scenes); each function below
imports its library on the first call and returns the module. A missing
library raises :class:`ModuleNotFoundError` naming the extra that installs it.
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["ipython_display", "ipywidgets", "psutil", "pyplot", "umsgpack", "zmq"]

#: ``pip install`` hint for every optional library.
EXTRAS = {
    "IPython.display": "robokin[views]",
    "ipywidgets": "robokin[views]",
    "matplotlib.pyplot": "robokin[views]",
    "psutil": "psutil",
    "umsgpack": "robokin[views]",
    "zmq": "robokin[views]",
}


def _load(name: str) -> ModuleType:
    """Import module ``name``; a missing library raises ModuleNotFoundError with the install hint."""
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as exc:
        raise ModuleNotFoundError(f"{name.split('.')[0]} is not installed ({exc}); "
                                  f"pip install '{EXTRAS[name]}'") from exc


def pyplot() -> ModuleType:
    """``matplotlib.pyplot`` (matplotlib figures of :mod:`robokin.views.plots`).

    Returns
    -------
    module

    Raises
    ------
    ModuleNotFoundError
        The library is not installed (the message says what to install).
    """
    return _load("matplotlib.pyplot")


def ipython_display() -> ModuleType:
    """``IPython.display`` (``display``, ``HTML``: notebook outputs).

    Returns
    -------
    module

    Raises
    ------
    ModuleNotFoundError
        The library is not installed (the message says what to install).
    """
    return _load("IPython.display")


def ipywidgets() -> ModuleType:
    """``ipywidgets`` (the joint sliders).

    Returns
    -------
    module

    Raises
    ------
    ModuleNotFoundError
        The library is not installed (the message says what to install).
    """
    return _load("ipywidgets")


def umsgpack() -> ModuleType:
    """``umsgpack`` (MeshCat's wire format; installed with meshcat).

    Returns
    -------
    module

    Raises
    ------
    ModuleNotFoundError
        The library is not installed (the message says what to install).
    """
    return _load("umsgpack")


def zmq() -> ModuleType:
    """``zmq`` (the command socket of a live MeshCat server; installed with meshcat).

    Returns
    -------
    module

    Raises
    ------
    ModuleNotFoundError
        The library is not installed (the message says what to install).
    """
    return _load("zmq")


def psutil() -> ModuleType:
    """``psutil`` (a process's environment where ``/proc`` is not available).

    Returns
    -------
    module

    Raises
    ------
    ModuleNotFoundError
        The library is not installed (the message says what to install).
    """
    return _load("psutil")
