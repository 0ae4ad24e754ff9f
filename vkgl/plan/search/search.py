"""Algorithm 1 of the paper, best first: graph sequences in the order of depth plus a lower bound of the graphs
still needed (`vkgl.plan.search.bound`), the first feasible sequence returned.

Sequences are extended one transition at a time (`successors` in
`vkgl.plan.graphs.graph`), queued (a heap) by depth plus bound, ties in the
order breadth-first search generates them (the indices of their actions among
their parents' successors), and checked when they leave the queue. The bound
never overestimates, so the first feasible sequence checked is a shortest one,
and the very one the paper's breadth-first search finds first; a sequence
whose depth plus bound passes `max_depth` is never queued. What never loses a
solution besides:

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

Each sequence carries what its prefix knows (`Sequence`: graphs, variables,
poses with the values at zero), so no work is repeated along a branch.
"""

from __future__ import annotations

import heapq
import itertools
import math
import sys
import time
from collections import Counter
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace

import numpy as np

from vkgl.plan.arm.paths import ArmPathPlanner, StraightPaths
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.graph import successors
from vkgl.plan.graphs.rollout import Sequence, extend, rollout, start_sequence
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.result.plan import PlanStep, plan_step
from vkgl.plan.search.bound import Bound
from vkgl.plan.search.exclusions import excluded, repeated_failure
from vkgl.plan.task_space.contacts import other_contacts
from vkgl.plan.task_space.feasible import Counters, TaskSolution, goal_holds, task_space, task_space_alternatives
from vkgl.plan.task_space.joint_space import JointSolution, joint_space
from vkgl.plan.task_space.workspace import unreachable


@dataclass
class SearchStats:
    """Counters of one search (reported in the plan and by bench/bench_solve.py)."""

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

    def reject(self, rejection: Rejection, label: str) -> None:
        """Count a rejection; keep the closest miss of each kind (the first among equals) as its example."""
        self.rejections[rejection.kind] += 1
        kept = self.examples.get(rejection.kind)
        if kept is None or rejection.excess < kept[0]:
            self.examples[rejection.kind] = (rejection.excess, label, rejection.why)


@dataclass
class SearchResult:
    """What the search ended with: `status` solved/infeasible/timeout, and for solved the sequence and its solutions."""

    status: str
    reason: str
    stats: SearchStats
    sequence: Sequence | None = None
    task: TaskSolution | None = None
    joints: JointSolution | None = None
    steps: tuple[PlanStep, ...] = ()
    paths: StraightPaths[PlanStep] | None = None  # a candidate's straight moves, its transits still to plan


def search(problem: Problem, *, deadline: float, progress: bool = False) -> SearchResult:
    """Best-first search for the shortest feasible graph sequence of `problem` (at most `max_depth` graphs).

    Sequences are checked in the order of their depth plus `Bound` (an admissible lower bound of the graphs
    still needed, `vkgl.plan.search.bound`), ties broken by the breadth-first order of their actions, and
    those whose depth plus bound passes `max_depth` are never made: the plan is the one breadth-first search
    returns, found sooner.
    """
    stats = SearchStats()
    reporter = _Progress(progress)
    geometry = GeometryCheck(problem)
    checks = _Checks(geometry, ArmPathPlanner(problem, geometry))
    bound = Bound(problem)
    root = start_sequence(problem)
    if goal_holds(problem, root.zero_poses):
        found = _unless_excluded(problem, _check(problem, root, stats, deadline, checks), stats)
        found = _with_transits(problem, found, stats, deadline, checks.arm_paths)
        return found or SearchResult("infeasible", "", stats)
    frontier: list[tuple[float, tuple[int, ...], Sequence]] = []
    _push(problem, frontier, root, (), bound(root), stats)
    try:
        while frontier:
            stats.level, path, seq = heapq.heappop(frontier)
            if time.perf_counter() > deadline:
                return SearchResult("timeout", _timeout_reason(problem, stats), stats)
            if seq.actions and stats.level == seq.depth and _moves_goal_body(problem, seq):
                found = _unless_excluded(problem, _check(problem, seq, stats, deadline, checks), stats)
                found = _with_transits(problem, found, stats, deadline, checks.arm_paths)
                if found is not None:
                    return found
            elif seq.actions:
                stats.passed_over += 1
            if seq.depth >= problem.max_depth:
                continue
            stats.graphs_expanded += 1
            stats.depth_reached = max(stats.depth_reached, seq.depth + 1)
            reporter.show(stats)
            for index, action in enumerate(successors(problem, seq.graphs[-1], seq.last)):
                child, hand = extend(problem, seq, action)
                stats.sequences += 1
                if hand is not None and (rejection := unreachable(problem, hand)) is not None:
                    stats.pruned += 1
                    stats.reject(rejection, action.label(problem))
                    continue
                if (rejection := repeated_failure(problem, seq, child, action)) is not None:
                    stats.excluded += 1  # with everything that would follow it
                    stats.reject(rejection, action.label(problem))
                    continue
                _push(problem, frontier, child, path + (index,), bound(child), stats)
    finally:
        reporter.done()
    if time.perf_counter() > deadline:
        return SearchResult("timeout", _timeout_reason(problem, stats), stats)
    return SearchResult("infeasible", _infeasible_reason(problem, stats, bound), stats)


