"""Carrying a grasped free body: where it is set down is a decision of the task-space optimisation.

A body held by the robot's own effector through an affordance whose motion is
`free` (a grasp) and let go of right after (`ADD grasp`, `REMOVE grasp`: pick
and place) is carried during the mode in which it is held: its pose at the
end of that mode (where it is set down) is `carried_pose(start, values)`, with
three values per carry: `dx`, `dy` (m, in the world's horizontal plane) and
`dyaw` (rad, about the world's vertical through the body's frame). The body
keeps the face it rested on at the grasp: a body resting stably on a face is
set down resting on the same face, level, at the table height it had
(`rollout.put_down` lowers it there). How it gets there (lifted over the
other bodies, carried in the hand along a collision-free transit, lowered
onto its place) is the arm's business (`vkgl.plan.arm.paths`); task space
only sees where it is picked up and where it is put down.

A tool (a body some effector frame belongs to, or whose type is explored held)
is never carried this way: it is put down where it was used
(`rollout._transition`).
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.plan.problem.problem import Problem

CARRY_VALUES = 3
"""Values per carry: dx, dy (m) and dyaw (rad)."""

CARRY_REACH = 2.0
"""m: how far one carry may move a body along x or y (beyond any table the examples use)."""


def carriable(problem: Problem, body: str) -> bool:
    """Whether `body` may be carried and set down elsewhere: it is no tool (a body some effector frame belongs
    to, or whose type is explored held, as the Stick is: a tool is put down where it was used, and a tool the
    program gives no correspondence is no goal's way either) and has no physical joint (a handle on a drawer or
    a door moves along its joint, not freely)."""
    placed = problem.bodies[body]
    if placed.joint is not None:
        return False
    if any(getattr(explore, "grasp", None) is not None for explore in placed.type.explores):
        return False
    return all(e.tool != body for e in problem.effectors)


def carried_pose(start: np.ndarray, values: np.ndarray) -> np.ndarray:
    """`start` moved by `values` = (dx, dy, dyaw): turned about the world's vertical through its frame, then
    shifted horizontally."""
    dx, dy, dyaw = (float(v) for v in values)
    c, s = math.cos(dyaw), math.sin(dyaw)
    turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    out = start.copy()
    out[:3, :3] = turn @ start[:3, :3]
    out[0, 3] += dx
    out[1, 3] += dy
    return out


def carry_values_to(start: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The values that carry a body from `start` to `target` (both level: the yaw difference and the shift)."""
    yaw = math.atan2(target[1, 0], target[0, 0]) - math.atan2(start[1, 0], start[0, 0])
    yaw = (yaw + math.pi) % (2.0 * math.pi) - math.pi
    return np.array([target[0, 3] - start[0, 3], target[1, 3] - start[1, 3], yaw])


def carry_bounds(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of `count` carries' values (flattened, `CARRY_VALUES` each)."""
    low = np.tile([-CARRY_REACH, -CARRY_REACH, -math.pi], count)
    high = np.tile([CARRY_REACH, CARRY_REACH, math.pi], count)
    return low.astype(float), high.astype(float)


__all__ = ["CARRY_REACH", "CARRY_VALUES", "carriable", "carried_pose", "carry_bounds", "carry_values_to"]
