"""The planner's collision geometry puts a body on a joint where the simulator hangs it: `JOINT_LIFT` higher."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXAMPLES

import vkgl
from vkgl.lang.ir.geometry import JOINT_LIFT
from vkgl.motion.collision import CollisionScene
from vkgl.plan.problem.problem import build_problem, collision_scene


def test_the_simulator_and_the_planner_lift_by_one_constant() -> None:
    from vkgl.sim import world

    assert world.JOINT_CLEARANCE == JOINT_LIFT == pytest.approx(0.001)


def test_a_body_on_a_joint_is_lifted_in_the_planners_scene_and_a_free_one_is_not() -> None:
    program = vkgl.compile(EXAMPLES / "tasks" / "g_open_drawer.vkg")
    problem = build_problem(program, program.task())
    scene = collision_scene(problem)
    rest = {name: body.rest for name, body in problem.bodies.items()}
    scene.place(rest)
    for name, lift in (("drawer", JOINT_LIFT), ("door", JOINT_LIFT), ("cabinet", 0.0)):
        [(world, _)] = scene.part_boxes(name)[:1]
        [(local, _)] = scene.part_boxes_local(name)[:1]
        expected = rest[name] @ local
        assert world[2, 3] - expected[2, 3] == pytest.approx(lift, abs=1e-12), name
        assert np.allclose(world[:2, 3], expected[:2, 3])
    unlifted = CollisionScene({"drawer": problem.bodies["drawer"].type.shape})
    pose = rest["drawer"][None]
    assert scene.lowest("drawer", pose)[0] - unlifted.lowest("drawer", pose)[0] == pytest.approx(JOINT_LIFT)
