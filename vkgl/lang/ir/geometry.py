"""Geometry of bodies: shapes as trimesh meshes, and where scene bodies stand.

Shared by the simulator (collision shapes, mass properties) and the planner
(footprints, resting poses), so both see the same body.

trimesh is imported where a mesh is made: its import (with networkx and
SciPy's image module) costs about a third of a second, and the planner only
needs the vertices of boxes and unions of boxes (`shape_vertices`, the same
numbers as the meshes' without making them).
"""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

from vkgl.errors import InputError
from vkgl.lang.ir.mesh_limits import file_too_large, too_many_faces
from vkgl.lang.ir.nodes import JOINT_LIFT as JOINT_LIFT  # defined there: the scene checks read it without numpy
from vkgl.lang.ir.nodes import (
    Body,
    BoxShape,
    CylinderShape,
    Joint,
    MeshShape,
    Scene,
    SceneBody,
    Shape,
    UnionShape,
)
from vkgl.rotations import matrix_rotvec, rotvec_matrix, yawed_points

if TYPE_CHECKING:
    import trimesh


def lifted(pose: np.ndarray, lift: float = JOINT_LIFT) -> np.ndarray:
    """`pose` raised by `lift` along the world's z: where a body on a joint placed at `pose` really is."""
    out = np.array(pose, dtype=float)
    out[2, 3] += lift
    return out


def shape_mesh(shape: Shape) -> trimesh.Trimesh:
    """The shape as one triangle mesh in the body frame (SI units)."""
    return _shape_mesh_cached(shape).copy()


@lru_cache(maxsize=256)
def _shape_mesh_cached(shape: Shape) -> trimesh.Trimesh:
    import trimesh

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
        merged = trimesh.util.concatenate(parts)
        assert isinstance(merged, trimesh.Trimesh)  # concatenating meshes gives a mesh
        return merged
    raise TypeError(f"unknown shape {shape!r}")


def _load_mesh(shape: MeshShape) -> trimesh.Trimesh:
    import trimesh

    path = shape.resolved or shape.path
    refused = file_too_large(path)
    if refused is not None:
        raise InputError(f"{path}: cannot use mesh: {refused}")
    try:
        loaded = trimesh.load(path, force="mesh")
    except Exception as exc:  # trimesh raises many types; we say which file and why
        raise InputError(f"{path}: cannot read mesh: {exc}") from exc
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise InputError(f"{path}: the file holds no triangles")
    refused = too_many_faces(len(loaded.faces))
    if refused is not None:
        raise InputError(f"{path}: cannot use mesh: {refused}")
    loaded.apply_scale(shape.scale)
    return loaded


def shape_vertices(shape: Shape) -> np.ndarray:
    """The vertices of `shape_mesh(shape)` (body frame), read-only: no copy of the mesh when only they are needed."""
    return _shape_vertices_cached(shape)


@lru_cache(maxsize=256)
def _shape_vertices_cached(shape: Shape) -> np.ndarray:
    vertices = _box_vertices(shape)
    if vertices is None:
        vertices = np.array(_shape_mesh_cached(shape).vertices, dtype=float)
    vertices.flags.writeable = False
    return vertices


_UNIT_BOX = np.array([[0, 0, 0], [0, 0, 1], [0, 1, 0], [0, 1, 1], [1, 0, 0], [1, 0, 1], [1, 1, 0], [1, 1, 1]], float)
_IDENTITY4 = np.eye(4)


def _box_vertices(shape: Shape) -> np.ndarray | None:
    """The vertices of the mesh of a box or a union of boxes, computed as trimesh computes them (its box's
    corners, `apply_transform` per part, parts stacked in order), without trimesh; None for other shapes."""
    if isinstance(shape, BoxShape):
        return (_UNIT_BOX - 0.5) * np.asarray(shape.size.values, dtype=np.float64)
    if not isinstance(shape, UnionShape):
        return None
    parts = []
    for part in shape.parts:
        vertices = _box_vertices(part.shape)
        if vertices is None:
            return None
        matrix = np.asarray(part.pose.matrix(), order="C", dtype=np.float64)
        if float(np.ptp(matrix - _IDENTITY4)) >= 1e-8 and np.abs(matrix - _IDENTITY4).max() >= 1e-8:
            vertices = np.dot(matrix, np.column_stack((vertices, np.ones(len(vertices)))).T).T[:, :3]
        parts.append(vertices)
    return np.vstack(parts)


