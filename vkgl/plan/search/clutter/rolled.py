"""A blocker pulled aside by a hook rolled over the body it lies before: its slides' rolled members.

A goal body's slides get members enacted by a tool rolled over a low body beside the contact
(`vkgl.plan.problem.over`: the Hook's shaft, 12 cm beside its tip, lifted over a 5 cm slab by a roll of 15 to 30
deg) when the problem is built. A body in the way is no goal body there, so when `clear_first` asks for it to be
moved aside, its slides had only the tool lying flat. On the physical bench that was the one way aside a far
cube has when it stands 2 to 6 cm before a wide slab that the hook must then pull (gen1_003, gen1_023, gen12_023):
the pull that takes it off the slab's side, made with the hook's tip on its far face, puts the shaft 12 cm
towards the slab, through it by 2 to 3 cm ("hook would pass through target"); the other way aside slides it into
the slab, and the hand reaches neither push itself. A person rolls the hook so that its shaft passes over the
slab's top, as the goal body's own pulls do.

`with_rolled_members` gives the blocker of a clearing sub-problem those members, made exactly as a goal body's
(`over_members`, the low bodies beside it from `clearing_height`), each enacted only by the tool it was rolled
for (`PlanBody.tool_members`). Every check a plan passes still decides (the rolled tool's collisions, the hand's
reach, the grip's torque): a member is one more way to try, not a plan.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from vkgl.lang.ir.families import over_member, over_name, over_pose
from vkgl.lang.ir.geometry import shape_vertices
from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.problem.hulls import hull_vertices
from vkgl.plan.problem.over import MAX_BESIDE_ROLL, clearing_height, over_members
from vkgl.plan.problem.problem import PlanBody, Problem


def with_rolled_members(problem: Problem, blocker: str) -> Problem:
    """`problem` with `blocker`'s slides also enacted by each tool rolled over the low bodies beside it (module
    docstring), where lying flat its parts beside the contact would not pass over them; unchanged when the blocker
    does not lie flat on the table, has a joint, or no member is found."""
    body = problem.bodies[blocker]
    if not body.on_table or body.joint is not None or abs(body.rest[2, 2]) < 0.99:
        return problem
    tools = [
        (e.name, problem.bodies[e.tool].type, e.frame)
        for e in problem.effectors
        if e.tool is not None and e.tool != blocker
    ]
    if not tools:
        return problem
    kinds = {tool.name for _, tool, _ in tools}
    others = [
        (b.rest, _hull_points(b))
        for name, b in problem.bodies.items()
        if name != blocker and b.on_table and b.type.name not in kinds
    ]
    points = _hull_points(body)
    beside = clearing_height(body.rest, points, [tool for _, tool, _ in tools], others, problem.table_z)
    members, pairs = over_members(body.affordances, points, tools, beside)
    members, pairs = _rolled_most(body.affordances, members, pairs)
    known = {a.name for a in body.affordances}
    fresh = tuple(m for m in members if m.name not in known)
    if not fresh:
        return problem
    rolled = replace(body, affordances=body.affordances + fresh, tool_members=body.tool_members | pairs)
    return replace(problem, bodies={**problem.bodies, blocker: rolled})


def _rolled_most(
    affordances: tuple[Affordance, ...], members: tuple[Affordance, ...], pairs: frozenset[tuple[str, str]]
) -> tuple[tuple[Affordance, ...], frozenset[tuple[str, str]]]:
    """`members` and, for each rolled less than `MAX_BESIDE_ROLL`, the same slide rolled that much (same side, same
    lift), for the same tools.

    The least roll (`over_members`) lifts the parts beside the contact over the low bodies beside it, as a goal
    body's pull needs; a blocker's body beside it often lies under the cross-piece as well, 2 to 6 cm from the
    blocker (gen1_023: the hook rolled 15 deg still passed 0.6 cm through the slab's top edge, rolled 25 to 35 deg
    its shaft's far end met a 12 cm cube, rolled 40 and 45 deg the plan passed every check). The most roll the
    grip is asked to carry is the other member: two tries, not one per 5 deg, keep the sub-search's branching
    small."""
    bases = {a.name: a for a in affordances}
    out, more = list(members), set(pairs)
    for member in members:
        pose = over_pose(member.name)
        if pose is None or pose[0] not in bases or abs(pose[1]) >= MAX_BESIDE_ROLL - 1e-9:
            continue
        roll = math.copysign(MAX_BESIDE_ROLL, pose[1])
        name = over_name(pose[0], roll, pose[2])
        out.append(over_member(bases[pose[0]], roll, pose[2]).model_copy(update={"name": name}))
        more |= {(name, effector) for enacted, effector in pairs if enacted == member.name}
    return tuple(dict((m.name, m) for m in out).values()), frozenset(more)


def _hull_points(body: PlanBody) -> np.ndarray:
    """The body's shape's hull points (its frame), as the problem's own members are made from."""
    points = np.asarray(shape_vertices(body.type.shape), dtype=float)
    return points[hull_vertices(points)] if len(points) > 4 else points


def rolls(problem: Problem, blocker: str) -> bool:
    """Whether `with_rolled_members` gives `blocker` any member."""
    return with_rolled_members(problem, blocker) is not problem


__all__ = ["rolls", "with_rolled_members"]
