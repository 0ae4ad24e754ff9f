"""Pose helpers shared by every stage: the heading of a pose, angle wrapping, and screw motions.

Small on purpose (numpy and `vkgl.rotations`, SciPy's rotations without importing SciPy), so that the planner, the
executor and the formats agree on what "yaw" means and on how a body's
planned motion is interpolated (along its screw axis) without importing each
other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from vkgl.rotations import matrix_rotvec, rotvec_matrices, rotvec_matrix


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


@dataclass(frozen=True)
class ScrewMotion:
    """A world-frame rigid motion as a screw: turn by `rotvec` about the line through `point`, slide `slide` along it.

    `at(s)` is the motion carried out to the fraction s: the interpolation
    along the screw axis (Chasles), straight for a translation and circular
    for a rotation about a fixed axis. (Closed form with rotation vectors
    rather than a 4x4 matrix exponential: cheaper, and free of BLAS threads
    competing with the simulator.)
    """

    rotvec: np.ndarray
    point: np.ndarray
    slide: np.ndarray

    def at(self, s: float = 1.0) -> np.ndarray:
        """The 4x4 world-frame motion after the fraction `s` of it."""
        rotation = np.array(rotvec_matrix(*(s * self.rotvec).tolist()))
        motion = np.eye(4)
        motion[:3, :3] = rotation
        motion[:3, 3] = self.point - rotation @ self.point + s * self.slide
        return motion

    def along(self, fractions: np.ndarray) -> np.ndarray:
        """`at(s)` for each s of `fractions` (k), as k x 4 x 4: one rotation call for all of them."""
        fractions = np.asarray(fractions, dtype=float)
        rotations = rotvec_matrices(np.outer(fractions, self.rotvec))
        motions = np.tile(np.eye(4), (len(fractions), 1, 1))
        motions[:, :3, :3] = rotations
        motions[:, :3, 3] = self.point - rotations @ self.point + np.outer(fractions, self.slide)
        return motions


def screw_motion(body_start: np.ndarray, body_end: np.ndarray) -> ScrewMotion:
    """The screw motion taking the pose `body_start` to `body_end` (world frame).

    `screw_motion(a, b).at(s) @ a` interpolates the body's planned motion:
    along a line for a prismatic affordance, about its axis for a revolute one.
    """
    motion = body_end @ np.linalg.inv(body_start)
    rotvec = matrix_rotvec(motion[:3, :3])
    angle = float(np.linalg.norm(rotvec))
    t = motion[:3, 3]
    if angle < 1e-9:
        return ScrewMotion(np.zeros(3), np.zeros(3), t.copy())
    axis = rotvec / angle
    slide = float(t @ axis) * axis
    # a point on the axis: (I - R) p = t - slide, solved in the plane normal to the axis
    point, *_ = np.linalg.lstsq(np.eye(3) - motion[:3, :3], t - slide, rcond=None)
    return ScrewMotion(rotvec, point, slide)
