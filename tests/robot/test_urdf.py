"""Loading the stdlib Panda URDF with DART."""

from __future__ import annotations

import numpy as np
from panda_fixtures import LOWER, UPPER, URDF

from vkgl.robot import load_skeleton


def test_dart_loads_the_urdf_with_the_published_joints_and_limits() -> None:
    skeleton = load_skeleton(URDF)
    names = [skeleton.getBodyNode(i).getName() for i in range(skeleton.getNumBodyNodes())]
    assert [f"panda_link{i}" for i in range(9)] + ["panda_hand"] == names
    assert skeleton.getNumDofs() == 7
    assert [skeleton.getDof(i).getName() for i in range(7)] == [f"panda_joint{i}" for i in range(1, 8)]
    np.testing.assert_allclose(skeleton.getPositionLowerLimits(), LOWER)
    np.testing.assert_allclose(skeleton.getPositionUpperLimits(), UPPER)
    assert all(skeleton.getBodyNode(i).getMass() > 0 for i in range(skeleton.getNumBodyNodes()))
    assert all(skeleton.getBodyNode(i).getNumShapeNodes() > 0 for i in range(8))  # links 0-7 have shapes
    assert 15.0 < skeleton.getMass() < 25.0  # the real arm weighs about 18 kg
