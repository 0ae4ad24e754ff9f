"""The `vkg-plan/8` document in memory: its constants and its frozen dataclasses (docs/formats.md)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

PLAN_FORMAT = "vkg-plan/8"
OLDER_READABLE = "vkg-plan/2"
"""Still read: the same without `steps[k].contact` (its steps get `contact` None)."""
SAME_LAYOUT = ("vkg-plan/3", "vkg-plan/4", "vkg-plan/5", "vkg-plan/6", "vkg-plan/7")
"""Still read exactly as the current version: the same fields, written before family members and pick and place
(/3), arc members and straight slides off the centre (/4), slides by a tool rolled over the body (/5), arc members
by a tool rolled (/6) or straight slides off the centre by a tool rolled (/7) had their meaning in the contract."""
STATUSES = ("solved", "infeasible", "timeout")
OPS = ("add", "remove")
MOTIONS = ("fixed", "prismatic", "revolute", "free")
"""The constraint types: of an affordance's motion, and of a graph edge."""

Poses = Mapping[str, np.ndarray]
Edge = tuple[str, str, str]
"""A graph edge `(parent, child, type)`."""

_TOP_KEYS = ("format", "task", "status", "depth", "stats", "robot", "graphs", "steps", "final")
_STATS_KEYS = ("solve_time_s", "graphs_expanded", "task_space_checks", "joint_space_checks")
_ROBOT_KEYS = ("name", "urdf", "base", "effector", "effector_link", "effector_offset", "joints")
_STEP_KEYS = (
    "op",
    "affordance",
    "body",
    "effector",
    "motion",
    "value",
    "poses_start",
    "poses_end",
    "q_start",
    "q_end",
    "path",
    "contact",
)
_SEGMENT_KEYS = ("phase", "times", "joints")
PHASES = ("lift", "retreat", "transit", "approach")
"""The kinds of planned arm motion before a step's action (`ArmSegment.phase`)."""


@dataclass(frozen=True, eq=False)
class PlanStats:
    """What the search did: wall time (s) and how many graphs and checks it took."""

    solve_time_s: float
    graphs_expanded: int
    task_space_checks: int
    joint_space_checks: int


@dataclass(frozen=True, eq=False)
class PlanRobot:
    """What an outside tool needs to recompute the arm's FK from its URDF.

    FK(q) = base @ link(q) @ effector_offset, with `q` in the order of `joints`.
    """

    name: str
    urdf: str
    base: np.ndarray
    effector: str
    effector_link: str
    effector_offset: np.ndarray
    joints: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class ArmSegment:
    """One planned arm motion: `joints` (k x n waypoints, joined by straight joint-space segments) reached at
    `times` (k seconds from the segment's start: 0 first, increasing).

    `phase`: "lift" (straight up after a grasp or a release), "retreat"
    (straight back out of a contact), "transit" (collision-free through free
    space, planned with OMPL) or "approach" (straight into a contact, the
    last centimetres).
    """

    phase: str
    times: np.ndarray
    joints: np.ndarray

    @property
    def duration(self) -> float:
        """How long the segment lasts (s)."""
        return float(self.times[-1])


@dataclass(frozen=True, eq=False)
class PlanStepRecord:
    """One step of a plan: the transition into the next graph and the motion that graph allows.

    `poses_start`/`poses_end` are the bodies' world poses right after the
    transition and after the motion; `q_start`/`q_end` the arm's joints there;
    `value` is the motion's amount (m or rad, >= 0; 0 for a REMOVE); `path`
    the arm's planned motions before the step's action (vkg-plan/2): from
    where the previous step left the arm to `q_start`; `contact` (vkg-plan/8;
    k x n, k >= 2, or None) the arm's joints at k evenly spaced fractions of a
    contact's motion, `q_start` first and `q_end` last: the one arm
    configuration the planner checked carries the whole motion, which
    execution follows. None for removals and grasps, and in older plans.
    """

    op: str
    affordance: str
    body: str
    effector: str
    motion: str
    value: float
    poses_start: Poses
    poses_end: Poses
    q_start: np.ndarray
    q_end: np.ndarray
    path: tuple[ArmSegment, ...] = ()
    contact: np.ndarray | None = None

    def title(self) -> str:
        """The step in words: `add Block.push_center_px on block with arm.fingertip: slide 15.0 cm`."""
        text = f"{self.op} {self.affordance} on {self.body} with {self.effector}"
        if self.op == "remove" and any(segment.phase == "transit" for segment in self.path):
            # a release whose path carries the body first: set down elsewhere (a carried body's place, or a tool
            # put back where it was picked up), not where the hand held it
            where = self.poses_start.get(self.body)
            return text if where is None else f"{text}: set down at ({where[0, 3]:.3f}, {where[1, 3]:.3f}) m"
        if self.op != "add" or self.motion not in ("prismatic", "revolute"):
            return text
        amount = (
            f"slide {self.value * 100:.1f} cm"
            if self.motion == "prismatic"
            else f"turn {math.degrees(self.value):.1f} deg"
        )
        if amount.endswith(" 0.0 cm") or amount.endswith(" 0.0 deg"):
            # A contact the planner keeps although it moves nothing: a tool set down against the body (parked).
            return f"{text}: touch only, moves nothing"
        return f"{text}: {amount}"


@dataclass(frozen=True, eq=False)
class PlanDocument:
    """A whole `vkg-plan/8` plan.

    `status` is "solved", "infeasible" or "timeout"; `depth` is the number of
    graphs (G0 included) of a solved plan, None otherwise; `graphs` holds each
    graph's edges; `reason` says why an unsolved plan is not solved (it is
    written only for those).
    """

    task: str
    status: str
    depth: int | None
    stats: PlanStats
    robot: PlanRobot
    graphs: tuple[tuple[Edge, ...], ...] = ()
    steps: tuple[PlanStepRecord, ...] = ()
    final: Poses = field(default_factory=dict)
    reason: str = ""

    @property
    def solved(self) -> bool:
        """True when the plan was found (status "solved")."""
        return self.status == "solved"
