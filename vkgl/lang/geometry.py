"""Geometry of bodies: shapes as trimesh meshes, and where scene bodies stand.

Shared by the simulator (collision shapes, mass properties) and the planner
(footprints, resting poses), so both see the same body.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import trimesh
from scipy.spatial.transform import Rotation

from vkgl.errors import InputError
from vkgl.lang.ir import (
    Body,
    BoxShape,
    CylinderShape,
    MeshShape,
    Scene,
    SceneBody,
    Shape,
    UnionShape,
)


def shape_mesh(shape: Shape) -> trimesh.Trimesh:
    """The shape as one triangle mesh in the body frame (SI units)."""
    return _shape_mesh_cached(shape).copy()


@lru_cache(maxsize=256)
def _shape_mesh_cached(shape: Shape) -> trimesh.Trimesh:
    if isinstance(shape, BoxShape):
        return trimesh.creation.box(extents=shape.size.values)
    if isinstance(shape, CylinderShape):
        return trimesh.creation.cylinder(radius=shape.radius.value, height=shape.height.value, sections=32)
    if isinstance(shape, MeshShape):
        return _load_mesh(shape)
    if isinstance(shape, UnionShape):
        parts = []
        for part in shape.parts:
            mesh = shape_mesh(part.shape)
            mesh.apply_transform(part.pose.matrix())
            parts.append(mesh)
        return trimesh.util.concatenate(parts)
    raise TypeError(f"unknown shape {shape!r}")


def _load_mesh(shape: MeshShape) -> trimesh.Trimesh:
    path = shape.resolved or shape.path
    try:
        loaded = trimesh.load(path, force="mesh")
    except Exception as exc:  # trimesh raises many types; we say which file and why
        raise InputError(f"{path}: cannot read mesh: {exc}") from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise InputError(f"{path}: the file holds no triangles")
    loaded.apply_scale(shape.scale)
    return loaded


def body_mesh(body: Body) -> trimesh.Trimesh:
    """The body's shape as a mesh in its own frame."""
    return shape_mesh(body.shape)


def resting_height(body: Body, yaw: float, table_top: float) -> float:
    """The z of the body frame when the body, turned by `yaw`, rests on a table top at `table_top`."""
    mesh = body_mesh(body)
    rotated = Rotation.from_euler("z", yaw).apply(mesh.vertices)
    return float(table_top - rotated[:, 2].min())


def scene_body_pose(scene: Scene, scene_body: SceneBody, body: Body) -> np.ndarray:
    """The 4x4 world pose where a scene body starts.

    `on table at (x, y)` puts the body's lowest point on the table top; a plain
    `at POSE` is taken as written.
    """
    pose = scene_body.placement.pose
    matrix = pose.matrix()
    if scene_body.placement.on_table:
        top = table_top(scene)
        yaw = pose.yaw.value if pose.yaw is not None else 0.0
        matrix[2, 3] = resting_height(body, yaw, top)
    return matrix


def table_top(scene: Scene) -> float:
    """The z of the scene's table top (0 when the table gives no z)."""
    if scene.table is None:
        return 0.0
    values = scene.table.position.values
    return float(values[2]) if len(values) > 2 else 0.0
