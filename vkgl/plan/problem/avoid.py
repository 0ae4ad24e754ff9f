"""What a re-solve must not do again: the plans already tried and the steps that failed in execution.

    from vkgl.plan.problem.avoid import Avoid
    avoid = Avoid.of(tried=[document], failed=[document.steps[0]])
    plan = solve(program, task, avoid=avoid)

The closed loop (`vkgl.execute.closed_loop`) re-solves when a plan went wrong
in physics. Re-solving the same scene with the same deterministic planner
gives the same plan, which fails the same way; so the re-solve names what it
must not repeat, and the search (`vkgl.plan.search.search`) rejects what repeats it
as a rejection of kind "excluded" (counted with the other rejections in the
plan's reason and details). Two rules:

- **a step that failed** (`Avoid.steps`): no plan makes the same transition
  (op, affordance, body, effector) with that body within `STEP_TOLERANCE` of
  where it was when the step failed. A sequence whose new transition repeats
  it where the body's pose is already known (it has not moved yet) is cut at
  once with everything that would follow it (`repeated_failure`); otherwise
  the found sequence is checked once its motion values are known
  (`excluded`). The arm's configuration is not part of the rule: before a
  contact motion fails the executor has tried the plan's configuration, the
  chain solved backwards from the end and every one of `Arm.spread_seeds`,
  and the joint-space check (IK warm-started from home) would choose the
  same one again. The same transition after the body has moved is a
  different attempt and may be tried.
- **a plan already tried** (`Avoid.plans`): no plan does the same as one tried:
  the same motions (the ADD steps that slide or turn a body by more than
  `VALUE_TOLERANCE`), in the same order, each with the same transition, value
  within `VALUE_TOLERANCE` and every body at its start within
  `PLAN_TOLERANCE`. Steps that move nothing (a grasp, a let-go, a push by 0)
  do not make a plan different: padding a tried plan with them is the same plan.
  A carry moves a body too (pick and place: a grasp, then the let-go that sets
  the body down elsewhere, `vkgl.plan.graphs.carry`): the pair counts as one
  motion, the same when both its steps are (picked up and set down at the
  same poses).

Keys are built from `vkg-plan/8` step records (`StepKey.of`), so what is
avoided is said in the terms of the plans the executor carried out.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from vkgl.formats.plan import PlanDocument, PlanStepRecord
from vkgl.plan.problem.rejection import Kind, Rejection

STEP_TOLERANCE = (0.01, math.radians(3.0))
"""(m, rad): a failed transition is excluded while its body lies this close to where it failed (a goal's default
tolerance: an arm that could not reach a contact will not reach one a few millimetres away either)."""

PLAN_TOLERANCE = (0.002, math.radians(1.0))
"""(m, rad): two plans are the same when every body at the start of every step is this close in both."""

VALUE_TOLERANCE = {"prismatic": 0.002, "revolute": math.radians(1.0)}
"""m or rad: two steps' motion values this close are the same (other motions have none)."""


@dataclass(frozen=True, eq=False)
class StepKey:
    """One plan step as a re-solve compares it: the transition, its motion value and the bodies at its start.

    `affordance` is qualified by the body type (`Block.push_center_px`), as in
    `vkg-plan/8`; `start` holds the world pose of every body at the step's
    start.
    """

    op: str
    affordance: str
    body: str
    effector: str
    motion: str
    value: float
    start: Mapping[str, np.ndarray]

    @classmethod
    def of(cls, step: PlanStepRecord) -> StepKey:
        """The key of a `vkg-plan/8` step."""
        return cls(
            step.op,
            step.affordance,
            step.body,
            step.effector,
            step.motion,
            float(step.value),
            {name: np.asarray(pose, dtype=float) for name, pose in step.poses_start.items()},
        )

    @property
    def transition(self) -> tuple[str, str, str, str]:
        """(op, affordance, body, effector): what the step does, wherever it does it."""
        return self.op, self.affordance, self.body, self.effector

    def label(self) -> str:
        """`add Block.push_center_px on block with arm.fingertip`."""
        return f"{self.op} {self.affordance} on {self.body} with {self.effector}"

    def repeats_failed(self, failed: StepKey) -> bool:
        """Whether this step makes the transition that `failed` with its body where it was then."""
        return self.transition == failed.transition and failed.failed_at(self.start.get(self.body))

    def failed_at(self, pose: np.ndarray | None) -> bool:
        """Whether `pose` of this (failed) step's body is within `STEP_TOLERANCE` of where it failed (None: yes)."""
        there = self.start.get(self.body)
        return pose is None or there is None or _close(pose, there, STEP_TOLERANCE)

    @property
    def moves(self) -> bool:
        """Whether the step slides or turns a body (an ADD of a prismatic or revolute motion by more than nothing)."""
        return self.op == "add" and self.value > VALUE_TOLERANCE.get(self.motion, math.inf)

    def same_as(self, other: StepKey) -> bool:
        """Whether the two steps are the same: transition, motion value and every body at the start."""
        if self.transition != other.transition:
            return False
        if abs(self.value - other.value) > VALUE_TOLERANCE.get(self.motion, 0.0) + 1e-12:
            return False
        common = self.start.keys() & other.start.keys()
        return all(_close(self.start[name], other.start[name], PLAN_TOLERANCE) for name in common)


