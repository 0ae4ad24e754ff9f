"""A last motion out of reach once (`vkgl.plan.search.last_motion`): remembered only when it is the sequence's one
motion, and known again only after a prefix that leaves its body and tool where they rest."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
from task_makers.block_problems import IN_THE_WAY, block_to, labelled_sequence

from vkgl.plan.graphs.rollout import rollout
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.search.last_motion import LastMotion, last_motion_key

OUT_OF_REACH = Rejection(Kind.REACH, "the hand would be 0.9 m from the arm's base", 0.1)


PUSH = "add Block.push_px on block with arm.fingertip"
OTHER = "add Block.push_px on other with arm.fingertip"
OTHER_OFF = "remove Block.push_px on other with arm.fingertip"
PUSH_OFF = "remove Block.push_px on block with arm.fingertip"


def test_a_push_out_of_reach_is_known_after_a_prefix_that_moved_another_body(tmp_path: Path) -> None:
    problem = block_to(tmp_path, 0.66, stick=False, grasp=False, depth=6, other=IN_THE_WAY)
    alone, after_other = labelled_sequence(problem, PUSH), labelled_sequence(problem, OTHER, OTHER_OFF, PUSH)
    assert last_motion_key(problem, alone) == last_motion_key(problem, after_other) is not None
    memo = LastMotion()
    assert memo.known(problem, after_other) is None
    memo.remember(problem, alone, OUT_OF_REACH)
    assert memo.known(problem, after_other) is OUT_OF_REACH


def test_nothing_is_known_after_a_prefix_that_moved_the_body_itself(tmp_path: Path) -> None:
    """The block pushed before starts its last push elsewhere: the hand's poses differ."""
    problem = block_to(tmp_path, 0.66, stick=False, grasp=False, depth=6, other=IN_THE_WAY)
    memo = LastMotion()
    memo.remember(problem, labelled_sequence(problem, PUSH), OUT_OF_REACH)
    assert last_motion_key(problem, labelled_sequence(problem, PUSH, PUSH_OFF, PUSH)) is None
    assert memo.known(problem, labelled_sequence(problem, PUSH, PUSH_OFF, PUSH)) is None


def test_only_a_sequences_one_motion_out_of_reach_is_remembered(tmp_path: Path) -> None:
    """A rejection of a sequence with an earlier motion may be that motion's fault; other kinds are not kept."""
    problem = block_to(tmp_path, 0.66, stick=False, grasp=False, depth=6, other=IN_THE_WAY)
    memo = LastMotion()
    memo.remember(problem, labelled_sequence(problem, OTHER, OTHER_OFF, PUSH), OUT_OF_REACH)
    memo.remember(problem, labelled_sequence(problem, PUSH), Rejection(Kind.GOAL, "missed", 0.0))
    assert not memo.seen


def test_bodies_passing_through_one_another_are_known_while_the_body_named_has_not_moved(tmp_path: Path) -> None:
    """The push swept the block through `other`: after a prefix that moved `other` it may not; after one that
    moved neither it does again. A collision that names no body (the arm's) is not remembered."""
    problem = block_to(tmp_path, 0.66, stick=False, grasp=False, depth=6, other=IN_THE_WAY)
    through = Rejection(Kind.COLLISION, "block would pass through other", 0.02, bodies=frozenset({"block", "other"}))
    memo = LastMotion()
    memo.remember(problem, labelled_sequence(problem, PUSH), Rejection(Kind.COLLISION, "the arm's link", 0.01))
    assert not memo.seen
    memo.remember(problem, labelled_sequence(problem, PUSH), through)
    assert memo.known(problem, labelled_sequence(problem, OTHER, OTHER_OFF, PUSH)) is None
    two = IN_THE_WAY + "    far : Block on table at (0.4, -0.35) m yaw 90deg\n"
    problem = block_to(tmp_path, 0.66, stick=False, grasp=False, depth=6, other=two)
    memo = LastMotion()
    memo.remember(problem, labelled_sequence(problem, PUSH), through)
    far = ("add Block.push_px on far with arm.fingertip", "remove Block.push_px on far with arm.fingertip")
    assert memo.known(problem, labelled_sequence(problem, *far, PUSH)) is through
    assert memo.known(problem, labelled_sequence(problem, OTHER, OTHER_OFF, PUSH)) is None


WIELD = "add Stick.wield on stick with arm.fingertip"
STICK_PUSH = "add Block.push_px on block with stick.tip"
STICK_PUSH_OFF = "remove Block.push_px on block with stick.tip"
STICK_OTHER = "add Block.push_px on other with stick.tip"
STICK_OTHER_OFF = "remove Block.push_px on other with stick.tip"


def test_a_tool_that_pushed_another_body_first_is_where_its_last_push_puts_it(tmp_path: Path) -> None:
    """The stick in the hand pushed `other`, then jumps to the block: its last push is the same as from the wield
    alone (the same key, and known), the stick named by the failure included; not when the block itself moved."""
    problem = block_to(tmp_path, 0.66, stick=True, grasp=False, depth=8, other=IN_THE_WAY)
    alone = labelled_sequence(problem, WIELD, STICK_PUSH)
    after_other = labelled_sequence(problem, WIELD, STICK_OTHER, STICK_OTHER_OFF, STICK_PUSH)
    assert last_motion_key(problem, alone) == last_motion_key(problem, after_other) is not None
    for first, last in itertools.product((0.0, 0.03, 0.1), (0.0, 0.05, 0.1)):  # `other` pushed first, then the block
        last_alone = rollout(problem, alone, np.array([last]))[-1]
        last_after = rollout(problem, after_other, np.array([first, last]))[-1]
        for name in ("stick", "block"):
            assert np.allclose(last_alone.start[name], last_after.start[name], atol=1e-9)
            assert np.allclose(last_alone.end[name], last_after.end[name], atol=1e-9)
        assert all(np.allclose(a, b, atol=1e-9) for a, b in zip(last_alone.hand, last_after.hand, strict=True))
    through = Rejection(Kind.COLLISION, "stick would pass through far", 0.02, bodies=frozenset({"stick", "far"}))
    for rejection in (OUT_OF_REACH, through):
        memo = LastMotion()
        memo.remember(problem, alone, rejection)
        assert memo.known(problem, after_other) is rejection
    pushed_block = labelled_sequence(problem, WIELD, STICK_PUSH, STICK_PUSH_OFF, STICK_PUSH)
    assert last_motion_key(problem, pushed_block) is None
    assert memo.known(problem, pushed_block) is None


def test_a_tool_moved_with_the_body_that_failed_is_not_forgiven(tmp_path: Path) -> None:
    """The failure names `other`, which the stick pushed before: not known."""
    problem = block_to(tmp_path, 0.66, stick=True, grasp=False, depth=8, other=IN_THE_WAY)
    memo = LastMotion()
    through = Rejection(Kind.COLLISION, "stick would pass through other", 0.02, bodies=frozenset({"stick", "other"}))
    memo.remember(problem, labelled_sequence(problem, WIELD, STICK_PUSH), through)
    after_other = labelled_sequence(problem, WIELD, STICK_OTHER, STICK_OTHER_OFF, STICK_PUSH)
    assert last_motion_key(problem, after_other) is not None
    assert memo.known(problem, after_other) is None
