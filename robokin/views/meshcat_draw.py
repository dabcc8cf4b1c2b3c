"""Lowering a :class:`~robokin.views.scene.Scene` to MeshCat commands.

A chain is drawn from its kinematic description alone (``frames(q)``,
``joint_axes``, ``joint_types``):

- one scene node per frame ``/meshcat/<item>/<i>_<frame name>`` whose transform is
  the frame's pose in the base frame (only these transforms change with ``q``);
- links: cylinders between consecutive frame origins.  A link that is rigid in the
  frame before it (the next joint is revolute, or it is the tool) hangs below that
  frame node; a link whose length changes (the next joint is prismatic) is its own
  node ``/meshcat/<item>/link_<i>`` with a scaled unit cylinder.  Zero-length links
  are skipped; a chain whose links are *all* zero-length raises ``DomainError``;
- revolute joints: short cylinders along the joint axis; prismatic joints: boxes;
- the end-effector: a sphere and a small triad; optional triads (with text
  labels) at every frame.

A chain item with visual meshes (``Scene.add_chain(chain, q, meshes=...)``, see
:mod:`robokin.views.meshes`) is drawn with them instead of the stick figure: mesh
``k`` of frame ``i`` is the object ``/meshcat/<item>/<i>_<frame name>/mesh_<k>``, a
child of the frame node, so the frame transforms (and the animation tracks) move
it. Each mesh is one ``set_object`` command whose object depends on the mesh alone
(``BufferGeometry`` with float32 positions and uint32 indices, a flat-shaded Phong
material, uuids hashed from the data): two scenes of the same robot, at any ``q``,
hold byte-identical mesh commands (their path is the same for the same item name),
which the book stores once.  A frame whose mesh files could not be read keeps its
stick-figure parts.

An ellipsoid item is MeshCat's unit sphere (``SphereGeometry``) at ``/meshcat/<item>``,
shaped by the node's transform :func:`ellipsoid_transform`,
``axes @ diag(radii)`` and its centre.

Sizes are proportional to the chain's reach (sum of link lengths).  Commands are
plain dicts in MeshCat's wire format; ids are derived from paths, so the output is
deterministic.  Only numpy is needed here (``umsgpack`` is used for packing).
The geometry (layout, scale, bounds) comes from :mod:`robokin.views.geometry`.
"""

from __future__ import annotations

import hashlib
import re

import numpy as np

from robokin.chains.protocol import DrawableChain
from robokin.views import optional
from robokin.views.geometry import (
    chain_frames,
    chain_frames_batch,
    chain_layout,
    quaternion_xyzw,
    scene_bounds,
    scene_floor,
    scene_points,
    scene_scale,
)
from robokin.views.record import ChainItem, EllipsoidItem, PathItem, PointsItem, SceneRecord, TargetItem

__all__ = ["animation_command", "chain_commands", "chain_transforms", "ellipsoid_transform", "scene_commands",
           "set_transform_command"]
# chain_layout, quaternion_xyzw, scene_bounds, scene_floor and scene_scale live in robokin.views.geometry;
# they are imported here too for code written when they lived here.

ROOT = "/meshcat"
LINK_COLOR = 0xE69F00        # orange
JOINT_COLOR = 0x3B3B3B       # dark grey
PRISMATIC_COLOR = 0x8E44AD   # purple
EE_COLOR = 0xD62728          # red
TARGET_COLOR = 0xFF00FF
AXIS_COLORS = (0xE41A1C, 0x2CA02C, 0x1F77B4)   # x red, y green, z blue
_DIGITS = 6
#: Up to this many points, ``Scene.add_points`` draws spheres; more are one point cloud (squares).
SPHERES_UP_TO = 500
#: An ellipsoid's semi-axis shorter than this fraction of its longest one is drawn at that length.
FLAT_FRACTION = 1e-3
#: ... and one shorter than this (m) at this length: a transform of 6 decimals keeps it non-zero.
SHORTEST_DRAWN_RADIUS = 1e-5


def _r(x):
    return round(float(x), _DIGITS) + 0.0  # + 0.0: no negative zeros, the same bytes on every machine


def _uuid(*parts):
    h = hashlib.md5("/".join(parts).encode()).hexdigest()
    return f"{h[:8]}-{h[8:12]}-{h[12:16]}-{h[16:20]}-{h[20:32]}"


