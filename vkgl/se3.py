"""Planar angle helpers shared by every stage: the heading of a pose and angle wrapping.

Tiny and dependency-free on purpose (the standard library and 4x4 numpy-like
matrices only), so that the planner, the executor and the formats agree on
what "yaw" means without importing each other.
"""

from __future__ import annotations

import math
from typing import Any


def yaw_of(pose: Any) -> float:
    """The heading (rad, in [-pi, pi]) of a 4x4 pose: the angle of its x axis about the world z axis."""
    return math.atan2(float(pose[1][0]), float(pose[0][0]))


def wrap_angle(angle: float) -> float:
    """`angle` wrapped into [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def angle_difference(a: float, b: float) -> float:
    """a - b wrapped into [-pi, pi)."""
    return wrap_angle(a - b)


__all__ = ["angle_difference", "wrap_angle", "yaw_of"]
