"""From a `vkg-trials/1` dataset to the two observed edges of each trial.

A trial records the effector in the body frame (`T_ro`, the robot–object edge:
the ACTION) and the body in the world (`T_ow`, the object–world edge: the
MOTION). Inference fits constraint models to each edge separately:

- the action edge is `T_ro` itself (already object-centric);
- the motion edge is the body's pose relative to its first observed sample,
  `T_ow(0)^-1 T_ow(t)`, so that motion parameters come out in the body frame.
  When the orientation of the first sample was not observed the reference
  frame keeps the world's axes (positions relative to the first one).

Partial observations are kept as they are: a NaN rotation block means the
orientation of that sample is unknown (positions alone count), a sample without
a finite position or time is dropped, NaN padding at the end is ignored.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.formats.trials import Trials

MIN_SAMPLES = 3
"""Fewer usable samples than this and an edge is not inferred."""

SIGMA_P_FLOOR = 0.01
"""Smallest position tolerance of the likelihood, m: how far from an ideal joint a motion may stray
and still count as that joint (real mechanisms and trackers wobble by millimetres)."""

SIGMA_R_FLOOR = np.deg2rad(2.0)
"""Smallest orientation tolerance of the likelihood, rad."""

NOISE_P_FLOOR = 0.0005
"""Smallest measurement noise assumed for positions, m (tells motion from jitter)."""

NOISE_R_FLOOR = np.deg2rad(0.25)
"""Smallest measurement noise assumed for orientations, rad."""

_ORTHONORMAL_TOL = 1e-3


class SkipTrial(Exception):
    """A trial cannot be inferred; the message is the per-trial `skipped` reason."""


@dataclass(frozen=True)
class EdgeData:
    """One edge's observed trajectory, ordered in time.

    `p` (n, 3) positions; `has_rot` (n,) whether the orientation of each sample was observed;
    `sigma_p`, `sigma_r`: the tolerance of the likelihood: the noise level
    estimated from the data, but at least `SIGMA_P_FLOOR` / `SIGMA_R_FLOOR`;
    `noise_p`, `noise_r`: the measurement noise alone (what tells motion from
    jitter);
    `plausible` (n,) 1.0 for samples that agree with their neighbours, 0.0 for
    obvious outliers (the starting weights of the robust fits); `rot` the
    rotations as one scipy Rotation (built once: constructing them is not free),
    identity where not observed; `rot_seen` only the observed ones (None if there are none).
    """

    p: np.ndarray
    has_rot: np.ndarray
    sigma_p: float
    sigma_r: float
    noise_p: float
    noise_r: float
    plausible: np.ndarray
    rot: Rotation
    rot_seen: Rotation | None

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.p.shape[0])

    @property
    def any_rot(self) -> bool:
        """Whether at least one orientation was observed."""
        return bool(self.has_rot.any())

    @property
    def observed_rotations(self) -> Rotation:
        """`rot_seen`, for callers that know at least one orientation was observed."""
        if self.rot_seen is None:
            raise ValueError("no orientation was observed")
        return self.rot_seen

    @property
    def rot_index(self) -> np.ndarray:
        """Indices of the samples whose orientation was observed."""
        return np.flatnonzero(self.has_rot)


@dataclass(frozen=True)
class TrialEdges:
    """The two edges of one trial; `action` is None when `T_ro` was not observed.

    `t` holds the times (s) of the motion's samples, in order.
    """

    action: EdgeData | None
    motion: EdgeData
    samples: int
    t: np.ndarray


def edge_data(p: np.ndarray, rot: Rotation, has_rot: np.ndarray) -> EdgeData:
    """An `EdgeData` with the noise level estimated from the trajectory itself.

    `rot` holds one rotation per sample (any value where `has_rot` is false).
    """
    if not has_rot.all():
        quat = rot.as_quat()
        quat[~has_rot] = (0.0, 0.0, 0.0, 1.0)
        rot = Rotation.from_quat(quat)
    noise_p = max(NOISE_P_FLOOR, _noise_of_positions(p))
    noise_r = max(NOISE_R_FLOOR, _noise_of_rotations(rot, has_rot))
    sigma_p = max(SIGMA_P_FLOOR, noise_p)
    sigma_r = max(SIGMA_R_FLOOR, noise_r)
    plausible = _agrees_with_neighbours(p, rot, has_rot, sigma_p, sigma_r)
    rot_seen = None if not has_rot.any() else rot if has_rot.all() else rot[np.flatnonzero(has_rot)]
    return EdgeData(
        p=p,
        has_rot=has_rot,
        sigma_p=sigma_p,
        sigma_r=sigma_r,
        noise_p=noise_p,
        noise_r=noise_r,
        plausible=plausible,
        rot=rot,
        rot_seen=rot_seen,
    )


def trial_edges(trials: Trials, i: int) -> TrialEdges:
    """The action and motion edges of trial `i`; raises SkipTrial with the reason if it cannot be used."""
    if not bool(trials.ok[i]):
        reason = str(trials.reason[i]) or "simulation failed"
        raise SkipTrial(f"not ok: {reason}")
    t = trials.t[i]
    T_ow = trials.T_ow[i]
    usable = np.isfinite(t) & np.isfinite(T_ow[:, :3, 3]).all(axis=1)
    if usable.sum() < MIN_SAMPLES:
        raise SkipTrial(f"{int(usable.sum())} usable sample(s) of the body's motion; at least {MIN_SAMPLES} needed")
    order = np.argsort(t[usable], kind="stable")
    motion = _relative_motion(*_poses(T_ow[usable][order], f"T_ow of trial {i}"))
    action = _action(trials.T_ro[i][usable][order], i)
    return TrialEdges(action=action, motion=motion, samples=int(usable.sum()), t=t[usable][order])


def _action(T_ro: np.ndarray, i: int) -> EdgeData | None:
    seen = np.isfinite(T_ro[:, :3, 3]).all(axis=1)
    if seen.sum() < MIN_SAMPLES:
        return None
    return edge_data(*_poses(T_ro[seen], f"T_ro of trial {i}"))


def _poses(T: np.ndarray, where: str) -> tuple[np.ndarray, Rotation, np.ndarray]:
    """Positions, rotations (identity where not observed) and the observed-rotation mask of 4x4 poses."""
    p = T[:, :3, 3].copy()
    R = T[:, :3, :3].copy()
    has_rot = np.isfinite(R).all(axis=(1, 2))
    R[~has_rot] = np.eye(3)
    gram = np.einsum("nji,njk->nik", R, R) - np.eye(3)
    bad = (np.abs(gram).max(axis=(1, 2)) > _ORTHONORMAL_TOL) | (np.linalg.det(R) <= 0)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise SkipTrial(f"{where}: sample {k} is not a rigid transform (its rotation block is not a rotation)")
    # from_matrix re-orthonormalises, so rounding in the file does not look like rotation noise.
    return p, Rotation.from_matrix(R), has_rot


def _relative_motion(p: np.ndarray, rot: Rotation, has_rot: np.ndarray) -> EdgeData:
    """The body's poses relative to its first sample: T_ow(0)^-1 T_ow(t)."""
    R0 = rot[0] if has_rot[0] else Rotation.identity()
    p_rel = R0.inv().apply(p - p[0])
    return edge_data(p_rel, R0.inv() * rot, has_rot)


