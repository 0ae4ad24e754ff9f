"""The scene checks' solids and transforms in plain Python (vkgl/lang/checks/geometry/solids.py, rigid.py).

They were computed with numpy, whose import was a third of a `vkgc check`. The
reference here is that numpy computation (the separating-axis test on arrays,
`ir.Pose.matrix()`, `ir.geometry.joint_pose`): the plain-Python results agree
with it to rounding, and `pieces_depth` with a floor is exact above the floor
and at most the floor below it.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from vkgl.lang.checks.geometry.rigid import Rigid, joint_pose, pose_rigid
from vkgl.lang.checks.geometry.solids import Piece, _box, _prism, depth, pieces_depth
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.geometry import joint_pose as numpy_joint_pose
from vkgl.rotations import rpy_matrix

_angles = st.floats(-math.pi, math.pi)
_offsets = st.floats(-0.3, 0.3)
_sizes = st.floats(0.01, 0.3)


def _numpy_depth(a: Piece, b: Piece) -> float:
    """The separating-axis depth as the scene checks computed it with numpy."""
    va, vb = np.array(a.vertices), np.array(b.vertices)
    ea, eb = np.array(a.edges), np.array(b.edges)
    cross = np.cross(ea[:, None, :], eb[None, :, :]).reshape(-1, 3)
    lengths = np.linalg.norm(cross, axis=1)
    keep = lengths > 1e-9
    axes = np.vstack([np.array(a.normals), np.array(b.normals), cross[keep] / lengths[keep, None]])
    pa, pb = va @ axes.T, vb @ axes.T
    return float((np.minimum(pa.max(axis=0), pb.max(axis=0)) - np.maximum(pa.min(axis=0), pb.min(axis=0))).min())


def _rigid(roll: float, pitch: float, yaw: float, x: float, y: float, z: float) -> Rigid:
    return rpy_matrix(roll, pitch, yaw), (x, y, z)


def _numpy_moved(piece: Piece, pose: Rigid) -> np.ndarray:
    rotation, translation = np.array(pose[0]), np.array(pose[1])
    return np.array(piece.vertices) @ rotation.T + translation


@st.composite
def _pieces(draw: st.DrawFn) -> Piece:
    shape = draw(st.sampled_from(["box", "prism"]))
    local = _box((draw(_sizes), draw(_sizes), draw(_sizes))) if shape == "box" else _prism(draw(_sizes), draw(_sizes))
    pose = _rigid(draw(_angles), draw(_angles), draw(_angles), draw(_offsets), draw(_offsets), draw(_offsets))
    return local.moved(pose)


@settings(max_examples=60, deadline=None)
@given(_pieces(), _pieces())
def test_the_depth_of_two_pieces_is_numpys(a: Piece, b: Piece) -> None:
    assert math.isclose(depth(a, b), _numpy_depth(a, b), rel_tol=1e-9, abs_tol=1e-12)


@settings(max_examples=60, deadline=None)
@given(_pieces(), _pieces(), st.floats(-0.05, 0.05))
def test_a_floor_keeps_the_depths_above_it_exact(a: Piece, b: Piece, floor: float) -> None:
    exact = pieces_depth([a], [b])
    found = pieces_depth([a], [b], floor)
    if exact > floor:
        assert found == exact
    else:
        assert found <= floor


@settings(max_examples=40, deadline=None)
@given(_pieces(), st.tuples(_angles, _angles, _angles), st.tuples(_offsets, _offsets, _offsets))
def test_a_moved_piece_is_numpys_product(piece: Piece, rpy: tuple[float, ...], xyz: tuple[float, ...]) -> None:
    pose = _rigid(*rpy, *xyz)
    assert np.allclose(np.array(piece.moved(pose).vertices), _numpy_moved(piece, pose), rtol=0, atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(_angles, _angles, _angles, st.lists(_offsets, min_size=2, max_size=3))
def test_a_pose_is_its_matrix(roll: float, pitch: float, yaw: float, position: list[float]) -> None:
    pose = ir.Pose(position=ir.Vector(values=tuple(position), unit="m"), rpy=ir.Vector(values=(roll, pitch, yaw)))
    rigid = pose_rigid(pose)
    assert rigid is not None
    matrix = pose.matrix()
    assert np.array_equal(np.array(rigid[0]), matrix[:3, :3])
    assert np.array_equal(np.array(rigid[1]), matrix[:3, 3])


def test_a_pose_that_is_not_finite_or_has_four_components_is_none() -> None:
    nowhere = ir.Pose(position=ir.Vector(values=(math.inf, 0.0), unit="m"))
    four = ir.Pose(position=ir.Vector(values=(0.0, 0.0, 0.7, 0.0), unit="m"))
    assert pose_rigid(nowhere) is None
    assert pose_rigid(four) is None


@settings(max_examples=40, deadline=None)
@given(
    st.sampled_from(["prismatic", "revolute"]),
    st.tuples(_offsets, _offsets, _offsets).filter(lambda v: math.hypot(*v) > 1e-3),
    st.floats(-1.5, 1.5),
    _angles,
    _offsets,
)
def test_a_bodys_pose_on_its_joint_is_the_ir_geometrys(
    kind: Literal["prismatic", "revolute"], axis: tuple[float, float, float], value: float, yaw: float, x: float
) -> None:
    joint = ir.Joint(
        type=kind,
        axis=ir.Vector(values=axis),
        through=ir.Vector(values=(0.1, -0.2, 0.05), unit="m"),
        lower=ir.Quantity(value=-2.0),
        upper=ir.Quantity(value=2.0),
    )
    rest = _rigid(0.0, 0.0, yaw, x, 0.2, 0.4)
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = rest
    expected = numpy_joint_pose(joint, matrix, value)
    rotation, translation = joint_pose(joint, rest, value)
    assert np.allclose(np.array(rotation), expected[:3, :3], rtol=0, atol=1e-12)
    assert np.allclose(np.array(translation), expected[:3, 3], rtol=0, atol=1e-12)
