"""Grasped handles carried out in DART (tasks o, by its grasp alone, and p): the shut Door opened 60 deg by the hand
holding its bar, the KnobDrawer pulled open 20 cm by the hand holding its knob, each reaching its goal, open loop.

The fingers must hold the handle (the executor's finger grip, `vkgl.execute.grip`): an executor that only welds
a free body it grasps does not hold a handle at all, and the door stays shut.
"""

from __future__ import annotations

import math

import pytest
from conftest import EXAMPLES
from task_makers.grasped_door import grasped_door

import vkgl
from vkgl.execute.closed_loop import execute

TASKS = {"o_open_door": ("door", math.radians(3)), "p_knob_drawer": ("drawer", 0.01)}


@pytest.mark.parametrize("name", list(TASKS))
def test_the_grasped_handle_is_moved_to_its_goal(name, tmp_path) -> None:
    # the Door by its grasp alone: the example's plan hooks the fingertip behind the bar (`grasped_door`)
    program = grasped_door(tmp_path) if name == "o_open_door" else vkgl.compile(EXAMPLES / "tasks" / f"{name}.vkg")
    plan = vkgl.solve(program).document()
    report = execute(program, name, plan)
    assert report.status == "reached", report.text()
    body, tolerance = TASKS[name]
    (step,) = report.steps
    (deviation,) = [d for d in step.deviations if d.body == body]
    assert deviation.opening is not None and abs(deviation.opening.error) < tolerance / 2, report.text()
    (goal,) = report.goals
    assert goal.opening is not None and abs(goal.opening.error) < tolerance / 2  # let go without dragging it on
    assert not report.disturbed
