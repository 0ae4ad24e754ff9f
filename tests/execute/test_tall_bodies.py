"""Bodies 5 to 30 cm tall are pushed and pulled to their goal in DART: the arm comes from the side at contact height.

Before the arm's paths were planned, the hand came down from above onto a
point just behind the contact, and its fingers touched any body taller than
about 6 cm on the way. Here each crate has hand-written affordances (a
pushed face and the opposite one), the planner plans the transit and the
straight approach, and the plan is carried out open loop in physics.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import vkgl

STDLIB_SCENE = """
use stdlib.robots.panda

body Crate {{
    shape box (16, 24, {height}) cm
    mass {mass} kg
    friction 0.5
}}

affordances Crate {{
    affordance push_center_px {{
        action fixed at (-8, 0, {contact_z}) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 20 cm
    }}
    affordance push_center_nx {{
        action fixed at (8, 0, {contact_z}) cm yaw 180deg
        motion prismatic along (-1, 0, 0) from (0, 0, 0) cm range 0 to 20 cm
    }}
}}

scene crate_scene {{
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    crate : Crate on table at ({start}, 0.05) m yaw 0deg
}}

task move_crate {{
    scene crate_scene
    goal crate at ({goal}, 0.05) m yaw 0deg within 1 cm, 3deg
    search {{ max_depth 3  timeout 30 s }}
}}
"""

CONTACT_HEIGHT = 0.04
"""m above the table where the hand touches a crate taller than twice this (low enough that it slides, not tips)."""


def crate_task(tmp_path: Path, height_cm: int, start: float, goal: float) -> Path:
    """A task file moving a crate `height_cm` tall from x = `start` to x = `goal` (m)."""
    height = height_cm / 100
    contact_z = (min(height / 2, CONTACT_HEIGHT) - height / 2) * 100
    source = STDLIB_SCENE.format(
        height=height_cm,
        mass=round(150 * 0.16 * 0.24 * height, 3),
        contact_z=round(contact_z, 3),
        start=start,
        goal=goal,
    )
    path = tmp_path / f"crate_{height_cm}.vkg"
    path.write_text(source, encoding="utf-8")
    return path


PUSHES = [("push", h, 0.45, 0.55) for h in (5, 10, 20, 30)]
PULLS = [("pull", 5, 0.52, 0.42)]


@pytest.mark.parametrize(("how", "height_cm", "start", "goal"), PUSHES + PULLS)
def test_a_crate_is_moved_to_its_goal_in_physics(tmp_path, how, height_cm, start, goal):
    program = vkgl.compile(crate_task(tmp_path, height_cm, start, goal))
    plan = vkgl.solve(program, "move_crate")
    assert plan.status == "solved", plan.reason
    used = {step.affordance for step in plan.steps}
    assert used == {"Crate.push_center_px" if how == "push" else "Crate.push_center_nx"}
    approach = plan.steps[0].path[-1]
    assert approach.phase == "approach"
    # the hand comes in from the side: the approach is level, at the contact's height
    fk = plan.problem.arm.fk
    first, last = fk(approach.joints[0]), fk(approach.joints[-1])
    assert abs(first[2, 3] - last[2, 3]) < 1e-3
    if height_cm >= 20:  # an upright hand overhangs the pad: it leans back from a tall face
        assert last[2, 2] < 0.95
    report = vkgl.execute(program, "move_crate", plan.document())
    assert report.status == "reached", report.reason


def test_pulling_a_tall_crate_over_its_top_is_an_honest_no_plan(tmp_path):
    program = vkgl.compile(crate_task(tmp_path, 30, 0.52, 0.42))
    plan = vkgl.solve(program, "move_crate")
    assert plan.status == "infeasible"
    assert "push_center_nx" in plan.reason and "would overlap crate" in plan.reason
