"""What one search counted (`SearchStats`) and how it words its end: the "no plan" reason with each kind of
rejection's closest miss, the `--max-depth` hint, the timeout's reason, and the progress line on a terminal."""

from __future__ import annotations

import math
import sys
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field, fields

from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.search.bounds.bound import Bound
from vkgl.plan.task_space.feasible import Counters


@dataclass
class SearchStats:
    """Counters of one search (reported in the plan and by bench/plan/bench_solve.py)."""

    graphs_expanded: int = 0
    sequences: int = 0
    pruned: int = 0
    excluded: int = 0  # sequences cut at once for repeating a step that failed in execution (`vkgl.plan.problem.avoid`)
    passed_over: int = 0  # extended, never checked themselves: their last mode moves no goal body, or the bound > 0
    cut_by_bound: int = 0  # sequences never queued: their depth plus the graphs they still need pass max_depth
    shortest_cut: float = math.inf  # the fewest graphs any of those could reach the goal in (inf: none)
    cut_at_start: bool = False  # G0 alone already needs more graphs than max_depth allows
    level: float = 1  # depth plus bound of the sequence checked last: every one below it has been checked
    task_space_checks: int = 0
    last_motion_known: int = 0  # rejected unchecked: their last motion failed alone before (`last_motion`)
    geometry_checks: int = 0
    joint_space_checks: int = 0
    arm_path_checks: int = 0  # sequences whose straight moves (approach, retreat, lift) were planned
    transit_checks: int = 0  # of those, candidates whose transits were then planned (after the search)
    transits: int = 0
    arm_path_time: float = 0.0  # s planning the straight moves and contact chains (part of the search's time)
    transit_time: float = 0.0  # s planning transits (after the search: not part of `arm_path_time`)
    work: Counters = field(default_factory=Counters)
    depth_reached: int = 1
    rejections: Counter = field(default_factory=Counter)
    examples: dict[str, tuple[float, str, str]] = field(default_factory=dict)  # kind: (excess, sequence, why)
    advice: dict[str, str] = field(default_factory=dict)  # kind: what to change, of its example (if it says)
    example_bodies: dict[str, frozenset[str]] = field(default_factory=dict)  # kind: the bodies its example named
    watch: frozenset[str] = frozenset()  # bodies kept still (`search(still=)`): a rejection naming one meets it
    met: set[str] = field(default_factory=set)  # those of `watch` that some rejection named
    arm_hits: set[str] = field(default_factory=set)  # bodies the arm's checks found in its way (`arm_aside`)
    named: dict[frozenset[str], float] = field(default_factory=dict)  # bodies rejections named: least excess

    def work_done(self) -> float:
        """The work done so far, in units of about one task-space optimisation (`WORK_WEIGHTS`): what a search's
        `budget` counts. Counts, not seconds: a budget then ends a search at the same sequence on any machine."""
        w = WORK_WEIGHTS
        return (
            self.work.optimisations * w["optimisation"]
            + self.task_space_checks * w["task_space_check"]
            + self.graphs_expanded * w["graph_expanded"]
            + self.work.ik_calls * w["ik_call"]
            + self.arm_path_checks * w["arm_path_check"]
            + self.transits * w["transit"]
        )

    def reject(self, rejection: Rejection, label: str | Callable[[], str]) -> None:
        """Count a rejection; keep the closest miss of each kind (the first among equals) as its example, with the
        sequence's `label` (made only then when given as a function: the search prunes thousands)."""
        self.rejections[rejection.kind] += 1
        kept = self.examples.get(rejection.kind)
        if kept is None or rejection.excess < kept[0]:
            words = label() if callable(label) else label
            self.examples[rejection.kind] = (rejection.excess, words, rejection.why)
            self.advice[rejection.kind] = rejection.advice
            self.example_bodies[rejection.kind] = frozenset(rejection.bodies)
        self.met.update(rejection.bodies & self.watch)
        if rejection.bodies:  # how deep the least a body was met with these (`clutter.tool_path`)
            names = frozenset(rejection.bodies)  # (some checks pass a set)
            self.named[names] = min(rejection.excess, self.named.get(names, math.inf))


WORK_WEIGHTS = {
    "optimisation": 1.0,
    "task_space_check": 0.02,
    "graph_expanded": 0.05,
    "ik_call": 0.15,
    "arm_path_check": 10.0,
    "transit": 6.0,
}
"""The weight of each counted step in `SearchStats.work_done`, in task-space optimisations (NLopt runs, about 10 ms
of CPU each): fitted by least squares (non-negative) to the CPU seconds of 56 searches of the physical bench's
blocked tasks (`bench/plan/bench_blocked.py`) and rounded: a graph expanded (its successors made, their reach checked)
costs about 0.5 ms, a task-space check's own work (closed form, before any optimisation) 0.2 ms, an IK call
1.5 ms, a sequence's straight arm moves (contact chains) about 100 ms and an OMPL transit about 60 ms. A budget is
a count; the timeout guards the clock."""


