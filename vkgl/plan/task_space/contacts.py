"""Other contacts of a sequence: its families' contacts pinned elsewhere along their faces.

The task-space optimiser (`feasible.task_space`) chooses each family's offset
for the goal and the reach only; what it cannot see (the hook's cross-piece
touching the body at the face's centre, the arm against a body in the way) is
found by the later checks. When they reject the first solution because the arm
cannot approach a contact, the search asks for this: the same sequence with
every contact pinned at its band's far end.
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import numpy as np

from vkgl.plan.graphs.rollout import Sequence, bounds
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Rejection
from vkgl.plan.task_space.feasible import Counters, TaskSolution, task_space


def other_contacts(
    problem: Problem, seq: Sequence, deadline: float, counters: Counters | None = None
) -> Iterator[TaskSolution]:
    """The solution of `seq` (if any) with each family's contact pinned at its band's end farthest from the written
    contact: the largest move along the face, tried once (each try costs the arm's checks again)."""
    lower, upper = bounds(problem, seq, offsets=True)
    # The values are the motions, then the offsets, then each carry's placement (dx, dy, dyaw): only the offsets.
    band = slice(len(seq.variables), len(seq.variables) + len(seq.offsets))
    pinned = np.where(np.abs(upper[band]) >= np.abs(lower[band]), upper[band], lower[band])
    if time.perf_counter() > deadline or not np.any(pinned):
        return
    found = task_space(problem, seq, deadline, counters, offsets=pinned)
    if not isinstance(found, Rejection):
        yield found
