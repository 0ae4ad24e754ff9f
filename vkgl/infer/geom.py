"""Small geometric and statistical helpers of the constraint models (weighted PCA, rotations, angles)."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.infer.data import EdgeData


def weighted_mean(x: np.ndarray, w: np.ndarray) -> np.ndarray:
    return (w[:, None] * x).sum(axis=0) / max(float(w.sum()), 1e-12)


def weighted_pca(x: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Weighted mean, eigenvalues (ascending) and eigenvectors (columns) of the weighted covariance."""
    mean = weighted_mean(x, w)
    d = x - mean
    C = (d * w[:, None]).T @ d / max(float(w.sum()), 1e-12)
    vals, vecs = np.linalg.eigh(C)
    return mean, vals, vecs


def mean_rotation(data: EdgeData, w: np.ndarray) -> Rotation:
    if not data.any_rot:
        return Rotation.identity()
    idx = data.rot_index
    return data.observed_rotations.mean(weights=np.maximum(w[idx], 1e-9))


def single_rotation(r: Rotation) -> Rotation:
    """A constant prediction: one rotation (as a stack of one) that applies to every sample."""
    return Rotation.from_quat(r.as_quat()[None, :])


def excursion(s: np.ndarray, w: np.ndarray) -> float:
    """The signed state of the inlier sample farthest from the start: which way the motion went."""
    trusted = w > 0.5
    if not trusted.any():
        trusted = np.ones_like(w, dtype=bool)
    k = np.flatnonzero(trusted)[np.argmax(np.abs(s[trusted]))]
    return float(s[k])


def orient_positive(axis: np.ndarray, s: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if excursion(s - s[0], w) < 0:
        return -axis, -s
    return axis, s


def angles_about(q_perp: np.ndarray, axis: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Angle of each vector (perpendicular to `axis`) about `axis`, from the direction of `ref`."""
    e1 = ref - (ref @ axis) * axis
    e1 /= np.linalg.norm(e1)
    e2 = cross(axis, e1)
    return np.arctan2(q_perp @ e2, q_perp @ e1)


def wrap_angle(angle: np.ndarray) -> np.ndarray:
    """Angles into [-pi, pi)."""
    return (angle + np.pi) % (2 * np.pi) - np.pi


def angle_between(a: Rotation, b: Rotation) -> np.ndarray:
    """Rotation angle of a^-1 b per sample, from the quaternions' dot product.

    Same as `(a.inv() * b).magnitude()`, without composing the rotations (this
    runs for every model on every sample; 2 acos|<qa, qb>| is exact enough here).
    """
    dot = np.abs(np.sum(a.as_quat() * b.as_quat(), axis=-1))
    return 2.0 * np.arccos(np.minimum(dot, 1.0))


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product over the last axis (np.cross is slow for the small arrays used here)."""
    return np.stack(
        [
            a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1],
            a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
            a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0],
        ],
        axis=-1,
    )


def perpendicular(a: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to `a` (deterministic)."""
    helper = np.eye(3)[int(np.argmin(np.abs(a)))]
    u = cross(a, helper)
    return u / np.linalg.norm(u)
