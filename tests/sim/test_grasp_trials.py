"""Grasps found from geometry and checked in DART: what fits the hand, what holds, what slips."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vkgl.api import learn_grasps
from vkgl.infer.grasps.kept import grasp_ir
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.grasps import GraspSettings
from vkgl.lang.syntax.parser import parse_module
from vkgl.robot.gripper import gripper
from vkgl.sim.grasp.candidates import grasp_candidates
from vkgl.sim.grasp.run import panda_urdf


def _body(text: str) -> ir.Body:
    (body,) = parse_module(text, "body.vkg").decls
    assert isinstance(body, ir.Body)
    return body


def test_a_body_wider_than_the_hand_gets_no_grasp() -> None:
    crate = _body("body Crate { shape box (10, 12, 9) cm mass 1 kg }")  # every side wider than 8 cm
    assert grasp_candidates(crate, gripper(panda_urdf()), GraspSettings()) == []
    trials, kept = learn_grasps(crate)
    assert trials.trials == [] and kept == []


def test_a_cube_is_grasped_from_above_across_either_pair_of_sides() -> None:
    cube = _body("body Cube { shape box (5, 5, 5) cm mass 0.2 kg explore grasps { approach top trials 1 } }")
    trials, kept = learn_grasps(cube)
    assert [a.name for a in kept] == ["grasp_top_x", "grasp_top_y"]
    for grasp in kept:
        assert isinstance(grasp.action, ir.GraspC) and isinstance(grasp.motion, ir.FreeC)
        assert grasp.action.width == pytest.approx(0.05) and grasp.action.force == pytest.approx(20.0)
        pose = grasp.action.pose.matrix()
        assert pose[:3, 2] == pytest.approx((0, 0, 1))  # from above: the effector frame's z up
        assert -1e-9 <= pose[2, 3] < 0.025  # the fingertips in the cube's upper half, 2.5 cm or more above the table
        assert grasp.evidence is not None and grasp.evidence.slip is not None and grasp.evidence.slip <= 0.005
    moved = [t.moved for t in trials.trials]
    assert min(moved) > 0.09  # lifted with the hand, 10 cm


def test_a_heavy_slippery_body_squeezed_too_lightly_slips_and_is_not_kept() -> None:
    # 2 kg need 19.6 N of friction; 5 N on each side with friction 0.2 give 2 N
    brick = _body(
        "body Brick { shape box (5, 5, 5) cm mass 2 kg friction 0.2 explore grasps { approach top force 5 N } }"
    )
    trials, kept = learn_grasps(brick)
    assert kept == []
    ran = [t for t in trials.trials if not t.blocked]
    assert ran and all(t.slip > 0.005 for t in ran)  # each candidate's first trial slipped: no more were run
    assert len(ran) == len(trials.candidates) == 2


def test_the_same_body_gives_the_same_grasps() -> None:
    cube = _body("body Cube { shape box (5, 5, 5) cm mass 0.2 kg explore grasps { approach top trials 2 } }")
    first, second = learn_grasps(cube, seed=3), learn_grasps(cube, seed=3)
    assert first[1] == second[1]


def test_a_grasp_from_the_side_reads_back_as_its_frame() -> None:
    cube = _body("body Cube { shape box (5, 5, 5) cm mass 0.2 kg }")
    side_only = GraspSettings(approaches=("side",))
    for candidate in grasp_candidates(cube, gripper(panda_urdf()), side_only):
        written = grasp_ir(candidate, 20.0).pose.matrix()
        assert np.abs(written - candidate.pose).max() < 1e-6, candidate.name
        if abs(candidate.pose[2, 1]) < 1e-9:  # closing level: the hand's x axis up, above the pads, clear of the table
            assert candidate.pose[2, 0] > 0.99


def test_approach_none_learns_no_grasps() -> None:
    cube = _body("body Cube { shape box (5, 5, 5) cm mass 0.2 kg explore grasps { approach none } }")
    trials, kept = learn_grasps(cube)
    assert trials.candidates == [] and kept == []


@settings(max_examples=60, deadline=None)
@given(st.tuples(*[st.integers(min_value=5, max_value=150)] * 3))
def test_every_candidate_fits_the_hand_and_puts_the_pads_across_the_box(size_mm: tuple[int, int, int]) -> None:
    box = _body(f"body B {{ shape box ({size_mm[0]}, {size_mm[1]}, {size_mm[2]}) mm mass 0.2 kg }}")
    hand = gripper(panda_urdf())
    pad_middle = np.append(hand.pad_box()[0], 1.0)
    for candidate in grasp_candidates(box, hand, GraspSettings()):
        closing = candidate.pose[:3, 1]
        across = int(np.argmax(np.abs(closing)))
        assert candidate.width == pytest.approx(size_mm[across] / 1000.0) and candidate.width <= 0.07 + 1e-12
        assert candidate.opening <= hand.max_opening + 1e-12
        middle = (candidate.pose @ pad_middle)[:3]
        assert abs(middle[across]) < 1e-9  # the pads centred across the box
        assert np.all(np.abs(middle) <= np.array(size_mm) / 2000.0 + 0.015)  # and on it, within half a pad
