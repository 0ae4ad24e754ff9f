"""The Panda's parallel gripper as its URDF has it: the hand, the two fingers on their prismatic joints, the pads.

Grasp learning (`vkgl.sim.grasp`) builds its simulated hand from this, so that
the fingers that close on a body in a trial are the URDF's: their shapes, the
axis and travel of their joints, their effort. Everything here is in the hand
link's frame (`panda_hand`: z the approach axis, y the axis the fingers slide
along) or in the effector frame (`fingertip`: the hand's frame turned by
180 deg about x, docs/language.md "The effector frame convention").

The pads are the lowest collision box of each finger (the one furthest along
the approach axis): `Gripper.pad_centre` is their centre in the effector frame
with the fingers closed, `pad_size` their extent (x, y, z) in it.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np

from vkgl.errors import InputError
from vkgl.robot.urdf import load_skeleton

HAND_LINK = "panda_hand"
FINGER_JOINTS = ("panda_finger_joint1", "panda_finger_joint2")
EFFECTOR_OFFSET = 0.103
"""m along the hand's z axis: the `fingertip` effector of stdlib/robots/panda.vkg (`offset (0, 0, 10.3) cm`)."""


@dataclass(frozen=True)
class Finger:
    """One finger: its joint's frame in the hand frame (`origin`, 4x4) and `axis` (unit, hand frame), its travel
    (`upper`, m from closed), `effort` (N), `mass` (kg) and collision `shapes` (DART shape, 4x4 pose in the
    finger's frame)."""

    joint: str
    origin: np.ndarray
    axis: np.ndarray
    upper: float
    effort: float
    mass: float
    shapes: tuple[tuple[Any, np.ndarray], ...]


@dataclass(frozen=True)
class Gripper:
    """The hand link's collision `shapes` (shape, 4x4 pose in the hand frame), its `mass`, the `fingers`, and the
    effector frame in the hand frame (`effector`, 4x4)."""

    urdf: str
    shapes: tuple[tuple[Any, np.ndarray], ...]
    mass: float
    fingers: tuple[Finger, ...]
    effector: np.ndarray

    @property
    def max_opening(self) -> float:
        """m: the widest the pads open (both fingers at the end of their travel)."""
        return float(sum(f.upper for f in self.fingers))

    @property
    def effort(self) -> float:
        """N: the smaller finger effort limit: the most a grasp can squeeze with."""
        return float(min(f.effort for f in self.fingers))

    def pad_box(self) -> tuple[np.ndarray, np.ndarray]:
        """(centre, size) of the closed fingers' pads together, in the effector frame: the box the pads cover."""
        corners = []
        for finger in self.fingers:
            shape, pose = _pad_of(finger)
            half = np.asarray(shape.getSize(), dtype=float) / 2.0
            for sign in np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).T.reshape(-1, 3):
                corner = finger.origin @ pose @ np.append(sign * half, 1.0)
                corners.append((np.linalg.inv(self.effector) @ corner)[:3])
        points = np.array(corners)
        low, high = points.min(axis=0), points.max(axis=0)
        return (low + high) / 2.0, high - low

    def pad_thickness(self) -> float:
        """m: how thick one pad is across the closing direction (the room a finger needs beside a body)."""
        shape, _ = _pad_of(self.fingers[0])
        return float(np.asarray(shape.getSize(), dtype=float)[1])


def _pad_of(finger: Finger) -> tuple[Any, np.ndarray]:
    """The finger's lowest box (furthest along the approach axis): its pad."""
    boxes = [(s, p) for s, p in finger.shapes if s.getType() == "BoxShape"]
    if not boxes:
        raise InputError(f"the finger of joint {finger.joint} has no box: no pad to grasp with")
    return max(boxes, key=lambda sp: float((finger.origin @ sp[1])[2, 3]))


@cache
def gripper(urdf: str) -> Gripper:
    """The gripper of the URDF at `urdf` (the Panda's: stdlib/robots/panda.urdf), read once per process.

    Raises InputError when the URDF has no hand link or no finger joints.
    """
    skeleton = load_skeleton(urdf)
    hand = skeleton.getBodyNode(HAND_LINK)
    if hand is None:
        raise InputError(f"{urdf}: no link `{HAND_LINK}` to grasp with")
    fingers = []
    for name in FINGER_JOINTS:
        joint = skeleton.getJoint(name)
        if joint is None or joint.getNumDofs() != 1:
            raise InputError(f"{urdf}: no prismatic finger joint `{name}`")
        node = joint.getChildBodyNode()
        fingers.append(
            Finger(
                joint=name,
                origin=np.asarray(joint.getTransformFromParentBodyNode().matrix(), dtype=float),
                axis=np.asarray(joint.getAxis(), dtype=float),
                upper=float(joint.getPositionUpperLimit(0)),
                effort=float(joint.getForceUpperLimit(0)),
                mass=float(node.getMass()),
                shapes=_collision_shapes(node),
            )
        )
    effector = np.eye(4)
    effector[2, 3] = EFFECTOR_OFFSET
    effector[:3, :3] = np.diag([1.0, -1.0, -1.0])  # Rx(180 deg): z up when the hand points down
    return Gripper(
        urdf=urdf, shapes=_collision_shapes(hand), mass=float(hand.getMass()), fingers=tuple(fingers), effector=effector
    )


def _collision_shapes(node: Any) -> tuple[tuple[Any, np.ndarray], ...]:
    found = []
    for i in range(node.getNumShapeNodes()):
        shape_node = node.getShapeNode(i)
        if shape_node.hasCollisionAspect():
            found.append((shape_node.getShape(), np.asarray(shape_node.getRelativeTransform().matrix(), dtype=float)))
    return tuple(found)


__all__ = ["EFFECTOR_OFFSET", "FINGER_JOINTS", "HAND_LINK", "Finger", "Gripper", "gripper"]
