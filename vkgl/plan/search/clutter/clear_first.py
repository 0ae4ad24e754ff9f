"""Clear first, then solve: a plan for a goal body with another body in its way, deeper than the search affords.

A goal body with a body lying across its straight way (`vkgl.plan.search.ordering.InTheWay`) needs a plan that
moves that body aside first, then the goal body, often with a tool: on the physical bench that is 7 graphs or
more, one past the default `max_depth`, and the search cannot afford the level of 7 graphs in a cluttered scene
(thousands of sequences, each checked by the optimiser). A person splits the task in two, and so does
`clear_first`, once the search has ended without a plan:

1. **Clear.** For the blocker nearest the goal body's start, a sub-problem whose only goal is a region goal: the
   blocker's footprint beyond one side of the goal body's straight corridor with a margin
   (`vkgl.plan.task_space.clearing.way_sides`: left, right, or beyond the goal; the sides one motion of the
   blocker's own affordances reaches first, then the nearest). It is searched like any problem, to at most
   `CLEAR_DEPTH` graphs (G0, a tool's grasp, the push that clears it, one more), and its plan passes every
   check a plan passes. Several blockers are cleared in turn, each sub-problem starting where the one before
   ended (one that plan already moved is first left to the goals' search, its values free: `_moves`); one that no
   plan moves is left where it lies, the others cleared (it may lie where no plan meets it: the search after says).
2. **Then solve.** The original problem is searched again from that plan (`search(..., root=prefix)`): every
   sequence extends it, with up to `max_depth - 1` graphs more, so the tool the prefix holds is still in hand
   and its contact still in force. The plan found is one graph sequence like any other: its motion values are
   chosen again for the whole sequence (the blocker moved as far as the goal body's real corridor needs,
   `clearing.cleared_values`), and it passes every check; the plan format does not change.

**Narrow first.** The walk first goes over the way's blockers with a narrow sub-problem per side (`NARROW_SHARE`):
each goal body slides only along its own way, every body is slid, not turned, and moved at most once
(`only_moving(along=True)`; a blocker its plan before moved already is left to the goal's values, not cleared
again; the sides one push of it alone clears come first, `_Walk._one_contact`): its plans leave the goal body on its
line, where the plan after needs no move back, and the searches for the goals after those that left every goal
body where it lies go on at once, unless one body alone is in the way or bodies in a path wait (`_wide_first`).
Then the bodies the closest miss of the search before failed on alone, in a tool's or the hand's path (`met_last`;
the goals' search after the first plan that clears them and leaves the goal bodies where they lie goes on at once,
`_Walk.eager`), then the wide walk. With nothing in any goal body's way, the bodies in the path of the tool that
alone carries a goal body (`tool_sweep.swept_bodies`) are the walk's blockers: cleared first, not left where they
lie (`_Walk.optional`), each slid out of the tool's sweep (`tool_path.path_sides`).

Sides and blockers are tried in turn (a depth-first walk) until a plan is found or the work budget is spent. The
search for the goals after each clearing plan first gets a small budget (`THEN_FIRST`); those that spend it wait
until every side of the blocker had its first try and then go again with `THEN_SHARE`, the clearing plan that left
the goal body where it lies first (`_Waiting.rank`): the work goes to the likeliest prefix, not to whichever side
was tried first. A search tried again (a goals' search, a side's) goes on where its first budget stopped it
(`search(paused=)`), its budget counting both runs: the same search as one started anew, without its first
try's work done twice.

**Counted work, not seconds.** The search before gets `SEARCH_SHARE` of the timeout and of the work budget,
whichever it spends first (fast enough, the count ends it, the same everywhere; under heavy load the clock, and the
clearing keeps its time; it pauses there, and goes on with what time is left when this finds no plan:
`vkgl.plan.solve`); what is tried here gets the rest of the task's work budget (`work_budget`: its timeout's
worth, in units of `SearchStats.work_done`), shared by counted work, not by the time left: the same clearing ends
the same way on any machine and under any load, the deadline the wall-clock guard. Each side of a blocker is first
searched with a small budget (`FIRST_TRY`: a push that clears it is found with a few units), only the sides that
spent it again with a share of what is left (`CLEAR_SHARE`); the search for the goals after a clearing plan gets
most of what is left (`THEN_SHARE`) (docs/planning.md, "Clear first, then solve": why the clock's cut too).

**Shortest or not.** The search before proved that no plan of at most `proven` graphs exists (every sequence
of `max_depth` graphs when it ended without a plan, those of fewer than its level when the time ran out). A plan
of `proven + 1` graphs found here is therefore a shortest one; a deeper one may not be (a plan that clears no
blocker, or clears it otherwise, might be shorter) and its words say "not proven shortest".

Where the bound says that no sequence of any length reaches the goal, nothing is tried: the answer stays immediate.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from dataclasses import dataclass, field, replace

import numpy as np

from vkgl.plan.graphs.graph import Action
from vkgl.plan.graphs.rollout import Sequence, start_sequence
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.search.clutter.blocking import blocking_bodies, proven_depth
from vkgl.plan.search.clutter.clear_tools import far_move_tools
from vkgl.plan.search.clutter.rolled import rolls, with_rolled_members
from vkgl.plan.search.clutter.side_problem import moved_before as _moves
from vkgl.plan.search.clutter.side_problem import only_moving, side_goal
from vkgl.plan.search.clutter.tool_path import met_last, path_blockers, path_sides
from vkgl.plan.search.clutter.tool_sweep import swept_bodies
from vkgl.plan.search.clutter.waiting import Cleared
from vkgl.plan.search.clutter.waiting import Waiting as _Waiting
from vkgl.plan.search.clutter.words import closest as _closest
from vkgl.plan.search.clutter.words import side_words as _side_words
from vkgl.plan.search.search import Paused, SearchResult, search
from vkgl.plan.search.stats import SearchStats, add_stats
from vkgl.plan.task_space.clearing import Side, way_sides

CLEAR_DEPTH = 5
"""Graphs of a plan that clears one blocker, G0 included: the push (2), or a tool's grasp first (3)."""

