"""Goals against the executed world (`vkgl.execute.goal_checks`): a joint goal on its joint's coordinate."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vkgl.errors import InputError
from vkgl.execute.goal_checks import check_goal, miss_reason, replan_limits
from vkgl.lang.syntax.parser import parse_module

TASK = parse_module(
    "task t { scene s  goal drawer open 20 cm within 1 cm and door open 45deg\n"
    "and block at (0.6, 0) m within 2 cm, 4 deg }",
    "t.vkg",
).decls[0]
DRAWER, DOOR, BLOCK = TASK.goals


def test_a_joint_goal_is_checked_on_the_coordinate_not_the_pose() -> None:
    far_away = np.eye(4)
    far_away[:3, 3] = (5.0, 5.0, 5.0)  # the pose does not matter for a joint goal
    met = check_goal(DRAWER, far_away, "prismatic", 0.195)
    assert met.ok and met.text == "drawer open 20.0 cm within 1.0 cm"
    assert met.position_error is None and met.yaw_error is None
    assert met.opening is not None and met.opening.error == pytest.approx(-0.005)
    missed = check_goal(DRAWER, far_away, "prismatic", 0.187)
    assert not missed.ok
    assert miss_reason([met, missed]) == "drawer is open 18.7 cm, goal 20.0 cm within 1.00 cm"
    door = check_goal(DOOR, np.eye(4), "revolute", math.radians(48.5))
    assert not door.ok and door.text == "door open 45.0 deg within 3.0 deg"  # the default tolerance: 3 deg
    assert "door is open 48.5 deg, goal 45.0 deg within 3.00 deg" in miss_reason([door])


def test_a_joint_goal_on_a_body_without_a_joint_cannot_be_checked() -> None:
    with pytest.raises(InputError, match="`drawer` has no physical joint"):
        check_goal(DRAWER, np.eye(4), None, None)


def test_pose_goals_are_checked_as_before() -> None:
    pose = np.eye(4)
    pose[:3, 3] = (0.63, 0.0, 0.025)
    result = check_goal(BLOCK, pose)
    assert result.opening is None and result.position_error == pytest.approx(0.03) and not result.ok
    assert miss_reason([result]) == "block is off its goal by 3.00 cm (tolerance 2.00 cm)"


def test_the_replanning_limits_are_half_the_tolerance_of_the_bodys_kind() -> None:
    assert replan_limits(TASK, "drawer", "prismatic") == pytest.approx((0.005, math.radians(1.5), 0.005))
    assert replan_limits(TASK, "door", "revolute")[2] == pytest.approx(math.radians(1.5))
    assert replan_limits(TASK, "block", None)[:2] == pytest.approx((0.01, math.radians(2)))
    # a body on a joint without a joint goal: half the default tolerance of its joint's kind
    assert replan_limits(TASK, "cupboard", "revolute")[2] == pytest.approx(math.radians(1.5))
    assert replan_limits(TASK, "slide", "prismatic")[2] == pytest.approx(0.005)


def test_the_animations_last_title_says_how_far_each_joint_goal_is_open() -> None:
    from vkgl.execute.animate import _openings
    from vkgl.formats.execution_report import ExecutionReport

    goals = [check_goal(DRAWER, np.eye(4), "prismatic", 0.1988), check_goal(BLOCK, np.eye(4))]
    report = ExecutionReport("g", "reached", "", [], goals, 0, [], {}, 10.0, 1.0, 0.0)
    assert _openings(report) == ", drawer open 19.9 cm (goal 20.0 cm)"
    assert _openings(ExecutionReport("a", "reached", "", [], goals[1:], 0, [], {}, 1.0, 1.0, 0.0)) == ""
