"""The task space's handling of arc members whose offset is a variable (`vkgl.plan.graphs.members.ArcSeed`).

`feasible.task_space` solves a sequence with its contacts' offsets pinned at 0 first, then free; these say
when an arc member skips the first (a seed: `seeds_only`), bound its turn over its band (`cap_arc_turns`) and
round its offset to what a member's name keeps (`named_offsets`).
"""

from __future__ import annotations

import numpy as np

from vkgl.plan.graphs.members import arc_seed, turn_cap
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem


def seeds_only(problem: Problem, seq: Sequence) -> bool:
    """Whether every contact that may move along its face is an arc member offered as a seed (`PlanBody.arc_seeds`:
    its exact turn from rest misses the goal): its offset is free from the start, and one run from the closed
    form's start does (a seed is offered to every sequence that turns its body: restarts would cost each failing
    sequence four runs more)."""
    return bool(seq.offsets) and all(e.affordance in problem.bodies[e.body].arc_seeds for _, e in seq.offsets)


def cap_arc_turns(problem: Problem, seq: Sequence, lower: np.ndarray, upper: np.ndarray) -> None:
    """Bound each arc member's turn (in place) by the least its slide's range allows over its band
    (`members.turn_cap`): its own range holds at its own offset only. A prefix's pinned values are kept."""
    for i, (_, e) in enumerate(seq.variables):
        if i >= len(problem.pinned):
            upper[i] = min(upper[i], turn_cap(problem, e.body, e.affordance))
            lower[i] = min(lower[i], upper[i])


def named_offsets(problem: Problem, seq: Sequence, x: np.ndarray) -> np.ndarray:
    """The contacts' offsets of `x` rounded to what the members' names keep (0.01 cm of the offset along the
    face: an arc member's own offset plus the change, rounded together)."""
    n = len(seq.variables)
    out = []
    for (_, e), value in zip(seq.offsets, x[n : n + len(seq.offsets)]):
        seed = arc_seed(problem, e.body, e.affordance)
        own = 0.0 if seed is None else seed.offset
        out.append(round((own + float(value)) * 1e4) / 1e4 - own)
    return np.asarray(out, dtype=float)
