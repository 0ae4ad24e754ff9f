"""Relative goals (lang/checks/geometry/relative.py): `moved by` and `turned by` become the pose goal they stand for.

The displacement is added in the world frame, or turned by the start rotation
of the body named after `in`; a turn is added to the start heading; the printer
gives back what was written; E423 applies to the pose a relative goal names.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vkgl.errors import CompileError
from vkgl.lang.compiler import compile_source
from vkgl.lang.syntax.parser import parse_module as parse
from vkgl.lang.syntax.printer import print_module

HEADER = """\
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

scene s {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0.1) m yaw 30deg
    other : Block on table at (0.45, -0.3) m yaw 90deg
}
"""
ROOT = Path(__file__).resolve().parents[3]


def _goal(goal: str):
    program = compile_source(HEADER + f"task t {{\n    scene s\n    goal {goal}\n}}\n", base_dir=ROOT)
    (only,) = program.tasks["t"].goals
    return only


def test_a_world_displacement_adds_to_the_start_and_leaves_the_heading_free() -> None:
    goal = _goal("block moved by (0, 10) cm within 1 cm")
    assert goal.position is not None and goal.position.values == pytest.approx((0.45, 0.2))
    assert goal.yaw is None and goal.tolerance()[0] == pytest.approx(0.01)


def test_a_displacement_in_a_body_frame_is_turned_by_that_body_at_its_start() -> None:
    own = _goal("block moved by (10, 0) cm in block")
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert own.position.values == pytest.approx((0.45 + 0.1 * c, 0.1 + 0.1 * s))
    other = _goal("block moved by (10, 0) cm in other")  # `other` starts turned by 90 deg
    assert other.position.values == pytest.approx((0.45, 0.2))


def test_a_turn_adds_to_the_start_heading() -> None:
    alone = _goal("block turned by 20deg within 2deg")
    assert alone.position is None and alone.yaw.value == pytest.approx(math.radians(50))
    both = _goal("block moved by (5, 0, 0) cm turned by -45deg within 1 cm, 3deg")
    assert both.position.values == pytest.approx((0.5, 0.1, 0.025))  # a 3-vector moves the height too
    assert both.yaw.value == pytest.approx(math.radians(-15))


def test_the_printer_writes_the_goal_as_written() -> None:
    text = (
        HEADER + "task t {\n    scene s\n    goal block moved by (10, 0) cm in block turned by 5deg within 1 cm, 2deg\n"
    )
    text += "        and other turned by -90deg within 3deg\n}\n"
    module = parse(text, "t.vkg")
    printed = print_module(module)
    assert "goal block moved by (10, 0) cm in block turned by 5deg within 1 cm, 2deg" in printed
    assert "and other turned by -90deg within 3deg" in printed
    assert parse(printed, "t.vkg") == module


def test_the_scene_checks_see_the_pose_a_relative_goal_names() -> None:
    with pytest.raises(CompileError) as error:
        _goal("block moved by (2, 0) m")
    assert [d.code for d in error.value.diagnostics] == ["E423"]


def test_a_turn_goal_takes_one_tolerance() -> None:
    with pytest.raises(CompileError) as error:
        _goal("block turned by 20deg within 3deg, 4deg")
    assert [d.code for d in error.value.diagnostics] == ["E204"]


@settings(max_examples=30, deadline=None)
@given(
    dx=st.floats(-0.1, 0.1),
    dy=st.floats(-0.1, 0.1),
    turn=st.floats(-180.0, 180.0),
)
def test_moving_in_the_body_frame_keeps_the_distance_and_the_turn_wraps(dx: float, dy: float, turn: float) -> None:
    goal = _goal(f"block moved by ({dx!r}, {dy!r}) m in block turned by {turn!r}deg within 20 cm, 3deg")
    moved = goal.position.array() - (0.45, 0.1)
    assert math.hypot(*moved) == pytest.approx(math.hypot(dx, dy), abs=1e-9)
    assert -math.pi <= goal.yaw.value <= math.pi
    assert math.remainder(goal.yaw.value - math.radians(30 + turn), 2 * math.pi) == pytest.approx(0, abs=1e-9)
