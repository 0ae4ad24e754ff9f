"""A tool let go of where it was picked up, when where it was used is in the way.

A tool let go of is put down where it was used (`vkgl.plan.graphs.rollout`): lowered onto the table beside the
body it acted on. That is right when nothing comes back there, and wrong when the same body moves on: the Hook
pulls a 30 cm slab from 1.0 m to 0.56 m over its top (rolled 20 deg, its shaft 1 cm above the slab), and the
fingertip is to turn the slab the rest of the way to its goal; put down where the pull left it, the hook would lie
2 cm inside the slab (bench_wide_pulls' SlabW `free-` goal 0: "target would pass through hook by 2.0 cm at the
start of mode 4: hook is in the way", every such sequence), and flat at the far face it lies where the slab turns.
A person puts the hook back where they took it from, then turns the slab by hand.

So when the bodies' geometry check finds a tool the sequence let go of in the way (`Rejection.bodies`), the same
motion values are tried with every release of that tool after a use of it set down where the hand last picked it
up (its pose at that grasp, `Sequence.returns`); the hand lets go of it there (`rollout._hand_path`: one hand pose
at the start of the mode after the release, which inverse kinematics and the reach check judge), and the arm's
paths carry it there, lifted clear of the others, and lower it onto its place (`vkgl.plan.arm.paths`: a release
whose tool lies away from where its last contact left it is a place, as a carried body's). The variant is kept
only when the bodies' geometry passes then; the goal bodies end where they did (their motions are the same).

Where the hand picked the tool up can be taken by then: the Hook pulls a 30 cm crate 46 cm from 1.0 m, onto the
place the hook lay on (bench_wide_pulls' CrateM `free+` goal 0), and the fingertip is to turn the crate from
there. A person sets the hook down beside its place. So when the bodies' geometry, with the tools back at their
places, still names one of them, the same places moved on the table (`PLACE_RINGS` around it, `PLACE_BEARINGS`
directions, nearest first; the tool's outline on the table and the hand at its grasp there inside the arm's usable
reach) are tried, the first that passes kept. A clash that names none of the returned tools is no place's to
solve, and ends the tries.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import replace

import numpy as np

from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.graph import Engagement, motion_type
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, rollout
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Rejection
from vkgl.plan.task_space.feasible import JOINT_SAMPLES, TaskSolution
from vkgl.plan.task_space.reach.workspace import hand_reach_violation

PLACE_RINGS = (0.10, 0.20, 0.30)
"""m: how far from where it was picked up a tool is set down when that place is taken (nearest first)."""

PLACE_BEARINGS = 8
"""The directions (evenly spaced on the table, from the world's +x) a tool's place is moved in, per ring."""

TABLE_MARGIN = 0.01
"""m: a tool set down away from its place keeps its outline this far inside the table's edge."""


def returned_tools(problem: Problem, seq: Sequence, traces: list[ModeTrace], tools: frozenset[str]) -> Sequence | None:
    """`seq` with each release of a tool of `tools` that follows a use of it (a contact made with one of its
    frames since the hand grasped it) set down where the hand grasped it (its pose at that grasp in `traces`, a
    rollout of `seq`); None when no release is such."""
    robot = problem.robot_effector.name
    picked: dict[str, np.ndarray] = {}  # tool -> where the hand grasped it last
    used: set[str] = set()  # the tools with a contact since that grasp
    returns: list[tuple[int, np.ndarray]] = []
    for k, action in enumerate(seq.actions, start=1):
        e = action.engagement
        held = e.effector == robot and motion_type(problem, e) == "free" and e.body in tools
        if action.op == "add" and held:
            picked[e.body] = traces[k].start[e.body]
            used.discard(e.body)
        elif action.op == "add" and (tool := problem.effector(e.effector).tool) is not None:
            used.add(tool)
        elif action.op == "remove" and held and e.body in picked and e.body in used:
            returns.append((k, picked.pop(e.body)))
    return replace(seq, returns=tuple(returns)) if returns else None


def put_back(
    problem: Problem, seq: Sequence, solution: TaskSolution, clash: Rejection, geometry: GeometryCheck
) -> tuple[Sequence, TaskSolution] | None:
    """`seq` and `solution` with the tools `clash` finds in the way set down where they were picked up
    (`returned_tools`), or, where a returned tool is still in the way there, beside that place (`moved_returns`),
    when the bodies' geometry then passes; None otherwise (no such tool, or still a clash)."""
    tools = frozenset(b for b in clash.bodies if any(e.tool == b for e in problem.effectors))
    if not tools:
        return None
    variant = returned_tools(problem, seq, solution.traces, tools)
    if variant is None:
        return None
    returned = {seq.actions[k - 1].engagement.body for k, _ in variant.returns}
    for moved in moved_returns(problem, variant):
        traces = rollout(problem, moved, solution.values, JOINT_SAMPLES)
        found = geometry.bodies(moved.graphs, traces)
        if found is None:
            return moved, replace(solution, traces=traces, sequence=moved)
        if not found.bodies & returned:
            return None  # the tools' places are free: what clashes is no place's to solve
    return None


def moved_returns(problem: Problem, seq: Sequence) -> Iterator[Sequence]:
    """`seq` (its `returns` as they are), then `seq` with every returned tool's place moved by the same shift on
    the table (`PLACE_RINGS` x `PLACE_BEARINGS`, nearest first), where each tool's outline stays on the table and
    the hand at its grasp there inside the arm's usable reach."""
    yield seq
    for radius in PLACE_RINGS:
        for i in range(PLACE_BEARINGS):
            bearing = 2 * math.pi * i / PLACE_BEARINGS
            shift = radius * np.array([math.cos(bearing), math.sin(bearing)])
            returns = []
            for mode, pose in seq.returns:
                moved = pose.copy()
                moved[:2, 3] += shift
                if not _placeable(problem, seq.actions[mode - 1].engagement, moved):
                    break
                returns.append((mode, moved))
            else:
                yield replace(seq, returns=tuple(returns))


def _placeable(problem: Problem, grasp: Engagement, pose: np.ndarray) -> bool:
    """Whether the tool of the hand's `grasp` may be set down at `pose`: its outline `TABLE_MARGIN` inside the
    table (a scene without a table: nowhere but its own place) and the hand at that grasp inside the reach."""
    if problem.table_center is None or problem.table_size is None:
        return False
    body = problem.bodies[grasp.body]
    corners = (body.outline @ pose[:3, :3].T + pose[:3, 3])[:, :2]
    low = problem.table_center - problem.table_size / 2 + TABLE_MARGIN
    high = problem.table_center + problem.table_size / 2 - TABLE_MARGIN
    if not (np.all(corners >= low) and np.all(corners <= high)):
        return False
    hand = pose @ problem.action(grasp.body, grasp.affordance)
    return hand_reach_violation(problem, hand) <= 0


__all__ = ["moved_returns", "put_back", "returned_tools"]
