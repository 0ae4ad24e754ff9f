"""The `vkg-plan/3` document: the one definition of the plan format, its only reader and writer.

docs/formats.md is the contract. In memory a plan document is a tree of frozen
dataclasses (`PlanDocument` > `PlanRobot`, `PlanStats`, `PlanStepRecord`) with
poses as 4x4 numpy arrays; `to_json` gives the plain data that `vkgc solve
--json` writes, `from_json` checks every field of such data and builds the
document, raising `PlanFormatError` with the JSON path of the first bad field
(`steps[2].poses_start.block: expected a 4x4 matrix of finite numbers`).

    from vkgl.formats import plan as plan_format
    doc = plan_format.read("a_push.json")
    plan_format.write("copy.json", doc)

Numbers are written rounded to 1e-12 (poses without negative zeros), so that
runs whose products differ only in their last bits give the same file. The
documents compare by identity; compare `to_json(a) == to_json(b)` for content.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.errors import InputError, PlanFormatError
from vkgl.formats.atomic import write_text
from vkgl.formats.json_checks import (
    expect_choice,
    expect_dotted,
    expect_joints,
    expect_list,
    expect_name,
    expect_number,
    expect_object,
    expect_pose,
    expect_poses,
    expect_text,
    frozen,
    is_int,
    show,
)

PLAN_FORMAT = "vkg-plan/3"
OLDER_READABLE = "vkg-plan/2"
"""Still read: the same without `steps[k].contact` (its steps get `contact` None)."""
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


# ---------------------------------------------------------------- the document


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
    where the previous step left the arm to `q_start`; `contact` (vkg-plan/3;
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
        if self.op == "add" and self.motion == "prismatic":
            text += f": slide {self.value * 100:.1f} cm"
        elif self.op == "add" and self.motion == "revolute":
            text += f": turn {math.degrees(self.value):.1f} deg"
        return text


@dataclass(frozen=True, eq=False)
class PlanDocument:
    """A whole `vkg-plan/3` plan.

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


# ---------------------------------------------------------------- writing


def to_json(doc: PlanDocument) -> dict[str, Any]:
    """The document as plain JSON data, keys in the contract's order; an unsolved plan adds `reason`."""
    out: dict[str, Any] = {
        "format": PLAN_FORMAT,
        "task": doc.task,
        "status": doc.status,
        "depth": doc.depth,
        "stats": {key: getattr(doc.stats, key) for key in _STATS_KEYS},
        "robot": _robot_json(doc.robot),
        "graphs": [{"edges": [list(edge) for edge in graph]} for graph in doc.graphs],
        "steps": [_step_json(step) for step in doc.steps],
        "final": _poses_json(doc.final),
    }
    if doc.status != "solved":
        out["reason"] = doc.reason
    return out


def rounded(doc: PlanDocument) -> PlanDocument:
    """`doc` with every number as its JSON writes it (rounded to 1e-12, poses without negative zeros) and its
    arrays read-only: what `from_json(to_json(doc))` reads back, built without writing or checking JSON. A plan
    carried out from memory and one read back from its file then give bit for bit the same result."""
    return PlanDocument(
        task=doc.task,
        status=doc.status,
        depth=doc.depth,
        stats=PlanStats(**{key: getattr(doc.stats, key) for key in _STATS_KEYS}),
        robot=replace(
            doc.robot,
            base=_rounded_matrix(doc.robot.base),
            effector_offset=_rounded_matrix(doc.robot.effector_offset),
            joints=tuple(doc.robot.joints),
        ),
        graphs=tuple(tuple((a, b, c) for a, b, c in graph) for graph in doc.graphs),
        steps=tuple(_rounded_step(step) for step in doc.steps),
        final=_rounded_poses(doc.final),
        reason="" if doc.status == "solved" else doc.reason,
    )


def _rounded_matrix(pose: np.ndarray) -> np.ndarray:
    return frozen(np.array(matrix_json(pose), dtype=float))


def _rounded_poses(poses: Poses) -> dict[str, np.ndarray]:
    return {name: _rounded_matrix(pose) for name, pose in poses.items()}


