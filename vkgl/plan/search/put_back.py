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
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.graph import motion_type
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, rollout
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Rejection
from vkgl.plan.task_space.feasible import JOINT_SAMPLES, TaskSolution


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
    (`returned_tools`), when the bodies' geometry then passes; None otherwise (no such tool, or still a clash)."""
    tools = frozenset(b for b in clash.bodies if any(e.tool == b for e in problem.effectors))
    if not tools:
        return None
    variant = returned_tools(problem, seq, solution.traces, tools)
    if variant is None:
        return None
    traces = rollout(problem, variant, solution.values, JOINT_SAMPLES)
    if geometry.bodies(variant.graphs, traces) is not None:
        return None
    return variant, replace(solution, traces=traces, sequence=variant)


__all__ = ["put_back", "returned_tools"]
