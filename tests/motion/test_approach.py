"""Approach and retreat: the stand-off along the contact's -x, 5 mm steps, chained IK without jumps."""

from __future__ import annotations

import numpy as np
import pytest
from panda_fixtures import panda_robot

from vkgl.motion.approach import (
    CartesianFailure,
    JointPath,
    approach_joints,
    approach_poses,
    follow_poses,
    pre_contact_pose,
    retreat_joints,
    retreat_poses,
)
from vkgl.robot import Arm


@pytest.fixture(scope="module")
def arm() -> Arm:
    return Arm.load(panda_robot(), "fingertip", np.eye(4))


def contact_at(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    """An effector frame at (x, y, z): x axis (the push) horizontal at `yaw`, z up."""
    c, s = np.cos(yaw), np.sin(yaw)
    pose = np.eye(4)
    pose[:3, :3] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    pose[:3, 3] = (x, y, z)
    return pose


def test_approach_poses_run_from_the_standoff_to_the_contact() -> None:
    contact = contact_at(0.5, 0.1, 0.25, yaw=0.4)  # a tall body: touched 25 cm up, from the side
    poses = approach_poses(contact, 0.03)
    assert np.array_equal(poses[-1], contact)
    assert np.allclose(poses[0], pre_contact_pose(contact, 0.03))
    assert np.allclose(poses[0][:3, 3], contact[:3, 3] - 0.03 * contact[:3, 0])
    positions = np.array([p[:3, 3] for p in poses])
    gaps = np.linalg.norm(np.diff(positions, axis=0), axis=1)
    assert gaps.max() <= 0.005 + 1e-12 and np.isclose(gaps.sum(), 0.03)
    assert np.allclose(positions[:, 2], 0.25)  # at contact height all the way
    assert all(np.array_equal(p[:3, :3], contact[:3, :3]) for p in poses)
    retreat = retreat_poses(contact, 0.03)
    assert np.array_equal(retreat[0], contact) and np.allclose(retreat[-1], poses[0])


def test_approach_in_joints_ends_at_the_contact(arm: Arm) -> None:
    contact = contact_at(0.55, 0.05, 0.12)
    path = approach_joints(arm, contact, 0.04)
    assert isinstance(path, JointPath), path
    assert len(path.joints) == len(path.poses) == 9
    assert np.array_equal(path.poses[-1], contact)
    for q, pose in zip(path.joints, path.poses):
        assert np.linalg.norm(arm.fk(q)[:3, 3] - pose[:3, 3]) < 1e-3
        assert (q >= arm.lower).all() and (q <= arm.upper).all()
    assert np.abs(np.diff(path.joints, axis=0)).max() < 0.05  # smooth: no jump
    retreat = retreat_joints(arm, contact, 0.04)
    assert isinstance(retreat, JointPath)
    assert np.array_equal(retreat.joints, path.joints[::-1])


def test_the_plan_configuration_seeds_the_contact(arm: Arm) -> None:
    contact = contact_at(0.45, -0.15, 0.1, yaw=-0.3)
    q_contact = arm.ik(contact)
    path = approach_joints(arm, contact, 0.02, q_contact)
    assert isinstance(path, JointPath)
    assert np.abs(path.joints[-1] - q_contact).max() < 1e-3


def test_jumps_and_unreachable_poses_are_rejected(arm: Arm) -> None:
    contact = contact_at(0.55, 0.05, 0.12)
    # a large joint step is accepted when the effector stays on the straight line between the poses (a fast
    # but continuous motion) ...
    smooth = follow_poses(arm, approach_poses(contact, 0.02), max_joint_step=1e-5)
    assert not isinstance(smooth, CartesianFailure)
    # ... and rejected when it leaves it (two poses 15 cm apart: the joint-space line bows away from the line)
    far_apart = contact.copy()
    far_apart[:3, 3] += (0.0, 0.15, 0.1)
    jumpy = follow_poses(arm, [contact, far_apart], max_joint_step=1e-5)
    assert isinstance(jumpy, CartesianFailure) and "joint jump at pose 1" in jumpy.reason
    far = approach_joints(arm, contact_at(1.5, 0.0, 0.1), 0.02)
    assert isinstance(far, CartesianFailure) and "no IK solution" in far.reason


def test_a_turning_path_is_smooth_where_the_hand_turns_evenly(arm: Arm) -> None:
    # a hook pulling a body round an arc turns the hand 2 to 3 deg between poses 1 cm apart: a large joint step
    # there is continuous when the hand turns evenly from one pose's orientation to the next (it was taken for a
    # branch switch, compared with the first pose's orientation)
    turning = [contact_at(0.55 - 0.01 * k, 0.05, 0.12, yaw=np.radians(2.5 * k)) for k in range(4)]
    smooth = follow_poses(arm, turning, max_joint_step=1e-5)
    assert not isinstance(smooth, CartesianFailure), smooth
    # turned and 15 cm away, the joint-space line bows away from the straight one: still a jump
    swung = [turning[0], contact_at(0.55, 0.2, 0.22, yaw=np.radians(7.5))]
    jumpy = follow_poses(arm, swung, max_joint_step=1e-5)
    assert isinstance(jumpy, CartesianFailure) and "joint jump at pose 1" in jumpy.reason
