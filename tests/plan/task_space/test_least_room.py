"""A body moved only to make room is moved least (`vkgl.plan.task_space.feasible.least_room`, `Problem.least`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.plan.graphs.graph import Action, Engagement
from vkgl.plan.graphs.rollout import extend, rollout, start_sequence
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.task_space.clearing import MARGIN, footprint
from vkgl.plan.task_space.feasible import TaskSolution, goal_holds, least_room, roomier_after

_HERE = Path(__file__).resolve().parent

SCENE = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene across {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    block2 : Block on table at (0.62, 0) m yaw 90deg
}

task through { scene across  goal block at (0.75, 0) m within 1 cm }
"""


def _aside_then_through(least: frozenset[str]):
    """block2 (across block's way) pushed aside along world +y, then block pushed 30 cm to its goal."""
    program = vkgl.compile_source(SCENE, "least.vkg", base_dir=_HERE)
    problem = replace(build_problem(program, program.tasks["through"]), least=least)
    aside = Engagement("arm.fingertip", "block2", "push_center_px")  # block2's x is the world's +y at yaw 90
    through = Engagement("arm.fingertip", "block", "push_center_px")
    seq = start_sequence(problem)
    for action in (Action("add", aside), Action("remove", aside), Action("add", through)):
        seq, _ = extend(problem, seq, action)
    return problem, seq


def test_a_body_moved_to_make_room_keeps_only_the_least_move_that_clears_the_way() -> None:
    problem, seq = _aside_then_through(frozenset({"block2"}))
    far = np.array([0.30, 0.30])  # block2 pushed 30 cm aside: it clears the way, as far as the optimiser left it
    x = least_room(problem, seq, far)
    # block2 spans 5 cm either side of its origin across the push, block's corridor 10 cm: 15 cm clears it
    assert 0.15 + MARGIN - 0.003 <= x[0] <= 0.15 + MARGIN + 0.005
    assert x[1] == far[1]  # the goal body's own motion is untouched
    end = rollout(problem, seq, x)[-1].end
    assert goal_holds(problem, end)
    corridor_edge = 0.10  # block's half width across its way
    assert footprint(problem, "block2", end["block2"])[:, 1].min() == pytest.approx(corridor_edge + MARGIN, abs=3e-3)


def test_nothing_changes_without_least_bodies_or_when_the_move_is_already_least() -> None:
    problem, seq = _aside_then_through(frozenset())
    far = np.array([0.30, 0.30])
    assert least_room(problem, seq, far) is far
    problem, seq = _aside_then_through(frozenset({"block2"}))
    short = np.array([0.12, 0.30])  # not clear of the way yet: the sweep check, not this, rejects it
    assert least_room(problem, seq, short) is short


def test_when_the_arm_rejects_the_least_move_the_optimisers_own_values_come_next_if_the_bodies_pass_clear() -> None:
    problem, seq = _aside_then_through(frozenset({"block2"}))
    far = np.array([0.30, 0.30])
    least = least_room(problem, seq, far)
    found = TaskSolution(least, rollout(problem, seq, least), free=True, roomier=far)
    clear = list(roomier_after(problem, [(seq, found)], lambda graphs, traces: None))
    assert len(clear) == 1 and clear[0][0] is seq
    assert clear[0][1].values is far and clear[0][1].roomier is None  # tried once, never shortened again
    assert clear[0][1].traces[-1].end["block2"][1, 3] == pytest.approx(0.30, abs=1e-6)  # rolled out anew
    assert not list(roomier_after(problem, [(seq, found)], lambda graphs, traces: "the bodies clash"))
    assert not list(roomier_after(problem, [], lambda graphs, traces: None))  # nothing rejected (yet)
