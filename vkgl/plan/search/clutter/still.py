"""Bodies kept still until a sequence meets them: clutter in no goal body's way keeps its affordances only lazily.

Every affordance of every body is a branch at every graph of the search. A body that is no goal body, no tool and
has no physical joint is moved in a plan only to clear the way of something else; on a cluttered table most such
bodies lie nowhere near what the plan moves, and their contacts (ten to twenty each: a push and four turns per
explored face) multiply the sequences of every level for nothing. `still_bodies` names them: the free bodies
that are no goal body, no tool, and lie in no goal body's straight way (`vkgl.plan.search.ordering.InTheWay`),
when every goal has a position (with a goal of heading or region only nothing is kept still: there is no way to
measure against).

`search_moving_less` searches the problem with those bodies kept still: their contacts withheld from the
successors (`search(still=...)`); they still count in every collision check. A rejected sequence that names one
of them (`Rejection.bodies`, filled by the checks that found it in the way: a body passed through it, the arm or
a tool hit it, it blocked an approach or a transit's end; `SearchStats.met`) shows that it matters: from then
on the same search gives it its contacts back, and queues at once the contacts on it that it withheld from the
sequences already expanded, each with the key it would have had (`search._Withheld`). So a body met at the
second level moves in sequences of the third, not after a search without it has exhausted every depth (the
physical bench's gen10_017: a CubeS beside the way, turned in its plan, came back only after 1,149 graphs of a
first search that could not succeed). A "no plan" then says which bodies stayed still and that no sequence met
them.

**What it can lose** (also in docs/planning.md): a plan that moves a body kept still although no rejected
sequence named it. That is a plan in which moving the body helps without the body ever being what a shorter
sequence collided with: a transit (OMPL) that finds no way because of it (a transit's rejection names a body only
where one blocks the arm at an end of the transit), or a goal the optimiser could not reach for another reason
while the body was also in the way. And a plan found
with bodies kept still is the shortest among those that move none of them: one graph shorter that moves one
of them (to make room for a tool, say) is not looked for, as long as no sequence met them.
"""

from __future__ import annotations

from dataclasses import replace

from vkgl.plan.problem.problem import Problem
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.search.search import Paused, SearchResult, search


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
    """`problem` with the bodies `names` kept still for good: no affordance (what a search after the one of
    `search_moving_less` extends: clearing's, `vkgl.plan.search.clutter.clear_first`)."""
    if not names:
        return problem
    bodies = {name: replace(b, affordances=()) if name in names else b for name, b in problem.bodies.items()}
    return replace(problem, bodies=bodies)


def search_moving_less(
    problem: Problem,
    *,
    deadline: float,
    progress: bool = False,
    budget: float | None = None,
    pause_at: float | None = None,
    paused: Paused | None = None,
) -> tuple[SearchResult, Problem]:
    """The search of `problem` with the bodies in no goal body's way kept still until a rejected sequence meets
    them (see the module's docstring), and the problem it searched with those it never met kept still for good.
    `budget`, `pause_at`, `paused`: `search`'s (none by default); called again with the same `problem` and
    `paused` that its budget or pause stopped, it goes on where it stopped (`vkgl.plan.solve`: the time the
    clear-first walk leaves given back)."""
    still = still_bodies(problem)
    result = search(
        problem, deadline=deadline, progress=progress, still=still, budget=budget, pause_at=pause_at, paused=paused
    )
    left = still - result.stats.met
    if result.status == "infeasible" and left and not result.stats.cut_at_start:  # (the bound cut G0: none matters)
        result = replace(result, reason=f"{result.reason}\n{still_words(left)}")
    return result, kept_still(problem, left)


def still_words(still: frozenset[str]) -> str:
    """The line a "no plan" ends with when bodies were kept still."""
    names = ", ".join(sorted(still))
    one = len(still) == 1
    return (
        f"kept still: {names} (in no goal body's way, and no sequence tried met {'it' if one else 'them'}; "
        f"{'its' if one else 'their'} contacts were not searched)"
    )


__all__ = ["kept_still", "search_moving_less", "still_bodies", "still_words"]
