"""The front end's rotation matrices are SciPy's, bit for bit, so that `vkgc check` needs no SciPy.

`Pose.matrix()`, the checker's scene geometry and `joint_pose` compute their rotations with
`vkgl.lang.ir.rotations` (no SciPy import); the planner and the simulator used SciPy's `Rotation` for
the same numbers before. Plans must not change with the shortcut, so these tests hold the matrices to
SciPy's to the last bit, as tests/lang/test_geometry_vertices.py holds the vertices to trimesh's.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from vkgl.lang.ir.nodes import Pose, Quantity, Vector
from vkgl.lang.ir.rotations import rotvec_matrix, rpy_matrix, yaw_matrix

ANGLES = st.floats(min_value=-20.0, max_value=20.0, allow_nan=False)
SMALL = st.floats(min_value=-2e-3, max_value=2e-3, allow_nan=False)  # both sides of SciPy's Taylor branch
SPECIAL = [0.0, -0.0, math.pi, -math.pi, math.pi / 2, math.pi / 4, 2 * math.pi, 1e-300, 5e-4, 1e-3]


def _same(ours: object, scipy_matrix: np.ndarray) -> bool:
    return np.array_equal(np.array(ours), scipy_matrix)


@settings(max_examples=300, deadline=None)
@given(ANGLES)
def test_a_yaw_is_scipys(yaw: float) -> None:
    assert _same(yaw_matrix(yaw), Rotation.from_euler("z", yaw).as_matrix())


@settings(max_examples=300, deadline=None)
@given(ANGLES, ANGLES, ANGLES)
def test_a_roll_pitch_yaw_is_scipys(roll: float, pitch: float, yaw: float) -> None:
    assert _same(rpy_matrix(roll, pitch, yaw), Rotation.from_euler("xyz", [roll, pitch, yaw]).as_matrix())


@settings(max_examples=300, deadline=None)
@given(st.one_of(st.tuples(ANGLES, ANGLES, ANGLES), st.tuples(SMALL, SMALL, SMALL)))
def test_a_rotation_vector_is_scipys(vector: tuple[float, float, float]) -> None:
    assert _same(rotvec_matrix(*vector), Rotation.from_rotvec(list(vector)).as_matrix())


def test_special_angles_are_scipys() -> None:
    for angle in SPECIAL:
        assert _same(yaw_matrix(angle), Rotation.from_euler("z", angle).as_matrix()), angle
        assert _same(rpy_matrix(angle, -angle, angle), Rotation.from_euler("xyz", [angle, -angle, angle]).as_matrix())
        assert _same(rotvec_matrix(0.0, angle, 0.0), Rotation.from_rotvec([0.0, angle, 0.0]).as_matrix()), angle


def test_infinite_angles_give_nan_as_scipy_does() -> None:
    """The checker reports poses that are not finite; an infinite angle must give NaN, never raise."""
    with np.errstate(all="ignore"):
        for matrix in (yaw_matrix(math.inf), rpy_matrix(0.0, -math.inf, 0.0), rotvec_matrix(math.inf, 0.0, 0.0)):
            assert np.isnan(np.array(matrix)).any()


def test_a_poses_matrix_is_its_scipy_rotation() -> None:
    poses = [
        Pose(position=Vector(values=(0.1, 0.2))),
        Pose(position=Vector(values=(0.1, 0.2, 0.3)), yaw=Quantity(value=0.7)),
        Pose(position=Vector(values=(0.1, 0.2, 0.3)), rpy=Vector(values=(0.3, -1.2, 2.5))),
    ]
    for pose in poses:
        assert np.array_equal(pose.matrix()[:3, :3], pose.rotation().as_matrix())
