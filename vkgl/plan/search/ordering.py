"""Which sequences of one level the search checks first: those that have already moved the bodies in the way.

The search checks sequences in the order of their depth plus bound (`vkgl.plan.search.bounds.bound`: admissible, so the
first feasible one is a shortest one). Among sequences of the same level any order keeps that; breadth-first
order (the successors' indices) checks first whatever the first-declared body allows, which in a scene with a
body lying across the target's way are the sequences that push the target into it, each one rejected only after
its collision checks and the search for values that move the body aside. A person clears the body first.

`InTheWay(problem)` names the bodies in the way: a body that is no goal body, no tool and has no physical joint
(it can be pushed aside) whose footprint comes within the goal body's own half-width of the straight segment from
a goal body's rest position to its goal position (in the table's plane; the footprints are the bodies' convex
outlines, `PlanBody.outline`, taken as discs about their origin: what matters is order, not exactness).
`InTheWay.left(seq)` is how many of them `seq` has not moved yet (not in `seq.dependent`): the search's queue is
ordered by (depth plus bound, that count, breadth-first order), so within a level the sequences that cleared
every body in the way come first. With no body in the way the count is 0 throughout and the order is the
breadth-first one. The count never grows along a branch (a body that is no tool never leaves `dependent` once
it has moved), which the search's late expansion relies on (`vkgl.plan.search.search._Entry`).
"""

from __future__ import annotations

import numpy as np

from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import GoalSpec, PlanBody, Problem


class InTheWay:
    """The bodies lying in the straight way of a goal body to its goal (see the module's docstring)."""

    def __init__(self, problem: Problem) -> None:
        tools = {e.tool for e in problem.effectors if e.tool is not None}
        goal_bodies = {g.body for g in problem.goals}
        movable = [b for name, b in problem.bodies.items() if name not in tools | goal_bodies and b.joint is None]
        found: set[str] = set()
        pairs: list[tuple[GoalSpec, str]] = []
        for goal in problem.goals:
            if goal.position is None:
                continue
            body = problem.bodies[goal.body]
            start = body.rest[:2, 3]
            end = np.asarray(goal.position[:2], dtype=float)
            for other in movable:
                reach = _radius(body) + _radius(other)
                if _distance_to_segment(other.rest[:2, 3], start, end) < reach:
                    found.add(other.name)
                    pairs.append((goal, other.name))
        self.bodies = frozenset(found)
        self.blocking = tuple(pairs)  # (goal, body in its way), in the goals' order, then the bodies' order

    def left(self, seq: Sequence) -> int:
        """How many bodies in the way `seq` has not moved yet."""
        return len(self.bodies - seq.dependent)


def _radius(body: PlanBody) -> float:
    """The largest distance of the body's outline from its origin in the table's plane (m)."""
    corners = body.outline[:, :2]
    return float(np.max(np.linalg.norm(corners, axis=1))) if len(corners) else 0.0


def _distance_to_segment(point: np.ndarray, start: np.ndarray, end: np.ndarray) -> float:
    """The distance from `point` to the segment `start`-`end` (2-D)."""
    along = end - start
    length = float(along @ along)
    t = 0.0 if length == 0.0 else float(np.clip((point - start) @ along / length, 0.0, 1.0))
    return float(np.linalg.norm(point - (start + t * along)))


__all__ = ["InTheWay"]
