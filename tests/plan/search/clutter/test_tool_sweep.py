"""Bodies in the sweep of the tool that alone can carry a goal body (`vkgl.plan.search.clutter.tool_sweep`): named
from geometry before any search, they make a task blocked and the clear-first walk clears them (the physical
bench's gen20_009: a SlabW behind a SlabN, across the Stick's path, in no goal body's corridor)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.search.clutter import clear_first
from vkgl.plan.search.clutter.blocking import blocked
from vkgl.plan.search.clutter.tool_path import PATH_STEP, path_sides
from vkgl.plan.search.clutter.tool_sweep import exit_slide, swept_bodies, tool_sweeps
from vkgl.plan.search.search import SearchResult
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.clearing import MARGIN, RESOLUTION, footprint, polygon_distance

SCENE = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.stick
use stdlib.affordances.block
use stdlib.affordances.stick
use stdlib.tools

scene behind_the_block {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (START) m yaw 0deg
    behind : Block on table at (0.4, 0) m yaw 90deg
    aside : Block on table at (0.4, 0.3) m yaw 90deg
    stick : Stick on table at (0.3, -0.4) m yaw 0deg
}

task far {
    scene behind_the_block
    goal block at (GOAL) m within 1 cm
}
"""
"""A Block pushed to (GOAL), `behind` 30 cm behind it at (0.4, 0) (across the Stick that pushes it from behind, in
no goal body's corridor), `aside` clear of everything and a Stick."""


def _problem(tmp_path: Path, start: str = "0.7, 0", goal: str = "0.95, 0") -> Problem:
    source = SCENE.replace("START", start).replace("GOAL", goal)
    program = vkgl.compile_source(source, "tool_sweep.vkg", base_dir=tmp_path)
    return build_problem(program, program.tasks["far"])


def test_a_body_across_the_sweep_of_the_tool_that_alone_carries_the_goal_body_makes_the_task_blocked(
    tmp_path: Path,
) -> None:
    """The Block's goal lies past the hand's reach: only the Stick carries it there, and pushed from behind the
    Stick sweeps through `behind` (not `aside`); nothing lies in the Block's own corridor, yet the task is blocked
    (before `tool_sweep` it was not, and the whole timeout went to a search that only met `behind` late)."""
    problem = _problem(tmp_path)
    swept = swept_bodies(problem)
    assert list(swept) == ["behind"] and swept["behind"].goal is problem.goals[0]
    assert len(swept["behind"].sweeps) >= 1
    assert blocked(problem)


def test_no_sweep_where_the_hand_itself_carries_the_goal_body(tmp_path: Path) -> None:
    """A Block pushed within the hand's reach: the hand may carry it, so no tool's path is known and nothing
    makes the task blocked."""
    problem = _problem(tmp_path, goal="0.75, 0")
    assert tool_sweeps(problem, problem.goals[0]) == [] and swept_bodies(problem) == {}
    assert not blocked(problem)


def test_the_exit_slide_leaves_every_sweep_by_the_margin_and_not_a_centimetre_less(tmp_path: Path) -> None:
    problem = _problem(tmp_path)
    sweeps = swept_bodies(problem)["behind"].sweeps
    shape = footprint(problem, "behind", problem.bodies["behind"].rest)
    up = np.array([0.0, 1.0])
    slide = exit_slide(shape, up, sweeps, 0.3)
    assert slide is not None and slide > 0.0
    assert all(polygon_distance(shape + slide * up, s) >= MARGIN for s in sweeps)
    assert any(polygon_distance(shape + (slide - 0.01) * up, s) < MARGIN for s in sweeps)
    assert exit_slide(shape, up, sweeps, slide / 2) is None  # no slide that long
    assert exit_slide(footprint(problem, "aside", problem.bodies["aside"].rest), up, sweeps, 0.3) == 0.0


def test_a_swept_body_is_slid_out_of_the_sweep_not_only_the_path_step(tmp_path: Path) -> None:
    """`path_sides` with the sweeps: each direction of `behind`'s slides (along y) is as long as leaves them,
    more than the step a rejection's depth alone gives."""
    problem = _problem(tmp_path)
    swept = swept_bodies(problem)["behind"]
    shape = footprint(problem, "behind", problem.bodies["behind"].rest)
    sides = path_sides(problem, swept.goal, "behind", 0.0, swept.sweeps)
    assert len(sides) == 2 and all(side.slide > PATH_STEP for side in sides)
    for side in sides:
        axis = -side.halfplane[:2]
        assert side.slide == pytest.approx(exit_slide(shape, axis, swept.sweeps, 1.0), abs=2 * RESOLUTION)
    assert [side.slide for side in path_sides(problem, swept.goal, "behind", 0.0)] == pytest.approx([PATH_STEP] * 2)


def test_with_nothing_in_a_goal_bodys_way_the_walk_clears_the_swept_body(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """`clear_first` with no body in the Block's corridor: no narrow walk has a blocker, then the wide walk clears
    `behind` with its sweeps, not left where it lies first (`_Walk.optional`); before `tool_sweep` nothing was
    tried (None at once)."""
    walks: list[tuple[bool, list[str], frozenset[str], list[str]]] = []

    def walked(walk: clear_first._Walk, blocking: list[tuple[object, str]], *args: object) -> None:
        walks.append((walk.narrow, [name for _, name in blocking], walk.optional, sorted(walk.sweeps)))

    monkeypatch.setattr(clear_first, "_clear_then_solve", walked)
    problem = _problem(tmp_path)
    before = SearchResult("timeout", "", SearchStats())
    assert clear_first.clear_first(problem, before, deadline=math.inf, budget=900.0) is None
    assert walks == [(True, [], frozenset(), ["behind"]), (False, ["behind"], frozenset(), ["behind"])]
