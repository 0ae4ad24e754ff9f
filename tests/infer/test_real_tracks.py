"""Real recorded tracks (Sturm et al.): doors, drawers, a dishwasher, a sliding cabinet; positions only.

Read in place from ../shared/data/articulation/ (never copied); skipped when absent.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from vkgl.formats.trials import Trials
from vkgl.infer.library import infer_library

DATA = Path(__file__).resolve().parents[3] / "shared" / "data" / "articulation"

pytestmark = pytest.mark.skipif(not (DATA / "sturm_tracks.npz").is_file(), reason="articulation data not present")


@pytest.fixture(scope="module")
def inferred():
    trials = Trials.load(DATA / "sturm_tracks.npz")
    labels = json.loads((DATA / "labels.json").read_text())
    result = infer_library(trials, body_use="tracks.vkg", header="real tracks")
    return result, labels


def test_motion_types_of_real_mechanisms(inferred) -> None:
    result, labels = inferred
    motions = {t["index"]: t["motion"]["type"] for t in result.report["trials"]}
    correct = sum(motions[label["index"]] == label["motion"] for label in labels)
    # 71 of 77 (92 %) at the time of writing: see docs/inference.md for the tracks that
    # positions alone cannot tell apart (nearly straight door tracks, bent drawer tracks).
    assert correct / len(labels) >= 0.90


def test_unobserved_actions_are_reported_as_null(inferred) -> None:
    result, _ = inferred
    first = result.report["trials"][0]
    assert first["action"] == {"type": None, "posterior": None, "params": None}
    assert first["motion"]["type"] in ("prismatic", "revolute")
    assert set(first["motion"]["params"]) in ({"axis", "origin"}, {"axis", "center"})


def test_the_real_module_has_a_turn_and_a_slide(inferred) -> None:
    result, _ = inferred
    names = [a.name for a in result.module.decls[0].affordances]
    assert "turn" in names and "push" in names