def _rounded_step(step: PlanStepRecord) -> PlanStepRecord:
    data = _step_json(step)  # the numbers exactly as written; arrays made of them directly

    def array(values: Any) -> np.ndarray:
        return frozen(np.array(values, dtype=float))

    return PlanStepRecord(  # a record, not the planner's subclass with its extra fields
        op=step.op,
        affordance=step.affordance,
        body=step.body,
        effector=step.effector,
        motion=step.motion,
        value=data["value"],
        poses_start=_rounded_poses(step.poses_start),
        poses_end=_rounded_poses(step.poses_end),
        q_start=array(data["q_start"]),
        q_end=array(data["q_end"]),
        path=tuple(ArmSegment(s["phase"], array(s["times"]), array(s["joints"])) for s in data["path"]),
        contact=array(data["contact"]) if data["contact"] else None,
    )


def dumps(doc: PlanDocument) -> str:
    """The text of a `vkg-plan/3` file (what `write` puts in it)."""
    return json.dumps(to_json(doc), indent=1) + "\n"


def write(path: str | Path, doc: PlanDocument) -> None:
    """Write `doc` to `path` atomically: a temporary file in the same folder, then renamed over `path`."""
    write_text(path, dumps(doc))


def matrix_json(pose: np.ndarray) -> list[list[float]]:
    """A 4x4 matrix as JSON rows, rounded to 1e-12 and without negative zeros."""
    return [[float(round(v, 12)) + 0.0 for v in row] for row in np.asarray(pose, dtype=float)]


def _poses_json(poses: Poses) -> dict[str, list[list[float]]]:
    return {name: matrix_json(pose) for name, pose in poses.items()}


def _robot_json(robot: PlanRobot) -> dict[str, Any]:
    return {
        "name": robot.name,
        "urdf": robot.urdf,
        "base": matrix_json(robot.base),
        "effector": robot.effector,
        "effector_link": robot.effector_link,
        "effector_offset": matrix_json(robot.effector_offset),
        "joints": list(robot.joints),
    }


def _step_json(step: PlanStepRecord) -> dict[str, Any]:
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
        "path": [_segment_json(segment) for segment in step.path],
        "contact": [] if step.contact is None else _joints_json(step.contact),
    }


def _joints_json(joints: np.ndarray) -> list[list[float]]:
    return [[float(round(v, 12)) + 0.0 for v in q] for q in joints]


def _segment_json(segment: ArmSegment) -> dict[str, Any]:
    return {
        "phase": segment.phase,
        "times": [float(round(t, 12)) + 0.0 for t in segment.times],
        "joints": _joints_json(segment.joints),
    }


# ---------------------------------------------------------------- reading


