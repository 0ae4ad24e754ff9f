"""Time-parametrisation of a joint path within the URDF's joint velocity limits (and optional acceleration limits).

A path is a polyline in joint space (k waypoints). `time_path` gives each
waypoint a time so that every joint stays within its velocity limit along
every straight segment, all joints moving in step (they start and end each
segment together):

- velocity limits only (`acceleration=None`): segment k takes
  `T_k = max_i |dq_ik| / v_i` at constant velocity; this is time-optimal for
  the polyline when accelerations are free (the execution drives the arm
  kinematically, `docs/execution.md`). Velocities jump at waypoints.
- with acceleration limits: a trapezoidal speed profile along the path.
  `rest_at_waypoints=False` (default): one trapezoid over the whole path in
  the path's "full-speed time" s (s advances by T_k over segment k), with
  speed ds/dt <= 1 and |d2s/dt2| <= min_i a_i / v_i, so within each segment
  every joint keeps |qdot_i| <= v_i and |qddot_i| <= a_i; direction changes
  at waypoints are still velocity steps (small after smoothing).
  `rest_at_waypoints=True`: each segment is its own rest-to-rest trapezoid,
  so accelerations are bounded everywhere (slower on many short segments).

The URDF gives velocity limits (`<limit velocity=...>`), not acceleration
limits: `PANDA_ACCELERATION_LIMITS` are Franka's published values, used only
when passed. Everything is closed-form arithmetic: deterministic.
"""

from __future__ import annotations

import functools
import itertools
import math
import xml.etree.ElementTree as ElementTree
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from vkgl.errors import InputError

if TYPE_CHECKING:
    from vkgl.robot import Arm

PANDA_ACCELERATION_LIMITS = (15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0)
"""rad/s^2: Franka's published joint acceleration limits of the Panda (not in its URDF)."""

STRAIGHT_SPEED_SCALE = 0.5
"""The share of each joint's velocity limit a straight Cartesian move may use (`straight_times`): half, so that
the arm tracking it each control period keeps headroom to catch up."""


def velocity_limits(urdf: str | Path, joint_names: Sequence[str]) -> np.ndarray:
    """The velocity limits (rad/s) of `joint_names` in the URDF at `urdf` (`<limit velocity=...>`).

    Raises InputError when the file cannot be read or a joint or its velocity limit is missing.
    """
    try:
        root = ElementTree.parse(str(urdf)).getroot()
    except (OSError, ElementTree.ParseError) as error:
        raise InputError(f"cannot read the URDF {urdf}: {error}") from None
    limits = {}
    for joint in root.iter("joint"):
        limit = joint.find("limit")
        if limit is not None and limit.get("velocity") is not None:
            limits[joint.get("name")] = float(limit.get("velocity", "nan"))
    missing = [name for name in joint_names if not (limits.get(name, 0.0) > 0.0)]
    if missing:
        raise InputError(f"the URDF {urdf} gives no positive velocity limit for {', '.join(missing)}")
    return np.array([limits[name] for name in joint_names])


@functools.cache
def _limits_of(urdf: str, joints: tuple[str, ...]) -> np.ndarray:
    return velocity_limits(urdf, list(joints))


def arm_velocity_limits(arm: Arm) -> np.ndarray:
    """The arm's joint velocity limits from its URDF (rad/s), in `arm.joint_names`' order, read once per URDF."""
    return _limits_of(str(arm.urdf), tuple(arm.joint_names)).copy()