def _safe(name):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", str(name)) or "_"


def _matrix_list(T):
    """Column-major flat list, as three.js ``Matrix4.fromArray`` wants it."""
    return [_r(v) for v in np.asarray(T, dtype=float).T.ravel()]


def _rot_y_to(d):
    """A rotation whose y column is the unit vector ``d`` (three.js cylinders run along y)."""
    d = np.asarray(d, dtype=float)
    d = d / np.linalg.norm(d)
    helper = np.array([1.0, 0, 0]) if abs(d[0]) < 0.9 else np.array([0, 0, 1.0])
    x = np.cross(d, helper)
    x /= np.linalg.norm(x)
    z = np.cross(x, d)
    return np.column_stack([x, d, z])


def _pose(R=None, p=None, scale=None):
    T = np.eye(4)
    if R is not None:
        T[:3, :3] = R
    if scale is not None:
        T[:3, :3] = T[:3, :3] @ np.diag(scale)
    if p is not None:
        T[:3, 3] = p
    return T


def _sizes(reach):
    r = 0.022 * reach
    return {"link": r, "joint_r": 1.7 * r, "joint_h": 5.0 * r, "box": 3.0 * r, "box_h": 6.5 * r,
            "ee": 1.5 * r, "triad": 0.14 * reach, "ee_triad": 0.1 * reach}


# ----------------------------------------------------------------- object JSON
def _material(kind, color, opacity=1.0, **extra):
    m = {"type": kind, "color": int(color)}
    if opacity < 1.0:
        m.update(transparent=True, opacity=_r(opacity), depthWrite=False)
    m.update(extra)
    return m


def _object(path, geometry, material, *, kind="Mesh", matrix=None):
    gid, mid = _uuid(path, "geometry"), _uuid(path, "material")
    obj = {"uuid": _uuid(path, "object"), "type": kind, "geometry": gid, "material": mid}
    if matrix is not None:
        obj["matrix"] = _matrix_list(matrix)
    return {"metadata": {"version": 4.5, "type": "Object"},
            "geometries": [dict(geometry, uuid=gid)], "materials": [dict(material, uuid=mid)],
            "object": obj}


def _cylinder(radius, height, segments=20):
    return {"type": "CylinderGeometry", "radiusTop": _r(radius), "radiusBottom": _r(radius),
            "height": _r(height), "radialSegments": segments}


def _sphere(radius):
    return {"type": "SphereGeometry", "radius": _r(radius), "widthSegments": 20, "heightSegments": 12}


def _box(w, h, d):
    return {"type": "BoxGeometry", "width": _r(w), "height": _r(h), "depth": _r(d)}


def _float32(array):
    return optional.umsgpack().Ext(0x17, (np.ascontiguousarray(array, dtype="<f4") + np.float32(0.0)).tobytes())


def _uint32(array):
    return optional.umsgpack().Ext(0x16, np.ascontiguousarray(array, dtype="<u4").tobytes())


def _data_uuid(*chunks):
    h = hashlib.md5()
    for c in chunks:
        h.update(c if isinstance(c, bytes) else repr(c).encode())
        h.update(b"|")
    d = h.hexdigest()
    return f"{d[:8]}-{d[8:12]}-{d[12:16]}-{d[16:20]}-{d[20:32]}"


def _mesh_object(mesh, color, opacity=1.0):
    """Object JSON of a :class:`~robokin.models.urdf_meshes.VisualMesh`; depends on the mesh (and colour) only."""
    V = (np.ascontiguousarray(mesh.vertices, dtype="<f4") + np.float32(0.0)).tobytes()
    F = np.ascontiguousarray(mesh.faces, dtype="<u4").tobytes()
    material = _material("MeshPhongMaterial", color, opacity, flatShading=True, side=2, shininess=20)
    gid = _data_uuid(b"geometry", V, F)
    mid = _data_uuid(b"material", sorted(material.items()))
    geometry = {"uuid": gid, "type": "BufferGeometry", "data": {
        "attributes": {"position": {"itemSize": 3, "type": "Float32Array", "array": _float32(mesh.vertices.ravel()),
                                    "normalized": False}},
        "index": {"itemSize": 1, "type": "Uint32Array", "array": _uint32(mesh.faces.ravel())}}}
    return {"metadata": {"version": 4.5, "type": "Object"},
            "geometries": [geometry], "materials": [dict(material, uuid=mid)],
            "object": {"uuid": _data_uuid(b"object", gid, mid), "type": "Mesh", "geometry": gid, "material": mid}}


