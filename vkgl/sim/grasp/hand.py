"""The simulated gripper of grasp trials: the URDF's hand and two fingers, the hand led along a path by a
stiff spring, the fingers closed by their own drives.

The hand is a free DART body with the hand link's collision shapes and mass,
without gravity (the robot carries it). Every physics step a spring-damper
wrench pulls it towards where the trial's path wants it (`target`), stiff
enough that a held body of a few kilograms moves it by millimetres: the trial
measures the body's slip relative to the hand, so the hand's own lag does not
count. Explicit forces, not DART's velocity or servo actuators: in dartpy 6.20
a skeleton driven by such rows gets no friction at its contacts
(`vkgl.sim.fingertip`), and a grasp holds by nothing but friction.

Each finger hangs on its URDF prismatic joint (axis, travel, shapes) and is
driven like the Franka gripper's motor: it closes with the grasp force when
stalled and with none at the no-load speed, F = F_grasp (1 - v / CLOSING_SPEED),
so the pads squeeze the body with the stated force once they touch it. A
finger's simulated mass is raised where that explicit drive would otherwise be
unstable (`vkgl.sim.fingertip.driven_mass`); the pads' friction is
PAD_FRICTION (DART takes the smaller of the pad's and the body's).
"""

from __future__ import annotations

from typing import Any

import dartpy as dart
import numpy as np

from vkgl.robot.gripper import Gripper
from vkgl.shapes import isometry
from vkgl.sim.fingertip import driven_mass

CLOSING_SPEED = 0.1
"""m/s: a finger's no-load speed (the Franka gripper closes at up to 0.1 m/s)."""
PAD_FRICTION = 1.0
"""The pads' friction coefficient (rubber-like): a grasp holds with the body's own coefficient."""
STIFFNESS = 4000.0
"""N/m of the spring that leads the hand (a 5 N load moves it by about 1 mm)."""
TURN_STIFFNESS = 40.0
"""N m/rad of the spring that turns the hand."""
HAND_MASS = 5.0
"""kg: the hand's simulated mass, the arm's inertia behind it (the link's own 0.73 kg would let the fingers'
drives, pushing back on it, outpace the explicit integration)."""
FINGER_MARGIN = 2.0
"""A finger's simulated mass is this many times the least for which its explicit drive is stable."""


class SimHand:
    """The hand with its two fingers in a DART world; `pose()` is the effector frame in the world."""

    def __init__(self, world: Any, gripper: Gripper, effector_pose: np.ndarray, opening: float, force: float) -> None:
        """The hand with its effector frame at the 4x4 `effector_pose`, the pads `opening` apart, squeezing with
        `force` (N) once closed."""
        self.gripper = gripper
        self.force = float(force)
        self.skeleton = dart.dynamics.Skeleton("hand")
        self.root, self.hand = self.skeleton.createFreeJointAndBodyNodePair()
        self.hand.setName("panda_hand")
        _dress(self.hand, gripper.shapes, max(gripper.mass, HAND_MASS))
        self.fingers = []
        damping = self.force / CLOSING_SPEED
        for finger in gripper.fingers:
            joint, node = self.hand.createPrismaticJointAndBodyNodePair()
            joint.setName(finger.joint)
            joint.setTransformFromParentBodyNode(isometry(finger.origin))
            joint.setAxis(finger.axis)
            joint.setPositionLowerLimit(0, 0.0)
            joint.setPositionUpperLimit(0, finger.upper)
            joint.setLimitEnforcement(True)
            _dress(node, finger.shapes, FINGER_MARGIN * driven_mass(damping, world.getTimeStep()) + finger.mass)
            self.fingers.append(joint)
        self.skeleton.setGravity(np.zeros(3))
        for i in range(self.skeleton.getNumBodyNodes()):
            self.skeleton.getBodyNode(i).setGravityMode(False)
        self._to_hand = np.linalg.inv(gripper.effector)  # effector frame -> hand frame
        hand_pose = effector_pose @ self._to_hand
        self.root.setPositions(dart.dynamics.FreeJoint.convertToPositions(isometry(hand_pose)))
        for joint in self.fingers:
            joint.setPosition(0, min(opening / 2.0, joint.getPositionUpperLimit(0)))
        world.addSkeleton(self.skeleton)
        mass = float(self.skeleton.getMass())
        self._damping = 2.0 * np.sqrt(STIFFNESS * mass)
        inertia = float(np.trace(self.hand.getInertia().getMoment())) / 3.0 + mass * 0.05**2
        self._turn_damping = 2.0 * np.sqrt(TURN_STIFFNESS * inertia)
        self.closing = False
        self._finger_damping = self.force / CLOSING_SPEED

    def pose(self) -> np.ndarray:
        """The effector frame in the world."""
        return np.asarray(self.hand.getWorldTransform().matrix(), dtype=float) @ self.gripper.effector

    def opening(self) -> float:
        """m between the pads."""
        return float(sum(joint.getPosition(0) for joint in self.fingers))

    def finger_speeds(self) -> np.ndarray:
        """m/s of each finger along its joint (negative: closing)."""
        return np.asarray(self.skeleton.getVelocities(), dtype=float)[6:]

    def drive(self, target: np.ndarray, velocity: np.ndarray) -> None:
        """Before a physics step: pull the hand towards the effector pose `target` moving at `velocity` (m/s),
        and drive the fingers (closing once `closing` is set, else holding them where they are)."""
        hand_target = target @ self._to_hand
        now = self.hand.getWorldTransform().matrix()
        error = hand_target[:3, 3] - now[:3, 3]
        speed = self.hand.getLinearVelocity()
        self.hand.addExtForce(STIFFNESS * error + self._damping * (velocity - speed), _ZERO, False, True)
        # the turn from where the hand is to where it should be, for small turns: the axis times sin(angle)
        r = hand_target[:3, :3] @ now[:3, :3].T
        turn = 0.5 * np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
        spin = self.hand.getAngularVelocity()
        self.hand.addExtTorque(TURN_STIFFNESS * turn - self._turn_damping * spin, False)
        v = self.skeleton.getVelocities()[6:]
        if self.closing:  # F = -F_grasp (1 - closing speed / no-load speed), never opening
            commands = np.minimum(0.0, -self.force - self._finger_damping * v)
        else:  # hold the opening: a damper only (the fingers have no gravity)
            commands = -self._finger_damping * v
        self.skeleton.setCommands(np.concatenate([_ZERO6, commands]))


_ZERO = np.zeros(3)
_ZERO6 = np.zeros(6)


def _dress(node: Any, shapes: tuple[tuple[Any, np.ndarray], ...], mass: float) -> None:
    for shape, pose in shapes:
        shape_node = node.createShapeNode(shape.clone() if hasattr(shape, "clone") else shape)
        shape_node.setRelativeTransform(isometry(pose))
        shape_node.createVisualAspect()
        shape_node.createCollisionAspect()
        shape_node.createDynamicsAspect().setFrictionCoeff(PAD_FRICTION)
    inertia = dart.dynamics.Inertia()
    inertia.setMass(mass)
    side = 0.05
    inertia.setMoment(mass * side**2 / 6.0 * np.eye(3))
    node.setInertia(inertia)


__all__ = ["CLOSING_SPEED", "PAD_FRICTION", "SimHand"]
