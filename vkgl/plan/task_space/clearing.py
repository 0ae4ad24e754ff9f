"""Clutter cleared on purpose: how far to move a body in the way so that it leaves the path of the bodies after it.

When a sequence's motions sweep a body through another (a cube pushed through a Block lying across its path),
the search asks task space for other motion values (`feasible.task_space_alternatives`). A body that no goal
names and that the sequence moves before the blocked motion (a "blocker") is moved by the smallest value of its
own motion that takes its footprint out of the corridor every later motion sweeps, with a margin:

- a corridor is the convex hull of a moving body's footprint (and of the tool that moves it) at evenly spaced
  fractions of its motion in one mode, on the table's plane;
- the blocker's footprint along its own motion is tested against every later corridor (convex polygons:
  separating axes, then the distance between their edges), from 0 up its range; the first clear value found on
  a grid is refined by bisection against the last blocked one, so that the answer is the boundary within
  `RESOLUTION`, never a value inside the corridor.

For a slide the set of values that leave the blocker inside a convex corridor is one interval (the footprint and
the corridor are convex, and the footprint moves along a line), so the smallest clear value past it is the
boundary the bisection finds. For a turn the same search is done along the angle (the grid is fine enough for
the footprints the stdlib's bodies have; the sweep check in the search has the last word either way). Several
blockers are cleared in turn, each against the corridors of the motions after its own.

Before any sequence exists, `way_sides` gives the sub-goals of "clear first, then solve"
(`vkgl.plan.search.clutter.clear_first`): the half-planes beyond each side of the corridor a goal body sweeps going
straight to its goal (its left, its right, and beyond its goal), each as far out as `MARGIN` plus
`SIDE_TOLERANCE`, and how far the blocker must move to lie in it. Left and right lie farther out by the most a
tool reaches past the goal body's footprint on that side while it enacts a slide of the goal body towards its
goal (from the tool's geometry, where the body rests: a hook's bar reaches 7 cm past a Cube): the tool sweeps
that strip too, and a blocker moved only clear of the body's own corridor would lie in the tool's way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from vkgl.lang.ir.families import tool_only
from vkgl.lang.ir.regions import convex_hull
from vkgl.lang.ir.regions import footprint as region_footprint
from vkgl.plan.graphs.graph import Engagement, tool_enacts
from vkgl.plan.graphs.motions import motion_matrices, rest_axis
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, rollout, tool_pose_on, value_bounds
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.rotations import yaw_matrix
from vkgl.se3 import wrap_angle, yaw_of

MARGIN = 0.01
"""m: a cleared blocker stays this far from every later corridor (the sweep check allows 1 mm of touching)."""

RESOLUTION = 0.002
"""m or rad: the bisection stops when the clear value is known this closely."""

GRID = 48
"""Values tried along a blocker's range before the bisection (the first clear one bounds the search)."""

CORRIDOR_SAMPLES = 9
"""Fractions of a mode's motion at which a moving body's footprint is taken for its corridor."""


@dataclass(frozen=True)
class Blocker:
    """A motion variable of the sequence that moves a body no goal names: variable `index`, in mode `mode`."""

    index: int
    mode: int
    engagement: Engagement


def footprint(problem: Problem, body: str, pose: np.ndarray) -> np.ndarray:
    """The convex footprint (k x 2, counter-clockwise) of `body` at world `pose`, on the table's plane."""
    return convex_hull(region_footprint(problem.footprint_points(body), pose))


def polygon_distance(a: np.ndarray, b: np.ndarray) -> float:
    """The distance between two convex polygons (0 when they overlap or touch)."""
    if _overlap(a, b):
        return 0.0
    return min(_to_edges(a, b), _to_edges(b, a))


def _to_edges(points: np.ndarray, polygon: np.ndarray) -> float:
    """The least distance from any of `points` to any edge of `polygon`: each point's nearest point on each edge
    (clamped to its ends), all at once (the clearing's bisections ask thousands of times)."""
    start = polygon
    edge = np.roll(polygon, -1, axis=0) - polygon
    length = edge[:, 0] * edge[:, 0] + edge[:, 1] * edge[:, 1]
    rel = points[:, np.newaxis, :] - start[np.newaxis, :, :]
    along = rel[..., 0] * edge[:, 0] + rel[..., 1] * edge[:, 1]
    t = np.where(length == 0.0, 0.0, np.clip(along / np.where(length == 0.0, 1.0, length), 0.0, 1.0))
    off = rel - t[..., np.newaxis] * edge[np.newaxis, :, :]
    return float(np.sqrt(off[..., 0] * off[..., 0] + off[..., 1] * off[..., 1]).min())