def body_mesh(body: Body) -> trimesh.Trimesh:
    """The body's shape as a mesh in its own frame."""
    return shape_mesh(body.shape)


def resting_height(body: Body, yaw: float, table_top: float) -> float:
    """The z of the body frame when the body, turned by `yaw`, rests on a table top at `table_top`."""
    rotated = yawed_points(yaw, shape_vertices(body.shape))
    return float(table_top - rotated[:, 2].min())


def scene_body_pose(scene: Scene, scene_body: SceneBody, body: Body) -> np.ndarray:
    """The 4x4 world pose where a scene body starts.

    `on table at (x, y)` puts the body's lowest point on the table top; a plain
    `at POSE` is taken as written. A body on a physical joint that starts
    `open Q` starts there with its joint at Q (`scene_body_anchor` is where it
    is placed, its joint at 0).
    """
    anchor = scene_body_anchor(scene, scene_body, body)
    if body.joint is None or scene_body.opening is None:
        return anchor
    return joint_pose(body.joint, anchor, scene_body.start_opening())


def scene_body_anchor(scene: Scene, scene_body: SceneBody, body: Body) -> np.ndarray:
    """The 4x4 world pose where a scene body is placed: where it starts, or for a body on a physical joint
    where the joint's coordinate is 0 (the joint is anchored to the world there)."""
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


def scene_table(scene: Scene) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The table's centre and size (x, y, m) in `scene`, or (None, None) without a table."""
    if scene.table is None:
        return None, None
    return np.asarray(scene.table.position.values[:2], dtype=float), np.asarray(
        scene.table.size.values[:2], dtype=float
    )


# ---------------------------------------------------------------- contact points of pushes

# The outward normals of the faces `contacts on faces ...` names, in the body frame.
FACES = {
    "+x": np.array([1.0, 0.0, 0.0]),
    "-x": np.array([-1.0, 0.0, 0.0]),
    "+y": np.array([0.0, 1.0, 0.0]),
    "-y": np.array([0.0, -1.0, 0.0]),
    "+z": np.array([0.0, 0.0, 1.0]),
    "-z": np.array([0.0, 0.0, -1.0]),
}


