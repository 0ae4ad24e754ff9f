"""`vkgl.rotations` is SciPy's `Rotation`, bit for bit, so that neither `vkgc check` nor `vkgc solve` imports SciPy.

`Pose.matrix()`, the checker's scene geometry, `joint_pose`, the planner's rollouts and screw motions, and
the arm's IK compute their rotations with `vkgl.rotations`; they used SciPy's `Rotation` for the same numbers
before. Plans must not change with the shortcut, so these tests hold every result to SciPy's to the last
bit, as tests/lang/ir/test_geometry_vertices.py holds the vertices to trimesh's.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from vkgl.lang.ir.nodes import Pose, Quantity, Vector
from vkgl.rotations import (
    axis_matrix,
    matrix_rotvec,
    rotvec_matrices,
    rotvec_matrix,
    rpy_matrix,
    yaw_matrix,
    yawed_points,
)

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


@settings(max_examples=200, deadline=None)
@given(st.integers(min_value=0, max_value=2), st.one_of(ANGLES, SMALL))
def test_a_turn_about_an_axis_is_scipys(axis: int, angle: float) -> None:
    assert _same(axis_matrix(axis, angle), Rotation.from_euler("xyz"[axis], angle).as_matrix())


@settings(max_examples=100, deadline=None)
@given(st.lists(st.one_of(ANGLES, SMALL), min_size=1, max_size=20), st.tuples(ANGLES, ANGLES, ANGLES))
def test_many_rotation_vectors_are_scipys(values: list[float], axis: tuple[float, float, float]) -> None:
    rotvecs = np.outer(values, axis)
    assert np.array_equal(rotvec_matrices(rotvecs), Rotation.from_rotvec(rotvecs).as_matrix())


def _matrices() -> st.SearchStrategy[np.ndarray]:
    """Rotation matrices as the planner makes them: exact ones, products of a few, and slightly off ones
    (orthogonalised by SVD first), of small, large and half-turn angles."""
    vectors = st.one_of(st.tuples(ANGLES, ANGLES, ANGLES), st.tuples(SMALL, SMALL, SMALL))
    exact = vectors.map(lambda v: Rotation.from_rotvec(list(v)).as_matrix())
    products = st.tuples(exact, exact).map(lambda pair: pair[0] @ pair[1].T)
    noisy = st.tuples(exact, st.floats(min_value=-1e-9, max_value=1e-9)).map(lambda p: p[0] + p[1] * np.ones((3, 3)))
    half_turns = st.sampled_from([np.diag([1.0, -1.0, -1.0]), np.diag([-1.0, 1.0, -1.0]), np.diag([-1.0, -1.0, 1.0])])
    return st.one_of(exact, products, noisy, half_turns, st.just(np.eye(3)))


@settings(max_examples=400, deadline=None)
@given(_matrices())
def test_a_matrixs_rotation_vector_is_scipys(matrix: np.ndarray) -> None:
    assert np.array_equal(matrix_rotvec(matrix), Rotation.from_matrix(matrix).as_rotvec())


def test_a_mirror_is_refused_as_scipy_refuses_it() -> None:
    for matrix in (-np.eye(3), np.zeros((3, 3))):
        with pytest.raises(ValueError):
            Rotation.from_matrix(matrix)
        with pytest.raises(ValueError):
            matrix_rotvec(matrix)


@settings(max_examples=100, deadline=None)
@given(ANGLES, st.integers(min_value=1, max_value=40), st.integers(min_value=0, max_value=2**32 - 1))
def test_points_turned_about_z_are_scipys(yaw: float, count: int, seed: int) -> None:
    points = np.random.default_rng(seed).normal(size=(count, 3))
    assert np.array_equal(yawed_points(yaw, points), Rotation.from_euler("z", yaw).apply(points))
    assert np.array_equal(yawed_points(yaw, points[0]), Rotation.from_euler("z", yaw).apply(points[0]))
