"""Inverse kinematics: iterative solvers behind one interface.

- :func:`solve_ik` — one target, with a per-iteration history;
- :func:`solve_ik_once` — one attempt of a method alone (no restarts, no polish);
- :func:`solve_ik_batch` — many targets at once, vectorised over targets;
- :mod:`~robokin.motion.ik.methods` — the step rules (``"lm"``, ``"pinv"``,
  ``"transpose"``, ``"weighted"``, ``"dls"``, ``"nullspace"``);
- :mod:`~robokin.motion.ik.objectives` — secondary objectives for ``"nullspace"``.

Inside: :mod:`~robokin.motion.ik.settings` checks the keywords once into an
``IKSettings`` record; :func:`~robokin.motion.ik.solve.run_attempt` is the
iteration of one attempt; :mod:`~robokin.motion.ik.stall` decides when an
attempt stalls and why; :mod:`~robokin.motion.ik.polish` polishes failures.
"""

from robokin.motion.ik.batch import solve_ik_batch
from robokin.motion.ik.methods import (
    METHODS,
    DampedLeastSquares,
    IKMethod,
    JacobianTranspose,
    LevenbergMarquardt,
    NullSpace,
    PseudoInverse,
    StepResult,
    WeightedPseudoInverse,
)
from robokin.motion.ik.objectives import GradientObjective, JointLimitDistance, Manipulability
from robokin.motion.ik.result import REASONS, IKBatchResult, IKHistory, IKResult
from robokin.motion.ik.solve import solve_ik, solve_ik_once

__all__ = [
    "solve_ik",
    "solve_ik_once",
    "solve_ik_batch",
    "IKResult",
    "IKHistory",
    "IKBatchResult",
    "REASONS",
    "METHODS",
    "IKMethod",
    "StepResult",
    "PseudoInverse",
    "JacobianTranspose",
    "WeightedPseudoInverse",
    "DampedLeastSquares",
    "NullSpace",
    "LevenbergMarquardt",
    "JointLimitDistance",
    "Manipulability",
    "GradientObjective",
]
