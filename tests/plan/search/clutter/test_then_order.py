"""Clear first, then solve: the searches for the goals after the plans that clear the way
(`vkgl.plan.search.clutter.clear_first._clear_then_solve`) first get a small budget each, and those that spend it
are searched again once every side had its first try, the plan that left the goal body where it lies first.

The walk's searches are stubbed here (no planning runs): what is tested is where the work goes."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from test_work_budget import BLOCKED

import vkgl
from vkgl.plan.graphs.graph import g0
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.search.clutter import clear_first
from vkgl.plan.search.search import SearchResult
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.clearing import Side

SCENE = BLOCKED.replace("    search { max_depth 3  timeout 60 s }\n", "")
"""test_work_budget's Block with another across its way, the task's search block left to the defaults."""

LEFT = Side("left", np.array([0.0, -1.0, -0.1]), 0.05)
RIGHT = Side("right", np.array([0.0, 1.0, -0.1]), 0.05)


def _problem(tmp_path: Path) -> Problem:
    program = vkgl.compile_source(SCENE, "through.vkg", base_dir=tmp_path)
    return build_problem(program, program.tasks["through"])


def _prefix(depth: int, moved: frozenset[str]) -> Sequence:
    return Sequence(graphs=(g0(),) * depth, dependent=moved)


class _Recorder:
    """A stub of `search`: every call recorded as (root's depth, budget), each ending as `outcome` says."""

    def __init__(self, outcome: object) -> None:
        self.calls: list[tuple[int, float]] = []
        self.outcome = outcome

    def __call__(
        self,
        problem: Problem,
        *,
        deadline: float,
        progress: bool,
        root: Sequence,
        budget: float,
        still: frozenset[str] = frozenset(),
        paused: object = None,
    ) -> object:
        self.calls.append((root.depth, budget))
        stats = SearchStats()
        stats.graphs_expanded = 20  # 1 unit of work (`WORK_WEIGHTS`)
        status = self.outcome(root, budget)  # type: ignore[operator]
        return SearchResult(
            status, "", stats, sequence=_prefix(root.depth + 1, frozenset()) if status == "solved" else None
        )


def _walk(problem: Problem, prefixes: list[object]) -> clear_first._Walk:
    walk = clear_first._Walk(problem, math.inf, False, SearchStats(), 1000.0)

    def stub(blocking: object, root: object, pinned: object = ()) -> Iterator[object]:
        yield from prefixes

    walk.prefixes = stub  # type: ignore[method-assign]
    return walk


def test_the_search_after_a_prefix_that_left_the_goal_body_still_goes_first_in_the_second_round(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A prefix that pushed the goal body back (4 graphs, found first) and one that did not (3 graphs, found
    second): each search for the goals first gets `THEN_FIRST` of the work left, in the order found; once the
    round is over (the marker), the one that left the block where it lies is searched with `THEN_SHARE` first."""
    problem = _problem(tmp_path)
    back = (_prefix(4, frozenset({"block", "block2"})), (), [("block2", LEFT)])
    aside = (_prefix(3, frozenset({"block2"})), (), [("block2", RIGHT)])
    recorder = _Recorder(lambda root, budget: "timeout")
    monkeypatch.setattr(clear_first, "search", recorder)
    walk = _walk(problem, [back, aside, None])
    assert clear_first._clear_then_solve(walk, [], Sequence(), 6) is None
    first, second = recorder.calls[:2], recorder.calls[2:]
    assert [depth for depth, _ in first] == [4, 3]
    assert [depth for depth, _ in second] == [3, 4]
    assert first[0][1] == pytest.approx(clear_first.THEN_FIRST * 1000.0)
    assert second[0][1] == pytest.approx(clear_first.THEN_SHARE * (1000.0 - 2.0))  # 1 unit per search spent
    assert all(budget > first[0][1] for _, budget in second)
    assert len(walk.log) == 2 and walk.log[0].startswith("block2 right of the way (3 graphs)")


def test_a_prefix_whose_first_search_finds_the_plan_ends_the_walk_at_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The second prefix's small search finds the plan: nothing is searched again, and the words say how the way
    was cleared."""
    problem = _problem(tmp_path)
    back = (_prefix(4, frozenset({"block", "block2"})), (), [("block2", LEFT)])
    aside = (_prefix(3, frozenset({"block2"})), (), [("block2", RIGHT)])
    recorder = _Recorder(lambda root, budget: "solved" if root.depth == 3 else "timeout")
    monkeypatch.setattr(clear_first, "search", recorder)
    cleared = clear_first._clear_then_solve(_walk(problem, [back, aside, None]), [], Sequence(), 6)
    assert cleared is not None and cleared.result is not None
    assert [depth for depth, _ in recorder.calls] == [4, 3]
    assert "block2 right of the way" in cleared.words


def test_a_prefix_found_in_the_second_round_of_sides_gets_the_large_share_at_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """After the marker (every side had its first try), a prefix found in the second round is not made to wait:
    its search for the goals gets `THEN_SHARE` of the work left."""
    problem = _problem(tmp_path)
    late = (_prefix(3, frozenset({"block2"})), (), [("block2", RIGHT)])
    recorder = _Recorder(lambda root, budget: "timeout")
    monkeypatch.setattr(clear_first, "search", recorder)
    assert clear_first._clear_then_solve(_walk(problem, [None, late]), [], Sequence(), 6) is None
    assert [budget for _, budget in recorder.calls] == [pytest.approx(clear_first.THEN_SHARE * 1000.0)]


def test_a_prefix_that_moved_the_goal_body_waits_for_the_second_round_of_sides(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The search after a prefix that pushed the goal body back spends its first try; at the marker it waits on,
    and a prefix found in the second round of sides (one that leaves the goal body where it lies) is searched
    first: the pushed-back one, with more to undo, gets its large share last."""
    problem = _problem(tmp_path)
    back = (_prefix(4, frozenset({"block", "block2"})), (), [("block2", LEFT)])
    late = (_prefix(3, frozenset({"block2"})), (), [("block2", RIGHT)])
    recorder = _Recorder(lambda root, budget: "timeout")
    monkeypatch.setattr(clear_first, "search", recorder)
    assert clear_first._clear_then_solve(_walk(problem, [back, None, late]), [], Sequence(), 6) is None
    assert [depth for depth, _ in recorder.calls] == [4, 3, 4]
    assert recorder.calls[1][1] == pytest.approx(clear_first.THEN_SHARE * (1000.0 - 1.0))