def read(path: str | Path) -> PlanDocument:
    """Read and check a `vkg-plan/3` (or `vkg-plan/2`) file. InputError if it cannot be read or is not JSON;
    PlanFormatError (an InputError) naming the file and the bad field's path if it is not a valid plan."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the plan {path}: {exc}") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not JSON ({exc})") from None
    try:
        return from_json(data)
    except PlanFormatError as exc:
        raise PlanFormatError(exc.path, f"{exc.problem} (in {path})") from None


def from_json(data: Any) -> PlanDocument:
    """Check `data` (parsed JSON) field by field and build the document.

    Raises PlanFormatError naming the path of the first bad field: a wrong
    `format`, a missing or unknown key, a null or empty name, a number that is
    not finite, a pose that is not a 4x4 homogeneous transform, joints that do
    not match `robot.joints`, or a `depth` that disagrees with the graphs.
    """
    obj = expect_object(data, "", _TOP_KEYS, optional=("reason",))
    if obj["format"] == "vkg-plan/1":
        raise PlanFormatError(
            "format",
            f"found 'vkg-plan/1', expected {PLAN_FORMAT!r}: the plan was written by an older vkgc, without the "
            "arm's paths between contacts; solve the task again",
        )
    if obj["format"] not in (PLAN_FORMAT, OLDER_READABLE):
        raise PlanFormatError("format", f"expected {PLAN_FORMAT!r}, found {obj['format']!r}: not a {PLAN_FORMAT} plan")
    task = expect_name(obj["task"], "task")
    status = expect_choice(obj["status"], "status", STATUSES)
    robot = _robot(obj["robot"], "robot")
    stats = _stats(obj["stats"], "stats")
    graphs = tuple(_graph(g, f"graphs[{k}]") for k, g in enumerate(expect_list(obj["graphs"], "graphs")))
    older = obj["format"] == OLDER_READABLE
    steps = tuple(
        _step(s, f"steps[{k}]", len(robot.joints), older) for k, s in enumerate(expect_list(obj["steps"], "steps"))
    )
    final = expect_poses(obj["final"], "final")
    depth = obj["depth"]
    if status == "solved":
        if "reason" in obj:
            raise PlanFormatError("reason", "only a plan that is not solved has a reason")
        if not is_int(depth) or depth < 1:
            raise PlanFormatError("depth", f"expected the number of graphs (1 or more), found {depth!r}")
        if depth != len(graphs):
            raise PlanFormatError("depth", f"is {depth} but the plan has {len(graphs)} graphs")
        if len(steps) != len(graphs) - 1:
            raise PlanFormatError(
                "steps", f"a plan of {len(graphs)} graphs has {len(graphs) - 1} steps, not {len(steps)}"
            )
        reason = ""
    else:
        if depth is not None:
            raise PlanFormatError("depth", f"expected null for a plan that is {status}, found {depth!r}")
        if "reason" not in obj:
            raise PlanFormatError("reason", f"missing: a plan that is {status} says why")
        reason = expect_text(obj["reason"], "reason")
    return PlanDocument(task, status, depth, stats, robot, graphs, steps, final, reason)


def _robot(data: Any, path: str) -> PlanRobot:
    obj = expect_object(data, path, _ROBOT_KEYS)
    joints = tuple(
        expect_name(j, f"{path}.joints[{k}]") for k, j in enumerate(expect_list(obj["joints"], f"{path}.joints"))
    )
    if not joints:
        raise PlanFormatError(f"{path}.joints", "expected the arm's joint names, found none")
    return PlanRobot(
        name=expect_name(obj["name"], f"{path}.name"),
        urdf=expect_name(obj["urdf"], f"{path}.urdf"),
        base=expect_pose(obj["base"], f"{path}.base"),
        effector=expect_name(obj["effector"], f"{path}.effector"),
        effector_link=expect_name(obj["effector_link"], f"{path}.effector_link"),
        effector_offset=expect_pose(obj["effector_offset"], f"{path}.effector_offset"),
        joints=joints,
    )


def _stats(data: Any, path: str) -> PlanStats:
    obj = expect_object(data, path, _STATS_KEYS)
    time = expect_number(obj["solve_time_s"], f"{path}.solve_time_s")
    if time < 0:
        raise PlanFormatError(f"{path}.solve_time_s", f"expected a duration >= 0, found {time!r}")
    counts = []
    for key in _STATS_KEYS[1:]:
        value = obj[key]
        if not is_int(value) or value < 0:
            raise PlanFormatError(f"{path}.{key}", f"expected a count (an integer >= 0), found {value!r}")
        counts.append(value)
    return PlanStats(time, *counts)


def _graph(data: Any, path: str) -> tuple[Edge, ...]:
    obj = expect_object(data, path, ("edges",))
    edges = []
    for k, raw in enumerate(expect_list(obj["edges"], f"{path}.edges")):
        where = f"{path}.edges[{k}]"
        if not isinstance(raw, list) or len(raw) != 3:
            raise PlanFormatError(where, f"expected [parent, child, type], found {show(raw)}")
        parent, child = expect_name(raw[0], f"{where}[0]"), expect_name(raw[1], f"{where}[1]")
        edges.append((parent, child, expect_choice(raw[2], f"{where}[2]", MOTIONS)))
    return tuple(edges)


def _step(data: Any, path: str, n_joints: int, older: bool = False) -> PlanStepRecord:
    obj = expect_object(data, path, _STEP_KEYS[:-1] if older else _STEP_KEYS)
    value = expect_number(obj["value"], f"{path}.value")
    if value < 0:
        raise PlanFormatError(f"{path}.value", f"expected an amount >= 0 (m or rad), found {value!r}")
    q_start = expect_joints(obj["q_start"], f"{path}.q_start", n_joints)
    q_end = expect_joints(obj["q_end"], f"{path}.q_end", n_joints)
    return PlanStepRecord(
        op=expect_choice(obj["op"], f"{path}.op", OPS),
        affordance=expect_dotted(obj["affordance"], f"{path}.affordance", "Type.affordance"),
        body=expect_name(obj["body"], f"{path}.body"),
        effector=expect_dotted(obj["effector"], f"{path}.effector", "owner.frame"),
        motion=expect_choice(obj["motion"], f"{path}.motion", MOTIONS),
        value=value,
        poses_start=expect_poses(obj["poses_start"], f"{path}.poses_start"),
        poses_end=expect_poses(obj["poses_end"], f"{path}.poses_end"),
        q_start=q_start,
        q_end=q_end,
        path=tuple(
            _segment(seg, f"{path}.path[{k}]", n_joints)
            for k, seg in enumerate(expect_list(obj["path"], f"{path}.path"))
        ),
        contact=None if older else _contact(obj["contact"], f"{path}.contact", n_joints, (q_start, q_end)),
    )


def _contact(data: Any, path: str, n_joints: int, ends: tuple[np.ndarray, np.ndarray]) -> np.ndarray | None:
    """A step's contact chain: none (`[]`), or 2 or more joint lists from `q_start` to `q_end`."""
    raw = expect_list(data, path)
    if not raw:
        return None
    if len(raw) < 2:
        raise PlanFormatError(
            path, f"expected [] or 2 or more joint configurations (q_start ... q_end), found {len(raw)}"
        )
    joints = np.array([expect_joints(q, f"{path}[{k}]", n_joints) for k, q in enumerate(raw)], dtype=float)
    for k, (q, name) in ((0, (ends[0], "q_start")), (len(raw) - 1, (ends[1], "q_end"))):
        if np.abs(joints[k] - q).max() > 1e-9:
            raise PlanFormatError(
                f"{path}[{k}]", f"expected the step's {name}: a contact chain runs from q_start to q_end"
            )
    return frozen(joints)


