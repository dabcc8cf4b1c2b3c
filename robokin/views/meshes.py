"""Visual meshes of a URDF, expressed in the frames of any chain of the same robot.

:func:`robot_meshes` reads the meshes with :func:`robokin.models.visual_meshes`
(trimesh, yourdfpy: ``pip install 'robokin[robots]'``, imported only here) and
re-expresses them in the frames of the chain to draw, which may be the URDF
chain itself (``from_urdf``) or a hand-built model of the same robot whose
frames sit on the same bodies (``models.ur10()``, ``models.panda()``,
``models.baxter_left()``: DH frames are rigid with the URDF links).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from robokin.chains.protocol import DrawableChain
from robokin.errors import DomainError, ShapeError
from robokin.models.urdf import ROBOT_DESCRIPTIONS, robot_description
from robokin.models.urdf_meshes import DEFAULT_MESH_BYTES, RobotMeshes, VisualMesh, visual_chain, visual_meshes

__all__ = ["robot_meshes"]

#: Largest distance (m) / angle (rad) by which a chain frame may wobble relative to its URDF link.
_RIGID_TOL = 1e-4


def _sample_qs(chain):
    n = int(chain.n)
    lim = np.asarray(chain.limits, dtype=float).reshape(n, 2)
    lo = np.where(np.isfinite(lim[:, 0]), lim[:, 0], -np.pi)
    hi = np.where(np.isfinite(lim[:, 1]), lim[:, 1], np.pi)
    rng = np.random.default_rng(2024)
    return [np.clip(np.zeros(n), lo, hi)] + [lo + (hi - lo) * rng.random(n) for _ in range(3)]


def robot_meshes(urdf: str | os.PathLike, chain: DrawableChain, *, base_link: str | None = None,
                 tip_link: str | None = None, max_bytes: int | None = None) -> RobotMeshes:
    """The visual meshes of a robot, frame by frame in the frames of ``chain``.

    Parameters
    ----------
    urdf : str or os.PathLike
        A robot name of :func:`robokin.models.robot_description` (``"ur10"``,
        ``"baxter"``, ``"panda"``, or any robot of
        :func:`robokin.models.available_robots`, e.g. ``"kinova"``) or the path
        of a URDF file.
    chain : SerialChain
        The chain to draw: ``from_urdf(urdf, base_link, tip_link)`` or any chain
        with the same joints whose frame ``i`` is rigid with the URDF link that
        joint ``i`` moves (such as the hand-built ``models.ur10()``), and whose
        base frame is ``base_link``'s.
    base_link, tip_link : str, optional
        The chain's ends in the URDF. Default: for a robot name, those of
        :data:`robokin.models.ROBOT_DESCRIPTIONS`; for another robot or a file, the
        chain's first and last frame names (those of a ``from_urdf`` chain).
    max_bytes : int, optional
        Budget of the meshes (see :func:`robokin.models.visual_meshes`; default 150 000).

    Returns
    -------
    robokin.models.urdf_meshes.RobotMeshes
        ``frames[i]``: meshes with vertices in frame ``i`` of ``chain``. Pass it to
        ``Scene.add_chain(chain, q, meshes=...)`` or ``views.show(chain, q, meshes=...)``.

    Raises
    ------
    ImportError
        yourdfpy, trimesh or fast-simplification missing (``pip install 'robokin[robots]'``).
    DomainError
        ``chain`` has another number of joints than the URDF chain, or one of its
        frames moves relative to the URDF link it should be attached to.
    """
    if isinstance(urdf, str) and urdf in ROBOT_DESCRIPTIONS:
        path = robot_description(urdf)
        base_link = base_link or ROBOT_DESCRIPTIONS[urdf][1]
        tip_link = tip_link or ROBOT_DESCRIPTIONS[urdf][2]
    elif isinstance(urdf, (str, os.PathLike)) and not isinstance(urdf, bytes):
        path = Path(os.fsdecode(os.fspath(urdf)))
        if not str(path).lower().endswith((".urdf", ".xml")) and not path.exists():
            if not isinstance(urdf, str):
                raise DomainError(f"urdf: {str(path)!r} is not a URDF file")
            path = robot_description(urdf)   # any robot of example-robot-data, or a DomainError naming them
        names = list(getattr(chain, "frame_names", None) or [])
        base_link = base_link or (names[0] if names else None)
        tip_link = tip_link or (names[-1] if names else None)
    else:
        raise TypeError(f"urdf must be a robot name or the path of a URDF file; got {type(urdf).__name__} "
                        f"{urdf!r}"[:200])
    if base_link is None or tip_link is None:
        raise TypeError("base_link and tip_link must be given (link names of the URDF) for a chain without "
                        "frame_names")
    meshes = visual_meshes(path, base_link, tip_link,
                           max_bytes=DEFAULT_MESH_BYTES if max_bytes is None else max_bytes)
    ref = visual_chain(path, base_link, tip_link)  # from_urdf's chain (stored for the packaged robots)
    n = int(chain.n)
    if n != ref.n:
        raise DomainError(f"chain has {n} joints but the URDF chain from {base_link!r} to {tip_link!r} has "
                          f"{ref.n}: the meshes cannot be attached to its frames")
    # Z_i = (X G_i(q))^-1 F_i(q), X = F_0 G_0^-1: chain frame i in URDF frame i, constant on a rigid body
    samples = []
    for q in _sample_qs(chain):
        F = np.asarray(chain.frames(q), dtype=float)
        G = np.asarray(ref.frames(q), dtype=float)
        if F.shape != (n + 2, 4, 4):
            raise ShapeError(f"chain.frames(q) must have shape ({n + 2}, 4, 4); got {F.shape}")
        X = F[0] @ np.linalg.inv(G[0])
        samples.append(np.linalg.solve(X @ G, F))
    Zs = np.stack(samples)
    wobble = np.abs(Zs - Zs[0]).max(axis=(0, 2, 3))
    bad = np.flatnonzero(wobble > _RIGID_TOL)
    if bad.size:
        i = int(bad[0])
        chain_names = getattr(chain, "frame_names", None)
        raise DomainError(
            f"chain frame {i} ({list(chain_names)[i] if chain_names else i!r}) "
            f"moves by up to {wobble[i]:.3g} relative to the URDF link {meshes.frame_names[i]!r} it should be "
            f"attached to: the chain does not have the same joints (order, signs, zero positions) as the URDF "
            f"chain from {base_link!r} to {tip_link!r}")
    Z = Zs[0]
    if np.allclose(Z, np.eye(4), atol=1e-12):
        return meshes
    frames = []
    for i, ms in enumerate(meshes.frames):
        Zinv = np.linalg.inv(Z[i])
        frames.append(tuple(
            VisualMesh(np.ascontiguousarray(np.asarray(m.vertices, dtype=float) @ Zinv[:3, :3].T + Zinv[:3, 3],
                                            dtype=np.float32), m.faces, m.color, m.opacity, m.links)
            for m in ms))
    return RobotMeshes(tuple(getattr(chain, "frame_names", None) or meshes.frame_names), tuple(frames),
                       meshes.unreadable, meshes.source, meshes.original_triangles)
