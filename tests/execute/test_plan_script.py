"""Scripted plans: valid vkg-plan/8 whose joints put the effector where the steps say."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXAMPLES
from plan_script import EXAMPLE_SCRIPTS, scripted_plan

from vkgl.errors import InputError
from vkgl.formats.plan import from_json, to_json
from vkgl.lang.compiler import compile_file
from vkgl.robot import Arm


@pytest.fixture(scope="module")
def program_b():
    return compile_file(str(EXAMPLES / "tasks" / "b_stick_push.vkg"))


def test_a_stick_push_moves_block_and_stick_together_and_fk_matches(program_b):
    plan = to_json(scripted_plan(program_b, "b_stick_push", EXAMPLE_SCRIPTS["b_stick_push"]))
    assert to_json(from_json(plan)) == plan  # valid vkg-plan/8
    assert plan["format"] == "vkg-plan/8" and plan["status"] == "solved" and plan["depth"] == 3
    np.testing.assert_allclose(np.array(plan["final"]["block"])[:3, 3], [0.95, 0.0, 0.025], atol=1e-9)
    push = plan["steps"][1]
    moved = {n for n in push["poses_start"] if not np.allclose(push["poses_start"][n], push["poses_end"][n])}
    assert moved == {"block", "stick"}
    robot = program_b.robots["Panda"]
    arm = Arm.load(robot, "fingertip", np.array(plan["robot"]["base"]))
    # the stick's tip is on the block's -x face at the start, and the hand holds the handle
    stick = np.array(push["poses_start"]["stick"])
    handle = stick @ program_b.affordances["Stick"][0].action.pose.matrix()
    np.testing.assert_allclose(arm.fk(np.array(push["q_start"])), handle, atol=2e-3)
    # the robot entry is the contract's: FK(q) = base @ link(q) @ effector_offset
    np.testing.assert_allclose(np.array(plan["robot"]["effector_offset"]), arm.link_offset, atol=1e-12)
    tip = stick @ program_b.bodies["Stick"].frame("tip").pose.matrix()
    np.testing.assert_allclose(tip[:3, 3], [0.65, 0.0, 0.025], atol=1e-9)


def test_unknown_affordance_is_an_input_error(program_b):
    with pytest.raises(InputError, match=r"no affordance Block\.fly"):
        scripted_plan(program_b, "b_stick_push", ["add Block.fly block arm.fingertip 0.1"])
