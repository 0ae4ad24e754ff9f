"""The closed form's test of goals that leave the heading free (`vkgl.plan.task_space.slides`): it must never
reject a sequence some motion values of which reach the goal (it saves the optimiser's four failing starts)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vkgl.lang.compiler import compile_file
from vkgl.lang.ir.nodes import RevoluteC, Vector
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.motions import _motion_matrices
from vkgl.plan.graphs.rollout import Sequence, bounds, extend, rollout, start_sequence
from vkgl.plan.problem.problem import GoalSpec, Problem, build_problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.closed_form import closed_form
from vkgl.plan.task_space.reach.workspace import reach_violation, unreachable
from vkgl.plan.task_space.slides import turn_matrices

PROGRAM = """
use stdlib.robots.panda
use stdlib.bodies.block

affordances Block {
    affordance push_px {
        action fixed at (-5, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 12 cm
    }
    affordance push_py {
        action fixed at (0, -5, 0) cm yaw 90deg
        motion prismatic along (0, 1, 0) from (0, 0, 0) cm range 0 to 6 cm
    }
    affordance turn_left {
        action fixed at (-5, 6.56, 0) cm yaw 0deg
        motion revolute about (-0.54, -11.1, 0) cm axis (0, 0, -1) range 0 to 40 deg
        family along (0, 1, 0) from 0 to 2.66 cm drift (0.288, 2.214, 0) sigma 1.37 cm
    }
    affordance turn_right {
        action fixed at (-5, -6.56, 0) cm yaw 0deg
        motion revolute about (3, 9, 0) cm axis (0, 0, 1) range 0 to 25 deg
        family along (0, 1, 0) from -2.66 to 0 cm drift (-0.586, 1.894, 0) sigma 1.87 cm
    }
}

scene s {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.5, 0.05) m yaw 20deg
}

