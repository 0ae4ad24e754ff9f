"""A grasped handle moves along its joint (tasks o and p): the hand follows the door's arc and the drawer's slide
with the grasp pose rigid, its yaw pinned, never leaned back; the fingers may touch the body they close on, the
palm and the rest of the arm may not.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import EXAMPLES
from task_makers.grasped_door import grasped_door

import vkgl
from vkgl.plan.graphs.graph import is_grasp
from vkgl.plan.problem.problem import build_problem
from vkgl.se3 import screw_motion

TASKS = {  # task: (body, affordance, joint goal)
    "o_open_door": ("door", "Door.grasp_side_px_z_p3", math.radians(60)),
    "p_knob_drawer": ("drawer", "KnobDrawer.grasp_top_y_p2", 0.20),
}


@pytest.fixture(scope="module")
def plans(tmp_path_factory):
    # the Door by its grasp alone: the example's plan hooks the fingertip behind the bar (`grasped_door`)
    door = grasped_door(tmp_path_factory.mktemp("door"))
    programs = {name: vkgl.compile(EXAMPLES / "tasks" / f"{name}.vkg") for name in TASKS if name != "o_open_door"}
    return {name: vkgl.solve(program) for name, program in {"o_open_door": door, **programs}.items()}


@pytest.mark.parametrize("name", list(TASKS))
def test_the_handle_is_grasped_and_moved_along_its_joint_in_one_contact(plans, name):
    plan = plans[name]
    body, affordance, opening = TASKS[name]
    assert plan.status == "solved", plan.reason
    assert plan.depth == 2 and plan.steps[0].affordance == affordance
    assert plan.problem.bodies[body].joint_state(plan.final[body]) == pytest.approx(opening, abs=1e-3)
    assert is_grasp(plan.problem, body, affordance.split(".")[1])


@pytest.mark.parametrize("name", list(TASKS))
def test_the_hand_holds_the_grasp_pose_rigidly_all_along_the_motion(plans, name):
    plan = plans[name]
    body, affordance, _ = TASKS[name]
    step = plan.steps[0]
    grasp = plan.problem.action(body, affordance.split(".")[1])
    motion = screw_motion(step.poses_start[body], step.poses_end[body])
    chain = np.asarray(step.contact)
    assert len(chain) > 10
    for s, q in zip(np.linspace(0.0, 1.0, len(chain)), chain, strict=True):
        in_body = np.linalg.inv(motion.at(s) @ step.poses_start[body]) @ plan.problem.arm.fk(q)
        assert np.linalg.norm(in_body[:3, 3] - grasp[:3, 3]) < 0.003  # the chain's IK tolerance
        cosine = (np.trace(in_body[:3, :3].T @ grasp[:3, :3]) - 1.0) / 2.0
        assert math.degrees(math.acos(min(1.0, cosine))) < 1.0  # yaw pinned, not leaned back


DEEP = """
use "{kitchen}"

affordances Door {{
    affordance grasp_bar {{
        action grasp at ({x}, 14.1, 15) cm rpy (90, 0, 90) deg width 1 cm force 20 N
        motion revolute about (0, -20, 0) cm axis (0, 0, -1) range 0 to 90deg
    }}
}}

task deep {{
    scene kitchen
    goal door open 60deg within 3deg
}}
"""
"""The Door's learned side grasp of its bar (`grasp_side_px_z_p3`), written in the task at depth `x` (cm)."""


def test_a_grasp_with_the_palm_inside_the_door_is_refused(tmp_path):
    # the learned grasp (the pads' ends at the bar's inner face, x = 5.3 cm) plans; 4 cm deeper the fingertips
    # would reach the door's board and the palm the bar: no plan, and the palm is named
    plans = {}
    for x in (5.3, 1.3):
        path = tmp_path / f"deep{x}.vkg"
        path.write_text(DEEP.format(kitchen=EXAMPLES / "scenes" / "kitchen.vkg", x=x), encoding="utf-8")
        program = vkgl.compile(path)
        plans[x] = vkgl.solve(program)
    assert plans[5.3].status == "solved", plans[5.3].reason
    assert plans[1.3].status == "infeasible", plans[1.3].text()
    assert "panda_hand would overlap door" in plans[1.3].reason, plans[1.3].reason
    problem = build_problem(program, program.task())
    assert is_grasp(problem, "door", "grasp_bar")
