"""Bodies as convex solids in the world, for the scene checks (vkgl/lang/checks/geometry/scene.py).

A body's shape becomes a list of convex pieces: a box is one piece, exact; a
cylinder is a 64-sided prism (inscribed: within 0.12 % of its radius); a union
gives the pieces of its parts; a mesh gives the convex hull of each of its
connected parts (so a concave mesh, a bowl, counts as filled). Two convex
pieces overlap by their penetration depth, found exactly with the separating
axis test (face normals of both and cross products of their edge directions).

Also here: the base of a robot, read from the first link of its URDF.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from vkgl.lang.ir import nodes as ir
from vkgl.rotations import rpy_matrix, yaw_matrix

CYLINDER_SIDES = 64
BASE_RADIUS = 0.10
"""m: a robot whose URDF's first link has no box, cylinder or sphere collision is taken as a
vertical cylinder of this radius (and height) around its `at` position."""


@dataclass(frozen=True)
class Piece:
    """A convex polytope: its vertices (n, 3), unit face normals (m, 3) and unit edge directions (k, 3)."""

    vertices: np.ndarray
    normals: np.ndarray
    edges: np.ndarray

    @property
    def low(self) -> np.ndarray:
        """The lowest corner of the piece's axis-aligned bounds (computed once)."""
        if "_low" not in self.__dict__:
            object.__setattr__(self, "_low", self.vertices.min(axis=0))
        return np.asarray(self.__dict__["_low"])

    @property
    def high(self) -> np.ndarray:
        """The highest corner of the piece's axis-aligned bounds (computed once)."""
        if "_high" not in self.__dict__:
            object.__setattr__(self, "_high", self.vertices.max(axis=0))
        return np.asarray(self.__dict__["_high"])

    def moved(self, pose: np.ndarray) -> Piece:
        """The piece under the rigid transform `pose` (4x4)."""
        rotation = pose[:3, :3]
        return Piece(self.vertices @ rotation.T + pose[:3, 3], self.normals @ rotation.T, self.edges @ rotation.T)


def _box(size: np.ndarray) -> Piece:
    half = np.asarray(size, dtype=float) / 2
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float) * half
    return Piece(corners, np.eye(3), np.eye(3))


