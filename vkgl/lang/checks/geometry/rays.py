"""Rays against a body's surface in plain Python: where the checks of pushes find contact points.

The explorer (vkgl/sim/policy.py) puts a push's contact points where a ray
meets the body's trimesh mesh (`vkgl.lang.ir.geometry.face_line`, `at_heights`,
`surface_point`, `ray_hit`), and the checks of `explore` blocks must give its
answers. Importing trimesh (and SciPy with it) was two thirds of a `vkgc check`
of a drawer, so for boxes, cylinders and unions of them this module makes the
same triangles (trimesh's box and 32-sided cylinder, corner for corner and in
its order, moved as `apply_transform` moves them) and runs the same ray test on
them in plain floats: the same arithmetic, so the same hits, down to which of
two coincident faces is met first. A body with a mesh file still needs trimesh
to read it (`shape_surface` gives None for it; `MeshSurface` wraps the mesh).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import TYPE_CHECKING, Protocol

from vkgl.lang.checks.geometry.rigid import Vec3
from vkgl.lang.ir import nodes as ir

if TYPE_CHECKING:
    import trimesh

Triangle = tuple[Vec3, Vec3, Vec3]
Hit = tuple[Vec3, Vec3]
"""Where a ray meets a surface: (point, outward normal of the triangle met)."""

CYLINDER_SECTIONS = 32  # as `vkgl.lang.ir.geometry.shape_mesh` makes cylinders
_BARYCENTRIC_SLACK = 1e-9  # `ray_hit`'s: a point this far (relative) outside a triangle still hits it
_AREA_MERGE = 1e-8  # trimesh's `tol.merge`: `revolve` drops triangles of no more area

# trimesh.creation.box: its corners (of the unit cube) and its triangles, in its order.
_BOX_CORNERS = ((0, 0, 0), (0, 0, 1), (0, 1, 0), (0, 1, 1), (1, 0, 0), (1, 0, 1), (1, 1, 0), (1, 1, 1))
_BOX_TRIANGLES = (
    (1, 3, 0), (4, 1, 0), (0, 3, 2), (2, 4, 0), (1, 7, 3), (5, 1, 4),
    (5, 7, 1), (3, 7, 2), (6, 4, 2), (2, 7, 6), (6, 5, 4), (7, 5, 6),
)  # fmt: skip


class Surface(Protocol):
    """A body's surface in its own frame: its bounds and the first hit of a ray."""

    @property
    def bounds(self) -> tuple[Vec3, Vec3]:
        """The lowest and the highest corner of its axis-aligned bounds."""

    def ray_hit(self, start: Vec3, direction: Vec3) -> Hit | None:
        """Where a ray from `start` along the unit `direction` first meets the surface, or None."""


@dataclass(frozen=True)
class Triangles:
    """A surface as a list of triangles, each with its unit normal (the right-hand normal of its corners)."""

    triangles: tuple[Triangle, ...]

    @cached_property
    def normals(self) -> tuple[Vec3, ...]:
        """Unit normals as trimesh computes them: the cross product of the edges from the first corner, unitized."""
        return tuple(_unit(_cross(_sub(b, a), _sub(c, a))) for a, b, c in self.triangles)

    @cached_property
    def bounds(self) -> tuple[Vec3, Vec3]:
        """The lowest and the highest corner of the axis-aligned bounds of the corners."""
        xs, ys, zs = zip(*(p for t in self.triangles for p in t), strict=True)
        return (min(xs), min(ys), min(zs)), (max(xs), max(ys), max(zs))

    def ray_hit(self, start: Vec3, direction: Vec3) -> Hit | None:
        """`vkgl.lang.ir.geometry.ray_hit` on these triangles: the nearest triangle whose plane the ray crosses
        ahead of `start` (the first in order among equals) with the crossing inside it, barycentric slack allowed."""
        best: Hit | None = None
        nearest = math.inf
        for (a, b, c), n in zip(self.triangles, self.normals, strict=True):
            facing = _dot(n, direction)
            if not abs(facing) > 1e-12:
                continue
            distance = _dot(_sub(a, start), n) / facing
            if not (distance > 0 and distance < nearest):
                continue
            point = (
                start[0] + distance * direction[0],
                start[1] + distance * direction[1],
                start[2] + distance * direction[2],
            )
            if _inside(a, b, c, point):
                best, nearest = (point, n), distance
        return best


