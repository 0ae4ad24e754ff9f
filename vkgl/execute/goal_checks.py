"""A task's goals and the closed loop's limits, checked against the executed world.

A pose goal (`B at POSE`, `B yaw Q`) is checked on the body's real pose; a
joint goal (`B open Q`) on the coordinate of the body's physical joint as the
simulated joint has it (`Replay.openings`): "drawer is open 18.7 cm, goal
20.0 cm within 1.0 cm". The closed loop compares a body with the plan by the
same measure: a body on a physical joint can only move along it, so its
deviation from the plan is the difference of the joint's coordinates, judged
against half the tolerance of its joint goal (`replan_limits`).
"""

from __future__ import annotations

import numpy as np

from vkgl.errors import InputError
from vkgl.formats.execution_report import GoalResult, Opening, joint_value_text
from vkgl.lang.ir.nodes import Goal, Task
from vkgl.lang.ir.regions import excess, footprint
from vkgl.lang.syntax.printer import goal_text
from vkgl.se3 import angle_difference, yaw_of


def replan_limits(task: Task, body: str, joint: str | None) -> tuple[float, float, float]:
    """Half the goal tolerance of `body`: (m, rad, joint coordinate in m or rad), the closed loop's limits.

    A body without a goal gets half the default tolerances (1 cm, 3 deg); a
    body on a joint without a joint goal half the pose goal's (or default)
    tolerance of its joint's kind, position for a slide, angle for a hinge.
    """
    goals = [g for g in task.goals if g.body.name == body]
    pose_goal = next((g for g in goals if g.opening is None), None)
    joint_goal = next((g for g in goals if g.opening is not None), None)
    tol_p, tol_a = pose_goal.tolerance() if pose_goal is not None else Goal.default_tolerance()
    if joint_goal is not None:
        tol_j = joint_goal.opening_tolerance()
    else:
        tol_j = tol_p if joint == "prismatic" else tol_a
    return tol_p / 2, tol_a / 2, tol_j / 2


def check_goal(
    goal: Goal,
    pose: np.ndarray,
    joint: str | None = None,
    opening: float | None = None,
    points: np.ndarray | None = None,
) -> GoalResult:
    """`goal` against the body's real `pose`; a joint goal against `opening`, the real coordinate of its `joint`
    ("prismatic" or "revolute"); a region goal with the body's shape `points` (body frame, n x 3): its position
    error is how far the footprint passes the region's edges (0 inside). Raises InputError for a joint goal on a
    body without a joint, or a region goal without `points`."""
    name = goal.body.name
    if goal.region is not None:
        return _check_region_goal(goal, pose, points)
    if goal.opening is not None:
        if joint is None or opening is None:
            raise InputError(f"the joint goal on `{name}` cannot be checked: `{name}` has no physical joint")
        tolerance = goal.opening_tolerance()
        reading = Opening(joint, float(goal.opening.value), float(opening), tolerance)
        text = f"{name} open {joint_value_text(joint, goal.opening.value)} within {joint_value_text(joint, tolerance)}"
        tol_p, tol_y = goal.tolerance()
        return GoalResult(name, text, None, None, tol_p, tol_y, reading)
    tol_p, tol_y = goal.tolerance()
    position_error = None
    # A relative goal is said as written, then where it puts the body: "block moved by (15, 0) cm in block: at ..."
    parts = [f"{relative_text(goal)}:" if goal.relative else name]
    if goal.position is not None:
        target = goal.position.array()
        position_error = float(np.linalg.norm(pose[: len(target), 3] - target))
        parts.append(f"at ({', '.join(f'{v:.3f}' for v in target)}) m")
    yaw_error = None
    if goal.yaw is not None:
        yaw_error = angle_difference(yaw_of(pose), goal.yaw.value)
        parts.append(f"yaw {np.degrees(goal.yaw.value):.1f} deg")
    within = [f"{tol_p * 100:.1f} cm"] if goal.position is not None else []
    within += [f"{np.degrees(tol_y):.1f} deg"] if goal.yaw is not None else []  # only what the goal asks for
    if within:
        parts.append(f"within {', '.join(within)}")
    return GoalResult(name, " ".join(parts), position_error, yaw_error, tol_p, tol_y)


def _check_region_goal(goal: Goal, pose: np.ndarray, points: np.ndarray | None) -> GoalResult:
    """A region goal: the footprint of the body at `pose` inside the region, within the position tolerance."""
    name = goal.body.name
    if goal.region is None or points is None:
        raise InputError(f"the region goal on `{name}` cannot be checked without the body's shape")
    tol_p, tol_y = goal.tolerance()
    outside = float(excess(goal.region.halfplanes(), footprint(points, pose)).max())
    parts = [f"{name} in {goal.region.words()}"]
    yaw_error = None
    if goal.yaw is not None:
        yaw_error = angle_difference(yaw_of(pose), goal.yaw.value)
        parts.append(f"yaw {np.degrees(goal.yaw.value):.1f} deg")
    parts.append(f"within {tol_p * 100:.1f} cm, {np.degrees(tol_y):.1f} deg")
    parts.append(f"(ends at ({pose[0, 3]:.3f}, {pose[1, 3]:.3f}) m)")
    return GoalResult(name, " ".join(parts), max(outside, 0.0), yaw_error, tol_p, tol_y)


def relative_text(goal: Goal) -> str:
    """A relative goal as written, without its tolerances: `block moved by (15, 0) cm in block`."""
    return goal_text(goal.model_copy(update={"tol_position": None, "tol_yaw": None}))


def miss_reason(results: list[GoalResult]) -> str:
    """Why the goals are not met, with the numbers: `drawer is open 18.7 cm, goal 20.0 cm within 1.0 cm`."""
    return "; ".join(reason for reason in (g.miss() for g in results) if reason)


__all__ = ["check_goal", "miss_reason", "relative_text", "replan_limits"]
