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

For a goal that leaves the heading free, the offered members are those whose
arc passes through the goal: per turning sense, the offset whose arc (within
the member's largest turn) comes nearest the goal's position, if inside the
tolerance, which leaves the law's error the most room. The task-space search
then turns the member to the arc's point nearest the goal (its optimiser,
from no turn: a single turn's distance to a point has one minimum over half a
turn). A family whose straight push (offset 0) already ends there gets none.
A member of an `open` slide turns on as far as the planner lets one turn go
(half a turn; the table and the collision checks decide).

The member is a turn named `NAME@+0.32cm`: the task-space search chooses its
angle like any turn's and its offset too, within half to twice its own
(`vkgl.plan.graphs.members.ArcSeed`), and the executor resolves the name of
the member chosen to the same member (`vkgl.lang.ir.families.find_member`),
so the plan promises exactly what the member does. The member is chosen for
the body's rest pose; a body moved first by another contact gets the same
member, whose offset the task space then fits to where the body lies. For a
goal whose change of heading (less its tolerance) is more than any written
turn of the body makes in one contact, the member nearest the goal is offered
however far its exact turn ends from it (a seed): only an arc turns the body
that far at once, and after an earlier contact (a push, a turn) its offset
reaches goals its own arc from rest misses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vkgl.lang.ir.families import at_offset, member_name, member_offset
from vkgl.lang.ir.nodes import Affordance, FixedC, PrismaticC, RevoluteC

STEP = 1e-4  # m: offsets are tried every 0.01 cm (what a member's name keeps)

HALF_TURN = math.pi
"""rad: the planner's cap on one turn (`vkgl.plan.graphs.rollout.REVOLUTE_MAX`), the largest turn of a member of
an `open` slide (pushed on, the body goes on turning; the table and the collision checks bound it)."""


def arc_members(
    affordances: tuple[Affordance, ...],
    rest: np.ndarray,
    goal: np.ndarray,
    goal_yaw: float | None,
    tolerances: tuple[float, float],
    reach: float | None = None,
) -> tuple[Affordance, ...]:
    """The members (named `NAME@+S.SScm`) of the arc families among `affordances` that take a body resting at `rest`
    (4x4 world pose) to the planar position `goal` (m) in one turn, within `tolerances` (m, rad).

    With a heading `goal_yaw` (rad): the member turned by exactly the goal's change of heading, one per family at
    most. Without (`None`, the heading free): the members whose arc passes through the goal, one per turning
    sense of each family at most, and none for a family whose straight push already reaches it.

    `reach`: how many position tolerances from the goal the exact turn of a place-and-heading goal's member may
    end; by default 1, or any distance (a seed) when the goal's change of heading is more than every written turn
    of the body makes (`_beyond_turns`).
    """
    found = []
    if reach is None:
        beyond = goal_yaw is not None and _beyond_turns(affordances, rest, goal_yaw, tolerances[1])
        reach = math.inf if beyond else 1.0
    for affordance in affordances:
        arc = _arc_geometry(affordance, rest)
        if arc is None:
            continue
        if goal_yaw is None:
            picks = _free_heading_offsets(arc, rest, goal, tolerances[0])
        else:
            picks = [p for p in [_best_offset(arc, rest, goal, goal_yaw, tolerances[0], reach)] if p is not None]
        for index in picks:
            # the offset as the member's name gives it back (`push@+0.32cm` -> 0.0032): planner and executor agree
            name = member_name(affordance.name, float(arc.offsets[index]))
            found.append(at_offset(affordance, member_offset(name)[1]).model_copy(update={"name": name}))
    return tuple(found)


def is_arc_member(name: str) -> bool:
    """Whether `name` names a member of a family (`NAME@+S.SScm`) rather than a written affordance."""
    return member_offset(name)[0] != name


@dataclass(frozen=True)
class _ArcGeometry:
    """Every member of one arc family on the 0.01 cm grid, in the world, for a body at rest: the offsets (m, not 0),
    their pivots (n x 2, m), turning senses (+1: counter-clockwise seen from above) and largest turns (rad, the
    slide's range as travel along the arc); `push` the straight push's direction (2, unit) and `travel` its range
    (m; inf when `open`)."""

    offsets: np.ndarray
    pivots: np.ndarray
    senses: np.ndarray
    max_turns: np.ndarray
    push: np.ndarray
    travel: float


