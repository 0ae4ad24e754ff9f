"""Bodies in a tool's or the hand's path, cleared first like the bodies in a goal body's way.

`clear_first` clears the bodies lying across a goal body's straight corridor (`InTheWay`). A free body beside
that corridor can still stop every plan: the stick that pushes a Block from behind stands through a crate lying
behind it (the physical bench's gen1_041: 29 cm behind the Block, across the 40 cm stick), the hand that pulls a
slab in with the hook passes 7 mm into a crate near the arm's base (gen1_003). Such a body is in no goal
body's way, so nothing moved it on purpose: the search only met it, and its rejections named it
(`Rejection.bodies`, recorded in `SearchStats.named`).

A person moves it out of the tool's or the hand's path a little, along the way it slides, and goes on.
`path_blockers` names the free bodies (no goal body, no tool, no physical joint, a slide among their
affordances, in no goal body's corridor) that some rejection named alone or together with tools only: the
hand, the arm or a tool met them, not a goal body's sweep (those are the corridor's, `InTheWay`), each with the
least depth a rejection met it at. `path_sides` gives each one's sides for the clear-first walk: one per
direction of its own slides, a half-plane that its footprint enters when it has slid that depth plus
`PATH_STEP` along that direction (the smallest displacement that leaves the hand or the tool clear of it), the
direction leading away from where the arm works first (the lines from its base to the goal body's start and
goal: the hand and a held tool reach out along them).

The walk (`clear_first`) clears these bodies after the corridor's blockers, each by a sub-problem like a
corridor blocker's; those the search's closest miss named (`met_last`: the sequence that got farthest failed
on them) it first clears alone, searching the goals from there before it tries the corridor's blockers. The
search for the goals after a clearing plan has the whole plan's checks, and when the pinned slide is too short
it is searched again with the prefix's values free (`clearing.cleared_values` then slides the body out of the
later corridors, the tool's included, as far as they need).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from vkgl.plan.graphs.motions import rest_axis
from vkgl.plan.graphs.rollout import value_bounds
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.search.clutter.tool_sweep import exit_slide
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.search.stats import SearchStats, closest_bodies, closest_miss
from vkgl.plan.task_space.clearing import SIDE_TOLERANCE, Side, footprint

PATH_STEP = 0.025
"""m: how far past the depth it was met at (`path_blockers`) a body in a tool's or the hand's path is slid: the
checks that name it find it millimetres deep (the hand's 7 mm into a crate along a pull), and the same plan's
motion values then leave the hand and the tool clear of it by centimetres without carrying it into other
bodies."""

DEPTH_LIMIT = 0.3
"""m: the deepest a rejection's excess is read as how deep a body was met (an arm's failure with no depth says
1 m: `Rejection.excess`); past it the body is slid `PATH_STEP` only."""

SAME_AXIS = 0.99
"""The least cosine between two slides' axes for them to move the body the same way (one side for both)."""


@dataclass(frozen=True)
class PathSide(Side):
    """A side of a body in a tool's or the hand's path: its footprint slid `slide` along one of its own slides
    (`movers`); `words` read whole ("clutter3 slid 3 cm along (+0.00, +1.00), out of a tool's or the hand's
    path")."""


def path_blockers(problem: Problem, stats: SearchStats) -> dict[str, float]:
    """The free bodies that rejections of `stats` named alone or with tools only (see the module's docstring),
    each with the least depth it was met at (0 when no rejection said a depth below `DEPTH_LIMIT`), nearest a
    goal body first (then by name: deterministic)."""
    tools = {e.tool for e in problem.effectors if e.tool is not None}
    goals = {g.body for g in problem.goals}
    way = InTheWay(problem).bodies
    found: dict[str, float] = {}
    for names, excess in sorted(stats.named.items(), key=lambda pair: sorted(pair[0])):
        free = [name for name in names if name not in tools]
        if len(free) != 1 or free[0] in goals | way or free[0] not in problem.bodies:
            continue
        body = problem.bodies[free[0]]
        if body.joint is None and any(a.motion.type == "prismatic" for a in body.affordances):
            depth = excess if 0.0 <= excess < DEPTH_LIMIT else math.inf
            found[free[0]] = min(found.get(free[0], math.inf), depth)
    starts = [problem.bodies[g].rest[:2, 3] for g in sorted(goals)]

    def nearest(name: str) -> tuple[float, str]:
        at = problem.bodies[name].rest[:2, 3]
        return min((float(np.linalg.norm(at - s)) for s in starts), default=0.0), name

    return {name: found[name] if math.isfinite(found[name]) else 0.0 for name in sorted(found, key=nearest)}