def straight_times(
    joints: np.ndarray, length: float, speed: float, velocity: np.ndarray, *, scale: float = STRAIGHT_SPEED_SCALE
) -> np.ndarray:
    """Times (s, from 0) for a straight Cartesian move of `length` (m) through `joints` (k x n, evenly spaced
    poses along it): at `speed` (m/s), and slower on each segment where a joint would move faster than its
    `velocity` limit (rad/s) times `scale`.

    Near a singularity a few millimetres of the effector can take a large joint motion (gen5_007: a 4 cm lift
    moved joint 5 by 1.1 rad, 6.8 rad/s at 0.15 m/s, past its 2.61 rad/s limit): timed by length alone, the
    arm could not follow it.
    """
    points = np.atleast_2d(np.asarray(joints, dtype=float))
    count = len(points) - 1
    if count < 1:
        return np.zeros(1)
    total = max(length / speed, 1e-3)
    cartesian = total / count
    spans = np.maximum(cartesian, _full_speed_durations(points, np.asarray(velocity, dtype=float) * scale))
    # evenly spaced at `speed`, plus what the joints' limits add: where they add nothing, exactly evenly spaced
    return np.linspace(0.0, total, count + 1) + np.concatenate([[0.0], np.cumsum(spans - cartesian)])


@dataclass(frozen=True)
class TimedPath:
    """`waypoints` (k x n) reached at `times` (k, from 0); `at(t)` interpolates the joints at time t."""

    waypoints: np.ndarray
    times: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray | None
    rest_at_waypoints: bool

    @property
    def duration(self) -> float:
        """The time of the last waypoint (s)."""
        return float(self.times[-1])

    def at(self, t: float) -> np.ndarray:
        """The joints at time `t` (clipped to [0, duration])."""
        t = min(max(float(t), 0.0), self.duration)
        k = int(np.searchsorted(self.times, t, side="right")) - 1
        k = min(max(k, 0), len(self.waypoints) - 2)
        if len(self.waypoints) == 1:
            return self.waypoints[0].copy()
        if self.acceleration is None or not self.rest_at_waypoints:
            s = self._full_speed_time(t)
            return _on_polyline(self.waypoints, self._segment_full_speed(), s)
        span = self.times[k + 1] - self.times[k]
        fraction = 1.0 if span <= 0 else _trapezoid_fraction(t - self.times[k], span, self._segment_profile(k))
        return self.waypoints[k] + fraction * (self.waypoints[k + 1] - self.waypoints[k])

    def _segment_full_speed(self) -> np.ndarray:
        return _full_speed_durations(self.waypoints, self.velocity)

    def _full_speed_time(self, t: float) -> float:
        """s(t): the path's full-speed time reached at time t."""
        total = float(self._segment_full_speed().sum())
        if self.acceleration is None:
            return t
        speed, accel = 1.0, float(np.min(self.acceleration / self.velocity))
        return _trapezoid_fraction(t, self.duration, (total, speed, accel)) * total

    def _segment_profile(self, k: int) -> tuple[float, float, float]:
        assert self.acceleration is not None
        return _rest_to_rest_bounds(self.waypoints[k + 1] - self.waypoints[k], self.velocity, self.acceleration)


def time_path(
    waypoints: np.ndarray | Sequence[Sequence[float]],
    velocity: Sequence[float] | np.ndarray,
    acceleration: Sequence[float] | np.ndarray | None = None,
    *,
    velocity_scale: float = 1.0,
    rest_at_waypoints: bool = False,
) -> TimedPath:
    """Times for `waypoints` (k x n) within per-joint `velocity` limits (rad/s) times `velocity_scale`
    (in (0, 1]), and within `acceleration` limits (rad/s^2) if given (see the module's docstring)."""
    points = np.atleast_2d(np.asarray(waypoints, dtype=float))
    v = np.asarray(velocity, dtype=float) * velocity_scale
    a = None if acceleration is None else np.asarray(acceleration, dtype=float)
    if not 0.0 < velocity_scale <= 1.0:
        raise ValueError(f"velocity_scale must be in (0, 1], got {velocity_scale}")
    if v.shape != points.shape[1:] or (v <= 0).any() or (a is not None and (a.shape != v.shape or (a <= 0).any())):
        raise ValueError("velocity (and acceleration) limits must be positive, one per joint")
    full_speed = _full_speed_durations(points, v)
    if a is None:
        times = np.concatenate([[0.0], np.cumsum(full_speed)])
    elif rest_at_waypoints:
        spans = [_trapezoid_time(*_rest_to_rest_bounds(q1 - q0, v, a)) for q0, q1 in itertools.pairwise(points)]
        times = np.concatenate([[0.0], np.cumsum(spans)])
    else:
        total = float(full_speed.sum())
        profile = (total, 1.0, float(np.min(a / v)))
        duration = _trapezoid_time(*profile)
        marks = np.concatenate([[0.0], np.cumsum(full_speed)])
        times = np.array([_trapezoid_inverse(s, duration, profile) for s in marks])
    return TimedPath(points, times, v, a, rest_at_waypoints)


