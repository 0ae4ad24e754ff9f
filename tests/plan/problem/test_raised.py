"""The fingertip raised on a tall face (`vkgl.plan.problem.raised`, `vkgl.plan.task_space.raised_contacts`): the
least lift that keeps the upright hand's fingers out of the face above the pad, tried only when the written contact
fails the arm's checks, never where the push could tip the body."""

from __future__ import annotations

import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from task_makers import generated_tasks

import vkgl
from vkgl.lang.ir.families import find_member, over_pose
from vkgl.lang.ir.geometry import pushed_face
from vkgl.lang.ir.nodes import Body, Tipping
from vkgl.lang.ir.values import Quantity
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.problem.raised import LIFT_STEP, PAD_CLEAR, TIP_SHARE, leading_edge, needed_lift, raised_name
from vkgl.plan.search.search import search


def _crate_task(tmp_path, x=0.673, y=0.014, yaw=-25.0, goal=(0.331, 0.173, -25.0)):
    """gen1_018 of the physical bench without the cube in its way: a CrateM (20 x 30 x 18 cm) pulled 37.7 cm toward
    the arm from 0.67 m, its far face 0.77 m from the arm's base."""
    target = generated_tasks.Placement("target", "CrateM", x, y, yaw)
    tools = tuple(generated_tasks.Placement(n, t.name, tx, ty, a) for n, t, tx, ty, a in generated_tasks.TOOLS)
    spec = generated_tasks.TaskSpec("raised", 0, 0, (target, *tools), goal, "near", False, 0.377)
    library = generated_tasks.fixture_library(("CrateM",))
    program = vkgl.compile(generated_tasks.write_task(spec, tmp_path / "raised", library))
    return program, build_problem(program, program.tasks["raised"], max_depth=2)


@given(st.floats(-0.05, 0.05), st.floats(0.0, 0.2))
def test_the_lift_is_the_least_step_that_brings_the_top_within_the_fingers_clearance(contact, rise):
    top = contact + rise
    lift = needed_lift(contact, top)
    assert lift >= 0.0 and round(lift / LIFT_STEP, 6) == round(lift / LIFT_STEP)
    assert top - (contact + lift) <= PAD_CLEAR + 1e-9  # the face's top within reach of the pad
    if lift > 0.0:  # one step less would leave the fingers in the face
        assert top - (contact + lift - LIFT_STEP) > PAD_CLEAR


def test_the_leading_edge_is_half_the_box_along_its_push_and_the_corner_diagonally():
    box = np.array([[x, y, z] for x in (-0.1, 0.1) for y in (-0.15, 0.15) for z in (-0.09, 0.09)])
    assert leading_edge(box, np.array([-1.0, 0.0, 0.0])) == pytest.approx(0.1)
    assert leading_edge(box, np.array([0.0, 1.0, 0.0])) == pytest.approx(0.15)
    assert leading_edge(box, np.array([1.0, 1.0, 0.0])) == pytest.approx(0.25 / np.sqrt(2.0))


def test_a_tall_crate_pulled_from_its_far_face_is_pulled_by_its_raised_far_face(tmp_path):
    """Upright at mid-height the hand stands 3 cm in the crate; leaned back 30 to 60 deg it has no IK solution at
    0.77 m: before the raised contact there was no plan of any depth that pulled the crate alone. The raised
    member is the same slide, its action 6.5 cm higher (2.5 cm below the crate's top), and reads back as the
    executor reads it."""
    program, problem = _crate_task(tmp_path)
    found = search(problem, deadline=time.perf_counter() + generated_tasks.TEST_SOLVE_TIMEOUT_S)
    assert found.status == "solved", found.reason
    name = "push_center_nx/over+0deg+6.50cm"
    assert [a.label(problem) for a in found.sequence.actions] == [f"add CrateM.{name} on target with arm.fingertip"]
    raised, written = problem.affordance("target", name), problem.affordance("target", "push_center_nx")
    assert raised.motion == written.motion
    assert raised.action.pose.matrix()[2, 3] == pytest.approx(written.action.pose.matrix()[2, 3] + 0.065)
    again = find_member(program.affordances["CrateM"], name)  # what the executor reads
    assert again is not None and again.action == raised.action
    assert over_pose(name) == ("push_center_nx", 0.0, pytest.approx(0.065))


def test_a_push_the_written_contact_carries_is_not_raised(tmp_path):
    """The crate pushed 20 cm away from the arm, its near face 0.35 m from the base: the hand leaned back carries it
    as written, and the plan keeps the contact exploration made."""
    _, problem = _crate_task(tmp_path, x=0.45, y=0.0, yaw=0.0, goal=(0.65, 0.0, 0.0))
    found = search(problem, deadline=time.perf_counter() + generated_tasks.TEST_SOLVE_TIMEOUT_S)
    assert found.status == "solved", found.reason
    assert [a.label(problem) for a in found.sequence.actions] == [
        "add CrateM.push_center_px on target with arm.fingertip"
    ]


def _tall(depth: float, height: float, friction: float) -> Body:
    program = vkgl.compile_source(
        f"body Tall {{\n    shape box ({100 * depth:g}, 20, {100 * height:g}) cm\n    mass 1 kg\n"
        f"    friction {friction}\n}}\n"
    )
    return program.bodies["Tall"]


def test_no_raise_where_the_raised_pull_could_tip_the_body_nor_where_the_face_is_low(tmp_path):
    _, problem = _crate_task(tmp_path)
    crate = problem.bodies["target"]
    pull = problem.affordance("target", "push_center_nx")
    assert raised_name(crate.type, pull, []) == "push_center_nx/over+0deg+6.50cm"  # at 15.5 cm; d / mu = 20 cm
    narrow = _tall(0.10, 0.30, 0.5)  # d = 5 cm: tips above 10 cm; raised 12.5 cm over its 15 cm mid-height
    assert TIP_SHARE * 0.05 / 0.5 < 0.275
    assert raised_name(narrow, pull, []) is None
    low = _tall(0.20, 0.05, 0.5)  # a Block's height: its face rises 2.5 cm over the contact, the fingers clear it
    assert raised_name(low, pull, []) is None
    turn = problem.affordance("target", "turn_center_nx")  # a turn about an axis off the body: not raised
    assert raised_name(crate.type, turn, []) is None
    # a `tips above` clause measured lower than the raised contact rules it out; one above it does not
    face = pushed_face(pull.action.pose.matrix()[:3, 0])
    assert raised_name(crate.type, pull, [Tipping(height=Quantity(value=0.14, unit="m"), faces=[face])]) is None
    assert raised_name(crate.type, pull, [Tipping(height=Quantity(value=0.16, unit="m"), faces=[face])]) is not None
