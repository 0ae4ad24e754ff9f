"""A tool let go of where it was picked up, when where it was used is in the way (`vkgl.plan.search.put_back`), and
the arm's paths that carry it there (`vkgl.plan.arm.paths._places`)."""

from __future__ import annotations

import itertools
from dataclasses import replace
from pathlib import Path

import numpy as np
from task_makers.block_problems import block_to, labelled_sequence

from vkgl.plan.arm.paths import _places
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, materialise, renamed, rollout
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.result.plan import PlanStep
from vkgl.plan.search.put_back import PLACE_BEARINGS, PLACE_RINGS, moved_returns, put_back, returned_tools
from vkgl.plan.task_space.feasible import TaskSolution
from vkgl.plan.task_space.reach.workspace import reach_violation

WIELD = "add Stick.wield on stick with arm.fingertip"
PUSH = "add Block.push_px on block with stick.tip"
PUSH_OFF = "remove Block.push_px on block with stick.tip"
LET_GO = "remove Stick.wield on stick with arm.fingertip"
FINGERTIP = "add Block.push_px on block with arm.fingertip"


def _stick_then_fingertip(tmp_path: Path) -> tuple[Problem, Sequence, np.ndarray]:
    """The stick pushes the block 4 cm, is let go of, and the fingertip pushes the block 3 cm more."""
    problem = block_to(tmp_path, 0.67, stick=True, grasp=False, depth=6)
    seq = labelled_sequence(problem, WIELD, PUSH, PUSH_OFF, LET_GO, FINGERTIP)
    return problem, seq, np.array([0.04, 0.03])


def test_a_used_tool_is_set_down_where_the_hand_picked_it_up(tmp_path: Path) -> None:
    problem, seq, values = _stick_then_fingertip(tmp_path)
    where_used = rollout(problem, seq, values)
    back = returned_tools(problem, seq, where_used, frozenset({"stick"}))
    assert back is not None and [mode for mode, _ in back.returns] == [4]
    traces = rollout(problem, back, values)
    rest = problem.bodies["stick"].rest
    assert np.allclose(traces[4].start["stick"], rest)
    assert not np.allclose(where_used[4].start["stick"][:2, 3], rest[:2, 3], atol=0.05)
    # the hand lets go of it there: one pose, at its grasp, which reach and IK judge
    grasp = problem.action("stick", "wield")
    assert len(traces[4].hand) == 1 and np.allclose(traces[4].hand[0], rest @ grasp)
    assert where_used[4].hand == []
    # the goal body moves as before
    assert np.allclose(traces[-1].end["block"], where_used[-1].end["block"])


def test_a_tool_not_named_stays_where_it_is_let_go_of(tmp_path: Path) -> None:
    problem, seq, values = _stick_then_fingertip(tmp_path)
    traces = rollout(problem, seq, values)
    assert returned_tools(problem, seq, traces, frozenset({"block"})) is None
    assert seq.returns == ()


def test_a_tool_put_back_stays_so_through_every_rebuild_of_its_sequence(tmp_path: Path) -> None:
    """`Sequence.returns` survives what rebuilds a sequence: an extension (the search after a clearing prefix that
    put a tool back), a rename of members (`renamed`: raised contacts) and the naming of family members
    (`materialise`); a raised retry once dropped it and planned a crate through the Stick."""
    problem, seq, values = _stick_then_fingertip(tmp_path)
    back = returned_tools(problem, seq, rollout(problem, seq, values), frozenset({"stick"}))
    assert back is not None and back.returns
    off = "remove Block.push_px on block with arm.fingertip"
    action = next(a for a in successors(problem, back.graphs[-1], back.last) if a.label(problem) == off)
    longer, _ = extend(problem, back, action)
    assert [m for m, _ in longer.returns] == [m for m, _ in back.returns]
    same = renamed(problem, back, lambda k, e: None)
    assert same.actions == back.actions and [m for m, _ in same.returns] == [4]
    named, _ = materialise(problem, back, values)
    assert [m for m, _ in named.returns] == [4]
    rest = problem.bodies["stick"].rest
    assert np.allclose(rollout(problem, longer, values)[4].start["stick"], rest)


