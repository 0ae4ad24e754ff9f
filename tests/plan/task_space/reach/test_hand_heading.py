"""The proof that the hand's last push on a goal body free of heading ends out of reach at every heading that lets
the body reach its goal (`vkgl.plan.task_space.reach.hand_heading`): it never rejects values task space would accept,
and it rejects what the heading-blind bounds let through."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from task_makers.far_block import block_moving_sequences, far_block_problem

from vkgl.lang.compiler import compile_file
from vkgl.plan.graphs.graph import motion_type, successors
from vkgl.plan.graphs.rollout import Sequence, bounds, extend, rollout, start_sequence
from vkgl.plan.problem.problem import GoalSpec, Problem, build_problem
from vkgl.plan.problem.rejection import Kind
from vkgl.plan.task_space.reach.hand_heading import hand_out_of_reach_at_free_heading, row_drifts
from vkgl.plan.task_space.reach.hand_reach import hand_out_of_reach_on_the_way
from vkgl.plan.task_space.reach.workspace import reach_violation
from vkgl.plan.task_space.slides import closest, position_out_of_reach, row_distances, turn_rows


@pytest.fixture(scope="module")
def problem(tmp_path_factory: pytest.TempPathFactory) -> Problem:
    return far_block_problem(Path(tmp_path_factory.mktemp("hand_heading")))


@pytest.fixture(scope="module")
def sequences(problem: Problem) -> list[Sequence]:
    return block_moving_sequences(problem)


def _verdict(problem: Problem, seq: Sequence, position: np.ndarray):
    goal = GoalSpec("block", position, None, 0.01, math.radians(3))
    own = [i for i, (_, e) in enumerate(seq.variables) if e.body == "block"]
    turns = [i for i in own if motion_type(problem, seq.variables[i][1]) == "revolute"]
    slides = [i for i in own if i not in turns]
    signs = [
        math.copysign(1.0, problem.affordance("block", seq.variables[i][1].affordance).motion.axis.array()[2])
        for i in turns
    ]
    return hand_out_of_reach_at_free_heading(problem, seq, goal, turns, slides, signs), goal, turns, slides


@settings(max_examples=12, deadline=None)
@given(
    fractions=st.lists(st.floats(0.0, 1.0), min_size=12, max_size=12),
    miss=st.tuples(st.floats(0.0, 1.0), st.floats(-math.pi, math.pi)),
)
def test_never_rejects_values_whose_last_push_stays_in_reach(problem, sequences, fractions, miss):
    # the witness: values (motions, then contacts along their families) and a goal they meet within its
    # tolerance; where the hand starts and ends its last push in reach, the proof must not reject the sequence
    # (a last turn is also proven out of reach where it starts: the body's final pose with that turn undone)
    checked = 0
    for seq in sequences:
        lower, upper = bounds(problem, seq, offsets=True)
        x = lower + np.array(fractions[: len(lower)]) * (upper - lower)
        traces = rollout(problem, seq, x)
        end = traces[-1].end["block"][:2, 3]
        goal = end + 0.01 * miss[0] * np.array([math.cos(miss[1]), math.sin(miss[1])])
        hands = [h[:3, 3] for h in traces[-1].hand]
        if not hands or any(reach_violation(problem, h) > 0.0 for h in (hands[0], hands[-1])):
            continue
        assert _verdict(problem, seq, goal)[0] is None, (seq.actions, x)
        checked += 1
    assert checked >= len(sequences) // 4


def test_rejects_what_the_heading_blind_bounds_let_through(problem, sequences):
    # 82 cm out, on the x axis: the block's turns leave it at many headings, but only at some does its push
    # reach the goal, and at those the hand's last push ends beyond the reach
    far = replace(problem, goals=[GoalSpec("block", np.array([0.82, 0.0]), None, 0.01, math.radians(3))])
    extra = []
    for seq in sequences:
        found, goal, turns, slides = _verdict(far, seq, np.array([0.82, 0.0]))
        if found is None:
            continue
        assert found.kind is Kind.REACH and "at every heading" in found.why
        if (
            position_out_of_reach(far, seq, goal, turns, slides) is None
            and hand_out_of_reach_on_the_way(far, seq) is None
        ):
            extra.append(seq)
    assert extra


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**16),
    slides=st.integers(0, 2),
)
def test_row_distances_are_the_slides_best_or_below_it(seed, slides):
    # one slide or none: the clipped projection is exactly `closest`'s answer; two: no bounds at all is a lower
    # bound of the bounded answer (what keeps a row `possible` in the scan)
    rng = np.random.default_rng(seed)
    rows = 5
    columns = rng.normal(size=(rows, 3, slides))
    origins = rng.normal(size=(rows, 3))
    position = rng.normal(size=2)
    limits = np.sort(rng.uniform(-1.0, 1.0, size=(slides, 2)), axis=1)
    found = row_distances(columns, origins, position, limits)
    for row in range(rows):
        exact = closest(columns[row], position - origins[row, :2], limits)[0]
        if slides <= 1:
            assert found[row] == pytest.approx(exact, abs=1e-9)
        else:
            assert found[row] <= exact + 1e-9


@settings(max_examples=60, deadline=None)
@given(
    travel=st.floats(0.0, 0.05),
    limit=st.floats(0.01, math.pi),
    where=st.floats(0.0, 1.0),
    toward=st.floats(-math.pi, math.pi),
    length=st.floats(0.0, 1.0),
    count=st.integers(2, 40),
)
def test_row_drifts_bound_the_pivots_travel_at_every_angle_near_the_row(travel, limit, where, toward, length, count):
    # the true angle lies within half a step of its row and within the turn's limits; the pivot moved by d
    # (|d| <= travel) moves the final position by |(I - R(a)) d|: never more than the row's drift
    limits = [(0.0, limit)]
    angles, steps = turn_rows(limits, count)
    true = where * limit
    row = int(np.argmin(np.abs(angles[:, 0] - true)))
    d = travel * length * np.array([math.cos(toward), math.sin(toward)])
    turned = np.array([[math.cos(true), -math.sin(true)], [math.sin(true), math.cos(true)]])
    moved = float(np.linalg.norm(d - turned @ d))
    drifts = row_drifts([travel], limits, angles, steps)
    assert moved <= drifts[row] + 1e-12
    assert drifts.max() <= 2.0 * travel * math.sin(limit / 2.0) + 1e-12  # never wider than the uniform slack


STICK_ARC = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.stick
use stdlib.affordances.stick
use stdlib.tools

affordances Block {
    affordance arc_back {
        action fixed at (5, 3, 0) cm yaw 180deg
        motion revolute about (-5, -30, 0) cm axis (0, 0, 1) range 0 to 120 deg
    }
}

scene s {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.62, 0.05) m yaw 0deg
    stick : Stick on table at (0.3, -0.4) m yaw 0deg
}

task t { scene s  goal block at (0.6, 0.1) m within 1 cm }
"""
"""The Block 62 cm out, turned toward the arm by the wielded Stick pushing its far face: the hand starts 35 cm
beyond that face, out of reach, and the turn swings it back within reach."""