def _line(path, points, color, opacity=1.0):
    geometry = {"type": "BufferGeometry", "data": {"attributes": {"position": {
        "itemSize": 3, "type": "Float32Array", "array": _float32(np.asarray(points).ravel()),
        "normalized": False}}}}
    return _object(path, geometry, _material("LineBasicMaterial", color, opacity), kind="Line")


def _point_cloud(path, points, color, size):
    """One MeshCat ``Points`` object: every point a square of side ``size`` (m) facing the camera."""
    geometry = {"type": "BufferGeometry", "data": {"attributes": {"position": {
        "itemSize": 3, "type": "Float32Array", "array": _float32(np.asarray(points).ravel()),
        "normalized": False}}}}
    return _object(path, geometry, _material("PointsMaterial", color, size=_r(size), sizeAttenuation=True),
                   kind="Points")


def _text_sprite(path, text, size):
    tid, mid = _uuid(path, "texture"), _uuid(path, "material")
    return {"metadata": {"version": 4.5, "type": "Object"}, "geometries": [],
            "textures": [{"uuid": tid, "type": "_text", "text": str(text), "font_size": 40,
                          "font_face": "sans-serif"}],
            "materials": [{"uuid": mid, "type": "SpriteMaterial", "map": tid, "transparent": True,
                           "depthTest": False}],
            "object": {"uuid": _uuid(path, "object"), "type": "Sprite", "material": mid,
                       "matrix": _matrix_list(_pose(scale=(size, size, size)))}}


def _set_object(path, obj):
    return {"type": "set_object", "path": path, "object": obj}


def set_transform_command(path: str, T: np.ndarray) -> dict:
    """The MeshCat command that sets the transform of node ``path``.

    Parameters
    ----------
    path : str
        A MeshCat path such as ``"/meshcat/robot/1_link1"``.
    T : array_like, shape (4, 4)
        The node's pose in its parent node (m); rounded to 6 decimals.

    Returns
    -------
    dict
        ``{"type": "set_transform", "path": path, "matrix": [16 floats, column-major]}``.
    """
    return {"type": "set_transform", "path": path, "matrix": _matrix_list(T)}


def ellipsoid_transform(center: np.ndarray, radii: np.ndarray, axes: np.ndarray) -> np.ndarray:
    r"""The transform that makes MeshCat's unit sphere the ellipsoid: :math:`\mathbf{A}\,\mathrm{diag}(\mathbf{r})`.

    The viewer splits a node's transform into position, rotation and scale (three.js
    ``Matrix4.decompose``), which a zero scale turns into NaN: a semi-axis shorter than
    ``FLAT_FRACTION`` (10⁻³) times the longest one, or than ``SHORTEST_DRAWN_RADIUS``
    (10⁻⁵ m), is drawn at that length (a flat disc for a velocity ellipsoid at a singularity). A
    reflection (:math:`\det\mathbf{A} = -1`, as singular vectors may come) is kept: the
    viewer splits it too, and the sphere's mirror image is itself.

    Parameters
    ----------
    center : numpy.ndarray, shape (3,)
        The centre (m).
    radii : numpy.ndarray, shape (3,)
        Semi-axes (m), finite, ≥ 0, the largest positive.
    axes : numpy.ndarray, shape (3, 3)
        Orthonormal unit axes as columns.

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        ``[[A @ diag(drawn radii), center], [0, 0, 0, 1]]`` (m).
    """
    radii = np.asarray(radii, dtype=float)
    drawn = np.maximum(radii, max(FLAT_FRACTION * float(radii.max()), SHORTEST_DRAWN_RADIUS))
    return _pose(np.asarray(axes, dtype=float), np.asarray(center, dtype=float), scale=drawn)


def _triad_commands(path, size, opacity=1.0, label=None):
    cmds = []
    for k, name in enumerate("xyz"):
        axis = np.eye(3)[k]
        sub = f"{path}/{name}"
        cmds.append(_set_object(sub, _object(sub, _cylinder(size / 28, size, 10),
                                             _material("MeshLambertMaterial", AXIS_COLORS[k], opacity))))
        cmds.append(set_transform_command(sub, _pose(_rot_y_to(axis), axis * size / 2)))
    if label:
        sub = f"{path}/label"
        cmds.append(_set_object(sub, _text_sprite(sub, label, 0.9 * size)))
        cmds.append(set_transform_command(sub, _pose(p=(0.25 * size, 0.25 * size, 0.35 * size))))
    return cmds


