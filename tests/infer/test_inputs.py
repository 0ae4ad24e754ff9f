"""Partial observations and bad input: a per-trial `skipped` reason or a clear error, never a traceback."""

from __future__ import annotations

import numpy as np
import pytest
from synthetic import block_pushes

from vkgl.errors import InputError
from vkgl.infer.library import infer_library
from vkgl.infer.trial import infer_trial


def _infer(trials):
    return infer_library(trials, body_use="stdlib.bodies.block", header="test")


def test_nan_rotations_mean_positions_only() -> None:
    trials = block_pushes()
    trials.T_ow[:, 10:30, :3, :3] = np.nan
    result = infer_trial(trials, 2)  # a centre push
    assert result.skipped is None
    assert result.motion.type == "prismatic"


def test_all_nan_effector_gives_a_null_action() -> None:
    trials = block_pushes()
    trials.T_ro[0] = np.nan
    report = _infer(trials).report
    assert report["trials"][0]["action"] == {"type": None, "posterior": None, "params": None}
    assert report["trials"][1]["action"]["type"] == "fixed"


def test_nan_padding_at_the_end_is_ignored() -> None:
    trials = block_pushes()
    trials.t[3, 40:] = np.nan
    trials.T_ow[3, 40:] = np.nan
    trials.T_ro[3, 40:] = np.nan
    result = infer_trial(trials, 3)
    assert result.samples == 40 and result.skipped is None


def test_too_few_samples_and_failed_trials_are_skipped_with_a_reason() -> None:
    trials = block_pushes()
    trials.T_ow[0, 2:] = np.nan
    trials.ok[1] = False
    trials.reason[1] = "body left the table"
    report = _infer(trials).report
    assert "at least 3 needed" in report["trials"][0]["skipped"]
    assert report["trials"][1]["skipped"] == "not ok: body left the table"
    assert "action" not in report["trials"][1]


def test_a_rotation_block_that_is_not_a_rotation_skips_the_trial() -> None:
    trials = block_pushes()
    trials.T_ow[4, 7, :3, :3] *= 2.0
    result = infer_trial(trials, 4)
    assert "sample 7 is not a rigid transform" in result.skipped


def test_all_trials_failed_is_a_clear_error() -> None:
    trials = block_pushes()
    trials.ok[:] = False
    trials.reason[:] = "penetration"
    with pytest.raises(InputError, match=r"none of the 10 trials can be used.*penetration"):
        _infer(trials)


def test_a_body_that_never_moved_is_a_clear_error() -> None:
    trials = block_pushes()
    trials.T_ow[:] = trials.T_ow[:, :1]
    with pytest.raises(InputError, match="did not move"):
        _infer(trials)


def test_report_numbers_are_json_safe_with_nan_contacts() -> None:
    import json

    trials = block_pushes()
    trials.contact[:] = np.nan
    text = json.dumps(_infer(trials).report, allow_nan=False)
    assert '"contact": [null, null, null]' in text


def test_an_empty_dataset_is_a_clear_error() -> None:
    trials = block_pushes()
    for name in ("t", "T_ro", "T_ow", "contact", "force", "ok", "reason"):
        setattr(trials, name, getattr(trials, name)[:0])
    with pytest.raises(InputError, match="no trials"):
        _infer(trials)


def test_infinite_and_unordered_samples_are_handled() -> None:
    trials = block_pushes()
    trials.T_ow[2, 5, 0, 3] = np.inf
    order = np.random.default_rng(0).permutation(trials.t.shape[1])
    trials.t[2], trials.T_ow[2], trials.T_ro[2] = trials.t[2, order], trials.T_ow[2, order], trials.T_ro[2, order]
    result = infer_trial(trials, 2)
    assert result.samples == trials.t.shape[1] - 1
    assert result.motion.type == "prismatic"
