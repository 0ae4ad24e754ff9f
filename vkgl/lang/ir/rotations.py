"""Rotation matrices for the front end, without SciPy.

Importing `scipy.spatial.transform` costs about a quarter of a second, more
than the rest of `vkgc check`. The front end needs only three kinds of
rotation (a yaw, a roll-pitch-yaw, a rotation vector), so they are computed
here with `math`, exactly as SciPy's `Rotation` computes them: the same
quaternions, composed and turned into a matrix with the same operations in
the same order, so the matrices are SciPy's to the last bit (the back ends,
which may use either, see the same numbers; tests/lang/ir/test_rotations.py
compares them).

Matrices are 3x3 tuples of rows; callers that want arrays wrap them.
"""

from __future__ import annotations

import math

Matrix3 = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
Quaternion = tuple[float, float, float, float]  # (x, y, z, w), SciPy's order

_SMALL_ANGLE = 1e-3  # rad: below it SciPy takes sin(a/2)/a from its Taylor series


def yaw_matrix(yaw: float) -> Matrix3:
    """The rotation by `yaw` (rad) about z: `Rotation.from_euler("z", yaw).as_matrix()`."""
    return _quaternion_matrix(_elementary(2, yaw))


def rpy_matrix(roll: float, pitch: float, yaw: float) -> Matrix3:
    """Extrinsic x, y, z rotations (roll, then pitch, then yaw): `Rotation.from_euler("xyz", rpy).as_matrix()`."""
    quaternion = _elementary(0, roll)
    quaternion = _compose(_elementary(1, pitch), quaternion)
    quaternion = _compose(_elementary(2, yaw), quaternion)
    return _quaternion_matrix(quaternion)


def rotvec_matrix(x: float, y: float, z: float) -> Matrix3:
    """The rotation by |v| (rad) about v = (x, y, z): `Rotation.from_rotvec(v).as_matrix()`."""
    angle = math.sqrt(x * x + y * y + z * z)
    if angle <= _SMALL_ANGLE:
        squared = angle * angle
        scale = 0.5 - squared / 48 + squared * squared / 3840
    else:
        scale = _sin(angle / 2) / angle
    return _quaternion_matrix((x * scale, y * scale, z * scale, _cos(angle / 2)))


def _elementary(axis: int, angle: float) -> Quaternion:
    half = angle / 2.0
    parts = [0.0, 0.0, 0.0]
    parts[axis] = _sin(half)
    return (parts[0], parts[1], parts[2], _cos(half))


def _sin(angle: float) -> float:
    # C's sin (SciPy's) gives NaN for an infinite angle where `math.sin` raises; the checker reports NaN poses.
    return math.nan if math.isinf(angle) else math.sin(angle)


def _cos(angle: float) -> float:
    return math.nan if math.isinf(angle) else math.cos(angle)


def _compose(p: Quaternion, q: Quaternion) -> Quaternion:
    """The quaternion product p q (rotation q first, then p)."""
    cross = (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])
    return (
        p[3] * q[0] + q[3] * p[0] + cross[0],
        p[3] * q[1] + q[3] * p[1] + cross[1],
        p[3] * q[2] + q[3] * p[2] + cross[2],
        p[3] * q[3] - p[0] * q[0] - p[1] * q[1] - p[2] * q[2],
    )


def _quaternion_matrix(quaternion: Quaternion) -> Matrix3:
    x, y, z, w = quaternion
    x2, y2, z2, w2 = x * x, y * y, z * z, w * w
    xy, zw, xz, yw, yz, xw = x * y, z * w, x * z, y * w, y * z, x * w
    return (
        (x2 - y2 - z2 + w2, 2 * (xy - zw), 2 * (xz + yw)),
        (2 * (xy + zw), -x2 + y2 - z2 + w2, 2 * (yz - xw)),
        (2 * (xz - yw), 2 * (yz + xw), -x2 - y2 + z2 + w2),
    )