# ----------------------------------------------------------------- chains
def _frame_paths(name, chain):
    n = int(chain.n)
    names = list(getattr(chain, "frame_names", None) or [f"frame{i}" for i in range(n + 2)])
    return [f"{ROOT}/{name}/{i}_{_safe(names[i])}" for i in range(n + 2)]


def _segment_pose(a, b):
    d = b - a
    L = float(np.linalg.norm(d))
    if L < 1e-12:
        return _pose(p=a, scale=(1.0, 1e-6, 1.0))
    return _pose(_rot_y_to(d / L), (a + b) / 2, scale=(1.0, L, 1.0))


def chain_transforms(name: str, chain: DrawableChain, q: np.ndarray, layout: dict | None = None
                     ) -> list[tuple[str, np.ndarray]]:
    """The pose of every moving node of chain item ``name`` at ``q``.

    Parameters
    ----------
    name : str
        The chain item's name.
    chain : SerialChain
        Any object with ``n``, ``frames(q)`` and ``limits``.
    q : array_like, shape (n,)
        Configuration (rad, m).
    layout : dict, optional
        :func:`~robokin.views.geometry.chain_layout` of the chain, when already computed.

    Returns
    -------
    list of (str, numpy.ndarray of shape (4, 4))
        MeshCat path and pose (m): one per frame, then one per link of varying length.
    """
    F = chain_frames(chain, q)
    layout = layout or chain_layout(chain, q)
    paths = _frame_paths(name, chain)
    out = [(paths[i], F[i]) for i in range(len(paths))]
    for i, rigid, _ in layout["segments"]:
        if not rigid:
            out.append((f"{ROOT}/{name}/link_{i}", _segment_pose(F[i, :3, 3], F[i + 1, :3, 3])))
    return out


def chain_commands(item: ChainItem, scene_scale: float | None = None) -> list[dict]:
    """MeshCat commands drawing a chain item.

    Parameters
    ----------
    item : ChainItem
        The chain, its configuration and style.
    scene_scale : float, optional
        Unused (sizes follow the chain's own reach); kept for callers that pass it.

    Returns
    -------
    list of dict
        ``set_transform`` and ``set_object`` commands.

    Raises
    ------
    DomainError
        All links of the chain have zero length.
    """
    chain, q, name = item.chain, item.q, item.name
    layout = chain_layout(chain, q)
    reach = layout["reach"]
    s = _sizes(reach)
    n = layout["n"]
    op = item.opacity
    link_color = item.color if item.color is not None else LINK_COLOR
    joint_color = item.color if item.color is not None else JOINT_COLOR
    paths = _frame_paths(name, chain)
    names = list(getattr(chain, "frame_names", None) or [f"frame{i}" for i in range(n + 2)])
    meshes = getattr(item, "meshes", None)
    if meshes is None:
        stick = set(range(n + 2))                      # frames whose stick-figure parts are drawn
    else:
        stick = {i for i, files in enumerate(meshes.unreadable) if files}
    cmds = []
    for path, T in chain_transforms(name, chain, q, layout):
        cmds.append(set_transform_command(path, T))
    if meshes is not None:
        for i, ms in enumerate(meshes.frames):
            for k, m in enumerate(ms):
                path = f"{paths[i]}/mesh_{k}"
                cmds.append(_set_object(path, _mesh_object(m, item.color if item.color is not None else m.color,
                                                           op * m.opacity)))
    # base plate
    if 0 in stick:
        base = f"{paths[0]}/base"
        cmds.append(_set_object(base, _object(base, _cylinder(3.2 * s["link"], 0.8 * s["link"], 28),
                                              _material("MeshLambertMaterial", joint_color, op),
                                              matrix=_pose(_rot_y_to([0, 0, 1.0]), (0, 0, -0.4 * s["link"])))))
    # links
    link_mat = _material("MeshPhongMaterial", link_color, op)
    for i, rigid, v in layout["segments"]:
        if i not in stick:
            continue
        if rigid:
            path = f"{paths[i]}/link"
            cmds.append(_set_object(path, _object(path, _cylinder(s["link"], float(np.linalg.norm(v))),
                                                  link_mat)))
            cmds.append(set_transform_command(path, _pose(_rot_y_to(v), v / 2)))
        else:
            path = f"{ROOT}/{name}/link_{i}"
            cmds.append(_set_object(path, _object(path, _cylinder(s["link"], 1.0), link_mat)))
    # joints
    axes = np.asarray(chain.joint_axes, dtype=float).reshape(n, 3)
    types = list(chain.joint_types)
    for j in range(n):
        if j + 1 not in stick:
            continue
        path = f"{paths[j + 1]}/joint"
        if types[j] == "prismatic":
            geom = _box(s["box"], s["box_h"], s["box"])
            mat = _material("MeshPhongMaterial", item.color if item.color is not None else PRISMATIC_COLOR, op)
        else:
            geom = _cylinder(s["joint_r"], s["joint_h"], 24)
            mat = _material("MeshPhongMaterial", joint_color, op)
        cmds.append(_set_object(path, _object(path, geom, mat)))
        cmds.append(set_transform_command(path, _pose(_rot_y_to(axes[j]))))
    # end-effector
    ee = f"{paths[n + 1]}/marker"
    if meshes is None or n in stick or n + 1 in stick:
        cmds.append(_set_object(ee, _object(ee, _sphere(s["ee"]),
                                            _material("MeshPhongMaterial", item.color if item.color is not None
                                                      else EE_COLOR, op))))
    if op == 1.0:
        cmds += _triad_commands(f"{paths[n + 1]}/triad", s["ee_triad"])
    if item.frames:
        for i in range(n + 1):
            cmds += _triad_commands(f"{paths[i]}/triad", s["triad"], op,
                                    label=names[i] if item.labels else None)
    return cmds


