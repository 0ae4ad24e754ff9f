"""A contact that moves nothing makes no plan of its depth (`vkgl.plan.task_space.idle`): the same sequence without
it ends every remaining mode with the bodies where it did, unless it parks a held tool the hand then lets go of."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vkgl.lang.compiler import compile_file
from vkgl.plan.graphs.graph import Action, Engagement
from vkgl.plan.graphs.rollout import Sequence, extend, rollout, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.problem.rejection import Kind
from vkgl.plan.task_space.idle import idle_contact

TASK = Path(__file__).resolve().parents[3] / "examples" / "tasks" / "b_stick_push.vkg"
FINGER, TIP = "arm.fingertip", "stick.tip"
PUSH = Engagement(FINGER, "block", "push_center_nx")
TURN = Engagement(FINGER, "block", "turn_px_left")
WIELD = Engagement(FINGER, "stick", "wield")
TIP_PUSH = Engagement(TIP, "block", "push_center_nx")
TIP_TURN = Engagement(TIP, "block", "turn_px_left")


@pytest.fixture(scope="module")
def problem() -> Problem:
    program = compile_file(str(TASK))
    return build_problem(program, program.task())


def _sequence(problem: Problem, *steps: tuple[str, Engagement]) -> Sequence:
    seq = start_sequence(problem)
    for op, e in steps:
        seq, _ = extend(problem, seq, Action(op, e))
    return seq


def test_an_idle_push_before_another_is_rejected_and_a_moving_one_is_not(problem):
    seq = _sequence(problem, ("add", TURN), ("remove", TURN), ("add", PUSH))
    idle = idle_contact(problem, seq, np.array([0.0, 0.2]))
    assert idle is not None and idle.kind is Kind.IDLE
    assert idle.why.startswith("step 1 (add Block.turn_px_left on block with arm.fingertip) moves its body 0.00 deg")
    assert idle_contact(problem, seq, np.array([0.1, 0.2])) is None


def test_without_the_idle_contact_every_body_ends_where_it_did(problem):
    """The soundness of the rejection: the shorter sequence reaches the very poses (so the goal, and every
    task-space constraint of the modes it keeps), for any value of the motion that remains."""
    long = _sequence(problem, ("add", PUSH), ("remove", PUSH), ("add", TURN), ("remove", TURN), ("add", PUSH))
    short = _sequence(problem, ("add", PUSH), ("remove", PUSH), ("add", PUSH))
    for first, last in ((0.05, 0.1), (0.0, 0.3), (0.2, 0.01)):
        ends = rollout(problem, long, np.array([first, 0.0, last]))
        again = rollout(problem, short, np.array([first, last]))
        assert long.graphs[4:] == short.graphs[2:]
        for body, pose in ends[-1].end.items():
            assert np.allclose(pose, again[-1].end[body], atol=1e-12), body


def test_an_idle_tool_contact_is_kept_when_it_parks_the_tool_and_not_when_the_tool_acts_again(problem):
    parks = _sequence(problem, ("add", WIELD), ("add", TIP_TURN), ("remove", TIP_TURN), ("remove", WIELD))
    assert idle_contact(problem, parks, np.array([0.0])) is None  # the stick is put down at the block
    again = _sequence(problem, ("add", WIELD), ("add", TIP_TURN), ("remove", TIP_TURN), ("add", TIP_PUSH))
    idle = idle_contact(problem, again, np.array([0.0, 0.2]))
    assert idle is not None and "step 2" in idle.why
