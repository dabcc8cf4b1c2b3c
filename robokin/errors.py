"""Exception hierarchy of robokin.

All exceptions raised deliberately by robokin derive from :class:`RobokinError`.
The two concrete classes also derive from :class:`ValueError`, so code that
already catches ``ValueError`` keeps working.

- :class:`ShapeError` -- an argument has the wrong shape or length.
- :class:`DomainError` -- an argument has the right shape but a value that is not
  allowed: NaN/inf, out of range, not a rotation matrix, lower limit above upper
  limit, zero-length axis, ...

A wrong *type* (e.g. a string where numbers are expected) raises the built-in
:class:`TypeError`.
"""

from __future__ import annotations

__all__ = ["RobokinError", "ShapeError", "DomainError"]


class RobokinError(Exception):
    """Base class of all robokin errors."""


class ShapeError(RobokinError, ValueError):
    """An argument has the wrong shape or length.

    Example message: ``q must have shape (6,) or (N, 6); got shape (5,)``.
    """


class DomainError(RobokinError, ValueError):
    """An argument has a value outside its domain.

    Raised for NaN or infinite entries, values out of range, matrices that are not
    rotations or transforms, joint limits with lower > upper, zero-length axes or
    quaternions, ...
    """
