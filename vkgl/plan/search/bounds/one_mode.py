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

**With the hand** (`missing_ends`). The mode also holds the hand, at `rest @ member_motions(f v, s) @ chain` at the
fractions `f` of its value task space checks (`feasible.TASK_SAMPLES`, the ends included), inside the arm's reach
(`chain`: the action at `s`, through a tool frame and the grasp by which the hand holds the tool: the tool jumps to
its contact when the contact is made, whatever it did before, `rollout.hand_chain`). So an effector (a tool held by
a grasp) and a mover are named when no `(v, s)` that ends the body where the goal accepts it keeps every such hand
sample in reach. Rigour as above: a sample moves by at most the hand's distance from the axis times half an angle
step, by `2 δ` with the pivot and by the offset's change with the contact; the reach's violation is 1-Lipschitz in
the hand's horizontal position at one height (a contact whose height changes along its band is not decided), and a
tilted hand is judged at its own point less `wrist_lever` times its z axis's horizontal part, as `goal_reach` does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.members import action_at, contact_band, pivot_shift
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import value_bounds
from vkgl.plan.graphs.tool_faces import slide_band
from vkgl.plan.problem.problem import GoalSpec, PlanBody, Problem
from vkgl.plan.search.bounds.goal_reach import SLACK as GOAL_SLACK
from vkgl.plan.search.bounds.goal_reach import End, level_movers
from vkgl.plan.task_space.feasible import TASK_SAMPLES
from vkgl.plan.task_space.reach.workspace import REACH_MARGIN, UPRIGHT
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
        off = np.abs(_wrapped(yaw_of(body.rest) + sign * angles - goal.yaw))
        near &= (off <= goal.tol_yaw + SLACK + half)[None]
    return not bool(near.any())


def _world_pivot(problem: Problem, body: PlanBody, mover: Affordance, center: np.ndarray, offset: float) -> np.ndarray:
    """The turn's pivot (world, horizontal) at contact offset `offset`."""
    shift = pivot_shift(problem, body.name, mover.name, offset)
    pivot = center if shift is None else center + shift
    return (body.rest[:3, :3] @ pivot + body.rest[:3, 3])[:2]


def missing_ends(
    problem: Problem, body: PlanBody, goal: GoalSpec, movers: list[Affordance], misses: frozenset[str]
) -> frozenset[End]:
    """Each effector (a tool by its grasp) and mover not in `misses` whose one mode from rest cannot end `body` where
    `goal` accepts it with the hand in reach at every sample (the module's docstring, "With the hand"); empty
    whenever that cannot be decided (and with a tool of two frames: the hand may follow the other's contact)."""
    if goal.position is None or body.joint is not None or not movers or not level_movers(body, movers):
        return frozenset()
    tools = [e.tool for e in problem.effectors if e.tool is not None]
    if len(tools) != len(set(tools)):
        return frozenset()
    out: set[End] = set()
    for mover in movers:
        if mover.name in misses:
            continue
        for end, effector, chain in _chains(problem, mover):
            mode = _Mode(problem, body, goal, mover, Engagement(effector, body.name, mover.name), chain)
            if not mode.ends_with_hand():
                out.add(end)
    return frozenset(out)


def _chains(problem: Problem, mover: Affordance) -> list[tuple[End, str, np.ndarray | None]]:
    """(End, effector, the hand in the tool frame's frame or None for the robot's own) of every effector and grasp."""
    out: list[tuple[End, str, np.ndarray | None]] = [((None, None, mover.name), problem.robot_effector.name, None)]
    for effector in problem.effectors:
        if effector.tool is None:
            continue
        for grasp in problem.bodies[effector.tool].affordances:
            if grasp.motion.type == "free":
                chain = effector.frame_inverse @ problem.action(effector.tool, grasp.name)
                out.append(((effector.tool, grasp.name, mover.name), effector.name, chain))
    return out


@dataclass(frozen=True)
class _Mode:
    """One mode from rest of `mover` on `body`, enacted by `engagement`'s effector (the hand in the tool frame's
    frame `tool_chain`, or None for the robot's own effector), judged against `goal`."""

    problem: Problem
    body: PlanBody
    goal: GoalSpec
    mover: Affordance
    engagement: Engagement
    tool_chain: np.ndarray | None

    def ends_with_hand(self) -> bool:
        """Whether some value and offset of the mode may end the body at its goal with every hand sample in reach
        (True when not decided)."""
        band = slide_band(self.problem, self.engagement) or contact_band(self.problem, self.body.name, self.mover.name)
        offsets = np.linspace(band[0], band[1], OFFSETS) if band[1] > band[0] else np.zeros(1)
        for i, offset in enumerate(offsets):
            upper = float(offsets[i + 1]) if i + 1 < len(offsets) else float(offset)
            if _ends_at(self, float(offset), upper):
                return True
        return False


