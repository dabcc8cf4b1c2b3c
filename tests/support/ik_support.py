"""Shared helpers for the motion tests (robots and reachable targets); no tests here."""

from __future__ import annotations

import numpy as np

import robokin.models as models
from robokin.chains import Rz, SerialChain, Tx


def ur10():
    return models.ur10()


def baxter_left():
    return models.baxter_left()


def planar_3r(limits=None):
    """Planar 3R arm (links 1, 0.8, 0.5 m) moving in the x-y plane."""
    return SerialChain(
        [Rz("q1"), Tx(1.0), Rz("q2"), Tx(0.8), Rz("q3"), Tx(0.5)],
        limits=limits,
        name="planar_3r",
    )


def reachable_targets(chain, N, seed):
    """FK of N seeded random configurations within the limits: (Q, T)."""
    Q = chain.random_configurations(N, seed=seed)
    return Q, chain.fk(Q)


def within_limits(chain, q, tol=0.0):
    lim = np.asarray(chain.limits)
    return np.all((q >= lim[:, 0] - tol) & (q <= lim[:, 1] + tol), axis=-1)
