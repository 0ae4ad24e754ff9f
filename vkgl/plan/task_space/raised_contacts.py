"""A candidate with its fingertip contacts raised on their faces: tried when the arm's checks reject it as written.

The arm's checks (joint space, the arm's geometry at each contact, the chains along each contact's motion) may
reject a candidate because the upright hand at a contact pressed at the body's mid-height stands in that body or
in a taller one beside it, and leaning back cannot help (`vkgl.plan.problem.raised`). `raised_contacts` gives the
same candidate with every fingertip contact on a body lying flat raised as that module says (`raised_name`): the
same motion values, the same bodies' poses in every mode, the hand higher on each face; the search checks it like
any candidate (`vkgl.plan.search.check.check`), and only after the written one failed, so a plan that pushed
where exploration pushed is never replaced by a raised one, and the search makes no more sequences: the raised
contact is another candidate of the same sequence, as a body moved farther aside is.

`after_arm` gives the candidates tried once the arm's checks rejected the first: its contacts raised, then its
values as the optimiser found them before `feasible.least_room` shortened a move that made room
(`feasible.roomier_after`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import replace

from vkgl.plan.graphs.graph import Engagement, KGraph
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, renamed, rollout
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.raised import raised_name
from vkgl.plan.task_space.feasible import JOINT_SAMPLES, TaskSolution, roomier_after


def raised_contacts(problem: Problem, seq: Sequence, found: TaskSolution) -> tuple[Sequence, TaskSolution] | None:
    """`seq` (its families' members named) with each fingertip contact that can be raised renamed to its raised
    member, and `found`'s values rolled out along it; None when no contact can be raised."""
    fingertip = problem.robot_effector.name

    def raised(k: int, e: Engagement) -> str | None:
        return _raised(problem, e) if e.effector == fingertip else None

    out = renamed(problem, seq, raised)  # a tool set down where it was picked up stays so (`put_back`)
    if out.actions == seq.actions:
        return None
    traces = rollout(problem, out, found.values, JOINT_SAMPLES)
    return out, replace(found, traces=traces, sequence=out)


def raised_after(
    problem: Problem, rejected: list[tuple[Sequence, TaskSolution]]
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """The first of `rejected` (the candidates the arm's checks rejected, read when this is asked for its item)
    with its fingertip contacts raised (`raised_contacts`), if any can be."""
    if rejected and (found := raised_contacts(problem, *rejected[0])) is not None:
        yield found


def after_arm(
    problem: Problem,
    rejected: list[tuple[Sequence, TaskSolution]],
    clash: Callable[[tuple[KGraph, ...], list[ModeTrace]], object | None],
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """The candidates tried after the arm's checks rejected the first of `rejected` (read when asked for): its
    fingertip contacts raised (`raised_after`), then its roomier values (`roomier_after`; `clash`: the bodies'
    collision check)."""
    yield from raised_after(problem, rejected)
    yield from roomier_after(problem, rejected, clash)


def _raised(problem: Problem, e: Engagement) -> str | None:
    """The raised member's name of engagement `e` (`raised_name`), for a body lying flat on the table; else None."""
    body = problem.bodies[e.body]
    if not body.on_table or body.joint is not None or abs(body.rest[2, 2]) < 0.99:
        return None
    clauses = problem.program.tipping.get(body.type.name, [])
    return raised_name(body.type, problem.affordance(e.body, e.affordance), clauses)


__all__ = ["after_arm", "raised_after", "raised_contacts"]
