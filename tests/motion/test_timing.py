"""Time-parametrisation: within the URDF's velocity limits (and given acceleration limits), deterministic."""

from __future__ import annotations

import numpy as np
import pytest
from panda_fixtures import URDF

from vkgl.errors import InputError
from vkgl.motion.timing import (
    PANDA_ACCELERATION_LIMITS,
    STRAIGHT_SPEED_SCALE,
    straight_times,
    time_path,
    velocity_limits,
)

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


# gen5_007's last lift: 4 cm straight up, 5 mm a pose, the hook held low beside the base (joint 4 near its limit):
# joint 5 turns 1.1 rad and joint 7 0.75 rad on the way
LIFT_NEAR_A_SINGULARITY = np.array(
    [
        [-0.984, 0.145, 0.023, -2.993, -0.693, 3.137, 0.779],
        [-1.070, 0.116, 0.124, -3.007, -0.625, 3.118, 0.726],
        [-1.164, 0.087, 0.242, -3.022, -0.528, 3.101, 0.652],
        [-1.269, 0.056, 0.388, -3.039, -0.384, 3.086, 0.549],
        [-1.372, 0.022, 0.560, -3.054, -0.159, 3.071, 0.394],
        [-1.412, -0.014, 0.682, -3.060, 0.096, 3.049, 0.222],
        [-1.374, -0.046, 0.695, -3.060, 0.251, 3.020, 0.119],
        [-1.334, -0.078, 0.684, -3.059, 0.335, 2.991, 0.064],
        [-1.303, -0.109, 0.670, -3.060, 0.388, 2.961, 0.030],
    ]
)


def test_a_straight_move_slows_where_a_joint_would_pass_its_velocity_limit() -> None:
    limits = velocity_limits(URDF, JOINTS)
    times = straight_times(LIFT_NEAR_A_SINGULARITY, 0.04, 0.15, limits)
    assert times[0] == 0.0 and len(times) == len(LIFT_NEAR_A_SINGULARITY)
    rates = np.abs(np.diff(LIFT_NEAR_A_SINGULARITY, axis=0)) / np.diff(times)[:, None]
    assert (rates <= limits * STRAIGHT_SPEED_SCALE * (1 + 1e-9)).all()
    # timed by its length alone (0.27 s), joint 5 would have to turn at 6.8 rad/s (its limit: 2.61)
    assert times[-1] > 3 * 0.04 / 0.15
    assert (np.diff(times) >= 0.04 / 0.15 / 8 - 1e-12).all()  # never faster than the Cartesian speed


def test_a_regular_straight_move_keeps_its_cartesian_speed() -> None:
    limits = velocity_limits(URDF, JOINTS)
    joints = PATH[0] + np.linspace(0.0, 1.0, 9)[:, None] * 0.01  # 0.01 rad per joint over 4 cm
    assert np.allclose(straight_times(joints, 0.04, 0.03, limits), np.linspace(0.0, 0.04 / 0.03, 9), rtol=0, atol=1e-12)
    assert straight_times(joints[:1], 0.0, 0.03, limits).tolist() == [0.0]
