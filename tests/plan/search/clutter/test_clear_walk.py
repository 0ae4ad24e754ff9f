"""Clear first, then solve: the walk over the blockers (`vkgl.plan.search.clutter.clear_first._Walk.prefixes`) leaves
a blocker that no plan moves where it lies and goes on with the others (gen13_018 of the physical bench: a Block
behind the crate's start counts as in its way, no side of it is reachable, and the cube that is in the way was
cleared for nothing).

The walk's searches are stubbed here (no planning runs): what is tested is which prefixes it yields."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from test_then_order import LEFT, _prefix, _problem

from vkgl.plan.graphs.graph import Engagement, g0
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.search.clutter import clear_first
from vkgl.plan.search.search import SearchResult
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.feasible import TaskSolution


def _walk(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, movable: set[str]) -> clear_first._Walk:
    """A walk whose blockers each have one side (`LEFT`), which a plan reaches for the blockers in `movable`."""
    monkeypatch.setattr(clear_first, "way_sides", lambda *args, **kwargs: [LEFT])
    monkeypatch.setattr(clear_first, "far_move_tools", lambda *args: None)
    monkeypatch.setattr(clear_first, "rolls", lambda *args: False)  # no rolled hook's second try

    def clear(
        walk: object,
        goal: object,
        blocker: str,
        side: object,
        root: Sequence,
        pinned: object,
        budget: float,
        *,
        rolled: bool = True,
        along: bool = False,
    ) -> SearchResult:
        if blocker not in movable or along:  # the narrow try finds nothing here: the walk goes on as before
            return SearchResult("infeasible", "", SearchStats())
        moved = _prefix(root.depth + 2, frozenset({blocker}))
        return SearchResult("solved", "", SearchStats(), sequence=moved, task=TaskSolution(np.zeros(0), []))

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    return clear_first._Walk(_problem(tmp_path), math.inf, False, SearchStats(), 1000.0)


def _moved(items: list[object]) -> list[list[str]]:
    return [[name for name, _ in item[2]] for item in items if item is not None]  # type: ignore[index]


def test_a_blocker_no_plan_moves_is_left_where_it_lies_after_the_one_cleared_before_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    walk = _walk(tmp_path, monkeypatch, {"cube"})
    goal = walk.problem.goals[0]
    items = list(walk.prefixes([(goal, "cube"), (goal, "behind")], Sequence()))
    assert _moved(items) == [["cube"]]
    prefix = next(item for item in items if item is not None)
    assert prefix[0].depth == 3  # the cube's clearing plan, nothing after it


def test_the_blockers_after_one_no_plan_moves_are_still_cleared(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    walk = _walk(tmp_path, monkeypatch, {"cube"})
    goal = walk.problem.goals[0]
    assert _moved(list(walk.prefixes([(goal, "behind"), (goal, "cube")], Sequence()))) == [["cube"]]


def test_no_prefix_when_no_plan_moves_any_blocker(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Nothing cleared is no prefix (not "nothing lies in the way", which would end clearing with no words)."""
    walk = _walk(tmp_path, monkeypatch, set())
    goal = walk.problem.goals[0]
    assert _moved(list(walk.prefixes([(goal, "behind"), (goal, "cube")], Sequence()))) == []


def test_a_blocker_the_plan_before_moved_is_first_left_to_the_goals_values(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """gen3_023 of the physical bench: the plan that clears the cube nudges the body behind it out of the Hook's
    way; the prefix that leaves that body to the goal's search (its values free, so that `cleared_values` moves it
    farther) comes before the one whose own plan clears it again."""
    walk = _walk(tmp_path, monkeypatch, {"cube", "behind"})
    nudged = (1, Engagement("arm.fingertip", "behind", "push")), (3, Engagement("stick.tip", "cube", "push"))

    def clear(walk: object, goal: object, blocker: str, side: object, root: Sequence, *args: object, **kw: object):
        if kw.get("along"):  # the narrow try finds nothing here
            return SearchResult("infeasible", "", SearchStats())
        if blocker == "cube":  # the cube's plan moves the body behind too
            moved = Sequence(graphs=(g0(),) * 5, variables=nudged, dependent=frozenset({"cube", "behind"}))
            return SearchResult("solved", "", SearchStats(), sequence=moved, task=TaskSolution(np.ones(2), []))
        moved = _prefix(root.depth + 2, frozenset({blocker}))
        return SearchResult("solved", "", SearchStats(), sequence=moved, task=TaskSolution(np.zeros(0), []))

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    goal = walk.problem.goals[0]
    items = [item for item in walk.prefixes([(goal, "cube"), (goal, "behind")], Sequence()) if item is not None]
    assert _moved(items) == [["cube"], ["cube", "behind"]]
    assert items[0][0].depth == 5 and items[0][1] == ()  # the cube's plan, its values free for the goal's search
    assert items[1][0].depth == 7  # then the body behind cleared by a plan of its own, after the cube's


def test_a_blocker_only_an_earlier_plan_of_another_moved_is_not_skipped_at_the_start(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """At the walk's start nothing has moved: every blocker gets its own clearing plan."""
    walk = _walk(tmp_path, monkeypatch, {"cube", "behind"})
    goal = walk.problem.goals[0]
    items = [item for item in walk.prefixes([(goal, "cube"), (goal, "behind")], Sequence()) if item is not None]
    assert _moved(items) == [["cube", "behind"]]
