"""Clear first, then solve (`vkgl.plan.search.clutter.clear_first._clear_then_solve`): the search for the goals
after a clearing plan that pushed the goal body back first gets a small budget and, when it spends that, goes again
once every side had its first try; one after a clearing plan that left the goal body where it lies gets the large
share at once.

The walk's searches are stubbed here (no planning runs): what is tested is where the work goes."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.plan.graphs.graph import g0
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.search.clutter import clear_first
from vkgl.plan.search.search import SearchResult
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.clearing import Side

SCENE = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene cluttered {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    block2 : Block on table at (0.62, 0) m yaw 90deg
}

task through {
    scene cluttered
    goal block at (0.75, 0) m within 1 cm
}
"""

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

    def __call__(self, problem: Problem, *, deadline: float, progress: bool, root: Sequence, budget: float) -> object:
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


def test_a_prefix_that_pushed_the_goal_body_back_waits_while_one_beside_the_way_is_searched_at_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A prefix that pushed the block back (4 graphs, found first) gets `THEN_FIRST` of the work left; the one that
    left it where it lies (3 graphs, found second) gets `THEN_SHARE` at once; once the round is over (the marker),
    the first is searched again with `THEN_SHARE`. Each failure is in the walk's log, the waiting one's last."""
    problem = _problem(tmp_path)
    back = (_prefix(4, frozenset({"block", "block2"})), (), [("block2", LEFT)])
    aside = (_prefix(3, frozenset({"block2"})), (), [("block2", RIGHT)])
    recorder = _Recorder(lambda root, budget: "timeout")
    monkeypatch.setattr(clear_first, "search", recorder)
    walk = _walk(problem, [back, aside, None])
    assert clear_first._clear_then_solve(walk, [], Sequence(), 6) is None
    assert [depth for depth, _ in recorder.calls] == [4, 3, 4]
    budgets = [budget for _, budget in recorder.calls]
    assert budgets[0] == pytest.approx(clear_first.THEN_FIRST * 1000.0)
    assert budgets[1] == pytest.approx(clear_first.THEN_SHARE * (1000.0 - 1.0))  # 1 unit per search spent
    assert budgets[2] == pytest.approx(clear_first.THEN_SHARE * (1000.0 - 2.0))
    assert [line.split(" (")[0] for line in walk.log] == ["block2 right of the way", "block2 left of the way"]


def test_waiting_prefixes_go_again_the_shorter_first(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Two prefixes that both pushed the block back wait; in the second round the shorter goes first."""
    problem = _problem(tmp_path)
    longer = (_prefix(5, frozenset({"block", "block2"})), (), [("block2", LEFT)])
    shorter = (_prefix(4, frozenset({"block", "block2"})), (), [("block2", RIGHT)])
    recorder = _Recorder(lambda root, budget: "timeout")
    monkeypatch.setattr(clear_first, "search", recorder)
    assert clear_first._clear_then_solve(_walk(problem, [longer, shorter, None]), [], Sequence(), 6) is None
    assert [depth for depth, _ in recorder.calls] == [5, 4, 4, 5]


def test_a_prefix_whose_first_search_finds_the_plan_ends_the_walk_at_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The second prefix's search finds the plan: the first, waiting, is not searched again, and the words say how
    the way was cleared."""
    problem = _problem(tmp_path)
    back = (_prefix(4, frozenset({"block", "block2"})), (), [("block2", LEFT)])
    aside = (_prefix(3, frozenset({"block2"})), (), [("block2", RIGHT)])
    recorder = _Recorder(lambda root, budget: "solved" if root.depth == 3 else "timeout")
    monkeypatch.setattr(clear_first, "search", recorder)
    cleared = clear_first._clear_then_solve(_walk(problem, [back, aside, None]), [], Sequence(), 6)
    assert cleared is not None and cleared.result is not None
    assert [depth for depth, _ in recorder.calls] == [4, 3]
    assert "block2 right of the way" in cleared.words