def _push(
    problem: Problem,
    frontier: list[tuple[float, tuple[int, ...], Sequence]],
    seq: Sequence,
    path: tuple[int, ...],
    needed: float,
    stats: SearchStats,
) -> None:
    """Queue `seq` (reached by the successor indices `path`) unless it and the `needed` graphs pass max_depth."""
    total = seq.depth + needed
    if total > problem.max_depth:
        stats.cut_by_bound += bool(seq.actions)  # G0 is no sequence tried: the reason says so instead
        stats.cut_at_start = not seq.actions
        stats.shortest_cut = min(stats.shortest_cut, total)
        return
    heapq.heappush(frontier, (total, path, seq))


def _moves_goal_body(problem: Problem, seq: Sequence) -> bool:
    """Whether the last mode of `seq` moves a body that a goal names, or its last action sets one down that
    the mode before carried."""
    mode = seq.depth - 1
    goal_bodies = {g.body for g in problem.goals}
    if any(m == mode - 1 and e.body in goal_bodies for m, e in seq.carries):
        return True
    return any(m == mode and e.body in goal_bodies for m, e in seq.variables)


def _unless_excluded(problem: Problem, found: SearchResult | None, stats: SearchStats) -> SearchResult | None:
    """`found`, unless it repeats what a re-solve must avoid (`problem.avoid`): then None, counted as "excluded"."""
    if found is None or found.sequence is None or found.task is None:
        return found
    rejection = excluded(problem, found.sequence.actions, found.task.traces)
    if rejection is None:
        return found
    stats.reject(rejection, " -> ".join(a.label(problem) for a in found.sequence.actions) or "G0")
    return None


@dataclass(frozen=True)
class _Checks:
    """The search's checks that keep state for a whole problem (collision world, arm path planner)."""

    geometry: GeometryCheck
    arm_paths: ArmPathPlanner


def _check(
    problem: Problem, seq: Sequence, stats: SearchStats, deadline: float, checks: _Checks
) -> SearchResult | None:
    """Task space, collision geometry, joint space, the arm's geometry and straight moves; a SearchResult (its
    transits still to plan) when all hold. Motion values whose bodies pass through one another are replaced by
    others that pass clear (`_clear_of_each_other`), each tried through the arm's checks in turn."""
    label = " -> ".join(a.label(problem) for a in seq.actions) or "G0"
    if seq.variables or seq.actions:
        stats.task_space_checks += 1
        solution = task_space(problem, seq, deadline, stats.work)
    else:
        solution = TaskSolution(np.zeros(0), rollout(problem, seq, np.zeros(0)))
    if isinstance(solution, Rejection):
        stats.reject(solution, label)
        return None
    stats.geometry_checks += 1
    named = solution.sequence or seq  # with the families' members the optimiser chose named
    clash = checks.geometry.bodies(named.graphs, solution.traces)
    candidates = (
        iter([(named, solution)])
        if clash is None
        else ((named, s) for s in _clear_of_each_other(problem, named, solution, stats, deadline, checks.geometry))
    )
    if seq.offsets:  # the contacts elsewhere along their faces, when the arm cannot approach these
        others = _at_other_contacts(problem, seq, stats, deadline, checks.geometry)
        candidates = itertools.chain(candidates, _if_unapproachable(lambda: first, others))
    first: Rejection | None = None
    reached: set[str] = set()  # the stages any candidate got to: each sequence counts once in each
    try:
        for named, candidate in candidates:
            for hold in _grasp_turns(named, candidate):
                found = _arm_checks(problem, named, hold, stats, deadline, checks, reached)
                if not isinstance(found, Rejection):
                    return found
                first = first or found
    finally:
        stats.joint_space_checks += int("joint space" in reached)
        stats.arm_path_checks += int("arm paths" in reached)
    # one rejection per sequence, so that the counts add up: the arm's, else the bodies'
    rejection = first or clash
    assert rejection is not None
    stats.reject(rejection, label)
    return None


