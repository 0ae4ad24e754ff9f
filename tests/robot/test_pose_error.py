"""The pose errors: the smooth residual the optimisers minimise, and the errors that decide a solution."""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.robot.pose_error import angle_error, orientation_residual, position_error


def pose(rotation: np.ndarray, translation: tuple[float, float, float] = (0, 0, 0)) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = rotation
    m[:3, 3] = translation
    return m


def test_the_orientation_residual_is_about_the_angle_squared() -> None:
    for yaw_free, turn in ((False, Rotation.from_euler("z", 0.01)), (True, Rotation.from_euler("x", 0.01))):
        residual, _ = orientation_residual(turn.as_matrix(), np.eye(3), yaw_free)
        assert math.isclose(residual, 0.01**2, rel_tol=1e-3)
    # with the yaw free, turning about z costs nothing
    residual, direction = orientation_residual(Rotation.from_euler("z", 1.0).as_matrix(), np.eye(3), True)
    assert residual == 0.0 and not direction.any()


def test_the_errors_measure_distance_and_angle() -> None:
    a = pose(np.eye(3), (0.1, 0.2, 0.3))
    b = pose(Rotation.from_euler("zx", [0.5, 0.2]).as_matrix(), (0.1, 0.2, 0.7))
    assert math.isclose(position_error(a, b), 0.4)
    assert math.isclose(angle_error(a, b, False), Rotation.from_euler("zx", [0.5, 0.2]).magnitude())
    assert math.isclose(angle_error(a, b, True), 0.2)  # only the z axes: the turn about x tilts it by 0.2
