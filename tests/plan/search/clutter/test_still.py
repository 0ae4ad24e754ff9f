"""Bodies kept still until a sequence meets them (`vkgl.plan.search.clutter.still`)."""

from __future__ import annotations

import time

import pytest
from block_problems import ASIDE, IN_THE_WAY, block_to, labels

import vkgl.plan.search.search as search_module
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.search.clutter.still import search_moving_less, still_bodies
from vkgl.plan.search.stats import SearchStats

WITHIN_REACH = "    other : Block on table at (0.45, -0.3) m yaw 90deg\n"
"""A second Block aside of the block's way, where the hand can push it."""


def _failing_checks(monkeypatch: pytest.MonkeyPatch, why: str) -> list[tuple[str, ...]]:
    """Every check fails with a collision rejection worded `why`; the sequences checked, in order."""
    checked: list[tuple[str, ...]] = []

    def failing(problem: Problem, seq: Sequence, stats: SearchStats, *args: object) -> None:
        checked.append(labels(problem, seq))
        named = frozenset({"other"}) if "other is in the way" in why else frozenset()
        stats.reject(Rejection(Kind.COLLISION, why, 0.01, bodies=named), " -> ".join(checked[-1]))

    monkeypatch.setattr(search_module, "_check", failing)
    return checked


def test_a_body_aside_of_every_way_is_kept_still_one_in_the_way_and_tools_never(tmp_path):
    assert still_bodies(block_to(tmp_path, 0.8, True, False, 6, ASIDE)) == {"other"}
    assert still_bodies(block_to(tmp_path, 0.8, True, False, 6, IN_THE_WAY)) == frozenset()


def test_a_body_no_sequence_meets_stays_still_and_the_no_plan_says_so(tmp_path, monkeypatch):
    checked = _failing_checks(monkeypatch, "block would pass through the table edge")
    problem = block_to(tmp_path, 0.8, False, False, 4, WITHIN_REACH, yaw="", slide=30)
    result, searched = search_moving_less(problem, deadline=time.perf_counter() + 600)
    assert result.status == "infeasible" and checked
    assert not any("on other" in " ".join(c) for c in checked)
    assert searched.still == {"other"} and searched.bodies["other"].affordances == ()
    assert result.reason.splitlines()[-1].startswith("kept still: other (in no goal body's way")


def test_a_body_a_rejection_names_gets_its_contacts_back(tmp_path, monkeypatch):
    checked = _failing_checks(monkeypatch, "block would pass through other by 1.0 cm: other is in the way")
    problem = block_to(tmp_path, 0.8, False, False, 4, WITHIN_REACH, yaw="", slide=30)
    result, searched = search_moving_less(problem, deadline=time.perf_counter() + 600)
    assert result.status == "infeasible"
    assert searched.still == frozenset() and searched.bodies["other"].affordances
    assert any("on other" in " ".join(c) for c in checked)
    assert "kept still" not in result.reason
    first = next(i for i, c in enumerate(checked) if "on other" in " ".join(c))
    assert all("on other" in " ".join(c) for c in checked[first:]), "checked again: only what moves the body met"
    assert len(set(checked)) == len(checked)


def test_a_rejection_meets_a_body_by_its_bodies_not_by_its_words():
    stats = SearchStats(watch=frozenset({"other", "clutter1"}))
    stats.reject(Rejection(Kind.COLLISION, "block would pass through other; clutter1 too"), "s")
    assert stats.met == set()
    stats.reject(Rejection(Kind.APPROACH, "the arm's way in is blocked", bodies=frozenset({"clutter1", "x"})), "s")
    assert stats.met == {"clutter1"}
