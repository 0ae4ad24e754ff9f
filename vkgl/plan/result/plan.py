"""The result of `vkgc solve`: a Plan, printed as text, as a `vkg-plan/8` document, or drawn (`picture`).

A plan of depth D has D graphs (G0 included) and D - 1 steps. Step k is the
transition into G_k followed by the motion G_k allows: `poses_start` are the
body poses right after the transition, `poses_end` after the motion, and
`q_start`/`q_end` the arm's joints there. Held tools move freely between steps
(their world edge is free); everything else is continuous from one step to
the next. A REMOVE step has value 0 and moves nothing, except that releasing
a tool puts it down on the table, and that letting go of a carried body (pick
and place, `vkgl.plan.graphs.carry`) sets it down at its place: the grasp's
step ends holding it where it was picked up, and the REMOVE step's
`poses_start` has it at its place, where its path (lift, transit with the body
in the hand, down onto the place) brings it before the hand lets go.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from vkgl.formats.plan import PlanDocument, PlanRobot, PlanStats, PlanStepRecord, rounded, to_json
from vkgl.plan.graphs.graph import edges
from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.problem import Problem
from vkgl.se3 import yaw_of


@dataclass(frozen=True, eq=False)
class PlanStep(PlanStepRecord):
    """One step of a plan: the `vkg-plan/8` step record, plus the hand's poses along it (for pictures)."""

    hand: list[np.ndarray] = field(default_factory=list)


@dataclass(frozen=True)
class Plan:
    """A solved, infeasible or timed-out plan for one task, with what the planner knows beyond `vkg-plan/8`.

    `status` is "solved", "infeasible" or "timeout"; `reason` says why when it
    is not solved. `graphs` holds each graph's edges `(parent, child, type)`.
    `start` (the bodies at rest), `problem` and `details` (more counters) are
    the planner's: `document()` is what leaves it.
    """

    task: str
    status: str
    reason: str
    stats: dict[str, Any]
    robot: PlanRobot
    graphs: list[list[tuple[str, str, str]]] = field(default_factory=list)
    steps: list[PlanStep] = field(default_factory=list)
    final: dict[str, np.ndarray] = field(default_factory=dict)
    start: dict[str, np.ndarray] = field(default_factory=dict)
    problem: Problem | None = field(default=None, repr=False)
    details: dict[str, Any] = field(default_factory=dict)  # more counters, not part of vkg-plan/8

    @property
    def depth(self) -> int | None:
        """Graphs in the sequence, G0 included (None when not solved)."""
        return len(self.graphs) if self.status == "solved" else None

    # ------------------------------------------------------------ the document

    def document(self) -> PlanDocument:
        """The plan as a `vkg-plan/8` document (`vkgl.formats.plan`), exactly as its JSON reads back.

        Numbers are rounded as the JSON writes them (`formats.plan.rounded`),
        so that carrying out the document in memory and carrying out the file
        `vkgc solve --json` wrote give bit for bit the same result. Built once:
        a Plan never changes.
        """
        return self._document

    @cached_property
    def _document(self) -> PlanDocument:
        return rounded(self._unrounded_document())

    def _unrounded_document(self) -> PlanDocument:
        return PlanDocument(
            task=self.task,
            status=self.status,
            depth=self.depth,
            stats=PlanStats(**self.stats),
            robot=self.robot,
            graphs=tuple(tuple(graph) for graph in self.graphs),
            steps=tuple(self.steps),
            final=dict(self.final),
            reason="" if self.status == "solved" else self.reason,
        )

    def to_json(self) -> dict[str, Any]:
        """The plan in the `vkg-plan/8` format (docs/formats.md); unsolved plans add a `reason`."""
        return to_json(self._unrounded_document())

    # ------------------------------------------------------------ text

    def _repr_png_(self) -> bytes | None:
        """The plan's picture, for notebooks (Jupyter shows it in place of the object); None when not solved."""
        if self.status != "solved":
            return None
        from vkgl.plan.result.picture import plan_image

        return plan_image(self)

    def text(self) -> str:
        """The graph sequence as in the paper's Figure 2: each graph's edges, and each step with its value."""
        stats = self.stats
        counts = (
            f"{stats['solve_time_s']:.3f} s; {_count(stats['graphs_expanded'], 'graph')} expanded, "
            f"{_count(stats['task_space_checks'], 'task-space check')}, "
            f"{_count(stats['joint_space_checks'], 'joint-space check')}"
        )
        if self.status != "solved":
            reason = "\n".join(f"  {line}" for line in self.reason.splitlines())
            return f"task {self.task}: {self.status} ({counts})\n{reason}"
        depth = f"depth {self.depth}: graphs G0 to G{len(self.graphs) - 1}" if self.steps else "depth 1: G0 only"
        lines = [f"task {self.task}: solved in {_count(len(self.steps), 'step')} ({depth}; {counts})"]
        for k, graph in enumerate(self.graphs):
            lines.append(f"G{k}: " + ", ".join(f"{a}-{b} {t}" for a, b, t in graph))
            if k < len(self.steps):
                lines.append(f"  step {k + 1}: {self.steps[k].title()}")
        for name, pose in self.final.items():
            if self.start.get(name) is None or np.abs(self.start[name] - pose).max() > 1e-9:
                lines.append(
                    f"final: {name} at ({pose[0, 3]:.3f}, {pose[1, 3]:.3f}, {pose[2, 3]:.3f}) m "
                    f"yaw {math.degrees(yaw_of(pose)):.1f} deg"
                )
        lines += self.region_lines()
        if self.reason:  # how a solved plan was found, when that is worth saying (cleared first: shortest or not)
            lines.append(self.reason)
        return "\n".join(lines)

    def region_lines(self) -> list[str]:
        """Where each region goal's body ends in its region: `block ends in region tray at (0.600, 0.000) m, its
        footprint 0.0 cm inside the region's nearest edge` (from `final`; nothing for other goals)."""
        if self.problem is None or self.status != "solved":
            return []
        out = []
        for goal in self.problem.goals:
            pose = self.final.get(goal.body)
            if goal.region is None or pose is None:
                continue
            inside = -float(goal.region_excess(pose).max())
            where = "inside" if inside >= -1e-6 else "outside (within the tolerance)"
            out.append(
                f"{goal.body} ends in {goal.region_words} at ({pose[0, 3]:.3f}, {pose[1, 3]:.3f}) m, its footprint "
                f"{abs(inside) * 100:.1f} cm {where} the region's nearest edge"
            )
        return out