# ----------------------------------------------------------------- scene
def _decompose(Ts):
    """positions (T,3), quaternions (T,4) xyzw, scales (T,3) of transforms with positive scales."""
    M = Ts[:, :3, :3]
    scale = np.linalg.norm(M, axis=1)
    R = M / scale[:, None, :]
    return Ts[:, :3, 3], quaternion_xyzw(R), scale


def animation_command(scene: SceneRecord) -> dict | None:
    """One ``set_animation`` command for all animations of the scene.

    Parameters
    ----------
    scene : SceneRecord

    Returns
    -------
    dict or None
        The command (position, quaternion and, for links of varying length,
        scale tracks of every node that moves); None without animations.
    """
    if not scene.animations:
        return None
    entries = []
    for anim in scene.animations:
        item = scene.chain_item(anim.chain_name)
        F = chain_frames_batch(item.chain, anim.trajectory)
        layout = chain_layout(item.chain, anim.trajectory[0])
        paths = _frame_paths(item.name, item.chain)
        tracks = [(paths[i], F[:, i]) for i in range(len(paths))]
        for i, rigid, _ in layout["segments"]:
            if not rigid:
                tracks.append((f"{ROOT}/{item.name}/link_{i}",
                               np.stack([_segment_pose(f[i, :3, 3], f[i + 1, :3, 3]) for f in F])))
        times = _float32(anim.times)
        for path, Ts in tracks:
            if np.allclose(Ts, Ts[0], atol=1e-12):
                continue                  # never moves: no track (the static transform is enough)
            pos, quat, scale = _decompose(Ts)
            clip_tracks = [
                {"name": ".position", "type": "vector3", "times": times, "values": _float32(pos.ravel())},
                {"name": ".quaternion", "type": "quaternion", "times": times, "values": _float32(quat.ravel())},
            ]
            if not np.allclose(scale, 1.0):
                clip_tracks.append({"name": ".scale", "type": "vector3", "times": times,
                                    "values": _float32(scale.ravel())})
            entries.append({"path": path, "clip": {"fps": 1, "name": "default", "tracks": clip_tracks}})
    options = {"play": bool(scene.options.play), "repetitions": 1_000_000 if scene.options.loop else 1,
               "clampWhenFinished": True}
    return {"type": "set_animation", "path": "", "animations": entries, "options": options}


def _trace_commands(scene, anim):
    item = scene.item(anim.chain_name)
    F = chain_frames_batch(item.chain, anim.trajectory)
    path = f"{ROOT}/{item.name}_trace"
    return [_set_object(path, _line(path, F[:, -1, :3, 3], anim.trace_color))]


