"""What slides and turns can do for a goal body's position and heading, per contact: part 1 of the search's bound.

A slide moves its body's frame origin by at most its range's upper end and keeps its heading; a turn changes the
heading by at most its angle (about an axis vertical in the world; up to half a turn about any other) and moves
the origin by at most its chord `2 r sin(θ / 2)`, `r` the origin's distance from the axis, the largest over its
family's band. `fewest_modes` counts the fewest contacts that can cover a distance and a heading together
(`vkgl.plan.search.bounds.bound`'s docstring, parts 1 and 2, says why that never overestimates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vkgl.lang.ir.families import offset_bounds
from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.members import arc_seed_in, family_vectors
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import value_bounds
from vkgl.plan.problem.problem import GoalSpec, PlanBody
from vkgl.se3 import wrap_angle, yaw_of

SLACK = 1e-6
"""Rounding room (m, rad, or modes): a need within it of a whole number of steps is that number, never one more."""


@dataclass(frozen=True)
class PoseNeed:
    """How far a goal body must move (`distance`, m) and turn (`heading`, rad) less the tolerances, and the most one
    slide (`slide`, m), one turn (`turn`, rad) and its chord (`chord`, m) can do of it (part 1)."""

    distance: float
    heading: float
    slide: float
    turn: float
    chord: float

    def left(self, slides: int, turns: int) -> float:
        """The fewest moving modes still needed after `slides` slides and `turns` turns of the body (part 2)."""
        distance = self.distance - slides * self.slide - turns * self.chord
        heading = self.heading - turns * self.turn
        return fewest_modes(distance, heading, self.slide, self.turn, self.chord)


def pose_need(body: PlanBody, goal: GoalSpec, movers: list[Affordance]) -> PoseNeed | None:
    """What `goal`'s position and heading need of slides and turns (part 1), or None when neither is off."""
    rest = body.rest
    distance = heading = 0.0
    if goal.position is not None:
        distance = float(np.linalg.norm(rest[: len(goal.position), 3] - goal.position)) - goal.tol_position
    if goal.yaw is not None:
        heading = abs(wrap_angle(yaw_of(rest) - goal.yaw)) - goal.tol_yaw
    if distance <= SLACK and heading <= SLACK:
        return None
    turners = [a for a in movers if a.motion.type == "revolute"]
    level = all(vertical(rest, a) for a in turners)  # else one turn may tilt the others' axes
    return PoseNeed(
        distance=max(0.0, distance),
        heading=max(0.0, heading),
        slide=max((translation(a) for a in movers if a.motion.type == "prismatic"), default=0.0),
        turn=max((value_bounds(a.motion)[1] if level else math.pi for a in turners), default=0.0),
        chord=max((translation(a, body.affordances) for a in turners), default=0.0),
    )


def fewest_modes(distance: float, heading: float, slide: float, turn: float, chord: float) -> float:
    """The fewest modes `k + j` of `k` turns (each changes the heading by at most `turn` and moves the origin by at
    most `chord`) and `j` slides (each moves it by at most `slide`, the heading not at all) that cover `distance`
    (m) and `heading` (rad): `k >= heading / turn` and `k chord + j slide >= distance` (triangle inequality)."""
    turns = 0
    if heading > SLACK:
        if turn <= 0:
            return math.inf
        turns = max(1, math.ceil(heading / turn - SLACK))
    if distance <= SLACK:
        return float(turns)

    def slides(k: int) -> float:
        rest = distance - k * chord
        if rest <= SLACK:
            return 0.0
        return math.ceil(rest / slide - SLACK) if slide > 0 else math.inf

    if slide <= 0:
        return float(max(turns, math.ceil(distance / chord - SLACK))) if chord > 0 else math.inf
    best, k = turns + slides(turns), turns
    while k + 1 < best:  # one more turn may save a slide; never more modes than `best`
        k += 1
        best = min(best, k + slides(k))
    return float(best)


def translation(affordance: Affordance, siblings: tuple[Affordance, ...] = ()) -> float:
    """The farthest one mode of `affordance` moves its body's frame origin (m).

    A turn's pivot may move along its family (`offset * drift`, `vkgl.plan.graphs.members`): the radius is the
    largest over the band, at one of its ends (the distance to the axis is convex in the offset). A member of a
    slide's arc family among `siblings` (its body's affordances) moves its pivot along a line over its band
    (`members.ArcSeed`): the largest at one of the band's ends too (its turn is never more than its own range:
    `members.turn_cap`)."""
    upper = value_bounds(affordance.motion)[1]
    axis, center = unit_axis_and_center(affordance.motion)
    if center is None:
        return upper
    _, drift = family_vectors(affordance)
    ends = offset_bounds(affordance) if drift is not None else (0.0, 0.0)
    pivots = [center if drift is None else center + s * drift for s in ends]
    seed = arc_seed_in(siblings, affordance) if siblings else None
    if seed is not None:
        pivots += [center + seed.shift(d) for d in seed.band]
    radius = max(float(np.linalg.norm(p - np.dot(p, axis) * axis)) for p in pivots)
    return 2.0 * radius * math.sin(min(upper, math.pi) / 2.0)


def vertical(rest: np.ndarray, affordance: Affordance) -> bool:
    """Whether `affordance` turns its body about an axis vertical in the world (at `rest`; slides and such turns
    keep it vertical). A turn about it changes the heading by its angle; about any other, by up to half a turn."""
    axis, _ = unit_axis_and_center(affordance.motion)
    return abs(float((rest[:3, :3] @ axis)[2])) > 1.0 - 1e-9