def test_put_back_answers_a_clash_that_names_the_tool_only(tmp_path: Path) -> None:
    problem, seq, values = _stick_then_fingertip(tmp_path)
    solution = TaskSolution(values, rollout(problem, seq, values, 6))
    geometry = GeometryCheck(problem)
    named = Rejection(Kind.COLLISION, "block would pass through stick", 0.02, bodies=frozenset({"block", "stick"}))
    found = put_back(problem, seq, solution, named, geometry)
    assert found is not None
    variant, moved = found
    assert moved.sequence is variant and np.allclose(moved.traces[4].start["stick"], problem.bodies["stick"].rest)
    other = Rejection(Kind.COLLISION, "block would pass through block", 0.02, bodies=frozenset({"block"}))
    assert put_back(problem, seq, solution, other, geometry) is None


def _step(op: str, motion: str, body: str, start: np.ndarray, end: np.ndarray) -> PlanStep:
    zero = np.zeros(7)
    return PlanStep(op, "Stick.wield", body, "arm.fingertip", motion, 0.0, {body: start}, {body: end}, zero, zero)


def test_the_arms_paths_carry_a_tool_set_down_away_from_its_contact() -> None:
    here, away = np.eye(4), np.eye(4)
    away[:2, 3] = (0.2, -0.1)
    lowered = here.copy()
    lowered[2, 3] = -0.03  # put down where it was used: lowered, its x and y kept
    contact_off = replace(_step("remove", "prismatic", "stick", here, here), affordance="Block.push_px")
    assert _places(_step("remove", "free", "stick", away, away), contact_off)
    assert not _places(_step("remove", "free", "stick", lowered, lowered), contact_off)
    # pick and place as before
    assert _places(_step("remove", "free", "stick", here, here), _step("add", "free", "stick", here, here))
    assert not _places(None, contact_off)


def test_the_arm_retreats_carries_the_tool_to_its_place_and_lets_go_there(tmp_path: Path) -> None:
    """The straight stage of the arm's paths for the put-back sequence: the stick's contact is left by a retreat
    (not let go of where it touched), the release comes down onto the stick's place, from a transit, at the
    joints that put the hand at its grasp there, and the fingertip's step lifts the open hand off it first."""
    import time

    from vkgl.plan.search import check as s
    from vkgl.plan.search.stats import SearchStats

    problem, seq, values = _stick_then_fingertip(tmp_path)
    back = returned_tools(problem, seq, rollout(problem, seq, values), frozenset({"stick"}))
    assert back is not None
    solution = TaskSolution(values, rollout(problem, back, values, 6), sequence=back)
    geometry = GeometryCheck(problem)
    checks = s.Checks(geometry, s.ArmPathPlanner(problem, geometry))
    found = s._arm_checks(problem, back, solution, SearchStats(), time.perf_counter() + 120, checks, set())
    assert not isinstance(found, Rejection), found.why
    steps = found.steps
    assert [p.phase for p in steps[2].path] == ["retreat"]  # the stick backs out of the block's face
    assert [p.phase for p in steps[3].path][-1] == "approach"  # down onto its place (after the transit)
    assert any(t.step == 3 for t in found.paths.pending)
    hand = problem.arm.fk(steps[3].q_start)
    assert np.allclose(hand[:3, 3], (problem.bodies["stick"].rest @ problem.action("stick", "wield"))[:3, 3], atol=2e-3)
    assert steps[4].path[0].phase == "lift"


class _PlaceTaken:
    """A stand-in for the bodies' geometry check: a body lies on the stick's place (within `taken` m of it), so a
    stick set down there clashes; `other` names a clash elsewhere too."""

    def __init__(self, problem: Problem, taken: float, other: bool = False) -> None:
        self.rest, self.taken, self.other, self.calls = problem.bodies["stick"].rest, taken, other, 0

    def bodies(self, graphs: object, traces: list) -> Rejection | None:  # type: ignore[type-arg]
        self.calls += 1
        if self.other:
            return Rejection(Kind.COLLISION, "block would pass through block", 0.01, bodies=frozenset({"block"}))
        if np.hypot(*(traces[4].start["stick"][:2, 3] - self.rest[:2, 3])) < self.taken:
            return Rejection(Kind.COLLISION, "block would pass through stick", 0.01, bodies=frozenset({"stick"}))
        return None


