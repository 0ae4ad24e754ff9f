"""Keep-out regions in feasibility: no body a region keeps out enters it, anywhere along a motion.

`keep out R` / `keep B out of R` (docs/language.md) is a convex region of the
table's plane. Every body a mode moves (with whatever moves rigidly with it:
the tool pushing it, a tool held against it) is sampled along its motion as
the sweep samples it (`vkgl.plan.geometry.sweep`, no point moves more than
`STEP` between samples), and its footprint (the convex hull of its shape,
seen from above) tested against each region by separating axes
(`vkgl.lang.ir.regions.overlap_depth`): a body may touch a region's edge, not
enter it by more than `TOUCH_TOL`. Bodies that only move without a motion
value (released tools put down) are checked at the mode's ends.
"""

from __future__ import annotations

import numpy as np

from vkgl.lang.ir.regions import footprint, overlap_depth
from vkgl.motion.collision import TOUCH_TOL
from vkgl.plan.geometry.sweep import STEP, moving_groups, sample_values
from vkgl.plan.graphs.motions import motion_matrices
from vkgl.plan.graphs.rollout import ModeTrace
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection


def keep_out_rejection(problem: Problem, trace: ModeTrace, where: str) -> Rejection | None:
    """Why a mode takes a body into a keep-out region (naming the region, the body, how deep and where), or None."""
    if not problem.keep_out:
        return None
    for frame, constraint, value, movers in moving_groups(problem, trace):
        inverse = np.linalg.inv(frame)
        relative = {name: inverse @ pose for name, pose in movers.items()}
        reach = max(float(np.linalg.norm(rel[:3, 3])) + _radius(problem, name) for name, rel in relative.items())
        motions = frame @ motion_matrices(constraint, sample_values(constraint, value, reach, STEP))
        for name, rel in relative.items():
            found = _entering(problem, name, motions @ rel, where)
            if found is not None:
                return found
    for name, pose in trace.end.items():
        if not np.allclose(pose, trace.start[name], atol=1e-9):
            found = _entering(problem, name, pose[None], f"at the end of {where.removeprefix('in ')}")
            if found is not None:
                return found
    return None


def keep_out_depths(problem: Problem, name: str, pose: np.ndarray) -> list[float]:
    """How deep body `name` at `pose` lies in each keep-out region that applies to it (m; <= 0 outside)."""
    points = footprint(problem.footprint_points(name), pose)
    return [overlap_depth(k.region, points) for k in problem.keep_out if k.applies_to(name)]


def _entering(problem: Problem, name: str, poses: np.ndarray, where: str) -> Rejection | None:
    for region in problem.keep_out:
        if not region.applies_to(name):
            continue
        for pose in poses:
            depth = overlap_depth(region.region, footprint(problem.footprint_points(name), pose))
            if depth > TOUCH_TOL:
                at = pose[:2, 3]
                return Rejection(
                    Kind.COLLISION,
                    f"{name} would enter the keep-out {region.words} by {depth * 100:.1f} cm, its frame at "
                    f"({at[0]:.2f}, {at[1]:.2f}) m {where}: the task keeps it out",
                    float(depth),
                )
    return None


def _radius(problem: Problem, name: str) -> float:
    points = problem.footprint_points(name)
    return float(np.linalg.norm(points, axis=1).max())


__all__ = ["keep_out_depths", "keep_out_rejection"]
