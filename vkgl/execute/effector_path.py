"""Task-space paths of the robot's effector, for carrying out a plan in DART.

A path is a list of `Segment`s, each a pose of the robot's effector frame as a
function of a phase s in [0, 1], run in a fixed duration. Three kinds exist:

- a straight `line` (position interpolated linearly, orientation by slerp):
  approach, retreat, straight up and down;
- a `swing` about the vertical axis through the robot's base: transit above
  the table that keeps its distance from the robot;
- a `screw` about a fixed world line: the motion of an affordance. When the
  effector is rigidly in contact with a body whose planned pose goes from
  B0 to B1, the effector moves by the same rigid motion B1 B0^-1, taken
  along its screw axis: a pure translation for a prismatic motion and a pure
  rotation about the revolute axis for a revolute one.

Nothing here touches the simulator: these are the targets the arm follows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation, Slerp

from vkgl.motion.moves import CARTESIAN_SPEED
from vkgl.se3 import ScrewMotion, screw_motion

# Speeds of the effector frame. Slow pushes keep the contact quasi-static, as
# in exploration; transits are faster because they touch nothing.
PUSH_SPEED = 0.05  # m/s along the contact path
APPROACH_SPEED = CARTESIAN_SPEED  # m/s for the last centimetres before contact, as the planner times them
TRANSIT_SPEED = 0.15  # m/s through free space
TURN_SPEED = 0.8  # rad/s for turning the effector about z
MIN_DURATION = 0.05  # s; even a zero-length segment lasts one control period or so


@dataclass(frozen=True)
class Segment:
    """One piece of effector path: `pose(s)` for s in [0, 1], carried out in `duration` seconds.

    `phase` names what the segment is for ("transit", "approach", "contact",
    "motion", "retreat", "grasp", "release", "hold"); the report and the
    animation use it.
    """

    phase: str
    start: np.ndarray
    end: np.ndarray
    duration: float
    motion: ScrewMotion | None = None  # the world-frame rigid motion carrying the effector (screws only)
    pivot: np.ndarray | None = None  # (x, y) of a vertical axis to swing about (arcs only)

    def pose(self, s: float) -> np.ndarray:
        """The effector pose at phase `s` (clipped to [0, 1])."""
        s = float(np.clip(s, 0.0, 1.0))
        if self.motion is not None:
            return self.motion.at(s) @ self.start
        if self.pivot is not None:
            return _swing(self.start, self.end, self.pivot, s)
        return _interpolate(self.start, self.end, s)


def _interpolate(a: np.ndarray, b: np.ndarray, s: float) -> np.ndarray:
    rotations = Rotation.from_matrix(np.stack([a[:3, :3], b[:3, :3]]))
    pose = np.eye(4)
    pose[:3, :3] = Slerp([0.0, 1.0], rotations)(s).as_matrix()
    pose[:3, 3] = (1.0 - s) * a[:3, 3] + s * b[:3, 3]
    return pose


def _polar(pose: np.ndarray, pivot: np.ndarray) -> tuple[float, float]:
    offset = pose[:2, 3] - pivot
    return float(np.hypot(*offset)), float(np.arctan2(offset[1], offset[0]))


def _swing(a: np.ndarray, b: np.ndarray, pivot: np.ndarray, s: float) -> np.ndarray:
    """Interpolate radius, bearing and height about a vertical axis through `pivot` (orientation by slerp)."""
    pose = _interpolate(a, b, s)
    (ra, ta), (rb, tb) = _polar(a, pivot), _polar(b, pivot)
    turn = (tb - ta + np.pi) % (2 * np.pi) - np.pi
    radius, bearing = (1 - s) * ra + s * rb, ta + s * turn
    pose[:2, 3] = pivot + radius * np.array([np.cos(bearing), np.sin(bearing)])
    return pose


def rotation_angle(a: np.ndarray, b: np.ndarray) -> float:
    """The angle of the rotation that takes orientation `a` to orientation `b` (rad).

    From the relative rotation's sine (its skew part) and cosine (its trace), precise at every angle, 0 and
    180 deg too; a twentieth of scipy's `Rotation.from_matrix(...).magnitude()`, which the grip's watch paid
    every control period.
    """
    r = b[:3, :3] @ a[:3, :3].T
    sine = 0.5 * math.hypot(r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1])
    cosine = 0.5 * (r[0, 0] + r[1, 1] + r[2, 2] - 1.0)
    return math.atan2(sine, cosine)


def line(phase: str, start: np.ndarray, end: np.ndarray, speed: float = TRANSIT_SPEED) -> Segment:
    """A straight segment from `start` to `end` at `speed` (m/s) and at most TURN_SPEED."""
    distance = float(np.linalg.norm(end[:3, 3] - start[:3, 3]))
    duration = max(distance / speed, rotation_angle(start, end) / TURN_SPEED, MIN_DURATION)
    return Segment(phase, start.copy(), end.copy(), duration)


def swing(phase: str, start: np.ndarray, end: np.ndarray, pivot: np.ndarray, speed: float = TRANSIT_SPEED) -> Segment:
    """From `start` to `end` around a vertical axis through `pivot` (the robot's base).

    Radius, bearing and height change linearly, so the path stays between
    the two ends' distances from the robot instead of cutting close to its
    base as a straight line would.
    """
    probe = Segment(phase, start, end, 1.0, pivot=np.asarray(pivot, dtype=float)[:2])
    points = np.array([probe.pose(s)[:3, 3] for s in np.linspace(0.0, 1.0, 33)])
    length = float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())
    duration = max(length / speed, rotation_angle(start, end) / TURN_SPEED, MIN_DURATION)
    return Segment(phase, start.copy(), end.copy(), duration, pivot=probe.pivot)


def hold(phase: str, pose: np.ndarray, duration: float) -> Segment:
    """Stay at `pose` for `duration` seconds (lets the bodies settle)."""
    return Segment(phase, pose.copy(), pose.copy(), max(duration, MIN_DURATION))


def screw(phase: str, start: np.ndarray, motion: ScrewMotion, speed: float = PUSH_SPEED) -> Segment:
    """The effector carried rigidly by the world `motion`, starting at `start`.

    The duration makes the effector's origin travel at `speed` along its
    (possibly circular) path.
    """
    samples = [motion.at(s) @ start for s in np.linspace(0.0, 1.0, 33)]
    points = np.array([p[:3, 3] for p in samples])
    length = float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())
    angle = rotation_angle(samples[0], samples[-1])
    duration = max(length / speed, angle / TURN_SPEED, MIN_DURATION)
    return Segment(phase, start.copy(), samples[-1], duration, motion=motion)


def backed_off(pose: np.ndarray, distance: float, direction: np.ndarray | None = None) -> np.ndarray:
    """`pose` moved back by `distance` against `direction` (default: its own x axis, the way it pushes)."""
    moved = pose.copy()
    moved[:3, 3] -= distance * (pose[:3, 0] if direction is None else np.asarray(direction, dtype=float))
    return moved


def at_height(pose: np.ndarray, z: float) -> np.ndarray:
    """`pose` with its origin at height `z`."""
    moved = pose.copy()
    moved[2, 3] = z
    return moved


__all__ = [
    "ScrewMotion",
    "Segment",
    "at_height",
    "backed_off",
    "hold",
    "line",
    "rotation_angle",
    "screw",
    "screw_motion",
    "swing",
]
