"""The paper's six tasks solve at the paper's depths, and an independent replay of each plan holds.

Paper (Table 1): a 2, b 3, c 3, d 4, e 5, f 5; tools in b, c, e, f only.
The replay (replay_check.py) recomputes every pose from the affordances and
the arm's forward kinematics from the URDF with DART, from the JSON alone.
"""

from __future__ import annotations

import json

import pytest
from plan_programs import compiled  # noqa: F401 (fixture)
from replay_check import check_plan

from vkgl.api import solve

PAPER = {
    "a_push": (2, False),
    "b_stick_push": (3, True),
    "c_hook_pull": (3, True),
    "d_rotate_push": (4, False),
    "e_rotate_stick_push": (5, True),
    "f_rotate_hook_pull": (5, True),
}


@pytest.fixture(scope="module")
def plans(compiled):
    return {name: solve(compiled(name)) for name in PAPER}


@pytest.mark.parametrize("name", list(PAPER))
def test_solves_at_the_paper_depth_with_tools_only_where_needed(plans, name):
    plan = plans[name]
    depth, uses_tool = PAPER[name]
    assert plan.status == "solved", plan.reason
    assert plan.depth == depth
    effectors = {s.effector for s in plan.steps if s.op == "add"}
    assert any(not e.startswith("arm.") for e in effectors) == uses_tool, effectors


@pytest.mark.parametrize("name", list(PAPER))
def test_independent_replay_of_the_json_plan_holds(plans, compiled, name):
    plan_json = json.loads(json.dumps(plans[name].to_json()))
    assert check_plan(compiled(name), plan_json) == []


def test_the_replay_check_catches_a_wrong_plan(plans, compiled):
    """The checker itself can fail: a plan with a shortened push misses the goal and breaks continuity."""
    plan_json = json.loads(json.dumps(plans["a_push"].to_json()))
    plan_json["steps"][0]["value"] *= 0.5
    assert check_plan(compiled("a_push"), plan_json)
    plan_json = json.loads(json.dumps(plans["b_stick_push"].to_json()))
    plan_json["steps"][1]["q_end"][0] += 0.2
    assert any("hand" in p for p in check_plan(compiled("b_stick_push"), plan_json))


def test_json_has_exactly_the_vkg_plan_2_keys(plans):
    out = plans["e_rotate_stick_push"].to_json()
    assert list(out) == ["format", "task", "status", "depth", "stats", "robot", "graphs", "steps", "final"]
    assert out["format"] == "vkg-plan/2" and out["depth"] == len(out["graphs"]) == len(out["steps"]) + 1
    assert set(out["stats"]) == {"solve_time_s", "graphs_expanded", "task_space_checks", "joint_space_checks"}
    assert set(out["robot"]) == {"name", "urdf", "base", "effector", "effector_link", "effector_offset", "joints"}
    step_keys = [
        "op",
        "affordance",
        "body",
        "effector",
        "motion",
        "value",
        "poses_start",
        "poses_end",
        "q_start",
        "q_end",
        "path",
    ]
    assert all(list(s) == step_keys for s in out["steps"])
    phases = [[segment["phase"] for segment in s["path"]] for s in out["steps"]]
    assert phases == [["transit", "approach"], ["retreat"], ["transit", "approach"], ["lift", "transit", "approach"]]
    assert out["steps"][0]["affordance"] == "Block.turn_px_left" and out["steps"][0]["effector"] == "arm.fingertip"


def test_two_runs_give_identical_json_apart_from_timings(compiled):
    first, second = (solve(compiled("f_rotate_hook_pull")).to_json() for _ in range(2))
    for out in (first, second):
        out["stats"].pop("solve_time_s")
    assert json.dumps(first) == json.dumps(second)


def test_text_shows_the_graph_sequence(plans):
    text = plans["d_rotate_push"].text()
    assert "G0: block-world fixed" in text
    assert "step 1: add Block.turn_px_left on block with arm.fingertip: turn 20." in text
    assert "G1: block-world revolute" in text and "arm-block fixed" in text
    assert "step 3: add Block.push_center_px on block with arm.fingertip: slide 10.0 cm" in text
