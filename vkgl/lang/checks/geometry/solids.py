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
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property, lru_cache
from pathlib import Path
from typing import TYPE_CHECKING

from vkgl.lang.checks.geometry.rigid import Rigid, Vec3, finite, pose_rigid, rotate
from vkgl.lang.ir import nodes as ir
from vkgl.rotations import rpy_matrix, yaw_matrix

if TYPE_CHECKING:  # numpy only for a mesh's pieces (trimesh has imported it): `vkgc check` of boxes needs none
    import numpy as np

CYLINDER_SIDES = 64
BASE_RADIUS = 0.10
"""m: a robot whose URDF's first link has no box, cylinder or sphere collision is taken as a
vertical cylinder of this radius (and height) around its `at` position."""


@dataclass(frozen=True)
class Piece:
    """A convex polytope: its vertices, unit face normals and unit edge directions (3-tuples)."""

    vertices: tuple[Vec3, ...]
    normals: tuple[Vec3, ...]
    edges: tuple[Vec3, ...]

    @cached_property
    def low(self) -> Vec3:
        """The lowest corner of the piece's axis-aligned bounds."""
        xs, ys, zs = zip(*self.vertices, strict=True)
        return (min(xs), min(ys), min(zs))

    @cached_property
    def high(self) -> Vec3:
        """The highest corner of the piece's axis-aligned bounds."""
        xs, ys, zs = zip(*self.vertices, strict=True)
        return (max(xs), max(ys), max(zs))

    def moved(self, pose: Rigid) -> Piece:
        """The piece under the rigid transform `pose`."""
        rotation, (tx, ty, tz) = pose
        (a, b, c), (d, e, f), (g, h, i) = rotation
        return Piece(
            tuple(
                (a * x + b * y + c * z + tx, d * x + e * y + f * z + ty, g * x + h * y + i * z + tz)
                for x, y, z in self.vertices
            ),
            tuple(rotate(rotation, n) for n in self.normals),
            tuple(rotate(rotation, e) for e in self.edges),
        )

    def shifted(self, shift: Sequence[float]) -> Piece:
        """The piece moved by `shift` (no turn)."""
        sx, sy, sz = shift
        return Piece(tuple((x + sx, y + sy, z + sz) for x, y, z in self.vertices), self.normals, self.edges)


_UNIT_AXES: tuple[Vec3, ...] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def _box(size: Sequence[float]) -> Piece:
    hx, hy, hz = (float(v) / 2 for v in size)
    corners = tuple((sx * hx, sy * hy, sz * hz) for sx in (-1.0, 1.0) for sy in (-1.0, 1.0) for sz in (-1.0, 1.0))
    return Piece(corners, _UNIT_AXES, _UNIT_AXES)


