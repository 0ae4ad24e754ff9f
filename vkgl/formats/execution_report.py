"""What an execution in DART did: per step, real vs planned poses; at the end, the error to the goal.

`ExecutionReport.text()` is what `vkgc solve --execute` prints;
`ExecutionReport.to_json()` is the `vkg-execution/5` record of the same, and
`write(path, report)` puts it in a file. A body on a physical joint is judged
by its joint's coordinate (`Opening`): how far its slide or hinge is open.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.atomic import write_text
from vkgl.se3 import yaw_of

FORMAT = "vkg-execution/5"
"""Version 2 added the `disturbed` list and the status "disturbed" (a bystander moved); version 3 adds the
`resolves` list (each re-solve: why, what it excluded, what it found); version 4 adds the joint coordinates of
bodies on physical joints: `opening` of goals and of step deviations, and `final_openings`; version 5 adds each
step's `grip` (the held tool's slip in the hand and the load on the grip; docs/execution.md)."""


def _planar(pose: np.ndarray) -> str:
    x, y = (_unsigned_zero(pose[k, 3], ".3f") for k in (0, 1))
    return f"({x}, {y}) m yaw {_unsigned_zero(np.degrees(yaw_of(pose)), '6.1f')} deg"


def joint_value_text(joint: str, value: float) -> str:
    """A joint coordinate in words: `18.7 cm` for a prismatic joint, `45.0 deg` for a revolute one."""
    if joint == "prismatic":
        return f"{_unsigned_zero(value * 100, '.1f')} cm"
    return f"{_unsigned_zero(np.degrees(value), '.1f')} deg"


def _unsigned_zero(value: float, spec: str) -> str:
    """`value` formatted by `spec`, a value that rounds to zero without its sign: a shut door reads `open 0.0
    deg`, not `open -0.0 deg` (the solver's last bits are not a direction)."""
    text = format(float(value), spec)
    return format(0.0, spec) if float(text) == 0.0 else text


def _joint_error_text(joint: str, value: float) -> str:
    return f"{abs(value) * 100:.2f} cm" if joint == "prismatic" else f"{np.degrees(abs(value)):.2f} deg"


@dataclass(frozen=True)
class Opening:
    """The coordinate of a body's physical joint (m for a prismatic joint, rad for a revolute one), 0 where the
    scene places the body: `real` in DART against `target` (the plan's, or a joint goal's), within `limit` (the
    goal's tolerance, or the closed loop's replanning limit)."""

    joint: str  # "prismatic" or "revolute"
    target: float
    real: float
    limit: float

    @property
    def error(self) -> float:
        """real - target (m or rad): positive when the joint is open further than wanted."""
        return self.real - self.target

    @property
    def exceeded(self) -> bool:
        """True when the real coordinate is farther than `limit` from the target."""
        return abs(self.error) > self.limit

    def to_json(self, target: str) -> dict[str, Any]:
        """As plain data; `target` names the target's key (`goal` or `planned`)."""
        return {"joint": self.joint, target: self.target, "real": self.real, "error": self.error}


@dataclass
class Frames:
    """What the simulation looked like, sampled at a fixed period (for the animation; not part of the JSON)."""

    bodies: list[str]
    t: list[float] = field(default_factory=list)
    real: list[np.ndarray] = field(default_factory=list)  # (n_bodies, 4, 4) per frame
    planned: list[np.ndarray] = field(default_factory=list)  # (n_bodies, 4, 4) per frame
    effector: list[np.ndarray] = field(default_factory=list)  # (4, 4) per frame
    arm: list[np.ndarray] = field(default_factory=list)  # (n_links, 3) link origins per frame
    label: list[str] = field(default_factory=list)  # "step 2 motion" etc.


@dataclass
class Deviation:
    """How far a body really is from where the plan wanted it: distance (m) and rotation angle (rad)."""

    body: str
    planned: np.ndarray
    real: np.ndarray
    position: float
    angle: float
    limit_position: float
    limit_angle: float
    opening: Opening | None = None  # a body on a physical joint: its coordinate, planned and real

    @property
    def exceeded(self) -> bool:
        """True when the deviation is beyond the replanning limits (for a body on a joint: its coordinate's)."""
        if self.opening is not None:
            return self.opening.exceeded
        return self.position > self.limit_position or self.angle > self.limit_angle

    def limit_text(self) -> str:
        """What an exceeded deviation went past: the replanning limit, half the goal's tolerance, in numbers."""
        if self.opening is not None:
            limit = _joint_error_text(self.opening.joint, self.opening.limit)
        else:
            limit = f"{self.limit_position * 100:.2f} cm, {np.degrees(self.limit_angle):.2f} deg"
        return f"replan limit {limit} (half the goal's tolerance)"

    def text(self) -> str:
        """One line: where the body was planned and where it is, and how far apart (the coordinate for a joint)."""
        if self.opening is not None:
            o = self.opening
            return (
                f"{self.body:<8} planned open {joint_value_text(o.joint, o.target)}   real open "
                f"{joint_value_text(o.joint, o.real)}   off {_joint_error_text(o.joint, o.error)}"
            )
        return (
            f"{self.body:<8} planned {_planar(self.planned)}   real {_planar(self.real)}"
            f"   off {self.position * 100:.2f} cm, {np.degrees(self.angle):.2f} deg"
        )


@dataclass
class GripReport:
    """The grip on the tool in the hand during one step: what it carries, the most of that the load used, and how
    far the tool slipped in the hand (from where it was grasped); `broke` says why the grip gave way, if it did."""

    tool: str
    force: float  # N each finger presses
    friction: float  # the pads' friction on the tool
    max_force: float  # N the grip carries in the pads' plane (2 mu F)
    max_torque: float  # N m it carries about the pads' normal
    peak_load: float = 0.0  # the largest fraction of that the load used (1 = all of it)
    slip: float = 0.0  # m, the largest
    slip_angle: float = 0.0  # rad, the largest
    broke: str = ""

    def note_load(self, usage: float) -> None:
        """Keep the largest fraction of the grip a load used."""
        self.peak_load = max(self.peak_load, usage)

    def note_slip(self, slip: float, angle: float) -> None:
        """Keep the largest slip (m) and turn (rad) of the tool in the hand."""
        self.slip = max(self.slip, slip)
        self.slip_angle = max(self.slip_angle, angle)

    def text(self) -> str:
        """One line: `grip on stick: slip 0.00 mm, 0.00 deg; load up to 12 % of 70.0 N, 0.47 N m (2 x 70 N, ...)`."""
        head = (
            f"grip on {self.tool}: slip {self.slip * 1000:.2f} mm, {np.degrees(self.slip_angle):.2f} deg; load up to "
            f"{self.peak_load * 100:.0f} % of {self.max_force:.1f} N, {self.max_torque:.2f} N m "
            f"(2 x {self.force:.0f} N, mu {self.friction:.2f})"
        )
        return f"{head}; BROKE: {self.broke}" if self.broke else head

    def to_json(self) -> dict[str, Any]:
        """As plain data (a step's `grip` in `vkg-execution/5`)."""
        return {
            "tool": self.tool,
            "force_n": self.force,
            "friction": self.friction,
            "max_force_n": self.max_force,
            "max_torque_nm": self.max_torque,
            "peak_load": self.peak_load,
            "slip_m": self.slip,
            "slip_angle_rad": self.slip_angle,
            "broke": self.broke,
        }


@dataclass
class StepReport:
    """One executed plan step: which plan it came from and where the bodies ended."""

    plan: int  # 0 = the plan given, 1.. = replans
    index: int
    title: str
    end_time: float
    deviations: list[Deviation] = field(default_factory=list)
    replan: str = ""  # set when the loop re-solved after this step: why, and what came of it
    grip: GripReport | None = None  # the tool in the hand during the step, if any


@dataclass
class GoalResult:
    """One goal of the task, checked against the real final pose."""

    body: str
    text: str  # the goal as written, e.g. "block at (0.600, 0.000) m yaw 0.0 deg within 1.0 cm, 3.0 deg"
    position_error: float | None  # m, None when the goal does not constrain position
    yaw_error: float | None  # rad, None when the goal does not constrain heading
    tol_position: float
    tol_yaw: float
    opening: Opening | None = None  # a joint goal: the joint's real coordinate against the goal's, within its tolerance

    @property
    def ok(self) -> bool:
        """True when the body is within the goal's tolerance."""
        pos_ok = self.position_error is None or self.position_error <= self.tol_position
        yaw_ok = self.yaw_error is None or abs(self.yaw_error) <= self.tol_yaw
        return pos_ok and yaw_ok and (self.opening is None or not self.opening.exceeded)

    def errors(self) -> str:
        """How far off the goal the body is: `off 0.04 cm, 0.03 deg`, or for a joint goal `drawer is open 18.7 cm,
        off 1.30 cm`."""
        parts = []
        if self.position_error is not None:
            parts.append(f"{self.position_error * 100:.2f} cm")
        if self.yaw_error is not None:
            parts.append(f"{np.degrees(abs(self.yaw_error)):.2f} deg")
        off = f"off {', '.join(parts)}" if parts else ""
        if self.opening is None:
            return off or "off"
        o = self.opening
        opened = f"{self.body} is open {joint_value_text(o.joint, o.real)}, off {_joint_error_text(o.joint, o.error)}"
        return f"{opened}; {off}" if off else opened

    def miss(self) -> str:
        """Why the goal is not met, with the numbers (empty when it is)."""
        errors = []
        if self.position_error is not None and self.position_error > self.tol_position:
            errors.append(f"{self.position_error * 100:.2f} cm (tolerance {self.tol_position * 100:.2f} cm)")
        if self.yaw_error is not None and abs(self.yaw_error) > self.tol_yaw:
            errors.append(f"{np.degrees(abs(self.yaw_error)):.2f} deg (tolerance {np.degrees(self.tol_yaw):.2f} deg)")
        out = [f"{self.body} is off its goal by {' and '.join(errors)}"] if errors else []
        o = self.opening
        if o is not None and o.exceeded:
            out.append(
                f"{self.body} is open {joint_value_text(o.joint, o.real)}, goal {joint_value_text(o.joint, o.target)} "
                f"within {_joint_error_text(o.joint, o.limit)}"
            )
        return "; ".join(out)


@dataclass(frozen=True)
class Disturbance:
    """A body the plan leaves where it is (or puts somewhere) that ended elsewhere: how far, and the tolerance."""

    body: str
    position: float  # m from where the plan leaves it
    angle: float  # rad
    tolerance: tuple[float, float]  # (m, rad) it was allowed

    def text(self) -> str:
        """One line: which body, how far, against which tolerance."""
        return (
            f"{self.body} ended {self.position * 100:.1f} cm, {np.degrees(self.angle):.1f} deg from where the plan "
            f"leaves it (tolerance {self.tolerance[0] * 100:.1f} cm, {np.degrees(self.tolerance[1]):.1f} deg)"
        )


@dataclass(frozen=True)
class ExcludedStep:
    """A step that failed in execution, which a re-solve excluded: which plan, which step, and why it failed."""

    plan: int  # 0 = the plan given, 1.. = replans
    index: int  # the step's number in its plan (from 1)
    title: str
    why: str

    def text(self) -> str:
        """`step 1 of plan 0 `add Block.push_center_px on block with arm.fingertip: slide 15.0 cm``."""
        return f"step {self.index} of plan {self.plan} `{self.title}`"


@dataclass(frozen=True)
class Resolve:
    """One re-solve of the closed loop: what triggered it, what it had to avoid, and what came of it.

    `excluded` are the steps that had failed so far (the new plan repeats
    none of them where it failed), `tried` the number of plans carried out so
    far (the new plan is none of them); `found` is the planner's status
    ("solved", "infeasible", "timeout", or "error"), `reason` why it is not
    solved, `new_plan` the titles of the new plan's steps; `outcome` says what
    the loop did: "new plan", "carry on" (no plan found, the current plan
    goes on) or "stop" (no plan found, nothing to go on with).
    """

    number: int
    after: str
    excluded: tuple[ExcludedStep, ...]
    tried: int
    found: str
    reason: str
    new_plan: tuple[str, ...]
    outcome: str
    solve_time: float

    def text(self) -> str:
        """One line for the log: why, what was excluded, and the new plan (or why there is none)."""
        tried = f"the {self.tried} plan{'s' if self.tried != 1 else ''} tried"
        failed = ", ".join(e.text() for e in self.excluded)
        what = f"the failed {failed} and {tried}" if failed else tried
        head = f"{self.after}; re-solve {self.number} excludes {what}"
        if self.outcome == "new plan":
            steps = ", ".join(f"`{title}`" for title in self.new_plan) or "nothing to do"
            return f"{head}; re-solved from the observed scene: new plan of {_count(len(self.new_plan))}: {steps}"
        summary = self.reason.splitlines()[0] if self.reason else ""  # a no-plan reason's summary line
        found = f"{self.found}: {summary}" if summary else self.found
        tail = "; carrying on with the current plan" if self.outcome == "carry on" else ""
        return f"{head}; re-solving found no plan ({found}){tail}"

    def to_json(self) -> dict[str, Any]:
        """The re-solve as plain data (an entry of `resolves` in `vkg-execution/3` and later)."""
        return {
            "number": self.number,
            "after": self.after,
            "excluded": [{"plan": e.plan, "step": e.index, "title": e.title, "why": e.why} for e in self.excluded],
            "tried_plans": self.tried,
            "found": self.found,
            "reason": self.reason,
            "new_plan": list(self.new_plan),
            "outcome": self.outcome,
            "solve_time_s": round(self.solve_time, 3),
        }


def _count(n: int) -> str:
    return f"{n} step{'s' if n != 1 else ''}"


@dataclass
class ExecutionReport:
    """The outcome of executing a plan in DART.

    `status`: "reached" (every goal within tolerance at the end, and every
    other body where the plan leaves it), "disturbed" (every goal met, but a
    body the plan does not aim at was moved beyond the tolerance: `disturbed`
    says which and how far), "missed" (the plan was carried out, or replanning
    gave up, and a goal is not met) or "failed" (a step could not be carried
    out, e.g. the arm could not reach a pose); `reason` says why when not
    reached.
    """

    task: str
    status: str
    reason: str
    steps: list[StepReport]
    goals: list[GoalResult]
    replans: int
    replan_log: list[str]
    final: dict[str, np.ndarray]
    sim_time: float
    wall_time: float
    solve_time: float  # wall time spent re-solving (part of wall_time)
    frames: Frames | None = None
    bodies: dict[str, Any] = field(default_factory=dict)  # body name -> Body IR (for drawing)
    table: Any = None  # the scene's Table IR (for drawing)
    closed_loop: bool = False
    disturbed: list[Disturbance] = field(default_factory=list)
    resolves: list[Resolve] = field(default_factory=list)  # every re-solve, in order (`replan_log` in words)
    final_openings: dict[str, float] = field(default_factory=dict)  # bodies on physical joints: m or rad at the end

    @property
    def reached(self) -> bool:
        """True when the goal was reached."""
        return self.status == "reached"

    def text(self) -> str:
        """A human-readable account: steps, deviations, goal errors, status line."""
        mode = "closed loop (replan)" if self.closed_loop else "open loop"
        lines = [f"execution of {self.task} in DART, {mode}:"]
        attached = {step.replan for step in self.steps}
        lines += [f"  replan: {entry}" for entry in self.replan_log if entry not in attached]  # before any step
        for step in self.steps:
            origin = "" if step.plan == 0 else f" [replan {step.plan}]"
            lines.append(f"  step {step.index}{origin}: {step.title}  (t = {step.end_time:.2f} s)")
            for dev in step.deviations:
                flag = f"  > {dev.limit_text()}" if dev.exceeded else ""
                lines.append(f"      {dev.text()}{flag}")
            if step.grip is not None:
                lines.append(f"      {step.grip.text()}")
            if step.replan:
                lines.append(f"    replan: {step.replan}")
        for goal in self.goals:
            lines.append(f"  goal {goal.text}: {goal.errors()}  {'ok' if goal.ok else 'NOT MET'}")
        lines += [f"  DISTURBED: {d.text()}" for d in self.disturbed]
        summary = (
            f"{self.status}: {self.sim_time:.1f} s simulated in {self.wall_time:.1f} s wall"
            f" ({self.replans} replan{'s' if self.replans != 1 else ''})"
        )
        lines.append(summary if not self.reason else f"{summary}: {self.reason}")
        return "\n".join(lines)

    def to_json(self) -> dict[str, Any]:
        """The report as plain data (`vkg-execution/5`)."""
        return {
            "format": FORMAT,
            "task": self.task,
            "status": self.status,
            "reason": self.reason,
            "closed_loop": self.closed_loop,
            "replans": self.replans,
            "replan_log": list(self.replan_log),
            "resolves": [r.to_json() for r in self.resolves],
            "sim_time_s": round(self.sim_time, 6),
            "wall_time_s": round(self.wall_time, 3),
            "solve_time_s": round(self.solve_time, 3),
            "steps": [
                {
                    "plan": s.plan,
                    "index": s.index,
                    "step": s.title,
                    "end_time_s": round(s.end_time, 6),
                    "bodies": {
                        d.body: {
                            "planned": d.planned.tolist(),
                            "real": d.real.tolist(),
                            "position_error_m": d.position,
                            "angle_error_rad": d.angle,
                            "opening": d.opening.to_json("planned") if d.opening is not None else None,
                        }
                        for d in s.deviations
                    },
                    "grip": s.grip.to_json() if s.grip is not None else None,
                }
                for s in self.steps
            ],
            "goals": [
                {
                    "goal": g.text,
                    "body": g.body,
                    "position_error_m": g.position_error,
                    "yaw_error_rad": g.yaw_error,
                    "opening": (
                        {**g.opening.to_json("goal"), "tolerance": g.opening.limit} if g.opening is not None else None
                    ),
                    "ok": g.ok,
                }
                for g in self.goals
            ],
            "disturbed": [
                {
                    "body": d.body,
                    "position_error_m": d.position,
                    "angle_error_rad": d.angle,
                    "tolerance": [d.tolerance[0], d.tolerance[1]],
                }
                for d in self.disturbed
            ],
            "final": {name: pose.tolist() for name, pose in self.final.items()},
            "final_openings": dict(self.final_openings),
        }


def write(path: str | Path, report: ExecutionReport) -> None:
    """Write the report as `vkg-execution/5` JSON to `path`, atomically (temporary file, then renamed)."""
    write_text(path, json.dumps(report.to_json(), indent=1) + "\n")
