"""Reading `vkg-plan/8` (and /7 down to /2): every field checked, the first bad one named by its JSON path."""

from __future__ import annotations

import itertools
import json
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.errors import InputError, PlanFormatError
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
from vkgl.formats.plan.document import (
    _ROBOT_KEYS,
    _SEGMENT_KEYS,
    _STATS_KEYS,
    _STEP_KEYS,
    _TOP_KEYS,
    MOTIONS,
    OLDER_READABLE,
    OPS,
    PHASES,
    PLAN_FORMAT,
    SAME_LAYOUT,
    STATUSES,
    ArmSegment,
    Edge,
    PlanDocument,
    PlanRobot,
    PlanStats,
    PlanStepRecord,
)


def read(path: str | Path) -> PlanDocument:
    """Read and check a `vkg-plan/8` (or /7 down to /2) file. InputError if it cannot be read or is not JSON;
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
    if obj["format"] not in (PLAN_FORMAT, *SAME_LAYOUT, OLDER_READABLE):
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