FIRST_TRY = 0.05
"""The part of the work left for clearing (`clear_first`'s `budget`) that each side of a blocker gets in the first
round: the sides one push of the fingertip or of a tool in hand reaches are found with a few units (3 to 40 on the
physical bench), and a side no plan reaches could take the whole level of `CLEAR_DEPTH` graphs; so every side is
tried cheaply first, and only those that spent it are tried again (`CLEAR_SHARE`)."""

CLEAR_SHARE = 0.25
"""The least part of the work left that one search for a plan clearing a blocker to one side may spend in the
second round (with `k` sides still to try, `1 / (k + 1)` if more): it must leave work for the other sides and goal."""

THEN_SHARE = 0.8
"""The part of the work left that the search for the goals after a plan clearing the way may spend in its second
round (after `THEN_FIRST`): it is the likeliest way to a plan (gen9_028 of the physical bench finds its plan of 8
graphs there at the last level, with about 450 units), and the rest is kept for the sides still to try."""

THEN_FIRST = 0.1
"""The part of the work left that the search for the goals after each plan clearing the way gets first (the
goal body's own plan, once the way is clear, is found with 10 to 60 units on the physical bench's near blocked
tasks); those that spend it are searched again with `THEN_SHARE` once every side had its first try."""

NARROW_SHARE = 1 / 3
"""The part of the work left that the narrow try at clearing a blocker to one side may spend (module docstring):
on the physical bench's gen3_033 it finds the Stick's clearing that leaves the crate on its line with 206 units
(the whole space: 1,146, after one that pushed the crate aside with 307); sides no plan reaches: about 100."""

MAX_DEPTH = 12
"""The deepest plan tried (the CLI's `--max-depth` limit)."""