def _grasp_turns(seq: Sequence, solution: TaskSolution) -> Iterator[TaskSolution]:
    """`solution`, then, when it carries a body, the same with the hand turned half a turn about its axis while
    it carries: a parallel gripper's two fingers hold the body the same way, and the arm may reach the place
    only so (its last wrist joint at a limit)."""
    yield solution
    if seq.carries:
        turned = [replace(t, hand=[h @ HALF_TURN for h in t.hand]) if t.carried else t for t in solution.traces]
        yield replace(solution, traces=turned)


HALF_TURN = np.diag([-1.0, -1.0, 1.0, 1.0])
"""The effector frame turned half a turn about its z axis (the hand's axis): the fingers' y axis reversed."""


def _arm_checks(
    problem: Problem,
    seq: Sequence,
    solution: TaskSolution,
    stats: SearchStats,
    deadline: float,
    checks: _Checks,
    reached: set[str],
) -> SearchResult | Rejection:
    """Joint space, the arm's geometry and its straight moves for `solution`'s motion values (`reached`: the
    stages it got to are added)."""
    geometry = checks.geometry
    reached.add("joint space")
    joints = joint_space(problem, solution, deadline, stats.work)
    if isinstance(joints, Rejection):
        return joints
    clash = geometry.arm(seq.graphs, solution.traces, joints.q_start, joints.q_end)
    if clash is not None and any(trace.yaw_free for trace in solution.traces):
        # the hand at the yaw IK chose may stand across a handle into its cabinet; along the face it may not
        pinned = joint_space(problem, solution, deadline, stats.work, pin_yaw=True)
        if not isinstance(pinned, Rejection):
            again = geometry.arm(seq.graphs, solution.traces, pinned.q_start, pinned.q_end)
            if again is None:
                joints, clash = pinned, None
    if clash is not None:
        return clash
    reached.add("arm paths")
    paths = _straight_paths(problem, seq, solution, joints, stats, checks.arm_paths)
    if isinstance(paths, Rejection):
        return paths
    return SearchResult("solved", "", stats, seq, solution, joints, tuple(paths.steps), paths)


def _clear_of_each_other(
    problem: Problem, seq: Sequence, found: TaskSolution, stats: SearchStats, deadline: float, geometry: GeometryCheck
) -> Iterator[TaskSolution]:
    """Other motion values of `seq` whose bodies pass clear of one another (a body in the way moved farther
    aside first), in turn: `found`'s bodies collide."""
    for other in task_space_alternatives(problem, seq, found, deadline, stats.work):
        stats.geometry_checks += 1
        if geometry.bodies(seq.graphs, other.traces) is None:
            yield other


