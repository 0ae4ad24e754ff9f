"""Bodies kept still until a sequence meets them: clutter in no goal body's way keeps its affordances only lazily.

Every affordance of every body is a branch at every graph of the search. A body that is no goal body, no tool and
has no physical joint is moved in a plan only to clear the way of something else; on a cluttered table most such
bodies lie nowhere near what the plan moves, and their contacts (ten to twenty each: a push and four turns per
explored face) multiply the sequences of every level for nothing. `still_bodies` names them: the free bodies
that are no goal body, no tool, and lie in no goal body's straight way (`vkgl.plan.search.ordering.InTheWay`),
when every goal has a position (with a goal of heading or region only nothing is kept still: there is no way to
measure against).

`search_moving_less` searches the problem with those bodies kept still (their affordances withheld, like the
sub-problems of `vkgl.plan.search.clutter.clear_first`; they still count in every collision check). A rejected sequence
that names one of them (`SearchStats.met`: a body passed through, hit by the arm or a tool, in the way of an
approach, named anywhere in the rejection's words) shows that it matters: when the search ends without a plan,
the bodies it met get their affordances back and the search runs again, until no body kept still was met or a
plan is found or the time runs out. The search again checks only the sequences that move a body just met (the
others were checked before, against the same bodies, and fail the same way): it only extends the rest. A "no
plan" then says which bodies were kept still and that no sequence met them.

**What it can lose** (also in docs/planning.md): a plan that moves a body kept still although no rejected
sequence named it. That is a plan in which moving the body helps without the body ever being what a shorter
sequence collided with: a transit (OMPL) that finds no way because of it (transit rejections name no body), or
a goal the optimiser could not reach for another reason while the body was also in the way. And a plan found
with bodies kept still is the shortest among those that move none of them: one graph shorter that moves one
of them (to make room for a tool, say) is not looked for, as long as no sequence met them.
"""

from __future__ import annotations

from dataclasses import replace

from vkgl.plan.problem.problem import Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.clutter.clear_first import add_stats
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.search.search import SearchResult, search
from vkgl.plan.search.stats import infeasible_reason


def still_bodies(problem: Problem) -> frozenset[str]:
    """The bodies with affordances that are no goal body, no tool, have no physical joint and lie in no goal
    body's straight way; none when a goal has no position."""
    if any(goal.position is None for goal in problem.goals):
        return frozenset()
    keep = {g.body for g in problem.goals} | {e.tool for e in problem.effectors if e.tool is not None}
    keep |= InTheWay(problem).bodies
    return frozenset(
        name for name, b in problem.bodies.items() if name not in keep and b.joint is None and b.affordances
    )


def kept_still(problem: Problem, names: frozenset[str]) -> Problem:
    """`problem` with the bodies `names` kept still: no affordance, and named in `Problem.still` (the search
    watches its rejections for them)."""
    if not names:
        return replace(problem, still=frozenset())
    bodies = {name: replace(b, affordances=()) if name in names else b for name, b in problem.bodies.items()}
    return replace(problem, bodies=bodies, still=names)


def search_moving_less(problem: Problem, *, deadline: float, progress: bool = False) -> tuple[SearchResult, Problem]:
    """The search of `problem` with the bodies in no goal body's way kept still until a rejected sequence meets
    them (see the module's docstring), and the problem last searched (its `still` bodies kept still)."""
    still = still_bodies(problem)
    searched = kept_still(problem, still)
    result = search(searched, deadline=deadline, progress=progress)
    stats = result.stats
    while result.status == "infeasible" and (met := frozenset(stats.met & still)):
        still = still - met
        searched = kept_still(problem, still)
        # a sequence that moves none of the bodies just met was checked before, and fails the same way
        again = search(searched, deadline=deadline, progress=progress, moving=met, arm_hits=frozenset(stats.arm_hits))
        add_stats(again.stats, stats)  # the counters of every search, the last one's level
        stats = again.stats
        for kind, example in result.stats.examples.items():  # the closest miss of every search
            if kind not in stats.examples or example[0] < stats.examples[kind][0]:
                stats.examples[kind] = example
        result = again
        if result.status == "infeasible":
            result = replace(result, reason=infeasible_reason(searched, stats, Bound(searched)))
    if result.status == "infeasible" and still and not stats.cut_at_start:  # (the bound cut G0: no body matters)
        result = replace(result, reason=f"{result.reason}\n{still_words(still)}")
    return result, searched


def still_words(still: frozenset[str]) -> str:
    """The line a "no plan" ends with when bodies were kept still."""
    names = ", ".join(sorted(still))
    one = len(still) == 1
    return (
        f"kept still: {names} (in no goal body's way, and no sequence tried met {'it' if one else 'them'}; "
        f"{'its' if one else 'their'} contacts were not searched)"
    )


__all__ = ["kept_still", "search_moving_less", "still_bodies", "still_words"]
