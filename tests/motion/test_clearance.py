"""The clearance bound of conservative advancement: spheres contain the links, the bound never says "clear" where the
exact check finds a collision, and a segment it passes is one the dense check passes too."""

from __future__ import annotations

import numpy as np
import pytest
from checkers.collision_shapes import box, pose
from hypothesis import given, settings
from hypothesis import strategies as st
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.motion.arm_collision import ArmCollision, Held
from vkgl.motion.clearance import cover_box, cover_cylinder, spheres_to_boxes
from vkgl.motion.collision import CollisionScene
from vkgl.motion.density import DEFAULT_RESOLUTION, link_reach, segment_is_valid
from vkgl.plan.problem.problem import build_problem

sides = st.floats(0.005, 0.4)


@settings(max_examples=60, deadline=None)
@given(size=st.tuples(sides, sides, sides), seed=st.integers(0, 2**16))
def test_a_boxs_spheres_contain_it(size: tuple[float, float, float], seed: int) -> None:
    centres, radii = cover_box(np.array(size))
    points = np.random.default_rng(seed).uniform(-0.5, 0.5, (200, 3)) * np.array(size)
    inside = np.linalg.norm(points[:, None, :] - centres[None], axis=2) <= radii[None] + 1e-12
    assert inside.any(axis=1).all()


@settings(max_examples=60, deadline=None)
@given(radius=st.floats(0.005, 0.2), height=st.floats(0.005, 0.6), seed=st.integers(0, 2**16))
def test_a_cylinders_spheres_contain_it(radius: float, height: float, seed: int) -> None:
    centres, radii = cover_cylinder(radius, height)
    rng = np.random.default_rng(seed)
    angle, r = rng.uniform(0, 2 * np.pi, 200), radius * np.sqrt(rng.uniform(0, 1, 200))
    points = np.column_stack([r * np.cos(angle), r * np.sin(angle), rng.uniform(-height / 2, height / 2, 200)])
    inside = np.linalg.norm(points[:, None, :] - centres[None], axis=2) <= radii[None] + 1e-12
    assert inside.any(axis=1).all()


def test_sphere_to_box_distances() -> None:
    boxes = (np.eye(3)[None], np.zeros((1, 3)), np.array([[0.1, 0.2, 0.3]]))
    assert spheres_to_boxes(np.array([[0.5, 0.0, 0.0]]), np.array([0.1]), boxes) == pytest.approx(0.3)
    assert spheres_to_boxes(np.array([[0.4, 0.5, 0.0]]), np.array([0.0]), boxes) == pytest.approx(np.hypot(0.3, 0.3))
    assert spheres_to_boxes(np.array([[0.0, 0.0, 0.0]]), np.array([0.05]), boxes) < 0  # inside


@pytest.fixture(scope="module")
def cluttered(compiled):
    """The b_stick_push problem's arm among its bodies and four posts around the workspace."""
    program = compiled("b_stick_push")
    problem = build_problem(program, program.task())
    shapes = {name: body.type.shape for name, body in problem.bodies.items()}
    spots = [(0.45, 0.2), (0.35, -0.25), (0.6, -0.05), (0.2, 0.4)]
    posts = {f"post{i}": pose(x, y, 0.15) for i, (x, y) in enumerate(spots)}
    shapes.update({name: box(0.06, 0.06, 0.3) for name in posts})
    scene = CollisionScene(
        shapes, table_center=problem.table_center, table_size=problem.table_size, table_z=problem.table_z
    )
    arm = ArmCollision(scene, problem.arm)
    scene.place({**{name: body.rest for name, body in problem.bodies.items()}, **posts})
    return problem, arm


def _configurations(problem, count: int, seed: int) -> np.ndarray:
    arm = problem.arm
    rng = np.random.default_rng(seed)
    return arm.home + rng.normal(0.0, 0.6, (count, len(arm.home))).clip(arm.lower - arm.home, arm.upper - arm.home)


def test_a_positive_bound_is_never_a_collision(cluttered) -> None:
    problem, arm = cluttered
    bound = arm.clearance()
    values = []
    for q in _configurations(problem, 300, 1):
        room = bound(q)
        values.append(room)
        if room > 0:
            assert arm.free(q), f"bound {room:.3f} m at a colliding configuration"
    assert min(values) <= 0 < max(values)  # both kinds were met


def test_a_positive_bound_with_a_held_stick_is_never_a_collision(cluttered) -> None:
    problem, arm = cluttered
    held = Held("stick", np.linalg.inv(problem.action("stick", "wield")), frozenset({"block"}))
    bound = arm.clearance(held)
    values = []
    for q in _configurations(problem, 300, 2):
        room = bound(q)
        values.append(room)
        if room > 0:
            assert arm.free(q, held=held)
    assert min(values) <= 0 < max(values)


def test_a_segment_conservative_advancement_passes_the_dense_check_passes(cluttered) -> None:
    problem, arm = cluttered
    advance = (arm.clearance(), link_reach(problem.arm))
    qs = [q for q in _configurations(problem, 80, 3) if arm.free(q)]
    agreed = 0
    for a, b in zip(qs[::2], qs[1::2], strict=False):
        fast = segment_is_valid(a, b, arm.free, DEFAULT_RESOLUTION, advance)
        dense = segment_is_valid(a, b, arm.free, DEFAULT_RESOLUTION)
        assert not fast or dense, "advancement passed a segment the dense check fails"
        agreed += fast == dense
    assert agreed >= len(qs) // 2 - 2  # it gives up clear segments rarely (only by sampling elsewhere)
