"""The arm's URDF collision shapes (and a tool in its hand) against the bodies and the table at joint configurations."""

from __future__ import annotations

import numpy as np
import pytest
from checkers.collision_shapes import box, pose
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.motion.arm_collision import PAD, ArmCollision, Held
from vkgl.motion.collision import TABLE, CollisionScene
from vkgl.plan.problem.problem import build_problem
from vkgl.robot import Arm


@pytest.fixture(scope="module")
def setup(compiled):
    """The a_push problem's arm, with its scene's bodies, a tall post and a small peg (parked far away) added."""
    program = compiled("a_push")
    problem = build_problem(program, program.task())
    shapes = {name: body.type.shape for name, body in problem.bodies.items()}
    shapes["post"] = box(0.1, 0.1, 1.0)
    shapes["peg"] = box(0.01, 0.004, 0.01)
    scene = CollisionScene(
        shapes, table_center=problem.table_center, table_size=problem.table_size, table_z=problem.table_z
    )
    arm = ArmCollision(scene, problem.arm)
    poses = {name: body.rest for name, body in problem.bodies.items()}
    poses["post"] = pose(5.0, 5.0, 0.5)
    poses["peg"] = pose(-5.0, 5.0, 0.5)
    return problem, arm, poses


def test_the_links_are_the_urdfs_and_the_effector_is_where_fk_puts_it(setup) -> None:
    problem, arm, _ = setup
    assert arm.links[0] == "panda_link0" and "panda_hand" in arm.links and len(arm.links) == 11
    q = problem.arm.home + 0.1
    arm.set_configuration(q)
    assert np.allclose(arm.effector_pose(), problem.arm.fk(q), atol=1e-9)


def test_a_moved_base_moves_the_links(setup, compiled) -> None:
    problem, arm, _ = setup
    robot = compiled("a_push").robots["Panda"]
    moved = Arm.load(robot, problem.arm.effector, pose(0.3, -0.2, 0.05, yaw=0.4))
    checker = ArmCollision(arm.scene, moved)
    checker.set_configuration(moved.home)
    assert np.allclose(checker.effector_pose(), moved.fk(moved.home), atol=1e-9)


def test_the_arm_at_home_is_free_of_the_bodies_and_the_table(setup) -> None:
    problem, arm, poses = setup
    assert arm.overlap(problem.arm.home, poses) == []
    assert arm.free(problem.arm.home)


def test_a_tall_body_in_the_arms_way_collides_with_its_links(setup) -> None:
    problem, arm, poses = setup
    hand = problem.arm.fk(problem.arm.home)
    tall = dict(poses, post=pose(hand[0, 3], hand[1, 3] + 0.02, 0.5))
    hits = arm.overlap(problem.arm.home, tall)
    assert hits and {c.body_b for c in hits} == {"post"}
    assert {c.body_a for c in hits} <= {*arm.links, PAD} and "panda_hand" in {c.body_a for c in hits}
    assert arm.overlap(problem.arm.home, tall, ignore={"post"}) == []
    assert arm.free(problem.arm.home, poses)  # moved away again


def test_an_arm_reaching_into_the_table_collides_with_it(setup) -> None:
    problem, arm, poses = setup
    q = problem.arm.home.copy()
    while problem.arm.fk(q)[2, 3] > -0.05:  # lean the shoulder forward until the fingertip is 5 cm under the top
        q[1] += 0.02
        assert q[1] < problem.arm.upper[1]
    hits = arm.overlap(q, poses)
    assert TABLE in {c.body_b for c in hits}
    assert all(c.body_b != TABLE for c in arm.overlap(q, poses, table=False))


def test_a_held_hooks_whole_shape_is_checked_but_not_against_what_it_acts_on(setup) -> None:
    problem, arm, poses = setup
    home = problem.arm.home
    in_hand = np.linalg.inv(problem.action("hook", "wield"))  # the hook's pose in the effector frame
    held = Held("hook", in_hand)
    assert arm.overlap(home, poses, held=held) == []
    hook_pose = problem.arm.fk(home) @ in_hand
    on_cross_piece = dict(poses, post=hook_pose @ pose(0.19, 0.12, -0.49))  # the post's top meets the cross-piece only
    hits = arm.overlap(home, on_cross_piece, held=held)
    assert {(c.body_a, c.body_b) for c in hits} == {("hook", "post")}
    assert arm.overlap(home, on_cross_piece, held=Held("hook", in_hand, acts_on=frozenset({"post"}))) == []
    # the fast check of transit planning gives the same answers
    assert not arm.free(home, on_cross_piece, held=held)
    assert arm.free(home, on_cross_piece, held=Held("hook", in_hand, acts_on=frozenset({"post"})))
    assert arm.free(home, poses, held=held)


def test_the_fingers_are_checked_open_around_a_held_tool_and_closed_without_one(setup) -> None:
    """The executor closes the fingers onto a held tool's faces (each 1.05 cm open on the Hook's 2 cm), not
    fully: a peg 1.5 cm beside the effector frame, clear of the closed fingers, is inside an open one."""
    problem, arm, poses = setup
    home = problem.arm.home
    in_hand = np.linalg.inv(problem.action("hook", "wield"))
    beside = dict(poses, peg=problem.arm.fk(home) @ pose(0.0, 0.015, 0.01))
    fingers = set(arm.finger_links)
    closed = Held("hook", in_hand, acts_on=frozenset({"peg"}))
    opened = Held("hook", in_hand, acts_on=frozenset({"peg"}), opening=0.0105)
    assert arm.overlap(home, beside, held=closed) == [] and arm.free(home, beside, held=closed)
    hits = arm.overlap(home, beside, held=opened)
    assert hits and {c.body_b for c in hits} == {"peg"} and {c.body_a for c in hits} <= fingers
    assert not arm.free(home, beside, held=opened)
    assert arm.clearance(opened)(home) <= 0.0 < arm.clearance(opened)(problem.arm.home + 0.3)
    # the checker's skeleton is shared: the next query without a tool has its fingers closed again
    away = dict(beside, hook=pose(5.0, -5.0, 0.0))
    assert not {c.body_a for c in arm.overlap(home, away)} & fingers
