"""Loading the stdlib Panda URDF with DART."""

from __future__ import annotations

import numpy as np
from panda_fixtures import LOWER, UPPER, URDF

from vkgl.robot import load_skeleton


def test_dart_loads_the_urdf_with_the_published_joints_and_limits() -> None:
    skeleton = load_skeleton(URDF)
    names = [skeleton.getBodyNode(i).getName() for i in range(skeleton.getNumBodyNodes())]
    assert [f"panda_link{i}" for i in range(9)] + ["panda_hand", "panda_leftfinger", "panda_rightfinger"] == names
    assert skeleton.getNumDofs() == 9
    assert [skeleton.getDof(i).getName() for i in range(7)] == [f"panda_joint{i}" for i in range(1, 8)]
    np.testing.assert_allclose(skeleton.getPositionLowerLimits()[:7], LOWER)
    np.testing.assert_allclose(skeleton.getPositionUpperLimits()[:7], UPPER)
    assert all(skeleton.getBodyNode(i).getMass() > 0 for i in range(skeleton.getNumBodyNodes()))
    assert all(skeleton.getBodyNode(i).getNumShapeNodes() > 0 for i in range(8))  # links 0-7 have shapes
    assert 15.0 < skeleton.getMass() < 25.0  # the real arm weighs about 18 kg


def test_the_fingers_slide_apart_along_the_hands_y_axis_up_to_an_8_cm_opening() -> None:
    skeleton = load_skeleton(URDF)
    hand = skeleton.getBodyNode("panda_hand")
    for name, side in (("panda_finger_joint1", 1.0), ("panda_finger_joint2", -1.0)):
        joint = skeleton.getJoint(name)
        assert joint.getType() == "PrismaticJoint" and joint.getParentBodyNode().getName() == "panda_hand"
        assert (joint.getPositionLowerLimit(0), joint.getPositionUpperLimit(0)) == (0.0, 0.04)
        assert joint.getForceUpperLimit(0) == 70.0
        finger = joint.getChildBodyNode()
        before = finger.getTransform(hand).translation()
        joint.setPosition(0, 0.04)
        moved = finger.getTransform(hand).translation() - before
        np.testing.assert_allclose(moved, [0.0, side * 0.04, 0.0], atol=1e-12)
