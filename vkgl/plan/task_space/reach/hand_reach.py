"""A proof, before any optimisation, that the hand cannot reach a goal body on its way to its goal position.

`closed_form` already rejects a sequence whose hand, holding the goal body at its goal at the end, is out of
reach. This module asks the same of every mode in which the hand (or the tool it holds) acts on a goal body,
earlier in the sequence: the goal pins where the body ends, and the motions still to come can take it only so
far from there, so the hand at that mode lies on a ring about the goal that may lie wholly outside the arm's
reach. A far crate pushed to its goal by the fingertip, then pushed once more from its near face, is the
common case (the physical bench's gen9_025: 183 sequences of that kind, each rejected for the hand's reach
after eight NLopt runs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vkgl.plan.graphs.graph import Engagement, KGraph, motion_type
from vkgl.plan.graphs.members import family_vectors
from vkgl.plan.graphs.mode_shapes import acting_engagement
from vkgl.plan.graphs.motions import unit_axis_and_center
from vkgl.plan.graphs.rollout import Sequence, bounds, hand_chain, value_bounds
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.reach.workspace import REACH_MARGIN, UPRIGHT

ACCEPTED_VIOLATION = 1e-6
"""m: the constraint violation task space still accepts as a solution (`feasible.task_space`): the proof must
show more than that, so that it rejects only what task space would reject too."""

LEVEL = 1e-9
"""How far from vertical (a turn's axis) or horizontal (a slide's) counts as exactly so."""


def hand_out_of_reach_on_the_way(problem: Problem, seq: Sequence) -> Rejection | None:
    """A Rejection when, at some mode that acts on a goal body with a position goal, the hand is out of the
    arm's usable reach at every motion value and contact offset that lets the goal hold; None otherwise.

    Why it is sound. Let the body lie level and move only by turns about vertical axes and horizontal
    slides (else nothing is claimed), never carried and never a tool. Then its height never changes and
    its final horizontal position p_end is the one at mode k, p_k, moved by each of its motions after that
    point of the rollout: a slide by v moves its origin by |v| at most (a unit axis); a turn by angle a
    about a pivot at distance r from the origin (fixed in the body's frame) moves it by the chord
    2 r sin(a / 2), with r at most |c| + |o| |drift| when the contact sits at offset o along a family whose
    turn's pivot drifts (`members.pivot_shift`). So |p_k - p_end| <= D, the sum of those largest moves
    over the values' bounds (`rollout.bounds`, a superset of any pinned prefix's). Task space accepts only
    values whose goal holds, |p_end - g| <= tol, so |p_k - g| <= tol + D. While the engagement acts, the
    hand is the body's pose times the fixed chain `hand_chain` (at the contact's offset): horizontally it
    lies at most rho from p_k (rho: the chain's horizontal length, largest at an end of the offset's band,
    as it is affine in the offset) and at the chain's height above the body (the same at every offset, else
    nothing is claimed). Its distance from the arm's base therefore lies in [d - tol - D - rho,
    d + tol + D + rho], d that of the goal. The rollout samples the hand at the start of mode k (the pose
    after the motions before k: D counts mode k's motions too) and, when the acting engagement is the
    body's only motion in mode k, at the end of that motion (D counts only the modes after k). When the
    whole interval lies more than `ACCEPTED_VIOLATION` outside the usable reach at that height (the reach
    interval less `REACH_MARGIN`, as `workspace.reach_violation` measures), that sample violates the reach
    constraint at every solution the optimiser could accept: task space would reject the sequence too.
    """
    for goal in problem.goals:
        if goal.position is None:
            continue
        found = _for_goal(problem, seq, goal)
        if found is not None:
            return found
    return None


@dataclass(frozen=True)
class HandBound:
    """Where the hand can be at one sample of a mode that acts on a goal body, whatever the values that let the
    goal hold: its horizontal distance from the arm's base lies in [nearest, farthest], at `height`."""

    mode: int
    at_end: bool  # the sample where the acting motion ends (else where the mode starts)
    nearest: float
    farthest: float
    height: float
    later: float  # how far the body's motions after the sample can move it (m)


def hand_bounds(problem: Problem, seq: Sequence, goal: GoalSpec) -> list[HandBound]:
    """A `HandBound` for each mode of `seq` in which the hand acts on `goal.body`, for a goal with a position;
    none when the body may leave its height or level (`hand_out_of_reach_on_the_way` says why they hold)."""
    assert goal.position is not None
    if not any(e.body == goal.body for _, e in seq.variables):
        return []  # nothing moves the body: the closed form's other checks decide
    limits = bounds(problem, seq, offsets=True)
    moves = _largest_moves(problem, seq, goal.body, limits)
    if moves is None:
        return []
    rest = problem.bodies[goal.body].rest
    target = np.array(goal.position[:2], dtype=float) - problem.arm.base[:2, 3]
    heading = math.atan2(rest[1, 0], rest[0, 0])
    out = []
    for k, graph in enumerate(seq.graphs):
        acting = acting_engagement(problem, graph)
        if acting is None or acting.body != goal.body:
            continue
        ring = hand_ring(problem, seq, graph, acting, limits)
        if ring is None:
            continue
        points, slack, height, lean = ring
        own = [move.engagement for move in moves if move.mode == k]
        at_end = own == [acting]  # the rollout samples the hand where the acting motion ends
        later = sum(move.largest for move in moves if move.mode > k or (move.mode == k and not at_end))
        turned = [move.headings for move in moves if move.mode < k or (move.mode == k and at_end)]
        low = heading + sum(t[0] for t in turned)
        high = heading + sum(t[1] for t in turned)  # (a slide adds (0, 0))
        nearest = min(_nearest(target, p, low, high) for p in points) - slack - lean - goal.tol_position - later
        farthest = float(np.linalg.norm(target)) + max(math.hypot(*p) for p in points) + goal.tol_position + later
        farthest += lean
        out.append(HandBound(k, at_end, max(0.0, nearest), farthest, float(rest[2, 3]) + height, later))
    return out


def _for_goal(problem: Problem, seq: Sequence, goal: GoalSpec) -> Rejection | None:
    """`hand_out_of_reach_on_the_way` for one goal with a position."""
    for bound in hand_bounds(problem, seq, goal):
        found = _outside(problem, bound.nearest, bound.farthest, bound.height)
        if found is not None:
            excess, words = found
            label = seq.actions[bound.mode - 1].label(problem) if bound.mode > 0 else "G0"
            later = f" and its later motions move it {bound.later * 100:.1f} cm at most" if bound.later > 0 else ""
            why = (
                f"after {label}: the hand would be {words}, whatever the motion values, as {goal.body} ends within "
                f"{goal.tol_position * 100:.1f} cm of its goal{later}"
            )
            return Rejection(Kind.REACH, why, excess)
    return None


def _nearest(target: np.ndarray, point: np.ndarray, low: float, high: float) -> float:
    """The least |target + R(yaw) point| over headings yaw in [low, high] (2-D, exact): the hand's distance from
    the arm's base with the body's origin at `target` and the hand at `point` in its frame."""
    reach, length = float(np.linalg.norm(target)), math.hypot(point[0], point[1])
    if high - low >= 2 * math.pi or length == 0.0 or reach == 0.0:
        return abs(reach - length)
    # |t + R p|^2 = |t|^2 + |p|^2 + 2 |t| |p| cos(yaw + angle(p) - angle(t)): least where that angle is pi
    phase = math.atan2(point[1], point[0]) - math.atan2(target[1], target[0])
    opposite = math.pi - phase
    opposite = low + (opposite - low) % (2 * math.pi)  # the first such heading from `low` on
    if opposite <= high:
        return abs(reach - length)
    return min(
        math.sqrt(max(0.0, reach**2 + length**2 + 2 * reach * length * math.cos(y + phase))) for y in (low, high)
    )


@dataclass(frozen=True)
class _Move:
    """A motion of the body in a sequence: its mode, the largest distance it can move the body's origin, its
    engagement, and the interval of headings it adds (a slide: none)."""

    mode: int
    largest: float
    engagement: Engagement
    headings: tuple[float, float] = (0.0, 0.0)


def _largest_moves(
    problem: Problem, seq: Sequence, body: str, limits: tuple[np.ndarray, np.ndarray]
) -> list[_Move] | None:
    """Each motion of `body` in `seq`, or None when the body may leave its height or level (a tilt, a vertical
    slide, a carry, a tool)."""
    if abs(problem.bodies[body].rest[2, 2] - 1.0) > LEVEL:
        return None
    if any(e.body == body for _, e in seq.carries) or any(f.tool == body for f in problem.effectors):
        return None
    bands = _offset_bands(seq, limits)
    out: list[_Move] = []
    for mode, e in seq.variables:
        if e.body != body:
            continue
        motion = problem.affordance(e.body, e.affordance).motion
        low, high = value_bounds(motion)
        if not (math.isfinite(low) and math.isfinite(high)):
            return None
        largest = max(abs(low), abs(high))
        axis, center = unit_axis_and_center(motion)
        kind = motion_type(problem, e)
        if kind == "prismatic" and abs(axis[2]) <= LEVEL:
            out.append(_Move(mode, largest, e))
        elif kind == "revolute" and center is not None and float(np.hypot(axis[0], axis[1])) <= LEVEL:
            _, drift = family_vectors(problem.affordance(e.body, e.affordance))
            drifted = 0.0 if drift is None else bands.get(e, 0.0) * float(np.linalg.norm(drift))
            radius = float(np.linalg.norm(center)) + drifted
            sign = 1.0 if axis[2] > 0 else -1.0
            headings = (min(sign * low, sign * high), max(sign * low, sign * high))
            out.append(_Move(mode, 2.0 * radius * math.sin(min(largest, math.pi) / 2), e, headings))
        else:
            return None
    return out


def _offset_bands(seq: Sequence, limits: tuple[np.ndarray, np.ndarray]) -> dict[Engagement, float]:
    """The largest |offset| each engagement's contact may take anywhere in `seq` (`limits`: the optimiser's
    bounds, `rollout.bounds` with offsets)."""
    lower, upper = limits
    n = len(seq.variables)
    out: dict[Engagement, float] = {}
    for j, (_, e) in enumerate(seq.offsets):
        out[e] = max(out.get(e, 0.0), abs(float(lower[n + j])), abs(float(upper[n + j])))
    return out


OFFSET_GRID = 9
"""Contact offsets along a family's band at which the hand's least distance is computed (ends included)."""


def hand_ring(
    problem: Problem, seq: Sequence, graph: KGraph, acting: Engagement, limits: tuple[np.ndarray, np.ndarray]
) -> tuple[list[np.ndarray], float, float, float] | None:
    """(the hand's horizontal position in the body's frame at `OFFSET_GRID` offsets over the acting contact's
    band, how far any offset's lies from the nearest of them, the hand's height above the body's origin, how far
    a tilted hand's reach is counted from its position: `Arm.wrist_lever` times its z axis's horizontal part,
    `workspace.hand_down_point`, 0 upright); None when the hand is not attached or its height changes with the
    offset.

    The chain is affine in the offset (`members.action_at`), so an offset within h / 2 of a grid offset puts
    the hand within |a| h / 2 of that one's (a: the chain's change per metre of offset)."""
    grid = offset_grid(seq, acting, limits)
    lo, hi = float(grid[0]), float(grid[-1])
    chains = [hand_chain(problem, graph, acting, float(o)) for o in grid]
    if any(c is None for c in chains):
        return None
    points = [c[0][:3, 3] for c in chains if c is not None]
    heights = [float(p[2]) for p in points]
    if max(heights) - min(heights) > LEVEL:
        return None
    slack = 0.0
    if hi > lo:
        step = (hi - lo) / (OFFSET_GRID - 1)
        slack = float(np.linalg.norm((points[-1] - points[0])[:2])) / (hi - lo) * step / 2
    up = chains[0][0][:3, 2] if chains[0] is not None else np.array([0.0, 0.0, 1.0])  # (the body lies level)
    lean = problem.arm.wrist_lever * math.hypot(up[0], up[1]) if up[2] < 1.0 - UPRIGHT else 0.0
    return [p[:2] for p in points], slack, heights[0], lean


def offset_grid(seq: Sequence, acting: Engagement, limits: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """The `OFFSET_GRID` offsets over the acting contact's band (its offset variables' limits, 0 included) at which
    `hand_ring` places the hand; one offset, 0, when the contact does not move along its face."""
    lower, upper = limits
    n = len(seq.variables)
    lo = hi = 0.0
    for j, (_, e) in enumerate(seq.offsets):
        if e == acting:
            lo, hi = min(lo, float(lower[n + j])), max(hi, float(upper[n + j]))
    return np.linspace(lo, hi, OFFSET_GRID) if hi > lo else np.zeros(1)


def _outside(problem: Problem, nearest: float, farthest: float, height: float) -> tuple[float, str] | None:
    """(how far, in words) distances from the arm's base between `nearest` and `farthest` lie wholly outside
    the usable reach at `height` by more than task space accepts; None otherwise."""
    if not problem.arm.reach(height)[1] > 0:
        return 1.0, f"at height {height:.3f} m, where the arm reaches nowhere"
    low, high = reach_interval(problem, height)
    beyond, short = nearest - high, low - farthest
    if max(beyond, short) <= ACCEPTED_VIOLATION:
        return None
    where = f"{nearest:.3f} m or more" if beyond > short else f"at most {farthest:.3f} m"
    return max(beyond, short), (
        f"{where} from the arm's base at height {height:.3f} m (usable reach there: {low:.3f} to {high:.3f} m)"
    )


def reach_interval(problem: Problem, height: float) -> tuple[float, float]:
    """The hand's usable distances from the arm's base at `height` (m): the arm's reach there less
    `REACH_MARGIN` at both ends (empty, low above high, where the arm reaches nowhere)."""
    r_min, r_max = problem.arm.reach(height)
    if not r_max > 0:
        return math.inf, -math.inf
    return r_min + REACH_MARGIN, r_max - REACH_MARGIN
