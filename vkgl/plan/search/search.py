"""Algorithm 1 of the paper, best first: graph sequences in the order of depth plus a lower bound of the graphs
still needed (`vkgl.plan.search.bounds.bound`), the first feasible sequence returned.

Sequences are extended one transition at a time (`successors` in
`vkgl.plan.graphs.graph`), queued (a heap) by depth plus bound, and checked
when they leave the queue. The bound never overestimates, so the first
feasible sequence checked is a shortest one; a sequence whose depth plus bound
passes `max_depth` is never queued. Among sequences of one level, those that
have moved every body lying in a goal body's way come first
(`vkgl.plan.search.ordering`), then the order breadth-first search generates
them (the indices of their actions among their parents' successors): with no
body in the way, the plan is the very one the paper's breadth-first search
finds first. What never loses a solution besides:

- a sequence is only checked when its last mode moves a goal body (or its last
  action sets down a goal body the hand carried, `vkgl.plan.graphs.carry`):
  otherwise its final poses are those of a shorter prefix, which was checked before;
  for the same reason the last level only generates such sequences;
- nor when its bound is above 0: the bound never exceeds the true remaining
  depth, 0 for a sequence that passes, so such a one cannot (it is extended);
- a transition whose hand pose no motion value can change (e.g. touching a
  body still at rest, or grasping a tool where it lies) is checked against the
  arm's reach at once, and when it is out of reach the whole subtree goes;
- the task-space check starts with exact reasoning (`closed_form`) and runs
  the optimiser only when that cannot decide; joint space only after task space.
- given `still` (`vkgl.plan.search.clutter.still`), a contact on one of those
  bodies is withheld until a rejected sequence names the body
  (`Rejection.bodies`); from then on it is a successor like any other, and the
  contacts on it withheld from the sequences already expanded are queued at
  once (`vkgl.plan.search.withheld`): every sequence that moves only bodies not kept still is
  queued as if none had been withheld, so the plan is a shortest among those.

Each sequence carries what its prefix knows (`Sequence`: graphs, variables,
poses with the values at zero), so no work is repeated along a branch.
"""

from __future__ import annotations

import copy
import functools
import heapq
import time
from dataclasses import dataclass

from vkgl.plan.arm.paths import ArmPathPlanner
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, start_sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.check import Checks, SearchResult, check
from vkgl.plan.search.exclusions import repeated_failure
from vkgl.plan.search.ordering import InTheWay
from vkgl.plan.search.stats import Progress, SearchStats, infeasible_reason, timeout_reason
from vkgl.plan.search.withheld import Withheld, withholds
from vkgl.plan.task_space.feasible import goal_holds
from vkgl.plan.task_space.reach.workspace import unreachable

__all__ = ["Paused", "SearchResult", "search"]


