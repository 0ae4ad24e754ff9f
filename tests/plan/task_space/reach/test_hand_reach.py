"""The proof that the hand cannot reach a goal body on its way to its goal (`vkgl.plan.task_space.reach.hand_reach`):
wherever the goal holds, the hand at each sample it bounds lies within its bounds (so it never rejects a
sequence task space would accept)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from task_makers.far_block import block_moving_sequences, far_block_problem

from vkgl.plan.graphs.rollout import Sequence, bounds, rollout
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.reach.hand_reach import hand_bounds, hand_out_of_reach_on_the_way
from vkgl.plan.task_space.reach.workspace import hand_down_point


@pytest.fixture(scope="module")
def problem(tmp_path_factory: pytest.TempPathFactory) -> Problem:
    return far_block_problem(Path(tmp_path_factory.mktemp("hand_reach")))


@pytest.fixture(scope="module")
def sequences(problem: Problem) -> list[Sequence]:
    return block_moving_sequences(problem)


@pytest.fixture(scope="module")
def bounded(problem: Problem, sequences: list[Sequence]) -> list[Sequence]:
    """Those with a hand sample to bound: the hand acting on the block in a mode before the last, or at its end."""
    goal = problem.goals[0]
    return [s for s in sequences if len(hand_bounds(problem, s, goal)) > 1]


def _goal_at(problem: Problem, position: np.ndarray, tolerance: float = 0.01) -> Problem:
    return replace(problem, goals=[GoalSpec("block", position, None, tolerance, math.radians(3))])


@settings(max_examples=10, deadline=None)
@given(
    fractions=st.lists(st.floats(0.0, 1.0), min_size=12, max_size=12),
    miss=st.tuples(st.floats(0.0, 1.0), st.floats(-math.pi, math.pi)),
)
def test_the_hand_lies_within_its_bounds_wherever_the_goal_holds(problem, bounded, fractions, miss):
    # the witness: values (motions, then contacts along their families) and a goal they meet within its tolerance
    assert any(s.offsets for s in bounded) and any(
        sum("turn" in e.affordance for _, e in s.variables) == 2 for s in bounded
    )
    seen = 0
    for seq in bounded:
        lower, upper = bounds(problem, seq, offsets=True)
        x = lower + np.array(fractions[: len(lower)]) * (upper - lower)
        traces = rollout(problem, seq, x)
        end = traces[-1].end["block"][:2, 3]
        goal = end + 0.01 * miss[0] * np.array([math.cos(miss[1]), math.sin(miss[1])])
        for bound in hand_bounds(problem, seq, _goal_at(problem, goal).goals[0]):
            pose = traces[bound.mode].hand[-1 if bound.at_end else 0]
            hand = pose[:3, 3]
            counted = hand_down_point(problem, pose)  # what task space judges (a tilted hand: its wrist's point)
            radius = math.hypot(counted[0], counted[1])
            assert bound.nearest - 1e-9 <= radius <= bound.farthest + 1e-9, (seq.actions, x, bound)
            assert abs(hand[2] - bound.height) < 1e-9
            seen += 1
    assert seen >= 2 * len(bounded)


def test_a_far_goal_rejects_pushing_back_from_beyond_the_reach(problem, sequences):
    # 85 cm from the arm's base: pushed there, the block's far face is beyond the reach, so the sequences that
    # end with a push back from that face, or push from it on the way, are rejected without optimising
    far = _goal_at(problem, np.array([0.85, 0.05]))
    verdicts = {seq: hand_out_of_reach_on_the_way(far, seq) for seq in sequences}
    rejected = [s for s, v in verdicts.items() if isinstance(v, Rejection)]
    assert rejected and all(verdicts[s].kind is Kind.REACH for s in rejected)  # type: ignore[union-attr]
    assert len(rejected) < len(sequences)
    assert all(any("_nx" in a.label(problem) or "right" in a.label(problem) for a in s.actions) for s in rejected)
    assert "whatever the motion values" in verdicts[rejected[0]].why  # type: ignore[union-attr]
