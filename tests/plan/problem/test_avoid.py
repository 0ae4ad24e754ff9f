"""`solve(..., avoid=Avoid(...))`: a re-solve returns no plan already tried and repeats no step that failed where
it failed; what it rejected is counted as "excluded"."""

from __future__ import annotations

import dataclasses
from dataclasses import replace

import numpy as np
import pytest
from conftest import EXAMPLES

from vkgl.formats.plan import PlanDocument
from vkgl.lang.compiler import compile_file
from vkgl.plan.problem.avoid import Avoid, StepKey
from vkgl.plan.solve import solve


@pytest.fixture(scope="module")
def task_d():
    program = compile_file(str(EXAMPLES / "tasks" / "d_rotate_push.vkg"))
    task = program.task("d_rotate_push")
    return program, task, solve(program, task).document()


def _titles(plan: PlanDocument) -> list[str]:
    return [s.title() for s in plan.steps]


def test_a_plan_already_tried_is_not_returned_again(task_d):
    program, task, first = task_d
    again = solve(program, task, avoid=Avoid.of(tried=[first]))
    assert again.status == "solved"
    assert _titles(again.document()) != _titles(first)
    assert again.details["rejections"]["excluded"] == 1
    # nothing to avoid: the same plan as without
    assert _titles(solve(program, task, avoid=Avoid()).document()) == _titles(first)


def test_a_failed_step_is_excluded_where_it_failed_only(task_d):
    program, task, first = task_d
    turn = first.steps[0]
    plan = solve(program, task, avoid=Avoid.of(failed=[turn])).document()
    assert plan.solved
    assert not any(StepKey.of(s).repeats_failed(StepKey.of(turn)) for s in plan.steps)
    # the same turn with the block 5 cm away is another attempt: nothing here repeats it
    block = np.array(turn.poses_start["block"])
    block[0, 3] += 0.05
    moved = dataclasses.replace(turn, poses_start={**turn.poses_start, "block": block})
    assert _titles(solve(program, task, avoid=Avoid.of(failed=[moved])).document()) == _titles(first)


def test_a_tried_plan_padded_with_steps_that_move_nothing_is_the_same_plan(task_d):
    _, _, first = task_d
    push = first.steps[-1]
    let_go = dataclasses.replace(push, op="remove", value=0.0)
    nothing = dataclasses.replace(push, poses_start=dict(push.poses_end), value=0.0)
    shorter = dataclasses.replace(push, value=push.value - 0.01)
    avoid = Avoid.of(tried=[dataclasses.replace(first, steps=(push,))])
    keys = [StepKey.of(s) for s in (push, let_go, nothing)]
    assert avoid.rejection(keys) is not None and avoid.rejection(keys).kind == "excluded"
    assert avoid.rejection([StepKey.of(shorter)]) is None  # a push 1 cm shorter is another plan


def test_when_every_plan_repeats_a_failure_the_reason_says_so():
    program = compile_file(str(EXAMPLES / "tasks" / "b_stick_push.vkg"))
    task = program.task("b_stick_push")
    grasp = solve(program, task).document().steps[0]
    # every grasp of either tool failed where the tools lie (the stdlib's tools have several learned grasps)
    failed = [
        replace(grasp, body=name, affordance=f"{tool}.{aff.name}")
        for name, tool in (("stick", "Stick"), ("hook", "Hook"))
        for aff in program.affordances[tool]
        if aff.motion.type == "free"
    ]
    plan = solve(program, task, avoid=Avoid.of(failed=failed))
    assert plan.status == "infeasible"
    assert "repeated a plan already tried or a step that failed in execution; the closest:\n" in plan.reason
    assert "`add Stick.wield on stick with arm.fingertip` failed in execution with stick where it is" in plan.reason
    assert " repeating a step that failed in execution, " in plan.reason  # the accounting counts them
