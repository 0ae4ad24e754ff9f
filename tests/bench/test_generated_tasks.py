"""The physical benchmark's parts: the task generator and the independent geometry check of plans."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from checkers.plan_geometry import check_plan, check_start, screw_interpolate
from task_makers.generated_tasks import generate_tasks, overlaps, task_spec

import vkgl

REPO = Path(__file__).resolve().parents[2]
TABLETOP = (REPO / "examples" / "scenes" / "tabletop.vkg").read_text(encoding="utf-8")


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def test_the_generator_is_a_pure_function_of_the_seed(tmp_path: Path) -> None:
    """Both runs on one machine: determinism, not a golden value, so CPU differences cannot enter."""
    first = generate_tasks(7, 8, tmp_path / "a")
    second = generate_tasks(7, 8, tmp_path / "b")
    assert [t.metadata()["name"] for t in first] == [t.metadata()["name"] for t in second]
    assert _files(tmp_path / "a") == _files(tmp_path / "b")
    assert len(_files(tmp_path / "a")) >= 8 * 2
    assert task_spec(7, 3) == task_spec(7, 3)
    assert task_spec(8, 3) != task_spec(7, 3)


def test_the_generator_covers_every_kind_reach_and_blocked_paths() -> None:
    metas = [task_spec(1, i).metadata() for i in range(28)]
    assert {m["kind"] for m in metas} == {"cube", "slab", "crate", "block"}
    assert {m["size_class"] for m in metas} == {"low", "mid", "tall"}
    assert {m["reach"] for m in metas} == {"near", "far-push", "far-pull"}
    assert {m["clutter"] for m in metas} <= {1, 2, 3, 4}
    assert any(m["in_path"] for m in metas) and not all(m["in_path"] for m in metas)


@pytest.mark.parametrize("seed", [1, 2])
def test_start_scenes_never_overlap(tmp_path: Path, seed: int) -> None:
    for task in generate_tasks(seed, 10, tmp_path):
        program = vkgl.compile(task.folder / "scene.vkg")
        assert check_start(program, task.spec.scene_name) == [], task.name
        bodies = task.spec.bodies
        assert len({b.name for b in bodies}) == len(bodies)


def test_footprints_overlap_only_when_they_touch() -> None:
    square = [np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)]
    assert overlaps(square, [s + [0.5, 0.5] for s in square])
    assert not overlaps(square, [s + [1.1, 0] for s in square])
    assert overlaps(square, [s + [1.1, 0] for s in square], gap=0.2)


def test_screw_interpolation_turns_about_the_pivot() -> None:
    start = np.eye(4)
    start[:3, 3] = [1.0, 0.0, 0.0]
    turn = np.eye(4)  # 90 deg about the vertical through (0.5, 0.5, 0)
    c, s = 0.0, 1.0
    turn[:2, :2] = [[c, -s], [s, c]]
    pivot = np.array([0.5, 0.5, 0.0])
    turn[:3, 3] = pivot - turn[:3, :3] @ pivot
    end = turn @ start
    for fraction in np.linspace(0, 1, 7):
        pose = screw_interpolate(start, end, fraction)
        assert np.linalg.norm(pose[:3, 3] - pivot) == pytest.approx(math.sqrt(0.5))
    assert np.allclose(screw_interpolate(start, end, 1.0), end)


@pytest.fixture(scope="module")
def a_push() -> tuple[Any, dict[str, Any]]:
    """The example task (a) and its plan, solved once."""
    program = vkgl.compile(REPO / "examples" / "tasks" / "a_push.vkg")
    plan = vkgl.solve(program, "a_push")
    assert plan.status == "solved"
    return program, plan.to_json()


def test_the_example_plan_passes(a_push: tuple[Any, dict[str, Any]]) -> None:
    program, plan_json = a_push
    assert check_plan(program, "a_push", plan_json) == []


def test_a_plan_through_another_block_is_caught(tmp_path: Path, a_push: tuple[Any, dict[str, Any]]) -> None:
    # The scene of task (a) with a second block 17 cm ahead of the first: the planned push ends 8 cm inside it.
    scene = TABLETOP.replace(
        "block : Block on table at (0.45, 0) m yaw 0deg",
        "block : Block on table at (0.45, 0) m yaw 0deg\n    block2 : Block on table at (0.62, 0) m yaw 0deg",
    )
    (tmp_path / "scenes").mkdir()
    (tmp_path / "scenes" / "tabletop.vkg").write_text(scene, encoding="utf-8")
    task = (REPO / "examples" / "tasks" / "a_push.vkg").read_text(encoding="utf-8")
    (tmp_path / "tasks").mkdir()
    (tmp_path / "tasks" / "a_push.vkg").write_text(task, encoding="utf-8")
    program = vkgl.compile(tmp_path / "tasks" / "a_push.vkg")
    _, plan_json = a_push
    block2 = np.array(plan_json["steps"][0]["poses_start"]["block"])
    block2[0, 3] = 0.62
    # the plan as it was, but block2 stands (still) in the way
    edited = {**plan_json, "steps": [_with_body(s, "block2", block2) for s in plan_json["steps"]]}
    assert check_start(program, "tabletop") == []
    findings = check_plan(program, "a_push", edited)
    assert [(f.step, f.a, f.b) for f in findings] == [(1, "block", "block2")]
    assert findings[0].depth == pytest.approx(0.05, abs=0.003)  # 8 cm deep along x, 5 cm along z: the least is 5
    assert findings[0].text == "step 1: block overlaps block2 by 5.0 cm at sample 17/20"  # 5 cm deep from s = 0.8 on
    # a third of the way the block's front (0.50 + 0.05 m) has not reached block2's back (0.57) yet
    assert check_plan(program, "a_push", edited, samples=4)[0].sample == 4
    assert check_plan(program, "a_push", {**edited, "steps": []}) == []


def _with_body(step: dict[str, Any], name: str, pose: np.ndarray) -> dict[str, Any]:
    return {
        **step,
        "poses_start": {**step["poses_start"], name: pose.tolist()},
        "poses_end": {**step["poses_end"], name: pose.tolist()},
    }
