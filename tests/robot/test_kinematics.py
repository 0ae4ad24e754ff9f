"""Forward kinematics and the Jacobian, checked against an independent numpy composition of Franka's
published modified-DH table.
"""

from __future__ import annotations

import numpy as np
from panda_fixtures import (
    FINGERTIP,
    LOWER,
    UPPER,
    arm_fixture,  # noqa: F401 (the `arm` fixture)
    dh_effector,
    panda_robot,
    transform,
)
from scipy.spatial.transform import Rotation

from vkgl.robot import Arm


def test_fk_matches_the_dh_table_at_zero_and_at_random_joints(arm: Arm) -> None:
    rng = np.random.default_rng(7)
    for q in [np.zeros(7), *rng.uniform(LOWER, UPPER, (20, 7))]:
        np.testing.assert_allclose(arm.fk(q), dh_effector(q), atol=1e-9)


def test_fk_at_zero_is_the_known_panda_pose(arm: Arm) -> None:
    # All joints at zero: the arm stands straight up, the flange 0.926 m high and 8.8 cm forward,
    # pointing down; the effector frame is 10.3 cm lower with its z axis up.
    pose = arm.fk(np.zeros(7))
    np.testing.assert_allclose(pose[:3, 3], [0.088, 0.0, 0.926 - FINGERTIP], atol=1e-9)
    np.testing.assert_allclose(pose[:3, 2], [0, 0, 1], atol=1e-9)


def test_fk_applies_the_base_pose() -> None:
    base = transform(Rotation.from_euler("z", 90, degrees=True).as_matrix(), (0.1, -0.2, 0.05))
    moved = Arm.load(panda_robot(), "fingertip", base)
    q = np.array([0.3, -0.2, 0.1, -2.0, 0.2, 1.9, 0.5])
    np.testing.assert_allclose(moved.fk(q), base @ dh_effector(q), atol=1e-9)


def test_jacobian_is_the_derivative_of_fk(arm: Arm) -> None:
    q = np.array([0.2, -0.4, 0.3, -2.1, 0.1, 1.8, 0.4])
    jac = arm.jacobian(q)
    step = 1e-6
    for k in range(7):
        dq = np.zeros(7)
        dq[k] = step
        ahead, behind = arm.fk(q + dq), arm.fk(q - dq)
        np.testing.assert_allclose(jac[:3, k], (ahead[:3, 3] - behind[:3, 3]) / (2 * step), atol=1e-6)
        spin = Rotation.from_matrix(ahead[:3, :3] @ behind[:3, :3].T).as_rotvec() / (2 * step)
        np.testing.assert_allclose(jac[3:, k], spin, atol=1e-6)
