"""Sweeps: bodies moving along prismatic and revolute motions against still bodies, sampled so nothing slips through."""

from __future__ import annotations

import numpy as np
import pytest
from checkers.collision_shapes import box, hook, pose
from plan_programs import compiled  # noqa: F401 (fixture)

from vkgl.lang.ir.nodes import PrismaticC, RevoluteC, Vector
from vkgl.motion.collision import TABLE, CollisionScene, pair
from vkgl.plan.geometry.sweep import MAX_SLIP, STEP, sample_values, sweep, sweep_mode
from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.graphs.motions import motion_matrix
from vkgl.plan.graphs.rollout import ModeTrace, tool_pose_on
from vkgl.plan.problem.problem import build_problem, collision_scene

ALONG_X = PrismaticC(axis=Vector(values=(1.0, 0.0, 0.0)))


def _blocks() -> CollisionScene:
    return CollisionScene({"mover": box(0.1, 0.1, 0.05), "wall": box(0.1, 0.1, 0.05)})


def test_a_block_pushed_through_another_is_caught_and_one_stopping_short_is_free() -> None:
    scene = _blocks()
    start, wall = pose(0, 0, 0), {"wall": pose(0.5, 0, 0)}
    hits = sweep(scene, start, ALONG_X, 0.8, {"mover": start}, wall)
    assert [(c.body_a, c.body_b) for c in hits] == [("mover", "wall")]
    # how deep it goes, not how deep the first sample that overlaps is (its face barely inside the wall): the
    # two 5 cm high boxes overlap by up to their height (lifting one 5 cm parts them)
    assert hits[0].depth == pytest.approx(0.05, abs=0.003)
    # faces meet at 0.4 m of travel; stopping 1 cm short is free, and so is just touching
    assert sweep(scene, start, ALONG_X, 0.39, {"mover": start}, wall) == []
    assert sweep(scene, start, ALONG_X, 0.4, {"mover": start}, wall) == []


def test_a_graze_is_reported_as_a_graze() -> None:
    """A mover passing a post's side by 3 mm: the depth said is the graze's, not a deep one."""
    scene = CollisionScene({"mover": box(0.1, 0.1, 0.05), "post": box(0.012, 0.1, 0.05)})
    start = pose(0, 0, 0)
    hits = sweep(scene, start, ALONG_X, 0.9, {"mover": start}, {"post": pose(0.4, 0.097, 0)})
    assert [(c.body_a, c.body_b) for c in hits] == [("mover", "post")]
    assert hits[0].depth == pytest.approx(0.003, abs=0.001)


def test_an_overlap_between_coarse_samples_is_still_caught() -> None:
    """A thin post that the mover grazes by 5.5 mm, halfway between samples 30 cm apart."""
    scene = CollisionScene({"mover": box(0.1, 0.1, 0.05), "post": box(0.012, 0.1, 0.05)})
    start = pose(0, 0, 0)
    post = {"post": pose(0.375, 0.1 - MAX_SLIP - 0.0005, 0)}  # overlaps the mover's side by 5.5 mm in y
    coarse = sweep(scene, start, ALONG_X, 0.9, {"mover": start}, post, step=0.3)
    assert coarse == []  # samples at 0, 0.3, 0.6, 0.9: the post falls between them (the test can fail)
    assert sweep(scene, start, ALONG_X, 0.9, {"mover": start}, post)
    for x in np.linspace(0.1, 0.8, 15):  # wherever along the way the post stands
        moved = {"post": pose(float(x), 0.1 - MAX_SLIP - 0.0005, 0)}
        assert sweep(scene, start, ALONG_X, 0.9, {"mover": start}, moved), x


def test_sample_values_keep_every_point_within_a_step() -> None:
    prismatic = sample_values(ALONG_X, 0.3, reach=0.2)
    assert np.diff(prismatic).max() <= STEP + 1e-12 and prismatic[-1] == 0.3
    turn = RevoluteC(center=Vector(values=(0.0, 0.1, 0.0)), axis=Vector(values=(0.0, 0.0, 1.0)))
    angles = sample_values(turn, np.pi / 2, reach=0.2)
    assert np.diff(angles).max() * (0.2 + 0.1) <= STEP + 1e-12


def test_a_pulled_hooks_cross_piece_is_swept_not_only_its_shaft() -> None:
    scene = CollisionScene({"hook": hook(), "obstacle": box(0.03, 0.03, 0.03), "block": box(0.1, 0.2, 0.05)})
    start = pose(0.5, 0, 0.01)
    back = PrismaticC(axis=Vector(values=(-1.0, 0.0, 0.0)))
    # the obstacle stands in the path of the cross-piece (y 0.03..0.15 of the hook), not of the shaft
    in_path = {"obstacle": pose(0.45, 0.1, 0.01)}
    hits = sweep(scene, start, back, 0.3, {"hook": start}, in_path)
    assert [(c.body_a, c.body_b) for c in hits] == [("hook", "obstacle")]
    assert sweep(scene, start, back, 0.3, {"hook": start}, {"obstacle": pose(0.45, -0.1, 0.01)}) == []