def _prism(radius: float, height: float) -> Piece:
    angles = [2 * math.pi * k / CYLINDER_SIDES for k in range(CYLINDER_SIDES)]
    ring = [(radius * math.cos(a), radius * math.sin(a)) for a in angles]
    vertices = tuple((x, y, -height / 2) for x, y in ring) + tuple((x, y, height / 2) for x, y in ring)
    mid = [a + math.pi / CYLINDER_SIDES for a in angles[: CYLINDER_SIDES // 2]]
    sides = tuple((math.cos(a), math.sin(a), 0.0) for a in mid)
    rims = tuple((-math.sin(a), math.cos(a), 0.0) for a in mid)
    up = (0.0, 0.0, 1.0)
    return Piece(vertices, (*sides, up), (*rims, up))


def _hull(points: np.ndarray) -> Piece:
    """The convex hull of `points` (an array, from a mesh trimesh has loaded) as a piece."""
    import numpy as np  # trimesh, which read the mesh, has imported it
    import trimesh

    hull = trimesh.convex.convex_hull(points)
    edges = hull.vertices[hull.edges_unique[:, 1]] - hull.vertices[hull.edges_unique[:, 0]]
    normals = _unique_directions(hull.face_normals)
    return Piece(_triples(np.asarray(hull.vertices)), _triples(normals), _triples(_unique_directions(edges)))


def _triples(array: np.ndarray) -> tuple[Vec3, ...]:
    return tuple((float(x), float(y), float(z)) for x, y, z in array.tolist())


def _unique_directions(vectors: np.ndarray) -> np.ndarray:
    """Unit vectors, one per direction up to sign (rounded to 1e-6)."""
    import numpy as np

    lengths = np.linalg.norm(vectors, axis=1)
    units = vectors[lengths > 1e-12] / lengths[lengths > 1e-12, None]
    flip = np.sign(units[np.arange(len(units)), np.argmax(np.abs(units), axis=1)])
    units = units * flip[:, None]
    _, keep = np.unique(np.round(units, 6), axis=0, return_index=True)
    return units[np.sort(keep)]


def shape_pieces(shape: ir.Shape) -> list[Piece] | None:
    """The convex pieces of `shape` in the body frame, or None when the shape is not valid (its error is reported)."""
    if isinstance(shape, ir.BoxShape):
        size = shape.size.values
        return [_box(size)] if len(size) == 3 and _positive(*size) else None
    if isinstance(shape, ir.CylinderShape):
        r, h = shape.radius.value, shape.height.value
        return [_prism(r, h)] if _positive(r, h) else None
    if isinstance(shape, ir.UnionShape):
        pieces: list[Piece] = []
        for part in shape.parts:
            inner = shape_pieces(part.shape)
            pose = pose_rigid(part.pose)
            if inner is None or pose is None:
                return None
            pieces += [p.moved(pose) for p in inner]
        return pieces or None
    if isinstance(shape, ir.MeshShape):
        return _mesh_pieces(shape)
    return None


def _mesh_pieces(shape: ir.MeshShape) -> list[Piece] | None:
    from vkgl.lang.ir.geometry import shape_mesh  # trimesh and numpy: only for a body with a mesh

    try:
        mesh = shape_mesh(shape)
        parts = mesh.split(only_watertight=False) or [mesh]
        pieces = [_hull(part.vertices) for part in parts if len(part.vertices) >= 4]
    except Exception:  # unreadable or degenerate: the body checks report the file (E503)
        return None
    return pieces or None  # no solid part (a flat mesh): reported as E503


def _positive(*values: float) -> bool:
    return all(math.isfinite(v) and v > 0 for v in values)


def pose_matrix(pose: ir.Pose) -> Rigid | None:
    """`pose` as a rigid transform, or None when a value is not finite or a vector has the wrong number of
    components (its error is reported)."""
    return pose_rigid(pose)


# ---------------------------------------------------------------- overlaps


@lru_cache(maxsize=256)
def _axes(
    normals_a: tuple[Vec3, ...], edges_a: tuple[Vec3, ...], normals_b: tuple[Vec3, ...], edges_b: tuple[Vec3, ...]
) -> tuple[Vec3, ...]:
    """The separating axes of two convex pieces: their face normals and the unit cross products of their edges,
    each direction once, in the order first found.

    An axis equal to one before it, or to its exact negation, is left out: its shadows give the same overlap to
    the last bit (negating every term of a sum negates the rounded sum), and `depth` only takes an overlap lower
    than the lowest so far, so its result is the same. Two upright 64-sided prisms (cylinders) have 1122 axes
    in 37 directions: every two of their 32 horizontal rims cross into the vertical. Cached by the pieces'
    directions, which `Piece.shifted` keeps: E420's clearing move measures one moved piece hundreds of times."""
    axes: dict[Vec3, None] = dict.fromkeys((*normals_a, *normals_b))
    for ux, uy, uz in edges_a:
        for vx, vy, vz in edges_b:
            cx, cy, cz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
            length = math.sqrt(cx * cx + cy * cy + cz * cz)
            if length > 1e-9:
                axis = (cx / length, cy / length, cz / length)
                if axis not in axes and (-axis[0], -axis[1], -axis[2]) not in axes:
                    axes[axis] = None
    return tuple(axes)


def depth(a: Piece, b: Piece, floor: float = -math.inf) -> float:
    """How deep two convex pieces interpenetrate, m (the shortest push that separates them); <= 0 when apart.

    Exact when deeper than `floor`; otherwise some value at most `floor` (the axes stop being tried once one
    shows the pieces overlap no more than that)."""
    best = math.inf
    for ux, uy, uz in _axes(a.normals, a.edges, b.normals, b.edges):
        pa = [ux * x + uy * y + uz * z for x, y, z in a.vertices]
        pb = [ux * x + uy * y + uz * z for x, y, z in b.vertices]
        overlap = min(max(pa), max(pb)) - max(min(pa), min(pb))
        if overlap < best:
            best = overlap
            if best <= floor:
                break
    return best


def pieces_depth(a: list[Piece], b: list[Piece], floor: float = -math.inf) -> float:
    """The deepest interpenetration of any piece of `a` with any piece of `b`, m (<= 0: apart or touching).

    Exact when deeper than `floor`; otherwise some value at most `floor`: callers that only ask whether the
    pieces overlap by more than a tolerance pass it, and pairs apart by more are not measured. (Two convex
    pieces never overlap deeper than their bounding boxes do along an axis: the depth is the least overlap
    of their shadows over every direction. That bound holds for pieces that overlap; for pieces apart, `depth`
    is the widest gap over the pieces' own axes, which may be narrower than their boxes' gap along x, y or z, so
    boxes are compared only against a level of 0 or more: a hypothesis example had two pieces 3.1245 cm apart
    by `depth` and 3.125 cm apart by their boxes, and a floor of -3.125 cm dropped the pair.)"""
    best = -math.inf
    for pa in a:
        for pb in b:
            level = max(best, floor)
            if level >= 0.0:
                corners = zip(pa.high, pb.high, pa.low, pb.low, strict=True)
                if min(min(ha, hb) - max(la, lb) for ha, hb, la, lb in corners) <= level:
                    continue  # their boxes already overlap less than the deepest found, or than asked about
            best = max(best, depth(pa, pb, level))
    return best


def footprint_overlap(a: list[Piece], b: list[Piece]) -> float:
    """How far the shadows of two sets of pieces on the table overlap, m (<= 0: they do not)."""
    best = -math.inf
    for pa in a:
        for pb in b:
            axes = []
            for ex, ey, _ in (*pa.edges, *pb.edges):
                length = math.sqrt(ex * ex + ey * ey)
                if length > 1e-9:
                    axes.append((-ey / length, ex / length))
            if not axes:
                continue
            least = math.inf
            for ux, uy in axes:
                qa = [ux * x + uy * y for x, y, _ in pa.vertices]
                qb = [ux * x + uy * y for x, y, _ in pb.vertices]
                least = min(least, min(max(qa), max(qb)) - max(min(qa), min(qb)))
            best = max(best, least)
    return best


def bounds(pieces: list[Piece]) -> tuple[Vec3, Vec3]:
    """The axis-aligned box around `pieces`: (low, high) corners."""
    if len(pieces) == 1:
        return pieces[0].low, pieces[0].high
    lows, highs = [p.low for p in pieces], [p.high for p in pieces]
    return (
        (min(v[0] for v in lows), min(v[1] for v in lows), min(v[2] for v in lows)),
        (max(v[0] for v in highs), max(v[1] for v in highs), max(v[2] for v in highs)),
    )


def lowest(pieces: list[Piece]) -> float:
    """The lowest z of any vertex of `pieces`."""
    return min(p.low[2] for p in pieces)


def yawed(pieces: list[Piece], yaw: float, position: Sequence[float]) -> list[Piece]:
    """`pieces` (given about their body's origin) turned by `yaw` about z and moved to `position`."""
    x, y, z = position
    pose = (yaw_matrix(yaw), (float(x), float(y), float(z)))
    return [p.moved(pose) for p in pieces]


# ---------------------------------------------------------------- robot bases


def robot_base(robot: ir.Robot, pose: Rigid) -> list[Piece]:
    """The solid base of a robot placed at `pose`: the collision boxes, cylinders and spheres of its URDF's
    first link (the link no joint moves), else a vertical cylinder of radius and height `BASE_RADIUS`."""
    local = _urdf_base(robot.urdf_resolved or robot.urdf)
    if not local:
        local = (_prism(BASE_RADIUS, BASE_RADIUS).shifted((0.0, 0.0, BASE_RADIUS / 2)),)
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
        if len(xyz) != 3:
            return None
        pose = (rpy_matrix(roll, pitch, yaw), (xyz[0], xyz[1], xyz[2]))
        geometry = collision.find("geometry")
        shape = geometry[0] if geometry is not None and len(geometry) else None
        if shape is None or not finite(pose):
            return None
        if shape.tag == "box":
            size = [float(v) for v in shape.get("size", "").split()]
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
