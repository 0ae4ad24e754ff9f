"""Which moving affordances cannot end a goal body at its goal in one mode from rest: part 7 of the search's bound.

A goal body that is no tool and has no `free` affordance moves only during modes of its own moving affordances
(`movers`), and the first of them starts from its rest pose (`vkgl.plan.search.bounds.bound`, part 1). When a
sequence has moved it once, by mover `a`, it lies where that one mode from rest put it: `rest @ member_motions(v, s)`
for a value `v` within `value_bounds(a)` and a contact offset `s` within the engagement's band (a family's or an
arc member's, `members.contact_band`; a slide's offset, a tool's flat face off its centre, moves the contact, not
the body). When no `(v, s)` puts its origin within the goal's position tolerance (and its heading within the
heading's), the sequence cannot end there: another mode must move it. `missing_movers` names those movers.

**Rigour on a grid.** Decided only for a body whose movers keep it level (`goal_reach.level_movers`: slides along
horizontal axes, turns about vertical ones, at rest) and that has no physical joint; for any other body no mover
is named. A slide moves the origin along a line: its distance to the goal over the slide's values is exact. A turn
by `θ` about a vertical axis through the pivot `c(s)` moves the origin along a circle about `c(s)`: between two
sampled angles `h` apart the true one lies within `r h / 2` of the nearer sample (`r` the origin's horizontal
distance from the axis), and between two sampled offsets the pivot lies on the segment between theirs (a family's
pivot moves by `s * drift`, an arc member's along a line, monotonically: `members.ArcSeed`), within `δ` (their
distance) of the lower one, which moves a turned point by `|(I - R) δ| <= 2 δ`. A mover is named only when every
sample misses the goal by more than that (and `SLACK`); its heading changes by exactly the turn's angle, so half an
angle step is the heading's room.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.members import contact_band, pivot_shift
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import value_bounds
from vkgl.plan.problem.problem import GoalSpec, PlanBody, Problem
from vkgl.plan.search.bounds.goal_reach import SLACK as GOAL_SLACK
from vkgl.plan.search.bounds.goal_reach import level_movers
from vkgl.se3 import wrap_angle, yaw_of

SLACK = GOAL_SLACK
"""m or rad: what the optimiser's tolerances may let a goal pass by (`goal_reach.SLACK`), kept as room."""

STEP = 0.002
"""m: the most half an angle step moves the origin (so the grid misses at most this)."""

MAX_ANGLES = 2001
"""Angles sampled per turn and offset at most."""

OFFSETS = 17
"""Offsets sampled over a turn's band."""


def missing_movers(problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance]) -> frozenset[str]:
    """The movers of `body` whose one mode from rest cannot end it where `goal` accepts it (the module's
    docstring); empty whenever that cannot be decided."""
    if goal.position is None or body.joint is not None or not movers or not level_movers(body, movers):
        return frozenset()
    return frozenset(m.name for m in movers if _misses(problem, body, goal, m))


def _misses(problem: Problem, body: PlanBody, goal: GoalSpec, mover: Affordance) -> bool:
    """Whether one mode of `mover` from rest misses `goal` (position or heading) whatever its value and offset."""
    assert goal.position is not None
    dims = len(goal.position)
    target = np.asarray(goal.position, dtype=float)
    low, high = value_bounds(mover.motion)
    axis, center = unit_axis_and_center(mover.motion)
    room = goal.tol_position + SLACK
    heading = goal.yaw is not None and math.hypot(body.rest[0, 0], body.rest[1, 0]) >= 0.1  # (else undefined)
    if center is None:  # a slide: the origin on a segment, the heading kept
        if heading and goal.yaw is not None and abs(wrap_angle(yaw_of(body.rest) - goal.yaw)) > goal.tol_yaw + SLACK:
            return True
        direction = (body.rest[:3, :3] @ axis)[:dims]
        origin = body.rest[:dims, 3]
        square = float(direction @ direction)
        value = low if square < 1e-18 else float(np.clip((target - origin) @ direction / square, low, high))
        return float(np.linalg.norm(origin + value * direction - target)) > room
    sign = float(np.sign((body.rest[:3, :3] @ axis)[2]))  # the turn about the world's z axis, up or down
    band = contact_band(problem, body.name, mover.name)
    offsets = np.linspace(band[0], band[1], OFFSETS) if band[1] > band[0] else np.zeros(1)
    pivots = np.array([_world_pivot(problem, body, mover, center, float(s)) for s in offsets])
    moves = np.r_[np.linalg.norm(np.diff(pivots, axis=0), axis=1), 0.0]  # to the next sample's pivot
    arms = body.rest[:2, 3] - pivots  # the origin from each pivot (horizontal)
    radius = float(np.max(np.linalg.norm(arms, axis=1)) + np.max(moves))
    count = min(MAX_ANGLES, max(2, math.ceil((high - low) * radius / (2 * STEP)) + 1))
    angles = np.linspace(low, high, count)
    half = (high - low) / (count - 1) / 2
    cos, sin = np.cos(sign * angles), np.sin(sign * angles)
    ends_x = pivots[:, None, 0] + cos[None] * arms[:, None, 0] - sin[None] * arms[:, None, 1]
    ends_y = pivots[:, None, 1] + sin[None] * arms[:, None, 0] + cos[None] * arms[:, None, 1]
    miss = np.hypot(ends_x - target[0], ends_y - target[1])  # offsets x angles
    if dims > 2:
        miss = np.hypot(miss, body.rest[2, 3] - target[2])  # level: its height stays its rest's
    near = miss <= room + radius * half + 2.0 * moves[:, None]
    if heading and goal.yaw is not None:  # a turn about the vertical turns the heading by its angle
        off = np.abs([wrap_angle(yaw_of(body.rest) + sign * float(a) - goal.yaw) for a in angles])
        near &= (off <= goal.tol_yaw + SLACK + half)[None]
    return not bool(near.any())


def _world_pivot(problem: Problem, body: PlanBody, mover: Affordance, center: np.ndarray, offset: float) -> np.ndarray:
    """The turn's pivot (world, horizontal) at contact offset `offset`."""
    shift = pivot_shift(problem, body.name, mover.name, offset)
    pivot = center if shift is None else center + shift
    return (body.rest[:3, :3] @ pivot + body.rest[:3, 3])[:2]


__all__ = ["missing_movers"]
