"""Contact families in the task space: the action and the motion of an engagement at an offset along its face.

An engagement of an affordance with a `family` (docs/language.md, "Families")
has one more variable in the task-space optimisation: the offset of its
contact along the face, fixed from its ADD to its REMOVE (`Sequence.offsets`).
At offset `s` the effector's frame is the action's pose moved by `s * along`
and a turn's pivot is moved by `s * drift` (`vkgl.lang.ir.families.at_offset`,
here as matrices, for the rollouts' inner loop). Once the optimiser has chosen
the offsets, the sequence is rewritten with the members' names
(`push_center_px@+3.12cm`, `rollout.materialise`) and every later stage reads
a point affordance.
"""

from __future__ import annotations

import numpy as np

from vkgl.lang.ir.families import offset_bounds
from vkgl.lang.ir.nodes import Affordance, PrismaticC, RevoluteC
from vkgl.plan.problem.problem import Problem

_VECTORS: dict[int, tuple[Affordance, np.ndarray, np.ndarray | None]] = {}


def family_vectors(affordance: Affordance) -> tuple[np.ndarray, np.ndarray | None]:
    """(unit `along`, a turn's `drift` or None) of a family; zeros and None without one (cached by identity)."""
    cached = _VECTORS.get(id(affordance))
    if cached is not None and cached[0] is affordance:
        return cached[1], cached[2]
    family = affordance.family
    along, drift = np.zeros(3), None
    if family is not None:
        along = family.along.array() / np.linalg.norm(family.along.array())
        if family.drift is not None and isinstance(affordance.motion, RevoluteC):
            drift = family.drift.array()
    _VECTORS[id(affordance)] = (affordance, along, drift)  # kept so that its id stays its own
    return along, drift


def has_family(problem: Problem, body: str, name: str) -> bool:
    """Whether the planner may move the affordance's contact along its face: a turn whose band is wider than a
    point.

    A slide's family is not used (yet): it was learned from exploration's force-limited pushes, which DART's
    friction holds straight off the centre, but the arm pushes by position, and that push turns the body
    (the stdlib Block pushed 10 cm by the arm 1.1, 2.2 and 3.3 cm off its centre turned 2, 17 and 24 deg;
    docs/planning.md, "Contacts along a face"). A turn's member executes as predicted (7.7 cm off the
    centre, between two explored contacts: 1.5 deg off over a 20 deg turn).
    """
    affordance = problem.affordance(body, name)
    lower, upper = offset_bounds(affordance)
    return upper > lower and isinstance(affordance.motion, RevoluteC)


def action_at(problem: Problem, body: str, name: str, offset: float) -> np.ndarray:
    """The effector frame in the body's frame at `offset` (m) along the family of affordance `name`."""
    base = problem.action(body, name)
    if offset == 0.0:
        return base
    affordance = problem.affordance(body, name)
    if isinstance(affordance.motion, PrismaticC):  # a slide a tool's flat face enacts off the centre (`tool_faces`)
        along = base[:3, 1]
    else:
        along, _ = family_vectors(affordance)
    out = base.copy()
    out[:3, 3] += offset * along
    return out


def pivot_shift(problem: Problem, body: str, name: str, offset: float) -> np.ndarray | None:
    """How far a turn's pivot moves at `offset` (None when it does not: a slide, no drift, offset 0)."""
    if offset == 0.0:
        return None
    _, drift = family_vectors(problem.affordance(body, name))
    return None if drift is None else offset * drift