def _ends_at(mode: _Mode, offset: float, upper: float) -> bool:
    """`_Mode.ends_with_hand` for the offsets in [`offset`, `upper`] (the sample `offset` stands for them). The mode
    is a slide along a level axis or a turn about a vertical one (`level_movers`): its poses are computed in the
    plane."""
    problem, body, goal, mover, tool_chain = mode.problem, mode.body, mode.goal, mode.mover, mode.tool_chain
    assert goal.position is not None
    low, high = value_bounds(mover.motion)
    axis, center = unit_axis_and_center(mover.motion)
    contact_moves = upper - offset
    heights = [(body.rest @ action_at(problem, body.name, mover.name, s))[2, 3] for s in (offset, upper)]
    if abs(float(heights[1] - heights[0])) > 1e-9:
        return True  # the hand's height changes along the band: not decided here
    chain = action_at(problem, body.name, mover.name, offset)
    hand = body.rest @ (chain if tool_chain is None else chain @ tool_chain)
    origin, point = body.rest[:2, 3], hand[:2, 3]
    fractions = np.linspace(0.0, 1.0, TASK_SAMPLES)
    if center is None:  # a slide: every point moves by its value along the axis, the heading kept
        direction = (body.rest[:3, :3] @ axis)[:2]
        count = max(2, math.ceil((high - low) / (2 * STEP)) + 1)
        values = np.linspace(low, high, count)
        half = (high - low) / (count - 1) / 2
        ends = origin + np.outer(values, direction)
        headings = np.full(count, yaw_of(body.rest))
        pivot_moves, lever_origin, lever_hand = 0.0, 1.0, 1.0
    else:
        pivot = _world_pivot(problem, body, mover, center, offset)
        pivot_moves = float(np.linalg.norm(pivot - _world_pivot(problem, body, mover, center, upper)))
        lever_origin = float(np.linalg.norm(origin - pivot)) + pivot_moves
        lever_hand = float(np.linalg.norm(point - pivot)) + pivot_moves + contact_moves
        count = min(MAX_ANGLES, max(2, math.ceil((high - low) * max(lever_origin, lever_hand) / (2 * STEP)) + 1))
        values = np.linspace(low, high, count)
        half = (high - low) / (count - 1) / 2
        sign = float(np.sign((body.rest[:3, :3] @ axis)[2]))
        ends = _turned(origin, pivot, sign * values)
        headings = yaw_of(body.rest) + sign * values
    miss = np.hypot(ends[:, 0] - goal.position[0], ends[:, 1] - goal.position[1])
    if len(goal.position) > 2:
        miss = np.hypot(miss, body.rest[2, 3] - goal.position[2])  # level: its height stays its rest's
    near = miss <= goal.tol_position + SLACK + lever_origin * half + 2.0 * pivot_moves
    if goal.yaw is not None and math.hypot(body.rest[0, 0], body.rest[1, 0]) >= 0.1:
        near &= np.abs(_wrapped(headings - goal.yaw)) <= goal.tol_yaw + SLACK + (half if center is not None else 0.0)
    if not near.any():
        return False
    samples = np.outer(values[near], fractions).ravel()  # per value reaching the goal, its mode's hand samples
    if center is None:
        hands = point + np.outer(samples, direction)
    else:
        hands = _turned(point, pivot, sign * samples)
    excess = _reach_excess(problem, hands, float(hand[2, 3]), _lean(problem, hand))
    room = SLACK + lever_hand * half + 2.0 * pivot_moves + contact_moves
    return bool(np.any(np.all(excess.reshape(-1, TASK_SAMPLES) <= room, axis=1)))


def _turned(point: np.ndarray, pivot: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """`point` (x, y) turned about `pivot` by each of `angles` (rad, counter-clockwise): n x 2."""
    arm = point - pivot
    cos, sin = np.cos(angles), np.sin(angles)
    return np.stack([pivot[0] + cos * arm[0] - sin * arm[1], pivot[1] + sin * arm[0] + cos * arm[1]], axis=1)


def _lean(problem: Problem, hand: np.ndarray) -> float:
    """How much nearer or farther a tilted hand is counted than its own point (`hand_down_point`: at most the wrist
    lever times its z axis's horizontal part, which a turn about the vertical keeps); 0 upright."""
    return problem.arm.wrist_lever * math.hypot(hand[0, 2], hand[1, 2]) if hand[2, 2] < 1.0 - UPRIGHT else 0.0


def _wrapped(angles: np.ndarray) -> np.ndarray:
    """`wrap_angle` of many angles at once."""
    return (angles + math.pi) % (2 * math.pi) - math.pi


def _reach_excess(problem: Problem, points: np.ndarray, height: float, lean: float) -> np.ndarray:
    """How far (m) each hand point (n x 2, at `height`) lies outside the usable reach at least, less `lean`."""
    r_min, r_max = problem.arm.reach(height)
    if r_max <= 0:
        return np.full(len(points), math.inf)
    radius = np.hypot(points[:, 0] - problem.arm.base[0, 3], points[:, 1] - problem.arm.base[1, 3])
    return np.maximum(r_min + REACH_MARGIN - radius, radius - (r_max - REACH_MARGIN)) - lean


__all__ = ["missing_ends", "missing_movers"]
