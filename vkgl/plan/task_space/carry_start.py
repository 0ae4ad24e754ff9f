"""Where the optimiser starts a carry: the body set down right at its goal.

A carried body's place (`vkgl.plan.graphs.carry`) moves it anywhere level on
the table in one mode, so its goal names the place exactly: the goal's
position (and heading, when the goal states one; else the heading it had) for
a pose goal, the Chebyshev centre of the region (the point deepest inside it,
a linear programme) for a region goal. Only a body's last carry is aimed at
the goal; earlier carries start at zero (set down where picked up). The start
pins the carry's values when the goal states position and heading: then the
optimiser has nothing to choose.
"""

from __future__ import annotations

import numpy as np

from vkgl.plan.graphs.carry import CARRY_VALUES, carry_values_to
from vkgl.plan.graphs.rollout import Sequence, rollout
from vkgl.plan.problem.problem import GoalSpec, Problem


def carry_start(problem: Problem, seq: Sequence, motion_guess: np.ndarray) -> tuple[np.ndarray, bool]:
    """The carries' start values (flattened, `CARRY_VALUES` each) given the motion values' start
    `motion_guess`, and whether the goals pin them all."""
    values = np.zeros(CARRY_VALUES * len(seq.carries))
    pinned = True
    last = {e.body: j for j, (_, e) in enumerate(seq.carries)}
    for j, (mode, e) in enumerate(seq.carries):
        goals = [g for g in problem.goals if g.body == e.body]
        if last[e.body] != j or not goals:
            pinned = False
            continue
        traces = rollout(problem, seq, np.concatenate([motion_guess, values]), 2)
        start = traces[mode].start[e.body]
        target, exact = _target(start, goals)
        values[CARRY_VALUES * j : CARRY_VALUES * (j + 1)] = carry_values_to(start, target)
        pinned = pinned and exact
    return values, pinned


def _target(start: np.ndarray, goals: list[GoalSpec]) -> tuple[np.ndarray, bool]:
    """Where the goals put a body now at `start` (level), and whether they pin that pose."""
    target = start.copy()
    has_position = has_yaw = False
    for goal in goals:
        if goal.position is not None:
            target[: min(2, len(goal.position)), 3] = goal.position[:2]
            has_position = True
        if goal.region is not None:
            centre = chebyshev_centre(goal.region)
            if centre is not None:
                target[:2, 3] = centre
        if goal.yaw is not None:
            c, s = np.cos(goal.yaw), np.sin(goal.yaw)
            target[:3, :3] = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ _level_part(start)
            has_yaw = True
    return target, has_position and has_yaw


def _level_part(pose: np.ndarray) -> np.ndarray:
    """The rotation of `pose` with its heading taken out (what stays when it is turned about the vertical)."""
    yaw = np.arctan2(pose[1, 0], pose[0, 0])
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]) @ pose[:3, :3]


def chebyshev_centre(half_planes: np.ndarray) -> np.ndarray | None:
    """The point deepest inside the region `n . p <= d` (rows `nx, ny, d`), or None when the region is empty
    or unbounded."""
    normals, offsets = half_planes[:, :2], half_planes[:, 2]
    norms = np.linalg.norm(normals, axis=1)
    from scipy.optimize import linprog  # only for region goals of carried bodies: a solve stays free of SciPy

    found = linprog(
        c=[0.0, 0.0, -1.0],
        A_ub=np.column_stack([normals, norms]),
        b_ub=offsets,
        bounds=[(None, None), (None, None), (0.0, None)],
        method="highs",
    )
    return np.asarray(found.x[:2], dtype=float) if found.status == 0 else None


__all__ = ["carry_start", "chebyshev_centre"]