def test_a_tool_whose_place_is_taken_is_set_down_beside_it(tmp_path: Path) -> None:
    problem, seq, values = _stick_then_fingertip(tmp_path)
    solution = TaskSolution(values, rollout(problem, seq, values, 6))
    clash = Rejection(Kind.COLLISION, "block would pass through stick", 0.02, bodies=frozenset({"block", "stick"}))
    geometry = _PlaceTaken(problem, taken=0.15)
    found = put_back(problem, seq, solution, clash, geometry)  # type: ignore[arg-type]
    assert found is not None
    variant, moved = found
    place = moved.traces[4].start["stick"]
    rest = problem.bodies["stick"].rest
    assert 0.15 <= np.hypot(*(place[:2, 3] - rest[:2, 3])) <= 0.2 + 1e-9  # the nearest ring that is free
    assert np.allclose(place[:3, :3], rest[:3, :3]) and np.isclose(place[2, 3], rest[2, 3])
    assert np.allclose(variant.returns[0][1], place)
    grasp = problem.action("stick", "wield")
    assert np.allclose(moved.traces[4].hand[0], place @ grasp)  # the hand lets go of it there
    assert np.allclose(moved.traces[-1].end["block"], solution.traces[-1].end["block"])


def test_a_clash_that_names_no_returned_tool_ends_the_tries(tmp_path: Path) -> None:
    problem, seq, values = _stick_then_fingertip(tmp_path)
    solution = TaskSolution(values, rollout(problem, seq, values, 6))
    clash = Rejection(Kind.COLLISION, "block would pass through stick", 0.02, bodies=frozenset({"block", "stick"}))
    geometry = _PlaceTaken(problem, taken=0.0, other=True)
    assert put_back(problem, seq, solution, clash, geometry) is None  # type: ignore[arg-type]
    assert geometry.calls == 1
    everywhere = _PlaceTaken(problem, taken=10.0)  # no place on the table is free
    assert put_back(problem, seq, solution, clash, everywhere) is None  # type: ignore[arg-type]
    assert 1 < everywhere.calls <= 1 + len(PLACE_RINGS) * PLACE_BEARINGS


def test_places_beside_stay_on_the_table_and_in_reach(tmp_path: Path) -> None:
    problem, seq, values = _stick_then_fingertip(tmp_path)
    back = returned_tools(problem, seq, rollout(problem, seq, values), frozenset({"stick"}))
    assert back is not None
    places = list(moved_returns(problem, back))
    assert places[0] is back  # where it was picked up, first
    grasp = problem.action("stick", "wield")
    low = problem.table_center - problem.table_size / 2  # type: ignore[operator]
    high = problem.table_center + problem.table_size / 2  # type: ignore[operator]
    outline = problem.bodies["stick"].outline
    for variant in places[1:]:
        ((mode, pose),) = variant.returns
        assert mode == 4 and reach_violation(problem, (pose @ grasp)[:3, 3]) <= 0
        corners = (outline @ pose[:3, :3].T + pose[:3, 3])[:, :2]
        assert np.all(corners >= low) and np.all(corners <= high)
    distances = [float(np.hypot(*(v.returns[0][1][:2, 3] - back.returns[0][1][:2, 3]))) for v in places]
    assert all(b >= a - 1e-9 for a, b in itertools.pairwise(distances)) and len(places) > 1
    assert len(places) < 1 + len(PLACE_RINGS) * PLACE_BEARINGS or problem.table_size is None  # some are left out
    tableless = replace(problem, table_center=None, table_size=None)
    assert list(moved_returns(tableless, back)) == [back]
