"""How far an effector pose is from a target: the smooth residual the optimisers use, and the
errors (with their tolerances) that decide whether a result counts as a solution."""

from __future__ import annotations

import math

import numpy as np

POSITION_TOL = 1e-3
"""m: an IK result is a solution when its effector is this close to the target ..."""

ANGLE_TOL = math.radians(0.5)
"""rad: ... and its orientation this close (about any axis, or of the z axis when yaw is free)."""


def orientation_residual(rotation: np.ndarray, target: np.ndarray, yaw_free: bool) -> tuple[float, np.ndarray]:
    """A smooth orientation residual (about angle^2 when small) and its gradient direction.

    The gradient of the residual with respect to joint k is `w_k . direction`
    (w_k: the joint's angular Jacobian column). Full orientation: 3 - trace(Rt^T R);
    yaw free: 2 (1 - z . z_t).
    """
    if yaw_free:
        # -2 (z x z_target) written out on Python floats (the same IEEE operations as on the array, ten
        # times faster: np.cross or numpy scalars cost more than the rest of the IK objective)
        (_, _, ax), (_, _, ay), (_, _, az) = rotation.tolist()
        (_, _, bx), (_, _, by), (_, _, bz) = target.tolist()
        direction = np.array([-2.0 * (ay * bz - az * by), -2.0 * (az * bx - ax * bz), -2.0 * (ax * by - ay * bx)])
        return 2.0 * (1.0 - (ax * bx + ay * by + az * bz)), direction
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = (rotation @ target.T).tolist()
    return 3.0 - (a00 + a11 + a22), np.array([-(a12 - a21), -(a20 - a02), -(a01 - a10)])


def position_error(pose: np.ndarray, target: np.ndarray) -> float:
    """The distance (m) between the origins of two 4x4 poses."""
    return float(np.linalg.norm(pose[:3, 3] - target[:3, 3]))


def angle_error(pose: np.ndarray, target: np.ndarray, yaw_free: bool) -> float:
    """The rotation angle (rad) between two 4x4 poses, or between their z axes when `yaw_free`."""
    if yaw_free:
        return math.acos(min(1.0, max(-1.0, float(pose[:3, 2] @ target[:3, 2]))))
    cosine = (float(np.trace(pose[:3, :3] @ target[:3, :3].T)) - 1.0) / 2.0
    return math.acos(min(1.0, max(-1.0, cosine)))


__all__ = ["ANGLE_TOL", "POSITION_TOL", "angle_error", "orientation_residual", "position_error"]
