"""The effector frame convention: one exact Rx(180 deg)."""

from __future__ import annotations

import numpy as np
from panda_fixtures import arm_fixture  # noqa: F401 (the `arm` fixture)
from scipy.spatial.transform import Rotation

from vkgl.robot import Arm, rx_pi


def test_rx_pi_is_the_rotation_by_half_a_turn_about_x_written_out_exactly() -> None:
    m = rx_pi()
    np.testing.assert_allclose(m[:3, :3], Rotation.from_euler("x", np.pi).as_matrix(), atol=1e-15)
    assert set(np.unique(m)) == {-1.0, 0.0, 1.0}  # exact: no cos(pi) residues
    m[0, 0] = 7.0
    assert rx_pi()[0, 0] == 1.0  # a fresh array each call


def test_the_arm_places_its_effector_frame_with_rx_pi(arm: Arm) -> None:
    np.testing.assert_array_equal(arm.link_offset[:3, :3], rx_pi()[:3, :3])  # the fingertip offset is a translation
