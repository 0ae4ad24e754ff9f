"""The four constraint models (after Sturm et al.): fixed, prismatic, revolute, free.

Each model explains a trajectory of poses (`EdgeData`) as a function of a few
parameters and one state per sample:

| model     | prediction                                   | parameters                  | state |
|-----------|----------------------------------------------|-----------------------------|-------|
| fixed     | p = p0, R = R0                               | pose (6; none for a motion) | none  |
| prismatic | p = o + s a, R = R0                          | line (4) + orientation (3)  | s, m  |
| revolute  | p = c + Rot(a, q) d, R = Rot(a, q) R0        | circle (6) + orientation (3)| q, rad|
| free      | the observation itself                       | none                        | 6 dof |

(Without observed orientations the orientation parameters drop out.) Fits are
closed form where one exists — the mean pose, principal component analysis of
the positions, a circle in the best-fit plane — made robust by re-weighting
each sample by its probability of being an inlier; the revolute circle is
then refined by scipy least squares with a robust loss.

How a fit is scored: vkgl/infer/likelihood.py; the revolute model:
vkgl/infer/revolute.py.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.infer.data import EdgeData
from vkgl.infer.geom import mean_rotation, orient_positive, single_rotation, weighted_mean, weighted_pca
from vkgl.infer.likelihood import TYPES, ModelFit, independence, reweighted, score_bound, score_fit
from vkgl.infer.revolute import fit_revolute, refine_revolute

__all__ = [
    "TYPES",
    "ModelFit",
    "express_in",
    "fit_model",
    "independence",
    "refine_revolute",
    "score_bound",
    "start_frame",
]

ROBUST_ITERATIONS = 2
_START_SAMPLES = 5


def fit_model(kind: str, data: EdgeData, *, relative: bool = False) -> ModelFit:
    """Fit model `kind` to `data`, robustly (re-weighting by inlier probability), and score it.

    `relative`: `data` is a motion relative to its start, so `fixed` is the sharp
    hypothesis "it stayed where it started" (no parameter to fit) rather than
    "it stayed somewhere".
    """
    if kind == "fixed" and relative:
        fit = _at_rest(data)
        score_fit(fit, data)
        return fit
    fitter = _FITTERS[kind]
    weights = data.plausible.copy()
    if weights.sum() < 3:
        weights = np.ones(data.n)
    # The revolute closed form is re-weighted once more by its refinement (`refine_revolute`).
    iterations = ROBUST_ITERATIONS if kind in ("fixed", "prismatic") else 1
    for _ in range(iterations):
        fit = fitter(data, weights)
        score_fit(fit, data)
        weights = reweighted(fit, weights)
    return fit


def start_frame(fit: ModelFit, data: EdgeData) -> np.ndarray:
    """The model's own estimate of the pose at the first sample (4x4), for object-centric parameters.

    Orientation is identity when none was observed (the edge keeps the world's axes).
    """
    T = np.eye(4)
    T[:3, 3] = fit.pred_p[0]
    if data.any_rot:
        T[:3, :3] = fit.pred_rot[0].as_matrix()  # constant predictions hold a single rotation
    return T


def express_in(fit: ModelFit, T: np.ndarray) -> dict[str, Any]:
    """The fit's parameters expressed in the frame `T` (4x4, given in the edge's frame)."""
    R, t = T[:3, :3], T[:3, 3]
    out: dict[str, Any] = {}
    for key, value in fit.params.items():
        if key == "axis":
            out[key] = R.T @ value
        elif key in ("origin", "center"):
            out[key] = R.T @ (value - t)
        elif key == "pose":
            out[key] = np.linalg.inv(T) @ value
        else:
            out[key] = value
    return out


def _fit_fixed(data: EdgeData, w: np.ndarray) -> ModelFit:
    p0 = weighted_mean(data.p, w)
    R0 = mean_rotation(data, w)
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = R0.as_matrix(), p0
    n = data.n
    return ModelFit(
        type="fixed",
        params={"pose": pose},
        states=np.zeros(0),
        pred_p=np.broadcast_to(p0, (n, 3)).copy(),
        pred_rot=single_rotation(R0),
        n_params=3 + 3 * data.any_rot,
        state_dof=0.0,
    )


def _at_rest(data: EdgeData) -> ModelFit:
    """The body stays at its start pose (median of the first plausible samples, against their noise)."""
    first = np.flatnonzero(data.plausible > 0)[:_START_SAMPLES]
    if len(first) == 0:
        first = np.arange(min(_START_SAMPLES, data.n))
    p0 = np.median(data.p[first], axis=0)
    R0 = Rotation.identity()
    seen = [k for k in first if data.has_rot[k]]
    if seen:
        R0 = data.rot[np.array(seen)].mean()
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = R0.as_matrix(), p0
    return ModelFit(
        type="fixed",
        params={"pose": pose},
        states=np.zeros(0),
        pred_p=np.broadcast_to(p0, (data.n, 3)).copy(),
        pred_rot=single_rotation(R0),
        n_params=0,
        state_dof=0.0,
    )


def _fit_prismatic(data: EdgeData, w: np.ndarray) -> ModelFit:
    mean, _, vecs = weighted_pca(data.p, w)
    axis = vecs[:, -1]
    s = (data.p - mean) @ axis
    axis, s = orient_positive(axis, s, w)
    origin = mean + s[0] * axis
    s = s - s[0]
    R0 = mean_rotation(data, w)
    n = data.n
    return ModelFit(
        type="prismatic",
        params={"axis": axis, "origin": origin},
        states=s,
        pred_p=origin + s[:, None] * axis,
        pred_rot=single_rotation(R0),
        n_params=4 + 3 * data.any_rot,
        state_dof=float(n),
    )


def _fit_free(data: EdgeData, w: np.ndarray) -> ModelFit:
    return ModelFit(
        type="free",
        params={},
        states=np.zeros(0),
        pred_p=data.p.copy(),
        pred_rot=data.rot,
        n_params=0,
        state_dof=float(np.sum(3 + 3 * data.has_rot)),
    )


_FITTERS: dict[str, Callable[[EdgeData, np.ndarray], ModelFit]] = {
    "fixed": _fit_fixed,
    "prismatic": _fit_prismatic,
    "revolute": fit_revolute,
    "free": _fit_free,
}
