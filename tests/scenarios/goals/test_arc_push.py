"""One push that slides and turns the Block, planned from its learned arc law and carried out in DART.

The goal (12 cm along +x, turned +15 deg) took two contacts before arcs (a slide, then a turn: depth 4). The
planner offers the member of `push_center_px`'s arc family that the law says reaches it (0.64 cm right of the
face's centre, a pivot about 45 cm away): the arm would push there once. A goal 15 cm along +x and 4 cm aside
that leaves the heading free is one push too: the member whose arc passes through it (1.82 cm left of the centre,
turned about 42 deg on the way), and DART's Block ends where the plan says, place and heading. (That push is the
one carried out in DART: the larger of the two arcs, checked against the plan itself, not only the goal; the
first would repeat the family at 5 CPU-s of physics.)
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import vkgl

TASK = """use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene alone {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    it : Block on table at (0.45, 0) m yaw 0deg
}

task arc {
    scene alone
    goal it at (0.57, 0) m yaw 15deg within 1 cm, 3deg
}
"""


def test_a_place_and_heading_goal_is_one_arc_push(tmp_path: Path) -> None:
    path = tmp_path / "arc.vkg"
    path.write_text(TASK, encoding="utf-8")
    program = vkgl.compile(path)
    plan = vkgl.solve(program, "arc")
    assert plan.status == "solved" and plan.depth == 2, plan.reason
    assert [s.affordance.partition("@")[0] for s in plan.steps] == ["Block.push_center_px"]
    assert plan.steps[0].affordance.startswith("Block.push_center_px@-")


def test_one_arc_push_reaches_a_goal_off_the_push_line_whatever_its_heading_in_dart(tmp_path: Path) -> None:
    path = tmp_path / "arc_free.vkg"
    path.write_text(TASK.replace("(0.57, 0) m yaw 15deg within 1 cm, 3deg", "(0.60, 0.04) m within 1 cm"))
    program = vkgl.compile(path)
    plan = vkgl.solve(program, "arc")
    assert plan.status == "solved" and plan.depth == 2, plan.reason  # the straight push misses by 4 cm
    assert [s.affordance for s in plan.steps] == ["Block.push_center_px@-1.82cm"]
    report = vkgl.execute(program, "arc", plan)
    assert report.status == "reached", report.reason
    assert plan.final is not None  # and DART's Block ends where the plan says, not only inside the goal
    planned, real = np.asarray(plan.final["it"]), report.final["it"]
    assert np.linalg.norm(real[:2, 3] - planned[:2, 3]) <= 0.01
    turn = np.degrees(np.arctan2(real[1, 0], real[0, 0]) - np.arctan2(planned[1, 0], planned[0, 0]))
    assert abs((turn + 180) % 360 - 180) <= 3.0
