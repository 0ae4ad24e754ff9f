"""Every body accounted for: an execution that shoves a bystander is "disturbed", not "reached".

The plan is written by hand (tests/support/plan_script.py): the planner
would refuse to push the block through the second one. The 15 cm push meets block2 after 9 cm and shoves it 6 cm,
six times the 1 cm a body the plan leaves still may end off (a goal's default tolerance). Every cm of that shove is
0.9 CPU-s of DART's contact solver (the two blocks and the table in contact), so block2 stands no nearer than that
makes the point: 3 cm nearer, a 9 cm shove, the test took 12 CPU-s instead of 9.5.
"""

from __future__ import annotations

from pathlib import Path

from plan_script import scripted_plan

import vkgl

SCENE = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene shove {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.4, 0) m yaw 0deg
    block2 : Block on table at (0.59, 0) m yaw 0deg
}

task shove_it {
    scene shove
    goal block at (0.55, 0) m within 2 cm
}
"""


def test_a_shoved_bystander_makes_the_execution_disturbed() -> None:
    # `use stdlib...` resolved beside this file (no stdlib/ here), so always the installed stdlib
    program = vkgl.compile_source(SCENE, "shove.vkg", base_dir=Path(__file__).parent)
    plan = scripted_plan(program, "shove_it", ["add Block.push_center_px block arm.fingertip 0.15"])
    report = vkgl.execute(program, "shove_it", plan)
    assert all(goal.ok for goal in report.goals)  # the goal itself is met
    assert report.status == "disturbed" and not report.reached  # `vkgc solve --execute` exits 5
    (shoved,) = report.disturbed
    assert shoved.body == "block2" and shoved.position > 0.05
    assert "block2 ended" in report.reason and "from where the plan leaves it" in report.reason
    assert "DISTURBED: block2" in report.text()
    data = report.to_json()
    assert data["format"] == "vkg-execution/5" and data["status"] == "disturbed"
    assert data["disturbed"][0]["body"] == "block2" and data["disturbed"][0]["position_error_m"] > 0.05