task t { scene s  goal block at (0.6, 0.1) m within 1 cm }
"""

DEPTH = 5
"""Graphs in the longest sequence enumerated (G0 included): up to two contacts, so up to two turns."""


@pytest.fixture(scope="module")
def problem(tmp_path_factory: pytest.TempPathFactory) -> Problem:
    path = Path(tmp_path_factory.mktemp("slides")) / "free_heading.vkg"
    path.write_text(PROGRAM, encoding="utf-8")
    program = compile_file(str(path))
    return build_problem(program, program.task(), max_depth=DEPTH)


def _moving(problem: Problem, depth: int = DEPTH) -> list[Sequence]:
    """Every sequence of at most `depth` graphs the search would make whose last mode moves the block."""
    found, layer = [], [start_sequence(problem)]
    while layer:
        deeper = []
        for seq in layer:
            if seq.depth >= depth:
                continue
            for action in successors(problem, seq.graphs[-1], seq.last):
                child, hand = extend(problem, seq, action)
                if hand is not None and unreachable(problem, hand) is not None:
                    continue
                deeper.append(child)
                if any(m == child.depth - 1 for m, _ in child.variables):
                    found.append(child)
        layer = deeper
    return found


def _goal_at(problem: Problem, position: np.ndarray, tolerance: float = 0.01) -> Problem:
    return replace(problem, goals=[GoalSpec("block", position, None, tolerance, math.radians(3))])


@settings(max_examples=12, deadline=None)  # 12 draws x 20 sequences: 240 witnesses, 55 ms each
@given(fractions=st.lists(st.floats(0.0, 1.0), min_size=12, max_size=12))
def test_a_position_some_values_reach_is_never_rejected(problem, fractions):
    # the witness: values (motions, then the turns' contacts along their families) and where they put the block
    sequences = _moving(problem)
    assert max(sum(1 for _, e in s.variables if "turn" in e.affordance) for s in sequences) == 2
    assert any(s.offsets for s in sequences)
    for seq in sequences:
        lower, upper = bounds(problem, seq, offsets=True)
        x = lower + np.array(fractions[: len(lower)]) * (upper - lower)
        last = rollout(problem, seq, x)[-1]
        # a tenth of a millimetre: the scan's rows miss the witness's angles by far more (the slack must cover it)
        verdict = closed_form(_goal_at(problem, last.end["block"][:2, 3], 1e-4), seq)
        if isinstance(verdict, Rejection) and verdict.kind is Kind.REACH:  # the hand on the block at the end
            assert last.hand and reach_violation(problem, last.hand[-1][:3, 3]) > 0, (seq.actions, x, verdict.why)
            continue
        assert not isinstance(verdict, Rejection), (seq.actions, x, verdict.why)


def test_a_position_no_values_reach_is_rejected_before_any_optimisation(problem):
    # 60 cm away: farther than every slide and chord of these motions together
    sequences = _moving(problem)
    far = _goal_at(problem, np.array([1.1, 0.05]))
    verdicts = [closed_form(far, seq) for seq in sequences]
    assert all(isinstance(v, Rejection) and v.kind is Kind.POSITION for v in verdicts)
    assert any("whatever heading it ends with" in v.why for v in verdicts if isinstance(v, Rejection))


@settings(max_examples=30, deadline=None)
@given(
    axis=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(0.1, 1)),
    center=st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2), st.floats(-0.1, 0.1)),
)
def test_the_scans_turn_matrices_are_the_planners_up_to_rounding(axis, center):
    motion = RevoluteC(center=Vector(values=center), axis=Vector(values=axis))
    angles = np.linspace(0.0, math.pi, 37)
    assert np.allclose(turn_matrices(motion, angles), _motion_matrices(motion, angles), atol=1e-12)


def test_a_goal_the_hand_on_the_block_cannot_follow_at_any_heading_is_rejected_for_reach(tmp_path):
    # the block 78 cm from the arm's base, to end 8 cm farther (its slides reach that): pushed from a face's
    # centre (5 cm from the block's), the hand would be out of the arm's reach (about 79 cm there) at any
    # heading; those sequences are rejected without optimising. Those from the turns' contacts (8 cm off) are
    # not by that ring, but by the headings the turns can give (`hand_reach`: the contact stays on the far side)
    path = tmp_path / "edge.vkg"
    path.write_text(PROGRAM.replace("at (0.5, 0.05) m yaw 20deg", "at (0.78, 0) m yaw 0deg"), encoding="utf-8")
    program = compile_file(str(path))
    problem = _goal_at(build_problem(program, program.task()), np.array([0.86, 0.0]))
    verdicts = {seq.actions[-1].label(problem): closed_form(problem, seq) for seq in _moving(problem, 2)}
    reach = {k: v.why for k, v in verdicts.items() if isinstance(v, Rejection) and v.kind is Kind.REACH}
    assert any("push_px" in label for label in reach) and any("turn" in label for label in reach)
    assert all(("at any heading" in why) != ("turn" in label) for label, why in reach.items())


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.tuples(st.floats(-1.2, 1.2), st.floats(-1.2, 1.2)), min_size=1, max_size=12),
    st.sampled_from([0.02, 0.05, 0.3]),
    st.booleans(),
)
def test_the_reach_of_many_points_is_each_points_reach(problem, xy, height, planar) -> None:
    from vkgl.plan.task_space.reach.workspace import reach_violations

    # planar: one height (the optimiser's hot path); otherwise three heights 1 mm apart, each for several points
    # (every new height costs a reach computation, a third of a second: three per drawn height keep that bounded)
    heights = [height if planar else height + 0.001 * (k % 3) for k in range(len(xy))]
    points = np.array([(x, y, z) for (x, y), z in zip(xy, heights)])
    each = [reach_violation(problem, p) for p in points]
    np.testing.assert_allclose(reach_violations(problem, points), each, rtol=0, atol=1e-12)


def test_affine_positions_are_remembered_as_computed(problem) -> None:
    from vkgl.plan.task_space import slides

    for seq in _moving(problem)[:40]:
        own = [i for i, (_, e) in enumerate(seq.variables) if e.body == "block"]
        motions = {i: problem.affordance("block", seq.variables[i][1].affordance).motion for i in own}
        turns = [i for i in own if isinstance(motions[i], RevoluteC)]
        slides_ = [i for i in own if i not in turns]
        angles = np.linspace(0.0, 1.0, 7 * len(turns)).reshape(7, len(turns)) if turns else np.zeros((1, 0))
        first = slides.affine_positions(problem, seq, "block", turns, slides_, angles)
        slides._AFFINE.clear()
        fresh = slides.affine_positions(problem, seq, "block", turns, slides_, angles)
        again = slides.affine_positions(problem, seq, "block", turns, slides_, angles)
        assert again[0] is fresh[0]  # remembered
        for a, b in zip(first, fresh):
            assert np.array_equal(a, b)


def test_remembered_affine_positions_keep_no_dropped_problem_alive(problem) -> None:
    """The cache is one for every problem (its cap bounds them all) and names each problem weakly: a copy of
    the problem remembered and then dropped is freed, and its entries are not served to another problem."""
    import gc
    import weakref

    from vkgl.plan.task_space import slides

    seq = next(s for s in _moving(problem) if any(e.body == "block" for _, e in s.variables))
    own = [i for i, (_, e) in enumerate(seq.variables) if e.body == "block"]
    copy = replace(problem)
    slides.affine_positions(copy, seq, "block", [], own, np.zeros((1, 0)))
    dropped = weakref.ref(copy)
    del copy
    gc.collect()
    assert dropped() is None
    assert any(entry[0]() is None for entry in slides._AFFINE.values())  # its entry stays (until the cap), dead


def test_remembered_body_constraints_give_the_numbers_computed_afresh(problem) -> None:
    from vkgl.plan.task_space.constraints.values import constraint_values

    placed: dict[tuple[str, bytes], list[float]] = {}
    rng = np.random.default_rng(5)
    for seq in _moving(problem)[:40]:
        lower, upper = bounds(problem, seq)
        x = lower + rng.uniform(0.0, 1.0, len(lower)) * (upper - lower)
        traces = rollout(problem, seq, x)
        fresh = constraint_values(problem, traces)
        for _ in range(2):  # filling the memo, then reading it
            np.testing.assert_allclose(constraint_values(problem, traces, placed), fresh, rtol=0, atol=1e-12)
    assert placed  # the sequences moved bodies: their constraints were kept


def test_closed_form_is_remembered_per_sequence_and_answers_as_computed_afresh(problem, monkeypatch) -> None:
    from vkgl.plan.task_space import closed_form as module

    # The memo is cleared when full: one left nearly full by earlier tests in this process would be cleared between
    # the two rounds below and the test would depend on the order of tests.
    monkeypatch.setattr(module, "_CLOSED_FORMS", {})
    sequences = _moving(problem, 3)
    first = [module.remembered_closed_form(problem, seq) for seq in sequences]
    calls: list[Sequence] = []
    real = module.closed_form
    monkeypatch.setattr(module, "closed_form", lambda p, s: calls.append(s) or real(p, s))
    again = [module.remembered_closed_form(problem, seq) for seq in sequences]
    assert calls == []  # every sequence's answer was remembered
    for seq, one, two in zip(sequences, first, again, strict=True):
        fresh = real(problem, seq)
        if isinstance(fresh, Rejection):
            assert one is two and isinstance(one, Rejection) and one.why == fresh.why
        else:
            assert not isinstance(one, Rejection) and not isinstance(two, Rejection)
            assert one[1] == two[1] == fresh[1]
            np.testing.assert_allclose(two[0], fresh[0], rtol=0, atol=1e-12)
            assert two[0] is not one[0]  # each caller's own array
    module.remembered_closed_form(_goal_at(problem, np.array([0.5, 0.0])), sequences[0])
    assert len(calls) == 1  # another problem: computed for it
