"""The `vkg-plan/1` document: the one definition of the plan format, its only reader and writer.

ARCHITECTURE.md is the contract. In memory a plan document is a tree of frozen
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

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.errors import InputError, PlanFormatError
from vkgl.formats.atomic import write_text

PLAN_FORMAT = "vkg-plan/1"
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
)
_ROTATION_TOL = 1e-6  # how far from orthonormal a pose's rotation block may be


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
class PlanStepRecord:
    """One step of a plan: the transition into the next graph and the motion that graph allows.

    `poses_start`/`poses_end` are the bodies' world poses right after the
    transition and after the motion; `q_start`/`q_end` the arm's joints there;
    `value` is the motion's amount (m or rad, >= 0; 0 for a REMOVE).
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
    """A whole `vkg-plan/1` plan.

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


def dumps(doc: PlanDocument) -> str:
    """The text of a `vkg-plan/1` file (what `write` puts in it)."""
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
    }


# ---------------------------------------------------------------- reading


def read(path: str | Path) -> PlanDocument:
    """Read and check a `vkg-plan/1` file. InputError if it cannot be read or is not JSON;
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
    obj = _object(data, "", _TOP_KEYS, optional=("reason",))
    if obj["format"] != PLAN_FORMAT:
        raise PlanFormatError("format", f"expected {PLAN_FORMAT!r}, found {obj['format']!r}: not a {PLAN_FORMAT} plan")
    task = _name(obj["task"], "task")
    status = _choice(obj["status"], "status", STATUSES)
    robot = _robot(obj["robot"], "robot")
    stats = _stats(obj["stats"], "stats")
    graphs = tuple(_graph(g, f"graphs[{k}]") for k, g in enumerate(_list(obj["graphs"], "graphs")))
    steps = tuple(_step(s, f"steps[{k}]", len(robot.joints)) for k, s in enumerate(_list(obj["steps"], "steps")))
    final = _poses(obj["final"], "final")
    depth = obj["depth"]
    if status == "solved":
        if "reason" in obj:
            raise PlanFormatError("reason", "only a plan that is not solved has a reason")
        if not _is_int(depth) or depth < 1:
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
        reason = _text(obj["reason"], "reason")
    return PlanDocument(task, status, depth, stats, robot, graphs, steps, final, reason)


def _robot(data: Any, path: str) -> PlanRobot:
    obj = _object(data, path, _ROBOT_KEYS)
    joints = tuple(_name(j, f"{path}.joints[{k}]") for k, j in enumerate(_list(obj["joints"], f"{path}.joints")))
    if not joints:
        raise PlanFormatError(f"{path}.joints", "expected the arm's joint names, found none")
    return PlanRobot(
        name=_name(obj["name"], f"{path}.name"),
        urdf=_name(obj["urdf"], f"{path}.urdf"),
        base=_pose(obj["base"], f"{path}.base"),
        effector=_name(obj["effector"], f"{path}.effector"),
        effector_link=_name(obj["effector_link"], f"{path}.effector_link"),
        effector_offset=_pose(obj["effector_offset"], f"{path}.effector_offset"),
        joints=joints,
    )


def _stats(data: Any, path: str) -> PlanStats:
    obj = _object(data, path, _STATS_KEYS)
    time = _number(obj["solve_time_s"], f"{path}.solve_time_s")
    if time < 0:
        raise PlanFormatError(f"{path}.solve_time_s", f"expected a duration >= 0, found {time!r}")
    counts = []
    for key in _STATS_KEYS[1:]:
        value = obj[key]
        if not _is_int(value) or value < 0:
            raise PlanFormatError(f"{path}.{key}", f"expected a count (an integer >= 0), found {value!r}")
        counts.append(value)
    return PlanStats(time, *counts)


def _graph(data: Any, path: str) -> tuple[Edge, ...]:
    obj = _object(data, path, ("edges",))
    edges = []
    for k, raw in enumerate(_list(obj["edges"], f"{path}.edges")):
        where = f"{path}.edges[{k}]"
        if not isinstance(raw, list) or len(raw) != 3:
            raise PlanFormatError(where, f"expected [parent, child, type], found {_show(raw)}")
        parent, child = _name(raw[0], f"{where}[0]"), _name(raw[1], f"{where}[1]")
        edges.append((parent, child, _choice(raw[2], f"{where}[2]", MOTIONS)))
    return tuple(edges)


