"""The order in which the search checks sequences (`vkgl.plan.search.search`).

A sequence without bound left is expanded one level later than it is checked (`search._Entry`): the order of
checks must be the one of expanding it at once, and a deeper `max_depth` must only add checks after those of a
shallower one (so that raising the default keeps every plan found within the old one).
"""

from __future__ import annotations

import heapq
import time

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from task_makers.block_problems import ASIDE, IN_THE_WAY, block_to, labels

import vkgl.plan.search.search as search_module
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, start_sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.task_space.reach.workspace import unreachable


def _checked_by_search(problem: Problem, monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, ...]]:
    """The sequences `search` checks, in order, every check failing (so that it goes through all of them)."""
    checked: list[tuple[str, ...]] = []

    def failing(problem_: Problem, seq: Sequence, *args: object, **kwargs: object) -> None:
        checked.append(labels(problem_, seq))

    monkeypatch.setattr(search_module, "check", failing)
    result = search_module.search(problem, deadline=time.perf_counter() + 600)
    assert result.status == "infeasible"
    return checked


def _checked_expanding_at_once(problem: Problem) -> list[tuple[str, ...]]:
    """The same, by the best-first search that makes every sequence's children as soon as it leaves the queue."""
    bound, in_the_way = Bound(problem), InTheWay(problem)
    root = start_sequence(problem)
    frontier: list[tuple[float, int, tuple[int, ...], Sequence]] = [(root.depth + bound(root), 0, (), root)]
    checked = []
    while frontier:
        level, _, path, seq = heapq.heappop(frontier)
        if seq.actions and level == seq.depth and search_module._moves_goal_body(problem, seq):
            checked.append(labels(problem, seq))
        if seq.depth >= problem.max_depth:
            continue
        for index, action in enumerate(successors(problem, seq.graphs[-1], seq.last)):
            child, hand = extend(problem, seq, action)
            if hand is not None and unreachable(problem, hand) is not None:
                continue
            total = child.depth + bound(child)
            if total <= problem.max_depth:
                heapq.heappush(frontier, (total, in_the_way.left(child), path + (index,), child))
    return checked


def test_the_bodies_in_the_way_are_those_near_the_straight_way_to_the_goal(tmp_path):
    assert InTheWay(block_to(tmp_path, 0.8, True, False, 6, IN_THE_WAY)).bodies == {"other"}
    assert InTheWay(block_to(tmp_path, 0.8, True, False, 6, ASIDE)).bodies == frozenset()


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    gx=st.sampled_from([0.7, 0.8, 0.95]),
    stick=st.booleans(),
    grasp=st.booleans(),
    other=st.sampled_from(["", IN_THE_WAY, ASIDE]),
)
def test_checks_come_in_the_order_of_expanding_each_sequence_at_once(tmp_path, monkeypatch, gx, stick, grasp, other):
    problem = block_to(tmp_path, gx, stick, grasp, 6, other)
    # (a goal past the fingertip's reach without the stick: nothing to check in either)
    assert _checked_by_search(problem, monkeypatch) == _checked_expanding_at_once(problem)


def test_within_a_level_the_sequences_that_moved_the_body_in_the_way_are_checked_first(tmp_path, monkeypatch):
    # one push of the block, or the other Block pushed first: 1 or 3 actions
    problem = block_to(tmp_path, 0.8, False, False, 4, IN_THE_WAY, yaw="", slide=30, gy=0.0)
    checked = _checked_by_search(problem, monkeypatch)
    levels = sorted({len(c) for c in checked})
    assert levels and any(any("on other" in a for a in c) for c in checked)
    mixed = 0
    for level in levels:
        moved = ["on other" in " ".join(c) for c in checked if len(c) == level]
        assert moved == sorted(moved, reverse=True), f"at {level} actions a sequence moving the block alone came first"
        mixed += len(set(moved)) == 2
    assert mixed, "some level must have sequences of both kinds"


def test_a_deeper_max_depth_checks_the_shallower_ones_checks_first(tmp_path, monkeypatch):
    # every sequence a search to 5 graphs checks is checked, in the same order, before any other by a search to 7
    shallow = _checked_by_search(block_to(tmp_path, 0.7, True, False, depth=5), monkeypatch)
    deep = _checked_by_search(block_to(tmp_path, 0.7, True, False, depth=7), monkeypatch)
    assert shallow and len(deep) > len(shallow)
    assert deep[: len(shallow)] == shallow