def kinds(stats: SearchStats) -> list[str]:
    """The kinds of rejection met, the furthest stage first (the decisive cause), then the most frequent."""
    return sorted(stats.rejections, key=lambda k: (-Kind(k).stage, -stats.rejections[k], k))


def summary(stats: SearchStats) -> str:
    """One line: how many sequences each kind of rejection took."""
    return ", ".join(f"{stats.rejections[kind]} {Kind(kind).words}" for kind in kinds(stats))


def closest(stats: SearchStats, kind: str, said: bool = False) -> list[str]:
    """The closest miss of one kind, as indented lines: the steps of its sequence, one a line, then why and what
    to change where its check says (unless `said` first already)."""
    _, label, why = stats.examples[kind]
    steps = label.split(" -> ")
    lines = [f"  {stats.rejections[kind]} {Kind(kind).words}; the closest:"]
    lines += [f"    {'-> ' if k else ''}{step}" for k, step in enumerate(steps)]
    if said:
        lines.append("    why: as said first")
    else:
        lines.append(f"    why: {why}")
        if stats.advice.get(kind):
            lines.append(f"    {stats.advice[kind]}")
    return lines


def decisive(stats: SearchStats) -> str | None:
    """The kind of rejection that decides a "no plan", when its check says what to change (the grip): the one
    that leads (`kinds`: it got furthest, and most often among those that got as far). None otherwise."""
    leading = kinds(stats)
    if not leading or not stats.advice.get(leading[0]) or leading[0] not in stats.examples:
        return None
    return leading[0]


def accounting(stats: SearchStats) -> str:
    """Where every sequence tried went; the parts add up to the total."""
    checked = stats.task_space_checks
    parts = [f"{stats.pruned} with the hand out of reach at once", f"{checked} checked in task space"]
    if stats.excluded:
        parts.insert(1, f"{stats.excluded} repeating a step that failed in execution")
    if stats.cut_by_bound:
        parts.insert(1, f"{stats.cut_by_bound} needing more graphs than max_depth allows")
    if stats.joint_space_checks:
        parts.append(f"{stats.joint_space_checks} of them also in joint space")
    if stats.rejections["excluded"] > stats.excluded:
        parts.append(f"{stats.rejections['excluded'] - stats.excluded} feasible but excluded as repeats")
    if stats.arm_path_checks:
        parts.append(f"{stats.arm_path_checks} of those also for the arm's straight moves into and out of contacts")
    if stats.transit_checks:
        parts.append(f"{stats.transit_checks} of those also for the arm's transits between contacts")
    return (
        f"{stats.sequences} sequences tried: {stats.passed_over} only lead to others (their last step moves "
        f"no goal body, or the bound says that more steps must follow), " + ", ".join(parts)
    )


def infeasible_reason(problem: Problem, stats: SearchStats, bound: Bound) -> str:
    """A one-line summary (what scripts print), then an indented line per kind with its closest miss.

    When the bound cut every sequence at the start, the summary says why with numbers instead. When the kind
    that leads says what to change (`decisive`: the grip), the summary is its closest miss's why, and what to
    change follows on a line of its own before the counts. The
    `--max-depth` hint, when the bound says a longer sequence could reach the goal, is a line of its own.
    """
    head = f"no sequence of at most {problem.max_depth} graphs reaches the goal"
    if stats.cut_at_start:
        needed = "" if math.isinf(stats.shortest_cut) else f"the goal needs at least {stats.shortest_cut:g} graphs"
        detail = ": ".join(part for part in (bound.explain(), needed) if part)
        lines = [f"{head}: {detail}" if detail else head]
    elif (lead := decisive(stats)) is not None:  # its why, then what to change, before the counts
        lines = [f"{head}: {stats.examples[lead][2]}", f"  {stats.advice[lead]}", f"  rejected: {summary(stats)}"]
        for kind in kinds(stats):
            lines += closest(stats, kind, said=kind == lead)
        lines.append(f"  ({accounting(stats)})")
    else:
        detail = summary(stats)
        lines = [f"{head}: {detail}" if detail else head]
        for kind in kinds(stats):
            lines += closest(stats, kind)
        lines.append(f"  ({accounting(stats)})")
    hint = depth_hint(problem, stats)
    if hint:
        lines.append(hint)
    return "\n".join(lines)


