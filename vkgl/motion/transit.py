"""Transit planning: a collision-free joint-space path between two configurations of the arm.

`plan_transit(start, goal, is_valid, lower, upper, seed=...)`:

1. checks the ends (within the joint limits, valid);
2. the fast path: if the straight joint-space segment is valid, densely checked
   (`vkgl.motion.density`), it is the answer and OMPL is not called;
3. otherwise OMPL's RRTConnect (bidirectional RRT) in a `RealVectorStateSpace`
   bounded by the joint limits, extensions at most `RRT_RANGE` long, its edges checked by OMPL's discrete motion
   validator at the same Euclidean step `resolution` (the state validity
   checking resolution is `resolution / maximum extent` of the space), then
   OMPL's `PathSimplifier`: `reduceVertices` (shortcutting: random pairs of
   vertices joined by a straight edge when it is valid) and one round of
   `smoothBSpline` (smoothing). Both run without a clock, so they are
   deterministic. `simplifyMax` shortens paths by about 10 % more for 3 to 4
   times the collision checks; `ropeShortcutPath` or `partialShortcutPath`
   instead of `reduceVertices` cost 10 to 20 % more checks for the same
   length (docs/transit.md);
4. the result is re-validated densely in Python, independently of how OMPL was
   configured (if the simplified path fails, the raw one is tried).

`is_valid(q)` is the collision checker (arm links and held tool against the
bodies and the table); it is called with numpy arrays and must not keep them.

Seeding: every call sets OMPL's seed generator (`ompl.util.RNG.setSeed`) to a
value derived from `seed` and then builds fresh OMPL objects, whose RNGs draw
their seeds from it in a fixed order; the same input therefore gives the same
path (as long as the planner finishes within `time_limit`: a search cut by
the clock is a failure, whose timing depends on the machine). OMPL's seed
generator is global, so the OMPL part of planning calls is serialised by a
lock: threads planning at the same time still get their seeded paths.

Quiet: OMPL's log level is `LOG_NONE` while it runs (then restored). nanobind
prints "leaked instances" warnings at interpreter exit for OMPL objects still
alive then; every OMPL object lives only in `_run_ompl`'s frame and is dropped
before it returns (also when `is_valid` raises: its exception is caught in the
callback, stops the planner, and is raised again once the OMPL objects are
gone), and nothing OMPL-owned escapes this module.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vkgl.motion.density import (
    DEFAULT_RESOLUTION,
    Advance,
    CountingChecker,
    Validity,
    path_is_valid,
    segment_is_valid,
)

PLANNER = "RRTConnect"

RRT_RANGE: float | None = 0.5
"""rad: RRTConnect's longest extension (None: OMPL's default, a fifth of the space's maximum extent, 2.7 rad
for the Panda). RRTConnect drops an extension whose edge is blocked anywhere, so long edges waste their checks:
on the benchmark 0.5 rad needs 60 % fewer collision checks in the search than the default (`docs/transit.md`)."""


@dataclass(frozen=True)
class TransitPath:
    """A valid joint-space path: `waypoints` (k x n, start first, goal last), joined by straight segments.

    `method` is "straight" (the fast path) or "rrtconnect"; `planning_time` (s)
    and `checks` (calls of `is_valid`) measure the work, `stages` splits the
    checks: "ends", "straight", "search", "simplify", "revalidate".
    """

    waypoints: np.ndarray
    method: str
    planning_time: float
    checks: int
    stages: dict[str, int] = field(default_factory=dict)

    def length(self) -> float:
        """The Euclidean joint-space length of the path (rad)."""
        return float(np.linalg.norm(np.diff(self.waypoints, axis=0), axis=1).sum())


@dataclass(frozen=True)
class TransitFailure:
    """No path: `reason` says why (e.g. the goal is invalid, or none was found within the time limit)."""

    reason: str
    planning_time: float
    checks: int
    stages: dict[str, int] = field(default_factory=dict)


def plan_transit(
    start_q: Sequence[float] | np.ndarray,
    goal_q: Sequence[float] | np.ndarray,
    is_valid: Validity,
    lower: Sequence[float] | np.ndarray,
    upper: Sequence[float] | np.ndarray,
    *,
    seed: int,
    time_limit: float = 1.0,
    resolution: float = DEFAULT_RESOLUTION,
    straight_first: bool = True,
    via: Iterable[np.ndarray] = (),
    advance: Advance | None = None,
) -> TransitPath | TransitFailure:
    """A collision-free joint path from `start_q` to `goal_q` within [`lower`, `upper`], or why there is none.

    Every configuration on the path, sampled every `resolution` rad (Euclidean
    joint step, see `vkgl.motion.density.edge_resolution`), satisfies `is_valid`.
    `seed` makes the search reproducible; `time_limit` (s) bounds the search
    (the fast path and the final checks are not cut). `straight_first=False`
    skips the fast path (for benchmarks). `via`: polylines of intermediate
    configurations (each k x n, without the ends) tried in turn after the
    straight line and before OMPL, e.g. up, across and down (a lazy iterable
    is only asked when the straight line is blocked). `advance` (a clearance
    bound and the link reach, `vkgl.motion.density.Advance`) lets the straight
    line, the polylines and the final re-validation skip the stretches the
    bound proves clear (OMPL's own edge checks stay dense). Exceptions of
    `is_valid` propagate.
    """
    began = time.perf_counter()
    start, goal = np.asarray(start_q, dtype=float), np.asarray(goal_q, dtype=float)
    low, high = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    check = CountingChecker(is_valid)
    stages: dict[str, int] = {}

    def stage(name: str) -> None:
        stages[name] = check.calls - sum(stages.values())

    def failed(reason: str) -> TransitFailure:
        return TransitFailure(reason, time.perf_counter() - began, check.calls, stages)

    def found(waypoints: np.ndarray, method: str) -> TransitPath:
        return TransitPath(waypoints, method, time.perf_counter() - began, check.calls, stages)

    if not (start.shape == goal.shape == low.shape == high.shape and start.ndim == 1):
        raise ValueError(f"start, goal and limits must be vectors of one length, got {start.shape}, {goal.shape}")
    if resolution <= 0 or time_limit <= 0:
        raise ValueError("resolution and time_limit must be positive")
    for name, q in (("start", start), ("goal", goal)):
        outside = np.flatnonzero((q < low - 1e-9) | (q > high + 1e-9))
        if outside.size:
            return failed(f"the {name} configuration is outside the joint limits (joints {list(outside + 1)})")
        if not check(q):
            return failed(f"the {name} configuration is invalid (in collision)")
    stage("ends")
    if straight_first:
        clear = segment_is_valid(start, goal, check, resolution, advance)
        stage("straight")
        if clear:
            return found(np.vstack([start, goal]), "straight")
        for middle in via:
            polyline = np.vstack([start, np.atleast_2d(np.asarray(middle, dtype=float)), goal])
            within = bool(np.all((polyline >= low - 1e-9) & (polyline <= high + 1e-9)))
            clear = within and path_is_valid(polyline, check, resolution, advance)
            stage("via")
            if clear:
                return found(polyline, "via")

    time_left = time_limit - (time.perf_counter() - began)
    if time_left <= 0:
        return failed(f"no time left for {PLANNER} within {time_limit:g} s")
    inside = np.clip(start, low, high), np.clip(goal, low, high)  # within 1e-9: OMPL would reject the ends
    outcome = _quiet_ompl(*inside, check, stage, low, high, seed=seed, time_limit=time_left, resolution=resolution)
    if isinstance(outcome, str):
        if outcome.startswith("no path found"):
            outcome = f"no path found by {PLANNER} within {time_limit:.3g} s or {SEARCH_CHECKS} checks"
        return failed(outcome)
    for waypoints in outcome:
        valid = path_is_valid(waypoints, check, resolution, advance)
        stage("revalidate")
        if valid:
            return found(waypoints, "rrtconnect")
    return failed(f"{PLANNER}'s path failed the dense re-validation")


SEARCH_CHECKS = 20_000
"""Validity checks RRTConnect may spend before it gives up. This budget, not the clock, ends a search on any
reasonably fast machine, so the same input gives the same answer however loaded the machine is (`time_limit`
is the safety net)."""

_OMPL_LOCK = threading.Lock()
"""OMPL's seed generator and log level are global: one planning call at a time in a process, so that threads
planning at once still get their seeded paths."""


def _ompl_seed(seed: int) -> int:
    """OMPL's seed for `seed`: in 1 .. 2^31 - 1 (OMPL turns 0 into 1, so 0 is avoided)."""
    return int(seed) % (2**31 - 1) + 1


def _quiet_ompl(
    start: np.ndarray,
    goal: np.ndarray,
    check: CountingChecker,
    stage: Callable[[str], None],
    low: np.ndarray,
    high: np.ndarray,
    *,
    seed: int,
    time_limit: float,
    resolution: float,
) -> list[np.ndarray] | str:
    """`_run_ompl` with OMPL's log silenced, re-raising an exception of `is_valid` after OMPL is done."""
    from ompl import util as ou

    errors: list[BaseException] = []
    with _OMPL_LOCK:
        previous = ou.getLogLevel()
        ou.setLogLevel(ou.LogLevel.LOG_NONE)
        try:
            outcome = _run_ompl(start, goal, check, stage, low, high, errors, seed, time_limit, resolution)
        finally:
            ou.setLogLevel(previous)
    if errors:
        raise errors[0]
    return outcome


def _run_ompl(
    start: np.ndarray,
    goal: np.ndarray,
    check: CountingChecker,
    stage: Callable[[str], None],
    low: np.ndarray,
    high: np.ndarray,
    errors: list[BaseException],
    seed: int,
    time_limit: float,
    resolution: float,
) -> list[np.ndarray] | str:
    """RRTConnect, shortcutting, smoothing: [simplified path, raw path] as arrays, or the reason for no path.

    Every OMPL object is a local of this frame, set to None before it ends.
    """
    from ompl import base as ob
    from ompl import geometric as og
    from ompl import util as ou

    n = len(start)
    validity = _StateValidity(check, n, errors)
    space: Any = None
    si: Any = None
    start_state: Any = None
    goal_state: Any = None
    pdef: Any = None
    planner: Any = None
    stop: Any = None
    path: Any = None
    simplifier: Any = None
    try:
        ou.RNG.setSeed(_ompl_seed(seed))
        space = ob.RealVectorStateSpace(n)
        bounds = ob.RealVectorBounds(n)
        for i in range(n):
            bounds.setLow(i, float(low[i]))
            bounds.setHigh(i, float(high[i]))
        space.setBounds(bounds)
        bounds = None
        si = ob.SpaceInformation(space)
        si.setStateValidityChecker(validity)
        si.setStateValidityCheckingResolution(min(1.0, resolution / space.getMaximumExtent()))
        si.setup()
        start_state, goal_state = si.allocState(), si.allocState()  # owned: freed with their wrappers
        start_state[0:n] = [float(v) for v in start]
        goal_state[0:n] = [float(v) for v in goal]
        pdef = ob.ProblemDefinition(si)
        pdef.setStartAndGoalStates(start_state, goal_state)
        planner = og.RRTConnect(si)
        if RRT_RANGE is not None:
            planner.setRange(RRT_RANGE)
        planner.setProblemDefinition(pdef)
        planner.setup()
        stop = ob.plannerOrTerminationCondition(
            ob.timedPlannerTerminationCondition(time_limit), ob.PlannerTerminationCondition(validity.failed)
        )
        planner.solve(stop)
        stage("search")
        if errors:
            return "the validity function raised an exception"
        if not pdef.hasExactSolution():
            return f"no path found by {PLANNER} within {time_limit:.3g} s"
        path = og.PathGeometric(pdef.getSolutionPath())
        raw = _waypoints(path, n)
        simplifier = og.PathSimplifier(si)
        simplifier.reduceVertices(path)
        simplifier.smoothBSpline(path, 1)
        stage("simplify")
        simplified = _waypoints(path, n)
        if errors:
            return "the validity function raised an exception"
        return [_pinned(simplified, start, goal), _pinned(raw, start, goal)]
    finally:
        space = si = start_state = goal_state = pdef = planner = stop = path = simplifier = None


def _waypoints(path: Any, n: int) -> np.ndarray:
    """The states of an OMPL `PathGeometric` as a k x n array."""
    return np.array([path.getState(i)[0:n] for i in range(path.getStateCount())], dtype=float)


def _pinned(waypoints: np.ndarray, start: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """`waypoints` with its ends set exactly to `start` and `goal` (OMPL copies them, within rounding)."""
    waypoints = waypoints.copy()
    waypoints[0], waypoints[-1] = start, goal
    return waypoints


class _StateValidity:
    """OMPL's state validity callback: the state as a numpy array to `check`; an exception is kept, not raised.

    Raising through OMPL's C++ would unwind the planner mid-step and keep OMPL
    objects alive in the traceback; instead the first exception is recorded,
    every state is then invalid, and `failed` stops the planner.
    """

    def __init__(self, check: CountingChecker, n: int, errors: list[BaseException]) -> None:
        """Call `check` with `n`-vectors; record exceptions in `errors`."""
        self.check = check
        self.n = n
        self.errors = errors
        self.budget = check.calls + SEARCH_CHECKS

    def __call__(self, state: Any) -> bool:
        """Whether the OMPL state is valid."""
        q = np.array(state[0 : self.n], dtype=float)
        del state
        return self._checked(q)

    def _checked(self, q: np.ndarray) -> bool:
        if self.errors:
            return False
        try:
            return self.check(q)
        except BaseException as error:  # also KeyboardInterrupt: raised again after OMPL returns
            self.errors.append(error)
            return False

    def failed(self) -> bool:
        """Whether `is_valid` raised, or the search used up its `SEARCH_CHECKS` (the planner's extra stop)."""
        return bool(self.errors) or self.check.calls > self.budget


__all__ = ["PLANNER", "TransitFailure", "TransitPath", "plan_transit"]