def _count(n: int, noun: str) -> str:
    """`1 graph`, `3 graphs`."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def robot_entry(problem: Problem) -> PlanRobot:
    """The `robot` entry of a plan: what an external tool needs to recompute FK from the URDF.

    `effector_offset` is the effector frame in the link's frame (the declared
    offset times Rx(180 deg), the effector frame convention of docs/language.md), so that
    FK(q) = base @ link(q) @ effector_offset.
    """
    arm = problem.arm
    return PlanRobot(
        name=problem.robot_name,
        urdf=arm.urdf,
        base=np.asarray(arm.base, dtype=float),
        effector=arm.effector,
        effector_link=arm.effector_link,
        effector_offset=np.asarray(arm.link_offset, dtype=float),
        joints=tuple(arm.joint_names),
    )


def graph_edges(problem: Problem, graphs: list[Any]) -> list[list[tuple[str, str, str]]]:
    """The edges of every graph of a sequence."""
    return [edges(problem, g) for g in graphs]


def plan_step(problem: Problem, action: Any, trace: ModeTrace, q_start: np.ndarray, q_end: np.ndarray) -> PlanStep:
    """The plan step of `action` (the transition into the mode of `trace`), the arm at `q_start`/`q_end`."""
    e = action.engagement
    aff = problem.affordance(e.body, e.affordance)
    value = trace.values.get(e, 0.0) if action.op == "add" else 0.0
    poses_end = dict(trace.end)
    if action.op == "add" and e in trace.carried:
        # a grasp of a body that is carried: the step ends holding it where it was picked up; the carry and the
        # place are the next step's (its path carries it there, then it lets go), as execution sees it
        poses_end[e.body] = trace.start[e.body]
        q_end = q_start
    return PlanStep(
        op=action.op,
        affordance=f"{problem.bodies[e.body].type.name}.{e.affordance}",
        body=e.body,
        effector=e.effector,
        motion=aff.motion.type,
        value=float(max(0.0, value)),
        poses_start=dict(trace.start),
        poses_end=poses_end,
        q_start=np.asarray(q_start, dtype=float),
        q_end=np.asarray(q_end, dtype=float),
        hand=list(trace.hand),
    )
