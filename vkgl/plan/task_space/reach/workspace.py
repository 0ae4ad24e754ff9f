"""The arm's reachable workspace as the planner uses it.

The reach is `Arm.reach(height)`: the radial interval around the arm's base in
which the hand can be held hand-down at that height, computed once per height
from the URDF (`vkgl/robot/`). Task space keeps the hand `REACH_MARGIN` inside
it, so that inverse kinematics has room.

A tilted hand (a tool rolled over a body, `vkgl.plan.problem.over`) is judged by
the point its wrist stands above (`hand_down_point`): leaning its top toward the
base reaches farther, away from it less far, as inverse kinematics finds.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection

REACH_MARGIN = 0.005
"""m: task space keeps the hand this far inside the reach interval, so that IK has room."""

UPRIGHT = 1e-9
"""A hand whose z axis is this close to vertical (1 - its z component) is upright: judged at its own point."""


def hand_down_point(problem: Problem, hand: np.ndarray) -> np.ndarray:
    """The point (world, 3-vector) whose hand-down reach stands for the hand at pose `hand` (4x4, world).

    An upright hand is its own point. A tilted hand's wrist (`Arm.wrist_lever` L above the effector along its z
    axis) leans by L times the z axis's component along the horizontal line from the arm's base to the hand, a:
    the arm holds the hand about as far as it holds an upright one whose wrist stands where this one's does, so
    the point moves by L a along that line, at the same height. The tilt across that line is left out (the wrist
    stays about as far from the base). Measured on the Panda (L 0.21 m) by inverse kinematics, radius bisection at
    12.5 cm, yaw free (hand-down 0.809 m; `Arm.reach` 0.806): leaning its top toward the base 15/20/35/45 deg it
    reaches 0.859/0.874/0.908/0.920 m, away from it 0.751/0.732/0.672/0.634 m, across 0.808/0.806/0.799/0.792 m;
    this point allows 0.861/0.878/0.927/0.955 m toward, 0.752/0.735/0.686/0.658 m away and 0.806 m across: within
    0.5 cm up to 20 deg, 1 to 3.5 cm too far at 35 to 45 deg, never short of what the arm reaches (inverse
    kinematics still decides). The hand-down reach alone allowed 0.806 m at every tilt."""
    point = np.asarray(hand[:3, 3], dtype=float)
    return hand_down_points(problem, hand[None])[0] if hand[2, 2] < 1.0 - UPRIGHT else point


def hand_down_points(problem: Problem, hands: np.ndarray) -> np.ndarray:
    """`hand_down_point` of many hand poses at once (n x 4 x 4): n x 3."""
    points = np.array(hands[:, :3, 3], dtype=float)
    tilted = hands[:, 2, 2] < 1.0 - UPRIGHT
    if not tilted.any():
        return points
    radial = points[tilted, :2] - problem.arm.base[:2, 3]
    length = np.linalg.norm(radial, axis=1)
    along = radial / np.maximum(length, 1e-12)[:, None]
    lean = np.sum(hands[tilted, :2, 2] * along, axis=1)  # the hand's z axis along the line out from the base
    points[tilted, :2] += problem.arm.wrist_lever * lean[:, None] * along
    return points


def hand_reach_violation(problem: Problem, hand: np.ndarray) -> float:
    """`reach_violation` of the hand at pose `hand` (4x4, world), a tilted hand at its `hand_down_point`."""
    return reach_violation(problem, hand_down_point(problem, hand))


def unreachable(problem: Problem, hand: np.ndarray) -> Rejection | None:
    """Why the hand cannot be at `hand` (outside the reach at its height; a tilted hand judged at its
    `hand_down_point`), or None."""
    point = hand_down_point(problem, hand)
    distance = reach_violation(problem, point)
    if distance <= 0:
        return None
    r_min, r_max = problem.arm.reach(float(hand[2, 3]))
    radius = float(np.hypot(*(hand[:2, 3] - problem.arm.base[:2, 3])))
    low, high = r_min + REACH_MARGIN, r_max - REACH_MARGIN
    tilt = math.degrees(math.acos(max(-1.0, min(1.0, float(hand[2, 2])))))
    counted = float(np.hypot(*(point[:2] - problem.arm.base[:2, 3])))
    tilted = f", tilted {tilt:.0f} deg: counted as {counted:.3f} m" if hand[2, 2] < 1.0 - UPRIGHT else ""
    return Rejection(
        Kind.REACH,
        f"the hand would be {radius:.3f} m from the arm's base{tilted} at height {hand[2, 3]:.3f} m "
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
