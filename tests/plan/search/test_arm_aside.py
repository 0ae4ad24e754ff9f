"""A body the arm runs into, pushed aside first (`vkgl.plan.search.arm_aside`): the bodies an arm rejection names,
and the physical bench's gen10_027, whose hook pull the arm can carry only once the crate beside it is pushed back."""

from __future__ import annotations

from pathlib import Path

from task_makers.generated_tasks import TEST_SOLVE_TIMEOUT_S, fixture_library, task_spec, write_task

import vkgl
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.search.arm_aside import SLIDE_STEPS, arm_hits


def test_an_arm_rejection_names_the_bodies_in_the_arms_way_but_no_goal_body(tmp_path: Path) -> None:
    spec = task_spec(10, 27)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    problem = build_problem(program, program.task(spec.name))
    why = "no arm configuration carries the whole motion (closest: the arm's panda_link6 would overlap clutter1)"
    ik = Rejection(Kind.IK, why, 1.0, bodies=frozenset({"clutter1"}))
    assert arm_hits(problem, ik) == {"clutter1"}
    assert arm_hits(problem, Rejection(Kind.IK, why, 1.0)) == set(), "read from `bodies`, not the words"
    hand = Rejection(Kind.COLLISION, "the arm's panda_hand would pass through target", bodies=frozenset({"target"}))
    assert arm_hits(problem, hand) == set()  # a goal body is moved by the plan itself, never aside
    assert arm_hits(problem, Rejection(Kind.REACH, "clutter1 is beyond", bodies=frozenset({"clutter1"}))) == set()


def test_gen10_027_pushes_the_crate_the_arm_brushes_back_before_the_hook_pulls(tmp_path: Path) -> None:
    # the straight hook pull: the arm's sixth link 1 mm into clutter1 8 % along it; pushing clutter1 aside first
    # came out of task space at 0 cm (nothing in the bodies' sweeps asks it to move) and was passed over as idle
    spec = task_spec(10, 27)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    plan = vkgl.solve(program, spec.name, timeout=TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    adds = [s for s in plan.to_json()["steps"] if s["op"] == "add"]
    assert adds[0]["body"] == "clutter1" and adds[0]["effector"] == "arm.fingertip"
    assert adds[0]["motion"] == "prismatic" and 0.01 < adds[0]["value"] <= max(SLIDE_STEPS) + 1e-9
    assert adds[-1]["body"] == "target" and adds[-1]["effector"] == "hook.tip"
