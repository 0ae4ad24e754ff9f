"""How well a fitted model explains a trajectory: likelihood, inliers, penalty, independence.

Every sample is scored under a mixture: a Gaussian on the position error
(sigma_p, isotropic in 3-d) and on the orientation error (sigma_r, as a
rotation vector), or with probability `OUTLIER_RATIO` an outlier drawn
uniformly from a 1 m cube of positions and from all orientations. A model's
score (its unnormalised log posterior) is its log-likelihood minus a BIC-like
penalty: 1/2 log(n_eff) per parameter and per state degree of freedom, where
n_eff counts the samples that carry independent evidence (`independence`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.infer.data import EdgeData
from vkgl.infer.geom import angle_between

TYPES = ("fixed", "prismatic", "revolute", "free")

OUTLIER_RATIO = 0.05
LOG_OUTLIER_DENSITY_P = 0.0  # uniform over a 1 m cube: density 1 / m^3
LOG_OUTLIER_DENSITY_R = -float(np.log(8.0 * np.pi**2))  # uniform over SO(3), rotation-vector measure
N_PARAMS = {"fixed": 3, "prismatic": 4, "revolute": 6, "free": 0}
"""Parameters of each model's position part; an observed orientation adds 3."""
_CORRELATION_MIN_POWER = 0.01  # residuals below 0.1 sigma rms: too small to judge their correlation
_MIN_EFFECTIVE_SAMPLES = 10.0


@dataclass
class ModelFit:
    """One model fitted to one edge.

    `params` holds the geometric parameters in the edge's frame (numpy arrays):
    fixed {"pose"}, prismatic {"axis", "origin"}, revolute {"axis", "center",
    "radius"}, free {}. `states` are the per-sample displacement (m) or angle
    (rad), zero at the first sample, positive in the direction the motion went.
    """

    type: str
    params: dict[str, Any]
    states: np.ndarray
    pred_p: np.ndarray
    pred_rot: Rotation  # per sample, or a stack of one when constant
    n_params: int
    state_dof: float
    loglik: float = 0.0
    sample_loglik: np.ndarray = field(default_factory=lambda: np.zeros(0))
    inliers: np.ndarray = field(default_factory=lambda: np.zeros(0))
    independence: float = 1.0

    @property
    def effective_samples(self) -> float:
        """How many independent samples the trajectory is worth (n times `independence`)."""
        return max(len(self.pred_p) * self.independence, 2.0)

    @property
    def penalty(self) -> float:
        """The BIC-like cost of the parameters and states, in nats: 1/2 log(n_eff) each."""
        n_eff = self.effective_samples
        dof = self.n_params + self.state_dof * self.independence
        return 0.5 * dof * float(np.log(n_eff))

    @property
    def score(self) -> float:
        """Log-likelihood (counted per independent sample) minus the penalty: the unnormalised log posterior."""
        return self.independence * self.loglik - self.penalty


def score_bound(kind: str, data: EdgeData, free: ModelFit) -> float:
    """An upper bound on the score of model `kind`: a perfect fit (the free model's likelihood) minus its penalty."""
    bound = ModelFit(
        type=kind,
        params={},
        states=np.zeros(0),
        pred_p=data.p,
        pred_rot=data.rot,
        n_params=N_PARAMS[kind] + 3 * data.any_rot,
        state_dof=float(data.n) if kind in ("prismatic", "revolute") else 0.0,
        loglik=free.loglik,
        independence=free.independence,
    )
    return bound.score


def independence(fit: ModelFit, data: EdgeData) -> float:
    """The fraction of samples that carry independent evidence, from the fit's residuals.

    Trackers and physics leave errors that are correlated in time (a slow
    wobble, not white noise); counting each sample as independent evidence
    would make any curve "significant". With the lag-one autocorrelation rho of
    the residuals (in noise sigmas, inliers only), an AR(1) process is worth
    (1 - rho) / (1 + rho) independent samples per sample. Residuals well
    inside the noise level count as independent (the tolerance dominates).
    """
    x = (data.p - fit.pred_p) / data.sigma_p
    if data.rot_seen is not None and fit.type != "free":
        rot_res = np.zeros((data.n, 3))
        idx = data.rot_index
        pred = fit.pred_rot if len(fit.pred_rot) == 1 or len(idx) == data.n else fit.pred_rot[idx]
        rot_res[idx] = (pred.inv() * data.rot_seen).as_rotvec() / data.sigma_r
        x = np.hstack([x, rot_res])
    pair = (fit.inliers[:-1] > 0.5) & (fit.inliers[1:] > 0.5)
    if pair.sum() < 3:
        return 1.0
    a, b = x[:-1][pair], x[1:][pair]
    power = float(np.sum(a * a))
    if power < _CORRELATION_MIN_POWER * a.size:
        return 1.0
    rho = float(np.clip(np.sum(a * b) / power, 0.0, 1.0))
    floor = min(1.0, _MIN_EFFECTIVE_SAMPLES / data.n)
    return max((1.0 - rho) / (1.0 + rho), floor)


def score_fit(fit: ModelFit, data: EdgeData) -> None:
    """Per-sample mixture log-likelihood, total log-likelihood and inlier probabilities."""
    err_p = np.linalg.norm(data.p - fit.pred_p, axis=1)
    err_r = np.zeros(data.n)
    if data.rot_seen is not None and fit.type != "free":
        idx = data.rot_index
        pred = fit.pred_rot if len(fit.pred_rot) == 1 or len(idx) == data.n else fit.pred_rot[idx]
        err_r[idx] = angle_between(pred, data.rot_seen)
    sp, sr = data.sigma_p, data.sigma_r
    rot = data.has_rot.astype(float)
    log_in = -1.5 * np.log(2 * np.pi * sp**2) - 0.5 * (err_p / sp) ** 2
    log_in = log_in + rot * (-1.5 * np.log(2 * np.pi * sr**2) - 0.5 * (err_r / sr) ** 2)
    log_out = LOG_OUTLIER_DENSITY_P + rot * LOG_OUTLIER_DENSITY_R
    a = np.log1p(-OUTLIER_RATIO) + log_in
    b = np.log(OUTLIER_RATIO) + log_out
    ll = np.logaddexp(a, b)
    fit.sample_loglik = ll
    fit.loglik = float(ll.sum())
    fit.inliers = np.exp(a - ll)


def reweighted(fit: ModelFit, weights: np.ndarray) -> np.ndarray:
    """Inlier probabilities as the next weights, while the model explains most samples.

    When it explains almost none, they are all ~0 and carry no information.
    """
    return fit.inliers if fit.inliers.sum() >= 0.5 * len(weights) else weights
