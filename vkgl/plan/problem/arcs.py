"""One push that slides and turns: the member of a slide's arc family that carries a body to its goal at once.

A slide whose family has an `arc` (docs/language.md, "Arcs") turns the body
when pushed off its centre, about a pivot that the offset places
(`vkgl.lang.ir.arcs`). For a goal that asks for a place and a heading, the
planner offers, besides the body's written affordances, the one member of each
such family that the law says takes the body from where it rests to the goal
in one contact: the offset (to the 0.01 cm a member's name keeps) whose turn
by exactly the goal's change of heading leaves the body nearest the goal's
position (the task-space search gives one turn the goal's heading exactly,
`vkgl.plan.task_space.closed_form`, and checks the position there). The member
is offered only when that position is inside the goal's tolerance.

The member is a plain turn named `NAME@+0.32cm`: the task-space search
chooses its angle like any turn's, and the executor resolves the same name to
the same member (`vkgl.lang.ir.families.find_member`), so the plan promises
exactly what the member does. It is offered for the body's rest pose only: a
body moved first by another contact keeps its written affordances.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.families import at_offset, member_name, member_offset
from vkgl.lang.ir.nodes import Affordance, FixedC, PrismaticC

STEP = 1e-4  # m: offsets are tried every 0.01 cm (what a member's name keeps)


def arc_members(
    affordances: tuple[Affordance, ...],
    rest: np.ndarray,
    goal: np.ndarray,
    goal_yaw: float,
    tolerances: tuple[float, float],
) -> tuple[Affordance, ...]:
    """The members (named `NAME@+S.SScm`) of the arc families among `affordances` that take a body resting at `rest`
    (4x4 world pose) to the planar position `goal` (m) and heading `goal_yaw` (rad) in one turn, within
    `tolerances` (m, rad); one member per family at most."""
    found = []
    for affordance in affordances:
        if _has_arc(affordance):
            best = _best_offset(affordance, rest, goal, goal_yaw, tolerances)
            if best is not None:
                found.append(
                    at_offset(affordance, best).model_copy(update={"name": member_name(affordance.name, best)})
                )
    return tuple(found)


def is_arc_member(name: str) -> bool:
    """Whether `name` names a member of a family (`NAME@+S.SScm`) rather than a written affordance."""
    return member_offset(name)[0] != name


def _has_arc(affordance: Affordance) -> bool:
    family = affordance.family
    return (
        family is not None
        and family.arc is not None
        and isinstance(affordance.motion, PrismaticC)
        and isinstance(affordance.action, FixedC)
        and affordance.action.pose is not None
    )


def _best_offset(
    slide: Affordance, rest: np.ndarray, goal: np.ndarray, goal_yaw: float, tolerances: tuple[float, float]
) -> float | None:
    """The offset (m, on the 0.01 cm grid, not 0) whose member, turned by the goal's change of heading, ends nearest
    the goal's position; None when none ends inside its tolerance."""
    family, motion, action = slide.family, slide.motion, slide.action
    assert family is not None and family.arc is not None and isinstance(motion, PrismaticC)
    assert isinstance(action, FixedC) and action.pose is not None
    offsets = np.arange(math.ceil(family.lower.value / STEP), math.floor(family.upper.value / STEP) + 1) * STEP
    offsets = offsets[np.abs(offsets) > STEP / 2]
    if offsets.size == 0 or motion.range is None:
        return None
    arc = family.arc
    normal = _unit(motion.axis.array())
    along = _unit(family.along.array())
    up = np.cross(normal, along)
    if abs(up[2]) < 0.99 or abs(rest[2, 2]) < 0.99:
        return None  # a turn about a vertical axis, of a body lying flat: the only arcs that were explored
    side = np.sign(offsets)
    radius = arc.lever.value**2 / np.abs(offsets) + arc.bias.value
    pivots = action.pose.position.array() + arc.ahead.value * normal - (side * radius)[:, None] * along
    sense = -side * up[2]  # + : counter-clockwise seen from above
    world = pivots @ rest[:3, :3].T + rest[:3, 3]
    yaw = math.atan2(rest[1, 0], rest[0, 0])
    wanted = math.remainder(goal_yaw - yaw, math.tau)
    usable = (sense * wanted > 0) & (np.abs(wanted) <= motion.range.upper.value / np.hypot(radius, arc.ahead.value))
    start = rest[:2, 3]
    c, s = math.cos(wanted), math.sin(wanted)
    rel = start - world[:, :2]
    ends = world[:, :2] + np.stack([c * rel[:, 0] - s * rel[:, 1], s * rel[:, 0] + c * rel[:, 1]], axis=1)
    score = np.where(usable, np.hypot(*(ends - goal[:2]).T) / tolerances[0], np.inf)
    index = int(np.argmin(score))
    if not score[index] <= 1.0:
        return None
    # the offset as the member's name gives it back (`push@+0.32cm` -> 0.0032), so planner and executor agree
    return member_offset(member_name(slide.name, float(offsets[index])))[1]


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)
