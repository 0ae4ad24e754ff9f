"""A candidate with its fingertip contacts raised (`vkgl.plan.task_space.raised_contacts`): the same motion values and
bodies' poses, each fingertip contact that can be raised renamed from its ADD to its REMOVE, the hand higher."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from task_makers import generated_tasks

import vkgl
from vkgl.plan.graphs.graph import Action, Engagement
from vkgl.plan.graphs.rollout import extend, rollout, start_sequence
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.task_space.feasible import JOINT_SAMPLES, TaskSolution
from vkgl.plan.task_space.raised_contacts import raised_contacts


def _problem(tmp_path, body: str):
    target = generated_tasks.Placement("target", body, 0.6, 0.0, 0.0)
    tools = tuple(generated_tasks.Placement(n, t.name, x, y, a) for n, t, x, y, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("lift", 0, 0, (target, *tools), (0.4, 0.0, 0.0), "near", False, 0.2)
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path / body, generated_tasks.fixture_library((body,))))
    return build_problem(program, program.tasks["lift"])


def _candidate(problem, *actions: Action, values=(0.2,)):
    seq = start_sequence(problem)
    for action in actions:
        seq, _ = extend(problem, seq, action)
    x = np.asarray(values, dtype=float)
    return seq, TaskSolution(x, rollout(problem, seq, x, JOINT_SAMPLES))


def test_the_fingertip_contacts_are_renamed_from_add_to_remove_and_the_bodies_move_the_same(tmp_path):
    problem = _problem(tmp_path, "CrateM")
    pull = Engagement("arm.fingertip", "target", "push_center_nx")
    seq, found = _candidate(problem, Action("add", pull), Action("remove", pull))
    raised = raised_contacts(problem, seq, found)
    assert raised is not None
    named, solution = raised
    member = Engagement("arm.fingertip", "target", "push_center_nx/over+0deg+6.50cm")
    assert named.actions == (Action("add", member), Action("remove", member))
    assert solution.sequence == named and np.array_equal(solution.values, found.values)
    for before, after in zip(found.traces, solution.traces, strict=True):
        assert np.allclose(before.end["target"], after.end["target"])
    hand_before, hand_after = found.traces[1].hand[0], solution.traces[1].hand[0]
    assert hand_after[2, 3] - hand_before[2, 3] == pytest.approx(0.065)
    assert np.allclose(hand_after[:2, 3], hand_before[:2, 3])


def test_nothing_to_raise_on_a_low_body(tmp_path):
    problem = _problem(tmp_path, "SlabN")  # 5 cm tall: its face rises 2.5 cm over the pad, the fingers clear it
    push = Engagement("arm.fingertip", "target", "push_center_nx")
    assert raised_contacts(problem, *_candidate(problem, Action("add", push))) is None


def test_a_tool_set_down_where_it_was_picked_up_stays_so_when_raised(tmp_path):
    # gen13_018 of the physical bench: the put-back variant (`Sequence.returns`) passed the bodies' check, the arm
    # rejected it, and its raised retry had lost the returns: the crate was planned through the Stick
    problem = _problem(tmp_path, "CrateM")
    pull = Engagement("arm.fingertip", "target", "push_center_nx")
    seq, found = _candidate(problem, Action("add", pull), Action("remove", pull))
    where = found.traces[2].start["target"].copy()  # the pose it has there anyway: only the field is under test
    raised = raised_contacts(problem, replace(seq, returns=((2, where),)), found)
    assert raised is not None
    named, solution = raised
    assert [mode for mode, _ in named.returns] == [2] and np.allclose(named.returns[0][1], where)
    assert solution.sequence is named
