"""Re-solving during a closed-loop execution: what has been tried, and how the planner is asked again.

The executor never imports the planner: it re-solves through the `resolve`
function its caller supplies (`Resolver`), and tells it what not to repeat
(`Attempts`): every plan carried out so far and the steps that failed in
physics. The driver (`vkgl.api`) turns that into the planner's
`vkgl.plan.problem.avoid.Avoid`, so the re-solve excludes the failed transitions
where they failed and never returns a plan already tried.

`resolve_with_margin` is the execution's policy around the resolver: ask for
half of every goal tolerance first (`RESOLVE_MARGIN`), then for all of it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

from vkgl.formats.execution_report import ExcludedStep
from vkgl.formats.plan import PlanDocument, PlanStepRecord
from vkgl.lang.ir.nodes import Quantity
from vkgl.lang.ir.program import Program


@dataclass(frozen=True)
class FailedStep:
    """A step the arm could not carry out: which plan (0 = the one given), its number there, the step, and why."""

    plan: int
    index: int
    step: PlanStepRecord
    why: str

    def record(self) -> ExcludedStep:
        """The step as the execution report names it."""
        return ExcludedStep(self.plan, self.index, self.step.title(), self.why)


@dataclass(frozen=True)
class Attempts:
    """What the closed loop has tried so far: the plans it carried out (or began to) and the steps that failed."""

    plans: tuple[PlanDocument, ...] = ()
    failed: tuple[FailedStep, ...] = ()
    arm: tuple[float, ...] | None = None
    """The arm's joints where it stands (the re-solved plan's paths start there); None: its home configuration."""

    @property
    def failed_steps(self) -> tuple[PlanStepRecord, ...]:
        """The `vkg-plan/8` records of the steps that failed, in order."""
        return tuple(f.step for f in self.failed)


Resolver = Callable[[Program, str, Attempts], PlanDocument]
"""Solves a task (by name) of a program, repeating none of the attempts; returns its `vkg-plan/8` document, of
any status. Must not return a plan of `attempts.plans` nor repeat a step of `attempts.failed` where it failed
(`vkgl.plan.problem.avoid` says how the planner decides). May raise VkgError (reported as a re-solve
that found no plan)."""


RESOLVE_MARGIN = 0.5
"""A re-solve first asks for this fraction of each goal tolerance, then (if that finds no plan) for all of it."""


def resolve_with_margin(
    resolve: Resolver, program: Program, task: str, attempts: Attempts | None = None
) -> PlanDocument:
    """Re-solve `task` of `program` with `resolve`, keeping a margin inside the goal tolerance if possible.

    A planner returns the first plan that meets the goal within its
    tolerance, often at the tolerance's edge; from an observed (already
    disturbed) scene that leaves physics no margin. So the re-solve first
    asks for `RESOLVE_MARGIN` of every tolerance and only when that finds no
    plan for all of it. Both avoid the same `attempts`.
    """
    attempts = Attempts() if attempts is None else attempts
    plan = resolve(_with_tighter_goals(program, task, RESOLVE_MARGIN), task, attempts)
    if not plan.solved:
        plan = resolve(program, task, attempts)
    return plan


def _with_tighter_goals(program: Program, task_name: str, fraction: float) -> Program:
    """A copy of `program` whose task `task_name` asks for `fraction` of each goal tolerance."""
    task = program.task(task_name)
    goals = []
    for goal in task.goals:
        tol_p, tol_y = goal.tolerance()
        tighter = {
            "tol_position": Quantity(value=tol_p * fraction, unit="m"),
            "tol_yaw": Quantity(value=tol_y * fraction, unit="rad"),
        }
        if goal.opening is not None:  # a joint goal: its one tolerance, in SI of its kind
            unit = "rad" if goal.opening.unit in ("deg", "rad") else "m"
            tighter["tol_opening"] = Quantity(value=goal.opening_tolerance() * fraction, unit=unit)
        goals.append(goal.model_copy(update=tighter))
    return dataclasses.replace(program, tasks={**program.tasks, task_name: task.model_copy(update={"goals": goals})})


__all__ = ["RESOLVE_MARGIN", "Attempts", "FailedStep", "Resolver", "resolve_with_margin"]
