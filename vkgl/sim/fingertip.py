"""The simulated effector of exploration: a fingertip that pushes, or a hand that holds a tool.

Both are DART bodies driven like a DC motor along the push direction: the
drive pushes with its force limit when stalled and with no force at its
no-load speed, F = F_max (1 - v / NO_LOAD_SPEED). The law is applied as a joint
force every physics step; contact with the explored body is made, kept or
lost by the simulator, never scripted.

Why not DART's own drives: in dartpy 6.20 a skeleton driven by SERVO (or
velocity-limit) rows gets no friction at its contacts, so the fingertip would
slide on any face; and DART's implicit joint damping is folded into the
inertia the contact solver sees, which swallows part of the push at a contact
(about c dt / (m + c dt) of it). An explicit force law has neither problem.

Pusher (policies `contacts on faces ... force normal F`): a sphere on a
translational joint, without gravity (the robot carries it). Its frame is the
effector frame (docs/language.md, "The effector frame convention"): origin on the sphere's surface along x, x the
direction it pushes, z up. Every control period the robot looks at the body
and aims the fingertip along the current inward normal of the pushed face
("force normal"); across the push the fingertip is compliant sideways and
vertically (light damping only, so friction can drag it along a turning face,
and can neither lift the body nor hold it down: docs/exploration.md, "A pusher
carries no vertical load").

Hand (policies `grasp FRAME ... force directions`): the hand body is welded
to the tool at the grasp frame, so its frame is the effector frame (a free
tool by a weld joint of the hand's skeleton, a body on its own joint by a
DART WeldJointConstraint). The robot drives the hand through its wrist, WRIST_HEIGHT above the grasp along
the effector's z, on a carriage driven along the trial's force direction, free
across it, and turning freely but damped (a passive ball joint): the tool
floats and turns as the force, applied off its centre of mass, makes it.
"""

from __future__ import annotations

from typing import Any

import dartpy as dart
import numpy as np

from vkgl.robot.pad import FINGERTIP_RADIUS
from vkgl.shapes import isometry, translation
from vkgl.sim.world import dress_body_node

FINGERTIP_MASS = 0.05  # kg
FINGERTIP_FRICTION = 1.0  # rubber-like; the pair takes the body's smaller coefficient
NO_LOAD_SPEED = 0.1  # m/s, the drive's speed when nothing resists (quasi-static pushing)
SIDEWAYS_DAMPING = 1.0  # N s/m, the fingertip's compliance across the push direction
VERTICAL_DAMPING = 1.0  # N s/m: no spring holds its height, so friction cannot carry the body's weight
STABLE_STEP = 1.0  # the drive's damping may remove at most this fraction of the velocity per step
WRIST_HEIGHT = 0.10  # m from the grasp frame to the wrist the robot drives (a Panda hand: 10.3 cm)
WRIST_DAMPING = 0.01  # N m s/rad: the wrist turns freely but not forever


def frame_facing(direction: np.ndarray, fallback_z: np.ndarray) -> np.ndarray:
    """A rotation matrix whose x is `direction` and whose z is as close to up as possible.

    When `direction` is vertical, z is taken from `fallback_z` (made orthogonal to x).
    """
    x = np.asarray(direction, dtype=float)
    x = x / np.linalg.norm(x)
    up = np.array([0.0, 0.0, 1.0])
    z = up - x * float(x @ up)
    if np.linalg.norm(z) < 1e-6:
        z = np.asarray(fallback_z, dtype=float) - x * float(x @ fallback_z)
    z = z / np.linalg.norm(z)
    # z x x written out: numpy's `cross` (the same products, the same differences, so the same bits) cost a third
    # of an exploration's control period in its axis handling
    y = np.array([z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]])
    return np.column_stack([x, y, z])


def _inertia(mass: float, radius: float) -> Any:
    return dart.dynamics.Inertia(mass, np.zeros(3), 0.4 * mass * radius**2 * np.eye(3))


def drive_damping(force_limit: float) -> float:
    """N s/m of the drive law F = F_max - c v: the force falls to zero at NO_LOAD_SPEED."""
    return force_limit / NO_LOAD_SPEED


def driven_mass(damping: float, time_step: float) -> float:
    """The effector's mass: FINGERTIP_MASS, or more when an explicit drive this stiff would be unstable."""
    return max(FINGERTIP_MASS, damping * time_step / STABLE_STEP)


