"""Backend-neutral geometry of a scene: frames, link layout, scale, bounds, floor (numpy only).

Both the MeshCat commands (:mod:`robokin.views.meshcat_draw`) and the
matplotlib figures (:mod:`robokin.views.plots`) are computed from these.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from robokin.chains.protocol import DrawableChain
from robokin.errors import DomainError
from robokin.views.record import ChainItem, EllipsoidItem, PathItem, PointsItem, SceneRecord, TargetItem

__all__ = ["chain_frames", "chain_frames_batch", "chain_layout", "ellipsoid_box_points", "mesh_box_points",
           "quaternion_xyzw", "sample_configurations", "scene_bounds", "scene_floor", "scene_points", "scene_scale"]


def chain_frames(chain: DrawableChain, q: np.ndarray) -> np.ndarray:
    """The frames of ``chain`` at ``q``, checked.

    Parameters
    ----------
    chain : SerialChain
        Any object with ``n`` and ``frames(q)``.
    q : array_like, shape (n,)
        Configuration (rad, m).

    Returns
    -------
    numpy.ndarray, shape (n + 2, 4, 4)
        Base, joint frames and tool, in the base frame (m).

    Raises
    ------
    DomainError
        ``chain.frames(q)`` has another shape.
    """
    F = np.asarray(chain.frames(np.asarray(q, dtype=float)), dtype=float)
    n = int(chain.n)
    if F.shape != (n + 2, 4, 4):
        raise DomainError(f"chain.frames(q) must return shape ({n + 2}, 4, 4); got {F.shape}")
    return F


def chain_frames_batch(chain: DrawableChain, Q: np.ndarray) -> np.ndarray:
    """The frames of ``chain`` at every row of ``Q``.

    Parameters
    ----------
    chain : SerialChain
        Any object with ``n`` and ``frames(q)`` (batched ``frames(Q)`` is used when it works).
    Q : array_like, shape (T, n)
        Configurations (rad, m).

    Returns
    -------
    numpy.ndarray, shape (T, n + 2, 4, 4)
    """
    Q = np.asarray(Q, dtype=float)
    n = int(chain.n)
    try:
        F = np.asarray(chain.frames(Q), dtype=float)
        if F.shape == (Q.shape[0], n + 2, 4, 4):
            return F
    except Exception:  # noqa: BLE001 - fall back to one call per row
        pass
    return np.stack([chain_frames(chain, q) for q in Q])


def sample_configurations(chain: DrawableChain, q: np.ndarray) -> list[np.ndarray]:
    """``q`` and two fixed pseudo-random configurations within the limits (``[-π, π]`` where infinite).

    Parameters
    ----------
    chain : SerialChain
        Any object with ``n`` and ``limits`` (n, 2).
    q : numpy.ndarray, shape (n,)

    Returns
    -------
    list of numpy.ndarray, shape (n,)
        Three configurations, the same on every machine (seeded).
    """
    n = int(chain.n)
    lim = np.asarray(chain.limits, dtype=float).reshape(n, 2)
    lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -np.pi)
    hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], np.pi)
    rng = np.random.default_rng(12345)
    return [q] + [lo + (hi - lo) * rng.random(n) for _ in range(2)]


def chain_layout(chain: DrawableChain, q: np.ndarray) -> dict:
    """Analyse the chain's geometry at ``q``.

    Parameters
    ----------
    chain : SerialChain
        Any object with ``n``, ``frames(q)`` and ``limits``.
    q : array_like, shape (n,)
        Configuration (rad, m).

    Returns
    -------
    dict
        ``frames`` (n + 2, 4, 4) at ``q``; ``reach`` (m), the sum of link
        lengths (the largest over ``q`` and two sample configurations);
        ``segments``, a list of ``(i, rigid, v)`` for each drawn link from
        frame i to frame i + 1 (``rigid``: its length does not change with
        the joints; ``v`` (3,) the link vector in frame i, m); ``n``.

    Raises
    ------
    DomainError
        All links have zero length (nothing to draw).
    """
    F = chain_frames(chain, q)
    n = int(chain.n)
    origins = F[:, :3, 3]
    lengths = np.linalg.norm(np.diff(origins, axis=0), axis=1)
    samples = [chain_frames(chain, qs) for qs in sample_configurations(chain, q)[1:]]
    reach = float(max([lengths.sum()] + [np.linalg.norm(np.diff(Fs[:, :3, 3], axis=0), axis=1).sum()
                                         for Fs in samples]))
    if not reach > 1e-9:
        raise DomainError(
            f"chain: all {n + 1} links have zero length (every frame origin coincides with the base), "
            "so there is nothing to draw")
    tol = 1e-9 * max(reach, 1.0)
    segments = []
    for i in range(n + 1):
        local = [np.linalg.solve(Fs[i], Fs[i + 1])[:3, 3] for Fs in [F] + samples]
        rigid = all(np.allclose(v, local[0], atol=tol * 1e3) for v in local[1:])
        varying_len = max(np.linalg.norm(v) for v in local)
        if rigid and np.linalg.norm(local[0]) < 1e-6 * reach:
            continue                      # zero-length link: nothing to draw
        if not rigid and varying_len < 1e-6 * reach:
            continue
        segments.append((i, rigid, local[0]))
    return {"frames": F, "reach": reach, "segments": segments, "n": n}


def scene_scale(scene: SceneRecord) -> float:
    """A characteristic length of the scene (m): the largest chain reach, else the farthest point.

    Parameters
    ----------
    scene : SceneRecord
        Usually a :class:`robokin.views.Scene`.

    Returns
    -------
    float
        In metres; 1.0 for an empty scene.
    """
    reaches = [chain_layout(it.chain, it.q)["reach"] for it in scene.items if isinstance(it, ChainItem)]
    if reaches:
        return max(reaches)
    pts = [it.points for it in scene.items if isinstance(it, (PathItem, PointsItem))]
    pts += [it.T[None, :3, 3] for it in scene.items if isinstance(it, TargetItem)]
    pts += [ellipsoid_box_points(it) for it in scene.items if isinstance(it, EllipsoidItem)]
    if pts:
        ext = float(np.abs(np.vstack(pts)).max())
        if ext > 0:
            return ext
    return 1.0


def scene_bounds(scene: SceneRecord, points: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """Centre and radius of the box around everything drawn (chains over their animations too).

    Parameters
    ----------
    scene : SceneRecord
    points : numpy.ndarray, shape (N, 3), optional
        :func:`scene_points` of the scene when already computed (m).

    Returns
    -------
    center : numpy.ndarray, shape (3,)
        Centre of the box (m).
    radius : float
        Half its diagonal (m).
    """
    P = scene_points(scene) if points is None else points
    lo, hi = P.min(axis=0), P.max(axis=0)
    return (lo + hi) / 2, float(np.linalg.norm(hi - lo) / 2)


def scene_floor(scene: SceneRecord, points: np.ndarray | None = None) -> float:
    """Height (m) of the grid: z = 0, or the lowest point drawn when the robot reaches below it.

    So the grid is a floor under a hanging arm or a leg, never a ceiling.

    Parameters
    ----------
    scene : SceneRecord
    points : numpy.ndarray, shape (N, 3), optional
        :func:`scene_points` of the scene when already computed (m).

    Returns
    -------
    float
        At most 0 (m).
    """
    P = scene_points(scene) if points is None else points
    return min(0.0, float(P[:, 2].min()))


def scene_points(scene: SceneRecord) -> np.ndarray:
    """Every point drawn: the origin, the chains' frames (over their animations), mesh boxes, targets, paths,
    the boxes around ellipsoids.

    Parameters
    ----------
    scene : SceneRecord

    Returns
    -------
    numpy.ndarray, shape (N, 3)
        Positions in the base frame (m).
    """
    pts = [np.zeros((1, 3))]
    animated = {a.chain_name: a for a in scene.animations}
    for it in scene.items:
        if isinstance(it, ChainItem):
            if it.name in animated:
                F = chain_frames_batch(it.chain, animated[it.name].trajectory)
            else:
                F = chain_frames(it.chain, it.q)[None]
            pts.append(F[:, :, :3, 3].reshape(-1, 3))
            if getattr(it, "meshes", None) is not None:
                pts += mesh_box_points(it.meshes, F)
        elif isinstance(it, TargetItem):
            pts.append(it.T[None, :3, 3])
        elif isinstance(it, (PathItem, PointsItem)):
            pts.append(it.points)
        elif isinstance(it, EllipsoidItem):
            pts.append(ellipsoid_box_points(it))
    return np.vstack(pts)


def ellipsoid_box_points(item: EllipsoidItem) -> np.ndarray:
    r"""Two opposite corners of the smallest box, along the base axes, around an ellipsoid.

    The ellipsoid :math:`\mathbf{c} + \mathbf{M}\mathbf{s}`, :math:`\|\mathbf{s}\| = 1`, with
    :math:`\mathbf{M} = \mathbf{A}\,\mathrm{diag}(\mathbf{r})`, reaches along base axis :math:`k`
    the half-width :math:`\|\mathbf{M}_{k,:}\|` (the largest of :math:`\mathbf{M}_{k,:}\mathbf{s}`).

    Parameters
    ----------
    item : EllipsoidItem

    Returns
    -------
    numpy.ndarray, shape (2, 3)
        The lowest and the highest corner (m).
    """
    half = np.linalg.norm(item.axes * item.radii, axis=1)
    return np.stack([item.center - half, item.center + half])


def mesh_box_points(meshes: Any, F: np.ndarray) -> list[np.ndarray]:
    """Corners of each frame's mesh bounding box, placed by the frames ``F``.

    Parameters
    ----------
    meshes : RobotMeshes
        ``meshes.frames[i]``: the meshes of frame i (vertices in m).
    F : numpy.ndarray, shape (T, n + 2, 4, 4)
        Frames of the chain at T configurations.

    Returns
    -------
    list of numpy.ndarray, shape (8 T, 3)
        One array per frame that has meshes (m, base frame).
    """
    out = []
    for i, ms in enumerate(meshes.frames):
        if not ms:
            continue
        V = np.vstack([np.asarray(m.vertices, dtype=float) for m in ms])
        lo, hi = V.min(axis=0), V.max(axis=0)
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        out.append((F[:, i, None, :3, :3] @ corners[None, :, :, None])[..., 0].reshape(-1, 3)
                   + np.repeat(F[:, i, :3, 3], 8, axis=0))
    return out


def quaternion_xyzw(R: np.ndarray) -> np.ndarray:
    """Unit quaternions (x, y, z, w) -- three.js order, scalar last -- of rotation matrices.

    Parameters
    ----------
    R : array_like, shape (..., 3, 3)
        Rotation matrices.

    Returns
    -------
    numpy.ndarray, shape (..., 4)
        Unit quaternions; for a sequence (T, 3, 3) sign-continuous along axis 0
        (consecutive quaternions have a non-negative dot product), as
        animation tracks need.
    """
    R = np.asarray(R, dtype=float)
    m00, m11, m22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    w = np.sqrt(np.maximum(0.0, 1 + m00 + m11 + m22)) / 2
    x = np.sqrt(np.maximum(0.0, 1 + m00 - m11 - m22)) / 2
    y = np.sqrt(np.maximum(0.0, 1 - m00 + m11 - m22)) / 2
    z = np.sqrt(np.maximum(0.0, 1 - m00 - m11 + m22)) / 2
    x = np.copysign(x, R[..., 2, 1] - R[..., 1, 2])
    y = np.copysign(y, R[..., 0, 2] - R[..., 2, 0])
    z = np.copysign(z, R[..., 1, 0] - R[..., 0, 1])
    quat = np.stack([x, y, z, w], axis=-1)
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    if quat.ndim == 2:
        for k in range(1, len(quat)):
            if quat[k] @ quat[k - 1] < 0:
                quat[k] = -quat[k]
    return quat