def depth_hint(problem: Problem, stats: SearchStats) -> str:
    """The `--max-depth` to try, only when the bound says that a longer sequence could reach the goal."""
    shortest = stats.shortest_cut
    if math.isinf(shortest) or shortest > MAX_DEPTH_HINT:
        return ""
    # A joint's limit or the table's edge stays where it is however long the sequence: no hint then.
    if stats.rejections and not set(stats.rejections) - {"table"}:
        return ""
    if stats.cut_at_start:
        return f"a longer sequence may reach the goal (try --max-depth {shortest:g})"
    return (
        f"a longer sequence may reach the goal: {stats.cut_by_bound} sequences need more than {problem.max_depth} "
        f"graphs, the shortest at least {shortest:g} (try --max-depth {shortest:g})"
    )


MAX_DEPTH_HINT = 12
"""No deeper search is suggested past this depth (the CLI's --max-depth limit)."""


def timeout_reason(problem: Problem, stats: SearchStats, budget: float | None = None) -> str:
    """Why the search timed out (or spent its work `budget`): how far it got, what it spent, its closest miss, and
    what to raise."""
    done = f"every sequence that could reach the goal in fewer than {stats.level:g} graphs was checked"
    closest, why = closest_miss(stats)
    spent = budget is not None and stats.work_done() > budget
    within = (
        f"its work budget of {budget:g} units (its share of the timeout's {problem.timeout:g} s, counted in work)"
        if spent
        else f"the timeout of {problem.timeout:g} s"
    )
    ran_out = "its budget ran out" if spent else "the time ran out"
    return (
        f"no plan within {within}: {ran_out} while checking sequences of "
        f"{stats.level:g} graphs or more ({done}; {stats.sequences} sequences made, "
        f"{stats.task_space_checks} checked in task space, {stats.work.optimisations} optimisations, "
        f"{stats.work.ik_calls} IK calls)"
        + (f"; the closest miss: {closest}" if closest else "")
        + "\n"
        + (f"why the closest miss failed: {why}\n" if why else "")
        + (f"{advice}\n" if (advice := closest_advice(stats)) else "")
        + (f"rejected so far: {summary(stats)}\n" if stats.rejections else "")
        + "raise `timeout` in the task's search block or pass --timeout"
    )


def closest_miss(stats: SearchStats) -> tuple[str, str]:
    """The rejection that got farthest towards a plan (the latest stage, then the smallest excess): its
    sequence and why it failed, in words; empty when nothing was rejected."""
    if not stats.examples:
        return "", ""
    _, label, why = stats.examples[_closest_kind(stats)]
    return label, why


def closest_bodies(stats: SearchStats) -> frozenset[str]:
    """The bodies `closest_miss`'s rejection found in the way (`Rejection.bodies`; none when no example)."""
    return stats.example_bodies.get(_closest_kind(stats), frozenset()) if stats.examples else frozenset()


def closest_advice(stats: SearchStats) -> str:
    """What to change for `closest_miss` to pass, where its check says (the grip); else empty."""
    return stats.advice.get(_closest_kind(stats), "") if stats.examples else ""


def _closest_kind(stats: SearchStats) -> str:
    """The kind whose example got farthest towards a plan: the latest stage, then the smallest excess."""
    return min(stats.examples, key=lambda k: (-Kind(k).stage, stats.examples[k][0], k))


class Progress:
    """A one-line progress report on stderr, on a terminal only, at most ten times a second."""

    def __init__(self, enabled: bool) -> None:
        self.enabled = enabled
        self._next = 0.0
        self._shown = False

    def show(self, stats: SearchStats) -> None:
        if not self.enabled or time.perf_counter() < self._next:
            return
        self._next = time.perf_counter() + 0.1
        self._shown = True
        sys.stderr.write(
            f"\rsearching: depth {stats.depth_reached}, {stats.sequences} sequences, "
            f"{stats.task_space_checks} task-space checks, {stats.joint_space_checks} IK checks "
        )
        sys.stderr.flush()

    def done(self) -> None:
        if self._shown:
            sys.stderr.write("\r\033[K")
            sys.stderr.flush()


def add_stats(total: SearchStats, part: SearchStats, since: SearchStats | None = None) -> None:
    """Add the counters of another search (`part`) to `total`: sequences, checks, rejections, times (what
    describes where one search ended, its level and cut sequences, stays `total`'s). `since`: `part`'s counters
    as they stood when `total` last had them added (a search gone on from where its budget stopped it,
    `search(paused=)`): only what it counted since is added."""
    kept = {"level", "depth_reached", "shortest_cut", "cut_at_start", "examples"}
    for f in fields(SearchStats):
        if f.name in kept:
            continue
        mine, theirs = getattr(total, f.name), getattr(part, f.name)
        if isinstance(mine, (int, float)):
            setattr(total, f.name, mine + theirs - (getattr(since, f.name) if since is not None else 0))
    for f in fields(total.work):
        before = getattr(since.work, f.name) if since is not None else 0
        setattr(total.work, f.name, getattr(total.work, f.name) + getattr(part.work, f.name) - before)
    total.rejections.update(part.rejections - since.rejections if since is not None else part.rejections)
