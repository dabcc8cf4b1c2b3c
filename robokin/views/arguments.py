"""Arguments of the views, checked: shapes, numbers, rigid transforms, sizes within the caps.

Every public function of :mod:`robokin.views` passes what it is given through
these checks first, so that bad input raises a robokin error that names the
argument, says what was expected and what came in -- never numpy's or MeshCat's
error from deep inside, and never a picture of something that is not what was
asked (a non-rigid "frame", a NaN path).

A scene is stored in a web page (static mode) or sent to a browser (live mode),
so its size is capped: at most :data:`MAX_POINTS` points per ``add_points``,
:data:`MAX_PATH_POINTS` per path and :data:`MAX_ANIMATION_STEPS` steps per
animation. Larger inputs are subsampled evenly (first and last kept) with a
:class:`~robokin.errors.ViewWarning` that gives both numbers: a million points
make a page of about 3 MB instead of 800 MB. Coordinates must lie within
:data:`MAX_COORDINATE` metres of the origin (the viewer stores float32).

This module imports only numpy (and robokin's core).
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from robokin.chains.protocol import DrawableChain
from robokin.errors import DomainError, ShapeError, ViewWarning
from robokin.validation import check_int, as_float_array, check_chain, check_positive, check_transform

__all__ = [
    "MAX_ANIMATION_STEPS",
    "MAX_COORDINATE",
    "MAX_DURATION",
    "MAX_PATH_POINTS",
    "MAX_POINTS",
    "as_chain",
    "as_color",
    "as_configuration",
    "as_height",
    "as_length",
    "as_numbers",
    "as_opacity",
    "as_points",
    "as_pose",
    "as_time_step",
    "as_times",
    "as_trajectory",
    "subsample",
]

#: Points of one ``Scene.add_points`` call kept in the scene (more are subsampled, with a warning).
MAX_POINTS = 100_000
#: Points of one path kept in the scene (more are subsampled, with a warning).
MAX_PATH_POINTS = 100_000
#: Steps of one animation kept in the scene (more are subsampled in time, with a warning).
MAX_ANIMATION_STEPS = 20_000
#: Longest animation (s) a scene plays (its times are stored as float32).
MAX_DURATION = 1e9
#: Largest coordinate (m) a scene accepts: the viewer stores float32, and a robot scene is metres wide.
MAX_COORDINATE = 1e6


def _describe(x: Any) -> str:
    text = repr(x)
    return f"{type(x).__name__} {text[:60] + '...' if len(text) > 60 else text}"


def as_numbers(x: Any, name: str, expected: str) -> np.ndarray:
    """``x`` as a finite float array.

    Parameters
    ----------
    x : array_like
        Numbers (any shape).
    name : str
        The argument's name, for messages.
    expected : str
        What was expected, for messages (e.g. ``"points of shape (N, 3)"``).

    Returns
    -------
    numpy.ndarray
        ``x`` as floats, same shape.

    Raises
    ------
    TypeError
        Not numbers (a string, a dict, None, objects).
    ShapeError
        A ragged sequence.
    DomainError
        NaN or infinity.
    """
    if isinstance(x, (str, bytes, dict, set)) or x is None:
        raise TypeError(f"{name} must be {expected}; got {_describe(x)}")
    try:
        return np.asarray(as_float_array(x, name), dtype=float)
    except TypeError:
        raise TypeError(f"{name} must be {expected} (numbers); got {_describe(x)}") from None
    except ShapeError:
        raise ShapeError(f"{name} must be {expected}; got a ragged sequence {_describe(x)}") from None


def _in_range(arr: np.ndarray, name: str) -> np.ndarray:
    if arr.size and np.abs(arr).max() > MAX_COORDINATE:
        raise DomainError(f"{name} must have coordinates within ±{MAX_COORDINATE:g} m (a scene is drawn in "
                          f"float32 metres); got a largest |coordinate| of {np.abs(arr).max():.3g}")
    return arr


def subsample(rows: np.ndarray, cap: int, name: str, what: str) -> np.ndarray:
    """At most ``cap`` rows, evenly spaced, first and last kept.

    Parameters
    ----------
    rows : numpy.ndarray, shape (N, ...)
        The rows.
    cap : int
        Most rows kept.
    name : str
        The argument's name, for the warning.
    what : str
        What a row is (``"points"``, ``"steps"``), for the warning.

    Returns
    -------
    numpy.ndarray, shape (min(N, cap), ...)
        ``rows`` itself when N <= cap.

    Warns
    -----
    ViewWarning
        When rows were dropped (both numbers in the message).
    """
    if len(rows) <= cap:
        return rows
    keep = np.unique(np.linspace(0, len(rows) - 1, cap).round().astype(int))
    warnings.warn(ViewWarning(
        f"{name}: {len(rows):,} {what} are more than a scene keeps ({cap:,}); drawing {len(keep):,} of "
        f"them, evenly spaced (subsample them yourself to choose which)"), stacklevel=4)
    return rows[keep]


def as_chain(chain: DrawableChain, name: str = "chain") -> Any:
    """A kinematic chain the views can draw.

    Parameters
    ----------
    chain : object
        Needs ``n`` (int >= 1) and ``frames(q)``; the views also read ``limits``.
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    object
        ``chain``.

    Raises
    ------
    TypeError
        ``chain`` has no integer ``n >= 1`` or no ``frames`` method.
    """
    check_chain(chain, name, methods=("frames",))
    return chain


def as_configuration(chain: DrawableChain, q: Any, name: str = "q") -> np.ndarray:
    """A joint configuration of ``chain``.

    Parameters
    ----------
    chain : SerialChain
        The chain.
    q : array_like, shape (n,), or None
        Configuration (rad, m); None: zeros moved into the joint limits.
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    numpy.ndarray, shape (n,)

    Raises
    ------
    ShapeError
        Another shape.
    TypeError, DomainError
        Not numbers; NaN or infinity.
    """
    n = int(as_chain(chain).n)
    if q is None:
        lim = np.asarray(chain.limits, dtype=float).reshape(n, 2)
        return np.clip(np.zeros(n), lim[:, 0], lim[:, 1])
    arr = as_numbers(q, name, f"a joint configuration of shape ({n},)")
    if arr.shape != (n,):
        raise ShapeError(f"{name} must have shape ({n},) for a chain with {n} joints; got shape {arr.shape}")
    return arr


def as_trajectory(chain: DrawableChain, trajectory: Any, name: str = "trajectory") -> np.ndarray:
    """A joint trajectory of ``chain``.

    Parameters
    ----------
    chain : SerialChain
        The chain.
    trajectory : array_like, shape (T, n)
        One configuration per step (rad, m), T >= 1; shape (T,) for a one-joint chain.
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    numpy.ndarray, shape (T, n)

    Raises
    ------
    ShapeError
        Another shape.
    TypeError, DomainError
        Not numbers; NaN or infinity.
    """
    n = int(as_chain(chain).n)
    expected = f"a joint trajectory of shape (T, {n}) (one row per time step, one column per joint)"
    arr = as_numbers(trajectory, name, expected)
    if arr.ndim == 1 and n == 1:
        arr = arr[:, None]
    if arr.ndim != 2 or arr.shape[1] != n or arr.shape[0] < 1:
        raise ShapeError(f"{name} must have shape (T, {n}) (one row per time step, T >= 1, one column per joint "
                         f"of the {n}-joint chain); got shape {arr.shape}")
    return arr


def as_points(points: Any, name: str = "points", *, minimum: int = 1, cap: int | None = None) -> np.ndarray:
    """Points in space, subsampled to at most ``cap``.

    Parameters
    ----------
    points : array_like, shape (N, 3) or (N, 2), or (3,) or (2,)
        Positions (m); rows of two get z = 0, a single point is one row.
    name : str, optional
        The argument's name, for messages.
    minimum : int, optional
        Fewest rows accepted.
    cap : int, optional
        Most rows kept (default :data:`MAX_POINTS`); more are subsampled with a warning.

    Returns
    -------
    numpy.ndarray, shape (N, 3)

    Raises
    ------
    ShapeError
        Another shape, or fewer than ``minimum`` rows.
    DomainError
        NaN, infinity, or a coordinate beyond :data:`MAX_COORDINATE`.
    TypeError
        Not numbers.
    """
    arr = as_numbers(points, name, "points of shape (N, 3) (or (N, 2) for planar points)")
    if arr.ndim == 1 and arr.shape[0] in (2, 3):
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] not in (2, 3):
        raise ShapeError(f"{name} must have shape (N, 3) (or (N, 2) for planar points); got shape {arr.shape}")
    if arr.shape[0] < minimum:
        raise ShapeError(f"{name} must have at least {minimum} row{'s' if minimum > 1 else ''}; got shape "
                         f"{arr.shape}")
    if arr.shape[1] == 2:
        arr = np.hstack([arr, np.zeros((arr.shape[0], 1))])
    return subsample(_in_range(arr, name), MAX_POINTS if cap is None else cap, name, "points")


def as_pose(T: Any, name: str = "T") -> np.ndarray:
    """A rigid transform.

    Parameters
    ----------
    T : array_like, shape (4, 4) or (3,)
        A homogeneous transform (m), or a position (m) meaning no rotation.
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    numpy.ndarray, shape (4, 4)

    Raises
    ------
    ShapeError
        Another shape.
    DomainError
        Not a rigid transform (rotation part, bottom row), NaN/inf, or a
        coordinate beyond :data:`MAX_COORDINATE`.
    """
    arr = as_numbers(T, name, "a (4, 4) homogeneous transform or a (3,) position")
    if arr.shape == (3,):
        out = np.eye(4)
        out[:3, 3] = arr
        arr = out
    if arr.shape != (4, 4):
        raise ShapeError(f"{name} must be a (4, 4) homogeneous transform (or a (3,) position); got shape "
                         f"{arr.shape}")
    check_transform(arr, name=name)
    return _in_range(arr, name)


def as_times(times: Any, count: int, name: str = "times") -> np.ndarray:
    """Sample times, shifted to start at 0.

    Parameters
    ----------
    times : array_like, shape (count,)
        Times (s), finite and strictly increasing.
    count : int
        Number of samples expected (the trajectory's length).
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    numpy.ndarray, shape (count,)
        ``times - times[0]`` (s).

    Raises
    ------
    ShapeError
        Another shape.
    DomainError
        Not strictly increasing, NaN/inf, or beyond :data:`MAX_DURATION`.
    """
    arr = as_numbers(times, name, f"sample times of shape ({count},) in seconds")
    if arr.shape != (count,):
        raise ShapeError(f"{name} must have shape ({count},) to match trajectory; got shape {arr.shape}")
    if arr.size and np.abs(arr).max() > MAX_DURATION:
        raise DomainError(f"{name} must be within ±{MAX_DURATION:g} s; got {np.abs(arr).max():.3g}")
    if np.any(np.diff(arr) <= 0):
        k = int(np.argmax(np.diff(arr) <= 0))
        raise DomainError(f"{name} must be strictly increasing; got {name}[{k}] = {arr[k]:g} and "
                          f"{name}[{k + 1}] = {arr[k + 1]:g}")
    return arr - arr[0]


def _positive_at_most(value: Any, name: str, largest: float, unit: str) -> float:
    """A positive number of ``unit`` at most ``largest`` (the errors name ``name``)."""
    number = check_positive(value, name, scalar=True)
    if number > largest:
        raise DomainError(f"{name} must be at most {largest:g} {unit}; got {number:.3g}")
    return number


def as_length(value: Any, name: str) -> float:
    """A positive length.

    Parameters
    ----------
    value : float
        Length (m).
    name : str
        The argument's name, for messages.

    Returns
    -------
    float
        In (0, :data:`MAX_COORDINATE`] (m).

    Raises
    ------
    DomainError
        Not positive, not finite, or larger than :data:`MAX_COORDINATE`.
    TypeError
        Not a number.
    """
    return _positive_at_most(value, name, MAX_COORDINATE, "m")


def as_time_step(value: Any, name: str = "dt") -> float:
    """A positive time step.

    Parameters
    ----------
    value : float
        Time step (s).
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    float
        In (0, :data:`MAX_DURATION`] (s).

    Raises
    ------
    DomainError
        Not positive, not finite, or larger than :data:`MAX_DURATION`.
    TypeError
        Not a number.
    """
    return _positive_at_most(value, name, MAX_DURATION, "s")


def as_height(height: Any, name: str = "height") -> int:
    """A scene's height.

    Parameters
    ----------
    height : int
        CSS pixels, in [100, 4000].
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    int

    Raises
    ------
    TypeError
        Not an int (a bool is not accepted).
    DomainError
        Outside [100, 4000].
    """
    return check_int(height, name, 100, 4000)


def as_color(color: Any, name: str = "color") -> int:
    """A colour.

    Parameters
    ----------
    color : int
        ``0xRRGGBB``, in [0, 0xFFFFFF].
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    int

    Raises
    ------
    TypeError
        Not an int (a bool is not accepted).
    DomainError
        Outside [0, 0xFFFFFF].
    """
    return check_int(color, name, 0, 0xFFFFFF)


def as_opacity(opacity: Any, name: str = "opacity") -> float:
    """An opacity.

    Parameters
    ----------
    opacity : float
        In (0, 1]; 1 is opaque.
    name : str, optional
        The argument's name, for messages.

    Returns
    -------
    float

    Raises
    ------
    TypeError
        Not a number.
    DomainError
        Outside (0, 1].
    """
    if isinstance(opacity, (bool, str, bytes)) or not isinstance(opacity, (int, float, np.number)):
        raise TypeError(f"{name} must be a number in (0, 1]; got {_describe(opacity)}")
    value = float(opacity)
    if not 0.0 < value <= 1.0:
        raise DomainError(f"{name} must be in (0, 1]; got {value}")
    return value