SEARCH_SHARE = 0.5
"""The part of the timeout and of the work budget (`work_budget`) the search itself gets when a body lies in a
goal body's way or a tool's path (`blocked`), whichever it spends first: the rest of the work budget is left for
clearing it first when the search times out. On the physical bench the tasks with a body in the way that the
search solves take at most a third of the 20 s timeout and 645 units (docs/physical_bench.md)."""

WORK_PER_SECOND = 80.0
"""Work units (`SearchStats.work_done`: about one task-space optimisation each) that one second of the timeout
buys for a blocked task's clearing (`work_budget`): on the physical bench's blocked tasks (`bench/plan/
bench_blocked.py`) one core does 65 to 150 units a second, about 100 on most, so that the clearing's half of a 20 s
timeout (800 units) is spent before the deadline ends anything on most tasks."""


def work_budget(problem: Problem) -> float:
    """The work (units of `SearchStats.work_done`) a blocked task's searches may spend in all: its timeout's
    worth, `WORK_PER_SECOND` units a second."""
    return problem.timeout * WORK_PER_SECOND


def clear_first(
    problem: Problem, before: SearchResult, *, deadline: float, budget: float, progress: bool = False
) -> Cleared | None:
    """A plan that clears the bodies in a goal body's way first, then reaches the goals (see the module's
    docstring), searched with at most `budget` units of work (`SearchStats.work_done`) until `deadline` at the
    latest; None when nothing was tried (nothing lies in the way, or clear of its straight way, or no sequence
    of any length reaches the goal). `before` is the search that ended without a plan; the counters of every
    search tried here are added to its."""
    start = start_sequence(problem)
    blocking = blocking_bodies(problem)
    bound = Bound(problem)
    swept = {} if blocking else swept_bodies(problem, bound)  # in a tool's path, nothing in a way (`tool_sweep`)
    if not (blocking or swept) or math.isinf(bound(start)):
        return None
    proven = proven_depth(problem, before)
    paths = {**dict.fromkeys(swept, 0.0), **path_blockers(problem, before.stats)}  # (`clutter.tool_path`)
    first = blocking[0][0] if blocking else next(iter(swept.values())).goal
    goals = {name: swept[name].goal if name in swept else first for name in paths}  # whose tool's path each is in
    walk = _Walk(problem, deadline, progress, before.stats, budget, paths=paths, narrow=True, bound=bound)
    walk.sweeps = {name: s.sweeps for name, s in swept.items()}
    held: list[_Waiting] = []  # the narrow walk's searches for the goals that spent their first try
    found = _clear_then_solve(walk, blocking, start, proven, held)  # first the narrow walk (`NARROW_SHARE`)
    if found is not None and found is not _NOTHING:
        return found
    walk.narrow, found = False, None
    if last := met_last(problem, paths, before.stats):  # the closest miss failed on them: cleared alone first
        walk.eager = True
        found = _clear_then_solve(walk, [(goals[name], name) for name in last], start, proven, held)
        walk.eager = False
    if found is None or found is _NOTHING:  # then the way's blockers, and the bodies in a path after them (left
        walk.optional = frozenset(paths) - set(swept)  # where they lie first: the plans the walk found before first)
        found = _clear_then_solve(walk, blocking + [(goals[name], name) for name in paths], start, proven, held)
    if found is _NOTHING:
        return None  # every body in the way lies clear of the straight way already: nothing to search anew
    if found is not None:
        return found
    if not walk.log:
        return None
    ran_out = f" ({walk.ran_out()})" if walk.spent() else ""
    share = (
        f" with the work the search left ({1 - SEARCH_SHARE:.0%} of the timeout's worth)"
        if before.status == "timeout"
        else ""
    )
    return Cleared(None, f"clearing the way first{share} found no plan either{ran_out}: " + "; ".join(walk.log))