class Pusher:
    """A fingertip sphere that pushes along its x axis, as hard as `force_limit` when stalled.

    It hangs on a translational joint whose frame is the fingertip's frame
    (x = push direction). dartpy's free joint takes linear coordinates in world
    axes, so a drive along a turning push direction needs a joint whose axes
    turn with it: each control period the joint frame is re-aimed and the
    fingertip's world position and velocity are re-expressed in it (a change of
    coordinates, not a move).
    """

    def __init__(self, world: Any, start: np.ndarray, force_limit: float, *, name: str = "fingertip") -> None:
        """Put the fingertip with its effector frame at the 4x4 world pose `start`."""
        self.skeleton = dart.dynamics.Skeleton(name)
        self.joint, self.node = self.skeleton.createTranslationalJointAndBodyNodePair()
        self.node.setName(name)
        shape = self.node.createShapeNode(dart.dynamics.SphereShape(FINGERTIP_RADIUS))
        shape.createVisualAspect()
        shape.createCollisionAspect()
        shape.createDynamicsAspect().setFrictionCoeff(FINGERTIP_FRICTION)
        self.force_limit = force_limit
        self.damping = drive_damping(force_limit)
        self.node.setInertia(_inertia(driven_mass(self.damping, world.getTimeStep()), FINGERTIP_RADIUS))
        self.fallback_z = start[:3, 2].copy()
        self.home = (start @ self._tip_offset(-1))[:3, 3]  # where the fingertip's centre starts
        self._aim(start[:3, :3], self.home, np.zeros(3))
        world.addSkeleton(self.skeleton)
        self.node.setGravityMode(False)  # the robot carries its own fingertip

    @staticmethod
    def _tip_offset(sign: int) -> np.ndarray:
        # The effector frame's origin is the sphere's surface point along x.
        return translation(np.array([sign * FINGERTIP_RADIUS, 0.0, 0.0]))

    def _aim(self, rotation: np.ndarray, centre: np.ndarray, velocity: np.ndarray) -> None:
        self.rotation = rotation
        self.joint.setTransformFromParentBodyNode(isometry(_pose(rotation, np.zeros(3))))
        self.joint.setPositions(rotation.T @ centre)
        self.joint.setVelocities(rotation.T @ velocity)

    def effector_pose(self) -> np.ndarray:
        """The world pose of the effector frame as simulated now."""
        return self.node.getWorldTransform().matrix() @ self._tip_offset(+1)

    def aim(self, direction: np.ndarray) -> None:
        """From now on push along the world `direction`."""
        centre = self.rotation @ self.joint.getPositions()
        velocity = self.rotation @ self.joint.getVelocities()
        self._aim(frame_facing(direction, self.fallback_z), centre, velocity)

    def drive(self) -> None:
        """Set the drive's forces for the next physics step (push; give way sideways and up or down)."""
        v = self.joint.getVelocities()
        self.joint.setCommands(
            np.array([self.force_limit - self.damping * v[0], -SIDEWAYS_DAMPING * v[1], -VERTICAL_DAMPING * v[2]])
        )


class Hand:
    """A hand holding a body at its grasp frame, driven through a damped, free-turning wrist.

    A floating tool becomes part of the hand's skeleton through a weld joint
    (`carry`): rigid and exact. A body that hangs on its own joint to the
    world keeps it and is held by a WeldJointConstraint (`hold`).
    """

    def __init__(
        self, world: Any, effector: np.ndarray, direction: np.ndarray, force: float, *, name: str = "hand"
    ) -> None:
        """A hand with its frame at the 4x4 world pose `effector`; its wrist will be driven
        along the unit world `direction` with at most `force`."""
        self.world = world
        self.skeleton = dart.dynamics.Skeleton(name)
        wrist = effector[:3, 3] + WRIST_HEIGHT * effector[:3, 2]
        along = frame_facing(direction, effector[:3, 0])
        self.carriage_joint, carriage = self.skeleton.createTranslationalJointAndBodyNodePair()
        # Carriage DOFs along the columns of `along`: 0 = the force direction, 1 and 2 across it (free).
        self.carriage_joint.setTransformFromParentBodyNode(isometry(_pose(along, wrist)))
        self.carriage_joint.setTransformFromChildBodyNode(isometry(_pose(along, np.zeros(3))))
        self.force = force
        self.damping = drive_damping(force)
        # The carriage carries the drive: its own mass keeps the explicit drive law stable even
        # when the held tool offers the wrist almost no inertia (a thin stick turning about its axis).
        carriage.setInertia(_inertia(driven_mass(self.damping, world.getTimeStep()), FINGERTIP_RADIUS))
        wrist_joint, self.node = self.skeleton.createBallJointAndBodyNodePair(carriage)
        wrist_joint.setTransformFromChildBodyNode(isometry(np.linalg.inv(effector) @ translation(wrist)))
        for i in range(3):
            wrist_joint.setDampingCoefficient(i, WRIST_DAMPING)
        self.node.setName(name)
        self.node.setInertia(_inertia(FINGERTIP_MASS, FINGERTIP_RADIUS))
        world.addSkeleton(self.skeleton)
        for node in (carriage, self.node):
            node.setGravityMode(False)  # the robot carries its hand

    def carry(self, body: Any, grasp: np.ndarray) -> Any:
        """Weld a new body node dressed as `body` to the hand, the hand at its frame `grasp`; return the node."""
        joint, node = self.skeleton.createWeldJointAndBodyNodePair(self.node)
        joint.setTransformFromParentBodyNode(isometry(np.linalg.inv(grasp)))
        node.setName(body.name)
        dress_body_node(node, body)
        node.setGravityMode(False)  # held up by the robot: only the declared force acts on it
        return node

    def hold(self, node: Any) -> None:
        """Hold a body node of another skeleton where it is now (a weld constraint)."""
        self.weld = dart.constraint.WeldJointConstraint(self.node, node)
        self.world.getConstraintSolver().addConstraint(self.weld)

    def effector_pose(self) -> np.ndarray:
        """The world pose of the effector frame (the hand's frame) as simulated now."""
        return self.node.getWorldTransform().matrix().copy()

    def drive(self) -> None:
        """Set the wrist's drive force for the next physics step."""
        speed = float(self.carriage_joint.getVelocities()[0])
        self.carriage_joint.setCommands(np.array([self.force - self.damping * speed, 0.0, 0.0]))


def _pose(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = rotation
    m[:3, 3] = position
    return m
