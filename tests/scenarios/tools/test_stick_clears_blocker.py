"""A body in the way cleared with the stick: beyond the fingertip's reach, pushed just out of the path, in DART.

A cube is to be pushed 37 cm, to 0.95 m from the arm's base: beyond the fingertip's reach, so with the stick.
A second cube, turned 60 deg, lies across that path at 0.84 m, where the fingertip cannot reach its faces
either. The plan takes the stick, pushes the second cube along its own slide by the least value that takes it
out of the first cube's corridor (1 cm margin, `vkgl.plan.task_space.clearing`), then pushes the first cube to
its goal. The plan passes the independent geometry check (no overlap along any motion) and the contact-chain
check, and carried out in DART it reaches the goal with the blocker where the plan left it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from checkers.contact_chain_check import check_contact_chains
from checkers.plan_geometry import check_plan
from task_makers.pushed_cube import CUBE_SOURCE

import vkgl

TASK = (
    """
use stdlib.robots.panda
use stdlib.bodies.stick
use stdlib.affordances.stick
use stdlib.tools

"""
    + CUBE_SOURCE
    + """

scene beyond {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    cube : Cube on table at (0.58, 0) m yaw 0deg
    blocker : Cube on table at (0.84, 0) m yaw 60deg
    stick : Stick on table at (0.3, -0.4) m yaw 0deg
}

task across {
    scene beyond
    goal cube at (0.95, 0) m within 1 cm
    search { timeout 60 s }
}
"""
)

CORRIDOR_HALF_WIDTH = 0.04
"""m: the cube's path is a band this wide either side of y = 0 (the cube is 8 cm wide and slides along x)."""


def test_a_blocker_beyond_the_fingertip_is_pushed_just_aside_with_the_stick_and_the_plan_holds_in_dart(
    tmp_path: Path,
) -> None:
    path = tmp_path / "beyond.vkg"
    path.write_text(TASK, encoding="utf-8")
    program = vkgl.compile(path)
    plan = vkgl.solve(program, "across")
    assert plan.status == "solved", plan.reason
    doc = plan.to_json()
    steps = doc["steps"]
    assert [(s["op"], s["body"], s["effector"]) for s in steps] == [
        ("add", "stick", "arm.fingertip"),
        ("add", "blocker", "stick.tip"),
        ("remove", "blocker", "stick.tip"),
        ("add", "cube", "stick.tip"),
    ]
    # the blocker ends beside the path by the margin and not much more: the least push that clears it
    problem = plan.problem
    assert problem is not None
    from vkgl.plan.task_space.clearing import MARGIN, footprint

    blocker = footprint(problem, "blocker", np.array(steps[1]["poses_end"]["blocker"]))
    gap = float(np.abs(blocker[:, 1]).min()) - CORRIDOR_HALF_WIDTH
    assert MARGIN - 0.002 <= gap <= MARGIN + 0.01, gap
    assert check_plan(program, "across", doc) == []
    assert check_contact_chains(program, doc) == []
    report = vkgl.execute(program, "across", plan)
    assert report.status == "reached", report.text()  # "reached": the blocker too stays where the plan left it
