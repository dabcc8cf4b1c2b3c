r"""Secondary objectives for null-space IK (:class:`robokin.motion.ik.NullSpace`).

A secondary objective is a scalar function :math:`H(q)` to be *maximised* by
self-motion, :math:`\dot q = J^+ e + (I - J^+ J)\, k\, \nabla H(q)`
(Liégeois 1977; Siciliano et al. 2009, §3.5.1).  Every objective
here offers ``value(q, ctx)`` and ``gradient(q, ctx)``, both broadcasting over
a batch ``q`` of shape ``(N, n)``.  ``ctx`` is what the solver knows about the
problem (an :class:`~robokin.motion.ik.problem.IKContext`); it is optional
where the objective can do without it: :class:`JointLimitDistance` takes the
joint limits directly (``JointLimitDistance(limits)`` or
``value(q, limits)``), :class:`GradientObjective` ignores it.

The null-space gain :math:`k` is a setting of the method
(:class:`~robokin.motion.ik.NullSpace`), applied to any objective; an
objective may state the default it needs with a ``default_gain`` attribute
(:class:`Manipulability`: 1).

References
----------
A. Liégeois, "Automatic supervisory control of the configuration and behavior
of multibody mechanisms", IEEE Trans. SMC 7(12), 1977.
Y. Nakamura, *Advanced Robotics: Redundancy and Optimization*, 1991.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

import numpy as np

from robokin.errors import ShapeError
from robokin.validation import check_limits, check_positive

__all__ = [
    "Objective",
    "JointLimitDistance",
    "Manipulability",
    "GradientObjective",
    "as_objective",
    "objective_limits",
]


class Objective(Protocol):
    """Interface of a secondary objective (maximised)."""

    def value(self, q: np.ndarray, ctx: Any) -> np.ndarray: ...

    def gradient(self, q: np.ndarray, ctx: Any) -> np.ndarray: ...


def objective_limits(limits: Any, name: str = "limits") -> tuple[np.ndarray, np.ndarray]:
    """Joint limits as ``(lower, upper)``, each (n,), from a context or an array (n, 2).

    ``limits`` is an object with ``lower`` and ``upper`` (the solver's
    :class:`~robokin.motion.ik.problem.IKContext`) or array_like (n, 2) of
    rows ``(lower, upper)``.
    """
    if hasattr(limits, "lower") and hasattr(limits, "upper"):
        return np.asarray(limits.lower, dtype=float), np.asarray(limits.upper, dtype=float)
    a = check_limits(limits, None, name)
    return a[:, 0], a[:, 1]


class JointLimitDistance:
    r"""Distance from the joint limits (Liégeois 1977; Siciliano et al. 2009, eq. 3.57).

    .. math::
        H(q) = -\frac{1}{2n}\sum_{i=1}^n
               \left(\frac{q_i - \bar q_i}{q_{M,i} - q_{m,i}}\right)^2,
        \qquad
        \frac{\partial H}{\partial q_i} = -\frac{1}{n}\,
               \frac{q_i - \bar q_i}{(q_{M,i} - q_{m,i})^2}

    with :math:`\bar q_i` the middle of the range.  Joints with an infinite
    range contribute nothing.  Maximal (0) with every joint at mid-range.

    Parameters
    ----------
    limits : array_like, shape (n, 2), optional
        Joint limits (rad or m), rows ``(lower, upper)``.  Without them the
        limits come with each call: ``value(q, ctx)`` with the solver's
        context or an array (n, 2).

    Examples
    --------
    >>> import numpy as np
    >>> H = JointLimitDistance([[-1.0, 1.0], [0.0, 2.0]])
    >>> float(H.value(np.array([0.5, 1.0])))
    -0.015625
    >>> H.gradient(np.array([0.5, 1.0]))
    array([-0.0625, -0.    ])
    """

    def __init__(self, limits: Any = None) -> None:
        self.limits = None if limits is None else check_limits(limits, None, "limits")

    def bounds(self, ctx: Any = None) -> tuple[np.ndarray, np.ndarray]:
        """``(lower, upper)`` (n,) used: the limits given when created, else those of ``ctx``."""
        if self.limits is not None:
            return self.limits[:, 0], self.limits[:, 1]
        if ctx is None:
            raise TypeError("JointLimitDistance needs the joint limits: create it with limits=(n, 2) "
                            "or pass the solver's context or the limits (n, 2) as ctx; got neither")
        return objective_limits(ctx, "ctx")

    def _terms(self, ctx: Any) -> tuple[np.ndarray, np.ndarray]:
        lo, hi = self.bounds(ctx)
        finite = np.isfinite(lo) & np.isfinite(hi) & (hi > lo)
        mid = np.where(finite, 0.5 * (lo + hi), 0.0)
        inv_range = np.where(finite, 1.0 / np.where(finite, hi - lo, 1.0), 0.0)
        return mid, inv_range

    def value(self, q: np.ndarray, ctx: Any = None) -> np.ndarray:
        """:math:`H(q)`, shape ``q.shape[:-1]``; ``ctx``: context or limits (n, 2), optional (see above)."""
        mid, inv_range = self._terms(ctx)
        n = q.shape[-1]
        return -0.5 / n * np.sum(((q - mid) * inv_range) ** 2, axis=-1)

    def gradient(self, q: np.ndarray, ctx: Any = None) -> np.ndarray:
        """:math:`\nabla H(q)`, shape of ``q``; ``ctx`` as for :meth:`value`."""
        mid, inv_range = self._terms(ctx)
        n = q.shape[-1]
        return -(q - mid) * inv_range**2 / n


class Manipulability:
    r"""Manipulability :math:`w(q) = \sqrt{\det(J J^T)}` (Yoshikawa 1985; Siciliano eq. 3.56).

    Computed on the task rows of the Jacobian; the gradient is taken by
    central differences with step ``h`` (one batched Jacobian call of
    ``2n`` configurations per configuration).  Needs the solver's context
    (for the chain, the tool and the mask).  Its default null-space gain is 1
    (``default_gain``): its gradient has other units than the joint-limit one.
    """

    #: Null-space gain used by :class:`~robokin.motion.ik.NullSpace` when none is given.
    default_gain = 1.0

    def __init__(self, h: float = 1e-6) -> None:
        self.h = check_positive(h, "h", scalar=True)

    def value(self, q: np.ndarray, ctx: Any) -> np.ndarray:
        if ctx is None:
            raise TypeError("Manipulability needs the solver's context (its chain, tool and mask) as ctx; got None")
        J = ctx.task_jacobian(q)
        return np.sqrt(np.maximum(np.linalg.det(J @ np.swapaxes(J, -1, -2)), 0.0))

    def gradient(self, q: np.ndarray, ctx: Any) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        n = q.shape[-1]
        lead = q.shape[:-1]
        qb = q.reshape(-1, n)
        offsets = np.concatenate((np.eye(n), -np.eye(n))) * self.h  # (2n, n)
        probes = (qb[:, None, :] + offsets[None]).reshape(-1, n)
        w = self.value(probes, ctx).reshape(-1, 2, n)
        grad = (w[:, 0] - w[:, 1]) / (2.0 * self.h)
        return grad.reshape(lead + (n,))


class GradientObjective:
    """Wrap user callables: ``gradient(q) -> (n,)`` and optionally ``value(q) -> float``.

    The callables receive one configuration ``q`` of shape ``(n,)``; a batch is
    handled row by row.  ``ctx`` is accepted and ignored.  A plain gradient
    function given as ``objective=`` is wrapped in this class; it gets the same
    default null-space gain as the joint-limit objective (see
    :class:`~robokin.motion.ik.NullSpace`).
    """

    def __init__(
        self,
        gradient: Callable[[np.ndarray], Any],
        value: Callable[[np.ndarray], Any] | None = None,
    ) -> None:
        if not callable(gradient):
            raise TypeError(f"objective gradient must be callable; got {type(gradient).__name__}")
        if value is not None and not callable(value):
            raise TypeError(f"objective value must be callable or None; got {type(value).__name__}")
        self._gradient = gradient
        self._value = value

    def value(self, q: np.ndarray, ctx: Any = None) -> np.ndarray:
        if self._value is None:
            raise TypeError("this objective was given without a value function")
        q = np.asarray(q, dtype=float)
        if q.ndim == 1:
            return np.asarray(float(self._value(q)))
        return np.array([float(self._value(row)) for row in q])

    def gradient(self, q: np.ndarray, ctx: Any = None) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        if q.ndim == 1:
            g = np.asarray(self._gradient(q), dtype=float)
        else:
            g = np.array([np.asarray(self._gradient(row), dtype=float) for row in q])
        if g.shape != q.shape:
            raise ShapeError(
                f"objective gradient must return shape {q.shape[-1:]} per configuration; "
                f"got shape {g.shape[-1:] if q.ndim > 1 else g.shape}"
            )
        return g


_NAMED: dict[str, Callable[[], Objective]] = {"joint_limits": JointLimitDistance, "manipulability": Manipulability}


def as_objective(objective: Any) -> Objective:
    """Turn ``"joint_limits"``, ``"manipulability"``, an objective object or a
    gradient callable into an objective object."""
    if isinstance(objective, str):
        try:
            return _NAMED[objective]()
        except KeyError:
            raise ValueError(
                f"objective must be one of {sorted(_NAMED)}, an objective object or a "
                f"gradient callable; got {objective!r}"
            ) from None
    if hasattr(objective, "gradient") and callable(objective.gradient):
        return objective
    if callable(objective):
        return GradientObjective(objective)
    raise TypeError(
        "objective must be a name, an object with .gradient(q, ctx) or a gradient "
        f"callable; got {type(objective).__name__}"
    )
