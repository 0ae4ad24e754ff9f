"""Time-parametrisation: within the URDF's velocity limits (and given acceleration limits), deterministic."""

from __future__ import annotations

import numpy as np
import pytest
from panda_fixtures import URDF

from vkgl.errors import InputError
from vkgl.motion.timing import PANDA_ACCELERATION_LIMITS, time_path, velocity_limits

JOINTS = [f"panda_joint{i}" for i in range(1, 8)]
PATH = np.array(
    [
        [0.0, 0.0, 0.0, -1.6, 0.0, 1.7, 0.8],
        [0.9, 0.3, -0.2, -1.2, 0.1, 1.9, 0.8],
        [1.0, 0.35, -0.2, -1.1, 0.1, 1.95, 0.9],  # a short segment
        [-0.5, -0.2, 0.4, -2.0, 0.6, 1.2, -0.3],
    ]
)


def test_velocity_limits_come_from_the_urdf() -> None:
    limits = velocity_limits(URDF, JOINTS)
    assert limits.tolist() == [2.175] * 4 + [2.61] * 3
    with pytest.raises(InputError, match="no positive velocity limit for nope"):
        velocity_limits(URDF, ["panda_joint1", "nope"])


def speeds(timed, dt: float = 2e-3) -> tuple[np.ndarray, np.ndarray]:
    """Finite-difference joint velocities and accelerations along the timed path."""
    t = np.arange(0.0, timed.duration + dt, dt)
    q = np.array([timed.at(x) for x in t])
    velocity = np.diff(q, axis=0) / dt
    return velocity, np.diff(velocity, axis=0) / dt


def test_velocity_only_timing_is_within_the_limits_and_tight() -> None:
    limits = velocity_limits(URDF, JOINTS)
    timed = time_path(PATH, limits)
    assert timed.times[0] == 0.0 and (np.diff(timed.times) > 0).all()
    # each segment lasts exactly as long as its slowest joint needs
    expected = np.max(np.abs(np.diff(PATH, axis=0)) / limits, axis=1)
    assert np.allclose(np.diff(timed.times), expected)
    velocity, _ = speeds(timed)
    assert (np.abs(velocity) <= limits * (1 + 1e-6)).all()
    assert np.allclose(timed.at(timed.duration), PATH[-1]) and np.allclose(timed.at(0.0), PATH[0])
    assert np.allclose(timed.at(timed.times[1]), PATH[1])
    half = time_path(PATH, limits, velocity_scale=0.5)
    assert np.isclose(half.duration, 2 * timed.duration)


@pytest.mark.parametrize("rest", [False, True])
def test_acceleration_limits_are_kept_within_segments(rest: bool) -> None:
    limits = velocity_limits(URDF, JOINTS)
    accel = np.array(PANDA_ACCELERATION_LIMITS)
    timed = time_path(PATH, limits, accel, rest_at_waypoints=rest)
    assert (np.diff(timed.times) > 0).all()
    assert timed.duration > time_path(PATH, limits).duration  # ramps take time
    for k in range(len(PATH)):
        assert np.allclose(timed.at(timed.times[k]), PATH[k], atol=1e-6)
    dt = 2e-3
    velocity, acceleration = speeds(timed, dt)
    assert (np.abs(velocity) <= limits * (1 + 1e-3)).all()
    t = np.arange(0.0, timed.duration + dt, dt)[1:-1]
    near_waypoint = np.min(np.abs(t[:, None] - timed.times[None]), axis=1) < 3 * dt
    inside = acceleration[~near_waypoint[: len(acceleration)]]
    assert (np.abs(inside) <= accel * 1.01).all()
    if rest:  # rest-to-rest: the arm is still at every waypoint
        assert np.allclose(timed.at(timed.times[1] + 1e-6), PATH[1], atol=1e-7)


def test_timing_is_deterministic() -> None:
    limits = velocity_limits(URDF, JOINTS)
    first = time_path(PATH, limits, PANDA_ACCELERATION_LIMITS)
    second = time_path(PATH.copy(), limits, PANDA_ACCELERATION_LIMITS)
    assert np.array_equal(first.times, second.times)