def _prism(radius: float, height: float) -> Piece:
    angles = 2 * np.pi * np.arange(CYLINDER_SIDES) / CYLINDER_SIDES
    ring = np.stack([radius * np.cos(angles), radius * np.sin(angles)], axis=1)
    vertices = np.vstack([np.c_[ring, np.full(len(ring), -height / 2)], np.c_[ring, np.full(len(ring), height / 2)]])
    mid = angles + np.pi / CYLINDER_SIDES
    sides = np.c_[np.cos(mid), np.sin(mid), np.zeros(len(mid))][: CYLINDER_SIDES // 2]
    rims = np.c_[-np.sin(mid), np.cos(mid), np.zeros(len(mid))][: CYLINDER_SIDES // 2]
    up = np.array([[0.0, 0.0, 1.0]])
    return Piece(vertices, np.vstack([sides, up]), np.vstack([rims, up]))


def _hull(points: np.ndarray) -> Piece:
    """The convex hull of `points` as a piece (its faces' normals and edges, duplicates dropped)."""
    import trimesh

    hull = trimesh.convex.convex_hull(points)
    edges = hull.vertices[hull.edges_unique[:, 1]] - hull.vertices[hull.edges_unique[:, 0]]
    return Piece(np.asarray(hull.vertices), _unique_directions(hull.face_normals), _unique_directions(edges))


def _unique_directions(vectors: np.ndarray) -> np.ndarray:
    """Unit vectors, one per direction up to sign (rounded to 1e-6)."""
    lengths = np.linalg.norm(vectors, axis=1)
    units = vectors[lengths > 1e-12] / lengths[lengths > 1e-12, None]
    flip = np.sign(units[np.arange(len(units)), np.argmax(np.abs(units), axis=1)])
    units = units * flip[:, None]
    _, keep = np.unique(np.round(units, 6), axis=0, return_index=True)
    return units[np.sort(keep)]


def shape_pieces(shape: ir.Shape) -> list[Piece] | None:
    """The convex pieces of `shape` in the body frame, or None when the shape is not valid (its error is reported)."""
    if isinstance(shape, ir.BoxShape):
        size = np.asarray(shape.size.values, dtype=float)
        return [_box(size)] if len(size) == 3 and _positive(*size) else None
    if isinstance(shape, ir.CylinderShape):
        r, h = shape.radius.value, shape.height.value
        return [_prism(r, h)] if _positive(r, h) else None
    if isinstance(shape, ir.UnionShape):
        pieces: list[Piece] = []
        for part in shape.parts:
            inner = shape_pieces(part.shape)
            pose = _matrix(part.pose)
            if inner is None or pose is None:
                return None
            pieces += [p.moved(pose) for p in inner]
        return pieces or None
    if isinstance(shape, ir.MeshShape):
        return _mesh_pieces(shape)
    return None


def _mesh_pieces(shape: ir.MeshShape) -> list[Piece] | None:
    from vkgl.lang.ir.geometry import shape_mesh

    try:
        mesh = shape_mesh(shape)
        parts = mesh.split(only_watertight=False) or [mesh]
        pieces = [_hull(np.asarray(part.vertices)) for part in parts if len(part.vertices) >= 4]
    except Exception:  # unreadable or degenerate: the body checks report the file (E503)
        return None
    return pieces or None  # no solid part (a flat mesh): reported as E503


def _positive(*values: float) -> bool:
    return all(math.isfinite(v) and v > 0 for v in values)


def _matrix(pose: ir.Pose) -> np.ndarray | None:
    """The pose's 4x4 matrix, or None when a value is not finite or a vector has the wrong number of components
    (its error is reported)."""
    try:
        with np.errstate(all="ignore"):
            matrix = pose.matrix()
    except ValueError:  # `at (0, 0, 0.7, 0) m`: E204, reported by the builder
        return None
    return matrix if np.all(np.isfinite(matrix)) else None


def pose_matrix(pose: ir.Pose) -> np.ndarray | None:
    """`pose` as a 4x4 matrix, or None when a value is not finite."""
    return _matrix(pose)


# ---------------------------------------------------------------- overlaps


def _axes(a: Piece, b: Piece) -> np.ndarray:
    cross = np.cross(a.edges[:, None, :], b.edges[None, :, :]).reshape(-1, 3)
    lengths = np.linalg.norm(cross, axis=1)
    keep = lengths > 1e-9
    return np.vstack([a.normals, b.normals, cross[keep] / lengths[keep, None]])


def depth(a: Piece, b: Piece) -> float:
    """How deep two convex pieces interpenetrate, m (the shortest push that separates them); <= 0 when apart."""
    axes = _axes(a, b)
    pa, pb = a.vertices @ axes.T, b.vertices @ axes.T
    overlap = np.minimum(pa.max(axis=0), pb.max(axis=0)) - np.maximum(pa.min(axis=0), pb.min(axis=0))
    return float(overlap.min())


def pieces_depth(a: list[Piece], b: list[Piece]) -> float:
    """The deepest interpenetration of any piece of `a` with any piece of `b`, m (<= 0: apart or touching)."""
    best = -math.inf
    for pa in a:
        for pb in b:
            gap = float(np.min(np.minimum(pa.high, pb.high) - np.maximum(pa.low, pb.low)))
            if gap <= best:
                continue  # their boxes already overlap less than the deepest found
            best = max(best, depth(pa, pb))
    return best


def footprint_overlap(a: list[Piece], b: list[Piece]) -> float:
    """How far the shadows of two sets of pieces on the table overlap, m (<= 0: they do not)."""
    best = -math.inf
    for pa in a:
        for pb in b:
            edges = np.vstack([pa.edges, pb.edges])[:, :2]
            lengths = np.linalg.norm(edges, axis=1)
            keep = lengths > 1e-9
            axes = np.c_[-edges[keep, 1], edges[keep, 0]] / lengths[keep, None]
            if len(axes) == 0:
                continue
            qa, qb = pa.vertices[:, :2] @ axes.T, pb.vertices[:, :2] @ axes.T
            overlap = np.minimum(qa.max(axis=0), qb.max(axis=0)) - np.maximum(qa.min(axis=0), qb.min(axis=0))
            best = max(best, float(overlap.min()))
    return best


def bounds(pieces: list[Piece]) -> tuple[np.ndarray, np.ndarray]:
    """The axis-aligned box around `pieces`: (low, high) corners."""
    if len(pieces) == 1:
        return pieces[0].low, pieces[0].high
    return np.min([p.low for p in pieces], axis=0), np.max([p.high for p in pieces], axis=0)


def yawed(pieces: list[Piece], yaw: float, position: np.ndarray) -> list[Piece]:
    """`pieces` (given about their body's origin) turned by `yaw` about z and moved to `position`."""
    pose = np.eye(4)
    pose[:3, :3] = yaw_matrix(yaw)
    pose[:3, 3] = position
    return [p.moved(pose) for p in pieces]


# ---------------------------------------------------------------- robot bases


def robot_base(robot: ir.Robot, pose: np.ndarray) -> list[Piece]:
    """The solid base of a robot placed at `pose`: the collision boxes, cylinders and spheres of its URDF's
    first link (the link no joint moves), else a vertical cylinder of radius and height `BASE_RADIUS`."""
    local = _urdf_base(robot.urdf_resolved or robot.urdf)
    if not local:
        lift = np.eye(4)
        lift[2, 3] = BASE_RADIUS / 2
        local = (_prism(BASE_RADIUS, BASE_RADIUS).moved(lift),)
    return [p.moved(pose) for p in local]


@lru_cache(maxsize=16)
def _urdf_base(path: str) -> tuple[Piece, ...]:
    try:
        root = ET.parse(path).getroot() if Path(path).is_file() else None
    except ET.ParseError:
        return ()
    if root is None or root.tag != "robot":
        return ()
    children = {child.get("link") for joint in root.iter("joint") for child in joint.iter("child")}
    first = next((link for link in root.iter("link") if link.get("name") not in children), None)
    if first is None:
        return ()
    pieces = []
    for collision in first.iter("collision"):
        piece = _urdf_piece(collision)
        if piece is not None:
            pieces.append(piece)
    return tuple(pieces)


def _urdf_piece(collision: ET.Element) -> Piece | None:
    try:
        origin = collision.find("origin")
        xyz = [float(v) for v in (origin.get("xyz", "0 0 0") if origin is not None else "0 0 0").split()]
        roll, pitch, yaw = [float(v) for v in (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split()]
        pose = np.eye(4)
        pose[:3, :3] = rpy_matrix(roll, pitch, yaw)
        pose[:3, 3] = xyz
        geometry = collision.find("geometry")
        shape = geometry[0] if geometry is not None and len(geometry) else None
        if shape is None or not np.all(np.isfinite(pose)):
            return None
        if shape.tag == "box":
            size = np.array([float(v) for v in shape.get("size", "").split()])
            return _box(size).moved(pose) if len(size) == 3 and _positive(*size) else None
        if shape.tag == "cylinder":
            r, h = float(shape.get("radius", "nan")), float(shape.get("length", "nan"))
            return _prism(r, h).moved(pose) if _positive(r, h) else None
        if shape.tag == "sphere":
            r = float(shape.get("radius", "nan"))
            return _prism(r, 2 * r).moved(pose) if _positive(r) else None  # a sphere's enclosing cylinder
    except (ValueError, IndexError):
        return None
    return None
