"""The settings of an IK solve, parsed and checked once: :class:`IKSettings`.

:func:`~robokin.motion.solve_ik`, :func:`~robokin.motion.solve_ik_once` and
:func:`~robokin.motion.solve_ik_batch` take the same keywords; :func:`parse_settings`
checks them (naming the argument in every error) and returns one frozen record,
so that the iteration loops read only plain, valid values.
"""

from __future__ import annotations

from typing import Any, NamedTuple, TypedDict

import numpy as np

from robokin.chains.protocol import Chain
from robokin.motion.ik.methods import IKMethod, make_method
from robokin.motion.ik.problem import (
    IKContext,
    chain_data,
    check_nonnegative_int,
    make_context,
    parse_mask,
    parse_q0,
    parse_stall,
    parse_target,
    parse_tolerance,
)
from robokin.validation import check_chain, check_positive

__all__ = ["DEFAULTS", "REFINE_STALL_TOLERANCE", "IKSettings", "parse_settings"]

class _Defaults(TypedDict):
    tol: float
    restarts: int
    seed: int
    stall_iterations: int | None
    stall_tolerance: float | None
    gradient_tolerance: float


#: Default stopping parameters shared by :func:`solve_ik` and :func:`solve_ik_batch`.
DEFAULTS: _Defaults = {
    "tol": 1e-6,
    "restarts": 20,
    "seed": 0,
    "stall_iterations": None,
    "stall_tolerance": None,
    "gradient_tolerance": 1e-2,
}

#: Stall tolerance of the final polishing run after all attempts failed.
REFINE_STALL_TOLERANCE = 1e-3


class IKSettings(NamedTuple):
    """Checked settings of one IK solve (single or batched); read-only.

    (A named tuple, not a frozen dataclass: it is made on every call of a solver,
    and a frozen dataclass costs about a microsecond more to make.)

    Attributes
    ----------
    ctx : IKContext
        The chain, its limits, the task mask, the tool and the angle wrapping.
    method : IKMethod
        The step rule.
    is_position : bool
        The targets are positions (3,), not poses (4, 4).
    tol_position, tol_orientation : float
        Tolerances on the position (m) and orientation (rad) error norms.
    max_iterations : int
        Steps per attempt.
    restarts : int
        Extra attempts from random configurations after a failed one.
    seed : int, Generator or None
        Seed of the restart configurations.
    stall_iterations : int
        Window (steps) of the stall test.
    stall_tolerance : float
        Fraction by which the best error must drop over a window.
    gradient_tolerance : float
        Threshold of :func:`~robokin.motion.ik.stall.classify_stall`.
    max_step : float or None
        Cap on the joint step norm (rad or m).
    polish : bool
        Polish the best configuration when every attempt failed.
    """

    ctx: IKContext
    method: IKMethod
    is_position: bool
    tol_position: float
    tol_orientation: float
    max_iterations: int
    restarts: int
    seed: int | np.integer | np.random.Generator | None
    stall_iterations: int
    stall_tolerance: float
    gradient_tolerance: float
    max_step: float | None
    polish: bool


def parse_settings(
    chain: Chain,
    target: Any,
    q0: Any,
    method: str | IKMethod,
    options: dict[str, Any],
    *,
    batched: bool,
    mask: Any,
    tool: Any,
    tol: Any,
    max_iterations: Any,
    restarts: Any,
    seed: Any,
    stall_iterations: Any,
    stall_tolerance: Any,
    gradient_tolerance: Any,
    max_step: Any,
    wrap: Any,
    polish: bool,
) -> tuple[IKSettings, np.ndarray, np.ndarray]:
    """Check the arguments of a solver once.

    Returns ``(settings, T_goal, q_start)``: the goal pose(s) ``(4, 4)`` or
    ``(N, 4, 4)`` (a position target gets an identity rotation) and the
    initial configuration(s) ``(n,)`` or ``(N, n)``, clamped to the limits.
    Errors name the argument (see :func:`~robokin.motion.solve_ik`).
    """
    check_chain(chain)
    T_goal, is_position = parse_target(target, batched=batched)
    ctx = make_context(chain, parse_mask(mask, is_position), tool, wrap)
    tol_position, tol_orientation = parse_tolerance(tol)
    meth = make_method(method, options)
    if max_iterations is None:
        max_iterations = meth.default_max_iterations
    else:
        max_iterations = check_nonnegative_int(max_iterations, "max_iterations", 1)
    restarts = check_nonnegative_int(restarts, "restarts")
    stall_iterations, stall_tolerance = parse_stall(meth, stall_iterations, stall_tolerance)
    gradient_tolerance = check_positive(gradient_tolerance, "gradient_tolerance", scalar=True)
    if max_step is not None:
        max_step = check_positive(max_step, "max_step", scalar=True)
    q_start = parse_q0(q0, ctx.n, ctx.lower, ctx.upper, T_goal.shape[0] if batched else None,
                       chain_data(chain).middle)
    if seed is not None and not isinstance(seed, (np.random.Generator, int, np.integer)):
        raise TypeError(f"seed must be an int, a numpy Generator or None; got {type(seed).__name__}")
    settings = IKSettings(
        ctx=ctx, method=meth, is_position=is_position, tol_position=tol_position,
        tol_orientation=tol_orientation, max_iterations=max_iterations, restarts=restarts, seed=seed,
        stall_iterations=stall_iterations, stall_tolerance=stall_tolerance,
        gradient_tolerance=gradient_tolerance, max_step=max_step, polish=bool(polish),
    )
    return settings, T_goal, q_start
