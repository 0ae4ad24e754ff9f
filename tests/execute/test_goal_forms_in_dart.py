"""The goal forms people say, carried out in DART: `vkgc solve --execute` reaches each example's goal.

Task j: a goal relative to the block's start; the report says it as written and where it put the block.
Task k: a region goal; the executor checks the block's footprint inside the region where DART leaves it.
"""

from __future__ import annotations

import json

from conftest import EXAMPLES

from vkgl.cli import main


def _execute(name: str, tmp_path, capsys) -> tuple[dict, str]:
    report = tmp_path / f"{name}.json"
    task = EXAMPLES / "tasks" / f"{name}.vkg"
    assert main(["solve", str(task), "--execute", "--execution-json", str(report)]) == 0
    return json.loads(report.read_text(encoding="utf-8")), capsys.readouterr().out


def test_the_relative_goal_is_reached_in_dart(tmp_path, capsys) -> None:
    data, out = _execute("j_move_relative", tmp_path, capsys)
    assert data["status"] == "reached", out
    assert "goal block moved by (15, 0) cm in block: at (0.600, 0.000) m" in out
    assert "goal block turned by 20deg: yaw 20.0 deg" in out
    assert all(g["ok"] for g in data["goals"]) and len(data["goals"]) == 2


def test_the_region_goal_is_reached_in_dart(tmp_path, capsys) -> None:
    data, out = _execute("k_region_goal", tmp_path, capsys)
    assert data["status"] == "reached", out
    (goal,) = data["goals"]
    assert goal["goal"].startswith("block in region (0.55, -0.16) to (0.75, 0.12) m yaw 0.0 deg") and goal["ok"]
    assert goal["position_error_m"] <= 0.01  # the footprint passes no edge by more than the tolerance
