"""The fingertip pad: the part of the closed gripper that pushes, the same in exploration, planning and execution.

Exploration pushes with a fingertip of radius `FINGERTIP_RADIUS`
(`vkgl.sim.fingertip`); the executed arm pushes with a pad of that radius,
`FINGER_PAD_WIDTH` wide across the push direction (a capsule along the effector
frame's y, its front point on the effector frame's origin:
`vkgl.execute.world_arm`); the planner checks the same capsule against the
bodies (`vkgl.motion.arm_collision`), so that a transit clear in the plan is
clear in physics.
"""

from __future__ import annotations

import numpy as np

from vkgl.rotations import axis_matrix

FINGERTIP_RADIUS = 0.005
"""m: the fingertip's (and the pad's) radius."""

FINGER_PAD_WIDTH = 0.02
"""m: the closed fingers of a Panda hand push with a pad about this wide (the capsule's length, without caps)."""


def pad_pose() -> np.ndarray:
    """The pad capsule's frame in the effector frame: centred `FINGERTIP_RADIUS` behind the origin, its axis
    (DART's capsule axis, z) along the effector frame's y."""
    pose = np.eye(4)
    pose[:3, :3] = axis_matrix(0, np.pi / 2)
    pose[0, 3] = -FINGERTIP_RADIUS
    return pose


def turned_pad(angle: float) -> np.ndarray:
    """The effector frame turned by `angle` (rad, counter-clockwise) about its z axis and moved back so that the
    pad's front along the push (its x before the turn: `pad_front`) lies where the pad's face was, the frame's
    origin before the turn. A hand so turned pushes with the pad's rounded end, its narrow side more along the
    face it pushes and its 20 cm width more along the push (`vkgl.plan.arm.contact_chains`: a small body close
    beside a big one)."""
    turn = np.eye(4)
    turn[:3, :3] = axis_matrix(2, angle)
    turn[:3, 3] = -pad_front(turn, np.array([1.0, 0.0, 0.0]))
    return turn


def pad_front(effector: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """The point of the pad (world) of a hand whose effector frame is `effector` (4x4, world) farthest along the
    unit push `direction`: where it touches a face it pushes. For a hand whose pad lies along the face (the pad's
    axis, the frame's y, across the push) that is the frame's origin; for a turned hand, on the rounded end of
    the pad's capsule."""
    centre = (effector @ pad_pose())[:3, 3]
    axis = effector[:3, 1]
    along = float(axis @ direction)
    if abs(along) > 1e-9:  # the end of the capsule's segment nearer the face; across the push, all of it: its middle
        centre = centre + (FINGER_PAD_WIDTH / 2) * (axis if along > 0.0 else -axis)
    return centre + FINGERTIP_RADIUS * direction


PAD_FLAT_SINE = 0.5
"""The pad lies along a face while its axis leaves the face's plane by at most 30 deg (the sine): a lean or a roll
keeps it in the plane, a hand turned about its axis (`turned_pad`, 60 deg or more) pushes with the rounded end."""


def pad_lies_along(effector: np.ndarray, normal: np.ndarray) -> bool:
    """Whether the pad of a hand whose effector frame is `effector` (4x4, world) lies along a face whose inward
    normal (the push's direction) is the unit `normal`: a line contact 2 cm long, not the point of its rounded
    end (`turned_pad`)."""
    return abs(float(effector[:3, 1] @ normal)) <= PAD_FLAT_SINE


__all__ = [
    "FINGERTIP_RADIUS",
    "FINGER_PAD_WIDTH",
    "PAD_FLAT_SINE",
    "pad_front",
    "pad_lies_along",
    "pad_pose",
    "turned_pad",
]
