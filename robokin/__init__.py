"""robokin: robot kinematics for teaching.

One model definition serves symbolic derivation (sympy), numeric evaluation
(NumPy, single and batched) and visualisation.

Layers (each imports only those above it; see CONTRIBUTING.md):

1. :mod:`robokin.errors`, :mod:`robokin.validation` — exceptions and argument checks;
2. :mod:`robokin.transforms` — rotations, homogeneous transforms, RPY, angle–axis, quaternions;
3. :mod:`robokin.chains`, :mod:`robokin.models` — serial chains and named robots;
4. :mod:`robokin.motion` — inverse kinematics, pose error, Cartesian control, simulation;
5. :mod:`robokin.views`, :mod:`robokin.check` — 3D scenes and plots; exercise checks.

The core (1–4) imports neither matplotlib nor MeshCat, so ``import robokin`` is
fast and works headless; ``robokin.views`` and ``robokin.check`` load on first use.
"""

from __future__ import annotations

import importlib
from typing import Any

from robokin import transforms
from robokin.errors import DomainError, RobokinError, ShapeError
from robokin.transforms import *  # noqa: F403  (the transform functions, listed in transforms.__all__)

__version__ = "0.1.0"

_LAZY_MODULES = ("chains", "models", "parallel", "motion", "views", "check")
_LAZY_NAMES = {
    "SerialChain": "robokin.chains",
    "from_dh": "robokin.chains",
    "from_modified_dh": "robokin.chains",
    "from_link_table": "robokin.chains",
    "Planar3RPR": "robokin.parallel",
    "solve_ik": "robokin.motion",
    "solve_ik_batch": "robokin.motion",
    "IKResult": "robokin.motion",
    "pose_error": "robokin.motion",
    "CartesianController": "robokin.motion",
    "simulate": "robokin.motion",
    "circle_trajectory": "robokin.motion",
    "line_trajectory": "robokin.motion",
    "via_point_trajectory": "robokin.motion",
}

__all__ = [
    "__version__",
    "RobokinError",
    "ShapeError",
    "DomainError",
    "transforms",
    *transforms.__all__,
    *_LAZY_MODULES,
    *_LAZY_NAMES,
]


def __getattr__(name: str) -> Any:
    """Import sub-packages and their main entry points on first use (PEP 562)."""
    if name in _LAZY_MODULES:
        return importlib.import_module(f"robokin.{name}")
    if name in _LAZY_NAMES:
        return getattr(importlib.import_module(_LAZY_NAMES[name]), name)
    raise AttributeError(f"module 'robokin' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
