"""The order in which the search checks sequences (`vkgl.plan.search.search`).

A sequence without bound left is expanded one level later than it is checked (`search._Entry`): the order of
checks must be the one of expanding it at once, and a deeper `max_depth` must only add checks after those of a
shallower one (so that raising the default keeps every plan found within the old one).
"""

from __future__ import annotations

import heapq
import time
from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_bound import GRASP, _problem

import vkgl.plan.search.search as search_module
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, start_sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.search.bound import Bound
from vkgl.plan.task_space.workspace import unreachable

STICK = "    stick : Stick on table at (0.3, -0.4) m yaw 0deg\n"


def _labels(problem: Problem, seq: Sequence) -> tuple[str, ...]:
    return tuple(a.label(problem) for a in seq.actions)


def _checked_by_search(problem: Problem, monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, ...]]:
    """The sequences `search` checks, in order, every check failing (so that it goes through all of them)."""
    checked: list[tuple[str, ...]] = []

    def failing(problem_: Problem, seq: Sequence, *args: object, **kwargs: object) -> None:
        checked.append(_labels(problem_, seq))

    monkeypatch.setattr(search_module, "_check", failing)
    result = search_module.search(problem, deadline=time.perf_counter() + 600)
    assert result.status == "infeasible"
    return checked


def _checked_expanding_at_once(problem: Problem) -> list[tuple[str, ...]]:
    """The same, by the best-first search that makes every sequence's children as soon as it leaves the queue."""
    bound = Bound(problem)
    root = start_sequence(problem)
    frontier: list[tuple[float, tuple[int, ...], Sequence]] = [(root.depth + bound(root), (), root)]
    checked = []
    while frontier:
        level, path, seq = heapq.heappop(frontier)
        if seq.actions and level == seq.depth and search_module._moves_goal_body(problem, seq):
            checked.append(_labels(problem, seq))
        if seq.depth >= problem.max_depth:
            continue
        for index, action in enumerate(successors(problem, seq.graphs[-1], seq.last)):
            child, hand = extend(problem, seq, action)
            if hand is not None and unreachable(problem, hand) is not None:
                continue
            total = child.depth + bound(child)
            if total <= problem.max_depth:
                heapq.heappush(frontier, (total, path + (index,), child))
    return checked


def _block(tmp_path: Path, gx: float, stick: bool, grasp: bool, depth: int) -> Problem:
    problem = _problem(
        tmp_path,
        x=0.6,
        gx=gx,
        gy=0.04,
        yaw=" yaw -20deg",
        slide=10,
        turn=25,
        stick=STICK if stick else "",
        grasp=GRASP if grasp else "",
    )
    return replace(problem, max_depth=depth)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(gx=st.sampled_from([0.7, 0.8, 0.95]), stick=st.booleans(), grasp=st.booleans())
def test_checks_come_in_the_order_of_expanding_each_sequence_at_once(tmp_path, monkeypatch, gx, stick, grasp):
    problem = _block(tmp_path, gx, stick, grasp, depth=6)
    # (a goal past the fingertip's reach without the stick: nothing to check in either)
    assert _checked_by_search(problem, monkeypatch) == _checked_expanding_at_once(problem)


def test_a_deeper_max_depth_checks_the_shallower_ones_checks_first(tmp_path, monkeypatch):
    # every sequence a search to 5 graphs checks is checked, in the same order, before any other by a search to 7
    shallow = _checked_by_search(_block(tmp_path, 0.7, True, False, depth=5), monkeypatch)
    deep = _checked_by_search(_block(tmp_path, 0.7, True, False, depth=7), monkeypatch)
    assert shallow and len(deep) > len(shallow)
    assert deep[: len(shallow)] == shallow
