"""Execution follows the plan's contact chains (vkg-plan/3 `steps[k].contact`), and lets go of a tool where the
plan leaves it (in the plan; in physics see the note below).

Before vkg-plan/3 the executor tracked a contact's motion by IK from the arm's
real joints; the redundant Panda drifted in its null space (1.9 rad in joint 1
on a generated hook task) and ended where no planned path started. Here the
arm must end a contact within a hair of the plan's `q_end`.

Not yet tested in physics: a tool let go of right after its contact. The
plan puts it down where it touched and lifts the hand 4 cm from there, but
in DART the hook lowered onto the table rests 8 mm higher than the plan says
and the rising fingertip carries it along (the transit then touches it).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import EXAMPLES
from plan_script import scripted_plan

import vkgl
from vkgl.execute import steps as steps_module
from vkgl.lang.compiler import compile_file

SCRIPT = [
    "add Hook.wield hook arm.fingertip",
    "add Block.push_center_nx block hook.tip 0.15",
    "remove Block.push_center_nx block hook.tip",
    "remove Hook.wield hook arm.fingertip",
    "add Block.push_center_px block arm.fingertip 0.05",
]


@pytest.fixture(scope="module")
def hook_then_hand():
    program = compile_file(str(EXAMPLES / "tasks" / "c_hook_pull.vkg"))
    return program, scripted_plan(program, "c_hook_pull", SCRIPT)


def test_the_plan_lets_go_of_a_tool_where_it_touched(hook_then_hand):
    _, plan = hook_then_hand
    pull, leave, release, push = plan.steps[1], plan.steps[2], plan.steps[3], plan.steps[4]
    assert pull.contact is not None and len(pull.contact) >= 15  # a chain every cm of the 15 cm pull
    assert leave.path == ()  # no retreat: the hook is put down where it touched
    assert np.allclose(release.q_start, pull.q_end) and np.allclose(release.q_end, pull.q_end)
    assert [segment.phase for segment in push.path] == ["lift", "transit", "approach"]
    assert np.allclose(push.path[0].joints[0], release.q_end)


def test_a_hook_pull_ends_in_the_planned_configuration(monkeypatch):
    program = compile_file(str(EXAMPLES / "tasks" / "c_hook_pull.vkg"))
    plan = vkgl.solve(program, "c_hook_pull")
    ends: list[tuple[np.ndarray, np.ndarray]] = []
    push = steps_module.StepKinds._push

    def recorded(self, step, label):
        push(self, step, label)
        ends.append((self.sim.arm.q.copy(), np.asarray(step.q_end)))

    monkeypatch.setattr(steps_module.StepKinds, "_push", recorded)
    report = vkgl.execute(program, "c_hook_pull", plan.document())
    assert report.status == "reached", report.reason
    assert len(ends) == 1 and plan.steps[1].contact is not None
    real, planned = ends[0]
    # following the chain ends on q_end to 1e-14 rad; tracking by IK from the real joints drifted 1.5e-3 rad here
    assert np.abs(real - planned).max() < 1e-4
