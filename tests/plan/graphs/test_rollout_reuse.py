"""Rollouts that reuse unchanged modes (`vkgl.plan.graphs.reuse`) equal full rollouts, bit for bit.

The optimiser's evaluations go through `Rollouts`; the search must do the same work with it as with
`rollout`, so the two are compared exactly (the same operations on the same inputs: no tolerance), over random
sequences of the rotate-push and pick-and-place examples (tools, families with offsets, releases, carries) and
random value vectors, some of them finite-difference steps of others (one value moved: the case the reuse is
for).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.reuse import Rollouts, mode_ranges
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, bounds, extend, rollout, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem


@pytest.fixture(scope="module")
def problem(compiled):
    program = compiled("d_rotate_push")
    return build_problem(program, program.task())


@pytest.fixture(scope="module")
def carrying(compiled):
    program = compiled("n_pick_place")
    return build_problem(program, program.task())


def _walk(problem: Problem, choices: list[int]) -> Sequence:
    """The sequence that takes, at each graph, the successor `choice` (modulo their number)."""
    seq = start_sequence(problem)
    for choice in choices:
        options = successors(problem, seq.graphs[-1], seq.last)
        if not options:
            break
        seq, _ = extend(problem, seq, options[choice % len(options)])
    return seq


def _same(a: list[ModeTrace], b: list[ModeTrace]) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.start.keys() == y.start.keys() and x.end.keys() == y.end.keys()
        assert all(np.array_equal(x.start[n], y.start[n]) for n in x.start)
        assert all(np.array_equal(x.end[n], y.end[n]) for n in x.end)
        assert len(x.hand) == len(y.hand) and all(np.array_equal(p, q) for p, q in zip(x.hand, y.hand))
        assert x.yaw_free == y.yaw_free and x.values == y.values
        assert x.carried.keys() == y.carried.keys()
        assert all(np.array_equal(x.carried[e], y.carried[e]) for e in x.carried)


@settings(max_examples=40, deadline=None)
@given(
    choices=st.lists(st.integers(0, 10_000), min_size=1, max_size=5),
    fractions=st.lists(st.floats(0.0, 1.0), min_size=1, max_size=4),
    steps=st.lists(st.integers(0, 20), max_size=6),
)
def test_a_reused_rollout_equals_the_full_rollout(problem, carrying, choices, fractions, steps):
    for each in (problem, carrying):
        _check_points(each, _walk(each, choices), fractions, steps)


def test_a_reused_rollout_of_a_carry_equals_the_full_rollout(carrying):
    walks = ([a, b, c] for a in range(6) for b in range(6) for c in range(6))
    seq = next(s for s in (_walk(carrying, w) for w in walks) if s.carries and s.variables)
    _check_points(carrying, seq, [0.0, 0.3, 0.8], [0, 1, 2, 3, 4, 5])


def _check_points(problem: Problem, seq: Sequence, fractions: list[float], steps: list[int]) -> None:
    """Points at `fractions` of every value's range, then steps of the last of them: reused == full."""
    lower, upper = bounds(problem, seq, offsets=True)
    upper = np.minimum(upper, lower + 1.0)  # (the caps are 2 m and pi: a metre is plenty)
    rollouts = Rollouts(problem, seq, 5)
    points = [lower + f * (upper - lower) for f in fractions]
    for i in steps:  # finite-difference steps of the last point, one value each
        if seq.size:
            step = points[-1].copy()
            step[i % seq.size] += 1e-7
            points.append(step)
    for values in points + points[:1]:  # the first point again: wholly remembered
        _same(rollouts.rollout(values), rollout(problem, seq, values, 5))


def test_a_step_rolls_out_only_the_modes_from_its_values_mode_on(problem):
    choices = [0, 0, 0, 0]  # four graphs, each the first successor
    seq = _walk(problem, choices)
    while not seq.variables:  # (the first successors may grasp a tool first: walk on)
        choices.append(0)
        seq = _walk(problem, choices)
    lower, upper = bounds(problem, seq, offsets=True)
    values = (lower + np.minimum(upper, lower + 1.0)) / 2
    rollouts = Rollouts(problem, seq, 5)
    rollouts.rollout(values)
    assert rollouts.modes_rolled == seq.depth
    last_mode = seq.variables[-1][0]
    step = values.copy()
    step[len(seq.variables) - 1] += 1e-7
    _same(rollouts.rollout(step), rollout(problem, seq, step, 5))
    assert rollouts.modes_rolled == seq.depth + seq.depth - last_mode
    rollouts.rollout(values)
    assert rollouts.modes_rolled == seq.depth + seq.depth - last_mode  # nothing new


def test_the_values_each_mode_reads(problem):
    seq = _walk(problem, [0, 0, 0, 0, 0])
    ranges = mode_ranges(seq, seq.size)
    read = sorted(i for mode in ranges for r in mode for i in range(seq.size)[r])
    assert read == list(range(seq.size))  # every value is read by exactly one mode
    for mode, ranges_of_mode in enumerate(ranges):
        for r in ranges_of_mode:
            for i in range(seq.size)[r]:
                if i < len(seq.variables):
                    assert seq.variables[i][0] == mode
    with pytest.raises(ValueError):
        mode_ranges(seq, seq.size + 1)
