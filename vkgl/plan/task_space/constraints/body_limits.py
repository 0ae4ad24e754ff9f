"""The limits a moved body keeps in the task space: on the table (its whole outline), within its physical joint's
limits, out of the keep-out regions; and the words that say which limit a motion would pass.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.regions import footprint, overlap_depth
from vkgl.plan.problem.problem import GoalSpec, Problem


def body_constraints(problem: Problem, name: str, pose: np.ndarray) -> list[float]:
    """A moved body's constraints at the end of a mode: on the table, within its joint's limits, out of the
    keep-out regions (<= 0 when satisfied, m)."""
    return _stay_constraints(problem, name, pose) + _keep_out_depths(problem, name, pose)


def _keep_out_depths(problem: Problem, name: str, pose: np.ndarray) -> list[float]:
    """How deep a moved body ends in each keep-out region that applies to it (m; <= 0 outside): the optimiser
    keeps the ends of motions out (the geometry check then samples the whole way, `plan.geometry.keep_out`)."""
    if not problem.keep_out:
        return []
    points = footprint(problem.footprint_points(name), pose)
    return [overlap_depth(k.region, points) for k in problem.keep_out if k.applies_to(name)]


def _stay_constraints(problem: Problem, name: str, pose: np.ndarray) -> list[float]:
    """A moved body stays on the table (if it lies on it: its whole outline) and within its physical joint's limits.

    The outline, not the body's frame: a slide that is not bounded by its range
    (`range ... open`) would otherwise stop with its centre on the table's edge,
    half of it in the air, and fall off in physics.
    """
    body = problem.bodies[name]
    out: list[float] = []
    if body.on_table and problem.table_center is not None:
        corners = body.outline @ pose[:3, :3].T + pose[:3, 3]
        # the farthest corner per axis, then the half size off it: subtracting a constant keeps the order of
        # the rounded numbers, so this is the largest of the corners' overhangs to the last bit, in fewer steps
        farthest = np.maximum.reduce(np.abs(corners[:, :2] - problem.table_center), axis=0)
        out.extend((farthest - problem.table_size / 2).tolist())  # type: ignore[operator]
    if body.joint_limits is not None and body.joint_axis is not None:
        lower, upper = body.joint_limits
        state = body.joint_state(pose)
        out.extend((lower - state, state - upper))
    return out


def limit_words(problem: Problem, name: str, pose: np.ndarray, goal: GoalSpec | None = None) -> str:
    """Which limit a body would pass, with the numbers: its joint's range, or the table's edge.

    The joint's coordinate is where `goal` (else the body's first goal that says) puts it, if one does.
    """
    body = problem.bodies[name]
    if body.joint_limits is not None and body.joint_axis is not None:
        lower, upper = body.joint_limits
        state = body.joint_state(pose)
        scale, unit = (100.0, "cm") if body.joint == "prismatic" else (math.degrees(1.0), "deg")
        needed = goal_joint_state(problem, name, goal)
        if needed is not None and lower <= needed <= upper:
            needed = None  # the goal is within the limits: it is the motion's way there that passes one
        what = "the goal needs it at" if needed is not None else "it would have to move to"
        state = needed if needed is not None else state
        edge, side = (upper, "upper") if state > (lower + upper) / 2 else (lower, "lower")
        return (
            f"{name}: {what} {state * scale:.1f} {unit} on its {body.joint} joint, past its {side} limit of "
            f"{edge * scale:.1f} {unit} (range {lower * scale:.1f} to {upper * scale:.1f} {unit})"
        )
    overhang = max(_stay_constraints(problem, name, pose) or [0.0])
    return f"{name} would have to go {overhang * 100:.1f} cm past the table's edge (part of it leaves the table)"


def goal_joint_state(problem: Problem, name: str, goal: GoalSpec | None = None) -> float | None:
    """Where a goal puts a body's physical joint (m or rad); None without such a goal.

    A joint goal says it (`opening`); a position goal says it for a prismatic
    joint. `goal` picks the goal; by default, the body's first that says.
    """
    body = problem.bodies[name]
    if body.joint_axis is None:
        return None
    for chosen in problem.goals if goal is None else [goal]:
        if chosen.body != name:
            continue
        if chosen.opening is not None:
            return chosen.opening
        if body.joint == "prismatic" and chosen.position is not None:
            offset = np.zeros(3)
            offset[: len(chosen.position)] = chosen.position[:3] - body.rest[: len(chosen.position), 3]
            return body.start_state + float(body.joint_axis @ (body.rest[:3, :3].T @ offset))
    return None
