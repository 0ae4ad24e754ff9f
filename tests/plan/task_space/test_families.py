"""Contact families in the planner: an engagement's offset along its face as a task-space variable, and the
members named once it is chosen."""

from __future__ import annotations

import numpy as np
import pytest
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.lang.ir.families import at_offset
from vkgl.plan.graphs.graph import Action, Engagement
from vkgl.plan.graphs.rollout import bounds, extend, materialise, rollout, start_sequence
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.task_space.contacts import other_contacts
from vkgl.plan.task_space.feasible import TaskSolution, task_space


@pytest.fixture(scope="module")
def problem(compiled):
    program = compiled("d_rotate_push")
    return build_problem(program, program.task())


def _sequence(problem, *actions: Action):
    seq = start_sequence(problem)
    for action in actions:
        seq, _ = extend(problem, seq, action)
    return seq


TURN = Engagement("arm.fingertip", "block", "turn_px_left")
SLIDE = Engagement("arm.fingertip", "block", "push_center_px")


def test_a_turns_family_adds_an_offset_variable_within_its_band_and_a_slides_does_not(problem):
    seq = _sequence(problem, Action("add", TURN), Action("remove", TURN), Action("add", SLIDE))
    assert seq.offsets == ((1, TURN),)  # the slide's family is not used by the planner (members.has_family)
    lower, upper = bounds(problem, seq, offsets=True)
    family = problem.affordance("block", "turn_px_left").family
    assert (lower[-1], upper[-1]) == (family.lower.value, family.upper.value)
    assert len(lower) == len(seq.variables) + 1


def test_a_rollout_at_an_offset_is_the_rollout_of_the_member_there(problem):
    seq = _sequence(problem, Action("add", TURN))
    traces = rollout(problem, seq, np.array([0.3, 0.015]))
    named, values = materialise(problem, seq, np.array([0.3, 0.015]))
    assert named.actions[0].engagement.affordance == "turn_px_left@+1.50cm" and named.offsets == ()
    member = problem.affordance("block", "turn_px_left@+1.50cm")
    assert member == at_offset(problem.affordance("block", "turn_px_left"), 0.015).model_copy(
        update={"name": "turn_px_left@+1.50cm"}
    )
    again = rollout(problem, named, values)
    assert np.allclose(traces[-1].end["block"], again[-1].end["block"], atol=1e-12)
    assert np.allclose(traces[-1].hand[0], again[-1].hand[0], atol=1e-12)
    hand_at_zero = rollout(problem, seq, np.array([0.3, 0.0]))[-1].hand[0]
    assert np.linalg.norm(traces[-1].hand[0][:3, 3] - hand_at_zero[:3, 3]) == pytest.approx(0.015, abs=1e-9)


def test_offset_zero_keeps_the_written_names(problem):
    seq = _sequence(problem, Action("add", TURN))
    named, values = materialise(problem, seq, np.array([0.3, 0.0]))
    assert named.actions == seq.actions and list(values) == [0.3]


def test_a_name_outside_the_band_is_no_member(problem):
    with pytest.raises(KeyError):
        problem.affordance("block", "turn_px_left@-1.00cm")


def test_the_task_space_keeps_the_written_contact_when_it_reaches_the_goal(problem):
    seq = _sequence(problem, Action("add", TURN), Action("remove", TURN), Action("add", SLIDE))  # task (d)'s plan
    solution = task_space(problem, seq, deadline=float("inf"))
    assert isinstance(solution, TaskSolution), solution
    assert solution.sequence is None and len(solution.values) == len(seq.variables)


def test_other_contacts_pin_the_turn_at_its_bands_far_end(problem, monkeypatch):
    import vkgl.plan.task_space.contacts as contacts

    asked = []

    def recorded(problem, seq, deadline, counters=None, *, offsets=None):
        asked.append(offsets)
        return task_space(problem, seq, deadline, counters, offsets=offsets)

    monkeypatch.setattr(contacts, "task_space", recorded)
    seq = _sequence(problem, Action("add", TURN), Action("remove", TURN), Action("add", SLIDE))
    found = list(other_contacts(problem, seq, deadline=float("inf")))
    family = problem.affordance("block", "turn_px_left").family
    far = max((family.lower.value, family.upper.value), key=abs)
    assert len(asked) == 1 and asked[0] == pytest.approx([far])  # the band's end farthest from the written contact
    for solution in found:  # when the goal can be reached from there, the members are named at that end
        assert solution.sequence is not None
        names = [a.engagement.affordance for a in solution.sequence.actions]
        assert names[0] == names[1] == f"turn_px_left@+{far * 100:.2f}cm" and names[2] == "push_center_px"
        assert len(solution.values) == len(solution.sequence.variables) == 2


def test_other_contacts_pin_only_the_offsets_of_a_sequence_that_also_carries(compiled):
    # A re-solve after a carried body fell (`vkgc solve --replan`) asked for other contacts of a sequence with a
    # family's offset and a carry; the carry's three placement values follow the offsets among the bounds and
    # were pinned as offsets too (a ValueError, exit 4).
    program = compiled("n_pick_place")
    problem = build_problem(program, program.task())
    turn = Engagement("arm.fingertip", "middle", "turn_px_left")
    grasp = Engagement("arm.fingertip", "cube", "grasp_top")
    seq = _sequence(problem, Action("add", turn), Action("remove", turn), Action("add", grasp), Action("remove", grasp))
    assert len(seq.offsets) == 1 and seq.carries
    lower, _ = bounds(problem, seq, offsets=True)
    assert len(lower) == len(seq.variables) + 1 + 3  # motions, the offset, the carry's dx, dy, dyaw
    found = list(other_contacts(problem, seq, deadline=float("inf")))
    assert all(isinstance(f, TaskSolution) for f in found)
