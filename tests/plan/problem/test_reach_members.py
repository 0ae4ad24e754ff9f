"""A tool's pull started nearer the arm (`vkgl.plan.problem.reach_members`): the Hook's contact moved along the far
face until the hand is within reach, rolled where its shaft would then lie in the body; and the plan that uses it
(gen2_027 of the physical bench: "no plan" before, the hand 4 cm beyond the arm's reach at the written contact)."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from task_makers import generated_tasks

import vkgl
from vkgl.lang.ir.families import find_member, over_member, over_pose, slide_member, tool_only
from vkgl.plan.graphs.graph import Action, Engagement, successors
from vkgl.plan.graphs.rollout import extend, start_sequence
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.problem.reach_members import REACH_SLACK, start_poses
from vkgl.plan.problem.rejection import Rejection
from vkgl.plan.task_space.feasible import task_space

MEMBER = "push_center_nx@-4.00cm/straight/over+20deg+0.50cm"


def _problem(tmp_path, x: float, y: float, yaw: float, goal: tuple[float, float, float | None]) -> Problem:
    target = generated_tasks.Placement("target", "Block", x, y, yaw)
    tools = tuple(generated_tasks.Placement(n, t.name, tx, ty, a) for n, t, tx, ty, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("nearer", 0, 0, (target, *tools), goal, "far-pull", False, 0.31)
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path, generated_tasks.fixture_library(())))
    return build_problem(program, program.tasks["nearer"])


def _far_block(tmp_path) -> Problem:
    """gen2_027's Block: at (0.906, -0.172) m, yaw 30 deg, to be pulled 31 cm along its -x to the same heading."""
    return _problem(tmp_path, 0.906, -0.172, 30.0, (0.638, -0.327, 30.0))


def _hand_radius(problem: Problem, name: str, grasp: str) -> float:
    """The hand's distance from the arm's base with the Hook held by `grasp` enacting `name` on the Block at rest."""
    hook = problem.effector("hook.tip")
    chain = problem.action("target", name) @ hook.frame_inverse @ problem.action("hook", grasp)
    hand = problem.bodies["target"].rest @ chain
    return float(np.hypot(*(hand[:2, 3] - problem.arm.base[:2, 3])))


def test_a_pull_whose_hand_is_out_of_reach_gets_a_member_nearer_the_arm_for_the_hook_alone(tmp_path):
    problem = _far_block(tmp_path)
    body = problem.bodies["target"]
    names = [a.name for a in body.affordances if "/straight" in a.name]
    assert names == [MEMBER]
    assert {pair for pair in body.tool_members if pair[0] == MEMBER} == {(MEMBER, "hook.tip")}
    _, r_max = problem.arm.reach(float(body.rest[2, 3]))
    # the written pull holds the hand beyond the arm's reach by either grasp; the member brings it inside
    assert min(_hand_radius(problem, "push_center_nx", g) for g in ("wield", "wield_2")) > r_max
    assert min(_hand_radius(problem, MEMBER, g) for g in ("wield", "wield_2")) <= r_max - REACH_SLACK + 1e-9
    # no other effector enacts it (a point off the centre turns the body: the fingertip's is the arc's member)
    start = start_sequence(problem)
    assert not [a for a in successors(problem, start.graphs[-1], None) if a.engagement.affordance == MEMBER]
    # the member is the same slide: its motion is the written one's, its contact 4 cm along the face and rolled
    written = problem.affordance("target", "push_center_nx")
    assert problem.affordance("target", MEMBER).motion == written.motion


def test_a_pull_the_arm_reaches_as_written_gets_no_member(tmp_path):
    near = _problem(tmp_path, 0.80, 0.0, 0.0, (0.55, 0.0, 0.0))  # the hand 0.55 m out at the written contact
    assert not [a.name for a in near.bodies["target"].affordances if "/straight" in a.name]


