"""The stdlib Panda for the robot tests: its robot IR, Franka's published DH table and limits, pose helpers.

Test modules that take the `arm` fixture import `arm_fixture` from here (pytest finds fixtures by module).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import STDLIB
from scipy.spatial.transform import Rotation

from vkgl.lang.ir.nodes import Effector, Pose, Robot, Vector
from vkgl.robot import Arm

URDF = STDLIB / "robots" / "panda.urdf"

# Franka's published modified-DH table: (a_{i-1}, d_i, alpha_{i-1}), joints 1..7 and the flange.
DH = [
    (0.0, 0.333, 0.0),
    (0.0, 0.0, -math.pi / 2),
    (0.0, 0.316, math.pi / 2),
    (0.0825, 0.0, math.pi / 2),
    (-0.0825, 0.384, -math.pi / 2),
    (0.0, 0.0, math.pi / 2),
    (0.088, 0.0, math.pi / 2),
    (0.0, 0.107, 0.0),
]
LOWER = [-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973]
UPPER = [2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973]
FINGERTIP = 0.103  # m along the hand's z axis


def fingertip_at(link: str, offset: float) -> Effector:
    return Effector(name="fingertip", link=link, offset=Pose(position=Vector(values=(0, 0, offset), unit="cm")))


def panda_robot(urdf: str = str(URDF), offset: float = FINGERTIP) -> Robot:
    """The IR of stdlib/robots/panda.vkg (built by hand, so these tests do not depend on the parser)."""
    return Robot(
        name="Panda",
        urdf="panda.urdf",
        urdf_resolved=urdf,
        effectors=[fingertip_at("panda_hand", offset)],
    )


@pytest.fixture(scope="module", name="arm")
def arm_fixture() -> Arm:
    """The stdlib Panda with its fingertip, based at the origin."""
    return Arm.load(panda_robot(), "fingertip", np.eye(4))


def transform(rotation: np.ndarray | None = None, translation: tuple[float, float, float] = (0, 0, 0)) -> np.ndarray:
    m = np.eye(4)
    if rotation is not None:
        m[:3, :3] = rotation
    m[:3, 3] = translation
    return m


def dh_effector(q: np.ndarray) -> np.ndarray:
    """The effector frame from the DH table: links, flange, hand at -45 deg, fingertip, Rx(180 deg)."""
    pose = np.eye(4)
    for (a, d, alpha), theta in zip(DH, [*q, 0.0]):
        pose = (
            pose
            @ transform(Rotation.from_euler("x", alpha).as_matrix())
            @ transform(translation=(a, 0, 0))
            @ transform(Rotation.from_euler("z", theta).as_matrix())
            @ transform(translation=(0, 0, d))
        )
    hand = pose @ transform(Rotation.from_euler("z", -math.pi / 4).as_matrix())
    return hand @ transform(translation=(0, 0, FINGERTIP)) @ transform(Rotation.from_euler("x", math.pi).as_matrix())


def hand_down(x: float, y: float, z: float, yaw: float = 0.0) -> np.ndarray:
    """An effector pose with z up (the hand pointing down) at (x, y, z), turned by `yaw`."""
    return transform(Rotation.from_euler("z", yaw).as_matrix(), (x, y, z))


def pose_error(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """(position error m, rotation angle rad) between two poses."""
    angle = Rotation.from_matrix(a[:3, :3] @ b[:3, :3].T).magnitude()
    return float(np.linalg.norm(a[:3, 3] - b[:3, 3])), float(angle)
