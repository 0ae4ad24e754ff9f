"""Model selection per edge: fit all four models, posterior over types, MAP type.

log p(C | T) = log p(T | C, theta_C) - penalty(C) + const, where the penalty is
BIC-like, 1/2 log(n) per parameter and per state degree of freedom: a fixed
pose costs 6, a prismatic or revolute joint a few parameters plus one state
per sample, free motion six states per sample. So sliding is never "free":
a constrained model wins whenever it explains the samples to within a couple
of noise sigmas. The types' prior is uniform beyond that.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from vkgl.infer.data import EdgeData
from vkgl.infer.models import (
    TYPES,
    ModelFit,
    express_in,
    fit_model,
    independence,
    refine_revolute,
    score_bound,
    start_frame,
)

PRUNE_MARGIN = 30.0
REFINE_MARGIN = 10.0
"""Nats: the revolute fit is refined by least squares when its closed form scores within this of the best."""
"""Nats: a model whose best possible score trails the leader by more is not fitted (posterior < 1e-13)."""


@dataclass
class EdgeInference:
    """The fits of one edge, their posterior and the MAP type (`fits` may lack a pruned revolute model).

    `params` are the MAP model's parameters as the report writes them: in the
    body frame (object-centric) for both edges.
    """

    type: str
    posterior: dict[str, float]
    fits: dict[str, ModelFit]
    params: dict[str, Any]

    @property
    def best(self) -> ModelFit:
        """The MAP model's fit."""
        return self.fits[self.type]

    @property
    def loglik(self) -> float:
        """The MAP model's log-likelihood."""
        return self.best.loglik


def posterior(scores: dict[str, float]) -> dict[str, float]:
    """Normalised posterior over the types from each type's score (log-likelihood minus penalty)."""
    values = np.array([scores[k] for k in TYPES])
    values -= values.max()
    prob = np.exp(values)
    prob /= prob.sum()
    return {k: float(v) for k, v in zip(TYPES, prob)}


def infer_edge(data: EdgeData, *, relative: bool) -> EdgeInference:
    """Fit the models to `data` and pick the MAP type.

    `relative`: the edge is a motion relative to its first sample, so the
    parameters are re-expressed in the model's own estimate of that first pose
    (less noisy than the raw first sample). An action edge (`T_ro`) is already
    in the body frame and keeps its parameters as fitted.

    The revolute model, the costly one, is fitted only when it could win: its
    score cannot exceed a perfect fit minus its penalty, and when that bound is
    far below the best score so far (the edge barely moves) the bound stands
    in for its score (its posterior is then an upper bound, ~0).
    """
    fits = {kind: fit_model(kind, data, relative=relative) for kind in ("fixed", "prismatic", "free")}
    _share_independence(fits, data)
    bound = score_bound("revolute", data, fits["free"])
    if bound > max(f.score for f in fits.values()) - PRUNE_MARGIN:
        fits["revolute"] = fit_model("revolute", data, relative=relative)
        _share_independence(fits, data)
        others = max(fits[k].score for k in ("fixed", "prismatic", "free"))
        if fits["revolute"].score > others - REFINE_MARGIN:
            fits["revolute"] = refine_revolute(fits["revolute"], data)
            _share_independence(fits, data)
    scores = {kind: fits[kind].score if kind in fits else bound for kind in TYPES}
    post = posterior(scores)
    best_type = max(fits, key=lambda k: (post[k], -TYPES.index(k)))
    best = fits[best_type]
    params = express_in(best, start_frame(best, data)) if relative else dict(best.params)
    return EdgeInference(type=best_type, posterior=post, fits=fits, params=params)


def _share_independence(fits: dict[str, ModelFit], data: EdgeData) -> None:
    """One independence factor for all models (so that their scores compare), from
    the residuals of the constrained model that explains the data best."""
    closest = max((k for k in ("fixed", "prismatic", "revolute") if k in fits), key=lambda k: fits[k].loglik)
    share = independence(fits[closest], data)
    for fit in fits.values():
        fit.independence = share
