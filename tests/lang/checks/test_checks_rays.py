"""The checks of contact points and contact frames (E415) give the explorer's answers without trimesh.

`vkgl.lang.checks.geometry.rays` triangulates boxes, cylinders and their unions as trimesh does and runs
`vkgl.lang.ir.geometry.ray_hit`'s test on them in plain floats. These tests hold it to the explorer's own
functions on the trimesh mesh (`face_line`, `at_heights`, `surface_point`, `ray_hit`: vkgl/sim/policy.py finds
contact points with them): the same triangles, the same hits, the same first missing contact point of a face
and the same words about a contact frame, on the stdlib's bodies and on random unions. Positions and sizes
on a centimetre grid make coincident faces, rays along edges and contact points on a part's border common.
"""

from __future__ import annotations

import math
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import vkgl
from vkgl.lang.checks.explore import contact_frame_problem, first_miss
from vkgl.lang.checks.geometry.rays import MeshSurface, Triangles, shape_surface
from vkgl.lang.ir import geometry
from vkgl.lang.ir.nodes import BoxShape, CylinderShape, Pose, Quantity, Shape, ShapePart, UnionShape, Vector

REPO = Path(__file__).resolve().parents[3]

CM = st.integers(-25, 25).map(lambda v: v / 100)
SIZE = st.integers(1, 30).map(lambda v: v / 100)
FREE = st.floats(-0.25, 0.25, allow_nan=False)
TURN = st.one_of(
    st.none(),
    st.sampled_from([0.0, math.pi / 2, math.pi, -math.pi / 2]).map(lambda a: {"yaw": Quantity(value=a)}),
    st.floats(-math.pi, math.pi).map(lambda a: {"yaw": Quantity(value=a)}),
    st.tuples(st.floats(-1.5, 1.5), st.floats(-1.5, 1.5), st.floats(-1.5, 1.5)).map(
        lambda v: {"rpy": Vector(values=v)}
    ),
)


@st.composite
def _piece(draw: st.DrawFn) -> BoxShape | CylinderShape:
    if draw(st.integers(0, 4)) == 0:
        return CylinderShape(radius=Quantity(value=draw(SIZE) / 2), height=Quantity(value=draw(SIZE)))
    return BoxShape(size=Vector(values=(draw(SIZE), draw(SIZE), draw(SIZE))))


@st.composite
def _union(draw: st.DrawFn, depth: int = 0) -> UnionShape:
    parts = []
    for _ in range(draw(st.integers(1, 4))):
        inner = draw(_union(depth + 1)) if depth == 0 and draw(st.integers(0, 5)) == 0 else draw(_piece())
        position = draw(st.tuples(CM, CM, CM) | st.tuples(FREE, FREE, FREE))
        turn = draw(TURN) or {}
        pose = Pose(position=Vector(values=position), **turn)  # type: ignore[arg-type]
        parts.append(ShapePart(shape=inner, pose=pose))
    return UnionShape(parts=parts)


DIRECTIONS = st.one_of(
    st.sampled_from([(1.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)]),
    st.tuples(FREE, FREE, FREE).filter(lambda v: math.hypot(*v) > 1e-3).map(lambda v: _unit(v)),
)


def _unit(v: tuple[float, float, float]) -> tuple[float, float, float]:
    n = math.hypot(*v)
    return (v[0] / n, v[1] / n, v[2] / n)


@cache
def _stdlib_shapes() -> list[Shape]:
    return [
        body.shape for path in sorted((REPO / "stdlib").rglob("*.vkg")) for body in vkgl.compile(path).bodies.values()
    ]


def _mesh_surface(shape: Shape) -> MeshSurface:
    return MeshSurface(geometry.shape_mesh(shape))


def _same_triangles(shape: Shape) -> None:
    plain = shape_surface(shape)
    assert plain is not None
    mesh = geometry.shape_mesh(shape)
    assert np.allclose(np.array(plain.triangles), mesh.triangles, rtol=0, atol=1e-15)
    assert np.allclose(np.array(plain.normals), mesh.face_normals, rtol=0, atol=1e-12)
    assert np.allclose(np.array(plain.bounds), mesh.bounds, rtol=0, atol=1e-15)


def test_the_stdlibs_bodies_are_trimeshs_triangles() -> None:
    shapes = [s for s in _stdlib_shapes() if shape_surface(s) is not None]
    assert any(isinstance(s, UnionShape) for s in shapes)
    for shape in shapes:
        _same_triangles(shape)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(_union())
def test_a_union_is_trimeshs_triangles(shape: UnionShape) -> None:
    _same_triangles(shape)


