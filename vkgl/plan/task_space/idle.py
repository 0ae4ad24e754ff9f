"""A contact that moves nothing: a candidate whose motion values leave one of its contacts idle is not a plan of
its sequence's depth.

The task-space optimiser starts a motion value that the goal does not need at 0 and leaves it there: a sequence
such as "push the slab 0 cm, let go, push it along its arc" reaches the goal with the first push idle. The search
passes over such a candidate (`vkgl.plan.search.check.check`), after the bodies' geometry. Take the contact
added at the transition into mode k whose values are 0 in every mode it is in force, and delete its ADD and its
REMOVE (if the sequence has one): the graphs after the REMOVE are the same (`KGraph.apply` keeps the order of the
others), every other motion value is unchanged, and each body starts and ends every remaining mode where it did
(an engagement moves its body by its value only, and a tool at an idle contact rests on a body that does not
move). So the goal, every task-space constraint and the bodies' sweeps of the kept modes are the same for the
shorter sequence, which has 2 graphs fewer (1 when the idle contact is never removed) and which the best-first
search checked before (`vkgl.plan.search.search`; where `successors` does not generate it, the equivalent it
does generate is shorter still: ADD x, REMOVE x, ADD x is ADD x alone, and picking a tool up and putting it back
is nothing). Passing over the idle candidate therefore loses no plan that task space and the bodies' geometry
accept. Only the candidate is passed over, not the sequence: where the idle values make bodies pass through one
another, the values that move a body out of the way (`feasible.task_space_alternatives`) are other candidates
of the same sequence, and there the contact moves something.

What the shorter sequence does differently is the arm's: it skips an approach and a retreat (a plan that needed
the idle contact only for the arm's configuration at a later one, gen1_024 of the physical bench once, is found
without it since contact chains try the arm's other configurations, `vkgl.plan.arm.contact_chains`).

One thing an idle contact does move is a held tool, which jumps to its contact: when the hand lets go of the
tool before the tool's next contact, it is put down where the idle contact left it, not where its last contact
did (`parks_tool`). That contact places the tool, and the sequence without it is a different world (gen8_046: the
hook let go of beside the cube it cleared lies in the crate's way; parked at the crate's far face it does not), so
such a contact is kept (docs/planning.md, "A contact that moves nothing").
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.plan.graphs.graph import motion_type
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection

IDLE_SLIDE = 1e-4
"""m: a slide shorter than this moves nothing (the optimiser's idle values are 0 to within 1e-9)."""

IDLE_TURN = 1e-3
"""rad (0.06 deg): a turn smaller than this moves nothing (a point 10 cm from the pivot moves 0.1 mm)."""


def idle_contact(problem: Problem, seq: Sequence, values: np.ndarray) -> Rejection | None:
    """Why `seq` with motion values `values` (the motions first, as `seq.variables` orders them) is not a
    plan of its depth: a contact it adds moves its body by (nearly) nothing in every mode it is in force;
    None when every contact moves its body."""
    moved: dict[tuple[int, object], float] = {}
    for (mode, e), value in zip(seq.variables, values):
        moved[(mode, e)] = float(value)
    for k, action in enumerate(seq.actions, start=1):
        e = action.engagement
        kind = motion_type(problem, e)
        if action.op != "add" or kind not in ("prismatic", "revolute") or parks_tool(problem, seq, k):
            continue
        modes = _modes_in_force(seq, k)
        largest = max((abs(moved.get((m, e), 0.0)) for m in modes), default=0.0)
        if largest < (IDLE_TURN if kind == "revolute" else IDLE_SLIDE):
            return Rejection(Kind.IDLE, _words(problem, seq, k, kind, largest))
    return None


def parks_tool(problem: Problem, seq: Sequence, k: int) -> bool:
    """Whether the contact added at the transition into mode k is a held tool's last before the hand lets go of
    the tool: the tool is then put down where that contact left it (`rollout._transition`), so the contact
    places the tool even when it moves nothing."""
    tool = problem.effector(seq.actions[k - 1].engagement.effector).tool
    if tool is None:
        return False
    for action in seq.actions[k:]:
        e = action.engagement
        if action.op == "add" and problem.effector(e.effector).tool == tool:
            return False  # the tool jumps to its next contact: where the idle one left it does not matter
        if action.op == "remove" and e.body == tool:
            return True
    return False


def _modes_in_force(seq: Sequence, k: int) -> range:
    """The modes in which the engagement added at the transition into mode k is in force: k up to the mode
    before its REMOVE (the last mode when it is never removed)."""
    e = seq.actions[k - 1].engagement
    for j in range(k, len(seq.actions)):
        if seq.actions[j].op == "remove" and seq.actions[j].engagement == e:
            return range(k, j + 1)
    return range(k, len(seq.graphs))


def _words(problem: Problem, seq: Sequence, k: int, kind: str, value: float) -> str:
    amount = f"{math.degrees(value):.2f} deg" if kind == "revolute" else f"{value * 100:.2f} cm"
    removed = any(a.op == "remove" and a.engagement == seq.actions[k - 1].engagement for a in seq.actions[k:])
    fewer = "2 graphs" if removed else "1 graph"
    return (
        f"step {k} ({seq.actions[k - 1].label(problem)}) moves its body {amount}: nothing; without that contact"
        f"{' and its release' if removed else ''} the sequence reaches the same poses in {fewer} fewer, "
        "checked before"
    )


__all__ = ["IDLE_SLIDE", "IDLE_TURN", "idle_contact", "parks_tool"]