def search(
    problem: Problem,
    *,
    deadline: float,
    progress: bool = False,
    root: Sequence | None = None,
    budget: float | None = None,
    still: frozenset[str] = frozenset(),
    paused: Paused | None = None,
    pause_at: float | None = None,
) -> SearchResult:
    """Best-first search for the shortest feasible graph sequence of `problem` (at most `max_depth` graphs).

    Sequences are checked in the order of their depth plus `Bound` (an admissible lower bound of the graphs
    still needed, `vkgl.plan.search.bounds.bound`), ties broken by the bodies in the way they have not moved
    (`vkgl.plan.search.ordering`), then by the breadth-first order of their actions, and those whose depth plus
    bound passes `max_depth` are never made: the plan is a shortest one, found sooner. `root` (G0 alone by
    default) is the sequence every one searched extends (`vkgl.plan.search.clutter.clear_first`: a plan that clears a
    body in the way): the plan is then a shortest among those that start with it. `budget` (none by default)
    bounds the work the search may do, in counted units (`SearchStats.work_done`): a search that spends it ends
    like one that ran out of time ("timeout"), at the same sequence on any machine and under any load (the
    deadline stays the wall-clock guard). `still` (none by default): bodies whose contacts are withheld until a
    rejected sequence names one of them (`vkgl.plan.search.clutter.still`; `SearchStats.met` says which were);
    the plan is then a shortest among those that move no body still withheld when it was found (`Withheld`).

    `paused` (none by default): where the search stops when it spends its `budget`, kept to go on from: called
    again with the same `paused`, `problem` and `root` and a larger budget, it goes on from the sequence it
    stopped at, the budget counting the work of both runs (`SearchStats` go on too): the same search, checks and
    result as one started anew with the larger budget, without the work done again (`Paused`). `pause_at` (none
    by default): a cut on the clock that ends the search as its budget does, kept in `paused`: the checks end
    there too (as with a deadline at `pause_at`: a check is not run past it), and one it cut short is made again
    first when the search goes on (`_check_once`): the first search of a blocked task, given back the time the
    clear-first walk left (`vkgl.plan.solve`).
    """
    run = paused.take(problem, root) if paused is not None else None
    if run is None:
        run = _Run(problem, root, still)
        if goal_holds(problem, run.root.zero_poses):
            return check(problem, run.root, run.stats, deadline, run.checks) or SearchResult(
                "infeasible", "", run.stats
            )
        _push(problem, run.frontier, run.root, (), run.order, run.stats)
    stats, frontier, withheld, order = run.stats, run.frontier, run.withheld, run.order
    by = deadline if pause_at is None else min(deadline, pause_at)  # the checks' deadline (`_check_once`)
    reporter = Progress(progress)
    try:
        if run.recheck is not None:  # the check its pause cut short: made again first, as it comes first
            seq, run.recheck = run.recheck, None
            found = _check_once(problem, run, seq, by, pause_at)
            if found is not None:
                return found
            for parent, at, met in withheld.bring_back(stats):
                _expand(problem, frontier, parent, at, order, stats, withheld.bodies, only=met)
        while frontier:
            entry = heapq.heappop(frontier)
            stats.level, _, path, seq, checked = entry
            if _cut(deadline, budget, pause_at, stats):
                if paused is not None and time.perf_counter() <= deadline:  # ended by its budget or pause alone
                    heapq.heappush(frontier, entry)  # (its key is unique: the queue's order is as it was)
                    paused.keep(run)
                return SearchResult("timeout", timeout_reason(problem, stats, budget), stats)
            if checked:
                pass  # queued again for its expansion only (`_Entry`)
            elif seq.actions and stats.level == seq.depth and _moves_goal_body(problem, seq):
                found = _check_once(problem, run, seq, by, pause_at)
                if found is not None:
                    return found
                for parent, at, met in withheld.bring_back(stats):  # contacts on a body just met
                    _expand(problem, frontier, parent, at, order, stats, withheld.bodies, only=met)
            elif seq.actions:
                stats.passed_over += 1
            if seq.depth >= problem.max_depth:
                continue
            if seq.depth + 1 > stats.level:  # its children all wait for a later level: so does their making
                heapq.heappush(frontier, (seq.depth + 1, 0, path, seq, True))
                continue
            stats.graphs_expanded += 1
            stats.depth_reached = max(stats.depth_reached, seq.depth + 1)
            reporter.show(stats)
            _expand(problem, frontier, seq, path, order, stats, withheld.bodies)
            withheld.expanded(seq, path)
    finally:
        reporter.done()
    if run.recheck is not None and paused is not None and time.perf_counter() <= deadline:
        paused.keep(run)  # (its last check cut short by the pause: no proof of no plan)
    if time.perf_counter() > deadline or run.recheck is not None:
        return SearchResult("timeout", timeout_reason(problem, stats), stats)
    return SearchResult("infeasible", infeasible_reason(problem, stats, order.bound), stats)


def _check_once(problem: Problem, run: _Run, seq: Sequence, by: float, pause_at: float | None) -> SearchResult | None:
    """`check` of `seq` until `by`. One that the pause (`search(pause_at=)`) cut short without a plan may have
    rejected what it had no time to try: it is kept to be made again when the search goes on (`_Run.recheck`),
    and the failures of last motions it remembered are forgotten (`LastMotion.forget_after`)."""
    known = len(run.checks.last_motion.seen)
    found = check(problem, seq, run.stats, by, run.checks)
    if found is None and pause_at is not None and time.perf_counter() > pause_at:
        run.recheck = seq
        run.checks.last_motion.forget_after(known)
    return found


