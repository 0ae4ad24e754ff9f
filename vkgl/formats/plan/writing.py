"""Writing `vkg-plan/8`: plain JSON data in the contract's key order, rounded, written atomically; and `rounded`,
the document with its numbers exactly as its JSON reads back."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.atomic import write_text
from vkgl.formats.json_checks import frozen
from vkgl.formats.plan.document import (
    _STATS_KEYS,
    PLAN_FORMAT,
    ArmSegment,
    PlanDocument,
    PlanRobot,
    PlanStats,
    PlanStepRecord,
    Poses,
)


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
    """The text of a `vkg-plan/8` file (what `write` puts in it)."""
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
