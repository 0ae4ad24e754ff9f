"""Rotations without SciPy, SciPy's to the last bit.

Importing `scipy.spatial.transform` costs about a quarter of a second: more
than the rest of `vkgc check`, and half of what `vkgc solve` may take. What
vkgl needs of SciPy's `Rotation` is computed here with `math`, exactly as
SciPy's compiled backend computes it: the same quaternions, composed, turned
into a matrix and back with the same operations in the same order, so the
results are SciPy's to the last bit and no plan changes
(tests/test_rotations.py compares them): a rotation about x, y or z, a
roll-pitch-yaw, a rotation vector (one or many) as a matrix, a matrix as its
rotation vector, and a turn about z applied to points.

Matrices are 3x3 tuples of rows; callers that want arrays wrap them. The
two functions that take or return arrays import numpy when called (the front
end imports this module and needs none of them).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

Matrix3 = tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
Quaternion = tuple[float, float, float, float]  # (x, y, z, w), SciPy's order

_SMALL_ANGLE = 1e-3  # rad: below it SciPy takes sin(a/2)/a from its Taylor series


def yaw_matrix(yaw: float) -> Matrix3:
    """The rotation by `yaw` (rad) about z: `Rotation.from_euler("z", yaw).as_matrix()`."""
    return _quaternion_matrix(_elementary(2, yaw))


def axis_matrix(axis: int, angle: float) -> Matrix3:
    """The rotation by `angle` (rad) about x, y or z (`axis` 0, 1 or 2): `Rotation.from_euler("xyz"[axis],
    angle).as_matrix()`."""
    return _quaternion_matrix(_elementary(axis, angle))


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


def rotvec_matrices(rotvecs: np.ndarray) -> np.ndarray:
    """The k x 3 x 3 matrices of k rotation vectors (k x 3): `Rotation.from_rotvec(rotvecs).as_matrix()`."""
    import numpy as np

    rows = np.asarray(rotvecs, dtype=float).reshape(-1, 3).tolist()
    try:
        flat = _rotvec_entries(rows)
    except ValueError:  # an infinite angle (`math.sin` raises): row by row, which gives NaN as SciPy does
        return np.array([rotvec_matrix(*row) for row in rows], dtype=float).reshape(-1, 3, 3)
    return np.array(flat, dtype=float).reshape(-1, 3, 3)


def _rotvec_entries(rows: list[list[float]]) -> list[float]:
    """The entries of `rotvec_matrix` of each row, row-major, one after the other: the same operations inlined
    (the task-space optimiser's rollouts ask for hundreds of thousands). Raises ValueError at an infinite angle."""
    sin, cos, sqrt = math.sin, math.cos, math.sqrt
    flat: list[float] = []
    for x0, y0, z0 in rows:
        angle = sqrt(x0 * x0 + y0 * y0 + z0 * z0)
        if angle <= _SMALL_ANGLE:
            squared = angle * angle
            scale = 0.5 - squared / 48 + squared * squared / 3840
        else:
            scale = sin(angle / 2) / angle
        x, y, z, w = x0 * scale, y0 * scale, z0 * scale, cos(angle / 2)
        x2, y2, z2, w2 = x * x, y * y, z * z, w * w
        xy, zw, xz, yw, yz, xw = x * y, z * w, x * z, y * w, y * z, x * w
        flat += (
            x2 - y2 - z2 + w2,
            2 * (xy - zw),
            2 * (xz + yw),
            2 * (xy + zw),
            -x2 + y2 - z2 + w2,
            2 * (yz - xw),
            2 * (xz - yw),
            2 * (yz + xw),
            -x2 - y2 + z2 + w2,
        )
    return flat


def matrix_rotvec(matrix: np.ndarray) -> np.ndarray:
    """The rotation vector of a 3x3 rotation matrix: `Rotation.from_matrix(matrix).as_rotvec()`.

    As SciPy: a matrix whose determinant is not positive is refused
    (ValueError), one that is not orthogonal to 1e-12 is first replaced by the
    nearest orthogonal one (its SVD, numpy's, as SciPy calls it), and the
    quaternion is read off the largest of the diagonal and the trace.
    """
    import numpy as np

    stack = np.array(matrix, dtype=float)
    if stack.shape != (3, 3):
        raise ValueError(f"Expected `matrix` to have shape (3, 3), got {stack.shape}")
    stack = stack[np.newaxis, :, :]
    if np.linalg.det(stack)[0] <= 0:
        raise ValueError(f"Non-positive determinant (left-handed or null coordinate frame) in matrix {stack[0]}")
    gramian = stack @ np.transpose(stack, (0, 2, 1))
    if not np.all(np.isclose(gramian, np.eye(3), atol=1e-12)):
        u, _, vt = np.linalg.svd(stack[np.array([0]), :, :])
        stack[np.array([0]), :, :] = u @ vt
    x, y, z, w = _canonical(_matrix_quaternion(stack[0].tolist()))
    angle = 2 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
    if angle <= _SMALL_ANGLE:
        squared = angle * angle
        scale = 2 + squared / 12 + 7 * squared * squared / 2880
    else:
        scale = angle / math.sin(angle / 2)
    return np.array([scale * x, scale * y, scale * z])


def yawed_points(yaw: float, points: np.ndarray) -> np.ndarray:
    """`points` (n x 3) turned by `yaw` (rad) about z: `Rotation.from_euler("z", yaw).apply(points)`."""
    import numpy as np

    matrix = np.array(yaw_matrix(yaw), dtype=float)[np.newaxis, :, :]
    vectors = np.asarray(points, dtype=float)
    if vectors.ndim == 1:
        return np.matmul(matrix, vectors)[0]
    if len(vectors) == 1:  # SciPy's shortcut for one rotation and one vector
        return np.matmul(matrix, vectors[0])
    return np.matmul(matrix, vectors, axes=[(-2, -1), (-1, -2), (-1, -2)])[0]


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


def _matrix_quaternion(m: list[list[float]]) -> Quaternion:
    """The unit quaternion of an orthogonal matrix, from its largest diagonal entry or its trace (SciPy's)."""
    decision = (m[0][0], m[1][1], m[2][2], m[0][0] + m[1][1] + m[2][2])
    choice = 0
    for index in (1, 2, 3):  # the first largest, as SciPy's _argmax4 (a NaN is never larger)
        if decision[index] > decision[choice]:
            choice = index
    q = [0.0, 0.0, 0.0, 0.0]
    if choice != 3:
        i = choice
        j = (i + 1) % 3
        k = (j + 1) % 3
        q[i] = 1 - decision[3] + 2 * m[i][i]
        q[j] = m[j][i] + m[i][j]
        q[k] = m[k][i] + m[i][k]
        q[3] = m[k][j] - m[j][k]
    else:
        q = [m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1], 1 + decision[3]]
    norm = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if norm == 0:  # SciPy leaves the quaternion as it is
        return (q[0], q[1], q[2], q[3])
    return (q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm)


def _canonical(q: Quaternion) -> Quaternion:
    """The quaternion of the pair (q, -q) with w > 0 (ties broken on x, y, z), so that its angle is at most pi."""
    x, y, z, w = q
    if w < 0 or (w == 0 and (x < 0 or (x == 0 and (y < 0 or (y == 0 and z < 0))))):
        return (x * -1.0, y * -1.0, z * -1.0, w * -1.0)
    return q


def _quaternion_matrix(quaternion: Quaternion) -> Matrix3:
    x, y, z, w = quaternion
    x2, y2, z2, w2 = x * x, y * y, z * z, w * w
    xy, zw, xz, yw, yz, xw = x * y, z * w, x * z, y * w, y * z, x * w
    return (
        (x2 - y2 - z2 + w2, 2 * (xy - zw), 2 * (xz + yw)),
        (2 * (xy + zw), -x2 + y2 - z2 + w2, 2 * (yz - xw)),
        (2 * (xz - yw), 2 * (yz + xw), -x2 - y2 + z2 + w2),
    )
