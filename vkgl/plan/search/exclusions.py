"""A re-solve's exclusions in the search: sequences that repeat what `Problem.avoid` names are rejected.

The rules are `vkgl.plan.problem.avoid`'s; this module applies them to the search's sequences: at once, where the
acting body has not moved yet (`repeated_failure`), or once a found sequence's motion values are known
(`excluded`).
"""

from __future__ import annotations

from collections.abc import Iterable

from vkgl.plan.graphs.graph import Action
from vkgl.plan.graphs.rollout import ModeTrace, Sequence
from vkgl.plan.problem.avoid import StepKey, failed_words
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection


def excluded(problem: Problem, actions: Iterable[Action], traces: list[ModeTrace]) -> Rejection | None:
    """Why the feasible sequence made of `actions` (rolled out as `traces`) repeats what `problem.avoid` names,
    or None (always None when nothing is avoided)."""
    if not problem.avoid:
        return None
    return problem.avoid.rejection(candidate_steps(problem, actions, traces))


def candidate_steps(problem: Problem, actions: Iterable[Action], traces: list[ModeTrace]) -> list[StepKey]:
    """The step keys of a found sequence, as its plan's steps will read (step k is mode k)."""
    keys = []
    for k, action in enumerate(actions, start=1):
        e = action.engagement
        affordance = problem.affordance(e.body, e.affordance)
        value = traces[k].values.get(e, 0.0) if action.op == "add" else 0.0
        keys.append(
            StepKey(
                action.op,
                f"{problem.bodies[e.body].type.name}.{e.affordance}",
                e.body,
                e.effector,
                affordance.motion.type,
                float(max(0.0, value)),
                traces[k].start,
            )
        )
    return keys


def repeated_failure(problem: Problem, before: Sequence, after: Sequence, action: Action) -> Rejection | None:
    """Why `after` (`before` extended by `action`) repeats a step that failed, when that is known before any
    motion value is (the acting body has not moved yet: its pose is the one with all values 0); else None."""
    avoid = problem.avoid
    e = action.engagement
    if not avoid or not avoid.steps or e.body in before.dependent:
        return None
    transition = (action.op, f"{problem.bodies[e.body].type.name}.{e.affordance}", e.body, e.effector)
    pose = after.zero_poses.get(e.body)
    for failed in avoid.steps:
        if failed.transition == transition and failed.failed_at(pose):
            return Rejection(Kind.EXCLUDED, failed_words(len(after.actions), failed))
    return None


__all__ = ["candidate_steps", "excluded", "repeated_failure"]
