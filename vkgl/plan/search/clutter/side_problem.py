"""The sub-problem that clears one blocker to one side of a goal body's way (`vkgl.plan.search.clutter.clear_first`):
the blocker's region goal beyond the side (`side_goal`) and which bodies keep which affordances while it is
cleared (`only_moving`)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from vkgl.lang.ir.families import find_member
from vkgl.lang.ir.nodes import Affordance
from vkgl.plan.graphs.motions import rest_axis
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import GoalSpec, PlanBody, Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.clutter.clear_tools import far_move_tools
from vkgl.plan.search.clutter.tool_path import PathSide
from vkgl.plan.task_space.clearing import SIDE_TOLERANCE, Side

ALONG = math.cos(math.radians(30.0))
"""The least |cosine| between a goal body's slide (its axis where the body rests) and its straight way for the
slide to count as along the way (`along_way`): a crate explored on four faces slides along its four face normals,
so on a way up to 30 deg off one of them one pair counts, and on one between two pairs (45 deg off each) none."""


def only_moving(
    problem: Problem,
    goal: GoalSpec,
    blocker: str,
    side: Side,
    root: Sequence | None = None,
    *,
    along: bool = False,
    bound: Bound | None = None,
) -> tuple[Problem, frozenset[str]]:
    """`problem` in which the goal bodies and the tools keep their affordances, and `blocker` those one motion of
    which takes it to `side` (all of them when none does), and the other free bodies, kept still (the second
    result, for `search(still=)`): the plan that clears a blocker moves it, with the hand or a tool, after moving
    a goal body out of the tool's way at most, or a body that a rejected sequence met (the tool's or the arm's
    way to the blocker crosses it: on the physical bench's gen1_001 the stick that pushes the cube in the way
    aside would pass through a crate, which the hand pushes away first); bodies with a joint keep none. A tool
    keeps only the grasps with which it can also end a goal body where its goal is, when it has some (`Bound`'s
    wrong grasps): the plan after the clearing keeps the tool in hand, and one held otherwise would have to be
    let go of and grasped again.

    A goal body with slides keeps no turn here: in the plan that clears its way it moves at most once, out of
    the tool's or the hand's way (a Block pushed back 5 cm with the fingertip before the Stick pushes the cube in
    its way aside), and its turns, each a branch of the search, would only leave it at a heading the move to its
    goal must undo (on the physical bench's gen9_041, a far goal, the same plan clearing the way in 1.3 s of CPU
    instead of 3.9 s; a crate explored on four faces has 16 turns and 4 slides). One that only a tool can carry
    to its goal (`far_move_tools`) keeps only its slides (no grasp either); its moves are kept least (`least`).

    With `along`, every goal body keeps only the slides along its own straight way (`along_way`: towards its goal
    or back from it, never aside; none when it has none): the clearing plan then leaves the goal body on its line,
    where the plan after it needs no move back (`clear_first` tries this sub-problem first).

    `bound`: `problem`'s `Bound` when made already (the walk tries many sides of one problem).

    Whatever is left out, a body keeps every affordance `root` (the plan the sub-problem's search extends) engages:
    the search rolls `root` out in the sub-problem, and a contact it lacks was a KeyError (a blocker the plan
    before nudged with the fingertip, cleared again to a side whose movers are other slides)."""
    keep = {g.body for g in problem.goals} | {e.tool for e in problem.effectors if e.tool is not None} | {blocker}
    still = frozenset(n for n, b in problem.bodies.items() if n not in keep and b.joint is None and b.affordances)
    bodies = {n: b if n in keep or n in still else replace(b, affordances=()) for n, b in problem.bodies.items()}
    mover = bodies[goal.body]
    bound = Bound(problem) if bound is None else bound
    far = far_move_tools(problem, goal, bound) is not None
    kept = tuple(a for a in mover.affordances if a.motion.type == ("prismatic" if far else a.motion.type))
    kept = tuple(a for a in kept if a.motion.type != "revolute")
    if any(a.motion.type == "prismatic" for a in kept):
        bodies[goal.body] = replace(mover, affordances=kept)
    own = problem.bodies[blocker]
    movers = tuple(a for a in own.affordances if a.name in side.movers) or own.affordances
    bodies[blocker] = replace(own, affordances=movers)
    if along:
        for own_goal in problem.goals:
            body = bodies[own_goal.body]
            bodies[own_goal.body] = replace(body, affordances=along_way(problem, own_goal, body.affordances))
        for name in still | {blocker}:
            bodies[name] = replace(bodies[name], affordances=_slides_first(bodies[name].affordances))
    wrong = frozenset().union(*(need.wrong_grasps for need in bound.needs))
    for tool in {e.tool for e in problem.effectors if e.tool is not None}:
        body = bodies[tool]
        right = tuple(a for a in body.affordances if a.motion.type != "free" or (tool, a.name) not in wrong)
        if any(a.motion.type == "free" for a in right):
            bodies[tool] = replace(body, affordances=right)
    for name, engaged in _engaged(root).items():
        bodies[name] = replace(bodies[name], affordances=_keeping(problem.bodies[name], bodies[name], engaged))
    once = (root.depth if root is not None else 1) if along else None
    return replace(problem, bodies=bodies, least=frozenset(g.body for g in problem.goals), moves_once=once), still


def along_way(problem: Problem, goal: GoalSpec, affordances: tuple[Affordance, ...]) -> tuple[Affordance, ...]:
    """The slides of `affordances` (of `goal`'s body) whose axis, where the body rests, lies within `ALONG` of its
    straight way to its goal, either way: a push along them leaves the body on its line (towards the goal, or
    back from it to make room). None when the goal has no position (nothing to be along)."""
    if goal.position is None:
        return ()
    rest = problem.bodies[goal.body].rest
    way = np.asarray(goal.position[:2], dtype=float) - rest[:2, 3]
    if float(np.linalg.norm(way)) < 1e-9:
        return ()
    way = way / float(np.linalg.norm(way))
    kept = []
    for affordance in affordances:
        if affordance.motion.type != "prismatic":
            continue
        axis = rest_axis(rest, affordance.motion)
        norm = float(np.linalg.norm(axis))
        if norm > 1e-9 and abs(float(axis @ way)) / norm >= ALONG:
            kept.append(affordance)
    return tuple(kept)


def _slides_first(affordances: tuple[Affordance, ...]) -> tuple[Affordance, ...]:
    """The slides of `affordances` when it has some, else all of them."""
    return tuple(a for a in affordances if a.motion.type == "prismatic") or affordances


def _engaged(root: Sequence | None) -> dict[str, set[str]]:
    """The affordances (or members) `root`'s actions engage, by body."""
    out: dict[str, set[str]] = {}
    for action in root.actions if root is not None else ():
        out.setdefault(action.engagement.body, set()).add(action.engagement.affordance)
    return out


def _keeping(whole: PlanBody, restricted: PlanBody, engaged: set[str]) -> tuple[Affordance, ...]:
    """`restricted`'s affordances, with those of `whole` that any of the `engaged` names (a member's too) is of."""
    kept = restricted.affordances
    extra = tuple(
        a for a in whole.affordances if a not in kept and any(find_member((a,), n) is not None for n in engaged)
    )
    return kept + extra


def moved_before(root: Sequence, blocker: str) -> bool:
    """Whether a motion value of `root` (the plan that cleared the blockers before) moves `blocker`: a body that
    plan nudged out of its tool's way (gen3_023 of the physical bench: the fingertip pushes a cube 0.9 cm so that
    the Hook, pushing the other cube aside, passes it). The search for the goals after `root`, its values free,
    moves it as far as the goal body's motions need (`clearing.cleared_values`), with no plan of its own: the
    plan is then two graphs shorter than one that clears it again."""
    return root.depth > 1 and any(e.body == blocker for _, e in root.variables)


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
        region_words=side.words if isinstance(side, PathSide) else f"{side.words} of {goal.body}'s way",
    )


__all__ = ["ALONG", "along_way", "moved_before", "only_moving", "side_goal"]