def met_last(problem: Problem, paths: dict[str, float], stats: SearchStats) -> dict[str, float]:
    """Those of `paths` that the closest miss of the search of `stats` named (`closest_bodies`), when that
    sequence had moved every body in a goal body's way already (its actions engage each, `closest_miss`'s
    label): it cleared the way and failed on them alone (gen1_003: a plan of 6 graphs, the cube in the slab's
    way pushed aside by the hook, whose hand then passes 7 mm into a crate on the pull). A closest miss that met
    them on the way to its blocker (gen1_001: the stick that would push a crate aside first stands in a cube)
    says nothing of the plan after: none then."""
    if not stats.examples:
        return {}
    label, _ = closest_miss(stats)
    if not all(f" on {name} with " in label for name in InTheWay(problem).bodies):
        return {}
    named = closest_bodies(stats)
    return {name: depth for name, depth in paths.items() if name in named}


def path_sides(
    problem: Problem, goal: GoalSpec, blocker: str, depth: float, sweeps: tuple[np.ndarray, ...] = ()
) -> list[Side]:
    """The sides `blocker`, met `depth` deep, may be slid to out of a tool's or the hand's path: one per direction
    of its own slides (affordances slid the same way share one), `depth + PATH_STEP` along it, away from the
    arm's work first (`_away_from_work`). With `sweeps` (a tool's path known from geometry, `tool_sweep`), each
    direction's slide is at least the one that leaves them all (`exit_slide`; a direction none of its slides
    leaves them by has no side)."""
    body = problem.bodies[blocker]
    shape = footprint(problem, blocker, body.rest)
    away = _away_from_work(problem, goal, body.rest[:2, 3])
    groups: list[tuple[np.ndarray, list[tuple[str, float]]]] = []  # (axis, its affordances and longest slides)
    for affordance in body.affordances:
        if affordance.motion.type != "prismatic":
            continue
        axis = rest_axis(body.rest, affordance.motion)
        norm = float(np.linalg.norm(axis))
        if norm < 1e-9:
            continue
        axis, mover = axis / norm, (affordance.name, value_bounds(affordance.motion)[1])
        for known, movers in groups:
            if float(known @ axis) >= SAME_AXIS:
                movers.append(mover)
                break
        else:
            groups.append((axis, [mover]))
    sides: list[tuple[float, Side]] = []
    for axis, movers in groups:
        leaves = exit_slide(shape, axis, sweeps, max(m for _, m in movers)) if sweeps else 0.0
        step = max(depth + PATH_STEP, leaves) if leaves is not None else math.inf
        names = [name for name, longest in movers if longest >= step]
        if not names:
            continue
        edge = float(np.min(shape @ axis)) + step + SIDE_TOLERANCE
        words = f"slid {step * 100:.1f} cm along ({axis[0]:+.2f}, {axis[1]:+.2f}), out of a tool's or the hand's path"
        side = PathSide(words, np.array([-axis[0], -axis[1], -edge]), step, slide=step, movers=tuple(names))
        sides.append((-float(axis @ away), side))
    return [side for _, side in sorted(sides, key=lambda pair: pair[0])]


def _away_from_work(problem: Problem, goal: GoalSpec, point: np.ndarray) -> np.ndarray:
    """The unit vector from the nearest point of where the arm works for `goal` to `point` (zeros on it): the
    straight lines from the arm's base to the goal body's start and to its goal position (the hand and the tool
    it holds reach out along them to the body, on a push from behind it, on a pull back towards the base)."""
    base = problem.arm.base[:2, 3]
    start = problem.bodies[goal.body].rest[:2, 3]
    end = np.asarray(goal.position[:2], dtype=float) if goal.position is not None else start
    nearest = min(
        (_nearest_on_segment(point, base, tip) for tip in (start, end)), key=lambda p: float(np.linalg.norm(point - p))
    )
    out = point - nearest
    norm = float(np.linalg.norm(out))
    return out / norm if norm > 1e-9 else np.zeros(2)


def _nearest_on_segment(point: np.ndarray, start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """The point of the segment `start`-`end` nearest `point` (2-D)."""
    along = end - start
    length = float(along @ along)
    t = 0.0 if length == 0.0 else float(np.clip((point - start) @ along / length, 0.0, 1.0))
    return start + t * along


__all__ = ["PATH_STEP", "PathSide", "met_last", "path_blockers", "path_sides"]
