"""Answers of the arm's straight moves remembered by step (`vkgl.plan.arm.remembered`): made once, as asked,
and the same as made afresh."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from conftest import EXAMPLES

import vkgl
from vkgl.plan.arm.paths import ArmPathPlanner
from vkgl.plan.arm.remembered import Replay
from vkgl.plan.arm.straight_moves import StraightMoves
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.problem.rejection import Rejection


def test_a_replay_makes_each_item_once_when_first_asked_and_gives_arrays_of_their_own() -> None:
    made: list[int] = []

    def source():  # type: ignore[no-untyped-def]
        for k in range(3):
            made.append(k)
            yield np.full(2, float(k))

    replay = Replay(source())
    first = next(iter(replay))
    assert made == [0]  # nothing made before it is asked for
    first[:] = 9.0  # the caller's own copy
    again = [float(a[0]) for a in replay]
    assert again == [0.0, 1.0, 2.0] and made == [0, 1, 2]
    assert [float(a[0]) for a in replay] == again and made == [0, 1, 2]  # from the first, nothing made again


def test_a_plans_straight_moves_planned_again_are_remembered_and_the_same(monkeypatch) -> None:
    plan = vkgl.solve(vkgl.compile(EXAMPLES / "tasks" / "c_hook_pull.vkg"))
    assert plan.status == "solved", plan.reason
    steps = [replace(s, path=(), contact=None) for s in plan.steps]
    planner = ArmPathPlanner(plan.problem, GeometryCheck(plan.problem))
    first = planner.straight(steps)
    solved: list[str] = []
    chains, approaches = ArmPathPlanner._solved_contact_chain, StraightMoves.solved_into_contact

    def counted_chain(self, step, state, label):  # type: ignore[no-untyped-def]
        solved.append(label)
        return chains(self, step, state, label)

    def counted_approach(self, step, state, label):  # type: ignore[no-untyped-def]
        solved.append(label)
        return approaches(self, step, state, label)

    monkeypatch.setattr(ArmPathPlanner, "_solved_contact_chain", counted_chain)
    monkeypatch.setattr(StraightMoves, "solved_into_contact", counted_approach)
    again = planner.straight(steps)
    assert solved == []  # every contact's chains and approach were remembered
    fresh = ArmPathPlanner(plan.problem, GeometryCheck(plan.problem)).straight(steps)
    assert len(solved) >= 2  # a new planner solves them
    assert not isinstance(first, Rejection) and not isinstance(again, Rejection) and not isinstance(fresh, Rejection)
    for one, two, three in zip(first.steps, again.steps, fresh.steps, strict=True):
        assert len(one.path) == len(two.path) == len(three.path)
        for a, b, c in zip(one.path, two.path, three.path, strict=True):
            assert a.phase == b.phase == c.phase
            np.testing.assert_allclose(a.joints, b.joints, atol=1e-12)
            np.testing.assert_allclose(a.joints, c.joints, atol=1e-12)
        if one.contact is not None:
            np.testing.assert_allclose(one.contact, two.contact, atol=1e-12)
            np.testing.assert_allclose(one.contact, three.contact, atol=1e-12)
