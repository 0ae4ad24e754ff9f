"""Model selection per edge: fit all four models, posterior over types, MAP type.

log p(C | T) = log p(T | C, theta_C) - penalty(C) + const, where the penalty is
BIC-like, 1/2 log(n) per parameter and per state degree of freedom: a fixed
pose costs 6, a prismatic or revolute joint a few parameters plus one state
per sample, free motion six states per sample. So sliding is never "free":
a constrained model wins whenever it explains the samples to within a couple
of noise sigmas. The types' prior is uniform beyond that.

One exception, for a motion edge: `fixed` there is the sharp hypothesis "the
body stayed where it started", and a body whose pose ended more than
`AT_REST_TOLERANCES` tolerances from its start (`moved_off_start`) is not at
rest, whatever the scores say. Without it a slide of a few tolerances is
called fixed: the per-sample state of the prismatic model costs 1/2 log(n)
nats a sample, more than a residual of 3 tolerances costs the at-rest model
(a 16 x 30 x 6 cm slab pushed 3.7 cm in 3 s: fixed 2430, prismatic 2369).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from vkgl.infer.data import EdgeData
from vkgl.infer.ending import END_WINDOW
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

AT_REST_TOLERANCES = 2.0
"""A body whose pose ended more than this many tolerances (`sigma_p`, `sigma_r`) from its start moved.

Under the at-rest model the window's median position (mean orientation) errs
by far less than a tolerance, but the start (the median of 5 samples) by
about half of one, shared by the whole window: measured on 1,000 seeded
trials of a body at rest with noise at its tolerance (1 and 2 cm; 2 and 4
deg), 1.0 to 1.3 % end beyond 2 tolerances in position, 0.1 % in orientation
(tests/infer/test_models.py; docs/inference.md, "Did the body move?", has the
measured displacements of simulated trials: none within 1 cm of the threshold).
"""

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


def infer_edge(data: EdgeData, *, relative: bool, t: np.ndarray | None = None) -> EdgeInference:
    """Fit the models to `data` and pick the MAP type.

    `relative`: the edge is a motion relative to its first sample, so the
    parameters are re-expressed in the model's own estimate of that first pose
    (less noisy than the raw first sample). An action edge (`T_ro`) is already
    in the body frame and keeps its parameters as fitted.

    The revolute model, the costly one, is fitted only when it could win: its
    score cannot exceed a perfect fit minus its penalty, and when that bound is
    far below the best score so far (the edge barely moves) the bound stands
    in for its score (its posterior is then an upper bound, ~0).

    `t`: the samples' times (s) of a motion edge; with them a body that moved
    off its start (`moved_off_start`) cannot be `fixed` (its posterior is 0).
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
    if relative and t is not None and moved_off_start(data, t):
        scores["fixed"] = -np.inf
    post = posterior(scores)
    best_type = max((k for k in fits if np.isfinite(scores[k])), key=lambda k: (post[k], -TYPES.index(k)))
    best = fits[best_type]
    params = express_in(best, start_frame(best, data)) if relative else dict(best.params)
    return EdgeInference(type=best_type, posterior=post, fits=fits, params=params)


def moved_off_start(data: EdgeData, t: np.ndarray) -> bool:
    """Whether a relative motion ended off its start: its `end_offset` beyond `AT_REST_TOLERANCES` x `sigma_p`
    (position) or that many `sigma_r` (orientation)."""
    offset = end_offset(data, t)
    if offset is None:
        return False
    distance, angle = offset
    if distance > AT_REST_TOLERANCES * data.sigma_p:
        return True
    return bool(np.isfinite(angle) and angle > AT_REST_TOLERANCES * data.sigma_r)


def end_offset(data: EdgeData, t: np.ndarray) -> tuple[float, float] | None:
    """How far a relative motion ended from its start: the distance (m) of the median position over its last
    `END_WINDOW` from the start, and the angle (rad; nan when no orientation was observed there) of the mean
    orientation over that window (its plausible samples) from the start. The start is the at-rest model's own
    pose (the median of the first plausible samples). None for fewer than 2 samples or times that do not match
    them: the statistic `moved_off_start` tests (bench/infer/bench_moved.py prints it).

    A position (orientation) of the window, not the median of the samples' distances (angles): the start's own
    error is shared by every sample of the window, so a median of their distances does not average it out, and
    a body at rest with noise at its tolerance ends "off its start" in 12 % of trials, against 1 % for the
    window's position (docs/inference.md, "Did the body move?")."""
    if data.n < 2 or len(t) != data.n:
        return None
    start = fit_model("fixed", data, relative=True)
    end = np.asarray(t) >= float(t[-1]) - END_WINDOW
    distance = float(np.linalg.norm(np.median(data.p[end], axis=0) - start.pred_p[0]))
    turned = end & data.has_rot
    if not turned.any():
        return distance, float("nan")
    trusted = turned & (data.plausible > 0)
    window = data.rot[np.flatnonzero(trusted if trusted.any() else turned)].mean()
    return distance, float((start.pred_rot[0].inv() * window).magnitude())


def _share_independence(fits: dict[str, ModelFit], data: EdgeData) -> None:
    """One independence factor for all models (so that their scores compare), from
    the residuals of the constrained model that explains the data best."""
    closest = max((k for k in ("fixed", "prismatic", "revolute") if k in fits), key=lambda k: fits[k].loglik)
    share = independence(fits[closest], data)
    for fit in fits.values():
        fit.independence = share