def _cut(deadline: float, budget: float | None, pause_at: float | None, stats: SearchStats) -> bool:
    """Whether the search ends before its next sequence: the deadline, its work budget or its pause has passed."""
    now = time.perf_counter()
    spent = budget is not None and stats.work_done() > budget
    return now > deadline or spent or (pause_at is not None and now > pause_at)


class _Run:
    """What one search holds while it runs: its counters, queue, checks and order (kept by `Paused`)."""

    def __init__(self, problem: Problem, root: Sequence | None, still: frozenset[str]) -> None:
        self.problem = problem
        self.root = start_sequence(problem) if root is None else root
        self.stats = SearchStats(watch=still)
        self.withheld = Withheld(still)
        geometry = GeometryCheck(problem)
        self.checks = Checks(geometry, ArmPathPlanner(problem, geometry), self.stats.arm_hits)
        self.order = _Order(Bound(problem), InTheWay(problem))
        self.frontier: list[_Entry] = []
        self.recheck: Sequence | None = None  # a check its pause cut short (`_check_once`)

    def searched(self, problem: Problem, root: Sequence | None) -> bool:
        """Whether this run searches `problem` from `root` (the same objects; no `root`: G0)."""
        return self.problem is problem and (self.root is root if root is not None else self.root.depth == 1)


class Paused:
    """A search that spent its budget, kept to go on from (`search(paused=)`): the clear-first walk searches a
    side, or the goals after a clearing plan, with a small budget first and again with a larger one
    (`vkgl.plan.search.clutter.clear_first`); started anew, the second search would first redo every check of
    the first (on the physical bench's gen3_023, 75 of the 205 units that find its plan). The first search of a
    blocked task is kept at its pause (`search(pause_at=)`) and goes on when the walk leaves time
    (`vkgl.plan.solve`).

    Nothing is kept of a search that ended otherwise: solved, proven infeasible, or stopped by its deadline (a
    check the deadline cut short may have rejected what it had no time to try; one its pause cut short is made
    again, `_check_once`)."""

    def __init__(self) -> None:
        self._run: _Run | None = None

    def keep(self, run: _Run) -> None:
        """Keep `run`, stopped by its budget."""
        self._run = run

    def take(self, problem: Problem, root: Sequence | None) -> _Run | None:
        """The run kept, if it searched `problem` from `root` (the same objects); None otherwise. Taken once: a
        run that goes on is kept again only if its budget stops it again."""
        run, self._run = self._run, None
        return run if run is not None and run.searched(problem, root) else None

    def holds(self, problem: Problem, root: Sequence | None = None) -> bool:
        """Whether `search` would go on from a run kept here (`take`) for `problem` from `root`."""
        return self._run is not None and self._run.searched(problem, root)

    def stats(self, problem: Problem, root: Sequence | None) -> SearchStats | None:
        """A copy of the counters of the run kept, if `search` would go on from it (`take`), as they stand: a
        caller that adds up its searches' work adds only what the run does after them (`add_stats(since=)`)."""
        run = self._run
        return copy.deepcopy(run.stats) if run is not None and run.searched(problem, root) else None


_Entry = tuple[float, int, tuple[int, ...], Sequence, bool]
"""A queued sequence: (depth plus bound, the bodies in the way it has not moved yet (`InTheWay.left`), the
successor indices that made it, the sequence, whether it was checked).

Keys are unique (one sequence per path; a sequence queued again for its expansion has a larger first member), so
two entries never compare their sequences. A sequence without bound left (depth = its level) is checked when it
leaves the queue, and queued again as (depth + 1, 0, path) to be expanded then. That changes no check's turn:
every child's key (depth + 1 + its bound, its count, path + (i,)) is larger than the entry's. So while a child's
turn has not come, neither has any entry after it, and when the queue of expanding at once would give a check next,
the late queue gives the same one, after the expansions of the entries smaller than it (each of which only adds
entries larger than itself): the checks come in the same order, and the children of the sequences of the level where
a plan is found (or the time runs out) are never made. With `max_depth` 6 those of the sequences of 6 graphs were
never made either; with a deeper `max_depth`, making them at once cost up to half the time of a level (gen1_005
of the physical bench: 4,548 graphs expanded and no plan in 16 s of CPU at `max_depth` 6; at 10 the time ran out
at the same level after 7,992)."""


