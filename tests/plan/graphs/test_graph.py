"""Kinematic graphs and the search's transitions: G0, ADD/REMOVE, and the pruning rules that keep solutions."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.plan.graphs.graph import Action, Engagement, edges, g0, successors
from vkgl.plan.graphs.rollout import extend, rollout, start_sequence
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.problem.rejection import Rejection
from vkgl.plan.task_space.closed_form import closed_form


@pytest.fixture(scope="module")
def problem(compiled):
    program = compiled("d_rotate_push")
    return build_problem(program, program.task())


def add(effector: str, body: str, affordance: str) -> Action:
    return Action("add", Engagement(effector, body, affordance))


def labels(actions: list[Action]) -> list[str]:
    return [f"{a.op} {a.engagement.body}.{a.engagement.affordance} {a.engagement.effector}" for a in actions]


def test_g0_has_every_body_at_rest_and_the_robot_free(problem):
    assert edges(problem, g0()) == [
        ("block", "world", "fixed"),
        ("stick", "world", "fixed"),
        ("hook", "world", "fixed"),
        ("arm", "world", "free"),
    ]


def test_from_g0_only_the_hand_acts_and_nothing_can_be_removed(problem):
    found = labels(successors(problem, g0(), None))
    grasps = [a.name for tool in ("stick", "hook") for a in problem.bodies[tool].affordances if a.motion.type == "free"]
    pushes = len(problem.bodies["block"].affordances)  # the block's learned affordances (ten under the cone)
    assert pushes >= 10 and len(grasps) >= 2 and len(found) == pushes + len(grasps)  # and every grasp of a tool
    assert all(a.startswith("add") and a.endswith("arm.fingertip") for a in found)
    assert "add stick.wield arm.fingertip" in found and "add hook.wield arm.fingertip" in found


def test_a_held_tool_becomes_an_effector_and_stays_in_hand_while_it_acts(problem):
    grasp = add("arm.fingertip", "stick", "wield")
    holding = g0().apply(grasp)
    found = labels(successors(problem, holding, grasp))
    assert found == [f"add block.{a.name} stick.tip" for a in problem.bodies["block"].affordances]  # no re-release
    push = add("stick.tip", "block", "push_center_px")
    pushing = holding.apply(push)
    assert edges(problem, pushing)[-2:] == [("arm", "stick", "fixed"), ("stick", "block", "fixed")]
    assert labels(successors(problem, pushing, push)) == ["remove block.push_center_px stick.tip"]


def _without_ranges(problem):
    """`problem` with the block's affordances as hand-written ones without a `range` (unbounded)."""
    block = problem.bodies["block"]
    unbounded = tuple(
        a.model_copy(update={"motion": a.motion.model_copy(update={"range": None})}) for a in block.affordances
    )
    bodies = dict(problem.bodies, block=dataclasses.replace(block, affordances=unbounded))
    return dataclasses.replace(problem, bodies=bodies, _affordances={})


def test_an_unbounded_engagement_just_removed_is_not_added_again(problem):
    push = add("arm.fingertip", "block", "push_center_px")
    removed = Action("remove", push.engagement)
    after = g0().apply(push).apply(removed)
    found = labels(successors(_without_ranges(problem), after, removed))
    assert "add block.push_center_px arm.fingertip" not in found
    assert "add block.turn_px_left arm.fingertip" in found


def test_a_ranged_engagement_just_removed_may_be_made_again(problem):
    push = add("arm.fingertip", "block", "push_center_px")
    assert problem.affordance("block", "push_center_px").motion.range is not None  # learned
    removed = Action("remove", push.engagement)
    after = g0().apply(push).apply(removed)
    assert "add block.push_center_px arm.fingertip" in labels(successors(problem, after, removed))


def test_rollout_composes_the_affordances_motions(problem):
    seq = start_sequence(problem)
    for action in (
        add("arm.fingertip", "block", "turn_px_left"),
        Action("remove", Engagement("arm.fingertip", "block", "turn_px_left")),
        add("arm.fingertip", "block", "push_center_px"),
    ):
        seq, _ = extend(problem, seq, action)
    traces = rollout(problem, seq, np.array([math.radians(20), 0.10]))
    final = traces[-1].end["block"]
    assert np.allclose(final[:2, 3], _turn_then_slide(problem, math.radians(20), 0.10), atol=1e-9)
    assert math.isclose(math.atan2(final[1, 0], final[0, 0]), math.radians(-20), abs_tol=1e-9)
    hand = traces[-1].hand
    assert len(hand) == 5 and np.allclose(hand[-1][:3, 3], (final @ problem.action("block", "push_center_px"))[:3, 3])


def _turn_then_slide(problem, angle: float, slide: float) -> np.ndarray:
    """Where the block ends, computed by hand from the affordances' source parameters: turn about the
    turn's centre (in the body frame, axis -z), then slide along the body's new +x."""
    turn = next(a for a in problem.program.affordances["Block"] if a.name == "turn_px_left")
    assert turn.motion.type == "revolute" and np.allclose(turn.motion.axis.array(), (0, 0, -1))
    center_body = turn.motion.center.array()[:2]
    start = np.array([0.45, 0.0])  # the block in scene `tabletop`, yaw 0
    center = start + center_body
    c, s = math.cos(-angle), math.sin(-angle)
    turned = center + np.array([[c, -s], [s, c]]) @ (start - center)
    return turned + slide * np.array([c, s])


def test_closed_form_rejects_a_turn_the_wrong_way_and_pins_the_right_one(problem):
    wrong, _ = extend(problem, start_sequence(problem), add("arm.fingertip", "block", "turn_px_right"))
    rejected = closed_form(problem, wrong)
    assert isinstance(rejected, Rejection) and rejected.kind == "yaw"
    seq = start_sequence(problem)
    for action in (
        add("arm.fingertip", "block", "turn_px_left"),
        Action("remove", Engagement("arm.fingertip", "block", "turn_px_left")),
        add("arm.fingertip", "block", "push_center_px"),
    ):
        seq, _ = extend(problem, seq, action)
    values, pinned = closed_form(problem, seq)
    assert pinned and math.isclose(values[0], math.radians(20), abs_tol=1e-3)  # the goal's yaw
    goal = np.array([0.582, -0.043])  # task d's goal, within 1 cm
    assert np.linalg.norm(_turn_then_slide(problem, values[0], values[1]) - goal) < 0.01


def test_a_held_tool_enacts_a_handles_pulls_but_never_its_grasps(compiled):
    # a correspondence lets the hook's tip push where the fingertip would; a grasp is the fingers closing
    program = compiled("i_hook_drawer")
    drawer_hook = build_problem(program, program.task())
    wield = add("arm.fingertip", "hook", "wield")
    found = labels(successors(drawer_hook, g0().apply(wield), wield))
    affordances = drawer_hook.bodies["drawer"].affordances
    grasps = {a.name for a in affordances if a.action.type == "grasp"}
    assert grasps and "add drawer.pull_px_left hook.tip" in found
    assert found == [f"add drawer.{a.name} hook.tip" for a in affordances if a.name not in grasps]
    assert any(f"add drawer.{g} arm.fingertip" in labels(successors(drawer_hook, g0(), None)) for g in grasps)
