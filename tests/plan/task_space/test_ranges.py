"""The planner keeps every motion value within its affordance's `range`: a longer motion is several contacts."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from vkgl.api import solve

SCENES = Path(__file__).resolve().parents[3] / "examples" / "scenes" / "tabletop.vkg"

BLOCK_PUSH = """
affordances Block {{
    affordance push_center_px {{
        action fixed at (-5, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm{range}
    }}
}}
"""


def task_file(tmp_path: Path, text: str, name: str = "t") -> str:
    path = tmp_path / f"{name}.vkg"
    path.write_text(f'use "{SCENES}"\n' + text, encoding="utf-8")
    return str(path)


def slide_task(tmp_path: Path, motion_range: str, max_depth: int) -> str:
    goal = "task slide { scene tabletop  goal block at (0.70, 0) m yaw 0deg within 1 cm, 3 deg"
    return task_file(
        tmp_path, BLOCK_PUSH.format(range=motion_range) + goal + f"  search {{ max_depth {max_depth} }} }}\n"
    )


def test_a_slide_longer_than_its_range_is_several_pushes_each_within_it(tmp_path):
    plan = solve(slide_task(tmp_path, " range 0 to 10 cm", 8))  # the block starts 25 cm from its goal
    assert plan.status == "solved", plan.reason
    pushes = [s.value for s in plan.steps if s.op == "add"]
    assert len(pushes) >= 3
    assert all(0.0 <= v <= 0.10 + 1e-9 for v in pushes)
    assert sum(pushes) == pytest.approx(0.25, abs=0.01)


def test_without_a_range_a_slide_is_unbounded(tmp_path):
    plan = solve(slide_task(tmp_path, "", 8))
    assert plan.status == "solved", plan.reason
    assert plan.depth == 2 and plan.steps[0].value == pytest.approx(0.25, abs=0.01)


def test_too_shallow_for_the_pushes_a_range_needs_says_so_with_numbers(tmp_path):
    plan = solve(slide_task(tmp_path, " range 0 to 10 cm", 4))
    assert plan.status == "infeasible"
    assert (
        "block is 25.0 cm from its goal (within 1.0 cm wanted) and Block.push_center_px moves it at most 10.0 cm "
        "per contact: at least 3 contacts: the goal needs at least 6 graphs"
    ) in plan.reason
    # the shortest depth that may work, on a line of its own (the tools' hint may follow it)
    assert any(line.endswith("(try --max-depth 6)") for line in plan.reason.splitlines()[1:])


def test_a_depth_with_room_for_the_pushes_but_not_for_their_contacts_is_checked_as_before(tmp_path):
    plan = solve(slide_task(tmp_path, " range 0 to 10 cm", 6))  # three pushes: ADD, REMOVE, ADD, REMOVE, ADD
    assert plan.status == "solved", plan.reason
    assert plan.depth == 6


def turn_task(tmp_path: Path, yaw_deg: float, max_depth: int) -> str:
    goal = f"goal block yaw {yaw_deg}deg within 3 deg"
    text = f"use stdlib.affordances.block\ntask turn {{ scene tabletop  {goal}  search {{ max_depth {max_depth} }} }}\n"
    return task_file(tmp_path, text)


def test_a_60_degree_turn_of_the_block_is_repeated_turns_within_the_explored_range(tmp_path):
    plan = solve(turn_task(tmp_path, -60, 8))
    assert plan.status == "solved", plan.reason
    explored = plan.problem.affordance("block", "turn_px_left").motion.range.upper.value  # learned: about 30 deg
    turns = [s for s in plan.steps if s.op == "add" and s.motion == "revolute"]
    assert len(turns) >= math.ceil(math.radians(57.0) / explored) >= 2  # the least 57 deg can take
    assert all(0.0 <= s.value <= explored + 1e-9 for s in turns)
    assert math.degrees(sum(s.value for s in turns)) == pytest.approx(60.0, abs=3.0)


def test_a_turn_past_the_explored_range_is_infeasible_with_the_numbers(tmp_path):
    plan = solve(turn_task(tmp_path, -35, 2))
    assert plan.status == "infeasible"
    assert "block's heading is 35.0 deg from its goal (within 3.0 deg wanted)" in plan.reason
    assert "turns it at most 30.6 deg per contact: at least 2 contacts: the goal needs at least 4 graphs" in plan.reason
    single = solve(turn_task(tmp_path, -35, 4))  # deep enough for two turns: searched, and the turns are found
    assert single.status == "solved" and single.depth == 4, single.reason


def test_an_open_slide_is_planned_past_its_explored_range_in_one_push(tmp_path):
    plan = solve(slide_task(tmp_path, " range 0 to 10 cm open", 2))  # still sliding when exploration ended at 10 cm
    assert plan.status == "solved", plan.reason
    assert plan.depth == 2 and plan.steps[0].value == pytest.approx(0.25, abs=0.01)


def test_a_closed_range_stays_a_bound_where_the_open_one_does_not(tmp_path):
    plan = solve(slide_task(tmp_path, " range 0 to 10 cm", 2))
    assert plan.status == "infeasible"
    assert "Block.push_center_px moves it at most 10.0 cm per contact" in plan.reason


def test_a_moved_body_stays_on_the_table_with_its_whole_outline(tmp_path):
    from vkgl.plan.task_space.constraints.body_limits import _stay_constraints

    plan = solve(slide_task(tmp_path, " range 0 to 10 cm open", 2))
    problem = plan.problem
    edge = problem.table_center[0] + problem.table_size[0] / 2
    pose = problem.bodies["block"].rest.copy()
    pose[0, 3] = edge - 0.03  # the frame 3 cm inside the edge, the 10 cm block's far half 2 cm beyond it
    assert max(_stay_constraints(problem, "block", pose)) == pytest.approx(0.02, abs=1e-6)
    pose[0, 3] = edge - 0.06
    assert max(_stay_constraints(problem, "block", pose)) < 0


def block_module(explored_cm: float) -> str:
    """The stdlib Block's learned module with its open slides' explored length replaced: what the short push grid
    learns (the 2 s pushes alone) against what the long `explore slides` pushes learn; nothing else differs."""
    module = (SCENES.parents[2] / "stdlib" / "affordances" / "block.vkg").read_text(encoding="utf-8")
    body = module[module.index("affordances Block") :]
    changed, slides = re.subn(r"range 0 to [0-9.]+ cm open", f"range 0 to {explored_cm} cm open", body)
    assert slides == 2  # push_center_px and push_center_nx
    return changed


@pytest.mark.parametrize(
    "goal",
    ["goal block at (0.72, 0.06) m within 1 cm", "goal block at (0.74, 0) m yaw 0deg within 1 cm, 3 deg"],
    ids=["arc", "slide"],
)
def test_an_open_slides_explored_length_changes_no_plan(tmp_path, goal):
    # 27 to 29 cm of travel: five times the short grid's 5.6 cm, within the long slides' 49.1 cm
    plans = []
    for explored in (5.6, 49.1):
        text = block_module(explored) + f"task t {{ scene tabletop  {goal}  search {{ max_depth 6 }} }}\n"
        plans.append(solve(task_file(tmp_path, text, f"explored_{explored}")))
    short, long = plans
    assert short.status == long.status == "solved", (short.reason, long.reason)
    contacts = [[(s.op, s.affordance, s.effector) for s in plan.steps] for plan in plans]
    assert contacts[0] == contacts[1]
    assert [s.value for s in short.steps] == pytest.approx([s.value for s in long.steps], abs=1e-6)