def _clear_then_solve(
    walk: _Walk,
    blocking: list[tuple[GoalSpec, str]],
    start: Sequence,
    proven: int,
    held: list[_Waiting] | None = None,
) -> Cleared | None:
    """The plans that clear the blockers (`_Walk.prefixes`), each followed by the search for the goals: the
    combined plan (`Cleared` with a result), or `_NOTHING` when every body in the way lies clear of the straight
    way already (nothing to search anew), or None when none was found (what failed is in `walk.log`).

    Each clearing plan's search for the goals first gets `THEN_FIRST` of the work left; those that spend it wait
    (`_Waiting`) until the sides of the blocker have all had their first try (`_Walk.prefixes` says when), and are
    then searched again with `THEN_SHARE` of the work left each, the most promising first (`_Waiting.rank`): the
    work goes to the clearing plan that leaves the goal body where it lies before one that moved it away, not to
    whichever side was tried first. A clearing plan found in the second round of sides gets `THEN_SHARE` at once
    (gen9_043: the Hook's plan found there, its search cut at 26 units and again at 67 after the last side's
    second try, where it needs a few hundred).

    `held`: the searches that wait from a walk before (the narrow walk's), taken over; the narrow walk
    (`_Walk.narrow`) leaves its own there for the walk after it instead of searching them again."""
    held = [] if held is None else held
    waiting, held[:] = held[:], []
    first = True  # the first round of sides: a search for the goals gets a first try and waits
    for item in walk.prefixes(blocking, start):
        if item is None:  # the first round of a blocker's sides is over: the waiting searches' turn, but those
            first = False  # after a prefix that moved a goal body wait for the sides' second round too
            now, waiting[:] = [w for w in waiting if not w.rank()[0]], [w for w in waiting if w.rank()[0]]
            found = _then_again(walk, now, proven)
            if found is not None or walk.spent():
                return found
            continue
        prefix, values, cleared = item
        if not cleared:
            return _NOTHING
        key = (prefix.actions, tuple((name, side.words) for name, side in cleared))
        if key in walk.seen:  # the narrow walk's plan, found again by the whole space's search: searched once
            continue
        walk.seen.add(key)
        deeper = replace(
            walk.problem, max_depth=min(MAX_DEPTH, prefix.depth - 1 + walk.problem.max_depth), pinned=values
        )
        then = _Waiting(deeper, prefix, cleared, len(waiting))
        result = then.search(walk, (THEN_FIRST if first else THEN_SHARE) * walk.left)
        again = first and walk.eager and result.status == "timeout" and not then.rank()[0]
        if again:  # (`_Walk.eager`: once)
            walk.eager = False
            result = then.search(walk, THEN_SHARE * walk.left)
        if result.status == "solved":
            return then.solved(walk, result, proven)
        if first and result.status == "timeout" and not again:
            waiting.append(then)
        else:
            then.log(walk, result)
        if walk.spent():
            break
    if walk.narrow and not walk.spent():  # those after a plan that left every goal body where it lies go on at
        go = [not w.rank()[0] and not _wide_first(walk, blocking) for w in waiting]  # once (`_wide_first`)
        held[:] = [w for w, now in zip(waiting, go, strict=True) if not now]
        return _then_again(walk, [w for w, now in zip(waiting, go, strict=True) if now], proven)
    return _then_again(walk, waiting, proven)


def _wide_first(walk: _Walk, blocking: list[tuple[GoalSpec, str]]) -> bool:
    """Whether the narrow walk's searches for the goals after a plan that left the goal bodies still wait for the
    wide walk's first round: with bodies in a path (gen1_041), or one body alone in the way (docs/planning.md)."""
    return bool(walk.paths) or len(blocking) < 2


