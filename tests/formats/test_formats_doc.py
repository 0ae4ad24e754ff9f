"""docs/formats.md is the formats' contract: every key a writer puts in a file is described in its section.

Each writer is run on real data (a golden plan, inferred synthetic pushes, an execution report with every
optional part, a reach cache file, a trials dataset), every key of its output is collected, and each must
appear as `key` in the format's section of docs/formats.md, and the section must name the format's version.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from synthetic import block_pushes

from vkgl.formats import execution_report, reach_cache
from vkgl.formats.execution_report import (
    Deviation,
    Disturbance,
    ExcludedStep,
    ExecutionReport,
    GoalResult,
    Opening,
    Resolve,
    StepReport,
)
from vkgl.formats.plan import PLAN_FORMAT
from vkgl.formats.trials import FORMAT as TRIALS_FORMAT
from vkgl.infer.library import infer_library

REPO = Path(__file__).resolve().parents[2]
DOC = REPO / "docs" / "formats.md"


def _section(version: str) -> str:
    """The text of the section whose heading starts with the format's name."""
    text = DOC.read_text(encoding="utf-8")
    match = re.search(rf"^## `{re.escape(version)}`.*?(?=^## |\Z)", text, flags=re.S | re.M)
    assert match, f"docs/formats.md has no section for {version}"
    return match.group(0)


def _keys(data: Any) -> set[str]:
    """Every object key at any depth, except those that are names (body names, heights, type names)."""
    found: set[str] = set()
    if isinstance(data, dict):
        for key, value in data.items():
            found.add(key)
            found |= _keys(value)
    elif isinstance(data, list):
        for value in data:
            found |= _keys(value)
    return found


def _undocumented(version: str, keys: set[str]) -> list[str]:
    """The keys the section names nowhere: not in a code span as a path part (`steps[k].path`, `q_end`), nor
    quoted as in a JSON example (`{"axis": [3]}`)."""
    section = _section(version)

    def named(key: str) -> bool:
        k = re.escape(key)
        return bool(re.search(rf"[`.]{k}(?=[`.\[])", section) or re.search(rf'"{k}"', section))

    return sorted(k for k in keys if not named(k))


NAMES = {"block", "stick", "hook", "drawer", "cabinet", "door", "cupboard", "cube", "left", "middle", "right"}
"""Body names of the example plans: keys of `poses_start`, `final`, ..., not fields."""


def test_every_key_of_a_plan_is_documented() -> None:
    keys = set()
    for golden in (REPO / "tests" / "formats" / "golden").glob("*.json"):
        keys |= _keys(json.loads(golden.read_text(encoding="utf-8")))
    keys.add("reason")  # written only for plans that are not solved
    assert "contact" in keys and "phase" in keys
    assert _undocumented(PLAN_FORMAT, keys - NAMES) == []
    assert _undocumented(PLAN_FORMAT, {"colour", "speed_limit"}) == ["colour", "speed_limit"]  # sees a missing key


def test_every_key_of_an_infer_report_is_documented() -> None:
    report = infer_library(block_pushes(), body_use="stdlib.bodies.block", header="doc").report
    keys = _keys(report) - {"fixed", "prismatic", "revolute", "free"}  # the posterior's keys: the types
    keys |= {"skipped"}  # written only for trials that could not be inferred
    assert "range" in keys and "kept" in keys
    assert _undocumented(report["format"], keys) == []


def _full_report() -> ExecutionReport:
    """A report with every optional part: a deviation on a joint, a joint goal, a disturbance, a re-solve."""
    pose = np.eye(4)
    opening = Opening(joint="prismatic", target=0.2, real=0.19, limit=0.01)
    step = StepReport(plan=0, index=1, title="add Drawer.pull on drawer with arm.fingertip", end_time=3.0)
    step.deviations.append(Deviation("drawer", pose, pose, 0.01, 0.0, 0.005, 0.03, opening=opening))
    goal = GoalResult("drawer", "drawer open 20.0 cm within 1.0 cm", None, None, 0.01, 0.05, opening=opening)
    resolve = Resolve(1, "step 1", (ExcludedStep(0, 1, "t", "why"),), 1, "solved", "", ("s",), "new plan", 0.2)
    return ExecutionReport(
        task="g",
        status="disturbed",
        reason="r",
        steps=[step],
        goals=[goal],
        replans=1,
        replan_log=["x"],
        final={"drawer": pose},
        sim_time=1.0,
        wall_time=1.0,
        solve_time=0.2,
        disturbed=[Disturbance("cabinet", 0.02, 0.0, (0.01, 0.05))],
        resolves=[resolve],
        final_openings={"drawer": 0.19},
    )


def test_every_key_of_an_execution_report_is_documented() -> None:
    data = _full_report().to_json()
    assert data["format"] == execution_report.FORMAT
    assert _undocumented(execution_report.FORMAT, _keys(data) - {"drawer"}) == []


def test_every_key_of_a_reach_cache_is_documented(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(reach_cache.ENV_DIR, str(tmp_path))
    reach_cache.store("ab" * 32, 0.025, (0.1, 0.8))
    (written,) = tmp_path.glob("reach-*.json")
    data = json.loads(written.read_text(encoding="utf-8"))
    assert _undocumented(reach_cache.CACHE_FORMAT, _keys(data) - {"0.025"}) == []


def test_every_array_of_a_trials_dataset_is_documented(tmp_path: Path) -> None:
    path = tmp_path / "trials.npz"
    block_pushes().save(path)
    with np.load(path) as data:
        arrays = set(data.files)
    assert {"T_ro", "T_ow", "reason"} <= arrays
    assert _undocumented(TRIALS_FORMAT, arrays) == []
