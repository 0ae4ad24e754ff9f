"""The tool that clears a blocker is the tool that then moves the goal body: which grasps may clear a far way.

A goal body beyond the hand's reach is moved by a tool (a stick's push away from the arm, a hook's pull towards
it). A person who finds a body lying across its way takes that tool, moves the blocker aside with it, and moves
the goal body with the same tool still in hand. A blocker cleared with another tool costs a release and a grasp
more, and the tool let go of lies where it was released, often in the goal body's corridor (on the physical bench,
a stick dropped beside the way of a crate the hook then pulls: "target would pass through stick").

`far_move_grasps` names the (tool, grasp) pairs that can start the goal body's move: the hand, holding the tool by
that grasp, within the arm's reach at some contact of a slide of the goal body towards its goal, with the body
where it rests (`goal_reach.ends_beyond_the_hand`, asked about the body's rest pose). When the hand itself can
start that move (or no slide points towards the goal, or nothing can be shown), nothing is restricted: None.
The test is conservative like `ends_beyond_the_hand` (a grasp is left out only when every frame of its tool is
shown out of reach at every such contact), so the sub-problem of `clear_first` loses no plan that clears the
blocker with the tool the goal body's first slide needs.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.motions import rest_axis
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.bounds.goal_reach import ends_beyond_the_hand
from vkgl.se3 import yaw_of

TOWARDS = math.cos(math.radians(45.0))
"""The least cosine between a slide's axis (in the world, where the body rests) and the goal body's straight way
for the slide to count as one that starts its move towards its goal."""


def towards_slides(problem: Problem, goal: GoalSpec) -> list[Affordance]:
    """The goal body's slides whose axis, where it rests, points towards its goal position (within `TOWARDS`)."""
    body = problem.bodies[goal.body]
    if goal.position is None:
        return []
    way = np.asarray(goal.position[:2], dtype=float) - body.rest[:2, 3]
    if float(np.linalg.norm(way)) < 1e-9:
        return []
    u = way / np.linalg.norm(way)
    out = []
    for affordance in body.affordances:
        if affordance.motion.type != "prismatic" or body.joint not in (None, "prismatic"):
            continue
        axis = rest_axis(body.rest, affordance.motion)
        norm = float(np.linalg.norm(axis))
        if norm > 1e-9 and float(axis @ u) / norm >= TOWARDS:
            out.append(affordance)
    return out


def far_move_grasps(problem: Problem, goal: GoalSpec) -> frozenset[tuple[str, str]] | None:
    """The (tool, grasp) pairs by which the hand can start `goal`'s body on a slide towards its goal where it rests
    (see the module's docstring); None when the hand itself may, or nothing restricts them."""
    body = problem.bodies[goal.body]
    slides = towards_slides(problem, goal)
    if not slides:
        return None
    at_rest = GoalSpec(goal.body, body.rest[:2, 3].copy(), yaw_of(body.rest), 0.0, 0.0)
    if ends_beyond_the_hand(problem, body, at_rest, slides) is None:
        return None  # the hand may hold one of them itself (or that cannot be shown)
    out = set()
    for tool in sorted({e.tool for e in problem.effectors if e.tool is not None}):
        frames = [e for e in problem.effectors if e.tool == tool]
        for grasp in problem.bodies[tool].affordances:
            if grasp.motion.type != "free":
                continue
            chains = [e.frame_inverse @ problem.action(tool, grasp.name) for e in frames]
            if not all(ends_beyond_the_hand(problem, body, at_rest, slides, chain) for chain in chains):
                out.add((tool, grasp.name))
    return frozenset(out)


def far_move_tools(problem: Problem, goal: GoalSpec, bound: Bound | None = None) -> frozenset[str] | None:
    """The tools that can carry `goal`'s body along its way when only a tool can (the hand can neither start it,
    `far_move_grasps`, nor end it at its goal, `Bound`'s `ends_by_tool`): those that can start it, of those the
    ones with a grasp that can also end it (not all of `Bound`'s wrong grasps for it). None when the hand itself
    may carry it, or when no tool is left (nothing is then known of which tool moves it). `bound`: `problem`'s
    `Bound` when made already (a clearing walk asks for every side it tries; making it costs tens of ms)."""
    tools = frozenset(e.tool for e in problem.effectors if e.tool is not None)
    needs = [need for need in (bound or Bound(problem)).needs if need.body == goal.body]
    starting = far_move_grasps(problem, goal)
    if starting:
        tools = frozenset(tool for tool, _ in starting)
    elif not any(need.ends_by_tool for need in needs):
        return None
    wrong = frozenset().union(*(need.wrong_grasps for need in needs))
    ending = frozenset(
        tool
        for tool in tools
        if any(a.motion.type == "free" and (tool, a.name) not in wrong for a in problem.bodies[tool].affordances)
    )
    return ending or None


__all__ = ["TOWARDS", "far_move_grasps", "far_move_tools", "towards_slides"]
