"""Bodies 5 to 30 cm tall are pushed and pulled to their goal in DART: the arm comes from the side at contact height.

Before the arm's paths were planned, the hand came down from above onto a
point just behind the contact, and its fingers touched any body taller than
about 6 cm on the way. Here each crate has hand-written affordances (a
pushed face and the opposite one), the planner plans the transit and the
straight approach, and the plan of each way the hand meets a crate is carried out open loop in
physics (`CARRIED_OUT`).

Pushes start 0.45 m from the arm's base and move the crate 10 cm away from
it. A pull (`push_center_nx`) touches the crate's far face and draws it 10 cm
toward the base, so the arm must reach over the crate and come down behind
it, the hand leaning outward (its wrist beyond the far face, outside the
crate). The 5, 10 and 20 cm crates are pulled from 0.52 m (far face 0.60 m
from the base's axis): the hand stays upright above the 5 cm one and leans
45 deg behind the taller ones. There the arm is at the edge of its reach: a
stand-off 3 cm straight back from the far face, hand leaned, has no IK, and
one 3 cm above the contact has the fingertip within the transit's 1 cm
clearance of the face, so the planner comes in slanted, 30 deg down
(`straight_moves.SLANT`). The 10, 20 and 30 cm crates are also pulled from 0.38 m,
comfortably inside the reach (near face 0.20 m from the base's axis at the
goal, 11 cm clear of the base's 9 cm column). A 30 cm crate is about as tall
as the Panda's shoulder (0.333 m): the forearm passes over its top only while
the far face is near, the hand leaned 60 deg. Measured limits: the 30 cm
crate is pulled from up to 0.38 m (from 0.39 to 0.40 m the arm at the
stand-off has its forearm within the transit's 1 cm clearance of the crate's
top; from 0.44 m no IK answer for the hand leaned 0 to 70 deg, in 10 deg
steps from 150 random seeds each, keeps the forearm off the crate). So a 30
cm crate 0.44 m or 0.52 m away is an honest no plan, naming the forearm
(panda_link5). The 10 and 20 cm crates have no plan from 0.54 m (no straight
approach of any of the three ways; from 0.56 m no arm configuration the
planner tries keeps the hand and wrist off the crate at the contact).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import vkgl
from vkgl.motion.moves import STANDOFF
from vkgl.plan.arm.straight_moves import SLANT

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
PULLS = [("pull", h, 0.52, 0.42) for h in (5, 10, 20)] + [("pull", h, 0.38, 0.28) for h in (10, 20, 30)]
SLANTED = {(10, 0.52), (20, 0.52)}
"""Pulls whose stand-off is above and behind the contact (no room to back off level at the edge of the reach)."""
CARRIED_OUT = {("push", 5, 0.45), ("push", 30, 0.45), ("pull", 5, 0.52), ("pull", 20, 0.52), ("pull", 30, 0.38)}
"""The moves also carried out in DART: one of each way the hand meets a crate (a push with the hand upright, one
leaned back from the tallest face; a pull at the edge of the reach with the hand upright, one slanted in and leaned
outward; a pull near the base under the forearm). Every move is planned and its approach checked; the other five
repeat a way in DART at another height (2 to 4 CPU-s each: the bench, bench/physical, carries out the breadth)."""


@pytest.mark.parametrize(("how", "height_cm", "start", "goal"), PUSHES + PULLS)
def test_a_crate_is_moved_to_its_goal_in_physics(tmp_path, how, height_cm, start, goal):
    program = vkgl.compile(crate_task(tmp_path, height_cm, start, goal))
    plan = vkgl.solve(program, "move_crate")
    assert plan.status == "solved", plan.reason
    used = {step.affordance for step in plan.steps}
    assert used == {"Crate.push_center_px" if how == "push" else "Crate.push_center_nx"}
    approach = plan.steps[0].path[-1]
    assert approach.phase == "approach"
    # the hand comes in from the side: the approach is level, at the contact's height (or slanted 30 deg down)
    fk = plan.problem.arm.fk
    first, last = fk(approach.joints[0]), fk(approach.joints[-1])
    drop = STANDOFF * math.sin(SLANT) if (height_cm, start) in SLANTED else 0.0
    assert first[2, 3] - last[2, 3] == pytest.approx(drop, abs=1e-3)
    if height_cm >= 20:  # an upright hand overhangs the pad: it leans back from a tall face
        assert last[2, 2] < 0.95
    if how == "pull" and height_cm >= 10:  # behind a tall crate the hand leans outward: the wrist stays outside it
        assert last[0, 2] > 0.5
    if (how, height_cm, start) in CARRIED_OUT:
        report = vkgl.execute(program, "move_crate", plan.document())
        assert report.status == "reached", report.reason


@pytest.mark.parametrize("start", [0.44, 0.52])
def test_pulling_a_30_cm_crate_beyond_the_forearms_reach_is_an_honest_no_plan(tmp_path, start):
    program = vkgl.compile(crate_task(tmp_path, 30, start, start - 0.1))
    plan = vkgl.solve(program, "move_crate")
    assert plan.status == "infeasible"
    assert "push_center_nx" in plan.reason and "no arm configuration carries the whole motion" in plan.reason
    assert "panda_link5 would overlap crate" in plan.reason  # the forearm, over the crate's top
    # of the configurations tried (every lean, and the arm's other configurations, since the forearm is a link
    # before the wrist), the reason names the closest: a lean whose forearm overlaps least
    assert "(closest: the hand leaned back " in plan.reason
    assert "deg: at the contact the arm's panda_link5 would overlap crate" in plan.reason
