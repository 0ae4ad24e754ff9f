"""The execution's animation (`--animate`): frames are recorded while the arm follows its planned path,
and the effector's trace shows those moves, in their phase's style.
"""

from __future__ import annotations

import ast
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image

from vkgl.execute.animate import animate, trace_group, trace_lines
from vkgl.execute.scene_world import FRAME_PERIOD
from vkgl.figure_colors import BODY_COLORS, body_color
from vkgl.motion.picture_paths import effector_track
from vkgl.robot import Arm

TASK = "a_push"


@pytest.fixture(scope="module")
def recorded(a_push_scripted, a_push_recorded) -> tuple[Any, Any, Any]:
    """Task (a): its plan (transit and approach, then the push) and its recorded execution (shared with
    test_closed_loop.py: tests/conftest.py); the arm model."""
    program, plan = a_push_scripted
    report = a_push_recorded
    scene = program.scenes[program.task(TASK).scene.name]
    robot = next(r for r in scene.robots if r.name == plan.robot.name)
    arm = Arm.load(program.robots[robot.type.name], plan.robot.effector, robot.pose.matrix())
    return plan, report, arm


def test_frames_are_recorded_along_the_planned_transit_and_approach(recorded) -> None:
    """Every planned segment is in the recording, as long as planned, and the effector is on its planned track."""
    plan, report, arm = recorded
    frames = report.frames
    assert report.status == "reached", report.text()
    for segment in plan.steps[0].path:
        chosen = [j for j, label in enumerate(frames.label) if label == f"step 1 {segment.phase}"]
        assert len(chosen) == pytest.approx(segment.duration / FRAME_PERIOD, abs=2)
        track = effector_track(arm.fk, segment.joints, max_step=0.001)  # < 1.5 mm apart
        for j in chosen:
            gap = np.linalg.norm(track - frames.effector[j][:3, 3], axis=1).min()
            assert gap < 0.003, (segment.phase, frames.t[j], gap)
    transit = [frames.effector[j][:3, 3] for j, label in enumerate(frames.label) if label == "step 1 transit"]
    assert np.ptp(np.array(transit)[:, 2]) > 0.2  # the transit comes down from the ready pose: it moves


def test_the_trace_follows_the_phases() -> None:
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0], [5.0, 0.0]])
    labels = ["start", "step 1 transit", "step 1 transit", "step 1 approach", "step 1 transit", "step 1 motion"]
    groups = [trace_group(label) for label in labels]
    assert groups == ["other", "transit", "transit", "approach", "transit", "contact"]
    assert trace_group("step 2 lift") == trace_group("replan retreat") == "lift / retreat"
    lines = trace_lines(points, groups, 0, 5)
    # each move is drawn in the group of the frame it arrives at; runs of a group apart are broken by NaN
    np.testing.assert_array_equal(lines["transit"][0], [0.0, 1.0, 2.0, np.nan, 3.0, 4.0])
    np.testing.assert_array_equal(lines["approach"][0], [2.0, 3.0])
    np.testing.assert_array_equal(lines["contact"][0], [4.0, 5.0])
    assert lines["other"] == ([], []) and lines["lift / retreat"] == ([], [])
    assert trace_lines(points, groups, 2, 2)["transit"] == ([], [])  # a window of one frame: nothing behind it


def test_the_animation_has_a_frame_per_kept_recording(recorded, tmp_path) -> None:
    _, report, _ = recorded
    path = animate(report, tmp_path / "a.gif", max_frames=40)
    stride = int(np.ceil(len(report.frames.t) / 40))
    kept = len(range(0, len(report.frames.t), stride)) + ((len(report.frames.t) - 1) % stride != 0)
    with Image.open(path) as gif:
        assert gif.n_frames == kept
        assert gif.size == (560, 448)


def test_the_animation_is_the_same_bytes_every_time(recorded, tmp_path) -> None:
    """Both runs on one machine: determinism, not a golden value, so CPU differences cannot enter."""
    _, report, _ = recorded
    first = animate(report, tmp_path / "1.gif", max_frames=12).read_bytes()
    assert animate(report, tmp_path / "2.gif", max_frames=12).read_bytes() == first


def test_bodies_take_the_one_palette_in_scene_order_and_wrap_around() -> None:
    assert [body_color(k) for k in range(3)] == list(BODY_COLORS[:3])
    assert body_color(len(BODY_COLORS)) == BODY_COLORS[0]
    assert len(set(BODY_COLORS)) == len(BODY_COLORS) and "tab:red" not in BODY_COLORS  # red is the plan's goals'


@pytest.mark.parametrize("module", ["vkgl/plan/result/picture.py", "vkgl/execute/animate.py"])
def test_the_plans_picture_and_the_animation_colour_bodies_alike(module: str) -> None:
    # Each had a palette of its own: the hook of a scene with a block, a stick and a hook was purple in the
    # plan's picture and red in the animation.
    tree = ast.parse((Path(__file__).resolve().parents[2] / module).read_text(encoding="utf-8"))
    imported = {alias.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) for alias in node.names}
    assert "body_color" in imported
    colours = [node for node in ast.walk(tree) if isinstance(node, ast.Constant) and str(node.value).startswith("tab:")]
    assert not colours, f"{module} names palette colours of its own"