#: Side of the floor grid, in units of the scene's half diagonal (its cells: 1/40 of it).
GRID_SPAN = 2.5


def scene_commands(scene: SceneRecord) -> list[dict]:
    """All MeshCat commands of a scene, in order: camera, objects, then the animation.

    Parameters
    ----------
    scene : SceneRecord
        Usually a :class:`robokin.views.Scene`.

    Returns
    -------
    list of dict
        Commands in MeshCat's wire format; deterministic (ids hashed from paths and data).
    """
    L = scene_scale(scene)
    points = scene_points(scene)                   # forward kinematics over every animation, once
    center, radius = scene_bounds(scene, points)
    floor = scene_floor(scene, points)
    shift = _pose(p=-center)
    size = max(radius, 0.1 * L)
    d = 1.5 * size / np.tan(np.deg2rad(37.5))
    eye = np.array([0.95, 0.75, 0.6]) / np.linalg.norm([0.95, 0.75, 0.6]) * d   # three.js camera frame: y up
    # The floor: MeshCat's grid (20 m, 40 cells) scaled to a square of side GRID_SPAN * size
    # under the scene's centre, at the height of its lowest point. At 20 m it reached behind
    # the camera, and a renderer that drops the lines crossing the camera's plane (headless
    # Chromium) drew only its far part, above the robot in the picture: a ceiling.
    grid = _pose(p=[0.0, 0.0, floor - center[2]], scale=[GRID_SPAN * size / 20.0] * 3)
    cmds = [
        # the orbit target is the world origin: move the scene so that its centre is there
        # (no rotation for "/Grid": the viewer turns its grid into the x-y plane with
        # Rx(π/2) on the object "/Grid/<object>", which a transform of the node "/Grid"
        # composes with -- adding that turn here again would stand the grid up vertically.)
        set_transform_command(ROOT, shift), set_transform_command("/Grid", grid),
        set_transform_command("/Axes", shift),
        {"type": "set_property", "path": "/Cameras/default/rotated/<object>", "property": "position",
         "value": [_r(v) for v in eye]},
    ]
    if not scene.options.grid:
        cmds.append({"type": "set_property", "path": "/Grid", "property": "visible", "value": False})
    for it in scene.items:
        if isinstance(it, ChainItem):
            cmds += chain_commands(it, L)
        elif isinstance(it, TargetItem):
            size = it.size or 0.18 * L
            path = f"{ROOT}/{it.name}"
            cmds += _triad_commands(path, size, label=it.label)
            cmds.append(_set_object(f"{path}/origin", _object(f"{path}/origin", _sphere(size / 12),
                                                               _material("MeshPhongMaterial", TARGET_COLOR))))
            cmds.append(set_transform_command(path, it.T))
        elif isinstance(it, PointsItem) and len(it.points) > SPHERES_UP_TO:
            path = f"{ROOT}/{it.name}"
            cmds.append(_set_object(path, _point_cloud(path, it.points, it.color, 2 * (it.radius or 0.02 * L))))
        elif isinstance(it, PointsItem):
            radius = it.radius or 0.02 * L
            for k, p in enumerate(it.points):
                path = f"{ROOT}/{it.name}/{k}"
                cmds.append(_set_object(path, _object(path, _sphere(radius),
                                                      _material("MeshPhongMaterial", it.color))))
                cmds.append(set_transform_command(path, _pose(p=p)))
        elif isinstance(it, PathItem):
            path = f"{ROOT}/{it.name}"
            cmds.append(_set_object(path, _line(path, it.points, it.color)))
        elif isinstance(it, EllipsoidItem):
            path = f"{ROOT}/{it.name}"
            sphere = {"type": "SphereGeometry", "radius": 1.0, "widthSegments": 32, "heightSegments": 16}
            cmds.append(_set_object(path, _object(path, sphere, _material("MeshPhongMaterial", it.color,
                                                                          it.opacity))))
            cmds.append(set_transform_command(path, ellipsoid_transform(it.center, it.radii, it.axes)))
    for anim in scene.animations:
        if anim.trace:
            cmds += _trace_commands(scene, anim)
    anim_cmd = animation_command(scene)
    if anim_cmd is not None:
        cmds.append(anim_cmd)
    return cmds