def _full_speed_durations(points: np.ndarray, velocity: np.ndarray) -> np.ndarray:
    """Per segment: the shortest time in which every joint covers its change within its velocity limit."""
    if len(points) < 2:
        return np.zeros(0)
    return np.max(np.abs(np.diff(points, axis=0)) / velocity, axis=1)


def _rest_to_rest_bounds(
    delta: np.ndarray, velocity: np.ndarray, acceleration: np.ndarray
) -> tuple[float, float, float]:
    """(distance 1, speed bound, acceleration bound) of the segment's fraction u in [0, 1] such that
    q = q0 + u * delta keeps every joint within its limits."""
    moving = np.abs(delta) > 0
    if not moving.any():
        return (0.0, 1.0, 1.0)
    return (
        1.0,
        float(np.min(velocity[moving] / np.abs(delta[moving]))),
        float(np.min(acceleration[moving] / np.abs(delta[moving]))),
    )


def _trapezoid_time(distance: float, speed: float, accel: float) -> float:
    """The shortest rest-to-rest time over `distance` with |velocity| <= speed and |acceleration| <= accel."""
    if distance <= 0:
        return 0.0
    if distance >= speed * speed / accel:  # reaches full speed
        return distance / speed + speed / accel
    return 2.0 * math.sqrt(distance / accel)


def _trapezoid_position(t: float, distance: float, speed: float, accel: float) -> float:
    """The position at time t of the shortest rest-to-rest trapezoid (or triangle) profile over `distance`."""
    duration = _trapezoid_time(distance, speed, accel)
    if distance <= 0 or t <= 0:
        return 0.0
    if t >= duration:
        return distance
    peak = min(speed, math.sqrt(distance * accel))
    ramp = peak / accel
    if t <= ramp:
        return 0.5 * accel * t * t
    if t >= duration - ramp:
        left = duration - t
        return distance - 0.5 * accel * left * left
    return 0.5 * accel * ramp * ramp + peak * (t - ramp)


def _trapezoid_fraction(t: float, duration: float, profile: tuple[float, float, float]) -> float:
    """The fraction of the profile's distance covered at time t (0 .. 1)."""
    distance = profile[0]
    if distance <= 0 or duration <= 0:
        return 1.0
    return _trapezoid_position(t, *profile) / distance


def _trapezoid_inverse(position: float, duration: float, profile: tuple[float, float, float]) -> float:
    """The time at which the profile reaches `position` (bisection: the position is monotonic in time)."""
    low, high = 0.0, duration
    if position >= profile[0]:
        return duration
    for _ in range(60):
        middle = (low + high) / 2
        if _trapezoid_position(middle, *profile) < position:
            low = middle
        else:
            high = middle
    return (low + high) / 2


def _on_polyline(points: np.ndarray, spans: np.ndarray, s: float) -> np.ndarray:
    """The point of the polyline at full-speed time s (segment k lasts spans[k])."""
    marks = np.concatenate([[0.0], np.cumsum(spans)])
    k = int(np.searchsorted(marks, s, side="right")) - 1
    k = min(max(k, 0), len(points) - 2)
    span = spans[k]
    fraction = 1.0 if span <= 0 else min(max((s - marks[k]) / span, 0.0), 1.0)
    return points[k] + fraction * (points[k + 1] - points[k])


__all__ = [
    "PANDA_ACCELERATION_LIMITS",
    "STRAIGHT_SPEED_SCALE",
    "TimedPath",
    "arm_velocity_limits",
    "straight_times",
    "time_path",
    "velocity_limits",
]
