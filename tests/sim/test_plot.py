"""The picture of an exploration."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from sim_bodies import stdlib_body, with_policy

from vkgl.errors import InputError
from vkgl.formats.trials import Trials
from vkgl.sim.explore import explore
from vkgl.sim.plot import plot_trials


def test_plot_trials_writes_a_png(tmp_path: Path) -> None:
    trials = explore(with_policy(stdlib_body("Block"), steps=3, duration=0.2), jobs=1)
    trials.ok[1] = False  # a failed trial is drawn too (grey, dashed)
    trials.reason[1] = "a reason"
    path = tmp_path / "block.png"
    plot_trials(trials, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 10_000


def test_plot_trials_of_nothing_is_an_input_error(tmp_path: Path) -> None:
    empty = Trials(
        "Block",
        np.zeros((0, 1)),
        np.zeros((0, 1, 4, 4)),
        np.zeros((0, 1, 4, 4)),
        np.zeros((0, 3)),
        np.zeros((0, 3)),
        np.zeros(0, bool),
        np.zeros(0, str),
    )
    with pytest.raises(InputError):
        plot_trials(empty, tmp_path / "x.png")


def test_plot_trials_to_an_unwritable_place_is_an_input_error(tmp_path: Path) -> None:
    trials = explore(with_policy(stdlib_body("Block"), steps=1, duration=0.1), jobs=1)
    with pytest.raises(InputError, match="cannot write"):
        plot_trials(trials, tmp_path / "no" / "such" / "dir" / "x.png")
