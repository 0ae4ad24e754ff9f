"""The ready pose (`Arm.home`)."""

from __future__ import annotations

import numpy as np
from panda_fixtures import arm_fixture  # noqa: F401 (the `arm` fixture)

from vkgl.robot import Arm


def test_home_is_a_ready_pose_with_the_hand_down(arm: Arm) -> None:
    assert arm.joint_names == [f"panda_joint{i}" for i in range(1, 8)]
    assert np.all(arm.lower <= arm.home) and np.all(arm.home <= arm.upper)
    pose = arm.fk(arm.home)
    np.testing.assert_allclose(pose[:3, :3], np.eye(3), atol=1e-4)  # z up, x forward
    assert abs(pose[1, 3]) < 1e-4 and 0.3 < pose[0, 3] < 0.7 and pose[2, 3] > 0.2
