"""The example tasks of the goal forms people say (examples/tasks/j_*.vkg ...) solve, and the plan meets them.

Task j says its goal relative to the block's start (`moved by ... in block`,
`turned by`); the planner sees the pose goal it stands for.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from plan_programs import compiled  # noqa: F401 (fixture)
from replay_check import check_plan

from vkgl.api import solve
from vkgl.se3 import yaw_of


@pytest.fixture(scope="module")
def j_plan(compiled):
    return solve(compiled("j_move_relative"))


def test_a_relative_goal_is_met_from_where_the_body_starts(j_plan, compiled):
    assert j_plan.status == "solved", j_plan.reason
    start, final = j_plan.start["block"], j_plan.final["block"]
    along = start[:2, :2] @ np.array([0.15, 0.0])  # 15 cm along the block's own x axis at its start
    assert np.linalg.norm(final[:2, 3] - (start[:2, 3] + along)) <= 0.01
    turned = math.remainder(yaw_of(final) - yaw_of(start) - math.radians(20), 2 * math.pi)
    assert abs(turned) <= math.radians(3)
    assert check_plan(compiled("j_move_relative"), j_plan.to_json()) == []