def test_the_member_s_name_reads_back_as_the_straight_member_rolled(tmp_path):
    problem = _far_block(tmp_path)
    slide = next(a for a in problem.bodies["target"].affordances if a.name == "push_center_nx")
    found = find_member([slide], MEMBER)
    assert found is not None and found.name == MEMBER
    base, roll, lift = over_pose(MEMBER)
    assert math.degrees(roll) == pytest.approx(20.0) and lift == pytest.approx(0.005)
    expected = over_member(slide_member(slide, -0.04), roll, lift)
    assert found.action == expected.action and found.motion == slide.motion and base.endswith("/straight")
    # a tool's members are that tool's alone, rolled or lying flat; an arc's member and a written slide are anyone's
    assert (
        tool_only(MEMBER)
        and tool_only("push_center_nx@-4.00cm/straight")
        and tool_only("push_center_nx/over+20deg+0.50cm")
    )
    assert not tool_only("push_center_nx@-4.00cm") and not tool_only("push_center_nx")


def test_a_start_turned_to_aim_at_the_goal_is_asked_too_and_a_slide_away_from_the_goal_not_at_all(tmp_path):
    problem = _far_block(tmp_path)
    rest = problem.bodies["target"].rest
    slide = problem.affordance("target", "push_center_nx").motion
    assert len(start_poses(rest, slide, problem.goals[0])) == 1  # the goal's heading is the rest's: no turn
    away = problem.affordance("target", "push_center_px").motion  # pushes away from the goal
    assert start_poses(rest, away, problem.goals[0]) == []
    # gen1_027: the goal 19 deg off the pull's axis, its heading free: the pull also asked turned to aim at it,
    # where the hand is out of reach as written (the Hook's shaft on the Block's far side) and 6.5 cm nearer is not
    aimed = _problem(tmp_path / "aimed", 0.872, -0.057, 30.0, (0.639, -0.325, None))
    rest = aimed.bodies["target"].rest
    poses = start_poses(rest, aimed.affordance("target", "push_center_nx").motion, aimed.goals[0])
    assert len(poses) == 2
    turned = math.degrees(math.atan2(poses[1][1, 0], poses[1][0, 0]))
    way = np.asarray(aimed.goals[0].position) - rest[:2, 3]
    assert turned - 180.0 == pytest.approx(math.degrees(math.atan2(way[1], way[0])), abs=1e-6)
    assert [a.name for a in aimed.bodies["target"].affordances if "/straight" in a.name] == [
        "push_center_nx@-6.50cm/straight/over+20deg+0.50cm"
    ]


def test_the_block_beyond_the_written_pull_s_reach_is_pulled_from_nearer_the_arm(tmp_path):
    problem = _far_block(tmp_path)
    seq = start_sequence(problem)
    seq, _ = extend(problem, seq, Action("add", Engagement("arm.fingertip", "hook", "wield")))
    seq, hand = extend(problem, seq, Action("add", Engagement("hook.tip", "target", MEMBER)))
    assert hand is not None and problem.arm.reachable(hand[:3, 3])  # not cut by the search's at-once reach check
    solution = task_space(problem, seq, time.perf_counter() + 30.0)
    assert not isinstance(solution, Rejection), solution.why
    assert solution.values[0] == pytest.approx(0.31, abs=0.01)  # the whole way in one pull


def test_the_solve_finds_the_pull_from_nearer_the_arm(tmp_path):
    target = generated_tasks.Placement("target", "Block", 0.906, -0.172, 30.0)
    tools = tuple(generated_tasks.Placement(n, t.name, tx, ty, a) for n, t, tx, ty, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("nearer", 0, 0, (target, *tools), (0.638, -0.327, 30.0), "far-pull", False, 0.31)
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path, generated_tasks.fixture_library(())))
    plan = vkgl.solve(program, "nearer", timeout=generated_tasks.TEST_SOLVE_TIMEOUT_S)
    assert plan.status == "solved", plan.reason
    assert [(s.op, s.affordance) for s in plan.steps][-1] == ("add", f"Block.{MEMBER}")
