"""Whether the hand itself can hold a body's contact where the body ends: part 6 of the search's bound.

A goal body that is no tool and has no `free` affordance moves only while an
engagement of one of its moving affordances (`movers`) is in force, and its
pose at the end of the sequence is its pose at the end of the last mode that
moved it (`vkgl.plan.search.bounds.bound`, part 1). In that mode some effector holds
the contact of a mover through to the mode's end, with the body at its goal
(within the goal's tolerances). When the robot's own effector enacts it, the
hand is at `pose @ action(s)` there (the action at offset `s` along its
family), and task space checks every hand sample of a mode against the
arm's reach, the mode's end included (`vkgl.plan.task_space.feasible`). So
when no such hand position lies inside the reach for any pose the goal
accepts, every feasible sequence moves the body last through a tool's frame,
and a tool frame acts only while its tool is held: a tool is in the hand then.

`ends_beyond_the_hand` decides it conservatively, only for bodies whose every
mover keeps them level at their height (slides along axes horizontal in the
world, turns about vertical axes, at rest; neither tilts the other's axes):
then the body's frame stays at its rest height, and its pose at the goal is
its rest orientation turned about the vertical by the heading change, moved
to a position within `tol_position` of the goal's. The hand's height is then
known exactly, and its radius from the arm's base is bounded from below and
above over the accepted headings and the family's band on a grid, less what
the grid may miss (Lipschitz: the radius changes by at most `|c|` per radian
of heading, `c` the contact's horizontal offset from the body's frame, and by
at most 1 m per m of offset); the position's tolerance and a millimetre of
the optimiser's slack are added.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.members import contact_band, contact_direction
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.problem.problem import GoalSpec, PlanBody, Problem
from vkgl.plan.task_space.reach.workspace import REACH_MARGIN, UPRIGHT
from vkgl.se3 import yaw_of

SLACK = 1e-3
"""m: what the optimiser's tolerances may let a hand sample pass the reach by, and the goal's tolerance too."""

HEADING_SAMPLES = 73
"""Headings sampled over a full turn (5 deg apart); a goal's tolerance band gets at least 9."""

OFFSET_SAMPLES = 9
"""Offsets sampled over a family's band."""


def ends_beyond_the_hand(
    problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance], chain: np.ndarray | None = None
) -> str | None:
    """Why no mover's contact, held by the robot's own effector with `body` anywhere `goal` accepts, lies within
    the arm's reach, with the numbers (see the module's docstring); None whenever that cannot be shown.

    With `chain` (the hand's pose in the frame of the effector that enacts the contact: a tool frame's inverse
    times the grasp by which the hand holds the tool, `rollout.hand_chain`), the same for that tool frame held
    by that grasp: the hand is then at `pose @ action(s) @ chain`."""
    if goal.position is None or not movers or not level_movers(body, movers):
        return None
    heading = _heading_change(body, goal)
    if heading is None:
        return None
    gaps = [_contact_beyond(problem, body, goal, mover, heading, chain) for mover in movers]
    if any(gap is None for gap in gaps):
        return None
    _, words = min(gap for gap in gaps if gap is not None)
    return f"wherever its goal accepts {body.name}, the hand at any of its contacts would be {words}"


def level_movers(body: PlanBody, movers: list[Affordance]) -> bool:
    """Whether every mover keeps the body level at its height: slides along horizontal axes, turns about vertical
    ones (in the world, at rest: a turn about a vertical axis keeps the other axes horizontal or vertical)."""
    rotation = body.rest[:3, :3]
    for mover in movers:
        axis, _ = unit_axis_and_center(mover.motion)
        z = abs(float((rotation @ axis)[2]))
        if mover.motion.type == "prismatic" and z > 1e-9:
            return False
        if mover.motion.type == "revolute" and z < 1.0 - 1e-9:
            return False
    return True


def _heading_change(body: PlanBody, goal: GoalSpec) -> tuple[float, float] | None:
    """The interval of heading changes (rad) from rest that the goal accepts (a full turn without a yaw goal), or
    None when the body's heading is not defined (its x axis vertical)."""
    if np.hypot(body.rest[0, 0], body.rest[1, 0]) < 0.1:
        return None
    if goal.yaw is None or goal.tol_yaw >= math.pi:
        return (-math.pi, math.pi)
    change = goal.yaw - yaw_of(body.rest)
    return (change - goal.tol_yaw, change + goal.tol_yaw)