def _overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Separating-axis test of two convex polygons: no edge normal of either separates their projections."""
    for polygon in (a, b):
        edge = np.roll(polygon, -1, axis=0) - polygon
        normals = np.stack([edge[:, 1], -edge[:, 0]], axis=1)
        normals = normals[normals.any(axis=1)]
        pa, pb = a @ normals.T, b @ normals.T
        if np.any((pa.max(axis=0) < pb.min(axis=0)) | (pb.max(axis=0) < pa.min(axis=0))):
            return False
    return True


def corridors(problem: Problem, seq: Sequence, traces: list[ModeTrace], after: int, skip: str) -> list[np.ndarray]:
    """The corridors of every body (and moving tool) that a motion of a mode after `after` sweeps, `skip` aside."""
    out = []
    fractions = np.linspace(0.0, 1.0, CORRIDOR_SAMPLES)
    for mode, trace in enumerate(traces):
        if mode <= after:
            continue
        for e, value in trace.values.items():
            if e.body == skip or value == 0.0:
                continue
            paths = motion_matrices(problem.affordance(e.body, e.affordance).motion, fractions * value)
            poses = [trace.start[e.body] @ m for m in paths]
            points = [footprint(problem, e.body, pose) for pose in poses]
            tool = problem.effector(e.effector).tool
            if tool is not None and tool != skip:
                points += [footprint(problem, tool, tool_pose_on(problem, e, pose)) for pose in poses]
            out.append(convex_hull(np.vstack(points)))
    return out


def clearing_value(
    problem: Problem, blocker: Blocker, start: np.ndarray, ways: list[np.ndarray], low: float, high: float
) -> float | None:
    """The smallest value in [low, high] of the blocker's motion (its body at world `start` before it) that keeps
    its footprint `MARGIN` away from every corridor of `ways`; `low` when it is clear already; None when no value
    of its range clears them."""
    e = blocker.engagement
    motion = problem.affordance(e.body, e.affordance).motion

    boxes = [_box(way) for way in ways]

    def clear(value: float) -> bool:
        pose = start @ motion_matrices(motion, np.array([value]))[0]
        shape = footprint(problem, e.body, pose)
        box = _box(shape)
        return all(
            _box_gap(box, way_box) >= MARGIN + BOX_SLACK or polygon_distance(shape, way) >= MARGIN
            for way, way_box in zip(ways, boxes, strict=True)
        )

    if clear(low):
        return low
    grid = np.linspace(low, high, GRID + 1)[1:]
    blocked = low
    for value in grid.tolist():
        if clear(value):
            return _bisect(clear, blocked, value)
        blocked = value
    return None


BOX_SLACK = 1e-9
"""m: a footprint's bounding box this much more than `MARGIN` from a corridor's decides without
`polygon_distance` (whose rounding is far below it)."""


def _box(polygon: np.ndarray) -> np.ndarray:
    """The polygon's axis-aligned bounding box: (min x, min y, max x, max y)."""
    return np.concatenate([polygon.min(axis=0), polygon.max(axis=0)])


def _box_gap(a: np.ndarray, b: np.ndarray) -> float:
    """How far apart two bounding boxes are along x or y, whichever is more (<= 0 when they overlap): a lower
    bound of the distance between the polygons inside them, since every point of one lies that far from every
    point of the other along that axis."""
    return float(max(a[0] - b[2], b[0] - a[2], a[1] - b[3], b[1] - a[3]))


def _bisect(clear: object, blocked: float, free: float) -> float:
    """The boundary between a blocked and a clear value, within `RESOLUTION`, on the clear side."""
    assert callable(clear)
    while free - blocked > RESOLUTION:
        middle = 0.5 * (blocked + free)
        if clear(middle):
            free = middle
        else:
            blocked = middle
    return free


def blockers(problem: Problem, seq: Sequence) -> list[Blocker]:
    """The sequence's motion variables that move a body no goal names."""
    goal_bodies = {goal.body for goal in problem.goals}
    return [Blocker(i, mode, e) for i, (mode, e) in enumerate(seq.variables) if e.body not in goal_bodies]


