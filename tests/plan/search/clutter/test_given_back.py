"""The time the clear-first walk leaves, given back to the first search (`vkgl.plan.solve`, `search(pause_at=)`):
a blocked task ends at its timeout or with a plan, not when the walk gives up."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from task_makers.block_problems import block_across_the_way

import vkgl
from vkgl.plan.problem.problem import Problem, build_problem
from vkgl.plan.search.clutter.still import search_moving_less
from vkgl.plan.search.clutter.waiting import Cleared
from vkgl.plan.search.search import Paused, search
from vkgl.plan.search.stats import SearchStats

_HERE = Path(__file__).resolve().parent

BLOCKED = block_across_the_way(max_depth=4)
"""A block with another across its way: the search itself finds the plan that pushes block2 aside first (4
graphs), given the time."""


def _program() -> vkgl.Program:
    return vkgl.compile_source(BLOCKED, "given_back.vkg", base_dir=_HERE)


def _problem() -> Problem:
    program = _program()
    return build_problem(program, program.tasks["through"])


def _counts(stats: SearchStats) -> tuple[int, int, int, int]:
    return stats.sequences, stats.graphs_expanded, stats.task_space_checks, stats.work.optimisations


def test_a_search_its_pause_stopped_goes_on_to_the_same_end_as_one_never_paused() -> None:
    """`search(pause_at=)`: a pause already past stops the search before its first check, kept in `paused`;
    gone on from there without one, it ends as a search never paused, with the same counts."""
    problem = _problem()
    far = time.perf_counter() + 1e6
    whole = search(problem, deadline=far)
    paused = Paused()
    first = search(problem, deadline=far, pause_at=time.perf_counter() - 1.0, paused=paused)
    assert first.status == "timeout" and first.stats.task_space_checks == 0
    assert paused.holds(problem) and not paused.holds(_problem())  # (kept for that problem only)
    went_on = search(problem, deadline=far, paused=paused)
    assert whole.status == went_on.status == "solved" and not paused.holds(problem)
    assert went_on.sequence is not None and whole.sequence is not None
    assert went_on.sequence.actions == whole.sequence.actions
    assert _counts(went_on.stats) == _counts(whole.stats)


def test_a_check_its_pause_cut_short_is_made_again_when_the_search_goes_on(monkeypatch: pytest.MonkeyPatch) -> None:
    """The pause passes while the check that finds the plan runs (the clock jumps past it as that check starts):
    the check is cut short as by a deadline and the search pauses, "timeout", not "no plan"; gone on, it makes
    that check again first and ends with the plan of a search never paused, having made the same sequences."""
    import vkgl.plan.search.search as search_module

    problem = _problem()
    calls: list[int] = []
    real_check, real_clock = search_module.check, time.perf_counter

    def counted(*args: object, **more: object) -> object:
        calls.append(1)
        return real_check(*args, **more)  # type: ignore[arg-type]

    monkeypatch.setattr(search_module, "check", counted)
    far = real_clock() + 1e6
    whole = search(problem, deadline=far)
    assert whole.status == "solved" and whole.sequence is not None
    last = len(calls)  # the check that finds the plan
    calls.clear()
    jumped: list[bool] = []

    def jumping(*args: object, **more: object) -> object:
        calls.append(1)
        if len(calls) == last:
            jumped.append(True)  # the pause passes as this check starts
        return real_check(*args, **more)  # type: ignore[arg-type]

    monkeypatch.setattr(search_module, "check", jumping)
    monkeypatch.setattr(time, "perf_counter", lambda: real_clock() + (1e4 if jumped else 0.0))
    paused = Paused()
    first = search(problem, deadline=far + 1e4, pause_at=real_clock() + 1e3, paused=paused)
    assert first.status == "timeout" and paused.holds(problem)
    went_on = search(problem, deadline=far + 1e4, paused=paused)
    assert went_on.status == "solved" and went_on.sequence is not None
    assert went_on.sequence.actions == whole.sequence.actions
    assert (went_on.stats.sequences, went_on.stats.graphs_expanded) == (
        whole.stats.sequences,
        whole.stats.graphs_expanded,
    )
    assert went_on.stats.task_space_checks == whole.stats.task_space_checks + 1  # (the one cut short, made again)


def test_the_time_the_walk_leaves_goes_back_to_the_first_search(monkeypatch: pytest.MonkeyPatch) -> None:
    """`vkgl.solve` of a blocked task whose first search pauses at once (a share of 0) and whose walk finds
    nothing: the first search goes on where it paused and finds the plan a search with the whole time finds (the
    same plan, the same counts), where before the task ended "timeout" when the walk gave up."""
    import vkgl.plan.solve as solve_module

    whole, _ = search_moving_less(_problem(), deadline=time.perf_counter() + 1e6)
    assert whole.status == "solved" and whole.sequence is not None
    monkeypatch.setattr(solve_module, "SEARCH_SHARE", 0.0)
    walks: list[str] = []

    def nothing_found(problem: Problem, before: object, **_: object) -> Cleared:
        walks.append(problem.task.name)
        return Cleared(None, "clearing the way first found no plan either")

    monkeypatch.setattr(solve_module, "clear_first", nothing_found)
    plan = vkgl.solve(_program(), "through")
    assert walks == ["through"]  # (the walk ran: the first search had paused without a plan)
    assert plan.status == "solved" and len(plan.graphs) == whole.sequence.depth
    assert plan.stats["graphs_expanded"] == whole.stats.graphs_expanded
    assert plan.stats["task_space_checks"] == whole.stats.task_space_checks


def test_a_first_search_that_proved_no_plan_is_not_searched_again(monkeypatch: pytest.MonkeyPatch) -> None:
    """With no plan of at most 3 graphs proven by the first search and the walk finding nothing, the task ends
    "infeasible" with both searches' words: nothing was kept to go on from."""
    import vkgl.plan.solve as solve_module

    monkeypatch.setattr(solve_module, "clear_first", lambda *_, **__: Cleared(None, "the walk found nothing"))
    plan = vkgl.solve(_program(), "through", max_depth=3)
    assert plan.status == "infeasible"
    assert "no sequence of at most 3 graphs" in plan.reason and "the walk found nothing" in plan.reason