@settings(max_examples=150, deadline=None, derandomize=True)
@given(_union(), st.tuples(CM, CM, CM) | st.tuples(FREE, FREE, FREE), DIRECTIONS)
@example(  # onto the vertical edge of a cylinder's mesh at angle 0: two triangles at one distance
    UnionShape(
        parts=[
            ShapePart(
                shape=CylinderShape(radius=Quantity(value=0.005), height=Quantity(value=0.01)),
                pose=Pose(position=Vector(values=(0.0, 0.0, 0.0))),
            )
        ]
    ),
    (0.01, 0.0, 0.0),
    (-1.0, 0.0, 0.0),
)
def test_a_ray_meets_what_trimeshs_mesh_meets(
    shape: UnionShape, start: tuple[float, float, float], direction: tuple[float, float, float]
) -> None:
    plain = shape_surface(shape)
    assert plain is not None
    ours = plain.ray_hit(start, direction)
    theirs = geometry.ray_hit(geometry.shape_mesh(shape), np.array(start), np.array(direction))
    assert (ours is None) == (theirs is None)
    if ours is not None and theirs is not None:
        assert np.allclose(ours[0], theirs[0], rtol=0, atol=1e-12)
        # on an edge or a corner the ray meets two or more triangles at one distance, equal to the last bits or
        # nearly: numpy's sums and Python's round it differently, so either may take another of them (a ray
        # along -x onto a cylinder's vertical edge at angle 0). Any of those triangles' normals is the answer.
        assert any(np.allclose(ours[1], normal, rtol=0, atol=1e-9) for normal in _tied_normals(shape, start, direction))


def _tied_normals(shape: UnionShape, start: tuple[float, float, float], direction: tuple[float, float, float]):
    """The normals of the mesh's triangles the ray meets within 1e-12 m of the nearest (trimesh's test)."""
    import trimesh  # here: tests/lang/ir/test_geometry_vertices.py asserts that checking imports no trimesh

    mesh = geometry.shape_mesh(shape)
    ray = np.array(direction)
    facing = np.abs(mesh.face_normals @ ray) > 1e-12
    triangles, normals = mesh.triangles[facing], mesh.face_normals[facing]
    distance = np.einsum("ij,ij->i", triangles[:, 0] - np.array(start), normals) / (normals @ ray)
    points = np.array(start) + distance[:, None] * ray
    inside = (distance > 0) & np.all(trimesh.triangles.points_to_barycentric(triangles, points) >= -1e-9, axis=1)
    nearest = distance[inside].min()
    return normals[inside & (distance <= nearest + 1e-12)]


FACES = st.sampled_from(["+x", "-x", "+y", "-y", "+z"])


@settings(max_examples=80, deadline=None, derandomize=True)
@given(_union(), FACES, st.integers(1, 12), st.integers(1, 4))
def test_the_first_missing_contact_point_is_the_explorers(
    shape: UnionShape, face: str, steps: int, heights: int
) -> None:
    ours = first_miss(shape_surface(shape), face, steps, heights)  # type: ignore[arg-type]
    _same_miss(ours, _explorers_first_miss(shape, face, steps, heights))
    _same_miss(ours, first_miss(_mesh_surface(shape), face, steps, heights))


def _same_miss(ours: tuple[int, float, int, float] | None, theirs: tuple[int, float, int, float] | None) -> None:
    """The same contact point (index, axis) at the same height and place, to rounding (a turned part's
    corners may differ from trimesh's in the last bit)."""
    assert (ours is None) == (theirs is None)
    if ours is not None and theirs is not None:
        assert (ours[0], ours[2]) == (theirs[0], theirs[2])
        assert math.isclose(ours[1], theirs[1], abs_tol=1e-12) and math.isclose(ours[3], theirs[3], abs_tol=1e-12)


def _explorers_first_miss(shape: Shape, face: str, steps: int, heights: int) -> tuple[int, float, int, float] | None:
    """vkgl/sim/policy.py's contact points on the trimesh mesh: the first whose ray meets nothing."""
    mesh = geometry.shape_mesh(shape)
    outward = geometry.FACES[face]
    line_axis, points = geometry.face_line(mesh, outward, steps)
    along = int(np.argmax(line_axis))
    for k, height, point in geometry.at_heights(mesh, points, heights):
        if geometry.surface_point(mesh, point, outward) is None:
            return k, height, along, float(point[along])
    return None


@settings(max_examples=150, deadline=None, derandomize=True)
@given(_union(), st.tuples(CM, CM, CM) | st.tuples(FREE, FREE, FREE), DIRECTIONS)
def test_a_contact_frame_gets_the_same_words(
    shape: UnionShape, origin: tuple[float, float, float], x: tuple[float, float, float]
) -> None:
    plain = shape_surface(shape)
    assert plain is not None
    assert contact_frame_problem(plain, origin, x) == contact_frame_problem(_mesh_surface(shape), origin, x)


@pytest.mark.parametrize("face", ["+x", "-x", "+y", "-y", "+z"])
def test_the_stdlibs_contact_points_are_the_explorers(face: str) -> None:
    for shape in _stdlib_shapes():
        plain = shape_surface(shape)
        if plain is not None:
            for steps, heights in ((1, 1), (9, 1), (5, 3)):
                _same_miss(first_miss(plain, face, steps, heights), _explorers_first_miss(shape, face, steps, heights))


def test_a_surface_with_no_triangle_in_the_way_is_missed() -> None:
    box = Triangles(shape_surface(BoxShape(size=Vector(values=(0.1, 0.1, 0.1)))).triangles)  # type: ignore[union-attr]
    assert box.ray_hit((1.0, 0.0, 0.0), (1.0, 0.0, 0.0)) is None  # it lies behind the ray
    hit = box.ray_hit((1.0, 0.0, 0.0), (-1.0, 0.0, 0.0))
    assert hit is not None and np.allclose(hit[0], (0.05, 0.0, 0.0), rtol=0, atol=1e-15) and hit[1] == (1.0, 0.0, 0.0)
