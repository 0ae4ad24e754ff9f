"""The gripper's fingers in the execution world: opened before a grasp, closed on the tool, opened to let go.

The robot's URDF may give the hand fingers on prismatic joints (the Panda's
`panda_finger_joint1/2`, 0 = closed, opening along the hand's y; any joint with
a degree of freedom that is not one of the arm's). Like the arm they are
driven kinematically (velocity commands, not moved by what they touch): before
a grasp the hand comes down with its fingers open `FINGER_CLEARANCE` wider than
the tool on each side, at the grasp they close until their pads touch the
tool's faces (the tool's width across the grip, where the effector frame
holds it), and when the tool is let go of they open again; they close fully
before the hand pushes with its fingertip. What holds the tool then is the
grip of `vkgl.robot.grip` (why: see there).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from vkgl.execute.world_arm import CONTROL_PERIOD, WorldArm
from vkgl.robot.grip import TOUCH_GAP, width_across_grip  # where the planner reads them too

FINGER_SPEED = 0.05
"""m/s each finger moves (the Panda hand's fingers move at up to about 0.1 m/s)."""

FINGER_CLEARANCE = 0.01
"""m between each open finger's pad and the tool's face as the hand comes down onto it."""


class Fingers:
    """The finger joints of the arm in the world (none for a hand without them: then nothing moves)."""

    def __init__(self, arm: WorldArm) -> None:
        self.arm = arm
        names = set(arm.arm.joint_names)
        skeleton = arm.skeleton
        self.joints = [
            j
            for j in (skeleton.getJoint(i) for i in range(skeleton.getNumJoints()))
            if j.getNumDofs() == 1 and j.getName() not in names and j is not skeleton.getRootJoint()
        ]

    @property
    def opening(self) -> float:
        """How far each finger is open now (m, the mean of the fingers'), 0 without fingers."""
        return float(np.mean([j.getPosition(0) for j in self.joints])) if self.joints else 0.0

    def move(self, each: float, advance: Callable[[int], None]) -> None:
        """Open (or close) every finger to `each` m (within its limits), the world running meanwhile."""
        if not self.joints:
            return
        targets = [float(np.clip(each, j.getPositionLowerLimit(0), j.getPositionUpperLimit(0))) for j in self.joints]
        travel = max(abs(t - j.getPosition(0)) for t, j in zip(targets, self.joints))
        if travel < 1e-6:
            return
        dt = self.arm.world.getTimeStep()
        periods = max(1, int(np.ceil(travel / FINGER_SPEED / CONTROL_PERIOD - 1e-9)))
        substeps = max(1, round(CONTROL_PERIOD / dt))
        for k in range(periods):
            for joint, target in zip(self.joints, targets):
                joint.setCommand(0, (target - joint.getPosition(0)) / ((periods - k) * substeps * dt))
            advance(substeps)
        for joint in self.joints:
            joint.setCommand(0, 0.0)


__all__ = ["FINGER_CLEARANCE", "FINGER_SPEED", "TOUCH_GAP", "Fingers", "width_across_grip"]
