"""Is a graph sequence feasible? Task space first (NLopt over the motion values), then joint space (IK).

Task space (paper §2.3, step 1): the variables are the motion values of the
sequence (>= 0, one per engaged prismatic/revolute affordance and mode); the
body poses are the graph edges composed as matrix products
(`vkgl.plan.graphs.rollout`); the goal must hold within its tolerance; the hand must
stay inside the arm's reachable workspace (the radial interval at its height,
computed once from the URDF by `Arm.reach`) at every sample along every
motion; bodies that lie on the table stay over it; bodies with a physical joint
stay within its limits. Before any optimisation, exact geometric reasoning
rejects what cannot work (`closed_form`) and gives the optimiser its start.
The optimiser is NLopt's SLSQP (gradient-based, finite-difference gradients)
from that start and, when some value is not pinned by the goal, from
deterministic restarts.

Joint space (step 2) is `vkgl.plan.task_space.joint_space`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace

import numpy as np

from vkgl.lang.ir.regions import footprint, overlap_depth
from vkgl.plan.graphs.graph import KGraph
from vkgl.plan.graphs.reuse import Rollouts
from vkgl.plan.graphs.rollout import ModeTrace, Sequence, bounds, materialise, rollout
from vkgl.plan.graphs.tool_faces import slide_band
from vkgl.plan.problem.problem import GoalSpec, Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.arc_offsets import cap_arc_turns, named_offsets, seeds_only
from vkgl.plan.task_space.carry_start import carry_start
from vkgl.plan.task_space.clearing import RESOLUTION, blockers, cleared_values
from vkgl.plan.task_space.closed_form import remembered_closed_form
from vkgl.plan.task_space.constraints.body_limits import _stay_constraints, limit_words
from vkgl.plan.task_space.constraints.values import constraint_values
from vkgl.plan.task_space.law_error import law_margins, uncertain_rejection
from vkgl.plan.task_space.reach.workspace import unreachable
from vkgl.robot.optimise import slsqp
from vkgl.se3 import wrap_angle, yaw_of

TASK_SAMPLES = 5
"""Hand poses checked against the reach along each motion in task space (ends included)."""

JOINT_SAMPLES = 6
"""Hand poses solved by IK along each motion in joint space (ends included; >= 5 as required)."""

RESTARTS = 3
"""Deterministic extra starts of the task-space optimisation when the goal leaves a value free."""

ALTERNATIVE_FRACTIONS = (0.25, 0.5, 1.0)
"""Where in their ranges the motion values start when the search asks the optimiser for other solutions of a
sequence, after the geometric ones (`ASIDE_BEYOND`) failed."""

ASIDE_BEYOND = (0.0, 0.05, 0.1, 0.5, 1.0)
"""A body in the way is moved by the smallest value that clears the later motions' corridors
(`clearing.cleared_values`), then that value plus these fractions of what is left of its range: farther aside,
for when the arm cannot carry the first (`task_space_alternatives`). The corridors are the pushed bodies' and
their tools' footprints, not the hand's, which passes beside a small body wider than it (the Panda's hand is
20 cm across, a cube 6 cm): a crate pushed back 1 cm clear of the cube's corridor before the fingertip slides
the cube past it still meets the hand by a millimetre (gen3_046 of the physical bench). So a little farther
first (a twentieth and a tenth of the rest: 1.5 to 4 cm on the bench's slides), then half and all of it, which
leave the body far from where it lay (a goal body pushed back to make room must come back)."""

FD_STEP = 1e-7
"""Step of the forward-difference gradients (m or rad)."""


@dataclass
class Counters:
    """Work done by the checks of one search: NLopt task-space runs and IK calls."""

    optimisations: int = 0
    ik_calls: int = 0


@dataclass
class TaskSolution:
    """A sequence's motion values that satisfy every task-space constraint, and the rollout they give."""

    values: np.ndarray
    traces: list[ModeTrace]
    free: bool = False  # the goal leaves some value free: other solutions may exist (`task_space_alternatives`)
    sequence: Sequence | None = None  # the sequence with its families' members named (`materialise`), if any
    roomier: np.ndarray | None = None  # the values before `least_room` shortened a move that made room, if it did


# ---------------------------------------------------------------- task space


class _Evaluator:
    """Rollouts of one sequence by motion values, memoised.

    The objective, the constraints and their gradients share them.
    """

    def __init__(self, problem: Problem, seq: Sequence) -> None:
        self.problem, self.seq = problem, seq
        self._memo: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
        self._placed: dict[tuple[str, bytes], list[float]] = {}  # `body_constraints` by body and end pose
        self.rollouts = Rollouts(problem, seq, TASK_SAMPLES)  # the modes a step leaves unchanged are reused
        self.last_x = np.zeros(seq.size)

    def evaluate(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(goal residuals scaled by their tolerances, constraint values <= 0 when satisfied)."""
        key = x.tobytes()
        if not all(map(math.isfinite, x.tolist())):  # SLSQP can step to NaN on a degenerate problem: make it bad
            ok = self.evaluate(np.zeros_like(x))
            return np.full_like(ok[0], 1e6), np.full_like(ok[1], 1.0)
        if key not in self._memo:
            if len(self._memo) > MEMO_KEPT:
                self._memo.clear()
            self._memo[key] = self._compute(x)
        return self._memo[key]

    def _compute(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        traces = self.rollouts.rollout(x)
        if len(self._placed) > PLACED_REMEMBERED:
            self._placed.clear()
        return goal_residuals(self.problem, traces[-1].end), constraint_values(self.problem, traces, self._placed)

    def objective(self, x: np.ndarray, grad: np.ndarray) -> float:
        residual, _ = self.evaluate(x)
        self.last_x = x.copy()
        value = float(residual @ residual)
        if grad.size:
            for i in range(len(x)):
                step = x.copy()
                step[i] += FD_STEP
                r, _ = self.evaluate(step)
                grad[i] = (float(r @ r) - value) / FD_STEP
        return value

    def constraints(self, result: np.ndarray, x: np.ndarray, grad: np.ndarray) -> None:
        _, c = self.evaluate(x)
        result[:] = c
        if grad.size:
            for i in range(len(x)):
                step = x.copy()
                step[i] += FD_STEP
                grad[:, i] = (self.evaluate(step)[1] - c) / FD_STEP


def goal_residuals(problem: Problem, final: dict[str, np.ndarray]) -> np.ndarray:
    """Each goal's position error (per component), yaw error and joint coordinate error, divided by its tolerance;
    for a region goal, how far the footprint passes each edge of the region (0 inside: an inequality)."""
    if len(problem.goals) == 1 and _position_only(problem.goals[0]):  # the usual goal, without the list's steps
        goal = problem.goals[0]
        assert goal.position is not None
        return (final[goal.body][: len(goal.position), 3] - goal.position) / goal.tol_position  # type: ignore[no-any-return]
    out: list[float] = []
    for goal in problem.goals:
        pose = final[goal.body]
        if goal.position is not None:
            out.extend((pose[: len(goal.position), 3] - goal.position) / goal.tol_position)
        if goal.yaw is not None:
            out.append(wrap_angle(yaw_of(pose) - goal.yaw) / goal.tol_yaw)
        if goal.opening is not None:
            out.append((problem.bodies[goal.body].joint_state(pose) - goal.opening) / goal.tol_opening)
        if goal.region is not None:  # an inequality: only the part of the footprint outside an edge counts
            out.extend(np.maximum(goal.region_excess(pose), 0.0) / goal.tol_position)
    return np.asarray(out, dtype=float)


def _position_only(goal: GoalSpec) -> bool:
    """Whether `goal` asks for a position alone (no heading, joint coordinate or region)."""
    return goal.position is not None and goal.yaw is None and goal.opening is None and goal.region is None


def goal_holds(
    problem: Problem,
    final: dict[str, np.ndarray],
    goals: list[GoalSpec] | None = None,
    margins: dict[str, tuple[float, float]] | None = None,
) -> bool:
    """Whether every goal (of the problem, or `goals`) holds at `final` within its tolerance; `margins` (m, rad by
    body: `law_error.law_margins`) is kept inside the position's and the heading's tolerance."""
    for goal in problem.goals if goals is None else goals:
        pose = final[goal.body]
        margin, turn_margin = (margins or {}).get(goal.body, (0.0, 0.0))
        if (
            goal.position is not None
            and np.linalg.norm(pose[: len(goal.position), 3] - goal.position) + margin > goal.tol_position
        ):
            return False
        if goal.yaw is not None and abs(wrap_angle(yaw_of(pose) - goal.yaw)) + turn_margin > goal.tol_yaw:
            return False
        if (
            goal.opening is not None
            and abs(problem.bodies[goal.body].joint_state(pose) - goal.opening) > goal.tol_opening
        ):
            return False
        if goal.region is not None and float(goal.region_excess(pose).max()) + margin > goal.tol_position:
            return False
    return True


MEMO_KEPT = 1024
"""Points an evaluator remembers (then forgets them all). With 64, the memo was cleared in the middle of a
point's finite differences often enough that the constraints' gradient computed again, bit for bit, what the
objective's had just computed (4 % of the evaluations of gen1_027); a point and its steps are tens of entries,
of a few hundred bytes each."""

PLACED_REMEMBERED = 4096
"""Bodies' `body_constraints` an evaluator keeps (its sequence's bodies at the poses the optimiser tried)."""


def task_space(
    problem: Problem,
    seq: Sequence,
    deadline: float,
    counters: Counters | None = None,
    *,
    offsets: np.ndarray | None = None,
) -> TaskSolution | Rejection:
    """Motion values for `seq` that reach the goal inside every constraint (NLopt SLSQP), or why not.

    The contacts' offsets along their families (`seq.offsets`) are variables too: pinned at 0 (as written)
    first, then, after a rejection for the hand's reach or for missing the goal (what moving a contact changes:
    a turn's pivot moves with it, so a hook pulling a wide body off its far face's centre reaches a goal off its
    written arc), free within their bands (arc seeds: from the start, `arc_offsets.seeds_only`); `offsets` pins
    them. A solution that moved a contact comes with its sequence renamed (`materialise`).
    """
    if seq.offsets and offsets is None and not seeds_only(problem, seq):
        written = task_space(problem, seq, deadline, counters, offsets=np.zeros(len(seq.offsets)))
        if not isinstance(written, Rejection) or written.kind not in (Kind.REACH, Kind.GOAL):
            return written
        if all(slide_band(problem, e) is not None for _, e in seq.offsets):
            return written  # a tool's slide moves the same at any offset: its contact moves for the tool's room only
    start = remembered_closed_form(problem, seq)
    if isinstance(start, Rejection):
        return start
    guess, pinned = start
    carry_guess = np.zeros(0)
    if seq.carries:
        carry_guess, carry_pinned = carry_start(problem, seq, guess)
        pinned = pinned and carry_pinned
    evaluator = _Evaluator(problem, seq)
    lower, upper = bounds(problem, seq, offsets=True)
    n, m = len(seq.variables), len(seq.offsets)  # the values: motions, then offsets, then carries
    if offsets is None or np.any(offsets):
        cap_arc_turns(problem, seq, lower, upper)
    if offsets is not None:
        lower[n : n + m] = upper[n : n + m] = offsets
    else:  # a tool's slide keeps its written contact here: it moves only when that contact fails (`other_contacts`)
        for j, (_, e) in enumerate(seq.offsets):
            if slide_band(problem, e) is not None:
                lower[n + j] = upper[n + j] = 0.0
    guess = np.clip(np.concatenate([guess, np.zeros(m), carry_guess]), lower, upper)
    best: tuple[float, np.ndarray] | None = None
    uncertain: Rejection | None = None  # a solution the arcs' law errors could take out of the goal's tolerance
    restarts = [] if pinned or (offsets is None and seeds_only(problem, seq)) else _restarts(lower, upper)
    for x0 in [guess, *restarts]:
        if time.perf_counter() > deadline:
            break
        x = _optimise(evaluator, x0, lower, upper, deadline)
        if counters is not None:
            counters.optimisations += 1
        residual, c = evaluator.evaluate(x)
        violation = float(c.max())
        traces = rollout(problem, seq, x, TASK_SAMPLES)
        if violation <= 1e-6 and goal_holds(problem, traces[-1].end):
            found = _near_edge(problem, seq, evaluator, x)
            x = least_room(problem, seq, found, evaluator)
            named, values = materialise(problem, seq, x)
            roomier = None if x is found else materialise(problem, seq, found)[1]
            renamed = named if named.actions != seq.actions else None
            traces = rollout(problem, named, values, JOINT_SAMPLES)
            if renamed is not None and offsets is None and not goal_holds(problem, traces[-1].end):
                # the members' names keep the offsets to 0.01 cm, and an arc's pivot moves by centimetres per
                # 0.01 cm near the centre: solved again with the contacts where the names put them
                return task_space(problem, seq, deadline, counters, offsets=named_offsets(problem, seq, x))
            margins = law_margins(problem, named, values, traces)
            if goal_holds(problem, traces[-1].end, margins=margins):
                return TaskSolution(values, traces, not pinned, renamed, roomier)
            uncertain = uncertain_rejection(problem, traces[-1].end, margins)
            continue
        score = violation + float(residual @ residual)
        if best is None or score < best[0]:
            best = (score, x)
    if uncertain is not None:
        return uncertain
    return _why_not(problem, seq, best[1] if best is not None else guess)


REGION_TRIM_STEPS = 20
"""Bisection steps that shorten the motions of a body with a region goal to where it just lies inside."""


def _near_edge(problem: Problem, seq: Sequence, evaluator: _Evaluator, x: np.ndarray) -> np.ndarray:
    """`x` with the motions of the bodies that have region goals scaled down to the least fraction that still
    puts each footprint inside its region (no tolerance used) with every constraint and goal holding.

    The optimiser stops anywhere inside a region (its residual is 0 there);
    the shortest motion ends at the region's near edge, and the goal's
    tolerance is then left to the execution.
    """
    bodies = {goal.body for goal in problem.goals if goal.region is not None}
    scaled = np.array(
        [e.body in bodies for _, e in seq.variables] + [False] * (seq.size - len(seq.variables)), dtype=bool
    )
    if not scaled.any():
        return x

    def inside(fraction: float) -> bool:
        trial = np.where(scaled, x * fraction, x)
        if float(evaluator.evaluate(trial)[1].max()) > 1e-6:
            return False
        final = rollout(problem, seq, trial, 2)[-1].end
        regions_hold = all(
            float(g.region_excess(final[g.body]).max()) <= 1e-6 for g in problem.goals if g.region is not None
        )
        return regions_hold and goal_holds(problem, final)

    if not inside(1.0):
        return x  # inside only within the tolerance: keep what the optimiser found
    low, high = 0.0, 1.0
    for _ in range(REGION_TRIM_STEPS):
        middle = (low + high) / 2
        low, high = (low, middle) if inside(middle) else (middle, high)
    return np.where(scaled, x * high, x)


def least_room(problem: Problem, seq: Sequence, x: np.ndarray, evaluator: _Evaluator | None = None) -> np.ndarray:
    """`x` with each motion of a body of `problem.least` (moved only to make room for a later motion: a goal body
    of the problem that a clearing sub-problem serves) shortened to the least that takes the body out of every
    later motion's corridor with `clearing.MARGIN` (`clearing.cleared_values`), when that is shorter and every
    constraint and goal still holds; `x` itself otherwise.

    The optimiser stops anywhere in the set of values that reach a region goal: a Crate pushed 46 cm aside so
    that a tool may pass where 10 cm would do. What a plan moves only to make room, the plan after it must
    undo (`clear_first`: the goal body still has its own goal to reach), so the least move is the one to keep. A
    motion whose body lies clear of the later corridors from the start (moved for the arm's sake, which the
    corridors do not see) keeps its value; so does one the checks after this reject with the least value: the
    search then tries the values farther aside (`task_space_alternatives`)."""
    least = [b for b in blockers(problem, seq) if b.engagement.body in problem.least]
    if not least:
        return x
    evaluator = evaluator or _Evaluator(problem, seq)
    lower, upper = bounds(problem, seq)
    cleared = cleared_values(problem, seq, x, rollout(problem, seq, x, TASK_SAMPLES), lower, upper)
    if cleared is None:
        return x
    trial = x.copy()
    for b in least:
        if RESOLUTION < cleared[b.index] < x[b.index]:
            trial[b.index] = cleared[b.index]
    if np.array_equal(trial, x) or float(evaluator.evaluate(trial)[1].max()) > 1e-6:
        return x
    return trial if goal_holds(problem, rollout(problem, seq, trial, 2)[-1].end) else x


def roomier_after(
    problem: Problem,
    rejected: list[tuple[Sequence, TaskSolution]],
    clash: Callable[[tuple[KGraph, ...], list[ModeTrace]], object | None],
) -> Iterator[tuple[Sequence, TaskSolution]]:
    """The first of `rejected` (the candidates the arm's checks rejected, read when this is asked for its item)
    with the values the optimiser found before `least_room` shortened them, when it did and their bodies pass
    clear of one another (`clash` None): a body moved farther aside than the least may leave the arm room that
    the least move does not (the corridors `least_room` reads are the bodies' and the tools', not the arm's);
    `clash` is the bodies' collision check (`GeometryCheck.bodies`)."""
    if rejected and (roomy := rejected[0][1].roomier) is not None:
        named, found = rejected[0]
        traces = rollout(problem, named, roomy, JOINT_SAMPLES)
        if clash(named.graphs, traces) is None:
            yield named, replace(found, values=roomy, traces=traces, roomier=None)


def task_space_alternatives(
    problem: Problem, seq: Sequence, found: TaskSolution, deadline: float, counters: Counters | None = None
) -> Iterator[TaskSolution]:
    """Other motion values for `seq` that reach the goal too, when the goal leaves some of them free.

    The search asks for them when `found` makes bodies pass through one
    another: a body in the way moved out of the path may clear it. First, no
    optimisation: `found`'s values for the goal bodies' motions (they reach
    the goal, and a goal body's pose depends on its own motions only) with
    every body in the way moved by the smallest value that takes it out of
    the corridors the later motions sweep, with a margin
    (`clearing.cleared_values`, computed from the footprints), then farther
    (`ASIDE_BEYOND`); kept when they break no constraint. Then the optimiser,
    started with every value at one of `ALTERNATIVE_FRACTIONS` of its range
    (the goal then pins the values it needs). Solutions equal to one already
    given are skipped. Deterministic.
    """
    if not found.free:
        return
    evaluator = _Evaluator(problem, seq)
    lower, upper = bounds(problem, seq)
    given = [found.values]
    starts: list[tuple[np.ndarray, bool]] = []
    cleared = cleared_values(problem, seq, found.values, found.traces, lower, upper)
    if cleared is not None:
        aside = np.array([i in {b.index for b in blockers(problem, seq)} for i in range(len(cleared))], dtype=bool)
        starts += [(np.where(aside, cleared + f * (upper - cleared), cleared), False) for f in ASIDE_BEYOND]
    starts += [(lower + f * (upper - lower), True) for f in ALTERNATIVE_FRACTIONS]
    for x0, optimise in starts:
        if time.perf_counter() > deadline:
            return
        x = x0
        if optimise:
            x = _optimise(evaluator, x0, lower, upper, deadline)
            if counters is not None:
                counters.optimisations += 1
        _, c = evaluator.evaluate(x)
        if float(c.max()) > 1e-6 or any(np.allclose(x, other, atol=1e-3) for other in given):
            continue
        traces = rollout(problem, seq, x, JOINT_SAMPLES)
        if goal_holds(problem, traces[-1].end, margins=law_margins(problem, seq, x, traces)):
            given.append(x)
            yield TaskSolution(x, traces, free=True)


def _optimise(
    evaluator: _Evaluator, x0: np.ndarray, lower: np.ndarray, upper: np.ndarray, deadline: float
) -> np.ndarray:
    """One SLSQP run from `x0`: minimise the goal error subject to the constraints, within the deadline."""
    if len(x0) == 0:
        return x0
    n_constraints = len(evaluator.evaluate(x0)[1])
    evaluator.last_x = x0.copy()
    found = slsqp(
        evaluator.objective,
        x0,
        lower,
        upper,
        max_evaluations=60,
        xtol=1e-7,
        ftol=1e-10,
        stop=1e-8,
        vector_inequalities=[(evaluator.constraints, np.full(n_constraints, 1e-7))],
        max_time=max(1e-3, deadline - time.perf_counter()),
    )
    return evaluator.last_x if found is None else found  # on an error: where SLSQP had got to, still worth judging


def _restarts(lower: np.ndarray, upper: np.ndarray) -> list[np.ndarray]:
    """Fixed, spread-out starts: a quarter, a half and a tenth of each range."""
    return [lower + f * (upper - lower) for f in (0.25, 0.5, 0.1)][:RESTARTS]


def _why_not(problem: Problem, seq: Sequence, x: np.ndarray) -> Rejection:
    """The reason the best values found still fail: out of reach, off the table, or the goal missed."""
    traces = rollout(problem, seq, x, TASK_SAMPLES)
    for trace in traces:
        for pose in trace.hand:
            found = unreachable(problem, pose)
            if found is not None:
                return found
    for trace in traces:  # a limit the optimiser ran into (or past) is what stopped it
        for name in sorted(trace.moved):
            excess = max(_stay_constraints(problem, name, trace.end[name]) or [-1.0])
            if excess > -1e-4:
                return Rejection(Kind.TABLE, limit_words(problem, name, trace.end[name]), max(excess, 0.0))
    for trace in traces:  # a keep-out region the optimiser could not get out of
        for name in sorted(trace.moved):
            points = footprint(problem.footprint_points(name), trace.end[name])
            for region in (k for k in problem.keep_out if k.applies_to(name)):
                depth = overlap_depth(region.region, points)
                if depth > 1e-4:
                    why = f"{name} would end {depth * 100:.1f} cm inside the keep-out {region.words}"
                    return Rejection(Kind.COLLISION, why, depth)
    why = "the optimiser found no motion values that reach the goal"
    return Rejection(Kind.GOAL, why + _at_range_ends(problem, seq, x))


def _at_range_ends(problem: Problem, seq: Sequence, x: np.ndarray) -> str:
    """` (at the end of the range it was explored over: Block.turn_px_left 25.0 deg)` for values stopped there."""
    _, upper = bounds(problem, seq)
    ended = {}
    for (_, e), value, top in zip(seq.variables, x, upper):
        motion = problem.affordance(e.body, e.affordance).motion
        if getattr(motion, "range", None) is not None and value >= top - 1e-6:
            name = f"{problem.bodies[e.body].type.name}.{e.affordance}"
            ended[name] = f"{math.degrees(top):.1f} deg" if motion.type == "revolute" else f"{top * 100:.1f} cm"
    parts = [f"{name} {limit}" for name, limit in ended.items()]
    return f" (at the end of the range it was explored over: {', '.join(parts)})" if parts else ""
