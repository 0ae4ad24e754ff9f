"""Other contacts of a sequence: its families' contacts pinned elsewhere along their faces.

The task-space optimiser (`feasible.task_space`) chooses each family's offset
for the goal and the reach only; what it cannot see (the hook's cross-piece
touching the body at the face's centre, the arm against a body in the way) is
found by the later checks. When they reject the first solution, the search asks
for these: the same sequence with every contact pinned at its band's upper end,
then at its lower end.
"""

from __future__ import annotations

import time
from collections.abc import Iterator

import numpy as np

from vkgl.plan.graphs.rollout import Sequence, bounds
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Rejection
from vkgl.plan.task_space.feasible import Counters, TaskSolution, task_space

OTHER_CONTACTS = (1.0, -1.0)
"""Where along their bands the contacts are pinned when the search asks for other contacts of a sequence whose
first solution failed a later check (the hook's cross-piece touching the body at the face's centre): each
family's upper end, then its lower end."""


def other_contacts(
    problem: Problem, seq: Sequence, deadline: float, counters: Counters | None = None
) -> Iterator[TaskSolution]:
    """Solutions of `seq` with its contacts pinned elsewhere along their families' bands (`OTHER_CONTACTS`)."""
    lower, upper = bounds(problem, seq, offsets=True)
    n = len(seq.variables)
    for side in OTHER_CONTACTS:
        if time.perf_counter() > deadline:
            return
        pinned = upper[n:] if side > 0 else lower[n:]
        if not np.any(pinned):
            continue
        found = task_space(problem, seq, deadline, counters, offsets=pinned)
        if not isinstance(found, Rejection):
            yield found
