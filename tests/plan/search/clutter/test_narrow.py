"""The narrow walk of clear-first (`vkgl.plan.search.clutter.clear_first`, `side_problem.only_moving(along=True)`):
a clearing sub-problem in which the goal body slides only along its own way, every body is slid, not turned, and
moved at most once (`Problem.moves_once`), searched for every side before the whole space (gen3_033 of the
physical bench: a clearing that leaves the crate on its line, where the whole space found one that pushed it
aside first)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from test_clear_first import _problem as _aside_problem
from test_then_order import LEFT, RIGHT, _prefix, _problem

from vkgl.plan.graphs.graph import Action, Engagement
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import Sequence, extend, start_sequence
from vkgl.plan.search.clutter import clear_first
from vkgl.plan.search.clutter.side_problem import ALONG, along_way, only_moving
from vkgl.plan.search.search import SearchResult, _moved_again
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.clearing import way_sides
from vkgl.plan.task_space.feasible import TaskSolution


def _world_axis(problem: object, body: str, affordance: object) -> np.ndarray:
    rest = problem.bodies[body].rest  # type: ignore[attr-defined]
    axis = (rest[:3, :3] @ unit_axis_and_center(affordance.motion)[0])[:2]  # type: ignore[attr-defined]
    return axis / np.linalg.norm(axis)


def test_the_narrow_sub_problem_keeps_the_goal_bodys_slides_along_its_way_only() -> None:
    """The block's way runs along +x, along both its slides: the narrow sub-problem keeps them, and no turn;
    block2 keeps only its slides; the moves are counted from the root's end. Its way turned 90 or 45 deg, the
    same slides lie across it (or 45 deg off): dropped, the block is not moved at all."""
    problem = _aside_problem(0.0)
    goal = problem.goals[0]
    side = way_sides(problem, goal, "block2")[0]
    wide, _ = only_moving(problem, goal, "block2", side)
    narrow, _ = only_moving(problem, goal, "block2", side, along=True)
    slides = {a.name for a in wide.bodies["block"].affordances if a.motion.type == "prismatic"}
    assert slides and {a.name for a in narrow.bodies["block"].affordances} == slides
    assert all(abs(_world_axis(problem, "block", a)[0]) >= ALONG for a in narrow.bodies["block"].affordances)
    assert {a.motion.type for a in narrow.bodies["block2"].affordances} == {"prismatic"}
    assert wide.moves_once is None and narrow.moves_once == 1
    for offset in ((0.0, 0.3), (0.2, 0.2)):
        position = np.array(goal.position, dtype=float)
        position[:2] = problem.bodies["block"].rest[:2, 3] + np.array(offset)
        assert along_way(problem, replace(goal, position=position), problem.bodies["block"].affordances) == ()


def test_a_contact_that_would_move_a_body_a_second_time_is_cut_past_the_root() -> None:
    """`Problem.moves_once`: block2 pushed, let go of, and pushed again is cut; pushed once after a root that
    pushed it already is not (the root's moves do not count)."""
    problem = _aside_problem(0.0)
    push = next(a.name for a in problem.bodies["block2"].affordances if a.motion.type == "prismatic")
    e = Engagement("arm.fingertip", "block2", push)
    seq = start_sequence(problem)
    seq, _ = extend(problem, seq, Action("add", e))
    assert not _moved_again(seq, 1)
    seq, _ = extend(problem, seq, Action("remove", e))
    assert not _moved_again(seq, 1)
    again, _ = extend(problem, seq, Action("add", e))
    assert _moved_again(again, 1)
    assert not _moved_again(again, seq.depth)  # the first push belongs to the root


def test_the_narrow_walk_tries_every_side_before_the_wide_one_and_searches_a_plan_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The narrow walk tries the sides (with `NARROW_SHARE` of the work left each) before any wide try, up to the
    first that has a plan (the left: the right is left to the wide walk); in the wide walk that plan stands for the
    left's first try (not searched again), and the search for the goals after it runs once."""
    monkeypatch.setattr(clear_first, "way_sides", lambda *args, **kwargs: [LEFT, RIGHT])
    monkeypatch.setattr(clear_first, "far_move_tools", lambda *args: None)
    monkeypatch.setattr(clear_first, "rolls", lambda *args: False)
    calls: list[tuple[str, bool, float]] = []
    plan = _prefix(4, frozenset({"block2"}))

    def clear(walk: object, goal: object, blocker: str, side: object, root: Sequence, pinned: object, budget: float,
              *, rolled: bool = False, along: bool = False) -> SearchResult:  # fmt: skip
        calls.append((side.words, along, budget))  # type: ignore[attr-defined]
        if side is LEFT:
            return SearchResult("solved", "", SearchStats(), sequence=plan, task=TaskSolution(np.zeros(0), []))
        return SearchResult("infeasible", "", SearchStats())

    then: list[int] = []

    def search(problem: object, *, deadline: float, progress: bool, root: Sequence, budget: float, **kw: object):
        then.append(root.depth)
        stats = SearchStats()
        stats.graphs_expanded = 20
        return SearchResult("infeasible", "", stats)

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    monkeypatch.setattr(clear_first, "search", search)
    problem = _problem(tmp_path)
    walk = clear_first._Walk(problem, math.inf, False, SearchStats(), 900.0, narrow=True)
    goal = problem.goals[0]
    assert clear_first._clear_then_solve(walk, [(goal, "block2")], Sequence(), 6) is None
    assert [(words, along) for words, along, _ in calls] == [("left", True)]
    assert calls[0][2] == pytest.approx(clear_first.NARROW_SHARE * 900.0)
    walk.narrow = False
    assert clear_first._clear_then_solve(walk, [(goal, "block2")], Sequence(), 6) is None
    assert [(words, along) for words, along, _ in calls[1:]] == [("right", False)]
    assert then == [4]  # the search for the goals after the plan: once, not again after the wide try found it


def test_the_narrow_walk_leaves_a_blocker_its_root_moved_to_the_goals_values(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """block2 pushed by the plan before (the root): the narrow walk yields the root with its values free (block2
    moved as far as the goal's search needs) and clears it no more (every body moved once); the wide walk still
    tries its sides."""
    monkeypatch.setattr(clear_first, "way_sides", lambda *args, **kwargs: [LEFT])
    monkeypatch.setattr(clear_first, "far_move_tools", lambda *args: None)
    monkeypatch.setattr(clear_first, "rolls", lambda *args: False)
    tried: list[bool] = []

    def clear(walk: object, goal: object, blocker: str, side: object, root: Sequence, pinned: object, budget: float,
              *, rolled: bool = False, along: bool = False) -> SearchResult:  # fmt: skip
        tried.append(along)
        return SearchResult("infeasible", "", SearchStats())

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    problem = _aside_problem(0.0)
    push = next(a.name for a in problem.bodies["block2"].affordances if a.motion.type == "prismatic")
    e = Engagement("arm.fingertip", "block2", push)
    root, _ = extend(problem, start_sequence(problem), Action("add", e))
    root, _ = extend(problem, root, Action("remove", e))
    goal = problem.goals[0]
    narrow = clear_first._Walk(problem, math.inf, False, SearchStats(), 900.0, narrow=True)
    assert [item[:2] for item in narrow.prefixes([(goal, "block2")], root, (0.1,)) if item] == [(root, ())]
    assert tried == []
    wide = clear_first._Walk(problem, math.inf, False, SearchStats(), 900.0)
    list(wide.prefixes([(goal, "block2")], root, (0.1,)))
    assert tried == [False]


@pytest.mark.parametrize(
    ("moved", "paths", "bodies"),
    [
        (frozenset({"block2"}), {}, ("block2", "block3")),
        (frozenset({"block", "block2"}), {}, ("block2", "block3")),
        (frozenset({"block2"}), {"crate": 0.01}, ("block2", "block3")),
        (frozenset({"block2"}), {}, ("block2",)),
    ],
)
def test_the_narrow_walks_search_after_a_plan_that_left_the_goal_body_still_goes_on_at_once(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    moved: frozenset[str],
    paths: dict[str, float],
    bodies: tuple[str, ...],
) -> None:
    """The narrow plan (each body in the way cleared in turn) has its search for the goals spend its first try:
    when the plan left the block where it lies it goes on at once with `THEN_SHARE` (the likeliest prefix); when
    it pushed the block back, or a body in a tool's path waits for the wide walk, or one body alone lies in the
    way (the wide walk's first round: a small try of its other sides), it waits for the wide walk too (held)."""
    monkeypatch.setattr(clear_first, "way_sides", lambda *args, **kwargs: [LEFT])
    monkeypatch.setattr(clear_first, "far_move_tools", lambda *args: None)
    plan = _prefix(4, moved)

    def clear(walk: object, goal: object, blocker: str, side: object, root: Sequence, pinned: object, budget: float,
              *, rolled: bool = False, along: bool = False) -> SearchResult:  # fmt: skip
        return SearchResult("solved", "", SearchStats(), sequence=plan, task=TaskSolution(np.zeros(0), []))

    budgets: list[float] = []

    def search(problem: object, *, deadline: float, progress: bool, root: Sequence, budget: float, **kw: object):
        budgets.append(budget)
        stats = SearchStats()
        stats.graphs_expanded = 20  # 1 unit
        return SearchResult("timeout", "", stats)

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    monkeypatch.setattr(clear_first, "search", search)
    problem = _problem(tmp_path)
    walk = clear_first._Walk(problem, math.inf, False, SearchStats(), 900.0, narrow=True, paths=paths)
    held: list[object] = []
    blocking = [(problem.goals[0], name) for name in bodies]
    assert clear_first._clear_then_solve(walk, blocking, Sequence(), 6, held) is None  # type: ignore[arg-type]
    assert budgets[0] == pytest.approx(clear_first.THEN_FIRST * 900.0)
    if "block" in moved or paths or len(bodies) == 1:
        assert len(budgets) == 1 and len(held) == 1
    else:
        assert budgets[1:] == [pytest.approx(clear_first.THEN_SHARE * 899.0)] and held == []


def test_the_narrow_walk_goes_first_then_the_bodies_the_closest_miss_failed_on_alone_then_the_wide_walk(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`met_last` names a body in a tool's path: the narrow walk over the way's blockers first, then that body
    cleared alone (wide), then the wide walk over the way's blockers and the bodies in a path."""
    walks: list[tuple[bool, list[str]]] = []

    def walked(walk: clear_first._Walk, blocking: list[tuple[object, str]], *args: object) -> None:
        walks.append((walk.narrow, [name for _, name in blocking]))

    monkeypatch.setattr(clear_first, "path_blockers", lambda *args: {"crate": 0.01})
    monkeypatch.setattr(clear_first, "met_last", lambda *args: {"crate": 0.01})
    monkeypatch.setattr(clear_first, "_clear_then_solve", walked)
    problem = _problem(tmp_path)
    before = SearchResult("infeasible", "", SearchStats())
    assert clear_first.clear_first(problem, before, deadline=math.inf, budget=900.0) is None
    assert walks == [(True, ["block2"]), (False, ["crate"]), (False, ["block2", "crate"])]


def test_the_first_plan_clearing_the_bodies_the_closest_miss_failed_on_goes_on_at_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`_Walk.eager` (the walk over `met_last`'s bodies): the search for the goals after its first clearing plan
    that left the block where it lies goes on at once with `THEN_SHARE` after its first try, once; the second
    plan's search waits as ever."""
    monkeypatch.setattr(clear_first, "way_sides", lambda *args, **kwargs: [LEFT, RIGHT])
    monkeypatch.setattr(clear_first, "far_move_tools", lambda *args: None)
    monkeypatch.setattr(clear_first, "rolls", lambda *args: False)

    def clear(walk: object, goal: object, blocker: str, side: object, root: Sequence, pinned: object, budget: float,
              *, rolled: bool = False, along: bool = False) -> SearchResult:  # fmt: skip
        plan = _prefix(3 if side is LEFT else 4, frozenset({"block2"}))
        return SearchResult("solved", "", SearchStats(), sequence=plan, task=TaskSolution(np.zeros(0), []))

    calls: list[tuple[int, float]] = []

    def search(problem: object, *, deadline: float, progress: bool, root: Sequence, budget: float, **kw: object):
        calls.append((root.depth, budget))
        stats = SearchStats()
        stats.graphs_expanded = 20  # 1 unit
        return SearchResult("timeout", "", stats)

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    monkeypatch.setattr(clear_first, "search", search)
    problem = _problem(tmp_path)
    walk = clear_first._Walk(problem, math.inf, False, SearchStats(), 900.0, eager=True)
    assert clear_first._clear_then_solve(walk, [(problem.goals[0], "block2")], Sequence(), 6) is None
    assert calls[:3] == [
        (3, pytest.approx(clear_first.THEN_FIRST * 900.0)),
        (3, pytest.approx(clear_first.THEN_SHARE * 899.0)),
        (4, pytest.approx(clear_first.THEN_FIRST * 898.0)),
    ]
    assert not walk.eager and [depth for depth, _ in calls[3:]] == [4]  # the second round: the second plan only


def test_the_narrow_walk_takes_a_push_of_the_blocker_alone_on_a_later_side_before_a_longer_plan_on_the_first(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Both sides are reached by one slide of block2; the left (first in order) has only a plan of 4 graphs
    (the goal body pushed back, a tool grasped), the right a push of block2 alone (2 graphs): every such side is
    first tried one contact deep (`FIRST_TRY` each), and the right's push is the narrow walk's plan, not searched
    again; the left's whole sub-problem is not searched (gen20_026 of the physical bench)."""
    left, right = replace(LEFT, slide=0.3), replace(RIGHT, slide=0.4)
    monkeypatch.setattr(clear_first, "way_sides", lambda *args, **kwargs: [left, right])
    monkeypatch.setattr(clear_first, "far_move_tools", lambda *args: None)
    calls: list[tuple[str, int, float]] = []
    longer, push = _prefix(4, frozenset({"block", "block2"})), _prefix(2, frozenset({"block2"}))

    def clear(walk: object, goal: object, blocker: str, side: object, root: Sequence, pinned: object, budget: float,
              *, rolled: bool = False, along: bool = False, depth: int = 5) -> SearchResult:  # fmt: skip
        calls.append((side.words, depth, budget))  # type: ignore[attr-defined]
        plans = {("left", 5): longer, ("right", 5): push, ("right", 2): push}
        found = plans.get((side.words, depth))  # type: ignore[attr-defined]
        if found is None:
            return SearchResult("infeasible", "", SearchStats())
        return SearchResult("solved", "", SearchStats(), sequence=found, task=TaskSolution(np.zeros(0), []))

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    problem = _problem(tmp_path)
    walk = clear_first._Walk(problem, math.inf, False, SearchStats(), 900.0, narrow=True)
    prefixes = [item for item in walk.prefixes([(problem.goals[0], "block2")], Sequence()) if item]
    assert [(prefix, [name for name, _ in cleared]) for prefix, _, cleared in prefixes] == [(push, ["block2"])]
    assert prefixes[0][2][0][1] is right
    assert [(words, depth) for words, depth, _ in calls] == [("left", 2), ("right", 2)]
    assert calls[0][2] == pytest.approx(clear_first.FIRST_TRY * 900.0)
    assert list(walk.narrowed) == [("block2", "right", ())]