def _arc_geometry(slide: Affordance, rest: np.ndarray) -> _ArcGeometry | None:
    """The members of `slide`'s arc family for a body resting at `rest`; None without an arc, a range, any offset
    but 0, or a vertical turn of a body lying flat (the only arcs that were explored)."""
    family, motion, action = slide.family, slide.motion, slide.action
    if family is None or family.arc is None or not isinstance(motion, PrismaticC) or motion.range is None:
        return None
    if not isinstance(action, FixedC) or action.pose is None:
        return None
    offsets = np.arange(math.ceil(family.lower.value / STEP), math.floor(family.upper.value / STEP) + 1) * STEP
    offsets = offsets[np.abs(offsets) > STEP / 2]
    normal = _unit(motion.axis.array())
    along = _unit(family.along.array())
    up = np.cross(normal, along)
    if offsets.size == 0 or abs(up[2]) < 0.99 or abs(rest[2, 2]) < 0.99:
        return None
    arc = family.arc
    side = np.sign(offsets)
    radius = arc.lever.value**2 / np.abs(offsets) + arc.bias.value
    lever = np.hypot(radius, arc.ahead.value)  # the contact's travel per radian of turn
    pivots = action.pose.position.array() + arc.ahead.value * normal - (side * radius)[:, None] * along
    world = pivots @ rest[:3, :3].T + rest[:3, 3]
    push = (rest[:3, :3] @ normal)[:2]
    return _ArcGeometry(
        offsets=offsets,
        pivots=world[:, :2],
        senses=-side * up[2],
        max_turns=np.full(offsets.size, HALF_TURN) if motion.range.open else motion.range.upper.value / lever,
        push=push / np.linalg.norm(push),
        travel=math.inf if motion.range.open else float(motion.range.upper.value),
    )


def _beyond_turns(affordances: tuple[Affordance, ...], rest: np.ndarray, goal_yaw: float, tol_yaw: float) -> bool:
    """Whether the goal's change of heading (less its tolerance) is more than any written turn of the body makes in
    one contact: then only an arc member turns it so far at once."""
    wanted = abs(math.remainder(goal_yaw - math.atan2(rest[1, 0], rest[0, 0]), math.tau)) - tol_yaw
    turns = [a.motion for a in affordances if isinstance(a.motion, RevoluteC) and not is_arc_member(a.name)]
    largest = max((HALF_TURN if t.range is None or t.range.open else t.range.upper.value for t in turns), default=0.0)
    return wanted > largest


def _best_offset(
    arc: _ArcGeometry, rest: np.ndarray, goal: np.ndarray, goal_yaw: float, tolerance: float, reach: float = 1.0
) -> int | None:
    """The index of the offset whose member, turned by the goal's change of heading, ends nearest the goal's
    position; None when none ends within `reach` times the `tolerance` (m)."""
    wanted = math.remainder(goal_yaw - math.atan2(rest[1, 0], rest[0, 0]), math.tau)
    usable = (arc.senses * wanted > 0) & (np.abs(wanted) <= arc.max_turns)
    ends = _turned(arc.pivots, rest[:2, 3], np.full(len(arc.offsets), wanted))
    score = np.where(usable, np.hypot(*(ends - goal[:2]).T) / tolerance, np.inf)
    index = int(np.argmin(score))
    return index if score[index] <= reach else None


def _free_heading_offsets(arc: _ArcGeometry, rest: np.ndarray, goal: np.ndarray, tolerance: float) -> list[int]:
    """For a goal that leaves the heading free: per turning sense, the index of the offset whose arc (within its
    largest turn) comes nearest the goal's position, if inside the `tolerance` (m). Nothing when the straight push
    (offset 0) ends there already: a member is offered for what the slide itself cannot do.

    The body's position on a member's arc nearest the goal is at the turn that brings the start's bearing from
    the pivot to the goal's (clipped to the member's range): what the task-space search chooses for a turn whose
    goal has no heading. The nearest arc is the one with the most margin for the law's error.
    """
    start = rest[:2, 3]
    ahead = float(np.dot(goal[:2] - start, arc.push))
    if np.linalg.norm(start + min(max(ahead, 0.0), arc.travel) * arc.push - goal[:2]) <= tolerance:
        return []
    from_pivot, to_goal = start - arc.pivots, goal[:2] - arc.pivots
    bearing = np.arctan2(to_goal[:, 1], to_goal[:, 0]) - np.arctan2(from_pivot[:, 1], from_pivot[:, 0])
    turn = np.mod(arc.senses * bearing, math.tau)  # the turn in the member's own sense, in [0, 2 pi)
    beyond = turn > arc.max_turns
    nearer_zero = math.tau - turn < turn - arc.max_turns  # past the range: clip to the nearer end
    turn = np.where(beyond, np.where(nearer_zero, 0.0, arc.max_turns), turn)
    miss = np.hypot(*(_turned(arc.pivots, start, arc.senses * turn) - goal[:2]).T)
    picks = []
    for sense in (1.0, -1.0):
        scores = np.where((arc.senses == sense) & (turn > 0.0), miss, np.inf)
        index = int(np.argmin(scores))
        if scores[index] <= tolerance:
            picks.append(index)
    return picks


def _turned(pivots: np.ndarray, start: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """Where `start` (2,) ends, turned about each pivot (n x 2) by its angle (n, rad, counter-clockwise)."""
    c, s = np.cos(angles), np.sin(angles)
    rel = start - pivots
    return pivots + np.stack([c * rel[:, 0] - s * rel[:, 1], s * rel[:, 0] + c * rel[:, 1]], axis=1)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)