def test_a_last_turn_that_starts_out_of_reach_is_rejected(tmp_path):
    # where the turn ends with the hand in reach, the end alone proves nothing; the body's final pose with the
    # turn undone puts the hand where it started, 22.8 cm out of reach: rejected, by no more than that
    path = tmp_path / "stick_arc.vkg"
    path.write_text(STICK_ARC, encoding="utf-8")
    program = compile_file(str(path))
    problem = build_problem(program, program.task(), max_depth=3)
    seq = start_sequence(problem)
    for label in ("add Stick.wield on stick with arm.fingertip", "add Block.arc_back on block with stick.tip"):
        action = next(a for a in successors(problem, seq.graphs[-1], seq.last) if a.label(problem) == label)
        seq, _ = extend(problem, seq, action)
    lower, upper = bounds(problem, seq, offsets=True)
    proven = 0
    for fraction in np.linspace(0.0, 1.0, 9):
        x = lower + fraction * (upper - lower)
        traces = rollout(problem, seq, x)
        start, end = (reach_violation(problem, h[:3, 3]) for h in (traces[-1].hand[0], traces[-1].hand[-1]))
        goal = traces[-1].end["block"][:2, 3]
        found = _verdict(replace(problem, goals=[GoalSpec("block", goal, None, 0.01, 0.05)]), seq, goal)[0]
        assert found is not None and found.excess <= max(start, end) + 1e-6  # never past the true violation
        if end <= 0.0:
            assert "where that turn starts or ends" in found.why
            proven += 1
    assert proven >= 3