@dataclass(frozen=True)
class _Order:
    """What orders the queue: the bound (first) and the bodies in the way (among sequences of one level)."""

    bound: Bound
    in_the_way: InTheWay


def _expand(
    problem: Problem,
    frontier: list[_Entry],
    seq: Sequence,
    path: tuple[int, ...],
    order: _Order,
    stats: SearchStats,
    withheld: frozenset[str] = frozenset(),
    only: frozenset[str] | None = None,
) -> None:
    """Queue `seq`'s children (`successors`), but those whose hand is out of reach at once, with everything
    that would follow them, and those that repeat a step that failed in execution. A contact on a body of
    `withheld` is no child (`Withheld`); given `only`, only contacts on those bodies are (each keeps its index
    among all the successors, so its key is the one it would have had)."""
    for index, action in enumerate(successors(problem, seq.graphs[-1], seq.last)):
        if withholds(action, withheld) or (only is not None and not withholds(action, only)):
            continue
        child, hand = extend(problem, seq, action)
        if problem.moves_once is not None and _moved_again(child, problem.moves_once):
            continue
        stats.sequences += 1
        if hand is not None and (rejection := unreachable(problem, hand)) is not None:
            stats.pruned += 1
            stats.reject(rejection, functools.partial(_label, problem, child))
            continue
        if (rejection := repeated_failure(problem, seq, child, action)) is not None:
            stats.excluded += 1  # with everything that would follow it
            stats.reject(rejection, functools.partial(_label, problem, child))
            continue
        _push(problem, frontier, child, path + (index,), order, stats)


def _moved_again(child: Sequence, after: int) -> bool:
    """Whether `child`'s last action makes a contact that moves a body which a mode of `child` from graph `after`
    on moved before (`Problem.moves_once`)."""
    action, mode = child.actions[-1], child.depth - 1
    if action.op != "add":
        return False
    body = action.engagement.body
    moving = any(m == mode and e.body == body for m, e in child.variables)
    return moving and any(after <= m < mode and e.body == body for m, e in child.variables)


def _label(problem: Problem, seq: Sequence) -> str:
    """The sequence in words, its actions in turn: a pruned child is named whole, not by its last action alone
    (which read as a tool used before its grasp)."""
    return " -> ".join(a.label(problem) for a in seq.actions)


def _push(
    problem: Problem,
    frontier: list[_Entry],
    seq: Sequence,
    path: tuple[int, ...],
    order: _Order,
    stats: SearchStats,
) -> None:
    """Queue `seq` (reached by the successor indices `path`) unless it and the graphs it still needs pass
    max_depth."""
    total = seq.depth + order.bound(seq)
    if total > problem.max_depth:
        stats.cut_by_bound += bool(seq.actions)  # G0 is no sequence tried: the reason says so instead
        stats.cut_at_start = not seq.actions
        stats.shortest_cut = min(stats.shortest_cut, total)
        return
    heapq.heappush(frontier, (total, order.in_the_way.left(seq), path, seq, False))


def _moves_goal_body(problem: Problem, seq: Sequence) -> bool:
    """Whether the last mode of `seq` moves a body that a goal names, or its last action sets one down that
    the mode before carried."""
    mode = seq.depth - 1
    goal_bodies = {g.body for g in problem.goals}
    if any(m == mode - 1 and e.body in goal_bodies for m, e in seq.carries):
        return True
    return any(m == mode and e.body in goal_bodies for m, e in seq.variables)
