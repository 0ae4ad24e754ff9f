"""The bodies in the goal bodies' way that `vkgl.plan.search.clutter.clear_first` clears (`blocking_bodies`), whether it
could try anything (`blocked`), and how deep the search before it proved that no plan lies (`proven_depth`)."""

from __future__ import annotations

import math

import numpy as np

from vkgl.plan.graphs.rollout import start_sequence
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.clutter.tool_sweep import swept_bodies
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.search.search import SearchResult
from vkgl.plan.task_space.clearing import way_sides


def blocked(problem: Problem) -> bool:
    """Whether `clear_first` could try anything: a body lies across a goal body's straight way (not clear of its
    corridor), or, with none in any goal body's way, in the path of the tool that alone can carry a goal body
    (`tool_sweep.swept_bodies`); and some sequence could reach the goal (the bound at G0 is finite)."""
    bound = Bound(problem)
    way = blocking_bodies(problem)
    for goal, blocker in way:
        if min((side.distance for side in way_sides(problem, goal, blocker, motions=False)), default=0.0) > 0.0:
            return not math.isinf(bound(start_sequence(problem)))
    return not way and bool(swept_bodies(problem, bound)) and not math.isinf(bound(start_sequence(problem)))


def blocking_bodies(problem: Problem) -> list[tuple[GoalSpec, str]]:
    """Each body in a goal body's way once, with that goal, nearest the goal body first."""
    seen: set[str] = set()
    out = []
    for goal, name in InTheWay(problem).blocking:
        if name not in seen:
            seen.add(name)
            out.append((goal, name))
    rest = {name: b.rest[:2, 3] for name, b in problem.bodies.items()}
    return sorted(out, key=lambda pair: float(np.linalg.norm(rest[pair[1]] - rest[pair[0].body])))


def proven_depth(problem: Problem, before: SearchResult) -> int:
    """The most graphs a plan could have that the search `before` proved there is none of."""
    if before.status == "infeasible":
        return problem.max_depth
    return max(1, math.ceil(before.stats.level) - 1)  # every sequence of fewer graphs than its level was checked


__all__ = ["blocked", "blocking_bodies", "proven_depth"]