def _noise_of_positions(p: np.ndarray) -> float:
    """Per-component noise from second differences (robust to outliers and to smooth motion)."""
    if len(p) < 3:
        return 0.0
    d2 = p[2:] - 2.0 * p[1:-1] + p[:-2]
    # var(x[t+1] - 2 x[t] + x[t-1]) = 6 sigma^2 for white noise; 1.4826 MAD = sigma for a Gaussian.
    return float(1.4826 * np.median(np.abs(d2)) / np.sqrt(6.0))


def _noise_of_rotations(rot: Rotation, has_rot: np.ndarray) -> float:
    idx = np.flatnonzero(has_rot)
    if len(idx) < 3:
        return 0.0
    rots = rot[idx]
    steps = (rots[:-1].inv() * rots[1:]).as_rotvec()
    d2 = steps[1:] - steps[:-1]
    # Differences of consecutive relative rotations: also 6 sigma^2 per component.
    return float(1.4826 * np.median(np.abs(d2)) / np.sqrt(6.0))


_JUMP = 6.0  # a sample this many sigmas away from its neighbourhood's median is an outlier


def _agrees_with_neighbours(
    p: np.ndarray, rot: Rotation, has_rot: np.ndarray, sigma_p: float, sigma_r: float
) -> np.ndarray:
    """1.0 per sample unless it jumps away from its neighbours (an outlier), then 0.0.

    Compares each sample with the running median of its neighbourhood (5
    samples; 3 next to the ends; a linear extrapolation at the ends), for
    positions and for orientations (as rotation vectors about their mean). Needs
    no model, so it seeds the robust fits of every model alike.
    """
    keep = np.ones(len(p))
    keep[_jumps(p, sigma_p)] = 0.0
    idx = np.flatnonzero(has_rot)
    if len(idx) >= 4:
        rots = rot[idx]
        # Rotation vectors about the mean are continuous while the motion stays within 180 deg of it.
        omega = (rots * rots.mean().inv()).as_rotvec()
        keep[idx[_jumps(omega, sigma_r)]] = 0.0
    return keep


def _jumps(x: np.ndarray, sigma: float) -> np.ndarray:
    """Which rows of a smooth sequence `x` (n, d) jump away from their neighbourhood."""
    n = len(x)
    if n < 4:
        return np.zeros(n, dtype=bool)
    idx = np.arange(n)
    # Medians of 5 and of 3 neighbours (np.partition: np.median is slow on small windows).
    med5 = np.partition(x[np.clip(idx[:, None] + np.arange(-2, 3), 0, n - 1)], 2, axis=1)[:, 2]
    med3 = np.partition(x[np.clip(idx[:, None] + np.arange(-1, 2), 0, n - 1)], 1, axis=1)[:, 1]
    expected = med5
    expected[[1, n - 2]] = med3[[1, n - 2]]
    expected[0] = 2 * med3[1] - med3[2]
    expected[-1] = 2 * med3[-2] - med3[-3]
    return np.linalg.norm(x - expected, axis=1) > _JUMP * sigma