def face_line(mesh: trimesh.Trimesh, outward: np.ndarray, steps: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """The direction of a face's centre line and `steps` points on it, just outside the body.

    Side faces: the horizontal line at mid height; the top: the line along the
    longer horizontal side through the centre. Points sit at the centres of
    `steps` equal cells of the body's extent along the line, one body size
    outside the face (rays start there).
    """
    lo, hi = mesh.bounds
    centre = (lo + hi) / 2
    normal_axis = int(np.argmax(np.abs(outward)))
    if normal_axis == 2:
        line = 0 if hi[0] - lo[0] >= hi[1] - lo[1] else 1
    else:
        line = 1 - normal_axis  # the other horizontal axis
    direction = np.zeros(3)
    direction[line] = 1.0
    fractions = (np.arange(steps) + 0.5) / steps
    outside = centre + outward * (float(np.max(hi - lo)) + 1.0)
    points = []
    for f in fractions:
        p = outside.copy()
        p[line] = lo[line] + f * (hi[line] - lo[line])
        points.append(p)
    return direction, points


SIDE_FACES = {"+x": (0, 1.0), "-x": (0, -1.0), "+y": (1, 1.0), "-y": (1, -1.0)}
"""The side faces a push can tip a body from: (axis of the body frame, sign of the outward normal)."""


def pushed_face(direction: np.ndarray) -> str | None:
    """The side face a push along `direction` (body frame, into the body) presses, or None (the top, or none)."""
    d = np.asarray(direction, dtype=float)
    if not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0.0:
        return None
    axis = int(np.argmax(np.abs(d)))
    if axis == 2:
        return None
    outward = -float(np.sign(d[axis]))
    return next(face for face, (a, s) in SIDE_FACES.items() if a == axis and s == outward)


def at_heights(mesh: trimesh.Trimesh, points: list[np.ndarray], heights: int) -> list[tuple[int, float, np.ndarray]]:
    """A side face's contact points (`face_line`) repeated at `heights` heights: (index along the line,
    height over the body's bottom, point), lowest height first.

    The heights are the centres of `heights` equal cells of the body's height;
    with one height the points stay at mid height, exactly as `face_line` made them.
    """
    lo, hi = mesh.bounds
    if heights == 1:
        return [(k, float((hi[2] - lo[2]) / 2), p) for k, p in enumerate(points)]
    out = []
    for j in range(heights):
        up = (j + 0.5) / heights * float(hi[2] - lo[2])
        for k, p in enumerate(points):
            q = p.copy()
            q[2] = lo[2] + up
            out.append((k, up, q))
    return out


def surface_point(mesh: trimesh.Trimesh, start: np.ndarray, outward: np.ndarray) -> np.ndarray | None:
    """Where a ray from `start` along -outward first meets the body's surface, or None."""
    hit = ray_hit(mesh, start, -np.asarray(outward, dtype=float))
    return None if hit is None else hit[0]


def ray_hit(mesh: trimesh.Trimesh, start: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(point, outward normal of the triangle) where a ray from `start` along `direction` first meets the mesh.

    (trimesh's own ray queries need the optional `rtree` package; a ray against
    every triangle plane plus trimesh's barycentric test is enough for one ray.)
    """
    import trimesh

    direction = np.asarray(direction, dtype=float)
    triangles = mesh.triangles
    normals = mesh.face_normals
    facing = np.abs(normals @ direction) > 1e-12
    if not facing.any():
        return None
    triangles, normals = triangles[facing], normals[facing]
    distance = np.einsum("ij,ij->i", triangles[:, 0] - start, normals) / (normals @ direction)
    points = start + distance[:, None] * direction
    barycentric = trimesh.triangles.points_to_barycentric(triangles, points)
    inside = (distance > 0) & np.all(barycentric >= -1e-9, axis=1)
    if not inside.any():
        return None
    first = int(np.argmin(np.where(inside, distance, np.inf)))
    return np.asarray(points[first], dtype=float), np.asarray(normals[first], dtype=float)


# ---------------------------------------------------------------- physical joints


def joint_axis(joint: Joint) -> np.ndarray:
    """The joint's axis as a unit vector in the body frame."""
    axis = joint.axis.array()
    return axis / np.linalg.norm(axis)


def joint_coordinate(kind: str, axis: np.ndarray, rest: np.ndarray, pose: np.ndarray) -> float:
    """The coordinate (m or rad) of a `kind` joint with unit `axis` whose body started at `rest`, now at `pose`.

    0 at rest. Prismatic: the displacement along the axis; revolute: the
    rotation about it (its rotation vector's component, exact up to half a
    turn). Joint limits and joint goals are measured alike, by the planner
    and on an executed plan.
    """
    if kind == "prismatic":
        return float(axis @ (rest[:3, :3].T @ (pose[:3, 3] - rest[:3, 3])))
    return float(axis @ matrix_rotvec(rest[:3, :3].T @ pose[:3, :3]))


def joint_pose(joint: Joint, rest: np.ndarray, value: float) -> np.ndarray:
    """The world pose of a body that started at `rest` once its joint is at coordinate `value` (m or rad)."""
    axis = joint_axis(joint)
    moved = np.eye(4)
    if joint.type == "prismatic":
        moved[:3, 3] = value * axis
    else:
        through = joint.through.array() if joint.through is not None else np.zeros(3)
        x, y, z = (value * axis).tolist()
        moved[:3, :3] = rotvec_matrix(x, y, z)  # SciPy's `from_rotvec(...).as_matrix()`, bit for bit
        moved[:3, 3] = through - moved[:3, :3] @ through
    return rest @ moved
