"""The result of `vkgc solve`: a Plan, printed as text, as `vkg-plan/1` JSON, or drawn (`vkgl.plan.picture`).

A plan of depth D has D graphs (G0 included) and D - 1 steps. Step k is the
transition into G_k followed by the motion G_k allows: `poses_start` are the
body poses right after the transition, `poses_end` after the motion, and
`q_start`/`q_end` the arm's joints there. Held tools move freely between steps
(their world edge is free); everything else is continuous from one step to
the next. A REMOVE step has value 0 and moves nothing, except that releasing
a tool puts it down on the table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vkgl.plan.graph import edges
from vkgl.plan.model import Problem, yaw_of

PLAN_FORMAT = "vkg-plan/1"


@dataclass
class PlanStep:
    """One step of a plan (see the module docstring)."""

    op: str
    affordance: str
    body: str
    effector: str
    motion: str
    value: float
    poses_start: dict[str, np.ndarray]
    poses_end: dict[str, np.ndarray]
    q_start: np.ndarray
    q_end: np.ndarray
    hand: list[np.ndarray] = field(default_factory=list)  # hand poses along the step (for pictures)


@dataclass
class Plan:
    """A solved, infeasible or timed-out plan for one task.

    `status` is "solved", "infeasible" or "timeout"; `reason` says why when it
    is not solved. `graphs` holds each graph's edges `(parent, child, type)`.
    """

    task: str
    status: str
    reason: str
    stats: dict[str, Any]
    robot: dict[str, Any]
    graphs: list[list[tuple[str, str, str]]] = field(default_factory=list)
    steps: list[PlanStep] = field(default_factory=list)
    final: dict[str, np.ndarray] = field(default_factory=dict)
    start: dict[str, np.ndarray] = field(default_factory=dict)
    problem: Problem | None = field(default=None, repr=False)
    details: dict[str, Any] = field(default_factory=dict)  # more counters, not part of vkg-plan/1

    @property
    def depth(self) -> int | None:
        """Graphs in the sequence, G0 included (None when not solved)."""
        return len(self.graphs) if self.status == "solved" else None

    # ------------------------------------------------------------ JSON

    def to_json(self) -> dict[str, Any]:
        """The plan in the `vkg-plan/1` format (ARCHITECTURE.md); unsolved plans add a `reason`."""
        out: dict[str, Any] = {
            "format": PLAN_FORMAT,
            "task": self.task,
            "status": self.status,
            "depth": self.depth,
            "stats": dict(self.stats),
            "robot": self.robot,
            "graphs": [{"edges": [list(e) for e in graph]} for graph in self.graphs],
            "steps": [_step_json(s) for s in self.steps],
            "final": _poses_json(self.final),
        }
        if self.status != "solved":
            out["reason"] = self.reason
        return out

    # ------------------------------------------------------------ text

    def text(self) -> str:
        """The graph sequence as in the paper's Figure 2: each graph's edges, and each step with its value."""
        stats = self.stats
        counts = (
            f"{stats['solve_time_s']:.3f} s; {stats['graphs_expanded']} graphs expanded, "
            f"{stats['task_space_checks']} task-space checks, {stats['joint_space_checks']} joint-space checks"
        )
        if self.status != "solved":
            return f"task {self.task}: {self.status} ({counts})\n  {self.reason}"
        lines = [f"task {self.task}: solved, depth {self.depth} ({counts})"]
        for k, graph in enumerate(self.graphs):
            lines.append(f"G{k}: " + ", ".join(f"{a}-{b} {t}" for a, b, t in graph))
            if k < len(self.steps):
                lines.append(f"  step {k + 1}: {_step_title(self.steps[k])}")
        for name, pose in self.final.items():
            if self.start.get(name) is None or np.abs(self.start[name] - pose).max() > 1e-9:
                lines.append(
                    f"final: {name} at ({pose[0, 3]:.3f}, {pose[1, 3]:.3f}, {pose[2, 3]:.3f}) m "
                    f"yaw {math.degrees(yaw_of(pose)):.1f} deg"
                )
        return "\n".join(lines)


def _step_title(step: PlanStep) -> str:
    text = f"{step.op} {step.affordance} on {step.body} with {step.effector}"
    if step.op == "add" and step.motion == "prismatic":
        text += f": slide {step.value * 100:.1f} cm"
    elif step.op == "add" and step.motion == "revolute":
        text += f": turn {math.degrees(step.value):.1f} deg"
    return text


def _poses_json(poses: dict[str, np.ndarray]) -> dict[str, list[list[float]]]:
    return {name: _matrix(pose) for name, pose in poses.items()}


def _matrix(pose: np.ndarray) -> list[list[float]]:
    # rounding to 1e-12 m keeps the JSON identical across runs where only the last bits of a product differ
    return [[float(round(v, 12)) + 0.0 for v in row] for row in np.asarray(pose)]


def _step_json(step: PlanStep) -> dict[str, Any]:
    return {
        "op": step.op,
        "affordance": step.affordance,
        "body": step.body,
        "effector": step.effector,
        "motion": step.motion,
        "value": float(round(step.value, 12)),
        "poses_start": _poses_json(step.poses_start),
        "poses_end": _poses_json(step.poses_end),
        "q_start": [float(round(v, 12)) for v in step.q_start],
        "q_end": [float(round(v, 12)) for v in step.q_end],
    }


def robot_entry(problem: Problem) -> dict[str, Any]:
    """The `robot` entry of a plan: what an external tool needs to recompute FK from the URDF.

    `effector_offset` is the effector frame in the link's frame (the declared
    offset times Rx(180 deg), LANGUAGE.md's effector convention), so that
    FK(q) = base @ link(q) @ effector_offset.
    """
    arm = problem.arm
    return {
        "name": problem.robot_name,
        "urdf": arm.urdf,
        "base": _matrix(arm.base),
        "effector": arm.effector,
        "effector_link": arm.effector_link,
        "effector_offset": _matrix(arm.link_offset),
        "joints": list(arm.joint_names),
    }


def graph_edges(problem: Problem, graphs: list[Any]) -> list[list[tuple[str, str, str]]]:
    """The edges of every graph of a sequence."""
    return [edges(problem, g) for g in graphs]
