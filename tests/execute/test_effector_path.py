"""Effector paths for execution: screws follow the body's planned motion, transits stay in free space."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from vkgl.execute import effector_path as paths


def pose(x: float, y: float, z: float, yaw_deg: float = 0.0) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = Rotation.from_euler("z", yaw_deg, degrees=True).as_matrix()
    m[:3, 3] = [x, y, z]
    return m


def test_screw_of_a_translation_is_a_straight_line_at_push_speed():
    start, end = pose(0.45, 0.0, 0.025), pose(0.60, 0.0, 0.025)
    effector = pose(0.40, 0.0, 0.025)
    segment = paths.screw("motion", effector, paths.screw_motion(start, end))
    assert segment.duration == pytest.approx(0.15 / paths.PUSH_SPEED)
    for s in np.linspace(0, 1, 7):
        p = segment.pose(s)
        np.testing.assert_allclose(p[:3, 3], [0.40 + 0.15 * s, 0.0, 0.025], atol=1e-9)
        np.testing.assert_allclose(p[:3, :3], np.eye(3), atol=1e-9)


def test_screw_of_a_rotation_keeps_the_contact_at_a_fixed_distance_from_the_axis():
    centre = np.array([0.50, -0.10, 0.025])
    turn = np.eye(4)
    turn[:3, :3] = Rotation.from_euler("z", -30, degrees=True).as_matrix()
    turn[:3, 3] = centre - turn[:3, :3] @ centre
    start = pose(0.45, 0.0, 0.025)
    end = turn @ start
    contact = start @ pose(-0.05, 0.09, 0.0)
    segment = paths.screw("motion", contact, paths.screw_motion(start, end))
    radius = np.linalg.norm(contact[:2, 3] - centre[:2])
    for s in np.linspace(0, 1, 9):
        assert np.linalg.norm(segment.pose(s)[:2, 3] - centre[:2]) == pytest.approx(radius, abs=1e-9)
    np.testing.assert_allclose(segment.pose(1.0), end @ pose(-0.05, 0.09, 0.0), atol=1e-9)


def test_backed_off_moves_against_the_push_direction():
    contact = pose(0.6, 0.0, 0.025, yaw_deg=180)  # pushes toward -x
    np.testing.assert_allclose(paths.backed_off(contact, 0.01)[:3, 3], [0.61, 0.0, 0.025], atol=1e-12)


def test_swing_stays_between_the_radii_of_its_ends():
    a, b = pose(0.15, -0.40, 0.1), pose(0.27, 0.0, 0.1)
    segment = paths.swing("transit", a, b, np.zeros(2))
    radii = [np.hypot(*segment.pose(s)[:2, 3]) for s in np.linspace(0, 1, 21)]
    assert min(radii) >= min(np.hypot(0.15, -0.40), 0.27) - 1e-9
    np.testing.assert_allclose(segment.pose(1.0), b, atol=1e-9)
