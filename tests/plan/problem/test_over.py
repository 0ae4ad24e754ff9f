"""A tool rolled over a wide body (`vkgl.plan.problem.over`): the least roll whose shaft passes over the top, the
cross-piece still on the centre line; offered to that tool only, and only where lying flat it stands in the body."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from task_makers import generated_tasks

import vkgl
from vkgl.lang.ir.families import find_member, over_name, over_pose
from vkgl.plan.graphs.graph import Action, Engagement, g0, successors
from vkgl.plan.graphs.rollout import extend, start_sequence
from vkgl.plan.problem.over import (
    COVER_MARGIN,
    PART_CLEARANCE,
    TABLE_CLEARANCE,
    TIP_SHARE,
    _rolled,
    highest_lift,
    roll_for,
    roll_over_beside,
)
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.task_space.feasible import TaskSolution, task_space


def _problem(tmp_path, body: str, goal=(0.78, 0.05, 0.0)):
    target = generated_tasks.Placement("target", body, 0.95, 0.05, 0.0)
    tools = tuple(generated_tasks.Placement(n, t.name, x, y, a) for n, t, x, y, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("over", 0, 0, (target, *tools), goal, "far-pull", False, 0.17)
    library = generated_tasks.fixture_library((body,))
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path / body, library))
    return build_problem(program, program.tasks["over"])


def _over(problem):
    return [a.name for a in problem.bodies["target"].affordances if "/over" in a.name]


# the Hook in its tip frame (x toward the handle, into the body; y toward the shaft): the cross-piece 2 cm deep
# behind the contact plane from 3 cm past the tip to the shaft, the shaft 2 x 2 cm from the cross-piece back 40 cm
CROSS = np.array([[x, y, z] for x in (-0.02, 0.0) for y in (-0.03, 0.13) for z in (-0.01, 0.01)])
SHAFT = np.array([[x, y, z] for x in (-0.02, 0.38) for y in (0.11, 0.13) for z in (-0.01, 0.01)])


def _box(depth: float, width: float, height: float) -> np.ndarray:
    """A body's hull points in the contact's frame: its face at x = 0, its centre line at y = 0, the contact at
    mid-height."""
    return np.array(
        [[x, y, z] for x in (0.0, depth) for y in (-width / 2, width / 2) for z in (-height / 2, height / 2)]
    )


def test_a_low_wide_slab_gets_the_least_roll_that_lifts_the_shaft_over_its_top():
    roll, lift = roll_for([CROSS, SHAFT], _box(0.16, 0.30, 0.06), 0.0)
    assert math.degrees(roll) == pytest.approx(20.0) and lift == pytest.approx(0.01)
    shaft, cross = _rolled(SHAFT, roll, lift), _rolled(CROSS, roll, lift)
    assert shaft[:, 2].min() >= 0.03 + PART_CLEARANCE  # over the slab's top
    assert cross[:, 2].min() >= -0.03 + TABLE_CLEARANCE  # the cross-piece's free end above the table
    # one roll less does not clear the top at any lift the rule allows (up to half-way to the top)
    lower = math.radians(15.0)
    assert all(_rolled(SHAFT, lower, lift)[:, 2].min() < 0.03 + PART_CLEARANCE for lift in np.arange(0, 0.016, 0.005))


def test_a_tall_crate_needs_more_roll_and_the_cross_piece_still_covers_its_centre_line():
    roll, lift = roll_for([CROSS, SHAFT], _box(0.20, 0.30, 0.18), 0.0)
    assert 30.0 <= math.degrees(roll) <= 40.0 and lift <= 0.045 + 1e-9
    assert _rolled(SHAFT, roll, lift)[:, 2].min() >= 0.09 + PART_CLEARANCE
    face = _rolled(CROSS[CROSS[:, 0] == 0.0], roll, lift)  # the contact plane's corners: the slanted strip
    assert face[:, 1].min() <= -COVER_MARGIN and face[:, 1].max() >= COVER_MARGIN


def test_a_crate_whose_friction_lets_it_be_pulled_high_gets_less_roll_below_its_tipping_height():
    crate = _box(0.20, 0.30, 0.18)
    assert highest_lift(crate, None) == pytest.approx(0.045)  # half-way to the top, friction unknown
    # friction 0.5, 20 cm deep: the contact at most 0.8 x 10 cm / 0.5 = 16 cm over the table, 7 cm over mid-height
    assert highest_lift(crate, 0.5) == pytest.approx(-0.09 + TIP_SHARE * 0.10 / 0.5)
    assert highest_lift(crate, 1.0) == pytest.approx(0.045)  # a grippy crate: never below half-way
    assert highest_lift(crate, 0.1) == pytest.approx(0.085)  # a slippery one: a lift step below its top
    roll, lift = roll_for([CROSS, SHAFT], crate, 0.0, friction=0.5)
    assert math.degrees(roll) == pytest.approx(20.0) and 0.045 < lift <= highest_lift(crate, 0.5) + 1e-9
    assert 0.5 * (0.09 + lift) <= TIP_SHARE * 0.10 + 1e-9  # friction times the height under the half-depth's share
    assert _rolled(SHAFT, roll, lift)[:, 2].min() >= 0.09 + PART_CLEARANCE
    face = _rolled(CROSS[CROSS[:, 0] == 0.0], roll, lift)
    assert face[:, 1].min() <= -COVER_MARGIN and face[:, 1].max() >= COVER_MARGIN
    grippy_roll, grippy_lift = roll_for([CROSS, SHAFT], crate, 0.0, friction=1.0)
    assert (grippy_roll, grippy_lift) == roll_for([CROSS, SHAFT], crate, 0.0)  # as without friction


def test_a_crate_gets_the_higher_member_after_the_half_way_one_and_a_slab_only_the_half_way_one(tmp_path):
    crate = [n for n in _over(_problem(tmp_path, "CrateM")) if n.startswith("push_center_nx/")]
    assert crate == ["push_center_nx/over+35deg+4.50cm", "push_center_nx/over+20deg+7.00cm"]
    assert [n for n in _over(_problem(tmp_path, "SlabW")) if n.startswith("push_center_nx/")] == [
        "push_center_nx/over+20deg+1.00cm"  # 15 deg 2 cm up saves 5 deg only
    ]


def test_nothing_where_the_tool_lying_flat_clears_the_body_or_slides_aside_to_clear_it():
    assert roll_for([CROSS, SHAFT], _box(0.20, 0.20, 0.06), 0.0) is None  # the Block: the shaft 1 cm clear
    assert roll_for([CROSS, SHAFT], _box(0.16, 0.24, 0.25), 0.0) is None  # CrateT: 2 cm along the face clears it
    assert roll_for([CROSS], _box(0.16, 0.30, 0.06), 0.0) is None  # no part beside the contact (a stick's end)


def test_the_shaft_on_the_other_side_rolls_the_other_way():
    mirrored = [p * np.array([1.0, -1.0, 1.0]) for p in (CROSS, SHAFT)]
    roll, _ = roll_for(mirrored, _box(0.16, 0.30, 0.06), 0.0)
    assert math.degrees(roll) == pytest.approx(-20.0)


def test_the_member_is_the_slide_rolled_about_its_push_and_raised_and_its_name_reads_back(tmp_path):
    problem = _problem(tmp_path, "SlabW")
    name = "push_center_nx/over+20deg+1.00cm"
    assert over_name("push_center_nx", math.radians(20), 0.01) == name
    assert over_pose(name) == pytest.approx(("push_center_nx", math.radians(20), 0.01))
    assert name in _over(problem)
    written = problem.affordance("target", "push_center_nx")
    member = problem.affordance("target", name)
    assert member.motion == written.motion
    a, b = problem.action("target", "push_center_nx"), problem.action("target", name)
    assert b[:3, 0] == pytest.approx(a[:3, 0])  # the same push direction
    assert b[:3, 3] - a[:3, 3] == pytest.approx([0.0, 0.0, 0.01])
    assert a[:3, 1] @ b[:3, 1] == pytest.approx(math.cos(math.radians(20)))
    assert b[2, 1] == pytest.approx(math.sin(math.radians(20)))  # the shaft's side up
    # the executor reads the same member from the program's affordances
    program_affordances = problem.program.affordances["SlabW"]
    again = find_member(program_affordances, name)
    assert again is not None and again.action == member.action
    with pytest.raises(ValueError, match="no rolled slide"):
        over_pose("push_center_nx/over20")


def test_only_the_hook_may_enact_it_and_bodies_it_clears_get_none(tmp_path):
    problem = _problem(tmp_path, "SlabW")
    names = _over(problem)
    assert problem.bodies["target"].tool_members == {(n, "hook.tip") for n in names}
    free = successors(problem, g0(), None)
    assert not any(a.engagement.affordance in names for a in free)  # the fingertip: never
    wield = Action("add", Engagement("arm.fingertip", "hook", "wield"))
    adds = {(a.engagement.effector, a.engagement.affordance) for a in successors(problem, g0().apply(wield), wield)}
    assert {("hook.tip", n) for n in names} <= adds
    wield = Action("add", Engagement("arm.fingertip", "stick", "wield"))
    adds = {(a.engagement.effector, a.engagement.affordance) for a in successors(problem, g0().apply(wield), wield)}
    assert not any(n in names for _, n in adds)  # the stick has no part beside its end
    assert _over(_problem(tmp_path, "CrateT")) == []  # its straight band serves (`tool_faces`)


@given(st.integers(-90, 90), st.integers(0, 2000), st.sampled_from(["push_center_nx", "push_center_px", "slide_2"]))
def test_an_over_members_name_gives_back_its_roll_and_lift(degrees, hundredths_cm, slide):
    roll, lift = math.radians(degrees), hundredths_cm * 1e-4  # what the name keeps: 1 deg, 0.01 cm
    base, roll_back, lift_back = over_pose(over_name(slide, roll, lift))
    assert base == slide and roll_back == pytest.approx(roll) and lift_back == pytest.approx(lift, abs=1e-9)


def test_an_arc_member_toward_the_shaft_rolls_over_and_its_cross_piece_covers_the_contact_not_the_centre_line():
    """A Block's arc member 1.74 cm toward the hook's shaft (the body's centre line at +1.74 cm in the contact's
    frame): lying flat, the shaft stands 0.74 cm inside the Block; moved along the face it would clear it, but an
    arc's offset is what makes its turn, so the tool rolls over instead, covering the contact itself."""
    block = _box(0.10, 0.20, 0.05) + np.array([0.0, 0.0174, 0.0])
    assert roll_for([CROSS, SHAFT], block, 0.0174) is None  # a slide: moved along the face it clears the Block
    roll, lift = roll_for([CROSS, SHAFT], block, 0.0174, turn=True)
    assert math.degrees(roll) == pytest.approx(20.0) and lift == pytest.approx(0.005)
    assert _rolled(SHAFT, roll, lift)[:, 2].min() >= 0.025 + PART_CLEARANCE  # over the Block's top
    assert roll_for([CROSS, SHAFT], _box(0.10, 0.20, 0.05) - np.array([0.0, 0.01, 0.0]), -0.01, turn=True) is None


