"""The Panda's gripper as its URDF has it: two fingers on prismatic joints, pads at the fingertip point."""

from __future__ import annotations

import numpy as np
import pytest
from panda_fixtures import URDF

from vkgl.robot.gripper import gripper


def test_the_fingers_open_8_cm_with_70_n_and_their_pads_end_at_the_fingertip_point() -> None:
    hand = gripper(str(URDF))
    assert hand.max_opening == pytest.approx(0.08) and hand.effort == pytest.approx(70.0)
    centre, size = hand.pad_box()
    # the pads, closed: 2.8 cm long above the effector frame's origin, 2 to 10 mm behind it along x (the
    # fingertip pad pushes first), 1.2 cm across both fingers
    assert centre == pytest.approx((-0.006, 0.0, 0.014), abs=1e-9)
    assert size == pytest.approx((0.008, 0.012, 0.028), abs=1e-9)
    assert [f.axis @ np.array([0.0, 1.0, 0.0]) for f in hand.fingers] == pytest.approx([1.0, -1.0])
