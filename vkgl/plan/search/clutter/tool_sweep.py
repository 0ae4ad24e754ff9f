"""Bodies in the sweep of the tool that alone can carry a goal body, known before any search meets them.

`InTheWay` names the bodies lying across a goal body's own straight corridor. A goal body beyond the hand's reach
is carried by a tool (`clear_tools.far_move_tools`), and that tool sweeps more than the body: a stick pushing a
slab from behind stands 40 cm behind it, and pushed along the slab's way it sweeps a strip that a body lying
behind the slab can cross although it lies in no goal body's corridor (the physical bench's gen20_009: a SlabW
about 40 cm behind a SlabN, across the Stick's path). Nothing then lets `clear_first` run: the whole timeout went
to a search that only meets the body at sequences of 5 graphs or more, and whose closest miss shoves it aside
without a goal for where it ends (into the arm's base).

`swept_bodies` names them from geometry alone, as `InTheWay` does: for each goal body that only a tool can carry
(`far_move_tools`), each of those tools at a contact enacting a slide of the goal body towards its goal, where the
body rests (`clearing.movers_reach`), swept straight along the goal body's way (the hull of its footprint there and
moved by the way); a free body (no goal body, no tool, no physical joint, a slide among its affordances, in no goal
body's corridor) whose footprint meets such a sweep is in a tool's path. `blocking.blocked` then keeps part of the
work for the clear-first walk, and the walk clears them like the bodies a rejection met in a tool's path
(`tool_path.path_sides`), each slid far enough along one of its own slides to leave the sweeps it lies in
(`exit_slide`), the direction away from where the arm works first (the arm's base is where the closest miss put
gen20_009's SlabW).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vkgl.lang.ir.regions import convex_hull
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.clutter.clear_tools import far_move_tools
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.task_space.clearing import MARGIN, RESOLUTION, footprint, movers_reach, polygon_distance


@dataclass(frozen=True)
class Swept:
    """A body in a tool's path: the goal whose tool sweeps it, and the sweeps (k x 2 convex polygons) it meets."""

    goal: GoalSpec
    sweeps: tuple[np.ndarray, ...]


def tool_sweeps(problem: Problem, goal: GoalSpec, bound: Bound | None = None) -> list[np.ndarray]:
    """The strips the tools that alone can carry `goal`'s body sweep on a straight slide of it to its goal (see the
    module's docstring); none when the hand itself may carry it or the goal has no position."""
    if goal.position is None:
        return []
    tools = far_move_tools(problem, goal, bound)
    start = problem.bodies[goal.body].rest[:2, 3]
    along = np.asarray(goal.position[:2], dtype=float) - start
    length = float(np.linalg.norm(along))
    if tools is None or length < 1e-9:
        return []
    reach = movers_reach(problem, goal.body, along / length)
    return [convex_hull(np.vstack([shape, shape + along])) for tool, _, shape in reach if tool in tools]


def swept_bodies(problem: Problem, bound: Bound | None = None) -> dict[str, Swept]:
    """The free bodies in a tool's path (see the module's docstring), each with its goal and the sweeps it meets,
    nearest its goal body first (then by name: deterministic)."""
    tools = {e.tool for e in problem.effectors if e.tool is not None}
    skip = tools | {g.body for g in problem.goals} | InTheWay(problem).bodies
    free = [
        name
        for name, body in sorted(problem.bodies.items())
        if name not in skip and body.joint is None and any(a.motion.type == "prismatic" for a in body.affordances)
    ]
    found: dict[str, Swept] = {}
    for goal in problem.goals:
        sweeps = tool_sweeps(problem, goal, bound)
        for name in free if sweeps else ():
            shape = footprint(problem, name, problem.bodies[name].rest)
            met = tuple(s for s in sweeps if polygon_distance(shape, s) < MARGIN)
            if met and name not in found:
                found[name] = Swept(goal, met)

    def nearest(name: str) -> tuple[float, str]:
        at, start = problem.bodies[name].rest[:2, 3], problem.bodies[found[name].goal.body].rest[:2, 3]
        return float(np.linalg.norm(at - start)), name

    return {name: found[name] for name in sorted(found, key=nearest)}


def exit_slide(shape: np.ndarray, axis: np.ndarray, sweeps: tuple[np.ndarray, ...], longest: float) -> float | None:
    """The least slide (m) of the footprint `shape` along the unit `axis` that leaves it `MARGIN` clear of every one
    of `sweeps` (within `RESOLUTION`, never short of it), or None when no slide up to `longest` does. The slides
    that leave a convex footprint inside a convex sweep are one interval, so a grid's first clear value and a
    bisection against the last blocked one find where it ends."""

    def clear(slide: float) -> bool:
        moved = shape + slide * axis
        return all(polygon_distance(moved, s) >= MARGIN for s in sweeps)

    if clear(0.0):
        return 0.0
    values = np.linspace(0.0, longest, 49)
    free = next((float(v) for v in values[1:] if clear(float(v))), None)
    if free is None:
        return None
    blocked = free - float(values[1])
    while free - blocked > RESOLUTION:
        middle = 0.5 * (free + blocked)
        free, blocked = (middle, blocked) if clear(middle) else (free, middle)
    return free


__all__ = ["Swept", "exit_slide", "swept_bodies", "tool_sweeps"]
