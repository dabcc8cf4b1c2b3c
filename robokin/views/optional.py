"""The optional libraries of the views, each imported here and only here, when first needed.

``import robokin.views`` imports none of them (a headless machine without
matplotlib or MeshCat can still build and export scenes); each function below
imports its library on the first call and returns the module. A missing
library raises :class:`ModuleNotFoundError` naming the extra that installs it.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
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


def _importer(attribute: str, name: str, use: str) -> Callable[[], ModuleType]:
    """The function ``attribute()`` of this module: module ``name`` (what the views ``use`` it for)."""
    def load() -> ModuleType:
        return _load(name)

    load.__name__ = load.__qualname__ = attribute
    load.__doc__ = f"""``{name}`` ({use}).

    Returns
    -------
    module

    Raises
    ------
    ModuleNotFoundError
        The library is not installed (the message says what to install).
    """
    return load


pyplot = _importer("pyplot", "matplotlib.pyplot", "matplotlib figures of :mod:`robokin.views.plots`")
ipython_display = _importer("ipython_display", "IPython.display", "``display``, ``HTML``: notebook outputs")
ipywidgets = _importer("ipywidgets", "ipywidgets", "the joint sliders")
umsgpack = _importer("umsgpack", "umsgpack", "MeshCat's wire format; installed with meshcat")
zmq = _importer("zmq", "zmq", "the command socket of a live MeshCat server; installed with meshcat")
psutil = _importer("psutil", "psutil", "a process's environment where ``/proc`` is not available")
