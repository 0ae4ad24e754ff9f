"""The bound's parts that look at one contact at a time (`vkgl.plan.search.bounds.bound`, parts 6 and 7): a
contact the hand (or a tool held one way) cannot hold where the goal puts the body does not end it there
(`goal_reach.wrong_ends`), and a contact whose one mode from rest cannot put the body there does not end a
sequence that moved the body once (`one_mode.missing_movers`). Each is checked against exhaustive search (the bound
never exceeds the true remaining depth) and against sampled poses."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st
from task_makers.block_problems import STICK, block_problem, drawn_block_problem
from test_bound import _assert_the_bound_never_exceeds_the_true_remaining_depth, _children, _remaining

from vkgl.plan.graphs.rollout import Sequence, start_sequence
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.task_space.reach.workspace import unreachable


@pytest.mark.parametrize(("gx", "yaw", "wrong"), [(0.86, "", "push_px"), (0.84, " yaw -20deg", "turn_left")])
def test_a_contact_the_hand_cannot_hold_at_the_goal_does_not_end_it_there(tmp_path, gx, yaw, wrong):
    # part 6 contact by contact: the hand can end the block there by one of its affordances, not by the other
    problem = block_problem(tmp_path, x=0.6, gx=gx, gy=0, yaw=yaw, slide=30, turn=25, stick=STICK)
    bound = Bound(problem)
    (need,) = bound.needs
    assert not need.ends_by_tool and need.cannot_end((None, None, wrong))
    assert {m for tool, _, m in need.ends_that_cannot() if tool is None} == {wrong}
    root = start_sequence(problem)
    pushed = next(
        c
        for c in _children(problem, root)
        if c.last.engagement.affordance == wrong and c.last.engagement.effector == problem.robot_effector.name
    )
    assert bound(pushed) >= 2  # let go, and a contact that can end it there
    seen: list[tuple[Sequence, float]] = []
    assert _remaining(problem, pushed, seen) >= bound(pushed)
    _assert_the_bound_never_exceeds_the_true_remaining_depth(problem)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    gx=st.floats(0.78, 0.9), gy=st.floats(-0.15, 0.15), yaw=st.sampled_from([None, -20, 20]), seed=st.integers(0, 99)
)
def test_a_contact_called_wrong_has_every_hand_pose_at_the_goal_out_of_reach(tmp_path, gx, gy, yaw, seed):
    from vkgl.plan.graphs.graph import Engagement, KGraph
    from vkgl.plan.graphs.rollout import hand_chain
    from vkgl.se3 import yaw_of

    problem = drawn_block_problem(tmp_path, x=0.6, gx=gx, gy=gy, yaw=yaw, stick=STICK)
    goal, block = problem.goals[0], problem.bodies["block"]
    rng = np.random.default_rng(seed)
    for tool, grasp, mover in Bound(problem).needs[0].ends_that_cannot() if Bound(problem).needs else ():
        effector = problem.robot_effector.name if tool is None else "stick.tip"
        graph = KGraph(() if tool is None else (Engagement(problem.robot_effector.name, tool, grasp),))
        chain = hand_chain(problem, graph, Engagement(effector, "block", mover))
        assert chain is not None
        for _ in range(100):  # poses the goal accepts
            radius, angle = goal.tol_position * np.sqrt(rng.uniform()), rng.uniform(0, 2 * math.pi)
            heading = (
                rng.uniform(-math.pi, math.pi) if goal.yaw is None else goal.yaw + rng.uniform(-1, 1) * goal.tol_yaw
            )
            turn = heading - yaw_of(block.rest)
            pose = block.rest.copy()
            pose[:3, :3] = np.array(
                [[math.cos(turn), -math.sin(turn), 0], [math.sin(turn), math.cos(turn), 0], [0, 0, 1]]
            )
            pose[:2, 3] = goal.position[:2] + radius * np.array([math.cos(angle), math.sin(angle)])
            assert unreachable(problem, pose @ chain[0]) is not None, (tool, grasp, mover)


def test_a_contact_whose_one_mode_from_rest_misses_the_goal_is_not_the_last(tmp_path):
    # part 7: the turn cannot take the block from rest to a goal straight ahead, the slide can
    problem = block_problem(tmp_path, x=0.45, gx=0.6, gy=0, yaw="", slide=30, turn=25, stick="")
    bound = Bound(problem)
    assert bound.needs[0].misses == {"turn_left"}
    turned = next(c for c in _children(problem, start_sequence(problem)) if c.last.engagement.affordance == "turn_left")
    assert bound(turned) == 2  # let go, push
    seen: list[tuple[Sequence, float]] = []
    assert _remaining(problem, turned, seen) >= 2
    _assert_the_bound_never_exceeds_the_true_remaining_depth(problem)


def test_a_goal_no_one_contact_reaches_from_rest_needs_two(tmp_path):
    # 4 cm off the slide's line, out of the turn's arc: two contacts and a break between them at least
    problem = block_problem(tmp_path, x=0.45, gx=0.6, gy=0.04, yaw="", slide=30, turn=25, stick="")
    bound = Bound(problem)
    assert bound.needs[0].misses == {"push_px", "turn_left"}
    assert bound(start_sequence(problem)) == 3
    assert "at least 2 contacts" in bound.explain()
    _assert_the_bound_never_exceeds_the_true_remaining_depth(problem)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    gx=st.floats(0.4, 0.75),
    gy=st.floats(-0.15, 0.15),
    yaw=st.sampled_from([None, -20, 10]),
    family=st.booleans(),
    seed=st.integers(0, 99),
)
def test_a_contact_said_to_miss_never_ends_the_body_at_the_goal_in_one_mode(tmp_path, gx, gy, yaw, family, seed):
    from vkgl.plan.graphs.graph import Engagement
    from vkgl.plan.graphs.members import contact_band
    from vkgl.plan.graphs.motions import member_motions
    from vkgl.plan.graphs.rollout import value_bounds
    from vkgl.plan.task_space.feasible import goal_holds

    problem = drawn_block_problem(tmp_path, x=0.45, gx=gx, gy=gy, yaw=yaw, family=family)
    rng = np.random.default_rng(seed)
    block = problem.bodies["block"]
    for need in Bound(problem).needs:
        for name in need.misses:
            low, high = value_bounds(problem.affordance("block", name).motion)
            band = contact_band(problem, "block", name)
            engagement = Engagement(problem.robot_effector.name, "block", name)
            for _ in range(200):
                offset = float(rng.uniform(*band)) if band[1] > band[0] else 0.0
                values = rng.uniform(low, high, 8)
                for motion in member_motions(problem, engagement, offset, values):
                    assert not goal_holds(problem, {"block": block.rest @ motion}), (name, offset)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    x=st.sampled_from([0.45, 0.6, 0.7]),
    gx=st.floats(0.7, 0.95),
    gy=st.floats(-0.1, 0.1),
    yaw=st.sampled_from([None, -20]),
    family=st.booleans(),
    seed=st.integers(0, 99),
)
def test_an_effector_said_to_miss_in_one_mode_leaves_the_hand_out_of_reach_wherever_it_ends_it(
    tmp_path, x, gx, gy, yaw, family, seed
):
    # part 7 with the hand: one mode from rest that ends the block at its goal has a hand sample out of reach
    from vkgl.plan.graphs.graph import Engagement, KGraph
    from vkgl.plan.graphs.members import contact_band
    from vkgl.plan.graphs.motions import member_motions
    from vkgl.plan.graphs.rollout import hand_chain, value_bounds
    from vkgl.plan.task_space.feasible import TASK_SAMPLES, goal_holds

    problem = drawn_block_problem(tmp_path, x=x, gx=gx, gy=gy, yaw=yaw, stick=STICK, family=family)
    rng = np.random.default_rng(seed)
    block = problem.bodies["block"]
    checked = 0
    for need in Bound(problem).needs:
        for tool, grasp, mover in need.missed_ends:
            effector = problem.robot_effector.name if tool is None else "stick.tip"
            graph = KGraph(() if tool is None else (Engagement(problem.robot_effector.name, tool, grasp),))
            engagement = Engagement(effector, "block", mover)
            low, high = value_bounds(problem.affordance("block", mover).motion)
            band = contact_band(problem, "block", mover)
            for _ in range(20):  # offsets at random, values on a fine grid: those that end it at its goal
                offset = float(rng.uniform(*band)) if band[1] > band[0] else 0.0
                ends = block.rest @ member_motions(problem, engagement, offset, np.linspace(low, high, 2001))
                chain = hand_chain(problem, graph, engagement, offset)
                assert chain is not None
                for value in np.linspace(low, high, 2001)[[goal_holds(problem, {"block": e}) for e in ends]]:
                    checked += 1
                    samples = np.linspace(0.0, float(value), TASK_SAMPLES)
                    hands = block.rest @ member_motions(problem, engagement, offset, samples) @ chain[0]
                    assert any(unreachable(problem, hand) is not None for hand in hands), (tool, grasp, mover, value)
    note(f"{checked} values that end the block at its goal checked")
