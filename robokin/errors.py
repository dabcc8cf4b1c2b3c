"""Exception hierarchy of robokin.

All exceptions raised deliberately by robokin derive from :class:`RobokinError`.
The two concrete classes also derive from :class:`ValueError`, so code that
already catches ``ValueError`` keeps working.

- :class:`ShapeError` -- an argument has the wrong shape or length.
- :class:`DomainError` -- an argument has the right shape but a value that is not
  allowed: NaN/inf, out of range, not a rotation matrix, lower limit above upper
  limit, zero-length axis, ...
- :class:`URDFError` -- a URDF file cannot be read or turned into a serial chain
  (:func:`robokin.models.from_urdf`); :class:`URDFNotFoundError`, its subclass for a
  missing file, is also a :class:`FileNotFoundError`.

A wrong *type* (e.g. a string where numbers are expected) raises the built-in
:class:`TypeError`.

Warnings (issued with :func:`warnings.warn`, never raised):

- :class:`RobokinWarning` -- base class of robokin's warnings (a ``UserWarning``).
- :class:`SingularityWarning` -- a controlled motion came close to a singular
  configuration (smallest singular value of the Jacobian below a threshold), where
  the pseudoinverse asks for huge joint rates. Issued once per
  :func:`robokin.motion.simulate` run or :func:`robokin.motion.track_position_batch`
  sweep; silence it with ``warn_singular=False`` or the standard filter
  ``warnings.simplefilter("ignore", robokin.errors.SingularityWarning)``.
- :class:`MeshWarning` -- a visual mesh file of a URDF could not be read
  (:func:`robokin.models.visual_meshes`); the robot is still drawn, those links
  as a stick figure.
"""

from __future__ import annotations

__all__ = ["RobokinError", "ShapeError", "DomainError", "URDFError", "URDFNotFoundError", "RobokinWarning",
           "SingularityWarning", "MeshWarning", "ViewWarning"]


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


class URDFError(RobokinError, ValueError):
    """A URDF file cannot be read, or does not hold the requested serial chain.

    Raised by :func:`robokin.models.from_urdf` for malformed XML or URDF, a base
    or tip link that is not in the file, no chain between the two links, a
    closed loop, or a joint type robokin does not model (floating, planar,
    mimic). The message names the file and the link or joint.
    """


class URDFNotFoundError(URDFError, FileNotFoundError):
    """The URDF file does not exist (also a :class:`FileNotFoundError`)."""


class RobokinWarning(UserWarning):
    """Base class of all robokin warnings."""


class SingularityWarning(RobokinWarning, RuntimeWarning):
    r"""A controlled motion passed close to a singular configuration.

    The smallest singular value :math:`\sigma_{min}` of the Jacobian used by the
    controller fell below a threshold: there the pseudoinverse
    :math:`\dot q = J^+ \nu` commands joint rates up to
    :math:`\|\nu\| / \sigma_{min}` (Siciliano et al. 2009, §3.3 and §3.5.2).
    The message gives the time of the closest approach, the smallest
    :math:`\sigma_{min}` and the peak commanded joint speed; the log's ``sigma_min``
    and ``singular`` fields hold the per-step values.
    """


class MeshWarning(RobokinWarning):
    """Visual mesh files named by a URDF were not read: outside the robot's package, missing,
    not a mesh, or over a size cap.

    Issued once per URDF file by :func:`robokin.models.visual_meshes`; the frames
    those meshes belong to are drawn as a stick figure. The message names each
    file and why it was not read.
    """


class ViewWarning(RobokinWarning):
    """A view drew less than it was given: more points, path points or animation steps than a scene keeps.

    Issued by :mod:`robokin.views` (caps in :mod:`robokin.views.arguments`); the
    message gives the number given and the number drawn.
    """
