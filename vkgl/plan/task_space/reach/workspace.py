"""The arm's reachable workspace as the planner uses it.

The reach is `Arm.reach(height)`: the radial interval around the arm's base in
which the hand can be held hand-down at that height, computed once per height
from the URDF (`vkgl/robot/`). Task space keeps the hand `REACH_MARGIN` inside
it, so that inverse kinematics has room.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection

REACH_MARGIN = 0.005
"""m: task space keeps the hand this far inside the reach interval, so that IK has room."""


def unreachable(problem: Problem, hand: np.ndarray) -> Rejection | None:
    """Why the hand cannot be at `hand` (outside the reach at its height), or None."""
    distance = reach_violation(problem, hand[:3, 3])
    if distance <= 0:
        return None
    r_min, r_max = problem.arm.reach(float(hand[2, 3]))
    radius = float(np.hypot(*(hand[:2, 3] - problem.arm.base[:2, 3])))
    low, high = r_min + REACH_MARGIN, r_max - REACH_MARGIN
    return Rejection(
        Kind.REACH,
        f"the hand would be {radius:.3f} m from the arm's base at height {hand[2, 3]:.3f} m "
        f"(usable reach there: {low:.3f} to {high:.3f} m, the hand {_outside_words(distance)} it; the arm's "
        f"{r_min:.3f} to {r_max:.3f} m less {REACH_MARGIN * 1000:g} mm kept for inverse kinematics)",
        distance,
    )


def _outside_words(distance: float) -> str:
    """How far (m, > 0) the hand lies outside the usable reach, in words: at millimetres the printed distance and
    interval agree to the last digit (`0.794 m`, `... to 0.794 m`), and the reader must not take it for inside."""
    return f"{distance * 1000:.1f} mm outside" if distance >= 0.00005 else "less than 0.1 mm outside"


def reach_violation(problem: Problem, point: np.ndarray) -> float:
    """How far (m) `point` lies outside the reach interval shrunk by `REACH_MARGIN` (<= 0 inside)."""
    if not np.isfinite(point).all():
        return 1.0
    r_min, r_max = problem.arm.reach(float(point[2]))
    if r_max <= 0:
        return 1.0
    radius = math.hypot(point[0] - problem.arm.base[0, 3], point[1] - problem.arm.base[1, 3])
    return max(r_min + REACH_MARGIN - radius, radius - (r_max - REACH_MARGIN))


def reach_violations(problem: Problem, points: np.ndarray) -> np.ndarray:
    """`reach_violation` of many points at once (n x 3)."""
    if not np.isfinite(points).all():
        return np.ones(len(points))
    heights = points[:, 2]
    base = problem.arm.base
    if float(heights.max()) - float(heights.min()) < 5e-4:  # planar motions: one height for all, one lookup
        # the same numbers as the general case's, element by element, without building its arrays (the
        # optimiser asks this for every point it tries)
        r_min, r_max = problem.arm.reach(float(heights[0]))
        if not r_max > 0:
            return np.ones(len(points))
        radius = np.hypot(points[:, 0] - base[0, 3], points[:, 1] - base[1, 3])
        return np.maximum(r_min + REACH_MARGIN - radius, radius - (r_max - REACH_MARGIN))
    known: dict[float, tuple[float, float]] = {}  # one reach lookup per height (a hand path holds few)
    for z in heights.tolist():
        if z not in known:
            known[z] = problem.arm.reach(z)
    intervals = np.array([known[z] for z in heights.tolist()])
    radius = np.hypot(points[:, 0] - base[0, 3], points[:, 1] - base[1, 3])
    out = np.maximum(intervals[:, 0] + REACH_MARGIN - radius, radius - (intervals[:, 1] - REACH_MARGIN))
    return np.where(intervals[:, 1] > 0, out, 1.0)
