"""Goals of one task that cannot all hold (vkgl/lang/checks/goal_pairs.py, E427)."""

from __future__ import annotations

from pathlib import Path

import pytest

from vkgl.errors import CompileError
from vkgl.lang.compiler import compile_source

ROOT = Path(__file__).resolve().parents[3]
SCENE = """\
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.drawer
use stdlib.furniture.drawer_cabinet
use stdlib.affordances.block
use stdlib.affordances.drawer

scene s {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.45, 0) m yaw 0deg
    cabinet : DrawerCabinet on table at (0.75, 0.37) m yaw 180deg
    drawer : Drawer in cabinet
}
"""


def _codes(goals: str) -> list[str]:
    try:
        compile_source(SCENE + f"task t {{\n    scene s\n    goal {goals}\n}}\n", base_dir=ROOT)
    except CompileError as error:
        return [d.code for d in error.diagnostics]
    return []


@pytest.mark.parametrize(
    "goals",
    [
        "block at (0.6, 0) m within 1 mm and block at (0.7, 0) m",  # 10 cm apart, 1.1 cm allowed
        "block yaw 0deg and block yaw 90deg within 5deg",
        "block at (0.6, 0) m yaw 10deg and block yaw -20deg",
        "drawer open 5 cm and drawer open 20 cm",
        "block moved by (15, 0) cm and block at (0.45, 0.2) m",  # the relative goal is the pose (0.6, 0) m
    ],
)
def test_goals_of_one_body_that_cannot_both_hold_are_an_error(goals: str) -> None:
    assert _codes(goals) == ["E427"]


@pytest.mark.parametrize(
    "goals",
    [
        "block at (0.6, 0) m and block yaw 90deg",  # a position and a heading: both can hold
        "block at (0.6, 0) m within 1 cm and block at (0.615, 0) m within 1 cm",  # 1.5 cm apart, 2 cm allowed
        "block yaw 179deg and block yaw -179deg",  # 2 deg apart across the half turn
        "block in region (0.5, -0.2) to (0.8, 0.2) m and block at (0.6, 0) m",  # a region: not compared
        "drawer open 10 cm and block at (0.6, 0) m",  # two bodies
    ],
)
def test_goals_that_can_hold_together_are_not(goals: str) -> None:
    assert _codes(goals) == []
