"""The task-space problem's inequality constraints at one rollout (`constraint_values`): the hand's reach at
every hand pose (a tilted hand judged where its wrist stands above, `hand_down_points`) and each moved body's
limits (`body_constraints`), each mode's part found once and kept on its trace."""

from __future__ import annotations

import numpy as np

from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.problem import Problem
from vkgl.plan.task_space.constraints.body_limits import body_constraints
from vkgl.plan.task_space.reach.workspace import hand_down_points, reach_violations


def constraint_values(
    problem: Problem, traces: list[ModeTrace], placed: dict[tuple[str, bytes], list[float]] | None = None
) -> np.ndarray:
    """Inequality constraints (<= 0 when satisfied, metres): reach of every hand sample, table, joint limits.

    `placed`: `body_constraints` already computed, by body and end pose (byte for byte: the same numbers),
    read and added to. The optimiser's finite differences move one value at a time, so most bodies end each
    mode where they ended at the point the step is taken from. What a mode gives is kept on its trace
    (`_mode_parts`): a rollout reuses the traces of the modes its values did not change (`Rollouts`)."""
    parts = [_mode_parts(problem, trace, placed) for trace in traces]
    points = [hands for hands, _ in parts if hands is not None]
    limits = [value for _, values in parts for value in values]
    if not points:
        return np.asarray(limits if limits else [-1.0], dtype=float)
    reach = reach_violations(problem, points[0] if len(points) == 1 else np.concatenate(points))
    return np.concatenate([reach, np.asarray(limits, dtype=float)]) if limits else reach


def _mode_parts(
    problem: Problem, trace: ModeTrace, placed: dict[tuple[str, bytes], list[float]] | None
) -> tuple[np.ndarray | None, list[float]]:
    """A mode's hand points (n x 3, `hand_down_points`, None without any) and its moved bodies'
    `body_constraints` (by name), with `placed` found once per trace (a trace's poses never change) and kept
    on it; without, afresh."""
    kept = trace.__dict__.get("_parts")
    if kept is not None and kept[0] is problem and placed is not None:
        return kept[1], kept[2]
    hands = hand_down_points(problem, np.array(trace.hand)) if trace.hand else None  # row by row: as all at once
    limits: list[float] = []
    for name in sorted(trace.moved):  # a set of str: its order changes with the hash seed
        pose = trace.end[name]
        if placed is None:
            limits.extend(body_constraints(problem, name, pose))
            continue
        key = (name, pose.tobytes())
        known = placed.get(key)
        if known is None:
            known = placed[key] = body_constraints(problem, name, pose)
        limits.extend(known)
    if placed is not None:
        trace.__dict__["_parts"] = (problem, hands, limits)
    return hands, limits


__all__ = ["constraint_values"]
