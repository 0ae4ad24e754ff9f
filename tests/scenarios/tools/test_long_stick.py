"""A stick 60 cm long (the stdlib's is 40 cm), defined by a user, pushes the block 30 cm out to 1.05 m.

Tried as a new user would before the arm's paths were planned: "the arm cannot
reach the effector pose ... (no IK solution)" in execution. Now the planner
checks the grasp, the carry and the push with the longer tool's geometry, and
the plan is carried out open loop in DART to the goal.

The stick weighs 80 g (light wood): held at its end, a 150 g one carries its
own weight's moment at 79 % of the Panda's grip by the planner's estimate (86 %
measured in DART), more than the 54 % a plan may use (docs/planning.md, "A held
tool's grip"), and the planner refuses it.
"""

from __future__ import annotations

from pathlib import Path

import vkgl

LONG_STICK_TASK = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

body LongStick {
    shape box (60, 2, 2) cm
    mass 0.08 kg
    frame handle = (-25, 0, 0) cm
    frame tip = (30, 0, 0) cm
}

affordances LongStick {
    affordance wield {
        action fixed at (-25, 0, 0) cm yaw 0deg
        motion free
    }
}

correspondences {
    LongStick.tip ~ fingertip
}

scene far {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.75, 0) m yaw 0deg
    stick : LongStick on table at (0.35, -0.4) m yaw 0deg
}

task long_push {
    scene far
    goal block at (1.05, 0) m yaw 0deg within 1 cm, 3deg
    search { max_depth 6  timeout 30 s }
}
"""


def test_a_long_stick_push_is_planned_and_executed_to_the_goal(tmp_path: Path) -> None:
    path = tmp_path / "long_stick.vkg"
    path.write_text(LONG_STICK_TASK, encoding="utf-8")
    program = vkgl.compile(path)
    plan = vkgl.solve(program, "long_push")
    assert plan.status == "solved", plan.reason
    steps = plan.to_json()["steps"]
    assert [(s["affordance"], s["effector"]) for s in steps] == [
        ("LongStick.wield", "arm.fingertip"),
        ("Block.push_center_px", "stick.tip"),
    ]
    assert all(s["path"] for s in steps)  # the grasp and the push are reached by planned arm paths
    report = vkgl.execute(program, "long_push", plan)
    assert report.status == "reached", report.text()