class MeshSurface:
    """A trimesh mesh (a body with a mesh file) as a `Surface`: `vkgl.lang.ir.geometry.ray_hit` on it."""

    def __init__(self, mesh: trimesh.Trimesh) -> None:
        self.mesh = mesh

    @property
    def bounds(self) -> tuple[Vec3, Vec3]:
        """The mesh's bounds."""
        lo, hi = self.mesh.bounds.tolist()
        return (lo[0], lo[1], lo[2]), (hi[0], hi[1], hi[2])

    def ray_hit(self, start: Vec3, direction: Vec3) -> Hit | None:
        """The mesh's first hit of the ray."""
        from vkgl.lang.ir.geometry import ray_hit

        hit = ray_hit(self.mesh, start, direction)  # type: ignore[arg-type]
        if hit is None:
            return None
        (x, y, z), (nx, ny, nz) = hit[0].tolist(), hit[1].tolist()
        return (x, y, z), (nx, ny, nz)


FACE_NORMALS: dict[str, Vec3] = {
    "+x": (1.0, 0.0, 0.0),
    "-x": (-1.0, 0.0, 0.0),
    "+y": (0.0, 1.0, 0.0),
    "-y": (0.0, -1.0, 0.0),
    "+z": (0.0, 0.0, 1.0),
    "-z": (0.0, 0.0, -1.0),
}
"""The outward normals of the faces `contacts on faces ...` names (`vkgl.lang.ir.geometry.FACES`)."""


def face_line(bounds: tuple[Vec3, Vec3], outward: Vec3, steps: int) -> tuple[int, list[Vec3]]:
    """`vkgl.lang.ir.geometry.face_line` on a surface's `bounds`: the axis of a face's centre line and `steps`
    points on it one body size outside the face (the centres of equal cells of the body's extent)."""
    lo, hi = bounds
    centre = [(a + b) / 2 for a, b in zip(lo, hi, strict=True)]
    normal_axis = max(range(3), key=lambda i: (abs(outward[i]), -i))  # numpy's argmax: the first largest
    if normal_axis == 2:
        line = 0 if hi[0] - lo[0] >= hi[1] - lo[1] else 1
    else:
        line = 1 - normal_axis  # the other horizontal axis
    size = max(b - a for a, b in zip(lo, hi, strict=True)) + 1.0
    outside = [c + n * size for c, n in zip(centre, outward, strict=True)]
    points = []
    for k in range(steps):
        p = list(outside)
        p[line] = lo[line] + (k + 0.5) / steps * (hi[line] - lo[line])
        points.append((p[0], p[1], p[2]))
    return line, points


def at_heights(bounds: tuple[Vec3, Vec3], points: list[Vec3], heights: int) -> list[tuple[int, float, Vec3]]:
    """`vkgl.lang.ir.geometry.at_heights`: the points of `face_line` at `heights` heights (index along the
    line, height over the body's bottom, point), lowest first; with one height, as they are, at mid height."""
    lo, hi = bounds
    if heights == 1:
        return [(k, (hi[2] - lo[2]) / 2, p) for k, p in enumerate(points)]
    out = []
    for j in range(heights):
        up = (j + 0.5) / heights * (hi[2] - lo[2])
        out += [(k, up, (p[0], p[1], lo[2] + up)) for k, p in enumerate(points)]
    return out


def shape_surface(shape: ir.Shape) -> Triangles | None:
    """The triangles of `shape_mesh(shape)` without trimesh, or None for a shape with a mesh file.

    Raises ValueError where making the mesh fails: a size or a part's position of the wrong length."""
    triangles = _shape_triangles(shape)
    return None if triangles is None else Triangles(triangles)


@lru_cache(maxsize=64)
def _shape_triangles(shape: ir.Shape) -> tuple[Triangle, ...] | None:
    if isinstance(shape, ir.BoxShape):
        return _box(shape.size.values)
    if isinstance(shape, ir.CylinderShape):
        return _cylinder(shape.radius.value, shape.height.value)
    if not isinstance(shape, ir.UnionShape):
        return None
    out: list[Triangle] = []
    for part in shape.parts:
        inner = _shape_triangles(part.shape)
        if inner is None:
            return None
        out += _moved(inner, part.pose)
    return tuple(out)


