"""Work budgets (`vkgl.plan.search.search`'s `budget`, `SearchStats.work_done`) and the clear-first policy that
counts in them (`vkgl.plan.search.clutter.clear_first`): the same input gives the same answer, whatever the clock
says."""

from __future__ import annotations

import math
import time
from copy import deepcopy
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest
from task_makers.block_problems import block_across_the_way

import vkgl
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.search.clutter.clear_first import clear_first, work_budget
from vkgl.plan.search.search import Paused, SearchResult, search
from vkgl.plan.search.stats import SearchStats, add_stats

_HERE = Path(__file__).resolve().parent

BLOCKED = block_across_the_way(max_depth=3)


def _problem() -> Problem:
    program = vkgl.compile_source(BLOCKED, "budget.vkg", base_dir=_HERE)
    return build_problem(program, program.tasks["through"])


def _counts(stats: SearchStats) -> tuple[int, int, int, int]:
    return stats.sequences, stats.graphs_expanded, stats.task_space_checks, stats.work.optimisations


def test_a_spent_budget_ends_the_search_at_the_same_sequence_however_slow_the_clock() -> None:
    """Two searches with the same small budget, one of them with a clock that runs a hundred times faster (as
    on a loaded machine), end at the same sequence with the same counts, and say that the budget ran out."""
    problem = _problem()
    far = time.perf_counter() + 1e6
    runs = [search(problem, deadline=far, budget=3.0)]
    real = time.perf_counter
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(time, "perf_counter", lambda: 100.0 * real())
        runs.append(search(problem, deadline=100.0 * far, budget=3.0))
    assert [r.status for r in runs] == ["timeout", "timeout"]
    assert "its work budget of 3 units" in runs[0].reason
    assert _counts(runs[0].stats) == _counts(runs[1].stats)
    assert 3.0 < runs[0].stats.work_done() < math.inf


def test_the_blocker_is_cleared_with_the_fingertip_within_a_work_budget_the_same_way_twice() -> None:
    """The search proves no plan of 3 graphs; clearing block2 first with the fingertip (one push) then pushing
    the block gives 4 graphs, within a budget far below the timeout's worth, twice with the same counts."""
    problem = _problem()
    far = time.perf_counter() + 1e6
    before = search(problem, deadline=far)
    assert before.status == "infeasible"
    budget = 0.1 * work_budget(problem)
    found = [  # clear_first adds its searches' counters to the search's before it: each run gets its own copy
        clear_first(problem, replace(before, stats=deepcopy(before.stats)), deadline=far, budget=budget)
        for _ in range(2)
    ]
    for cleared in found:
        assert cleared is not None and cleared.result is not None, cleared
        assert cleared.result.sequence is not None and cleared.result.sequence.depth == 4
        assert "cleared the way first: block2" in cleared.words
        labels = [a.label(problem) for a in cleared.result.sequence.actions]
        assert labels[0].startswith("add Block.") and "block2 with arm.fingertip" in labels[0]
        assert cleared.result.stats.work_done() <= before.stats.work_done() + budget + 10.0
    first, second = (c.result for c in found if c is not None and c.result is not None)
    assert _counts(first.stats) == _counts(second.stats)
    assert [a.label(problem) for a in first.sequence.actions] == [a.label(problem) for a in second.sequence.actions]


def test_a_search_its_budget_stopped_goes_on_to_the_same_end_as_one_started_with_the_larger_budget() -> None:
    """`search(paused=)`: stopped by a budget of 1 unit, then gone on from there with 6, the search ends where one
    started anew with 6 ends, with the same counts (its work done once, not twice); the walk adds up only the
    work of the second run (`add_stats(since=)`)."""
    problem = _problem()
    far = time.perf_counter() + 1e6
    anew = search(problem, deadline=far, budget=6.0)
    paused = Paused()
    first = search(problem, deadline=far, budget=1.0, paused=paused)
    assert first.status == "timeout"
    total = SearchStats()
    add_stats(total, first.stats)  # (the run's counters go on counting: added before it goes on, as the walk does)
    since = paused.stats(problem, None)
    assert since is not None and _counts(since) == _counts(first.stats) < _counts(anew.stats)
    went_on = search(problem, deadline=far, budget=6.0, paused=paused)
    assert went_on.status == anew.status and went_on.reason == anew.reason
    assert _counts(went_on.stats) == _counts(anew.stats)
    add_stats(total, went_on.stats, since)
    assert _counts(total) == _counts(anew.stats)
    assert paused.stats(replace(problem), None) is None  # another problem starts anew


def test_the_search_before_clearing_gets_half_the_work_budget_and_half_the_clock(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """`vkgl.solve` with a body in the way: the search before the clearing pauses at half the task's work budget
    or at half its timeout, whichever comes first (the count ends it the same on any machine fast enough; each
    check runs to the task's deadline, `search(pause_at=)`); with none in the way it has the whole timeout, no
    budget and no pause."""
    import vkgl.plan.solve as solve_module
    from vkgl.plan.search.clutter.clear_first import SEARCH_SHARE

    calls: list[tuple[float, float | None, float | None]] = []
    original = solve_module.search_moving_less

    def recording(
        problem: Problem, *, deadline: float, budget: float | None = None, pause_at: float | None = None, **more: Any
    ) -> tuple[SearchResult, Problem]:
        now = time.perf_counter()
        calls.append((deadline - now, budget, None if pause_at is None else pause_at - now))
        return original(problem, deadline=deadline, budget=budget, pause_at=pause_at, **more)

    monkeypatch.setattr(solve_module, "search_moving_less", recording)
    program = vkgl.compile_source(BLOCKED, "budget.vkg", base_dir=_HERE)
    vkgl.solve(program, "through", timeout=10.0)
    clear = BLOCKED.replace("block2 : Block on table at (0.62, 0) m", "block2 : Block on table at (0.45, 0.3) m")
    vkgl.solve(vkgl.compile_source(clear, "clear.vkg", base_dir=_HERE), "through", timeout=10.0)
    (blocked_left, blocked_budget, blocked_pause), (clear_left, clear_budget, clear_pause) = calls
    timed = build_problem(program, program.tasks["through"], timeout=10.0)
    assert blocked_budget == pytest.approx(SEARCH_SHARE * work_budget(timed))
    assert blocked_pause is not None and SEARCH_SHARE * 10.0 - 1.0 < blocked_pause <= SEARCH_SHARE * 10.0
    assert 10.0 - 1.0 < blocked_left <= 10.0  # (its checks run to the task's deadline)
    assert clear_budget is None and clear_pause is None and 10.0 - 1.0 < clear_left <= 10.0