def cleared_values(
    problem: Problem, seq: Sequence, values: np.ndarray, traces: list[ModeTrace], lower: np.ndarray, upper: np.ndarray
) -> np.ndarray | None:
    """`values` with every blocker's value replaced by the smallest that clears the later motions' corridors
    (`traces`: the rollout of `values`); None when some blocker cannot clear them or there is none.

    A blocker whose whole range does not clear them goes to the end of its range when the sequence moves the
    same body again later (a Block turned twice, 25 deg at most each: the first turn all the way, the second as
    far as the rest needs); otherwise nothing clears it."""
    found = blockers(problem, seq)
    if not found:
        return None
    out = np.array(values, dtype=float)
    for k, blocker in enumerate(found):
        if k > 0:  # a blocker moved before changes where the next one starts when it is the same body
            traces = rollout(problem, seq, out)
        body = blocker.engagement.body
        ways = corridors(problem, seq, traces, blocker.mode, body)
        if not ways:
            continue
        start = traces[blocker.mode].start[body]
        low, high = float(lower[blocker.index]), float(upper[blocker.index])
        value = clearing_value(problem, blocker, start, ways, low, high)
        if value is None:
            if not any(later.engagement.body == body for later in found[k + 1 :]):
                return None
            value = high  # as far as this motion goes: a later motion of the same body takes it the rest of the way
        out[blocker.index] = value
    return out


SIDE_TOLERANCE = 0.005
"""m: the tolerance of a side's region goal (a footprint may pass the half-plane's edge by this much and hold):
the half-plane lies `MARGIN + SIDE_TOLERANCE` out, so a blocker that holds it stays `MARGIN` clear."""


@dataclass(frozen=True)
class Side:
    """A half-plane beyond one side of a goal body's straight way to its goal: `halfplane` (nx, ny, d: inside
    when `n . p <= d`), `words` naming the side, `distance` the blocker must move across the edge to lie in it
    (m), the shortest slide of the blocker's own affordances that takes it there (`slide`, m), whether a turn
    does (`turn`), the affordances one motion of which does (`movers`, their names), and whether the arm
    reaches through it to the goal body (`arm_side`: beyond the goal of a body pulled towards the arm's base,
    where the hand and the tool pass)."""

    words: str
    halfplane: np.ndarray
    distance: float
    slide: float = math.inf
    turn: bool = False
    movers: tuple[str, ...] = ()
    arm_side: bool = False

    @property
    def rank(self) -> tuple[bool, int, float]:
        """The order sides are tried in: those one slide reaches, the shortest slide first; then those one
        turn reaches; then the rest; each nearest first; the arm's side after all others (a blocker moved there
        lies where the hand passes to pull the goal body)."""
        if math.isfinite(self.slide):
            return self.arm_side, 0, self.slide
        return self.arm_side, (1 if self.turn else 2), self.distance


def way_corridor(problem: Problem, goal: GoalSpec) -> np.ndarray:
    """The convex footprint (k x 2) of the goal body swept straight from where it rests to its goal position
    (turned to the goal's heading, when it has one): the hull of its footprints at both ends."""
    body = problem.bodies[goal.body]
    assert goal.position is not None
    end = body.rest.copy()
    if goal.yaw is not None:
        end[:3, :3] = np.asarray(yaw_matrix(wrap_angle(goal.yaw - yaw_of(body.rest))), dtype=float) @ end[:3, :3]
    end[:2, 3] = np.asarray(goal.position[:2], dtype=float)
    return convex_hull(np.vstack([footprint(problem, goal.body, body.rest), footprint(problem, goal.body, end)]))


def way_sides(
    problem: Problem, goal: GoalSpec, blocker: str, *, motions: bool = True, tools: frozenset[str] | None = None
) -> list[Side]:
    """The sides of `goal`'s straight way (`way_corridor`) that `blocker` could be moved to: left, right and
    beyond the goal (not behind the goal body, which stands there), those one motion of the blocker's own
    reaches first, then the nearest; left and right lie farther out by how far a tool that can slide the goal
    body towards its goal reaches past it there (`_overhang`); a side it already lies in comes back alone with
    distance 0. Without `motions`, the blocker's motions are not tried (the sides' distances only, nearest first).
    With `tools` (the tools that can carry the goal body along its way, `clear_first`), each side is widened only
    by the least that one of those tools reaches past the body there: the goal body is then moved by that tool,
    whose sweep the side leaves free (a stick pushing a cube reaches past it on one side, a hook's bar on the
    other); without, by the most any tool reaches."""
    assert goal.position is not None
    corridor = way_corridor(problem, goal)
    start = problem.bodies[goal.body].rest[:2, 3]
    along = np.asarray(goal.position[:2], dtype=float) - start
    length = float(np.linalg.norm(along))
    if length < 1e-9:
        return []
    u = along / length
    normal = np.array([-u[1], u[0]])
    shape = footprint(problem, blocker, problem.bodies[blocker].rest)
    base = problem.arm.base[:2, 3]
    pulled = np.linalg.norm(np.asarray(goal.position[:2], dtype=float) - base) < np.linalg.norm(start - base)
    sides = []
    reach = movers_reach(problem, goal.body, u)
    for words, out, across in (("left", normal, True), ("right", -normal, True), ("beyond the goal", u, False)):
        # beside the way, a tool moving the goal body sweeps past its footprint (a hook's bar); beyond the goal
        # lies its shaft's projection, rising to the hand (the arm's side of a pull, tried last): not widened
        overhang = _overhang(reach, out, tools) if across else 0.0
        edge = float(np.max(corridor @ out)) + overhang + MARGIN + SIDE_TOLERANCE
        halfplane = np.array([-out[0], -out[1], -edge])  # inside: out . p >= edge
        distance = max(0.0, edge - float(np.min(shape @ out)))
        if distance == 0.0:
            return [Side(words, halfplane, 0.0, 0.0)]
        side = Side(words, halfplane, distance, arm_side=bool(pulled) and words == "beyond the goal")
        sides.append(_one_motion_reaches(problem, blocker, side) if motions else side)
    return sorted(sides, key=lambda side: side.rank)


