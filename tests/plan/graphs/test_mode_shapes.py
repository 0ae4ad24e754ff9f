"""What a rollout mode reads of its sequence, found once (`vkgl.plan.graphs.mode_shapes`): kept per sequence and
problem, and the rollouts that read it equal those of a sequence that never had it, bit for bit, whatever contact
frames and hand chains its modes remembered before."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.mode_shapes import HAND_ACTING, HAND_FREE, mode_shapes
from vkgl.plan.graphs.rollout import Sequence, bounds, extend, rollout, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem


@pytest.fixture(scope="module")
def problem(compiled):
    program = compiled("d_rotate_push")
    return build_problem(program, program.task())


def _sequences(problem: Problem, depth: int = 4) -> list[Sequence]:
    """Every sequence of up to `depth` graphs that moves something (breadth first, the first 60)."""
    out, level = [], [start_sequence(problem)]
    for _ in range(depth - 1):
        level = [extend(problem, s, a)[0] for s in level for a in successors(problem, s.graphs[-1], s.last)]
        out += [s for s in level if s.variables]
    return out[:60]


def test_shapes_are_kept_per_sequence_and_problem(problem, compiled) -> None:
    seq = _sequences(problem)[0]
    assert mode_shapes(problem, seq) is mode_shapes(problem, seq)
    other = build_problem(compiled("d_rotate_push"), compiled("d_rotate_push").task())
    assert mode_shapes(other, seq) is not mode_shapes(problem, seq)  # another problem: found again for it


def test_shapes_say_how_the_hand_is_attached(problem) -> None:
    for seq in _sequences(problem):
        for k, shape in enumerate(mode_shapes(problem, seq)):
            holding = seq.graphs[k].using(problem.robot_effector.name)
            assert (shape.hand == HAND_FREE) == (holding is None and not any(m == k for m, _ in seq.returns))
            tools = {e for e in seq.graphs[k].engaged if problem.effector(e.effector).tool is not None}
            assert {e for e, _, _ in shape.tools} == tools
            if shape.hand == HAND_ACTING:
                assert shape.hand_engagement in seq.graphs[k].engaged


def test_rollouts_reading_remembered_frames_equal_fresh_ones(problem) -> None:
    rng = np.random.default_rng(3)
    for seq in _sequences(problem):
        lower, upper = bounds(problem, seq, offsets=True)
        for _ in range(3):  # fills each mode's remembered contact frames and hand chains with other offsets
            rollout(problem, seq, lower + rng.uniform(0.0, 1.0, len(lower)) * (upper - lower))
        x = lower + rng.uniform(0.0, 1.0, len(lower)) * (upper - lower)
        kept, fresh = rollout(problem, seq, x), rollout(problem, dataclasses.replace(seq), x)
        for a, b in zip(kept, fresh, strict=True):
            assert all(np.array_equal(a.end[n], b.end[n]) for n in a.end)
            assert len(a.hand) == len(b.hand) and all(np.array_equal(p, q) for p, q in zip(a.hand, b.hand))
            assert a.yaw_free == b.yaw_free