def test_the_body_a_tool_acts_on_may_be_ignored_and_what_moves_with_it_is_swept() -> None:
    scene = CollisionScene({"hook": hook(), "block": box(0.1, 0.2, 0.05), "wall": box(0.05, 0.4, 0.05)})
    block, tool = pose(0.3, 0.0, 0.0), pose(0.17, -0.12, 0.0)  # the cross-piece against the far face (x 0.35)
    back = PrismaticC(axis=Vector(values=(-1.0, 0.0, 0.0)))
    movers = {"block": block, "hook": tool}
    wall = {"wall": pose(-0.2, 0.0, 0.0)}
    # with the hook touching the block only, a short pull is free and a long one hits the wall (the shaft first)
    assert sweep(scene, block, back, 0.05, movers, wall, ignore={pair("hook", "block")}) == []
    hits = sweep(scene, block, back, 0.3, movers, wall, ignore={pair("hook", "block")})
    assert {c.body_a for c in hits} == {"hook"} and {c.body_b for c in hits} == {"wall"}


def test_a_revolute_sweep_hits_what_lies_within_the_turn_only() -> None:
    scene = CollisionScene({"stick": box(0.4, 0.02, 0.02), "block": box(0.05, 0.05, 0.05)})
    start = pose(0.2, 0, 0)  # the stick from x 0 to 0.4; it turns about its end at the origin
    turn = RevoluteC(center=Vector(values=(-0.2, 0.0, 0.0)), axis=Vector(values=(0.0, 0.0, 1.0)))
    at_45 = {"block": pose(0.3 * np.cos(np.pi / 4), 0.3 * np.sin(np.pi / 4), 0)}
    at_135 = {"block": pose(0.3 * np.cos(3 * np.pi / 4), 0.3 * np.sin(3 * np.pi / 4), 0)}
    assert sweep(scene, start, turn, np.pi / 2, {"stick": start}, at_45)
    assert sweep(scene, start, turn, np.pi / 2, {"stick": start}, at_135) == []
    assert sweep(scene, start, turn, np.pi / 6, {"stick": start}, at_45) == []  # stops before it


def test_the_table_counts_in_a_sweep() -> None:
    scene = CollisionScene(
        {"block": box(0.1, 0.2, 0.05)}, table_center=np.array([0.5, 0.0]), table_size=np.array([1.6, 1.2])
    )
    start = pose(0.4, 0, 0.025)  # resting on the top
    assert sweep(scene, start, ALONG_X, 0.3, {"block": start}, {}) == []  # sliding on the table is touching
    down = PrismaticC(axis=Vector(values=(0.0, 0.0, -1.0)))
    hits = sweep(scene, start, down, 0.05, {"block": start}, {})
    assert [c.body_b for c in hits] == [TABLE]
    assert sweep(scene, start, down, 0.05, {"block": start}, {}, table=False) == []


@pytest.fixture(scope="module")
def problem(compiled):
    program = compiled("a_push")
    return build_problem(program, program.task())


def test_sweep_mode_sweeps_a_rollouts_pushed_block_against_the_other_bodies(problem) -> None:
    scene = collision_scene(problem)
    poses = {n: b.rest for n, b in problem.bodies.items()}
    push = Engagement(problem.robot_effector.name, "block", "push_center_px")
    motion = problem.affordance("block", "push_center_px").motion

    def trace(value: float, start: dict[str, np.ndarray]) -> ModeTrace:
        end = dict(start)
        end["block"] = start["block"] @ motion_matrix(motion, value)
        return ModeTrace(start, end, [], True, {push: value})

    assert sweep_mode(scene, problem, trace(0.3, poses)) == []
    # put the hook across the block's way: pushing the block 30 cm along its x now hits it
    blocked = dict(poses, hook=poses["block"] @ pose(0.3, 0.0, 0.0, yaw=np.pi / 2))
    hits = sweep_mode(scene, problem, trace(0.3, blocked))
    assert {(c.body_a, c.body_b) for c in hits} == {("block", "hook")}
    assert sweep_mode(scene, problem, trace(0.05, blocked)) == []  # a short push stops before it


def test_sweep_mode_sweeps_the_tool_that_turns_a_block_with_it(compiled) -> None:
    program = compiled("e_rotate_stick_push")
    problem = build_problem(program, program.task())
    scene = collision_scene(problem)
    turn = Engagement("stick.tip", "block", "turn_px_left")
    motion = problem.affordance("block", "turn_px_left").motion
    start = {n: b.rest for n, b in problem.bodies.items()}
    start["stick"] = tool_pose_on(problem, turn, start["block"])
    end = dict(start, block=start["block"] @ motion_matrix(motion, 0.5))
    end["stick"] = tool_pose_on(problem, turn, end["block"])
    # the hook lies where only the stick's handle swings to (40 cm from the block)
    start["hook"] = end["hook"] = end["stick"] @ pose(-0.34, 0.0, 0.0)
    trace = ModeTrace(start, end, [], False, {turn: 0.5})
    hits = sweep_mode(scene, problem, trace)
    assert {(c.body_a, c.body_b) for c in hits} == {("stick", "hook")}
