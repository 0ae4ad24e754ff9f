"""Generated tasks whose first plans failed in physics, carried out in DART (bench/physical/bench_physical.py's tasks).

The generated bodies' affordances are the fixtures of tests/bench/learned (`tests/bench/test_generated_plans.py`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from task_makers.generated_tasks import TEST_SOLVE_TIMEOUT_S, fixture_library, task_spec, write_task

import vkgl


def test_the_hand_does_not_sweep_a_bystander_while_it_pushes(tmp_path: Path) -> None:
    # gen1_028: a cube pushed out of the way lies 12 cm beside the target cube. The hand, leaned back 30 deg behind
    # the fingertip, cleared the target where the push started and ended but swept through it halfway, and shoved
    # it 15 cm: the planner now checks the arm along the whole contact, and the plan takes the stick instead
    spec = task_spec(1, 28)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    report = vkgl.execute(program, spec.name, plan)
    assert report.status == "reached", report.reason
    for name in ("target", "clutter1", "clutter2"):  # every body where the plan leaves it
        off = np.linalg.norm(report.final[name][:2, 3] - plan.final[name][:2, 3])
        assert off < 0.01, f"{name} is {off * 100:.1f} cm from where the plan leaves it"


def test_leaving_a_hook_pull_near_the_base_does_not_throw_the_cube(tmp_path: Path) -> None:
    # gen5_007: the hook pulls a cube 37.7 cm to within 0.02 cm of the plan, and the plan ends in that contact.
    # Letting go at the end, the 4 cm lift of the held hook beside the base turned joint 5 by 1.1 rad: timed by
    # its length alone, 6.8 rad/s, past the joint's limit, so DART held the arm back while the hook was driven
    # where the commanded joints put the hand; 5.4 cm and 17 deg apart, the hook snapped back into the hand in
    # one control period and threw the cube 139 cm, off the table
    spec = task_spec(5, 7)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    assert plan.steps[-1].op == "add" and plan.steps[-1].effector == "hook.tip"  # it ends pulling with the hook
    report = vkgl.execute(program, spec.name, plan)
    assert report.status == "reached", report.reason
    off = np.linalg.norm(report.final["target"][:2, 3] - plan.final["target"][:2, 3])
    assert off < 0.005, f"the cube ends {off * 100:.1f} cm from where the plan leaves it"


def test_a_tall_crate_turned_then_pushed_reaches_its_goal(tmp_path: Path) -> None:
    # gen1_012: a 25 cm tall crate turned by the fingertip, then pushed. Learned under DART's boxed LCP (friction
    # bounded along world x and y) and carried out under the friction cone, the turn was 13.2 of 17.1 deg about
    # another pivot and the crate ended 1.6 cm from its goal; exploration and execution now share one physics
    # (vkgl.sim.world.new_world: tests/execute/test_one_physics.py)
    spec = task_spec(1, 12)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    assert any(s.op == "add" and s.motion == "revolute" for s in plan.steps)  # the crate is turned
    report = vkgl.execute(program, spec.name, plan)
    assert report.status == "reached", report.reason
    off = np.linalg.norm(report.final["target"][:2, 3] - plan.final["target"][:2, 3])
    assert off < 0.005, f"the crate ends {off * 100:.1f} cm from where the plan leaves it"