def _then_again(walk: _Walk, waiting: list[_Waiting], proven: int) -> Cleared | None:
    """The waiting searches for the goals (`waiting` emptied), the likeliest first, each with `THEN_SHARE` left."""
    for then in sorted(waiting, key=_Waiting.rank):
        if walk.spent():
            walk.log.append(f"{then.moved()} ({then.prefix.depth} graphs), then {walk.ran_out()}")
            continue
        result = then.search(walk, THEN_SHARE * walk.left)
        if result.status == "solved":
            waiting.clear()
            return then.solved(walk, result, proven)
        then.log(walk, result)
    waiting.clear()
    return None


_NOTHING = Cleared(None, "")
"""What `_clear_then_solve` returns when nothing lies in the way."""

_Prefix = tuple[Sequence, tuple[float, ...], list[tuple[str, Side]]]
"""A plan that clears the way: its sequence, its motion values, the blockers and the sides they were cleared to."""


@dataclass
class _Walk:
    """The depth-first walk over the blockers and their sides: the work left (`left`, units of
    `SearchStats.work_done`), the searches' counters and what failed, in words."""

    problem: Problem
    deadline: float
    progress: bool
    stats: SearchStats
    left: float
    log: list[str] = field(default_factory=list)
    paths: dict[str, float] = field(default_factory=dict)  # bodies in a tool's or the hand's path: how deep met
    sweeps: dict[str, tuple[np.ndarray, ...]] = field(default_factory=dict)  # the tools' sweeps they lie in
    optional: frozenset[str] = frozenset()  # those of `paths` the walk leaves where they lie first
    narrow: bool = False  # the narrow walk: each blocker's sides with `only_moving`'s `along` only
    seen: set[tuple[tuple[Action, ...], tuple[tuple[str, str], ...]]] = field(default_factory=set)  # prefixes
    narrowed: dict[tuple[str, str, tuple[Action, ...]], SearchResult] = field(default_factory=dict)  # its plans
    eager: bool = False  # the walk over met_last's bodies: its first plan that left the goal bodies still goes on
    bound: Bound | None = None  # `problem`'s, made once (`far_move_tools` and `only_moving` ask for it per side)
    way: dict[tuple[str, int], tuple[GoalSpec, list[Side]]] = field(default_factory=dict)  # `_way_sides`' memo
    subs: dict[tuple[object, ...], tuple[Problem, frozenset[str], Paused]] = field(default_factory=dict)  # `_clear`'s

    def search(
        self,
        problem: Problem,
        root: Sequence,
        budget: float,
        still: frozenset[str] = frozenset(),
        paused: Paused | None = None,
    ) -> SearchResult:
        """`problem` searched from `root` with at most `budget` units of the work left (the bodies `still` kept
        still until a rejection names one, `search(still=)`); its work is taken off. With `paused`, a search of
        the same problem and root that an earlier budget stopped goes on from there (`search(paused=)`): its
        budget counts both runs, and only the work since is taken off."""
        since = paused.stats(problem, root) if paused is not None else None
        result = search(
            problem,
            deadline=self.deadline,
            progress=self.progress,
            root=root,
            budget=budget,
            still=still,
            paused=paused,
        )
        add_stats(self.stats, result.stats, since)
        self.left -= result.stats.work_done() - (since.work_done() if since is not None else 0.0)
        return result

    def spent(self) -> bool:
        """Whether the work or the time left is gone."""
        return self.left <= 0.0 or time.perf_counter() > self.deadline

    def ran_out(self) -> str:
        """What ran out, in words."""
        return "the time ran out" if time.perf_counter() > self.deadline else "the work budget ran out"

    def prefixes(
        self, blocking: list[tuple[GoalSpec, str]], root: Sequence, pinned: tuple[float, ...] = ()
    ) -> Iterator[_Prefix | None]:
        """Plans that clear every blocker in turn starting from `root` (each blocker's sides in turn), each with
        its motion values (`root`'s are `pinned`) and the blockers and the sides they were cleared to (none when
        every one lies clear of the way already); None between a blocker's two rounds of sides. A blocker no
        side's plan moves is left where it lies: the plans that clear the others (if any)."""
        if not blocking:
            yield root, pinned, []
            return
        (goal, blocker), rest = blocking[0], blocking[1:]
        if blocker in self.paths and blocker in root.dependent:  # a body in a tool's path the plan moved already
            yield from self.prefixes(rest, root, pinned)  # (its sub-problem keeps only the slides, not the root's)
            return
        sides = (
            path_sides(self.problem, goal, blocker, self.paths[blocker], self.sweeps.get(blocker, ()))
            if blocker in self.paths and not self.narrow
            else self._way_sides(goal, blocker)
        )
        if len(sides) == 1 and sides[0].distance == 0.0:  # clear of the straight way already
            yield from self.prefixes(rest, root, pinned)
            return
        if _moves(root, blocker):  # moved by the plan before, still in the way: first left to the goal's values
            yield from self.prefixes(rest, root, ())
            if self.narrow:  # the narrow walk moves every body once: clearing it again is the wide walk's
                return
        optional = blocker in self.optional  # a body in a tool's path, first left where it lies (as before)
        if optional:
            yield from (item for item in self.prefixes(rest, root, pinned) if item is None or item[2] or root.depth > 1)
        moved = False  # some side's plan moved it; the narrow walk: with `NARROW_SHARE`, up to the first plan
        quick = self._one_contact(goal, blocker, sides, root, pinned) if self.narrow else None
        order = sides if quick is None else [quick[0], *(side for side in sides if side is not quick[0])]
        for side in order if self.narrow else ():
            if self.spent():
                return
            found = (
                quick[1]
                if quick is not None and side is quick[0]
                else self._clear(goal, blocker, side, root, pinned, NARROW_SHARE * self.left, rolled=False, along=True)
            )
            if found.status == "solved":  # (the other sides' plans are the wide walk's: each costs a search after)
                moved = True
                self.narrowed[(blocker, side.words, root.actions)] = found
                yield from self._then(found, rest, blocker, side)
                break
        first = FIRST_TRY * self.left
        again: list[tuple[Side, bool]] = []  # the sides that spent their first budget, and whether rolled next
        for side in sides if not self.narrow else ():  # first round: every side with a small budget
            if self.spent():
                return
            narrow = self.narrowed.get((blocker, side.words, root.actions))  # its narrow plan stands for its first
            found = narrow or self._clear(goal, blocker, side, root, pinned, first, rolled=False)  # try's (same plan)
            if found.status == "timeout":
                again.append((side, False))
            elif found.status == "infeasible" and blocker not in self.paths and rolls(self.problem, blocker):
                # (not for a body in a tool's path: the search for the goals after it knows no rolled member of it)
                # a rolled hook's pulls only where the flat tools are proven to fail (`clutter.rolled`): on a
                # side that merely ran out, they widen its second search (gen1_001 lost its plan to them)
                again.append((side, True))
            elif found.status == "solved":
                moved = True
                yield from self._then(found, rest, blocker, side)
        if again:
            yield None  # the first round is over: the searches for the goals waiting go first
        for k, (side, rolled) in enumerate(again):  # second round: a share of what is left
            if self.spent():
                return
            budget = max(CLEAR_SHARE, 1.0 / (len(again) - k + 1)) * self.left
            found = self._clear(goal, blocker, side, root, pinned, budget, rolled=rolled)
            if found.status == "timeout":
                self.log.append(f"{_side_words(blocker, side)}: no plan within its budget{_closest(found)}")
            elif found.status == "solved":
                moved = True
                yield from self._then(found, rest, blocker, side)
        if not moved and not optional and not self.spent():  # no plan moves it: the others cleared, it is left
            yield from (item for item in self.prefixes(rest, root, pinned) if item is None or item[2] or root.depth > 1)

    def _one_contact(
        self, goal: GoalSpec, blocker: str, sides: list[Side], root: Sequence, pinned: tuple[float, ...]
    ) -> tuple[Side, SearchResult] | None:
        """The first of `sides` one motion of `blocker` reaches that one contact more than `root` clears it to in
        the narrow sub-problem (`FIRST_TRY` each), with its plan; None: none. A longer plan on a side tried first
        (a tool grasped) must not hide another side's push of the blocker alone (docs/planning.md, gen20_026)."""
        for side in sides:
            if not (math.isfinite(side.slide) or side.turn):
                continue
            if self.spent():
                return None
            found = self._clear(
                goal, blocker, side, root, pinned, FIRST_TRY * self.left, rolled=False, along=True, depth=2
            )
            if found.status == "solved":
                return side, found
        return None

    def _way_sides(self, goal: GoalSpec, blocker: str) -> list[Side]:
        """`way_sides` of `blocker` in `goal`'s way, widened for the tools that carry the goal body: made once per
        walk (they depend on neither the root nor the walk's round; each costs a few hundred ms of trying the
        blocker's motions)."""
        key = (blocker, id(goal))  # (the goal kept with its sides: its id names no other while they are kept)
        if key not in self.way:
            tools = far_move_tools(self.problem, goal, self.bound)
            self.way[key] = (goal, way_sides(self.problem, goal, blocker, tools=tools))
        return self.way[key][1]

    def _clear(
        self,
        goal: GoalSpec,
        blocker: str,
        side: Side,
        root: Sequence,
        pinned: tuple[float, ...],
        budget: float,
        *,
        rolled: bool,
        along: bool = False,
        depth: int = CLEAR_DEPTH,
    ) -> SearchResult:
        """The search for a plan that clears `blocker` to `side` from `root` with `budget` units (`rolled`: also by a
        rolled hook; `along`: the narrow try) and `depth` graphs at most (`root` counted as one): solved (with its
        sequence), proven infeasible (logged, at `CLEAR_DEPTH`) or "timeout"."""
        key = (blocker, side.words, root.actions, pinned, rolled, along, depth)
        if key not in self.subs:  # a side tried again (its second round) goes on where its first try stopped
            moving, still = only_moving(self.problem, goal, blocker, side, root, along=along, bound=self.bound)
            sub = replace(
                with_rolled_members(moving, blocker) if rolled else moving,
                goals=[side_goal(self.problem, goal, blocker, side)],
                max_depth=root.depth - 1 + depth,
                pinned=pinned,
            )
            self.subs[key] = (sub, still, Paused())
        sub, still, paused = self.subs[key]
        found = self.search(sub, root, budget, still=still, paused=paused)
        if found.status == "solved" and found.sequence is not None:
            return found
        if found.status != "timeout" and depth < CLEAR_DEPTH:
            return replace(found, status="infeasible", sequence=None)  # a shallow try proves nothing of the side
        if found.status != "timeout":
            words = f"no plan of at most {sub.max_depth} graphs{_closest(found)}"
            narrow = " (the goal body on its line, each body slid once)" if along else ""
            self.log.append(f"{_side_words(blocker, side)}{narrow}: {words}")
            return replace(found, status="infeasible", sequence=None)
        return found

    def _then(
        self, found: SearchResult, rest: list[tuple[GoalSpec, str]], blocker: str, side: Side
    ) -> Iterator[_Prefix | None]:
        """The prefixes that start with `found`'s plan clearing `blocker` to `side`, then clear the `rest` (and
        the markers between rounds of their sides)."""
        assert found.task is not None and found.sequence is not None
        values = tuple(float(v) for v in found.task.values[: len(found.sequence.variables)])
        for item in self.prefixes(rest, found.sequence, values):
            if item is None:
                yield None
                continue
            prefix, kept, cleared = item
            yield prefix, kept, [(blocker, side), *cleared]


__all__ = [
    "CLEAR_DEPTH",
    "SEARCH_SHARE",
    "WORK_PER_SECOND",
    "Cleared",
    "clear_first",
    "side_goal",
    "work_budget",
]
