"""The goal forms people say, carried out in DART: `vkgc solve --execute` reaches each example's goal.

Task j: a goal relative to the block's start; the report says it as written and where it put the block.
Task k: a region goal; the executor checks the block's footprint inside the region where DART leaves it.
Task l: a keep-out region; the block turned from its far face ends outside it in DART too.
Task m: a drawer placed `at cabinet.slot`, pulled open in DART.
"""

from __future__ import annotations

import json
import re

import numpy as np
from conftest import EXAMPLES

import vkgl
from vkgl.cli import main
from vkgl.lang.ir.geometry import shape_vertices
from vkgl.lang.ir.regions import footprint, overlap_depth


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


def test_the_keep_out_task_is_reached_and_the_block_ends_outside_the_region_in_dart(tmp_path, capsys) -> None:
    data, out = _execute("l_keep_out", tmp_path, capsys)
    assert data["status"] == "reached", out
    # turned from its far face (from the near one it would end inside the region)
    assert re.search(r"add Block\.turn_\w*nx\w* on block", out), out
    program = vkgl.compile(EXAMPLES / "tasks" / "l_keep_out.vkg")
    (keep,) = program.task("l_keep_out").keep_out
    points = shape_vertices(program.bodies["Block"].shape)
    final = np.array(data["final"]["block"])
    assert overlap_depth(keep.region.points(), footprint(points, final)) <= 0.001  # its real footprint stays out


def test_the_drawer_placed_at_its_cabinets_slot_opens_in_dart(tmp_path, capsys) -> None:
    data, out = _execute("m_drawer_at_slot", tmp_path, capsys)
    assert data["status"] == "reached", out
    (goal,) = data["goals"]
    assert goal["ok"] and abs(goal["opening"]["error"]) < 0.01
