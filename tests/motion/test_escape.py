"""The way out of a transit's room (`vkgl.motion.escape.way_out`) and transits that start inside it
(`vkgl.motion.transit_segment`): the arm's ready pose with a cupboard's door touching the side of the hand."""

from __future__ import annotations

import numpy as np
import pytest

import vkgl
from vkgl.motion import escape
from vkgl.motion.transit import TransitFailure
from vkgl.motion.transit_segment import transit_segment
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.problem.problem import build_problem

SCENE = """
use stdlib.robots.panda
use stdlib.bodies.door
use stdlib.furniture.door_cabinet

scene beside {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    cupboard : DoorCabinet on table at (0.6, Y) m yaw 180deg   # Y -0.3: the door's edge on the hand's side
    door : Door in cupboard
}

task t { scene beside goal door open 0.3 rad within 0.1 rad }
"""


def _spaces(y: float) -> tuple[GeometryCheck, dict[str, np.ndarray], np.ndarray]:
    program = vkgl.compile_source(SCENE.replace("Y", str(y)))
    problem = build_problem(program, program.tasks["t"])
    geometry = GeometryCheck(problem)
    poses = {name: body.rest for name, body in problem.bodies.items()}
    geometry.transit_collision.scene.place(poses)
    geometry.arm_collision.scene.place(poses)
    return geometry, poses, np.asarray(problem.arm.home, dtype=float)


@pytest.fixture(scope="module")
def touching() -> tuple[GeometryCheck, dict[str, np.ndarray], np.ndarray]:
    return _spaces(-0.3)


def test_the_way_out_moves_the_hand_straight_away_from_the_door_until_it_has_the_room(touching) -> None:
    geometry, _, home = touching
    room, exact = geometry.transit_collision, geometry.arm_collision
    assert exact.free(home) and not room.free(home)  # touching the door, inside the 1 cm of room
    joints = escape.way_out(room, exact, home)
    assert joints is not None
    assert np.array_equal(joints[0], home) and room.free(joints[-1])
    assert not any(room.free(q) for q in joints[:-1])  # it ends as soon as it has the room
    assert all(exact.free(q) for q in joints)
    moved = geometry.problem.arm.fk(joints[-1])[:3, 3] - geometry.problem.arm.fk(home)[:3, 3]
    assert moved[1] == pytest.approx(0.01, abs=1e-3) and abs(moved[0]) < 1e-3 and abs(moved[2]) < 1e-3  # +y


def test_a_way_along_the_door_is_refused(touching, monkeypatch) -> None:
    """Up or level along the door's face the hand would slide on it: those ways do not leave the room."""
    geometry, _, home = touching
    monkeypatch.setattr(escape, "ESCAPE_DIRECTIONS", escape.ESCAPE_DIRECTIONS[:3])  # up, back, forward
    monkeypatch.setattr(escape, "ESCAPE_DIAGONALS", ())
    assert escape.way_out(geometry.transit_collision, geometry.arm_collision, home) is None


def test_where_no_axis_leads_out_a_level_diagonal_does(touching, monkeypatch) -> None:
    """A held tool left along a face it has just turned (gen9_008 of the physical bench) gets out only slanted
    away from it: with up and the axes along the door alone, the hand leaves along the diagonal back and away
    from the door (the first of the two that lead out), as soon as it has the room, touching nothing."""
    geometry, _, home = touching
    room, exact = geometry.transit_collision, geometry.arm_collision
    monkeypatch.setattr(escape, "ESCAPE_DIRECTIONS", escape.ESCAPE_DIRECTIONS[:3])  # up, back, forward: none
    joints = escape.way_out(room, exact, home)
    assert joints is not None
    assert room.free(joints[-1]) and not any(room.free(q) for q in joints[:-1])
    assert all(exact.free(q) for q in joints)
    moved = geometry.problem.arm.fk(joints[-1])[:3, 3] - geometry.problem.arm.fk(home)[:3, 3]
    assert moved[1] > 0.009 and moved[0] == pytest.approx(-moved[1], abs=1e-3) and abs(moved[2]) < 1e-3


def test_no_way_out_where_the_hand_overlaps_the_door() -> None:
    geometry, _, home = _spaces(-0.295)  # the door 5 mm into the hand
    assert escape.way_out(geometry.transit_collision, geometry.arm_collision, home) is None


def test_a_transit_starts_inside_the_room_only_with_the_real_shapes_given(touching) -> None:
    geometry, poses, home = touching
    arm = geometry.problem.arm
    goal = arm.ik(arm.fk(home) @ _shift(0.0, 0.15, -0.1), q0=home)
    assert goal is not None
    room = geometry.transit_collision
    refused = transit_segment(room, home, goal, poses, seed=1)
    assert isinstance(refused, TransitFailure) and "start configuration is invalid" in refused.reason
    found = transit_segment(room, home, goal, poses, seed=1, exact=geometry.arm_collision)
    assert not isinstance(found, TransitFailure)
    assert np.array_equal(found.joints[0], home) and np.allclose(found.joints[-1], goal)
    inside = [room.free(q) for q in found.joints].index(True)
    assert all(room.free(q) for q in found.joints[inside:])
    assert np.all(np.diff(found.times) > 0)


def _shift(x: float, y: float, z: float) -> np.ndarray:
    out = np.eye(4)
    out[:3, 3] = (x, y, z)
    return out
