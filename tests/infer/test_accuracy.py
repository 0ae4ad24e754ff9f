"""Inference on synthetic trials with known ground truth (a fast subset of bench/infer/bench_infer.py)."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import score, synthetic_trials

from vkgl.infer.trial import infer_trials


def _score(noise_p: float, noise_deg: float) -> tuple[float, float, float, float]:
    trials, truths = synthetic_trials(11, 3, noise_p=noise_p, noise_r=np.deg2rad(noise_deg))
    results = infer_trials(trials)
    found = score(results, truths)
    return found.motion_accuracy, found.action_accuracy, found.axis_error_deg, found.center_error


@pytest.mark.parametrize("noise_p, noise_deg", [(0.0, 0.0), (0.005, 2.0)])
def test_types_axes_and_centres_are_recovered(noise_p: float, noise_deg: float) -> None:
    motion_ok, action_ok, axis_deg, center_m = _score(noise_p, noise_deg)
    assert motion_ok >= 0.95
    assert action_ok >= 0.95
    assert axis_deg < 2.0
    assert center_m < 0.01
