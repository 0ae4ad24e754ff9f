"""`vkg-execution/3` (vkgl.formats.execution_report): written atomically, the same data as `to_json`."""

from __future__ import annotations

import json

import numpy as np

from vkgl.formats.execution_report import Deviation, ExecutionReport, GoalResult, StepReport, write


def _report() -> ExecutionReport:
    planned, real = np.eye(4), np.eye(4)
    real[0, 3] = 0.004
    deviation = Deviation("block", planned, real, 0.004, 0.0, 0.005, 0.026)
    step = StepReport(0, 1, "add Block.push_center_px on block with arm.fingertip: slide 15.0 cm", 6.8, [deviation])
    goal = GoalResult("block", "block at (0.600, 0.000) m", 0.004, 0.0, 0.01, 0.05)
    return ExecutionReport("a_push", "reached", "", [step], [goal], 0, [], {"block": real}, 8.0, 1.5, 0.0)


def test_write_puts_the_report_json_in_the_file_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "run.json"
    write(path, _report())
    assert [p.name for p in tmp_path.iterdir()] == ["run.json"]
    data = json.loads(path.read_text(encoding="utf-8"))
    assert data == json.loads(json.dumps(_report().to_json()))
    assert data["format"] == "vkg-execution/3" and data["steps"][0]["step"].endswith("slide 15.0 cm")
    assert path.read_text(encoding="utf-8").endswith("}\n")