def _box(size: Sequence[float]) -> tuple[Triangle, ...]:
    sx, sy, sz = size
    corners = [((u - 0.5) * sx, (v - 0.5) * sy, (w - 0.5) * sz) for u, v, w in _BOX_CORNERS]
    return tuple((corners[i], corners[j], corners[k]) for i, j, k in _BOX_TRIANGLES)


def _cylinder(radius: float, height: float) -> tuple[Triangle, ...]:
    """trimesh.creation.cylinder: a profile (axis, rim, rim, axis) revolved in CYLINDER_SECTIONS slices, each
    slice's quads split in two and the ones of no area (on the axis) dropped."""
    half = abs(float(height)) / 2.0
    profile = ((0.0, -half), (radius, -half), (radius, half), (0.0, half))
    step = (2 * math.pi) / CYLINDER_SECTIONS
    rings = []
    for k in range(CYLINDER_SECTIONS):
        cos, sin = math.cos(k * step), math.sin(k * step)
        rings.append([(cos * r, sin * r, z) for r, z in profile])
    axis = (rings[0][0], rings[0][3])  # the axis points of all slices merge into slice 0's (trimesh merges vertices)
    for ring in rings:
        ring[0], ring[3] = axis

    def slice_triangles(k: int) -> list[Triangle]:
        this, after = rings[k], rings[(k + 1) % CYLINDER_SECTIONS]
        quads = []
        for j in range(3):
            quads += [(this[j], after[j], this[j + 1]), (this[j + 1], after[j], after[j + 1])]
        return quads

    kept = [i for i, t in enumerate(slice_triangles(0)) if _area(t) > _AREA_MERGE]
    return tuple(t for k in range(CYLINDER_SECTIONS) for i, t in enumerate(slice_triangles(k)) if i in kept)


def _moved(triangles: tuple[Triangle, ...], pose: ir.Pose) -> list[Triangle]:
    """The triangles under `pose.matrix()`, as trimesh's `apply_transform` moves a mesh (which leaves it
    untouched when the matrix is the identity to 1e-8)."""
    rotation = pose.rotation_matrix()
    values = [float(v) for v in pose.position.values] + [0.0] * (3 - len(pose.position.values))
    tx, ty, tz = values
    (a, b, c), (d, e, f), (g, h, i) = rotation
    matrix = (a, b, c, tx, d, e, f, ty, g, h, i, tz, 0.0, 0.0, 0.0, 1.0)
    identity = (1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)
    differences = [m - n for m, n in zip(matrix, identity, strict=True)]
    if max(differences) - min(differences) < 1e-8 or max(abs(v) for v in differences) < 1e-8:
        return list(triangles)

    def move(p: Vec3) -> Vec3:
        x, y, z = p
        return (a * x + b * y + c * z + tx, d * x + e * y + f * z + ty, g * x + h * y + i * z + tz)

    return [(move(p), move(q), move(r)) for p, q, r in triangles]


def _inside(a: Vec3, b: Vec3, c: Vec3, point: Vec3) -> bool:
    """trimesh's `points_to_barycentric` (Cramer's rule) with `ray_hit`'s slack: every coordinate >= -1e-9."""
    e0, e1, w = _sub(b, a), _sub(c, a), _sub(point, a)
    dot00, dot01, dot02 = _dot(e0, e0), _dot(e0, e1), _dot(e0, w)
    dot11, dot12 = _dot(e1, e1), _dot(e1, w)
    denominator = dot00 * dot11 - dot01 * dot01
    if denominator == 0:
        return False  # no area (numpy's division gives inf or nan there, which fail the test as well)
    inverse = 1.0 / denominator
    v = (dot00 * dot12 - dot01 * dot02) * inverse
    u = (dot11 * dot02 - dot01 * dot12) * inverse
    return v >= -_BARYCENTRIC_SLACK and u >= -_BARYCENTRIC_SLACK and 1 - u - v >= -_BARYCENTRIC_SLACK


def _area(t: Triangle) -> float:
    return math.sqrt(_dot(n := _cross(_sub(t[1], t[0]), _sub(t[2], t[0])), n)) / 2


def _sub(p: Vec3, q: Sequence[float]) -> Vec3:
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


def _dot(p: Sequence[float], q: Sequence[float]) -> float:
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]


def _cross(p: Vec3, q: Vec3) -> Vec3:
    return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])


def _unit(v: Vec3) -> Vec3:
    length = math.sqrt(_dot(v, v))
    return (v[0] / length, v[1] / length, v[2] / length) if length > 0 else (0.0, 0.0, 0.0)
