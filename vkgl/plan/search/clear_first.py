"""Clear first, then solve: a plan for a goal body with another body in its way, deeper than the search affords.

A goal body with a body lying across its straight way (`vkgl.plan.search.ordering.InTheWay`) needs a plan that
moves that body aside first, then the goal body, often with a tool: on the physical bench that is 7 graphs or
more, one past the default `max_depth`, and the search cannot afford the level of 7 graphs in a cluttered scene
(thousands of sequences, each checked by the optimiser). A person splits the task in two, and so does
`clear_first`, once the search has ended without a plan:

1. **Clear.** For the blocker nearest the goal body's start, a sub-problem whose only goal is a region goal: the
   blocker's footprint beyond one side of the goal body's straight corridor with a margin
   (`vkgl.plan.task_space.clearing.way_sides`: left, right, or beyond the goal; the sides one motion of the
   blocker's own affordances reaches first, then the nearest). It is searched like any problem, to at most
   `CLEAR_DEPTH` graphs (G0, a tool's grasp, the push that clears it, one more), and its plan passes every
   check a plan passes. Several blockers are cleared in turn, each sub-problem starting where the one before
   ended.
2. **Then solve.** The original problem is searched again from that plan (`search(..., root=prefix)`): every
   sequence extends it, with up to `max_depth - 1` graphs more, so the tool the prefix holds is still in hand
   and its contact still in force. The plan found is one graph sequence like any other: its motion values are
   chosen again for the whole sequence (the blocker moved as far as the goal body's real corridor needs,
   `clearing.cleared_values`), and it passes every check; the plan format does not change.

Sides and blockers are tried in turn (a depth-first walk) until a plan is found or the deadline passes.

**Shortest or not.** The search before proved that no plan of at most `proven` graphs exists (every sequence
of `max_depth` graphs when it ended without a plan, those of fewer than its level when the time ran out). A plan
of `proven + 1` graphs found here is therefore a shortest one; a deeper one may not be (a plan that clears no
blocker, or clears it otherwise, might be shorter) and its words say "not proven shortest".

Where the bound says that no sequence of any length reaches the goal, nothing here is tried: the answer stays
immediate.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from dataclasses import dataclass, fields, replace

import numpy as np

from vkgl.plan.graphs.rollout import Sequence, start_sequence
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.search.bound import Bound
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.search.search import SearchResult, search
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.clearing import SIDE_TOLERANCE, Side, way_sides

CLEAR_DEPTH = 5
"""Graphs of a plan that clears one blocker, G0 included: the push (2), or a tool's grasp first (3)."""

MAX_DEPTH = 12
"""The deepest plan tried (the CLI's `--max-depth` limit)."""


@dataclass(frozen=True)
class Cleared:
    """What `clear_first` found: the combined plan's search result and how it was found, in words."""

    result: SearchResult
    words: str


def clear_first(
    problem: Problem, before: SearchResult, *, deadline: float, progress: bool = False
) -> Cleared | None:
    """A plan that clears the bodies in a goal body's way first, then reaches the goals (see the module's
    docstring), searched until `deadline`; None when none is found (or nothing lies in the way, or no sequence
    of any length reaches the goal). `before` is the search that ended without a plan; its counters are added
    to the plan's."""
    start = start_sequence(problem)
    blocking = _blocking(problem)
    if not blocking or math.isinf(Bound(problem)(start)):
        return None
    proven = _proven(problem, before)
    stats = before.stats
    for prefix, cleared in _prefixes(problem, blocking, start, deadline, progress, stats):
        deeper = replace(problem, max_depth=min(MAX_DEPTH, prefix.depth - 1 + problem.max_depth))
        result = search(deeper, deadline=deadline, progress=progress, root=prefix)
        add_stats(stats, result.stats)
        if result.status == "solved":
            assert result.sequence is not None
            return Cleared(replace(result, stats=stats), _words(cleared, prefix, result.sequence.depth, proven))
        if time.perf_counter() > deadline:
            break
    return None


def _blocking(problem: Problem) -> list[tuple[GoalSpec, str]]:
    """Each body in a goal body's way once, with that goal, nearest the goal body first."""
    seen: set[str] = set()
    out = []
    for goal, name in InTheWay(problem).blocking:
        if name not in seen:
            seen.add(name)
            out.append((goal, name))
    rest = {name: b.rest[:2, 3] for name, b in problem.bodies.items()}
    return sorted(out, key=lambda pair: float(np.linalg.norm(rest[pair[1]] - rest[pair[0].body])))


