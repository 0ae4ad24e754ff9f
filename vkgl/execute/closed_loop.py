"""Execute a plan in DART: `vkgc solve TASK --execute [--replan]`.

    from vkgl.execute.closed_loop import execute
    report = execute(program, "a_push", plan_document, replan=True, resolve=resolver)
    print(report.text())

The plan is a `vkgl.formats.plan.PlanDocument` (read it with
`vkgl.formats.plan.read` or `from_json`); the executor never reads files,
never compiles and never imports the planner: re-solving goes through the
`resolve` function the caller (the driver) supplies.

Open loop (`replan=False`) the plan's steps are carried out one after another
(`vkgl.execute.replay`) and the bodies end wherever physics puts them. Closed loop
(`replan=True`), before the first step and after every step the real poses are
compared with the plan (a body on a physical joint by its joint's
coordinate, `vkgl.execute.goal_checks`); when a body is off by more than half
the goal's tolerance the robot lets go, puts down what it holds, and the task is solved
again from the observed scene (the same task, its scene's start poses replaced
by the observed ones); after `max_replans` re-solves it gives up and says why.
A re-solve first asks for half of every goal tolerance (`RESOLVE_MARGIN`), and
for all of it only when that finds no plan: an execution policy, kept here.
A re-solve learns from what went wrong (`vkgl.execute.resolving.Attempts`):
it excludes every step the arm could not carry out, where it failed, and
every plan already tried; the report's `resolves` say what each excluded and
found. If a re-solve finds no plan and nothing was put down, the current plan
goes on.
The report's status is `reached` when every goal of the task holds at the end
(a joint goal on the simulated joint's coordinate).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping

import numpy as np

from vkgl.errors import InputError, VkgError
from vkgl.execute.effector_path import rotation_angle
from vkgl.execute.goal_checks import check_goal, miss_reason, replan_limits
from vkgl.execute.progress import Progress, ProgressFeed
from vkgl.execute.replay import Replay
from vkgl.execute.resolving import RESOLVE_MARGIN, Attempts, FailedStep, Resolver, resolve_with_margin
from vkgl.execute.world_arm import ArmStuck
from vkgl.formats.execution_report import (
    Deviation,
    Disturbance,
    ExecutionReport,
    GoalResult,
    Opening,
    Resolve,
    StepReport,
)
from vkgl.formats.plan import PlanDocument, PlanStepRecord
from vkgl.lang.ir.geometry import shape_vertices
from vkgl.lang.ir.nodes import Goal, Task
from vkgl.lang.ir.program import Program
from vkgl.se3 import angle_difference, yaw_of

Step = tuple[int, PlanStepRecord]
"""A plan step with its number in its plan (from 1)."""

FINAL_SETTLE = 0.5  # s the world runs after the last step before the goal is checked


def execute(
    program: Program,
    task: Task | str | None,
    plan: PlanDocument,
    *,
    replan: bool = False,
    max_replans: int = 3,
    record: bool = False,
    resolve: Resolver | None = None,
    on_step: Callable[[StepReport], None] | None = None,
    on_progress: Callable[[Progress], None] | None = None,
    on_resolve: Callable[[Resolve], None] | None = None,
) -> ExecutionReport:
    """Carry out a solved `vkg-plan/8` plan for `task` in DART and report how close it got to the goal.

    `on_step(step_report)` is called as each step ends (progress for long runs),
    `on_progress(progress)` while the world runs (`vkgl.execute.progress`: the
    step, the arm's phase, the simulated time), `on_resolve(resolve)` after
    each re-solve (why, what it excluded, what it found).
    `task` is the Task IR, its name, or None for the program's first task.
    With `replan`, re-solve from the observed scene whenever a body strays
    from the plan by more than half its tolerance (at most `max_replans`
    times) with `resolve(program, task_name, attempts) -> PlanDocument`, which
    the caller must then supply (ValueError otherwise); `attempts` names the
    plans tried and the steps that failed, which the new plan must not
    repeat. With `record`, the report keeps frames for `animate`.
    Raises InputError when `max_replans` is negative (before any work), when
    the plan is not solved or does not fit the program.
    """
    if max_replans < 0:
        raise InputError(f"max_replans must be 0 or more, not {max_replans}")
    if replan and resolve is None:
        raise ValueError(
            "execute(replan=True) needs `resolve`, a function (program, task name, attempts) -> PlanDocument"
        )
    if not isinstance(plan, PlanDocument):
        raise TypeError(
            f"execute() takes a vkgl.formats.plan.PlanDocument, not {type(plan).__name__} "
            "(vkgl.formats.plan.from_json reads one from JSON data)"
        )
    started = time.perf_counter()
    task = _task(program, task)
    scene = program.scenes.get(task.scene.name)
    if scene is None:
        raise InputError(f"task {task.name}: no scene `{task.scene.name}` in the program")
    if plan.task != task.name:
        raise InputError(f"the plan is for task `{plan.task}`, not `{task.name}`")
    replay = Replay(program, scene, _solved(plan).robot, record=record)
    loop = _Loop(program, task, replay, replan=replan, max_replans=max_replans, resolve=resolve)
    loop.on_step, loop.on_resolve = on_step, on_resolve
    loop.feed = ProgressFeed(on_progress, lambda: replay.label, lambda: replay.time)
    replay.watch(loop.feed.tick if on_progress is not None else None)
    loop.expect(plan)
    try:
        status, reason = loop.run(_numbered(plan))
    finally:
        replay.watch(None)
    disturbed = loop.disturbances() if status in ("reached", "missed") else []
    if disturbed and status == "reached":
        status, reason = "disturbed", "; ".join(d.text() for d in disturbed)
    return ExecutionReport(
        task=task.name,
        status=status,
        reason=reason,
        steps=loop.reports,
        goals=loop.goal_results(),
        replans=loop.replans,
        replan_log=loop.log,
        final=replay.poses(),
        sim_time=replay.time,
        wall_time=time.perf_counter() - started,
        solve_time=loop.solve_time,
        frames=replay.frames,
        bodies=dict(replay.types),
        table=scene.table,
        closed_loop=replan,
        disturbed=disturbed,
        resolves=loop.resolves,
        final_openings=replay.openings(),
    )


def _solved(plan: PlanDocument) -> PlanDocument:
    if not plan.solved:
        raise InputError(f"plan for `{plan.task}` is {plan.status!r}: there is nothing to execute")
    return plan


def _numbered(plan: PlanDocument) -> list[Step]:
    return list(enumerate(_solved(plan).steps, start=1))


def _task(program: Program, task: Task | str | None) -> Task:
    if isinstance(task, Task):
        return task
    try:
        return program.task(task)
    except KeyError as exc:
        known = ", ".join(sorted(program.tasks)) or "none"
        raise InputError(f"no task `{task}` in the program (tasks: {known})") from exc


class _Loop:
    """The step loop with optional replanning; fills the per-step reports."""

    def __init__(
        self,
        program: Program,
        task: Task,
        replay: Replay,
        *,
        replan: bool,
        max_replans: int,
        resolve: Resolver | None,
    ) -> None:
        self.resolve = resolve
        self.on_step: Callable[[StepReport], None] | None = None  # told of every step as it ends
        self.on_resolve: Callable[[Resolve], None] | None = None  # told of every re-solve
        self.feed = ProgressFeed(None, lambda: "", lambda: 0.0)  # where the execution is, for a live display
        self.program = program
        self.task = task
        self.replay = replay
        self.replan = replan
        self.max_replans = max_replans
        self.replans = 0
        self.plan_no = 0
        self.solve_time = 0.0
        self.reports: list[StepReport] = []
        self.log: list[str] = []
        self.resolves: list[Resolve] = []
        self.tried: list[PlanDocument] = []  # every plan carried out (or begun), for re-solves to avoid
        self.failed: list[FailedStep] = []  # every step the arm could not carry out, for re-solves to avoid
        self.plan_length = 0
        self.watching = True  # False while carrying on with a plan that could not be replaced
        self.bystanders: dict[str, np.ndarray] = {}  # bodies the plan being carried out leaves still, and where

    def run(self, steps: list[Step]) -> tuple[str, str]:
        """Execute `steps` (and the plans that replace them); return (status, reason).

        Closed loop, a step the arm could not carry out (say, a held tool
        touched a body on its way) is re-solved from the observed scene too:
        the world may no longer be what the plan assumed.
        """
        if self.replan and steps:  # look before the first step too: the world may not be what was planned
            first_index, first = steps[0]
            strays = [d for d in self._deviations(first, first.poses_start) if d.exceeded]
            if strays:
                new_steps = self._replan(_stray(f"before step {first_index}", strays[0]), remaining=steps)
                if isinstance(new_steps, tuple):
                    return new_steps
                steps = new_steps
        while True:
            outcome = self._run_plan(steps)
            if outcome is None:  # every step of the plan was carried out
                self.feed.begin(self.plan_no, 0, self.plan_length, "letting go at the end")
                try:
                    self.replay.let_go("end")
                    self.replay.settle(FINAL_SETTLE, "end")
                except ArmStuck as exc:
                    return "failed", f"letting go at the end: {exc}"
                if all(g.ok for g in self.goal_results()):
                    return "reached", ""
                if not self.replan:
                    return "missed", self._miss_reason()
                remaining: list[Step] = []
                status, why = "missed", f"at the end of plan {self.plan_no}: {self._miss_reason()}"
            elif outcome[0] == "failed" and not self.replan:
                return outcome[0], outcome[1]
            else:
                kind, why, remaining = outcome
                status = "failed" if kind == "failed" else "missed"
            new_steps = self._replan(why, status, remaining)
            if isinstance(new_steps, tuple):
                return new_steps
            steps = new_steps

    def _run_plan(self, steps: list[Step]) -> tuple[str, str, list[Step]] | None:
        """Carry out `steps`; None when all were, else (kind, why, the steps not carried out)."""
        for i, (index, step) in enumerate(steps):
            self.feed.begin(self.plan_no, index, self.plan_length, step.title())
            try:
                self.replay.run_step(index, step)
            except ArmStuck as exc:
                self.failed.append(FailedStep(self.plan_no, index, step, str(exc)))
                self._report(index, step, [])
                return "failed", f"step {index} ({step.title()}): {exc}", []
            deviations = self._deviations(step)
            self._report(index, step, deviations)
            strays = [d for d in deviations if d.exceeded]
            if self.replan and self.watching and strays and i < len(steps) - 1:
                return "stray", _stray(f"after step {index}", strays[0]), steps[i + 1 :]
        return None

    def _report(self, index: int, step: PlanStepRecord, deviations: list[Deviation]) -> None:
        report = StepReport(
            self.plan_no, index, step.title(), self.replay.time, deviations, grip=self.replay.grip_report()
        )
        self.reports.append(report)
        if self.on_step is not None:
            self.on_step(report)

    # ------------------------------------------------------------ comparisons

    def _deviations(
        self, step: PlanStepRecord, planned_poses: Mapping[str, np.ndarray] | None = None
    ) -> list[Deviation]:
        """Real vs planned poses (default: the step's end poses) of the bodies that matter: the goal
        bodies and the step's body; a body on a physical joint also by its joint's coordinate."""
        planned_poses = step.poses_end if planned_poses is None else planned_poses
        real = self.replay.poses()
        openings = self.replay.openings()
        held = self.replay.holding()
        names = [g.body.name for g in self.task.goals]
        if step.body not in names and step.body != held:
            names.append(step.body)
        out = []
        for name in dict.fromkeys(names):
            if name not in planned_poses or name not in real:
                continue
            planned = planned_poses[name]
            joint = self.replay.joint_type(name)
            lim_p, lim_a, lim_j = replan_limits(self.task, name, joint)
            opening = None
            if joint is not None:
                opening = Opening(joint, self.replay.opening_at(name, planned), openings[name], lim_j)
            out.append(
                Deviation(
                    name,
                    planned,
                    real[name],
                    float(np.linalg.norm(real[name][:3, 3] - planned[:3, 3])),
                    rotation_angle(planned, real[name]),
                    lim_p,
                    lim_a,
                    opening,
                )
            )
        return out

    def expect(self, plan: PlanDocument) -> None:
        """Note the bodies `plan` leaves where they are (the ones it never moves), and where that is."""
        self.tried.append(plan)
        self.plan_length = len(plan.steps)
        start = plan.steps[0].poses_start if plan.steps else {}
        self.bystanders = {
            name: np.asarray(pose)
            for name, pose in plan.final.items()
            if name in start and np.allclose(np.asarray(start[name]), np.asarray(pose), atol=1e-6)
        }

    def disturbances(self) -> list[Disturbance]:
        """Bodies the plan leaves still that ended farther from there than the default tolerance.

        The planner promises every body's final pose, not only the goal
        bodies'; a bystander shoved aside breaks that promise even when the
        goals hold. (A tool the plan moves is not a bystander: where it lands
        once let go at the end is not planned.)
        """
        goal_bodies = {g.body.name for g in self.task.goals}
        tol_p, tol_a = Goal.default_tolerance()
        out = []
        for name, real in self.replay.poses().items():
            planned = self.bystanders.get(name)
            if name in goal_bodies or planned is None:
                continue
            position = float(np.linalg.norm(real[:2, 3] - planned[:2, 3]))
            angle = abs(angle_difference(yaw_of(real), yaw_of(planned)))
            if position > tol_p or angle > tol_a:
                out.append(Disturbance(name, position, angle, (tol_p, tol_a)))
        return out

    def goal_results(self) -> list[GoalResult]:
        """Every goal of the task against the bodies' real poses now (a joint goal against its joint's coordinate)."""
        real = self.replay.poses()
        openings = self.replay.openings()
        return [
            check_goal(goal, real[name], self.replay.joint_type(name), openings.get(name), self._points(goal))
            for goal in self.task.goals
            if (name := goal.body.name) in real
        ]

    def _points(self, goal: Goal) -> np.ndarray | None:
        """The body-frame points of a region goal's body (its shape's vertices); None for other goals."""
        scene = self.program.scenes.get(self.task.scene.name)
        placed = next((b for b in scene.bodies if b.name == goal.body.name), None) if scene is not None else None
        body = self.program.bodies.get(placed.type.name) if placed is not None else None
        return shape_vertices(body.shape) if goal.region is not None and body is not None else None

    def _miss_reason(self) -> str:
        return miss_reason(self.goal_results())

    # ------------------------------------------------------------ replanning

    def _note(self, text: str) -> None:
        self.log.append(text)
        if self.reports:
            self.reports[-1].replan = text

    def _replan(
        self, why: str, status: str = "missed", remaining: list[Step] | None = None
    ) -> list[Step] | tuple[str, str]:
        """Put things down, re-solve from the observed scene; the new plan's steps, or (status, reason).

        When no plan is found but the robot held nothing (so nothing of the
        current plan was undone), it carries on with the `remaining` steps of
        the current plan, no longer checking them against it: a plan that
        strays a little may still end within the tolerance, no plan cannot.
        """
        if self.replans >= self.max_replans:
            return status, f"gave up after {self.replans} replan{'s' if self.replans != 1 else ''}: {why}"
        undoes_plan = self.replay.holding() is not None
        self.feed.begin(self.plan_no, 0, self.plan_length, "putting things down to re-solve")
        try:
            self.replay.let_go("replan")
            self.replay.put_down("replan")
            self.replay.settle(0.2, "replan")
        except ArmStuck as exc:
            return "failed", f"{why}; then, putting things down to re-solve: {exc}"
        observed = self.program.with_start_poses(self.task, self.replay.poses())
        self.replans += 1
        self.plan_no += 1
        assert self.resolve is not None  # execute() refuses replan=True without one
        self.feed.phase("re-solving")
        attempts = Attempts(tuple(self.tried), tuple(self.failed), tuple(float(v) for v in self.replay.sim.arm.q))
        started = time.perf_counter()
        plan: PlanDocument | None = None
        try:
            plan = resolve_with_margin(self.resolve, observed, self.task.name, attempts)
            found, reason = plan.status, plan.reason
        except VkgError as exc:
            found, reason = "error", str(exc)
        finally:
            spent = time.perf_counter() - started
            self.solve_time += spent
        solved = plan is not None and plan.solved
        carry_on = not solved and bool(remaining) and not undoes_plan
        record = Resolve(
            self.replans,
            why,
            tuple(f.record() for f in attempts.failed),
            len(attempts.plans),
            found,
            "" if solved else reason,
            tuple(s.title() for s in plan.steps) if plan is not None and solved else (),
            "new plan" if solved else "carry on" if carry_on else "stop",
            spent,
        )
        self.resolves.append(record)
        self._note(record.text())
        if self.on_resolve is not None:
            self.on_resolve(record)
        if plan is None or not plan.solved:
            if carry_on:
                self.plan_no -= 1  # still the same plan
                self.watching = False
                return remaining or []
            summary = reason.splitlines()[0] if reason else ""  # the whole reason is in the report's resolves
            return status, f"replan {self.replans} found no plan ({found}{': ' + summary if summary else ''})"
        self.expect(plan)
        self.watching = True
        return _numbered(plan)


def _stray(when: str, deviation: Deviation) -> str:
    if deviation.opening is not None:
        o = deviation.opening
        off = f"{abs(o.error) * 100:.2f} cm" if o.joint == "prismatic" else f"{np.degrees(abs(o.error)):.2f} deg"
        return f"{when} {deviation.body} is off the plan by {off} on its {o.joint} joint"
    return (
        f"{when} {deviation.body} is off the plan by {deviation.position * 100:.2f} cm, "
        f"{np.degrees(deviation.angle):.2f} deg"
    )


__all__ = ["RESOLVE_MARGIN", "Attempts", "Progress", "Resolver", "execute", "resolve_with_margin"]