def _if_unapproachable(
    rejection: Callable[[], Rejection | None], candidates: Iterator[tuple[Sequence, TaskSolution]]
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """`candidates`, only while the first rejection (`rejection()`, read when each is asked for) is an approach:
    moving a contact along its face changes where the arm comes in, and little else (a turn's pivot moves by
    millimetres); trying other contacts after any failure doubled the time of deep searches."""
    while (found := rejection()) is not None and found.kind is Kind.APPROACH:
        try:
            yield next(candidates)
        except StopIteration:
            return


def _at_other_contacts(
    problem: Problem, seq: Sequence, stats: SearchStats, deadline: float, geometry: GeometryCheck
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """Solutions of `seq` with its families' contacts pinned elsewhere (`other_contacts`) whose bodies pass clear
    of one another, each with its named sequence."""
    for other in other_contacts(problem, seq, deadline, stats.work):
        named = other.sequence or seq
        stats.geometry_checks += 1
        if geometry.bodies(named.graphs, other.traces) is None:
            yield named, other


def _straight_paths(
    problem: Problem,
    seq: Sequence,
    solution: TaskSolution,
    joints: JointSolution,
    stats: SearchStats,
    planner: ArmPathPlanner,
) -> StraightPaths[PlanStep] | Rejection:
    """The sequence's plan steps with the arm's straight moves around its contacts (the first stage of the
    arm's paths), or why one cannot be planned."""
    steps = [
        plan_step(problem, action, solution.traces[k], joints.q_start[k], joints.q_end[k])
        for k, action in enumerate(seq.actions, start=1)
    ]
    planned = planner.straight(steps, problem.arm_start)
    stats.arm_path_time = planner.seconds
    return planned


def _with_transits(
    problem: Problem, found: SearchResult | None, stats: SearchStats, deadline: float, planner: ArmPathPlanner
) -> SearchResult | None:
    """`found` with its transits planned (the arm's paths' second stage, after the search found a candidate),
    or None when one cannot be: counted as a "transit" rejection, and the search goes on."""
    if found is None or found.paths is None:
        return found
    stats.transit_checks += 1
    planned = planner.transits(found.paths, deadline=deadline)
    stats.transits, stats.transit_time = planner.transit_count, planner.transit_seconds
    if isinstance(planned, Rejection):
        assert found.sequence is not None
        stats.reject(planned, " -> ".join(a.label(problem) for a in found.sequence.actions))
        return None
    return replace(found, steps=tuple(planned), paths=None)


def _kinds(stats: SearchStats) -> list[str]:
    """The kinds of rejection met, the furthest stage first (the decisive cause), then the most frequent."""
    return sorted(stats.rejections, key=lambda k: (-Kind(k).stage, -stats.rejections[k], k))


def _summary(stats: SearchStats) -> str:
    """One line: how many sequences each kind of rejection took."""
    return ", ".join(f"{stats.rejections[kind]} {Kind(kind).words}" for kind in _kinds(stats))


def _closest(stats: SearchStats, kind: str) -> list[str]:
    """The closest miss of one kind, as indented lines: the steps of its sequence, one a line, then why."""
    _, label, why = stats.examples[kind]
    steps = label.split(" -> ")
    lines = [f"  {stats.rejections[kind]} {Kind(kind).words}; the closest:"]
    lines += [f"    {'-> ' if k else ''}{step}" for k, step in enumerate(steps)]
    lines.append(f"    why: {why}")
    return lines


def _accounting(stats: SearchStats) -> str:
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


def _infeasible_reason(problem: Problem, stats: SearchStats, bound: Bound) -> str:
    """A one-line summary (what scripts print), then an indented line per kind with its closest miss.

    When the bound cut every sequence at the start, the summary says why with numbers instead. The
    `--max-depth` hint, when the bound says a longer sequence could reach the goal, is a line of its own.
    """
    head = f"no sequence of at most {problem.max_depth} graphs reaches the goal"
    if stats.cut_at_start:
        needed = "" if math.isinf(stats.shortest_cut) else f"the goal needs at least {stats.shortest_cut:g} graphs"
        detail = ": ".join(part for part in (bound.explain(), needed) if part)
        lines = [f"{head}: {detail}" if detail else head]
    else:
        detail = _summary(stats)
        lines = [f"{head}: {detail}" if detail else head]
        for kind in _kinds(stats):
            lines += _closest(stats, kind)
        lines.append(f"  ({_accounting(stats)})")
    hint = _depth_hint(problem, stats)
    if hint:
        lines.append(hint)
    return "\n".join(lines)


def _depth_hint(problem: Problem, stats: SearchStats) -> str:
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


def _timeout_reason(problem: Problem, stats: SearchStats) -> str:
    done = f"every sequence that could reach the goal in fewer than {stats.level:g} graphs was checked"
    closest = _closest_miss(stats)
    return (
        f"no plan within the timeout of {problem.timeout:g} s: the time ran out while checking sequences of "
        f"{stats.level:g} graphs or more ({done}; {stats.sequences} sequences made, "
        f"{stats.task_space_checks} checked in task space, {stats.work.optimisations} optimisations, "
        f"{stats.work.ik_calls} IK calls)" + (f"; the closest miss: {closest}" if closest else "") + "\n"
        "raise `timeout` in the task's search block or pass --timeout"
    )


def _closest_miss(stats: SearchStats) -> str:
    """The rejection that got farthest towards a plan (the latest stage, then the smallest excess), in words."""
    if not stats.examples:
        return ""
    kind = min(stats.examples, key=lambda k: (-Kind(k).stage, stats.examples[k][0], k))
    return stats.examples[kind][1]


class _Progress:
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