def test_a_free_heading_pull_whose_arc_needs_the_shaft_side_gets_the_rolled_hook_one_pull_reaching_the_goal(tmp_path):
    """gen9_027's Block and goal without its clutter: the one arc through the goal puts the contact 1.74 cm toward
    the shaft; the hook rolled 20 deg over the Block pulls it there in one contact, a 60 deg turn (solved at depth
    3 and carried out in DART within 0.02 cm: docs/planning.md, "Arcs toward the shaft")."""
    target = generated_tasks.Placement("target", "Block", 0.819, 0.379, -5.0)
    tools = tuple(generated_tasks.Placement(n, t.name, x, y, a) for n, t, x, y, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("arc_over", 0, 0, (target, *tools), (0.609, 0.305, None), "far-pull", False, 0.22)
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path / "arc_over", {}))
    problem = build_problem(program, program.tasks["arc_over"])
    name = "push_center_nx@-1.74cm/over+20deg+0.50cm"
    assert _over(problem) == [name]  # pulled 1 cm higher it rolls 15 deg: too little saved for another member
    assert problem.bodies["target"].tool_members == {(name, "hook.tip")}
    turn, rolled = problem.affordance("target", "push_center_nx@-1.74cm"), problem.affordance("target", name)
    assert rolled.motion == turn.motion  # the arc's turn, enacted rolled
    again = find_member(program.affordances["Block"], name)  # what the executor reads
    assert again is not None and again.action == rolled.action and again.motion == turn.motion
    seq = start_sequence(problem)
    for action in (
        Action("add", Engagement("arm.fingertip", "hook", "wield")),
        Action("add", Engagement("hook.tip", "target", name)),
    ):
        seq, _ = extend(problem, seq, action)
    found = task_space(problem, seq, time.perf_counter() + 60)  # one pull reaches the goal, the hand in reach
    assert isinstance(found, TaskSolution), found
    assert math.degrees(found.values[0]) == pytest.approx(60.3, abs=1.0)


