"""Per trial: the MAP kinematic graph = MAP action edge x MAP motion edge.

The edges are independent (docs/method.md, "Inference"), so each is selected on its
own: the action on `T_ro` (effector in the body frame), the motion on the
body's pose relative to its first sample. A trial that cannot be used keeps
its reason (`skipped`) instead of raising.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vkgl.formats.trials import Trials
from vkgl.infer.data import SkipTrial, trial_edges
from vkgl.infer.ending import Ending, motion_ending
from vkgl.infer.select import EdgeInference, infer_edge


@dataclass
class TrialInference:
    """The inferred graph of one trial, or why there is none.

    `action` is None when the effector was not observed (or the trial was
    skipped); `motion` is None only when the trial was skipped. `ending`: how
    the MAP motion's state ended (`vkgl.infer.ending`), None for a motion
    without a state (fixed, free) or a trial too short to tell.
    """

    index: int
    contact: np.ndarray
    force: np.ndarray
    samples: int = 0
    action: EdgeInference | None = None
    motion: EdgeInference | None = None
    skipped: str | None = None
    ending: Ending | None = None

    @property
    def loglik(self) -> float:
        """Log-likelihood of the MAP graph (sum over its observed edges)."""
        total = 0.0
        for edge in (self.action, self.motion):
            if edge is not None:
                total += edge.loglik
        return total


def infer_trial(trials: Trials, i: int) -> TrialInference:
    """The MAP graph of trial `i` (never raises for bad data: the reason goes to `skipped`)."""
    result = TrialInference(index=i, contact=np.asarray(trials.contact[i]), force=np.asarray(trials.force[i]))
    try:
        edges = trial_edges(trials, i)
    except SkipTrial as exc:
        result.skipped = str(exc)
        return result
    result.samples = edges.samples
    result.motion = infer_edge(edges.motion, relative=True, t=edges.t)
    if result.motion.type in ("prismatic", "revolute"):
        result.ending = motion_ending(edges.t, result.motion.best.states)
    if edges.action is not None:
        result.action = infer_edge(edges.action, relative=False)
    return result


def infer_trials(trials: Trials) -> list[TrialInference]:
    """The MAP graph of every trial, in order."""
    return [infer_trial(trials, i) for i in range(len(trials))]
