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


__all__ = ["FINGERTIP_RADIUS", "FINGER_PAD_WIDTH", "pad_pose"]
