"""Bodies in a tool's or the hand's path (`vkgl.plan.search.clutter.tool_path`): which bodies the search's rejections
make clearing targets, the sides they are slid to, and the clear-first walk clearing them after the way's blockers
(the physical bench's gen1_003: the hand that pulls a slab in with the hook passes 7 mm into a crate)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.plan.graphs.graph import g0
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.search.clutter import clear_first
from vkgl.plan.search.clutter.tool_path import PATH_STEP, PathSide, met_last, path_blockers, path_sides
from vkgl.plan.search.search import SearchResult
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.clearing import SIDE_TOLERANCE, footprint
from vkgl.plan.task_space.feasible import TaskSolution

SCENE = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.stick
use stdlib.affordances.block
use stdlib.affordances.stick
use stdlib.tools

scene cluttered {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    block2 : Block on table at (0.62, 0) m yaw 90deg
    behind : Block on table at (0.22, 0.16) m yaw 90deg
    stick : Stick on table at (0.3, -0.4) m yaw 0deg
}

task through {
    scene cluttered
    goal block at (0.75, 0) m within 1 cm
}
"""
"""A Block with another across its way (block2), a third beside the arm's line to it (behind) and a Stick."""


def _problem(tmp_path: Path) -> Problem:
    program = vkgl.compile_source(SCENE, "tool_path.vkg", base_dir=tmp_path)
    return build_problem(program, program.tasks["through"])


def _stats(named: dict[frozenset[str], float]) -> SearchStats:
    stats = SearchStats()
    stats.named.update(named)
    return stats


def test_a_body_the_hand_or_a_tool_met_becomes_a_path_blocker_with_the_least_depth_it_was_met_at(
    tmp_path: Path,
) -> None:
    problem = _problem(tmp_path)
    met = {frozenset({"behind"}): 1.0, frozenset({"behind", "stick"}): 0.012}  # the arm (no depth), the stick
    assert path_blockers(problem, _stats(met)) == pytest.approx({"behind": 0.012})


def test_an_arm_failure_without_a_depth_slides_the_body_by_the_step_alone(tmp_path: Path) -> None:
    problem = _problem(tmp_path)
    assert path_blockers(problem, _stats({frozenset({"behind"}): 1.0})) == {"behind": 0.0}


def test_bodies_a_goal_body_or_another_free_body_met_or_in_the_way_are_no_path_blockers(tmp_path: Path) -> None:
    problem = _problem(tmp_path)
    met = {
        frozenset({"behind", "block"}): 0.01,  # the goal body's own sweep: the corridor's business
        frozenset({"behind", "block2"}): 0.01,  # two free bodies
        frozenset({"block2", "stick"}): 0.01,  # in the goal body's way already (`InTheWay`)
        frozenset({"stick"}): 0.01,  # a tool
    }
    assert path_blockers(problem, _stats(met)) == {}


def test_a_path_blocker_is_slid_past_its_depth_along_its_own_slides_away_from_the_arms_work_first(
    tmp_path: Path,
) -> None:
    """`behind` (turned 90 deg: its pushes slide it along y) lies left of the line from the arm's base to the
    Block: slid left (+y) first; its region goal (the half-plane within its tolerance) holds it slid the step,
    not a centimetre less."""
    problem = _problem(tmp_path)
    sides = path_sides(problem, problem.goals[0], "behind", 0.01)
    assert len(sides) == 2 and all(isinstance(side, PathSide) for side in sides)
    step = 0.01 + PATH_STEP
    assert sides[0].slide == pytest.approx(step)
    assert "+1.00" in sides[0].words and "out of a tool's or the hand's path" in sides[0].words
    rest = problem.bodies["behind"].rest
    for moved, inside in ((step, True), (step - 0.01, False)):
        pose = rest.copy()
        pose[1, 3] += moved
        shape = footprint(problem, "behind", pose)
        halfplane = sides[0].halfplane
        assert bool(np.all(shape @ halfplane[:2] <= halfplane[2] + SIDE_TOLERANCE + 1e-9)) is inside


