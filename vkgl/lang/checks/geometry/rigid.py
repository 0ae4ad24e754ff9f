"""Rigid transforms for the scene checks, in plain Python: a rotation (3x3 rows) and a translation.

The scene checks decide diagnostics only (nothing they compute enters the IR),
and a scene has a few bodies of a few pieces each: plain floats do it without
numpy, whose import alone was a third of a `vkgc check`. The poses that flow
into plans (`vkgl.lang.ir.geometry`: where bodies start, relative placements
and goals) are computed there, with numpy, as before; these agree with them up
to rounding in the last bits, far below the millimetre the checks measure in.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.nodes import JOINT_LIFT
from vkgl.rotations import Matrix3, rotvec_matrix

Vec3 = tuple[float, float, float]
Rigid = tuple[Matrix3, Vec3]
"""A rigid transform: x -> rotation x + translation."""

IDENTITY3: Matrix3 = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
IDENTITY: Rigid = (IDENTITY3, (0.0, 0.0, 0.0))


def rotate(rotation: Matrix3, v: Sequence[float]) -> Vec3:
    """`rotation` applied to the vector `v`."""
    x, y, z = v
    r0, r1, r2 = rotation
    return (r0[0] * x + r0[1] * y + r0[2] * z, r1[0] * x + r1[1] * y + r1[2] * z, r2[0] * x + r2[1] * y + r2[2] * z)


def transposed(rotation: Matrix3) -> Matrix3:
    """The transpose (the inverse of a rotation)."""
    r0, r1, r2 = rotation
    return ((r0[0], r1[0], r2[0]), (r0[1], r1[1], r2[1]), (r0[2], r1[2], r2[2]))


def product(a: Matrix3, b: Matrix3) -> Matrix3:
    """The matrix product a b."""
    bt = transposed(b)
    return (
        (_dot(a[0], bt[0]), _dot(a[0], bt[1]), _dot(a[0], bt[2])),
        (_dot(a[1], bt[0]), _dot(a[1], bt[1]), _dot(a[1], bt[2])),
        (_dot(a[2], bt[0]), _dot(a[2], bt[1]), _dot(a[2], bt[2])),
    )


def compose(a: Rigid, b: Rigid) -> Rigid:
    """The transform a b (b first, then a)."""
    rotation, translation = a
    return product(rotation, b[0]), add(rotate(rotation, b[1]), translation)


def inverse(pose: Rigid) -> Rigid:
    """The inverse transform."""
    back = transposed(pose[0])
    x, y, z = rotate(back, pose[1])
    return back, (-x, -y, -z)


def add(a: Sequence[float], b: Sequence[float]) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a: Sequence[float], b: Sequence[float]) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scaled(v: Sequence[float], k: float) -> Vec3:
    return (v[0] * k, v[1] * k, v[2] * k)


def norm(values: Sequence[float]) -> float:
    """The Euclidean length of a vector of any length."""
    return math.sqrt(sum(v * v for v in values))


def _dot(a: Sequence[float], b: Sequence[float]) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def finite(pose: Rigid) -> bool:
    """True when every number of `pose` is finite."""
    rotation, translation = pose
    return all(math.isfinite(v) for v in (*rotation[0], *rotation[1], *rotation[2], *translation))


def pose_rigid(pose: ir.Pose) -> Rigid | None:
    """`pose` as a transform (a 2-d position has z = 0, as `ir.Pose.matrix` pads it), or None when a value is
    not finite or the position has more than 3 components (their errors are reported)."""
    values = pose.position.values
    if len(values) > 3:  # `at (0, 0, 0.7, 0) m`: E204, reported by the builder
        return None
    x, y, z = (*values, 0.0, 0.0, 0.0)[:3]
    try:
        rotation = pose.rotation_matrix()
    except ValueError:  # roll-pitch-yaw of the wrong length: reported by the builder
        return None
    found = (rotation, (float(x), float(y), float(z)))
    return found if finite(found) else None


def lifted(pose: Rigid, lift: float = JOINT_LIFT) -> Rigid:
    """`pose` raised by `lift` along the world's z (`vkgl.lang.ir.geometry.lifted`)."""
    x, y, z = pose[1]
    return pose[0], (x, y, z + lift)


def joint_pose(joint: ir.Joint, rest: Rigid, value: float) -> Rigid:
    """Where a body that started at `rest` is once its joint is at `value` (m or rad), as
    `vkgl.lang.ir.geometry.joint_pose` puts it. The joint's axis must be 3 finite numbers, not all zero."""
    length = norm(joint.axis.values)
    axis = scaled(joint.axis.values, 1.0 / length)
    if joint.type == "prismatic":
        return compose(rest, (IDENTITY3, scaled(axis, value)))
    through = tuple(joint.through.values) if joint.through is not None else (0.0, 0.0, 0.0)
    rotation = rotvec_matrix(*scaled(axis, value))
    return compose(rest, (rotation, sub(through, rotate(rotation, through))))


__all__ = [
    "IDENTITY",
    "Rigid",
    "Vec3",
    "compose",
    "finite",
    "inverse",
    "joint_pose",
    "lifted",
    "norm",
    "pose_rigid",
    "product",
    "rotate",
]
