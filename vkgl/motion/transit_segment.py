"""One timed, collision-free transit of an arm among a scene's bodies: what the planner and the executor share.

`transit_segment(collision, start, goal, poses, held, seed=...)` tries, in
turn, the straight joint-space line, going up over what stands between the
ends (`over`: the configurations `VIA_HEIGHTS` above both ends), and OMPL's
RRTConnect (`vkgl.motion.transit.plan_transit`). Valid configurations keep the
arm's links (and a held tool) clear of every body and the table
(`vkgl.motion.arm_collision`). The path is timed within the URDF's joint velocity
limits scaled by `TRANSIT_SPEED_SCALE` (`vkgl.motion.timing`).

Given the real shapes (`exact`), an end inside the transit's room (the bodies
grown) where the arm touches nothing is left (the goal: entered) by the
shortest straight hand move out of the room (`vkgl.motion.escape.way_out`):
the arm's ready pose beside a cupboard starts every plan there.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping

import numpy as np

from vkgl.formats.plan import ArmSegment
from vkgl.motion.arm_collision import ArmCollision, Held
from vkgl.motion.density import DEFAULT_TOLERANCE, edge_resolution, link_reach
from vkgl.motion.escape import way_out
from vkgl.motion.timing import arm_velocity_limits, time_path
from vkgl.motion.transit import TransitFailure, plan_transit
from vkgl.robot import Arm

TRANSIT_SPEED_SCALE = 0.35
"""Transits run at this fraction of the URDF's joint velocity limits (0.76 rad/s for the Panda's joints 1-4)."""

TRANSIT_TIME_LIMIT = 5.0
"""s: the clock's bound on OMPL's search for one transit (less when the search's deadline is nearer); its budget
of validity checks (`vkgl.motion.transit.SEARCH_CHECKS`) normally ends a failing search first, deterministically."""

HELD_TOLERANCE = 0.004
"""m: with a tool in the hand no point of the arm or the tool moves more than this between two checked
configurations (without one, `vkgl.motion.density.DEFAULT_TOLERANCE`, 1 cm, as the bare arm keeps 1 cm from
every body): the planner keeps a held tool 2 mm clear of the bodies it does not work on, so samples 4 mm apart
keep the line between them clear."""

VIA_HEIGHTS = (0.1, 0.2)
"""m: before OMPL is asked, a transit tries going this high over what lies between its ends."""


def transit_segment(
    collision: ArmCollision,
    start: np.ndarray,
    goal: np.ndarray,
    poses: Mapping[str, np.ndarray],
    held: Held | None = None,
    *,
    seed: int,
    time_limit: float = TRANSIT_TIME_LIMIT,
    exact: ArmCollision | None = None,
) -> ArmSegment | TransitFailure:
    """A timed, collision-free transit from `start` to `goal` with the bodies at `poses`, or why there is none.

    `exact`: the arm against the bodies' real shapes, where `collision` checks them grown by a room: an end
    inside the room that touches nothing is left along `vkgl.motion.escape.way_out` (the goal entered along it
    reversed), and the rest keeps the room."""
    arm = collision.arm
    collision.scene.place(poses)

    def valid(q: np.ndarray) -> bool:
        return collision.free(q, held=held)

    reach = 0.0 if held is None else tool_reach(collision, held)
    out, into = _ways_out(collision, exact, start, goal, poses, held, reach)
    advance = (collision.clearance(held), link_reach(arm, reach))
    found = plan_transit(
        out[-1], into[-1], valid, arm.lower, arm.upper, seed=seed, time_limit=time_limit,
        resolution=edge_resolution(arm, DEFAULT_TOLERANCE if held is None else HELD_TOLERANCE, reach),
        via=_over_when_asked(arm, out[-1], into[-1]), advance=advance,
    )  # fmt: skip
    if isinstance(found, TransitFailure):
        return found
    waypoints = np.vstack([out[:-1], found.waypoints, into[::-1][1:]])
    timed = time_path(waypoints, _velocity(arm), velocity_scale=TRANSIT_SPEED_SCALE)
    return ArmSegment("transit", np.asarray(timed.times, dtype=float), waypoints)


def _ways_out(
    collision: ArmCollision,
    exact: ArmCollision | None,
    start: np.ndarray,
    goal: np.ndarray,
    poses: Mapping[str, np.ndarray],
    held: Held | None,
    reach: float,
) -> tuple[np.ndarray, np.ndarray]:
    """The ways out of the room from the start and from the goal (each k x n, the end first; just the end when
    it is clear of the room, has no way out, or no `exact` geometry is given: the transit then fails there)."""
    ends = []
    for q in (np.asarray(start, dtype=float), np.asarray(goal, dtype=float)):
        found = None
        if exact is not None and not collision.free(q, held=held):
            exact.scene.place(poses)
            found = way_out(collision, exact, q, held, reach)
        ends.append(q[None] if found is None else found)
    return ends[0], ends[1]


def over(arm: Arm, start: np.ndarray, goal: np.ndarray) -> list[np.ndarray]:
    """Up, across and down: the configurations `VIA_HEIGHTS` above both ends, for each height IK finds.

    Most transits whose straight joint-space line is blocked are blocked by
    what stands on the table between the ends (the body a hook must reach
    behind); going over it is the obvious way, and checking it costs far
    less than a sampling-based search.
    """
    return list(_over_when_asked(arm, start, goal))


def _over_when_asked(arm: Arm, start: np.ndarray, goal: np.ndarray) -> Iterator[np.ndarray]:
    """`over`'s polylines, each solved only when the transit gets to it (most transits take the straight line,
    and each height costs two IK solves)."""
    for height in VIA_HEIGHTS:
        yield from _over_at(arm, start, goal, height)


def _over_at(arm: Arm, start: np.ndarray, goal: np.ndarray, height: float) -> list[np.ndarray]:
    ends = []
    for q in (start, goal):
        pose = arm.fk(q)
        pose[2, 3] += height
        found = arm.ik(pose, q0=q)
        if found is not None:
            ends.append(np.asarray(found, dtype=float))
    return [np.vstack(ends)] if len(ends) == 2 else []


def tool_reach(collision: ArmCollision, held: Held) -> float:
    """How far a held tool reaches beyond the effector (m): for the check density of transits."""
    radius = collision.scene.radius.get(held.body, 0.0)
    return float(np.linalg.norm(held.in_hand[:3, 3]) + radius)


def _velocity(arm: Arm) -> np.ndarray:
    """The arm's joint velocity limits from its URDF (rad/s), read once per URDF."""
    return arm_velocity_limits(arm)


__all__ = [
    "HELD_TOLERANCE",
    "TRANSIT_SPEED_SCALE",
    "TRANSIT_TIME_LIMIT",
    "VIA_HEIGHTS",
    "over",
    "tool_reach",
    "transit_segment",
]
