"""DART worlds from the IR: table, shapes, mass properties, physical joints."""

from __future__ import annotations

import numpy as np
import pytest
from sim_bodies import HANDMADE, q, stdlib_body, v

from vkgl.errors import InputError
from vkgl.lang.ir.nodes import Body, BoxShape, CylinderShape, Joint, Pose, ShapePart, Table, UnionShape
from vkgl.shapes import dart_shapes
from vkgl.sim import world as sim_world


def settle(world, seconds: float) -> None:
    for _ in range(round(seconds / world.getTimeStep())):
        world.step()


def test_a_block_rests_on_the_table_top_at_z_zero() -> None:
    world = sim_world.new_world()
    sim_world.add_table(world)
    _, node = sim_world.add_body(world, "block", stdlib_body("Block"), sim_world.translation(np.array([0, 0, 0.025])))
    settle(world, 0.5)
    assert node.getWorldTransform().translation() == pytest.approx([0.0, 0.0, 0.025], abs=2e-4)


def test_a_scene_table_has_its_top_where_the_scene_says() -> None:
    world = sim_world.new_world()
    table = Table(size=v(1.6, 1.2), position=v(0.5, 0.0, 0.1))
    sim_world.add_table(world, table)
    cylinder = Body(name="Can", shape=CylinderShape(radius=q(0.03), height=q(0.1)), mass=q(0.2))
    _, node = sim_world.add_body(world, "can", cylinder, sim_world.translation(np.array([0.5, 0.3, 0.16])))
    settle(world, 0.5)
    assert node.getWorldTransform().translation() == pytest.approx([0.5, 0.3, 0.15], abs=5e-4)


def test_mass_properties_follow_the_declared_mass_and_the_geometry() -> None:
    mass, com, inertia = sim_world.mass_properties(stdlib_body("Block"))
    a, b, c = 0.10, 0.20, 0.05
    assert mass == 0.5 and com == pytest.approx([0, 0, 0], abs=1e-12)
    expected = 0.5 / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    assert inertia == pytest.approx(expected, rel=1e-9, abs=1e-12)


def test_a_union_puts_its_centre_of_mass_where_its_parts_are() -> None:
    union = UnionShape(
        parts=[
            ShapePart(shape=BoxShape(size=v(0.1, 0.1, 0.1)), pose=Pose(position=v(0, 0, 0))),
            ShapePart(shape=BoxShape(size=v(0.1, 0.1, 0.1)), pose=Pose(position=v(0.3, 0, 0))),
        ]
    )
    _mass, com, _ = sim_world.mass_properties(Body(name="Dumbbell", shape=union, mass=q(2.0)))
    assert com == pytest.approx([0.15, 0.0, 0.0], abs=1e-9)
    assert len(dart_shapes(union)) == 2


def test_a_revolute_joint_turns_the_body_about_the_line_it_declares() -> None:
    world = sim_world.new_world()
    door = stdlib_body("Door")
    skeleton, node = sim_world.add_body(world, "door", door, np.eye(4))
    joint = skeleton.getJoint(0)
    assert joint.getPositionUpperLimit(0) == pytest.approx(np.pi / 2)
    skeleton.setPositions([np.pi / 2])
    hinge = node.getWorldTransform().matrix() @ np.array([0.0, -0.20, 0.0, 1.0])
    assert hinge[:3] == pytest.approx([0.0, -0.20, sim_world.JOINT_CLEARANCE], abs=1e-12)
    corner = node.getWorldTransform().matrix() @ np.array([0.0, 0.20, 0.0, 1.0])
    assert corner[:2] == pytest.approx([0.40, -0.20], abs=1e-12)  # swung a quarter turn, about -z


def test_reversed_joint_limits_are_an_input_error() -> None:
    drawer = HANDMADE["Drawer"]()
    bad = drawer.model_copy(update={"joint": Joint(type="prismatic", axis=v(1, 0, 0), lower=q(0.3), upper=q(0.0))})
    with pytest.raises(InputError, match="reversed"):
        sim_world.add_body(sim_world.new_world(), "drawer", bad, np.eye(4))


@pytest.mark.parametrize("name", sorted(HANDMADE))
def test_the_handmade_test_bodies_are_the_stdlib_bodies(name: str) -> None:
    assert stdlib_body(name) == HANDMADE[name]()


def _slid_block(tolerance: float | None) -> np.ndarray:
    """Where the stdlib Block ends after sliding from 0.5 m/s at a heading of 30 deg until friction stops it (2.5 cm),
    its four corners on the table (a slide is where the friction-cone solver's sweeps run longest)."""
    world = sim_world.new_world(tolerance=tolerance)
    sim_world.add_table(world)
    skeleton, node = sim_world.add_body(
        world, "block", stdlib_body("Block"), sim_world.translation(np.array([0, 0, 0.025]))
    )
    settle(world, 0.05)
    velocities = np.zeros(6)
    velocities[3:5] = 0.5 * np.cos(np.pi / 6), 0.5 * np.sin(np.pi / 6)  # a free joint's linear part, in the body frame
    skeleton.setVelocities(velocities)
    settle(world, 0.2)
    return node.getWorldTransform().matrix()


def test_a_looser_stop_of_the_solver_slides_a_block_as_far_as_dart_s_default() -> None:
    """`new_world(tolerance=)` stops the solver's sweeps where asked: at 1e-4 a straight slide ends within hundredths
    of a millimetre of DART's 1e-5 (bench/sim/bench_step.py; a crate turned about its arc did not, so every world
    keeps DART's: vkgl.sim.world.EXECUTION_SOLVER_TOLERANCE)."""
    default = _slid_block(None)
    loose = _slid_block(1e-4)
    assert np.linalg.norm(default[:3, 3]) > 0.02  # it really slid (0.5 m/s against a friction of 0.5 g)
    assert np.linalg.norm(default[:3, 3] - loose[:3, 3]) < 1e-4
    assert np.abs(default[:3, :3] - loose[:3, :3]).max() < 1e-3