def _segment(data: Any, path: str, n_joints: int) -> ArmSegment:
    obj = expect_object(data, path, _SEGMENT_KEYS)
    phase = expect_choice(obj["phase"], f"{path}.phase", PHASES)
    raw_times = expect_list(obj["times"], f"{path}.times")
    times = [expect_number(t, f"{path}.times[{k}]") for k, t in enumerate(raw_times)]
    if not times or times[0] != 0 or any(b <= a for a, b in itertools.pairwise(times)):
        raise PlanFormatError(f"{path}.times", "expected seconds from 0, increasing (one per waypoint)")
    raw_joints = expect_list(obj["joints"], f"{path}.joints")
    if len(raw_joints) != len(times):
        raise PlanFormatError(
            f"{path}.joints", f"expected {len(times)} waypoints (one per time), found {len(raw_joints)}"
        )
    joints = [expect_joints(q, f"{path}.joints[{k}]", n_joints) for k, q in enumerate(raw_joints)]
    return ArmSegment(phase, frozen(np.asarray(times, dtype=float)), frozen(np.array(joints, dtype=float)))


__all__ = [
    "MOTIONS",
    "OLDER_READABLE",
    "OPS",
    "PHASES",
    "PLAN_FORMAT",
    "STATUSES",
    "ArmSegment",
    "Edge",
    "PlanDocument",
    "PlanFormatError",
    "PlanRobot",
    "PlanStats",
    "PlanStepRecord",
    "Poses",
    "dumps",
    "from_json",
    "matrix_json",
    "read",
    "rounded",
    "to_json",
    "write",
]
