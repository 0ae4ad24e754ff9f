"""A body the arm runs into, pushed aside first: candidates for a sequence whose contact on that body moves nothing.

Task space moves a body no goal names only as far as the bodies' and tools' sweeps need
(`clearing.cleared_values`): it knows nothing of the arm, whose links are placed only by inverse kinematics
later. So where the arm, not a body, runs into clutter, the sequence that pushes the clutter aside first comes
out of task space with that push at 0, a contact that moves nothing (`vkgl.plan.task_space.idle`), and is passed
over: the physical bench's gen10_027 hooks a Block 35 cm back past a crate that the arm's sixth link brushes by
1 mm 8 % along the pull ("no arm configuration carries the whole motion"), while pushing the crate 11 to 13 cm
back with the fingertip first clears it (checked alone: every check holds).

The search (`search._check`) records the bodies the arm's checks name as in its way (`arm_hits`); a sequence
checked later, whose candidate leaves a contact on such a body idle, is given candidates with that motion at
`SLIDE_STEPS` or `TURN_STEPS` (the smallest first, within its bounds), each kept only when the goal still holds,
every task-space constraint holds and the bodies pass clear of one another; the arm's checks then decide, as for
any candidate. The shorter sequence was rejected by the arm against that body, so these are the plans the idle
rule would otherwise lose; nothing else changes (a sequence whose contacts all move is never given one).
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.graph import motion_type
from vkgl.plan.graphs.rollout import Sequence, bounds, rollout
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.constraints.values import constraint_values
from vkgl.plan.task_space.feasible import JOINT_SAMPLES, TASK_SAMPLES, TaskSolution, goal_holds

SLIDE_STEPS = (0.02, 0.05, 0.08, 0.12, 0.16)
"""m: how far a slide moves a body the arm ran into, tried in turn (the arm brushes by millimetres to centimetres;
a body moved much farther tends to run into another)."""

TURN_STEPS = tuple(math.radians(a) for a in (5.0, 10.0, 20.0, 30.0))
"""rad: the same for a turn."""

ARM_KINDS = (Kind.COLLISION, Kind.IK, Kind.APPROACH)
"""The rejections of the arm's checks that can name a body in the arm's way."""


def arm_hits(problem: Problem, rejection: Rejection) -> set[str]:
    """The bodies no goal names that `rejection`, from the arm's checks, says the arm (or the tool it holds) runs
    into: its `bodies`, as the geometry found them (its words name them too: "... clutter1 is in the way",
    "... would overlap clutter1 by 0.1 cm")."""
    if rejection.kind not in ARM_KINDS:
        return set()
    goals = {g.body for g in problem.goals}
    return {name for name in rejection.bodies if name in problem.bodies and name not in goals}


def moved_aside(
    problem: Problem,
    seq: Sequence,
    idle: TaskSolution,
    hits: set[str],
    geometry: GeometryCheck,
) -> Iterator[TaskSolution]:
    """Candidates of `seq` like `idle`, with each idle motion of a body in `hits` moved by `SLIDE_STEPS` or
    `TURN_STEPS` in turn (see the module's docstring); none when no such motion is idle."""
    goals = {g.body for g in problem.goals}
    lower, upper = bounds(problem, seq)
    for i, (_, e) in enumerate(seq.variables):
        if e.body in goals or e.body not in hits or idle.values[i] != 0.0:
            continue
        steps = TURN_STEPS if motion_type(problem, e) == "revolute" else SLIDE_STEPS
        for step in steps:
            if not lower[i] <= step <= upper[i]:
                continue
            values = np.array(idle.values, dtype=float)
            values[i] = step
            traces = rollout(problem, seq, values, TASK_SAMPLES)
            if float(constraint_values(problem, traces).max()) > 1e-6 or not goal_holds(problem, traces[-1].end):
                continue
            traces = rollout(problem, seq, values, JOINT_SAMPLES)
            if geometry.bodies(seq.graphs, traces) is None:
                yield TaskSolution(values, traces, free=True)
