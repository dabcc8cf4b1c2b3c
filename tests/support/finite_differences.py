"""Central finite differences of a chain's pose, the independent reference for Jacobian tests."""

from __future__ import annotations

import numpy as np


def pose_jacobian(chain, q, h: float = 1e-6) -> np.ndarray:
    """(6, n) geometric Jacobian [v; ω] of ``chain.fk`` at ``q`` by central differences:
    linear rows from the positions, angular rows from the skew part of R(q+h) R(q−h)ᵀ."""
    q = np.asarray(q, dtype=float)
    n = len(q)
    J = np.empty((6, n))
    for i in range(n):
        dq = np.zeros(n)
        dq[i] = h
        Tp, Tm = chain.fk(q + dq), chain.fk(q - dq)
        J[:3, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        A = Tp[:3, :3] @ Tm[:3, :3].T
        J[3:, i] = 0.5 * np.array([A[2, 1] - A[1, 2], A[0, 2] - A[2, 0], A[1, 0] - A[0, 1]]) / (2 * h)
    return J
