"""The yardstick the benchmark tables divide by: a naive NumPy forward kinematics.

One 4×4 Denavit–Hartenberg matrix per joint built with ``np.array`` and
multiplied with ``@`` -- what a student writes first (UR10 parameters).
Timed in the same run as the code it measures, so that the ratio cancels the
machine's speed and its load; the goals are ratios to it:
forward kinematics ≤ 0.3×, geometric Jacobian ≤ 0.5×, default IK median ≤ 15×.
"""

from __future__ import annotations

import math
import time
import timeit

import numpy as np

#: UR10 DH rows (a, alpha, d) in m and rad
UR10_DH = ((0.0, math.pi / 2, 0.1273), (-0.612, 0.0, 0.0), (-0.5723, 0.0, 0.0),
           (0.0, math.pi / 2, 0.163941), (0.0, -math.pi / 2, 0.1157), (0.0, 0.0, 0.0922))


def naive_dh_fk(q: np.ndarray) -> np.ndarray:
    """End-effector pose (4, 4) of the UR10 at ``q`` (6,), one DH matrix per joint."""
    T = np.eye(4)
    for (a, alpha, d), theta in zip(UR10_DH, q):
        ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
        T = T @ np.array([[ct, -st * ca, st * sa, a * ct],
                          [st, ct * ca, -ct * sa, a * st],
                          [0.0, sa, ca, d],
                          [0.0, 0.0, 0.0, 1.0]])
    return T


def cpu_per_call(fn, number: int, repeat: int = 9) -> float:
    """Best-of-``repeat`` CPU seconds of this process per call (less sensitive to other load)."""
    return min(timeit.Timer(fn, timer=time.process_time).repeat(number=number, repeat=repeat)) / number


def yardstick_seconds(number: int = 5000) -> float:
    """CPU seconds of one :func:`naive_dh_fk` call on a fixed configuration."""
    q = np.array([0.1, -1.2, 1.3, -0.4, 0.5, 0.6])
    return cpu_per_call(lambda: naive_dh_fk(q), number)
