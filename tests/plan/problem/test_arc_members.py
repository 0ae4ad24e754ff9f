"""The member of a slide's arc family that reaches a place-and-heading goal in one push (vkgl/plan/problem/arcs.py)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import vkgl
from vkgl.lang.ir.families import find_member
from vkgl.lang.ir.nodes import RevoluteC
from vkgl.plan.problem.arcs import arc_members

REPO = Path(__file__).resolve().parents[3]
TOLERANCES = (0.01, math.radians(3.0))


def _task(dx: float, dyaw: float | None, dy: float = 0.0) -> str:
    """The Block at (0.45, 0) m and a goal `dx`, `dy` (m) from there, turned by `dyaw` (deg; None: any heading)."""
    heading = "" if dyaw is None else f" yaw {dyaw:g}deg"
    within = "1 cm" if dyaw is None else "1 cm, 3deg"
    return (
        "use stdlib.robots.panda\nuse stdlib.bodies.block\nuse stdlib.affordances.block\n\n"
        "scene alone {\n    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
        "    it : Block on table at (0.45, 0) m yaw 0deg\n}\n\n"
        f"task turn_and_slide {{\n    scene alone\n"
        f"    goal it at ({0.45 + dx:.3f}, {dy:g}) m{heading} within {within}\n"
        "    search { max_depth 6  timeout 20 s }\n}\n"
    )


@pytest.fixture(scope="module")
def block() -> list:
    return vkgl.compile(REPO / "stdlib" / "affordances" / "block.vkg").affordances["Block"]


def _rest() -> np.ndarray:
    rest = np.eye(4)
    rest[:3, 3] = (0.45, 0.0, 0.025)
    return rest


def test_a_goal_one_arc_reaches_gets_the_member_the_executor_resolves_and_it_ends_at_the_goal(block: list) -> None:
    goal, yaw = np.array([0.55, 0.0]), math.radians(-10.0)
    members = arc_members(tuple(block), _rest(), goal, yaw, TOLERANCES)
    assert len(members) == 1
    member = members[0]
    assert member.name.startswith("push_center_px@+")  # pushed left of the centre: turned clockwise
    assert find_member(block, member.name) == member  # what the executor resolves from the plan's name
    motion = member.motion
    assert isinstance(motion, RevoluteC) and motion.axis.values[2] < 0
    pivot = motion.center.array()[:2] + _rest()[:2, 3]
    c, s = math.cos(yaw), math.sin(yaw)
    end = pivot + np.array([[c, -s], [s, c]]) @ (_rest()[:2, 3] - pivot)
    assert np.linalg.norm(end - goal) <= TOLERANCES[0]


@pytest.mark.parametrize(("dx", "dyaw"), [(0.10, 0.0), (0.15, -20.0), (0.02, -20.0)])
def test_no_member_for_a_goal_without_a_turn_or_out_of_one_arcs_reach(block: list, dx: float, dyaw: float) -> None:
    assert arc_members(tuple(block), _rest(), np.array([0.45 + dx, 0.0]), math.radians(dyaw), TOLERANCES) == ()


def test_a_heading_goal_is_one_push_at_depth_two(tmp_path: Path) -> None:
    task = tmp_path / "task.vkg"
    task.write_text(_task(0.12, 15.0), encoding="utf-8")
    plan = vkgl.solve(vkgl.compile(task), "turn_and_slide")
    assert plan.status == "solved" and plan.depth == 2
    assert plan.steps[0].affordance.startswith("Block.push_center_px@-")
    assert plan.final is not None
    final = plan.final["it"]
    assert np.linalg.norm(np.asarray(final)[:2, 3] - (0.57, 0.0)) <= 0.01


def _nearest_on_arc(member_motion: RevoluteC, goal: np.ndarray) -> np.ndarray:
    """The point of the member's arc (from the rest position, in its own sense, within its range) nearest `goal`."""
    pivot = member_motion.center.array()[:2] + _rest()[:2, 3]
    sense = math.copysign(1.0, member_motion.axis.values[2])
    top = math.pi if member_motion.range is None or member_motion.range.open else member_motion.range.upper.value
    angles = np.linspace(0.0, top, 20001)
    rel = _rest()[:2, 3] - pivot
    c, s = np.cos(sense * angles), np.sin(sense * angles)
    ends = pivot + np.stack([c * rel[0] - s * rel[1], s * rel[0] + c * rel[1]], axis=1)
    return ends[int(np.argmin(np.linalg.norm(ends - goal, axis=1)))]


@pytest.mark.parametrize(("dy", "sign"), [(0.04, "-"), (-0.04, "+")])
def test_a_heading_free_goal_off_the_push_line_gets_the_arc_through_it(block: list, dy: float, sign: str) -> None:
    goal = np.array([0.60, dy])
    members = arc_members(tuple(block), _rest(), goal, None, TOLERANCES)
    assert [m.name[: len("push_center_px@") + 1] for m in members] == [f"push_center_px@{sign}"]
    member = members[0]
    assert find_member(block, member.name) == member
    motion = member.motion
    assert isinstance(motion, RevoluteC)
    assert motion.range is not None and motion.range.open  # the Block's slide was still going: so is its arc
    assert math.copysign(1.0, motion.axis.values[2]) == (1.0 if dy > 0 else -1.0)  # turned toward the goal
    assert np.linalg.norm(_nearest_on_arc(motion, goal) - goal) <= 0.1 * TOLERANCES[0]  # the arc through the goal


@pytest.mark.parametrize("goal", [(0.60, 0.0), (0.60, 0.008), (0.55, 0.10), (0.40, 0.03)])
def test_no_heading_free_member_where_the_straight_push_reaches_or_no_arc_does(block: list, goal: tuple) -> None:
    # on the push line (within the tolerance) the slide itself does it; 10 cm aside over 10 cm, or 3 cm aside
    # over 5 cm behind it, needs an arc tighter than any of the band (the tightest: a pivot about 35 cm away)
    assert arc_members(tuple(block), _rest(), np.array(goal), None, TOLERANCES) == ()


def test_a_heading_free_goal_off_the_push_line_is_one_push_at_depth_two(tmp_path: Path) -> None:
    task = tmp_path / "task.vkg"
    task.write_text(_task(0.15, None, 0.04), encoding="utf-8")
    plan = vkgl.solve(vkgl.compile(task), "turn_and_slide")
    assert plan.status == "solved" and plan.depth == 2, plan.reason
    assert [s.affordance for s in plan.steps] == ["Block.push_center_px@-1.82cm"]
    assert plan.final is not None
    assert np.linalg.norm(np.asarray(plan.final["it"])[:2, 3] - (0.60, 0.04)) <= 0.01