TOWARDS = math.cos(math.radians(45.0))
"""The least cosine between a slide's axis (in the world, where its body rests) and the goal body's straight way
for its tool to count in `_overhang`: the slides that can carry the body towards its goal."""


def movers_reach(problem: Problem, body: str, u: np.ndarray) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """For each tool frame that can enact a slide of `body` towards its goal (along `u` within `TOWARDS`), its
    tool and the footprints (k x 2) of `body` at rest and of the tool enacting that slide there: the tools that
    may sweep the goal body's way."""
    plan_body = problem.bodies[body]
    rest = plan_body.rest
    out = []
    for affordance in plan_body.affordances:
        if affordance.motion.type != "prismatic":
            continue
        axis = rest_axis(rest, affordance.motion)
        if float(np.linalg.norm(axis)) < 1e-9 or float(axis @ u) / float(np.linalg.norm(axis)) < TOWARDS:
            continue
        for effector in problem.effectors:
            if effector.tool is None or effector.tool == body or not tool_enacts(affordance):
                continue
            if tool_only(affordance.name) and (affordance.name, effector.name) not in plan_body.tool_members:
                continue
            tool_pose = tool_pose_on(problem, Engagement(effector.name, body, affordance.name), rest)
            out.append((effector.tool, footprint(problem, body, rest), footprint(problem, effector.tool, tool_pose)))
    return out


def _overhang(
    reach: list[tuple[str, np.ndarray, np.ndarray]], out: np.ndarray, tools: frozenset[str] | None = None
) -> float:
    """How far past the goal body's footprint, in direction `out`, a tool that moves it reaches (m, the largest
    over `movers_reach`; 0 with none): the tool sweeps that much beside the goal body's corridor, so a blocker
    cleared to that side must lie that much farther out. With `tools`, the least over those tools of each one's
    largest (0 when none of them moves the body towards its goal): the side is left free for one of them."""
    per_tool: dict[str, float] = {}
    for tool, body, shape in reach:
        past = max(0.0, float(np.max(shape @ out) - np.max(body @ out)))
        per_tool[tool] = max(per_tool.get(tool, 0.0), past)
    if tools is None:
        return max(per_tool.values(), default=0.0)
    return min((past for tool, past in per_tool.items() if tool in tools), default=0.0)


def _one_motion_reaches(problem: Problem, blocker: str, side: Side) -> Side:
    """`side` with the shortest slide of `blocker`'s own affordances that puts its footprint inside its
    half-plane (m, `inf`: none), whether a turn does, and the affordances that do (each motion tried at `GRID`
    values over its range)."""
    body = problem.bodies[blocker]
    slide, turn, movers = math.inf, False, []
    halfplane = side.halfplane
    for affordance in body.affordances:
        motion = affordance.motion
        if motion.type not in ("prismatic", "revolute"):
            continue
        low, high = value_bounds(motion)
        values = np.linspace(low, high, GRID + 1)
        for value, pose in zip(values, body.rest @ motion_matrices(motion, values), strict=True):
            shape = footprint(problem, blocker, pose)
            if float(np.max(shape @ halfplane[:2] - halfplane[2])) <= 0.0:
                if motion.type == "prismatic":
                    slide = min(slide, float(value))
                else:
                    turn = True
                movers.append(affordance.name)
                break
    return replace(side, slide=slide, turn=turn, movers=tuple(movers))


__all__ = [
    "CORRIDOR_SAMPLES",
    "GRID",
    "MARGIN",
    "RESOLUTION",
    "SIDE_TOLERANCE",
    "Blocker",
    "Side",
    "blockers",
    "cleared_values",
    "clearing_value",
    "corridors",
    "footprint",
    "movers_reach",
    "polygon_distance",
    "way_corridor",
    "way_sides",
]
