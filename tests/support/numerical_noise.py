"""Make NumPy's linear algebra round differently, the way another computer would.

Imported at kernel start-up by ``test_notebooks_other_machines.py`` (through an
IPython start-up file). Every float array returned by the ``numpy.linalg``
functions below is multiplied by ``1 + 1e-14 * n`` with ``n`` drawn from a seeded
standard normal: about a hundred times the differences between BLAS kernels,
CPUs and thread counts, so an output that survives it does not depend on the
machine. Only the digits a computation's conditioning supports survive.
"""

from __future__ import annotations

import functools

import numpy as np
import numpy.linalg

RELATIVE_NOISE = 1e-14
FUNCTIONS = ("svd", "pinv", "solve", "inv", "lstsq", "eig", "eigh", "qr", "cholesky")
_rng = np.random.default_rng(20261123)


def _perturb(value):
    if isinstance(value, np.ndarray) and value.dtype.kind == "f":
        return value * (1.0 + RELATIVE_NOISE * _rng.standard_normal(value.shape))
    if isinstance(value, tuple):  # plain tuples and NumPy's named result tuples
        parts = [_perturb(part) for part in value]
        return type(value)(*parts) if hasattr(value, "_fields") else tuple(parts)
    return value


def _noisy(function):
    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        return _perturb(function(*args, **kwargs))

    return wrapper


def install() -> None:
    """Replace the ``numpy.linalg`` functions in :data:`FUNCTIONS` by noisy ones (idempotent)."""
    for name in FUNCTIONS:
        function = getattr(numpy.linalg, name)
        if not getattr(function, "_robokin_noisy", False):
            wrapper = _noisy(function)
            wrapper._robokin_noisy = True
            setattr(numpy.linalg, name, wrapper)
            np.linalg.__dict__[name] = wrapper
