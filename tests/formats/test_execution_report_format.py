"""`vkg-execution/5` (vkgl.formats.execution_report): written atomically, the same data as `to_json`."""

from __future__ import annotations

import json

import numpy as np
import pytest

from vkgl.formats.execution_report import Deviation, ExecutionReport, GoalResult, Opening, StepReport, write


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
    assert data["format"] == "vkg-execution/5" and data["steps"][0]["step"].endswith("slide 15.0 cm")
    assert path.read_text(encoding="utf-8").endswith("}\n")


def _drawer_report(real_opening: float) -> ExecutionReport:
    """The drawer pulled open, planned 20 cm, really `real_opening` m; its joint goal 20 cm within 1 cm."""
    planned, real = np.eye(4), np.eye(4)
    planned[0, 3], real[0, 3] = 0.2, real_opening
    off = abs(real_opening - 0.2)
    deviation = Deviation(
        "drawer", planned, real, off, 0.0, 0.005, 0.026, Opening("prismatic", 0.2, real_opening, 0.005)
    )
    step = StepReport(0, 1, "add Drawer.pull_center_px on drawer with arm.fingertip: slide 20.0 cm", 8.9, [deviation])
    goal = GoalResult(
        "drawer",
        "drawer open 20.0 cm within 1.0 cm",
        None,
        None,
        0.01,
        0.05,
        Opening("prismatic", 0.2, real_opening, 0.01),
    )
    status = "reached" if goal.ok else "missed"
    return ExecutionReport(
        "g",
        status,
        "",
        [step],
        [goal],
        0,
        [],
        {"drawer": real},
        10.0,
        2.0,
        0.0,
        final_openings={"drawer": real_opening},
    )


def test_a_joint_goal_is_reported_by_the_joints_coordinate():
    near, far = _drawer_report(0.196), _drawer_report(0.187)
    assert near.goals[0].ok and not far.goals[0].ok
    assert not near.steps[0].deviations[0].exceeded and far.steps[0].deviations[0].exceeded  # half of 1 cm
    text = far.text()
    assert (
        "drawer   planned open 20.0 cm   real open 18.7 cm   off 1.30 cm  > replan limit 0.50 cm "
        "(half the goal's tolerance)"
    ) in text
    assert "goal drawer open 20.0 cm within 1.0 cm: drawer is open 18.7 cm, off 1.30 cm  NOT MET" in text
    assert far.goals[0].miss() == "drawer is open 18.7 cm, goal 20.0 cm within 1.00 cm"
    data = json.loads(json.dumps(far.to_json()))
    assert data["goals"][0]["opening"] == {
        "joint": "prismatic",
        "goal": 0.2,
        "real": 0.187,
        "error": pytest.approx(-0.013),
        "tolerance": 0.01,
    }
    assert data["goals"][0]["ok"] is False and data["goals"][0]["position_error_m"] is None
    assert data["steps"][0]["bodies"]["drawer"]["opening"]["planned"] == 0.2
    assert data["final_openings"] == {"drawer": 0.187}
    door = Opening("revolute", np.radians(45), np.radians(46.2), np.radians(3))
    assert not door.exceeded and GoalResult("door", "door open 45.0 deg", None, None, 0.01, 0.05, door).errors() == (
        "door is open 46.2 deg, off 1.20 deg"
    )


def test_a_pose_goal_and_a_free_bodys_deviation_carry_no_opening():
    data = _report().to_json()
    assert data["goals"][0]["opening"] is None and data["steps"][0]["bodies"]["block"]["opening"] is None
    assert data["final_openings"] == {}


def test_a_value_that_rounds_to_zero_is_shown_without_a_sign():
    """A shut door whose solver left it at -1e-12 rad reads `open 0.0 deg`, and a heading of -0.01 deg reads
    `yaw 0.0 deg`: a `-0.0` looks like a direction that is not there."""
    from vkgl.formats.execution_report import _planar, joint_value_text

    assert joint_value_text("revolute", -1e-12) == "0.0 deg"
    assert joint_value_text("prismatic", -0.0004) == "0.0 cm"
    assert joint_value_text("revolute", np.radians(-0.06)) == "-0.1 deg"
    pose = np.eye(4)
    pose[:3, :3] = [[1.0, 1e-4, 0.0], [-1e-4, 1.0, 0.0], [0.0, 0.0, 1.0]]  # turned by -0.006 deg
    pose[:2, 3] = (-0.0001, 0.25)
    assert _planar(pose) == "(0.000, 0.250) m yaw    0.0 deg"
