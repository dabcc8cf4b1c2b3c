"""Tiny chain test doubles following the chain contract (used until/besides robokin.models)."""

from __future__ import annotations

import numpy as np


def _rot_z(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def _trans(x=0.0, y=0.0, z=0.0):
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


class ChainDouble:
    """Joints about/along local z; ``offsets[i]`` is the fixed transform before joint i (i < n) or the tool."""

    def __init__(self, offsets, joint_types, limits=None, names=None):
        self.n = len(joint_types)
        self.joint_types = list(joint_types)
        self.joint_names = [f"q{i + 1}" for i in range(self.n)]
        self.joint_axes = np.tile([0.0, 0.0, 1.0], (self.n, 1))
        self._offsets = [np.asarray(o, float) for o in offsets]
        self.limits = np.array(limits if limits is not None else [[-np.pi, np.pi]] * self.n, float)
        self.frame_names = names or (["base"] + [f"link{i + 1}" for i in range(self.n)] + ["tool"])

    def _one(self, q):
        T = np.eye(4)
        out = [T]
        for i in range(self.n):
            motion = _rot_z(q[i]) if self.joint_types[i] == "revolute" else _trans(z=q[i])
            T = T @ self._offsets[i] @ motion
            out.append(T)
        out.append(T @ self._offsets[self.n])
        return np.stack(out)

    def frames(self, q):
        q = np.asarray(q, float)
        if q.ndim == 2:
            return np.stack([self._one(r) for r in q])
        return self._one(q)

    def fk(self, q):
        return self.frames(q)[-1]


def two_link(l1=1.0, l2=0.8):
    return ChainDouble([np.eye(4), _trans(x=l1), _trans(x=l2)], ["revolute", "revolute"])


def scara_like():
    """Revolute, revolute, prismatic (vertical), like a SCARA."""
    down = np.diag([1.0, -1, -1, 1])
    return ChainDouble([_trans(z=0.4), _trans(x=0.5), _trans(x=0.4) @ down, _trans(z=0.1)],
                       ["revolute", "revolute", "prismatic"],
                       limits=[[-2.5, 2.5], [-2.5, 2.5], [0.0, 0.3]])


def zero_length():
    return ChainDouble([np.eye(4), np.eye(4), np.eye(4)], ["revolute", "revolute"])
