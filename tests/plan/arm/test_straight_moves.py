"""The arm's straight moves (`vkgl.plan.arm.straight_moves`): what the arm would overlap is named in words and,
for the search (`Rejection.bodies`), by the body's name; the table by words only."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import vkgl
from vkgl.plan.arm.straight_moves import StraightMoves
from vkgl.plan.geometry.bodies import GeometryCheck

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


def test_the_body_the_arm_would_overlap_is_named_by_its_name_the_table_by_words_only() -> None:
    program = vkgl.compile(EXAMPLES / "tasks" / "a_push.vkg")
    plan = vkgl.solve(program)
    assert plan.status == "solved" and plan.problem is not None, plan.reason
    problem, step = plan.problem, plan.steps[0]
    moves = StraightMoves(problem, GeometryCheck(problem))
    q = np.asarray(step.q_start, dtype=float)
    assert moves.first_overlap(q[None, :], step.poses_start, None, set(), {"block"}) is None  # the pad on its face
    hand = problem.arm.fk(q)
    onto = {name: pose.copy() for name, pose in step.poses_start.items()}
    onto["block"][:3, 3] = hand[:3, 3] + [0.0, 0.0, 0.05]  # the block around the hand
    clash = moves.first_overlap(q[None, :], onto, None, set())
    assert clash is not None and clash.bodies == {"block"} and "would overlap block" in clash.words, clash
    assert clash.link and f"the arm's {clash.link} would overlap" in clash.words  # the link, for contact chains
    lower = hand.copy()
    lower[2, 3] -= 0.04  # the fingertip 1.5 cm into the table
    q_low = problem.arm.ik(lower, q0=q)
    assert q_low is not None
    away = {name: pose.copy() for name, pose in step.poses_start.items()}
    away["block"][:3, 3] += [0.0, 0.6, 0.0]
    clash = moves.first_overlap(q_low[None, :], away, None, set())
    assert clash is not None and "would overlap table" in clash.words and clash.bodies == frozenset(), clash