def test_an_arc_member_beside_low_bodies_rolls_its_shaft_over_them_and_not_where_flat_clears_them():
    """A cube's pull whose shaft, lying flat 4 cm up, would sweep a 5 cm Block beside it: the least roll that lifts
    the shaft 0.5 cm over the Block's top (15 deg: 12 cm out, 3.1 cm up); nothing where nothing stands that high."""
    cube = _box(0.08, 0.08, 0.08)  # the contact at mid-height: the table at z = -0.04
    roll, lift = roll_over_beside([CROSS, SHAFT], cube, 0.05)
    assert math.degrees(roll) == pytest.approx(15.0) and lift == 0.0
    assert _rolled(SHAFT, roll, 0.0)[:, 2].min() >= -0.04 + 0.05 + PART_CLEARANCE
    assert _rolled(SHAFT, math.radians(10.0), 0.0)[:, 2].min() < -0.04 + 0.05 + PART_CLEARANCE
    assert roll_over_beside([CROSS, SHAFT], cube, 0.02) is None  # the shaft flat (3 to 5 cm up) clears 2.5 cm
    assert roll_over_beside([CROSS, SHAFT], cube, 0.0) is None


def test_a_straight_pull_beside_a_low_body_rolls_the_shaft_over_it(tmp_path):
    """gen11_015: a 12 cm cube pulled 34.9 cm straight along its own axis (its heading kept), a CubeS (8 cm) 13 cm
    beside the pull. Lying flat at the cube's mid-height the Hook's shaft passed 0.3 cm through it and no plan of
    6 graphs existed; the slide rolled 20 deg lifts the shaft over it, and one pull does it."""
    spec = generated_tasks.task_spec(11, 15)
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path / spec.name, generated_tasks.fixture_library()))
    plan = vkgl.solve(program, spec.name, max_depth=3, timeout=generated_tasks.TEST_SOLVE_TIMEOUT_S)
    assert "push_center_nx/over+20deg+0.00cm" in _over(plan.problem)
    assert plan.status == "solved", plan.reason
    assert [s.affordance for s in plan.steps] == ["Hook.wield", "CubeM.push_center_nx/over+20deg+0.00cm"]