@dataclass(frozen=True)
class Avoid:
    """What a re-solve must not repeat: `plans` already tried (each a tuple of step keys) and `steps` that failed."""

    plans: tuple[tuple[StepKey, ...], ...] = ()
    steps: tuple[StepKey, ...] = ()

    @classmethod
    def of(cls, tried: Iterable[PlanDocument] = (), failed: Iterable[PlanStepRecord] = ()) -> Avoid:
        """From the `vkg-plan/8` plans tried (unsolved ones are skipped) and the step records that failed."""
        plans = tuple(tuple(StepKey.of(s) for s in doc.steps) for doc in tried if doc.solved)
        return cls(plans, tuple(StepKey.of(s) for s in failed))

    def __bool__(self) -> bool:
        """True when there is anything to avoid."""
        return bool(self.plans or self.steps)

    def rejection(self, steps: list[StepKey]) -> Rejection | None:
        """Why a plan made of `steps` repeats what is avoided ("excluded"), or None when it does not."""
        for k, step in enumerate(steps, start=1):
            for failed in self.steps:
                if step.repeats_failed(failed):
                    return Rejection(Kind.EXCLUDED, failed_words(k, step))
        motions = _motions(steps)
        for number, tried in enumerate(self.plans, start=1):
            done = _motions(tried)
            if len(done) == len(motions) and all(_same(a, b) for a, b in zip(motions, done, strict=True)):
                return Rejection(Kind.EXCLUDED, f"does the same as the plan tried {_ordinal(number)}")
        return None


def _motions(steps: Iterable[StepKey]) -> list[tuple[StepKey, ...]]:
    """The motions of a plan, in order: each step that slides or turns a body, and each carry (the grasp and the
    let-go that sets its body down elsewhere)."""
    out: list[tuple[StepKey, ...]] = []
    previous: StepKey | None = None
    for step in steps:
        if step.moves:
            out.append((step,))
        elif previous is not None and _carries(previous, step):
            out.append((previous, step))
        previous = step
    return out


def _carries(grasp: StepKey, release: StepKey) -> bool:
    """Whether `release` sets down elsewhere the body `grasp` (the step before it) picked up."""
    if (grasp.op, release.op, grasp.motion, release.motion) != ("add", "remove", "free", "free"):
        return False
    if grasp.transition[1:] != release.transition[1:]:
        return False
    picked, placed = grasp.start.get(grasp.body), release.start.get(release.body)
    return picked is not None and placed is not None and not _close(picked, placed, PLAN_TOLERANCE)


def _same(a: tuple[StepKey, ...], b: tuple[StepKey, ...]) -> bool:
    """Whether two motions are the same: as many steps, each the same (`StepKey.same_as`)."""
    return len(a) == len(b) and all(x.same_as(y) for x, y in zip(a, b, strict=True))


def failed_words(k: int, step: StepKey) -> str:
    """How a rejection names step `k` repeating the failed `step`."""
    return (
        f"step {k} `{step.label()}` failed in execution with {step.body} where it is here "
        f"(within {STEP_TOLERANCE[0] * 100:g} cm, {math.degrees(STEP_TOLERANCE[1]):g} deg)"
    )


def _close(a: np.ndarray, b: np.ndarray, tolerance: tuple[float, float]) -> bool:
    """Whether two 4x4 poses are within (m, rad) of each other."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if float(np.linalg.norm(a[:3, 3] - b[:3, 3])) > tolerance[0]:
        return False
    cosine = (float(np.trace(a[:3, :3].T @ b[:3, :3])) - 1.0) / 2.0
    return math.acos(min(1.0, max(-1.0, cosine))) <= tolerance[1]


def _ordinal(n: int) -> str:
    return {1: "first", 2: "second", 3: "third"}.get(n, f"{n}th")


__all__ = ["Avoid", "StepKey", "failed_words"]