def _proven(problem: Problem, before: SearchResult) -> int:
    """The most graphs a plan could have that the search `before` proved there is none of."""
    if before.status == "infeasible":
        return problem.max_depth
    return max(1, math.ceil(before.stats.level) - 1)  # every sequence of fewer graphs than its level was checked


def _prefixes(
    problem: Problem,
    blocking: list[tuple[GoalSpec, str]],
    root: Sequence,
    deadline: float,
    progress: bool,
    stats: SearchStats,
) -> Iterator[tuple[Sequence, list[tuple[str, Side]]]]:
    """Plans that clear every blocker in turn starting from `root` (depth first over each blocker's sides), each
    with the blockers and the sides they were cleared to."""
    if not blocking:
        yield root, []
        return
    (goal, blocker), rest = blocking[0], blocking[1:]
    sides = way_sides(problem, goal, blocker)
    if len(sides) == 1 and sides[0].distance == 0.0:  # clear of the straight way already
        yield from _prefixes(problem, rest, root, deadline, progress, stats)
        return
    for side in sides:
        if time.perf_counter() > deadline:
            return
        sub = replace(
            _only_moving(problem, blocker, side),
            goals=[side_goal(problem, goal, blocker, side)],
            max_depth=root.depth - 1 + CLEAR_DEPTH,
        )
        found = search(sub, deadline=deadline, progress=progress, root=root)
        add_stats(stats, found.stats)
        if found.status != "solved" or found.sequence is None:
            continue
        for prefix, cleared in _prefixes(problem, rest, found.sequence, deadline, progress, stats):
            yield prefix, [(blocker, side), *cleared]


def _only_moving(problem: Problem, blocker: str, side: Side) -> Problem:
    """`problem` in which only the goal bodies and the tools keep their affordances, and `blocker` those one
    motion of which takes it to `side` (all of them when none does): the plan that clears a blocker moves it,
    with the hand or a tool, after moving a goal body out of the tool's way at most; the other bodies stay
    where they lie (they still count in every collision check)."""
    keep = {g.body for g in problem.goals} | {e.tool for e in problem.effectors if e.tool is not None}
    bodies = {name: b if name in keep else replace(b, affordances=()) for name, b in problem.bodies.items()}
    own = problem.bodies[blocker]
    movers = tuple(a for a in own.affordances if a.name in side.movers) or own.affordances
    bodies[blocker] = replace(own, affordances=movers)
    return replace(problem, bodies=bodies)


def side_goal(problem: Problem, goal: GoalSpec, blocker: str, side: Side) -> GoalSpec:
    """The region goal that puts `blocker`'s footprint beyond `side` of `goal`'s straight way, any heading."""
    return GoalSpec(
        blocker,
        None,
        None,
        SIDE_TOLERANCE,
        math.pi,
        region=side.halfplane[np.newaxis, :],
        footprint=problem.footprint_points(blocker),
        region_words=f"{side.words} of {goal.body}'s way",
    )


def _words(cleared: list[tuple[str, Side]], prefix: Sequence, depth: int, proven: int) -> str:
    """How the plan was found, and whether it is proven shortest."""
    moves = ", then ".join(f"{name} {side.words} of the way" for name, side in cleared)
    shortest = (
        f"a shortest plan (no plan of at most {proven} graphs exists)"
        if depth <= proven + 1
        else f"not proven shortest (no plan of at most {proven} graphs exists; this one has {depth})"
    )
    return (
        f"cleared first: {moves} (a plan of {prefix.depth} graphs), then the goal from there, {depth} graphs "
        f"in all: {shortest}"
    )


def add_stats(total: SearchStats, part: SearchStats) -> None:
    """Add the counters of another search (`part`) to `total`: sequences, checks, rejections, times (what
    describes where one search ended, its level and cut sequences, stays `total`'s)."""
    kept = {"level", "depth_reached", "shortest_cut", "cut_at_start", "examples"}
    for f in fields(SearchStats):
        if f.name in kept:
            continue
        mine, theirs = getattr(total, f.name), getattr(part, f.name)
        if isinstance(mine, (int, float)):
            setattr(total, f.name, mine + theirs)
    for f in fields(total.work):
        setattr(total.work, f.name, getattr(total.work, f.name) + getattr(part.work, f.name))
    total.rejections.update(part.rejections)


__all__ = ["CLEAR_DEPTH", "Cleared", "add_stats", "clear_first", "side_goal"]
