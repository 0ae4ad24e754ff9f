"""The check of one graph sequence the search took from its queue (`vkgl.plan.search.search`): task space,
the bodies' collision geometry, joint space, the arm's geometry, its straight moves and transits, with the
candidates tried when the first motion values fail (bodies farther aside, contacts elsewhere along their faces,
a tool set down where it was picked up, the arm's bystanders moved aside, raised contacts).

`check` keeps what the problem's checks share (`Checks`: the collision world, the arm path planner, the bodies
the arm ran into, the last motions that failed alone) and returns a `SearchResult` when every stage holds."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace

import numpy as np

from vkgl.plan.arm.paths import ArmPathPlanner, StraightPaths
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.rollout import Sequence, rollout
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.result.plan import PlanStep, plan_step
from vkgl.plan.search.arm_aside import arm_hits, moved_aside
from vkgl.plan.search.exclusions import excluded
from vkgl.plan.search.last_motion import LastMotion
from vkgl.plan.search.put_back import put_back
from vkgl.plan.search.stats import SearchStats
from vkgl.plan.task_space.contacts import other_contacts
from vkgl.plan.task_space.feasible import TaskSolution, task_space, task_space_alternatives
from vkgl.plan.task_space.idle import idle_contact
from vkgl.plan.task_space.joint_space import JointSolution, joint_space
from vkgl.plan.task_space.raised_contacts import after_arm


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
class Checks:
    """The search's checks that keep state for a whole problem (collision world, arm path planner)."""

    geometry: GeometryCheck
    arm_paths: ArmPathPlanner
    hits: set[str] = field(default_factory=set)  # bodies the arm's checks found in its way (`arm_aside`)
    last_motion: LastMotion = field(default_factory=LastMotion)  # last motions that failed alone, whatever came before


def check(problem: Problem, seq: Sequence, stats: SearchStats, deadline: float, checks: Checks) -> SearchResult | None:
    """Task space, collision geometry, joint space, the arm's geometry, straight moves and transits; a
    SearchResult when all hold. Motion values whose bodies pass through one another are replaced by others that
    pass clear (`_clear_of_each_other`), each tried through the arm's checks in turn; when a candidate's transits
    cannot be planned (the hand left beside the target by the push that cleared a body in its way), the next
    one is tried, up to `TRANSIT_TRIES`. A candidate with a contact that moves nothing is passed over
    (`vkgl.plan.task_space.idle`): the sequence without that contact, checked before, puts every body where it
    does; a body in the way moved aside by that contact comes in another candidate."""
    label = " -> ".join(a.label(problem) for a in seq.actions) or "G0"
    if (known := checks.last_motion.known(problem, seq)) is not None:
        stats.last_motion_known += 1
        stats.reject(known, label)
        return None
    if seq.variables or seq.actions:
        stats.task_space_checks += 1
        solution = task_space(problem, seq, deadline, stats.work)
    else:
        solution = TaskSolution(np.zeros(0), rollout(problem, seq, np.zeros(0)))
    if isinstance(solution, Rejection):
        checks.last_motion.remember(problem, seq, solution)
        stats.reject(solution, label)
        return None
    stats.geometry_checks += 1
    named = solution.sequence or seq  # with the families' members the optimiser chose named
    clash = checks.geometry.bodies(named.graphs, solution.traces)
    if clash is not None and (back := put_back(problem, named, solution, clash, checks.geometry)) is not None:
        (named, solution), clash = back, None  # a tool let go of in the way set down where it was picked up
    clashes: list[Rejection] = []  # those of the contacts elsewhere along their faces, if tried
    clear = ((named, s) for s in _clear_of_each_other(problem, named, solution, stats, deadline, checks.geometry))
    # bodies clear of each other: the solution, then, only when its transits fail, the bodies in the way farther aside
    candidates = (
        itertools.chain([(named, solution)], _while(lambda: last is not None, clear)) if clash is None else clear
    )
    if seq.offsets:  # the contacts elsewhere along their faces, when the arm cannot approach these
        others = _at_other_contacts(problem, seq, stats, deadline, checks.geometry, clashes)
        failed = lambda: _contact_failed(problem, first, clash)  # noqa: E731 (read when each is asked for)
        candidates = itertools.chain(candidates, _while(failed, others))
    idle_seen: list[tuple[Sequence, TaskSolution]] = []  # the first idle candidate, for `arm_aside`
    candidates = itertools.chain(candidates, _aside(problem, idle_seen, checks))
    rejected: list[tuple[Sequence, TaskSolution]] = []  # those the arm's checks rejected: raised contacts after all
    candidates = itertools.chain(candidates, after_arm(problem, rejected, checks.geometry.bodies))
    first: Rejection | None = None
    idle: Rejection | None = None  # a candidate with a contact that moves nothing (`idle_contact`), if any
    reached: set[str] = set()  # the stages any candidate got to: each sequence counts once in each
    tries = 0  # candidates that passed the arm's checks, then failed their transits
    last: Rejection | None = None  # the last of those rejections
    try:
        for named, candidate in candidates:
            moves_nothing = idle_contact(problem, named, candidate.values)
            if moves_nothing is not None:  # the same without that contact puts every body where this one does
                idle = idle or moves_nothing
                idle_seen.append((named, candidate))
                continue
            for hold in _grasp_turns(named, candidate):
                found = _arm_checks(problem, named, hold, stats, deadline, checks, reached)
                if not isinstance(found, Rejection):
                    kept = _unless_excluded(problem, found, stats)
                    if kept is None:
                        return None
                    stats.transit_checks += int(tries == 0 and kept.paths is not None)
                    done = _with_transits(kept, stats, deadline, checks)
                    tries += 1
                    if isinstance(done, Rejection) and tries < TRANSIT_TRIES:
                        last = done
                        continue
                    if isinstance(done, Rejection):
                        stats.reject(done, label)
                        return None
                    return done
                first = first or found
                checks.hits.update(arm_hits(problem, found))
                rejected.append((named, candidate))
    finally:
        stats.joint_space_checks += int("joint space" in reached)
        stats.arm_path_checks += int("arm paths" in reached)
    if last is not None:  # one rejection per sequence: the last candidate's transits
        stats.reject(last, label)
        return None
    # one rejection per sequence, so that the counts add up: the arm's, else the bodies' (with the contacts
    # moved, when that was tried: what is left once the tool stands clear)
    rejection = first or (clashes[-1] if clashes else clash) or idle
    assert rejection is not None
    if first is None and rejection is not idle:  # the bodies' geometry, not the arm's: the same after any prefix
        checks.last_motion.remember(problem, seq, rejection)
    stats.reject(rejection, label)
    return None