def _contact_beyond(
    problem: Problem,
    body: PlanBody,
    goal: GoalSpec,
    mover: Affordance,
    heading: tuple[float, float],
    chain: np.ndarray | None = None,
) -> tuple[float, str] | None:
    """How far (m) and why the hand holding `mover`'s contact (through `chain`) is outside the reach wherever the
    goal accepts the body, or None when it may be inside."""
    assert goal.position is not None
    pose = problem.action(body.name, mover.name)
    action = pose[:3, 3] if chain is None else (pose @ chain)[:3, 3]  # the offset moves the hand as the contact
    along = contact_direction(problem, body.name, mover.name)
    lower, upper = contact_band(problem, body.name, mover.name)  # an arc member's too (`members.ArcSeed`)
    offsets = np.linspace(lower, upper, OFFSET_SAMPLES if upper > lower else 1)
    contacts = (body.rest[:3, :3] @ (action[:, None] + np.outer(along, offsets))).T  # per offset, world axes
    heights = body.rest[2, 3] + contacts[:, 2]
    if np.ptp(heights) > 1e-9:
        return None  # the hand's height changes along the band: not decided here
    height = float(heights[0])
    r_min, r_max = problem.arm.reach(height)
    if r_max <= 0:
        return 1.0, f"at height {height:.3f} m, where the arm reaches nowhere"
    width = heading[1] - heading[0]
    count = HEADING_SAMPLES if width >= 2 * math.pi - 1e-9 else max(9, math.ceil(width / math.radians(5)) + 1)
    angles = np.linspace(heading[0], heading[1], count)
    offset_xy = contacts[:, :2]
    spin = np.stack([np.cos(angles), -np.sin(angles), np.sin(angles), np.cos(angles)], axis=1).reshape(-1, 2, 2)
    turned = np.einsum("hij,oj->hoi", spin, offset_xy)  # headings x offsets x 2
    centre = np.asarray(goal.position[:2], dtype=float) - problem.arm.base[:2, 3]
    radii = np.linalg.norm(centre + turned, axis=2)
    step_heading = width / (count - 1) if count > 1 else 0.0
    step_offset = (upper - lower) / (len(offsets) - 1) if len(offsets) > 1 else 0.0
    missed = float(np.max(np.linalg.norm(offset_xy, axis=1))) * step_heading / 2 + step_offset / 2
    slack = missed + goal.tol_position + SLACK
    hand = pose if chain is None else pose @ chain
    if hand[2, 2] < 1.0 - UPRIGHT:  # a tilted hand is counted up to this much nearer or farther (`hand_down_point`)
        slack += problem.arm.wrist_lever * math.hypot(hand[0, 2], hand[1, 2])
    usable = (
        f"from the arm's base at height {height:.3f} m (usable reach there: {r_min + REACH_MARGIN:.3f} to "
        f"{r_max - REACH_MARGIN:.3f} m)"
    )
    if (beyond := radii.min() - slack - (r_max - REACH_MARGIN)) > 0:
        return float(beyond), f"at least {radii.min() - slack:.3f} m {usable}"
    if (within := r_min + REACH_MARGIN - radii.max() - slack) > 0:
        return float(within), f"at most {radii.max() + slack:.3f} m {usable}"
    return None


End = tuple[str | None, str | None, str]
"""(tool or None for the robot's own effector, the grasp by which the hand holds that tool or None, mover)."""


def wrong_ends(problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance]) -> frozenset[End]:
    """Each effector and mover that cannot end `body` where `goal` accepts it: `(None, None, mover)` when the
    robot's own effector cannot hold that mover's contact there in reach, `(tool, grasp, mover)` when no frame
    of `tool` held by `grasp` can (`ends_beyond_the_hand` of that one mover, through each chain). The proof is
    the module's, for one mover: the last mode that moves the body is some effector's mode of some mover, with
    the hand in reach at its end and the body where the goal accepts it."""
    return WrongEnds(problem, body, goal, movers).every()


class WrongEnds:
    """`wrong_ends`, found end by end when asked (`end in self`) and kept: a search asks about the few effectors,
    grasps and contacts its sequences end with, and each costs a grid of headings and offsets."""

    def __init__(self, problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance]) -> None:
        self.problem, self.body, self.goal = problem, body, goal
        self.movers = {m.name: m for m in movers}
        self.known: dict[object, bool] = {}

    def __contains__(self, end: object) -> bool:
        """Whether `end` (tool or None, grasp or None, mover) cannot end the body where the goal accepts it."""
        known = self.known.get(end)
        if known is None:
            known = self.known[end] = self._wrong(end)
        return known

    def every(self) -> frozenset[End]:
        """Every end that cannot (each effector, each grasp of a tool, each mover)."""
        grasps: list[tuple[str | None, str | None]] = [(None, None)]
        for tool in sorted({e.tool for e in self.problem.effectors if e.tool is not None}):
            grasps += [(tool, a.name) for a in self.problem.bodies[tool].affordances if a.motion.type == "free"]
        return frozenset((t, g, m) for t, g in grasps for m in self.movers if (t, g, m) in self)

    def _wrong(self, end: object) -> bool:
        assert isinstance(end, tuple) and len(end) == 3
        tool, grasp, name = end
        mover = self.movers.get(name)
        if mover is None:
            return False
        if tool is None:
            return bool(ends_beyond_the_hand(self.problem, self.body, self.goal, [mover]))
        frames = [e for e in self.problem.effectors if e.tool == tool]
        chains = [e.frame_inverse @ self.problem.action(tool, grasp) for e in frames]
        return bool(chains) and all(
            ends_beyond_the_hand(self.problem, self.body, self.goal, [mover], chain) for chain in chains
        )


__all__ = ["End", "WrongEnds", "ends_beyond_the_hand", "wrong_ends"]
