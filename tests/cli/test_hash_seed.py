"""`vkgc solve` gives the same plan in processes with different string hashes.

Python salts the hash of every `str` per process (PYTHONHASHSEED), so iterating a set of body or affordance
names can change order between runs; where such an order reaches the optimiser (the order of its constraints)
the plan's numbers could differ from one run to the next. Both runs are on one machine: this is determinism,
not a golden value, so the JSON is compared as text. The examples: a carry over another body (n) and a held
tool that pulls after a turn (f), where most of the planner's paths run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import EXAMPLES, REPO


def _plan_json(task: Path, out: Path, hash_seed: str, cache: Path) -> str:
    env = {**os.environ, "PYTHONHASHSEED": hash_seed, "PYTHONPATH": str(REPO), "VKGL_CACHE_DIR": str(cache)}
    result = subprocess.run(
        [sys.executable, "-m", "vkgl.cli", "solve", str(task), "--json", str(out)],
        capture_output=True,
        text=True,
        cwd=REPO,
        env=env,
        timeout=240,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    document = json.loads(out.read_text())
    document.get("stats", {}).pop("solve_time_s", None)
    return json.dumps(document, sort_keys=True)


@pytest.mark.parametrize("example", ["n_pick_place", "f_rotate_hook_pull"])
def test_the_plan_does_not_depend_on_the_hash_seed(example: str, tmp_path: Path) -> None:
    task = EXAMPLES / "tasks" / f"{example}.vkg"
    cache = tmp_path / "cache"
    first = _plan_json(task, tmp_path / "first.json", "1", cache)
    second = _plan_json(task, tmp_path / "second.json", "2024", cache)
    assert first == second
