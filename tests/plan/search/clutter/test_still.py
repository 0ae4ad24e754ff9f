"""Bodies kept still until a sequence meets them (`vkgl.plan.search.clutter.still`): a body a rejection names
(`Rejection.bodies`) gets its contacts back in the running search, at once."""

from __future__ import annotations

import time
from collections.abc import Callable

import pytest
from task_makers.block_problems import ASIDE, IN_THE_WAY, block_to, labels

import vkgl.plan.search.search as search_module
from vkgl.plan.graphs.rollout import Sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.search.clutter.still import search_moving_less, still_bodies
from vkgl.plan.search.search import search
from vkgl.plan.search.stats import SearchStats

WITHIN_REACH = "    other : Block on table at (0.45, -0.3) m yaw 90deg\n"
"""A second Block aside of the block's way, where the hand can push it."""

WORDS = "block would pass through other by 1.0 cm: other is in the way"
"""A rejection's words naming the other Block, as the geometry words them."""


def _failing_checks(
    monkeypatch: pytest.MonkeyPatch, names: Callable[[tuple[str, ...]], frozenset[str]]
) -> list[tuple[str, ...]]:
    """Every check fails with a collision rejection (worded `WORDS`) whose `bodies` are `names(the sequence's
    labels)`; the sequences checked, in order."""
    checked: list[tuple[str, ...]] = []

    def failing(problem: Problem, seq: Sequence, stats: SearchStats, *args: object) -> None:
        checked.append(labels(problem, seq))
        stats.reject(Rejection(Kind.COLLISION, WORDS, 0.01, bodies=names(checked[-1])), " -> ".join(checked[-1]))

    monkeypatch.setattr(search_module, "check", failing)
    return checked


def _moves_other(sequence: tuple[str, ...]) -> bool:
    return "on other" in " ".join(sequence)


def _problem(tmp_path, depth: int = 4) -> Problem:
    return block_to(tmp_path, 0.8, False, False, depth, WITHIN_REACH, yaw="", slide=30, gy=0.0)


def test_a_body_aside_of_every_way_is_kept_still_one_in_the_way_and_tools_never(tmp_path):
    assert still_bodies(block_to(tmp_path, 0.8, True, False, 6, ASIDE)) == {"other"}
    assert still_bodies(block_to(tmp_path, 0.8, True, False, 6, IN_THE_WAY)) == frozenset()


def test_a_body_no_rejection_names_stays_still_and_the_no_plan_says_so(tmp_path, monkeypatch):
    checked = _failing_checks(monkeypatch, lambda _: frozenset())  # the words name other: they do not count
    result, searched = search_moving_less(_problem(tmp_path), deadline=time.perf_counter() + 600)
    assert result.status == "infeasible" and checked
    assert not any(_moves_other(c) for c in checked)
    assert searched.bodies["other"].affordances == ()
    assert result.reason.splitlines()[-1].startswith("kept still: other (in no goal body's way")


def test_a_body_the_first_rejection_names_is_searched_as_if_never_kept_still(tmp_path, monkeypatch):
    # the contacts withheld before the meeting are queued with the keys they would have had: the same checks in
    # the same order as the search that kept nothing still
    problem = _problem(tmp_path)
    checked = _failing_checks(monkeypatch, lambda _: frozenset({"other"}))
    result, searched = search_moving_less(problem, deadline=time.perf_counter() + 600)
    assert result.status == "infeasible" and "kept still" not in result.reason
    assert searched.bodies["other"].affordances and result.stats.met == {"other"}
    assert any(_moves_other(c) for c in checked) and len(set(checked)) == len(checked)
    unwithheld = list(checked)
    checked.clear()
    search(problem, deadline=time.perf_counter() + 600)
    assert unwithheld == checked


def test_a_body_met_at_a_later_level_moves_in_it_not_after_the_search_without_it_ends(tmp_path, monkeypatch):
    # the sequences of 4 graphs meet it: those of 4 that move it are checked before any of 6 (once, the search
    # without it ran through the sequences of 6 first)
    checked = _failing_checks(monkeypatch, lambda seq: frozenset({"other"}) if len(seq) >= 3 else frozenset())
    result, _ = search_moving_less(_problem(tmp_path, 6), deadline=time.perf_counter() + 600)
    assert result.status == "infeasible" and result.stats.met == {"other"}
    met = next(i for i, c in enumerate(checked) if len(c) >= 3)
    moves = [i for i, c in enumerate(checked) if _moves_other(c)]
    assert moves and moves[0] > met and not any(_moves_other(c) for c in checked[:met])
    level = len(checked[moves[0]])
    assert max(len(c) for c in checked[: moves[0]]) == level < max(len(c) for c in checked)
    assert len(set(checked)) == len(checked), "a sequence checked before the meeting is not checked again"


def test_a_rejection_meets_a_body_by_its_bodies_not_by_its_words():
    stats = SearchStats(watch=frozenset({"other", "clutter1"}))
    stats.reject(Rejection(Kind.COLLISION, "block would pass through other; clutter1 too"), "s")
    assert stats.met == set()
    stats.reject(Rejection(Kind.APPROACH, "the arm's way in is blocked", bodies=frozenset({"clutter1", "x"})), "s")
    assert stats.met == {"clutter1"}
