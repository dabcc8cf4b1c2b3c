"""No docstring of robokin names a file of the machine it was written on.

``help(robokin.models.eth_leg)`` is read on a student's machine: a path such as
``/work/...`` or ``/home/...`` means nothing there. The sources of a model are named
for what they are (a report, a tutorial), not where a copy was kept.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re

import robokin

#: An absolute path of a machine: /home/..., /Users/..., /work/..., /mnt/..., C:\...
MACHINE_PATH = re.compile(r"(?<![\w.:/])(?:/(?:home|Users|work|mnt|tmp|srv|root)/[\w.*-]+|[A-Z]:\\\\\w)")


def _docstrings():
    for info in pkgutil.walk_packages(robokin.__path__, "robokin."):
        try:
            module = importlib.import_module(info.name)
        except Exception:  # noqa: BLE001 - an optional dependency missing: nothing to read there
            continue
        yield info.name, inspect.getdoc(module) or ""
        for name, obj in vars(module).items():
            if getattr(obj, "__module__", None) == info.name and (inspect.isfunction(obj) or inspect.isclass(obj)):
                yield f"{info.name}.{name}", inspect.getdoc(obj) or ""


def test_no_docstring_names_a_path_of_the_authors_machine():
    found = [(name, match.group(0)) for name, doc in _docstrings() for match in MACHINE_PATH.finditer(doc)]
    assert not found, f"docstrings that name a path of a machine: {found[:5]}"
