"""What robokin's solvers and views read from a serial chain, as typing protocols.

:class:`~robokin.chains.SerialChain` satisfies both protocols; any other object
with the same attributes and methods does too (duck typing, checked statically
by mypy and at run time by :func:`robokin.validation.check_chain`).

Public API
----------
Chain
    A serial chain for the numeric algorithms (IK, control, simulation, sweeps,
    joint sliders): ``n``, ``limits``, joint names/types/axes, frame names,
    ``fk``, ``frames``, ``jacobian``, ``position_jacobian``.
DrawableChain
    The smaller contract of the 3D views and plots: ``n``, ``limits``,
    ``joint_types``, ``joint_axes`` and ``frames(q)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["Chain", "DrawableChain", "Frame"]

#: A frame of a chain: an index (0 base, 1..n joint frames, n+1 or -1 end-effector) or a name.
Frame = int | str


class DrawableChain(Protocol):
    """A chain the views can draw (e.g. :class:`~robokin.chains.SerialChain`)."""

    @property
    def n(self) -> int:
        """Number of joints, >= 1."""
        ...

    @property
    def limits(self) -> NDArray[np.float64]:
        """Joint limits ``[lower, upper]`` (rad, m), shape (n, 2)."""
        ...

    @property
    def joint_types(self) -> Sequence[str]:
        """``'revolute'`` or ``'prismatic'`` for each joint."""
        ...

    @property
    def joint_axes(self) -> NDArray[np.float64]:
        """Unit joint axes, each in its joint's own frame, shape (n, 3)."""
        ...

    def frames(self, q: ArrayLike) -> NDArray[np.float64]:
        """Poses of the ``n + 2`` frames (base, joints, end-effector) in the base frame.

        Parameters
        ----------
        q : array_like, shape (n,) or (N, n)
            Configuration(s) (rad, m).

        Returns
        -------
        numpy.ndarray, shape (n+2, 4, 4) or (N, n+2, 4, 4)
        """
        ...


class Chain(DrawableChain, Protocol):
    """A serial chain for the numeric algorithms (e.g. :class:`~robokin.chains.SerialChain`).

    :class:`DrawableChain`'s members, the names below, and the kinematics, each
    with ``check=False`` to skip the validation of ``q`` in hot loops.
    """

    @property
    def joint_names(self) -> Sequence[str]:
        """Joint names, base to tool (``n`` of them)."""
        ...

    @property
    def frame_names(self) -> Sequence[str]:
        """Names of the ``n + 2`` frames of :meth:`frames`."""
        ...

    def frames(self, q: ArrayLike, *, check: bool = True) -> NDArray[np.float64]:
        """Poses of the ``n + 2`` frames, shape (n+2, 4, 4) or (N, n+2, 4, 4)."""
        ...

    def fk(self, q: ArrayLike, frame: Frame | None = None, *, check: bool = True) -> NDArray[np.float64]:
        """Pose of the end-effector (or of ``frame``) in the base, shape (4, 4) or (N, 4, 4)."""
        ...

    def jacobian(self, q: ArrayLike, frame: Frame | None = None, point: ArrayLike | None = None, *,
                 check: bool = True) -> NDArray[np.float64]:
        """Geometric Jacobian in the base frame, rows ``[v; ω]``, shape (6, n) or (N, 6, n)."""
        ...

    def position_jacobian(self, q: ArrayLike, frame: Frame | None = None, point: ArrayLike | None = None, *,
                          check: bool = True) -> NDArray[np.float64]:
        """The linear-velocity rows of :meth:`jacobian`, shape (3, n) or (N, 3, n)."""
        ...

    def fk_and_jacobian(self, q: ArrayLike, *, check: bool = True
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """:meth:`fk` and :meth:`jacobian` of the end-effector from one pass, shapes (4, 4) and
        (6, n), or (N, 4, 4) and (N, 6, n)."""
        ...
