"""Task (i) in DART: the Hook catches the Drawer's bar at its overhang and pulls the drawer 20 cm open, open
loop and, from a drawer found 4 cm open, closed loop."""

from __future__ import annotations

import pytest
from conftest import EXAMPLES
from task_makers.joint_tasks import started_open

import vkgl
from vkgl.lang.ir.program import Program


@pytest.fixture(scope="module")
def i_task() -> tuple[Program, vkgl.plan.result.plan.Plan]:
    program = vkgl.compile(EXAMPLES / "tasks" / "i_hook_drawer.vkg")
    return program, vkgl.solve(program)


def test_the_hook_pulls_the_drawer_open_20_cm(i_task) -> None:
    program, plan = i_task
    assert [s.effector for s in plan.steps] == ["arm.fingertip", "hook.tip"]
    report = vkgl.execute(program, "i_hook_drawer", plan)
    assert report.status == "reached", report.text()  # nothing else disturbed either
    (goal,) = report.goals
    assert goal.opening is not None and abs(goal.opening.error) < 0.005
    # the drawer moved only because the held hook pulled it: it followed the hook the whole way
    assert report.steps[1].deviations[0].opening.real == pytest.approx(0.20, abs=0.005)


def test_closed_loop_hooks_the_rest_of_the_way_from_a_drawer_found_open(i_task) -> None:
    program, plan = i_task
    ajar = started_open(program, "i_hook_drawer", "drawer", 0.04)
    report = vkgl.execute(ajar, "i_hook_drawer", plan, replan=True)
    assert report.status == "reached", report.text()
    assert report.replans == 1 and "on its prismatic joint" in report.replan_log[0]
    assert abs(report.goals[0].opening.error) < 0.005