def test_the_walk_clears_the_ways_blocker_then_slides_the_path_blocker(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The walk's searches stubbed: the way's blocker first (one side), then the body in the tool's path along
    its first path side; the words say where each went."""
    problem = _problem(tmp_path)
    left = clear_first.Side("left", np.array([0.0, -1.0, -0.1]), 0.05)
    monkeypatch.setattr(clear_first, "way_sides", lambda *args, **kwargs: [left])
    monkeypatch.setattr(clear_first, "far_move_tools", lambda *args: None)
    monkeypatch.setattr(clear_first, "rolls", lambda *args: False)
    tried: list[tuple[str, str]] = []

    def clear(
        walk: object, goal: object, blocker: str, side: clear_first.Side, root: Sequence, *args: object, **kw: object
    ) -> SearchResult:
        tried.append((blocker, side.words))
        moved = Sequence(graphs=(g0(),) * (root.depth + 2), dependent=root.dependent | {blocker})
        return SearchResult("solved", "", SearchStats(), sequence=moved, task=TaskSolution(np.zeros(0), []))

    monkeypatch.setattr(clear_first._Walk, "_clear", clear)
    walk = clear_first._Walk(problem, math.inf, False, SearchStats(), 1000.0, paths={"behind": 0.0})
    goal = problem.goals[0]
    first = next(item for item in walk.prefixes([(goal, "block2"), (goal, "behind")], Sequence()) if item)
    assert [name for name, _ in first[2]] == ["block2", "behind"]
    assert tried[0] == ("block2", "left") and tried[1][0] == "behind"
    words = clear_first._Waiting(problem, first[0], first[2], 0).moved()
    assert words.startswith("block2 left of the way, then behind slid 2.5 cm along")
    walk.optional = frozenset({"behind"})  # the second walk: the body in the path left where it lies first
    moved = [
        [name for name, _ in item[2]]
        for item in walk.prefixes([(goal, "block2"), (goal, "behind")], Sequence())
        if item
    ]
    assert moved[0] == ["block2"] and moved[1] == ["block2", "behind"]
    assert all(names[0] == "block2" for names in moved)  # never the path alone (nothing cleared from the way)
    tried.clear()  # a root that moved the body in the path already: not cleared again (its sub-problem would
    moved_root = Sequence(graphs=(g0(),) * 3, dependent=frozenset({"behind"}))  # lack the root's contact on it)
    again = [item for item in walk.prefixes([(goal, "behind")], moved_root) if item]
    assert tried == [] and [(item[0], item[2]) for item in again] == [(moved_root, [])]


def test_the_path_blockers_the_closest_miss_named_after_clearing_the_way_are_cleared_alone_first(
    tmp_path: Path,
) -> None:
    """The sequence that got farthest (a collision, stage 2) moved block2 (in the way) and failed on `behind`
    alone: `met_last` names it; not when that sequence had not moved block2 yet, nor when a closer miss (an
    approach, stage 3) named no path blocker."""
    problem = _problem(tmp_path)
    cleared = (
        "add Block.push_center_px on block2 with arm.fingertip -> add Block.push_center_px on block with arm.fingertip"
    )
    for label, named in ((cleared, {"behind": 0.007}), ("add Block.push_center_px on block with arm.fingertip", {})):
        stats = SearchStats()
        stats.reject(Rejection(Kind.REACH, "out of reach", 0.001, bodies=frozenset({"block2"})), "a")
        stats.reject(Rejection(Kind.COLLISION, "the hand in behind", 0.007, bodies=frozenset({"behind"})), label)
        paths = path_blockers(problem, stats)
        assert paths == pytest.approx({"behind": 0.007})
        assert met_last(problem, paths, stats) == pytest.approx(named)
    stats.reject(Rejection(Kind.APPROACH, "no way in", 0.5, bodies=frozenset({"stick"})), cleared)
    assert met_last(problem, path_blockers(problem, stats), stats) == {}
