"""Approach and retreat: the straight Cartesian move between a contact and its pre-contact pose, in joints.

A contact is an effector frame (4x4, world) in the project's convention
(docs/language.md, "The effector frame convention"): its x axis is the direction of the applied force, into the
touched body, its z axis points up. Its pre-contact pose is the same frame
backed off by a stand-off along -x: clear of the body, at the contact's own
height. A tall body is therefore approached from the side at contact height;
the transit planner (`vkgl.motion.transit`) brings the arm to the pre-contact
pose, and the last centimetres are this straight Cartesian move.

- `pre_contact_pose(contact, standoff)`;
- `approach_poses(contact, standoff, step)`: effector poses from the
  pre-contact pose to the contact, at most `step` (5 mm) apart, the last one
  exactly the contact; `retreat_poses` is the same list reversed;
- `follow_poses(arm, poses, q_first)`: joints for each pose by chained IK
  (`Arm.ik` warm-started from the previous solution), rejecting a jump (a joint
  moving more than `max_joint_step` between consecutive poses: IK switched
  branch, or the straight line crosses a singularity);
- `approach_joints(arm, contact, standoff, q_contact)`: the approach in joints,
  solved from the contact outward (the contact's configuration is what the
  plan chose; `q_contact` seeds it) and returned pre-contact first;
  `retreat_joints` is the same path reversed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from vkgl.rotations import matrix_rotvec, rotvec_matrix

if TYPE_CHECKING:
    from vkgl.robot import Arm

APPROACH_STEP = 0.005
"""m: the largest distance between consecutive poses of an approach or retreat."""

MAX_JOINT_STEP = 0.1
"""rad: the largest change of any joint between consecutive poses (5 mm apart) of a Cartesian path. A regular
Panda configuration moves its joints by 0.01 to 0.03 rad per 5 mm; more means an IK branch switch or a
singularity."""


@dataclass(frozen=True)
class JointPath:
    """`joints` (k x n): one configuration per pose of `poses` (k 4x4 effector poses, world)."""

    poses: list[np.ndarray]
    joints: np.ndarray

    def reversed(self) -> JointPath:
        """The same path walked backwards (a retreat from an approach)."""
        return JointPath(self.poses[::-1], self.joints[::-1].copy())


@dataclass(frozen=True)
class CartesianFailure:
    """No joint path: `reason`, and `index`, the pose of the Cartesian path where it failed."""

    reason: str
    index: int


def pre_contact_pose(contact: np.ndarray, standoff: float, direction: np.ndarray | None = None) -> np.ndarray:
    """`contact` (4x4) moved back by `standoff` (m) against `direction`, same orientation.

    `direction` (world, unit) is the way the contact moves into the body: by
    default the contact's own x axis; a tool's push direction when the hand
    holds the tool that pushes, straight down for a grasp from above.
    """
    if standoff < 0:
        raise ValueError(f"the stand-off must not be negative, got {standoff}")
    pose = np.array(contact, dtype=float)
    way = pose[:3, 0] if direction is None else np.asarray(direction, dtype=float)
    pose[:3, 3] -= standoff * way
    return pose


def approach_poses(
    contact: np.ndarray, standoff: float, step: float = APPROACH_STEP, direction: np.ndarray | None = None
) -> list[np.ndarray]:
    """The straight approach: poses from the pre-contact pose to `contact`, evenly spaced at most `step` apart.

    The orientation is the contact's throughout; the first pose is
    `pre_contact_pose(contact, standoff, direction)` and the last is `contact` exactly.
    """
    if step <= 0:
        raise ValueError(f"the step must be positive, got {step}")
    contact = np.array(contact, dtype=float)
    start = pre_contact_pose(contact, standoff, direction)
    count = max(1, math.ceil(standoff / step - 1e-9))
    poses = []
    for k in range(count):
        pose = contact.copy()
        pose[:3, 3] = start[:3, 3] + (contact[:3, 3] - start[:3, 3]) * (k / count)
        poses.append(pose)
    poses.append(contact)
    return poses


def retreat_poses(
    contact: np.ndarray, standoff: float, step: float = APPROACH_STEP, direction: np.ndarray | None = None
) -> list[np.ndarray]:
    """The straight retreat: `approach_poses` reversed (from the contact back to the pre-contact pose)."""
    return approach_poses(contact, standoff, step, direction)[::-1]


def follow_poses(
    arm: Arm,
    poses: Sequence[np.ndarray],
    q_first: Sequence[float] | np.ndarray | None = None,
    *,
    max_joint_step: float = MAX_JOINT_STEP,
    yaw_free: bool = False,
    tol: float = 1e-4,
) -> JointPath | CartesianFailure:
    """Joints for every pose of `poses` by chained IK, or where and why that fails.

    The first pose's IK starts from `q_first` (if given), each later one from
    the previous solution. Fails when a pose has no IK solution or when a joint
    moves more than `max_joint_step` (rad) from the previous pose's solution.
    `yaw_free` and `tol` are `Arm.ik`'s.
    """
    joints: list[np.ndarray] = []
    previous = None if q_first is None else np.asarray(q_first, dtype=float)
    for index, pose in enumerate(poses):
        if previous is None:
            q = arm.ik(pose, None, yaw_free=yaw_free, tol=tol)
        else:  # the poses are 1 cm apart: the previous solution is a step away
            q = arm.ik_near(pose, previous, yaw_free=yaw_free, tol=tol)
        if q is None:
            return CartesianFailure(f"no IK solution for pose {index} of {len(poses)}", index)
        if joints:
            jump = np.abs(q - joints[-1])
            if jump.max() > max_joint_step and not _smooth_between(arm, joints[-1], q, poses[index - 1], pose):
                joint = arm.joint_names[int(jump.argmax())]
                return CartesianFailure(
                    f"joint jump at pose {index} of {len(poses)}: {joint} moves {jump.max():.3f} rad "
                    f"(limit {max_joint_step:g} rad)",
                    index,
                )
        joints.append(q)
        previous = q
    return JointPath([np.array(p, dtype=float) for p in poses], np.array(joints))


MIDWAY_TOL = 0.002
"""m: how far the effector may stray from the straight line halfway between two configurations whose joints
moved more than `max_joint_step` (near the base's axis joint 1 swings fast while the hand moves little)."""


MIDWAY_TURN_TOL = 0.02
"""How far (largest entry of the rotation matrices' difference, about rad) the effector's orientation halfway
between two such configurations may stray from the orientation turned evenly from one pose to the next."""


def _smooth_between(arm: Arm, q_a: np.ndarray, q_b: np.ndarray, pose_a: np.ndarray, pose_b: np.ndarray) -> bool:
    """Whether the joint-space line from q_a to q_b keeps the effector on the straight line between its poses,
    turned evenly from the one's orientation to the other's.

    A large joint step is then a fast but continuous motion (near a singularity), not a switch of IK branch. The
    orientation is compared with the even turn between the poses, not with the first pose's: along a turning
    contact (a hook pulling a body through 70 deg, 2.4 deg between poses 1 cm apart) the first pose's orientation
    is 0.04 rad from the next one's, so every step near a singularity was taken for a branch switch.
    """
    turn = matrix_rotvec(pose_a[:3, :3].T @ pose_b[:3, :3])
    for s in (0.25, 0.5, 0.75):
        wanted = pose_a[:3, 3] + s * (pose_b[:3, 3] - pose_a[:3, 3])
        found = arm.fk(q_a + s * (q_b - q_a))
        if np.linalg.norm(found[:3, 3] - wanted) > MIDWAY_TOL:
            return False
        if np.abs(found[:3, :3] - pose_a[:3, :3] @ rotvec_matrix(*(s * turn))).max() > MIDWAY_TURN_TOL:
            return False
    return True


def approach_joints(
    arm: Arm,
    contact: np.ndarray,
    standoff: float,
    q_contact: Sequence[float] | np.ndarray | None = None,
    *,
    step: float = APPROACH_STEP,
    max_joint_step: float = MAX_JOINT_STEP,
    yaw_free: bool = False,
    direction: np.ndarray | None = None,
) -> JointPath | CartesianFailure:
    """The approach to `contact` in joints, pre-contact pose first, contact last.

    Solved from the contact outward (its IK seeded by `q_contact`, e.g. the
    plan's configuration at the contact), so the contact configuration is the
    one the plan chose and the chain follows it back to the stand-off. A
    failure's `index` counts poses from the pre-contact pose.
    """
    poses = retreat_poses(contact, standoff, step, direction)
    outward = follow_poses(arm, poses, q_contact, max_joint_step=max_joint_step, yaw_free=yaw_free)
    if isinstance(outward, CartesianFailure):
        reason = f"{outward.reason} (poses counted from the contact outward)"
        return CartesianFailure(reason, len(poses) - 1 - outward.index)
    return outward.reversed()


def retreat_joints(
    arm: Arm,
    contact: np.ndarray,
    standoff: float,
    q_contact: Sequence[float] | np.ndarray | None = None,
    *,
    step: float = APPROACH_STEP,
    max_joint_step: float = MAX_JOINT_STEP,
    yaw_free: bool = False,
    direction: np.ndarray | None = None,
) -> JointPath | CartesianFailure:
    """The retreat from `contact` in joints: contact first, pre-contact pose last (`approach_joints` reversed)."""
    approach = approach_joints(
        arm,
        contact,
        standoff,
        q_contact,
        step=step,
        max_joint_step=max_joint_step,
        yaw_free=yaw_free,
        direction=direction,
    )
    return approach if isinstance(approach, CartesianFailure) else approach.reversed()


__all__ = [
    "APPROACH_STEP",
    "MAX_JOINT_STEP",
    "CartesianFailure",
    "JointPath",
    "approach_joints",
    "approach_poses",
    "follow_poses",
    "pre_contact_pose",
    "retreat_joints",
    "retreat_poses",
]