def _aside(
    problem: Problem, idle_seen: list[tuple[Sequence, TaskSolution]], checks: Checks
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """The first idle candidate's motions on bodies the arm ran into, moved aside (`arm_aside.moved_aside`): read
    when the other candidates are spent."""
    if idle_seen and checks.hits:
        named, candidate = idle_seen[0]
        for other in moved_aside(problem, named, candidate, checks.hits, checks.geometry):
            yield named, other


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
    checks: Checks,
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


def _while(
    failed: Callable[[], bool], candidates: Iterator[tuple[Sequence, TaskSolution]]
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """`candidates`, only while `failed()` (read when each is asked for): other contacts only while the contact
    is what failed (the arm cannot approach it, or a tool at it stands in a body; moving a contact along its face
    changes where the arm and the tool come in, and little else: trying other contacts after any failure doubled
    the time of deep searches); bodies moved farther aside only while the transits fail."""
    while failed():
        try:
            yield next(candidates)
        except StopIteration:
            return


def _at_other_contacts(
    problem: Problem,
    seq: Sequence,
    stats: SearchStats,
    deadline: float,
    geometry: GeometryCheck,
    clashes: list[Rejection],
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """Solutions of `seq` with its families' contacts pinned elsewhere (`other_contacts`) whose bodies pass clear
    of one another (with the bodies in the way cleared, when they are not), each with its named sequence; the
    bodies' clash of each one found is appended to `clashes`."""
    for other in other_contacts(problem, seq, deadline, stats.work):
        named = other.sequence or seq
        stats.geometry_checks += 1
        clash = geometry.bodies(named.graphs, other.traces)
        if clash is None:
            yield named, other
        else:
            clashes.append(clash)  # a body in the way may still be cleared with the contacts moved
            yield from ((named, s) for s in _clear_of_each_other(problem, named, other, stats, deadline, geometry))


def _contact_failed(problem: Problem, first: Rejection | None, clash: Rejection | None) -> bool:
    """Whether the contacts are what failed: the arm's first rejection is an approach, or no candidate got to the
    arm and the bodies' clash is a tool placed in a body (`Rejection.between`: at its contact it stands in a body
    beside the one it acts on; a contact elsewhere along the face may stand clear of it). A tool swept through a
    body during a motion is not: with those too, two blocked tasks of the physical bench (gen1_001, gen1_013)
    checked 12 and 42 % fewer sequences in 10 s of CPU than without other contacts for tools; as it is, 4 and 8 %."""
    if first is not None:
        return first.kind is Kind.APPROACH
    tools = {e.tool for e in problem.effectors if e.tool is not None}
    return clash is not None and bool(tools.intersection(clash.between))


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


TRANSIT_TRIES = 3
"""Candidates of one sequence whose transits are planned before the sequence is given up (each is one OMPL run
or more): the first, and two with the bodies in the way moved farther aside."""


def _with_transits(
    found: SearchResult | None, stats: SearchStats, deadline: float, checks: Checks
) -> SearchResult | Rejection | None:
    """`found` with its transits planned (the arm's paths' second stage, after the search found a candidate),
    or the rejection when one cannot be (`check` counts it once per sequence, as a "transit" rejection)."""
    if found is None or found.paths is None:
        return found
    planner = checks.arm_paths
    planned = planner.transits(found.paths, deadline=deadline)
    stats.transits, stats.transit_time = planner.transit_count, planner.transit_seconds
    if isinstance(planned, Rejection):
        return planned
    return replace(found, steps=tuple(planned), paths=None)