def _step(data: Any, path: str, n_joints: int) -> PlanStepRecord:
    obj = _object(data, path, _STEP_KEYS)
    value = _number(obj["value"], f"{path}.value")
    if value < 0:
        raise PlanFormatError(f"{path}.value", f"expected an amount >= 0 (m or rad), found {value!r}")
    return PlanStepRecord(
        op=_choice(obj["op"], f"{path}.op", OPS),
        affordance=_dotted(obj["affordance"], f"{path}.affordance", "Type.affordance"),
        body=_name(obj["body"], f"{path}.body"),
        effector=_dotted(obj["effector"], f"{path}.effector", "owner.frame"),
        motion=_choice(obj["motion"], f"{path}.motion", MOTIONS),
        value=value,
        poses_start=_poses(obj["poses_start"], f"{path}.poses_start"),
        poses_end=_poses(obj["poses_end"], f"{path}.poses_end"),
        q_start=_joints(obj["q_start"], f"{path}.q_start", n_joints),
        q_end=_joints(obj["q_end"], f"{path}.q_end", n_joints),
    )


# ---------------------------------------------------------------- field checks


def _show(value: Any) -> str:
    """`value` as JSON writes it (NaN as NaN), cut to 40 characters."""
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _object(data: Any, path: str, keys: Sequence[str], optional: Sequence[str] = ()) -> dict[str, Any]:
    where = path or "the plan"
    if not isinstance(data, dict):
        raise PlanFormatError(
            path, f"expected a JSON object, found {_show(data)}" + (f" ({where})" if not path else "")
        )
    for key in keys:
        if key not in data:
            raise PlanFormatError(_join(path, key), "missing")
    unknown = [k for k in data if k not in keys and k not in optional]
    if unknown:
        raise PlanFormatError(_join(path, str(unknown[0])), f"unknown key (expected {', '.join(keys)})")
    return data


def _join(path: str, key: str) -> str:
    return f"{path}.{key}" if path else key


def _list(data: Any, path: str) -> list[Any]:
    if not isinstance(data, list):
        raise PlanFormatError(path, f"expected a list, found {_show(data)}")
    return data


def _text(data: Any, path: str) -> str:
    if not isinstance(data, str):
        raise PlanFormatError(path, f"expected a string, found {_show(data)}")
    return data


def _name(data: Any, path: str) -> str:
    if not isinstance(data, str) or not data:
        raise PlanFormatError(path, f"expected a non-empty string, found {_show(data)}")
    return data


def _dotted(data: Any, path: str, form: str) -> str:
    text = _name(data, path)
    head, dot, tail = text.partition(".")
    if not (head and dot and tail):
        raise PlanFormatError(path, f"expected `{form}`, found {_show(text)}")
    return text


def _choice(data: Any, path: str, choices: Sequence[str]) -> str:
    if data not in choices or not isinstance(data, str):
        raise PlanFormatError(path, f"expected one of {', '.join(choices)}, found {_show(data)}")
    return data


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _number(data: Any, path: str) -> float:
    if not _is_number(data):
        raise PlanFormatError(path, f"expected a finite number, found {_show(data)}")
    return data  # type: ignore[no-any-return]


def _joints(data: Any, path: str, count: int) -> np.ndarray:
    if not isinstance(data, list) or not all(_is_number(v) for v in data):
        raise PlanFormatError(path, f"expected a list of finite numbers (joint positions, rad), found {_show(data)}")
    if len(data) != count:
        raise PlanFormatError(path, f"expected {count} joint positions (one per robot.joints), found {len(data)}")
    return _frozen(np.asarray(data, dtype=float))


def _pose(data: Any, path: str) -> np.ndarray:
    shaped = isinstance(data, list) and len(data) == 4 and all(isinstance(r, list) and len(r) == 4 for r in data)
    if not shaped or not all(_is_number(v) for row in data for v in row):
        raise PlanFormatError(path, "expected a 4x4 matrix of finite numbers")
    pose = np.asarray(data, dtype=float)
    if np.abs(pose[3] - (0.0, 0.0, 0.0, 1.0)).max() > 1e-9:
        raise PlanFormatError(path, "expected a homogeneous transform (last row 0 0 0 1)")
    rotation = pose[:3, :3]
    if np.abs(rotation.T @ rotation - np.eye(3)).max() > _ROTATION_TOL or np.linalg.det(rotation) < 0:
        raise PlanFormatError(path, "expected a rotation in the upper-left 3x3 block (orthonormal, det +1)")
    return _frozen(pose)


def _poses(data: Any, path: str) -> dict[str, np.ndarray]:
    if not isinstance(data, dict):
        raise PlanFormatError(path, f"expected an object of body name -> 4x4 pose, found {_show(data)}")
    return {_name(name, path): _pose(pose, f"{path}.{name}") for name, pose in data.items()}


def _frozen(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


__all__ = [
    "MOTIONS",
    "OPS",
    "PLAN_FORMAT",
    "STATUSES",
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
    "to_json",
    "write",
]
