"""The arm's paths between contacts, planned for every step of a plan: straight moves, then transits.

A plan step's action (make a contact and move with it, grasp a tool, let go,
put a tool down) needs the arm to get there first. For each step, from where
the previous step left the arm, the path is:

- **lift**: after a grasp or a release, straight up (`vkgl.plan.arm.straight_moves`);
- **retreat** (a REMOVE of a push): straight back out of the contact; none
  when the next step lets go of the tool that touched (it is let go of where
  the search leaves it);
- **transit**: a collision-free joint-space path (`vkgl.motion.transit_segment`:
  the straight line when it is clear, up and over, else OMPL's RRTConnect) to
  the step's pre-contact configuration; valid means the arm's links and a
  held tool clear every body and the table (`vkgl.motion.arm_collision`);
- **approach**: straight into the contact (`vkgl.plan.arm.straight_moves`: along
  its push, from above, or slanted), ending in the configuration the search
  checked. A contact's configuration must carry its whole motion: the plan
  stores it as a chain of joints along the motion (`contact`), the first arm
  configuration of `_contact_chain` that can be approached.

Planning runs in two stages. `ArmPathPlanner.straight` plans everything but
the transits, inside the search, for every candidate that passed the other
checks: a plan whose contact cannot be approached or left is rejected there
(kind "approach"). `ArmPathPlanner.transits` then plans the transits between
the fixed ends the first stage chose (their ends do not depend on one
another), after the search has a candidate; when one fails, the search goes
on with the next candidate (kind "transit"). `ArmPathPlanner.plan` runs both.
Every segment is timed: transits within the URDF's joint velocity limits, the
straight moves at `straight_moves.CARTESIAN_SPEED`. Deterministic: transit `k` of a plan is
seeded with `k`.
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Generic, TypeVar

import numpy as np

from vkgl.formats.plan import ArmSegment, PlanStepRecord
from vkgl.motion.arm_collision import Held
from vkgl.motion.escape import way_out
from vkgl.motion.moves import GRASP_STANDOFF
from vkgl.motion.transit import TransitFailure
from vkgl.motion.transit_segment import TRANSIT_TIME_LIMIT, transit_segment
from vkgl.plan.arm.approaches import DOWN
from vkgl.plan.arm.contact_chains import ContactChains
from vkgl.plan.arm.remembered import Remembered, Replay, step_key
from vkgl.plan.arm.straight_moves import ArmState, StraightMoves
from vkgl.plan.geometry.bodies import TRANSIT_CLEARANCE, GeometryCheck
from vkgl.plan.geometry.grip_load import held as held_tool
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.plan.task_space.feasible import goal_holds
from vkgl.plan.task_space.law_error import POINT_SIGMAS, point_margins, uncertain_rejection
from vkgl.robot.pad import pad_lies_along

StepT = TypeVar("StepT", bound=PlanStepRecord)


@dataclass(frozen=True)
class PendingTransit:
    """A transit the first stage left to plan: into `steps[step].path` at `at`, from `start` to `goal` (joints),
    with the bodies at `poses` and `held` in the hand, toward a contact with `body`; `label` names the step in a
    rejection."""

    step: int
    at: int
    start: np.ndarray
    goal: np.ndarray
    poses: Mapping[str, np.ndarray]
    held: Held | None
    label: str
    body: str | None = None
    clear: bool = False  # a carried body: kept `TRANSIT_CLEARANCE` from the others where it can be


@dataclass(frozen=True)
class StraightPaths(Generic[StepT]):
    """The first stage's result: the steps with their straight moves, and the transits still to plan."""

    steps: list[StepT]
    pending: list[PendingTransit]


class ArmPathPlanner:
    """Plans the arm's segments for the steps of one problem's plans (built once per search)."""

    def __init__(self, problem: Problem, geometry: GeometryCheck) -> None:
        """Paths for `problem`'s arm, checked with `geometry`'s collision world."""
        self.problem = problem
        self.geometry = geometry
        self.moves = StraightMoves(problem, geometry)
        self.chains = ContactChains(problem, self.moves)
        self._chains: Remembered[Replay[np.ndarray | Rejection]] = Remembered()
        self.transit_count = 0
        self.seconds = 0.0  # in the first stage (IK of straight moves and contact chains, their checks)
        self.transit_seconds = 0.0  # in the second (transit planning)

    def plan(
        self, steps: Sequence[StepT], q_start: np.ndarray | None = None, *, deadline: float | None = None
    ) -> list[StepT] | Rejection:
        """The steps with their `path` (the segments before each step's action), or why one cannot be planned:
        both stages, `straight` then `transits`."""
        first = self.straight(steps, q_start)
        return first if isinstance(first, Rejection) else self.transits(first, deadline=deadline)

    def straight(self, steps: Sequence[StepT], q_start: np.ndarray | None = None) -> StraightPaths[StepT] | Rejection:
        """The first stage: every step's straight moves and contact chain, and the transits left to plan.

        A contact whose arm configuration cannot carry the whole motion (the
        arm would have to switch configuration in contact) gets one that can:
        the returned steps' `q_start`/`q_end` may differ from the given ones.
        `q_start`: the arm's joints before the first step (the arm's home by default).
        """
        began = time.perf_counter()
        try:
            state = ArmState(np.asarray(self.problem.arm.home if q_start is None else q_start, dtype=float))
            out: list[StepT] = []
            pending: list[PendingTransit] = []
            for k, step in enumerate(steps, start=1):
                following = steps[k] if k < len(steps) else None
                previous = steps[k - 2] if k > 1 else None
                planned = self._planned_step(
                    k, step, state, last=following is None, following=following, places=_places(step, previous),
                    then_places=_places(following, step), final=steps[-1].poses_end,
                )  # fmt: skip
                if isinstance(planned, Rejection):
                    return planned
                found, transit = planned
                out.append(found)
                if transit is not None:
                    pending.append(transit)
            return StraightPaths(out, pending)
        finally:
            self.seconds += time.perf_counter() - began

    def transits(self, paths: StraightPaths[StepT], *, deadline: float | None = None) -> list[StepT] | Rejection:
        """The second stage: the steps of `paths` with their transits planned in, or why one cannot be."""
        steps = list(paths.steps)
        for transit in paths.pending:
            segment = self._transit(transit, deadline)
            if isinstance(segment, Rejection):
                return segment
            step = steps[transit.step]
            path = (*step.path[: transit.at], segment, *step.path[transit.at :])
            steps[transit.step] = replace(step, path=path)
        return steps

    def _planned_step(
        self,
        k: int,
        step: StepT,
        state: ArmState,
        *,
        last: bool = False,
        following: PlanStepRecord | None = None,
        places: bool = False,
        then_places: bool = False,
        final: Mapping[str, np.ndarray] | None = None,
    ) -> tuple[StepT, PendingTransit | None] | Rejection:
        """The step with its straight moves and the transit it needs; a contact tries each arm configuration
        that carries its motion in turn, until one can be approached (and, for the `last` step, left again).
        A release happens where the arm is (its `q_start`/`q_end` become those joints), unless it `places` a
        carried body or a tool (`_places`): then its path carries the body to its place first (`q_start`, as the
        search solved it), and the contact before such a tool's release (`then_places`) retreats out of it.
        A chain whose hand pushes an arc with a point (`_point_arc`) is passed over where the plan's `final` poses
        would not keep the goal with the point's error."""
        if step.op != "add" or step.motion == "free":
            q_before = state.q
            # a tool the next step carries elsewhere backs out of its contact first (a retreat, as before a contact)
            releases = _releases(following, state.held) and not then_places
            found = self._step(k, step, state, releases_next=releases, places=places)
            if isinstance(found, Rejection):
                return found
            segments, transit = found
            if step.op == "remove" and step.motion == "free" and not places:
                return replace(step, path=segments, q_start=q_before, q_end=q_before), transit
            return replace(step, path=segments), transit
        label = f"step {k} ({step.title()})"
        first: Rejection | None = None
        for chain in self._contact_chain(step, state, label):
            if isinstance(chain, Rejection):
                return first or chain
            loose = self._point_arc(step, chain, final, label)
            if loose is not None:
                first = first or loose
                continue
            attempt = state.copy()
            # the whole chain goes into the plan: execution follows this configuration, not one of its own
            moved = replace(step, q_start=chain[0], q_end=chain[-1], contact=chain)
            found = self._step(k, moved, attempt)
            if not isinstance(found, Rejection) and last:
                found = self.moves.leave(moved, attempt, label) or found
            if not isinstance(found, Rejection):
                state.q, state.held, state.lift = attempt.q, attempt.held, attempt.lift
                segments, transit = found
                return replace(moved, path=segments), transit
            first = first or found
            if found.kind != Kind.APPROACH:
                return found
        return first or Rejection(Kind.IK, f"{label}: no arm configuration carries the whole motion", 1.0)

    def _point_arc(
        self, step: PlanStepRecord, chain: np.ndarray, final: Mapping[str, np.ndarray] | None, label: str
    ) -> Rejection | None:
        """Why the hand of `chain` cannot promise the arc member `step` pushes: turned about its axis, its pad does
        not lie along the face, so it pushes with the rounded end, a point that does not hold the arc
        (`law_error.point_margins`), and the plan's `final` poses miss a goal by that error; None otherwise."""
        if final is None or step.effector != self.problem.robot_effector.name or step.body not in final:
            return None
        _, _, name = step.affordance.partition(".")
        body = step.body
        push = (step.poses_start[body] @ self.problem.action(body, name))[:3, 0]
        if pad_lies_along(self.problem.arm.fk(chain[0]), push):
            return None
        motion = (step.poses_start[body], step.poses_end[body])
        margins = point_margins(self.problem, body, name, motion, final[body])
        ends = dict(final)
        if not margins or goal_holds(self.problem, ends, margins=margins):
            return None
        cause = f"{POINT_SIGMAS:g} of its law's sigmas over the turn: the turned hand pushes with a point"
        missed = uncertain_rejection(self.problem, ends, margins, cause)
        why = f"{label}: the hand turned about its axis does not hold the arc: {missed.why}"
        return Rejection(Kind.GOAL, why, missed.excess)

    def _contact_chain(self, step: PlanStepRecord, state: ArmState, label: str) -> Iterator[np.ndarray | Rejection]:
        """`_solved_contact_chain`, remembered by what it depends on (`remembered.step_key`): each chain is
        solved once, when the first caller asks for it (the solver gets a copy of `state`: the caller's
        changes once a chain worked do not reach it)."""
        key = step_key(step, state.held, label)
        chains = self._chains.get(key)
        if chains is None:
            chains = self._chains.keep(key, Replay(self._solved_contact_chain(step, state.copy(), label)))
        yield from chains

    def _solved_contact_chain(
        self, step: PlanStepRecord, state: ArmState, label: str
    ) -> Iterator[np.ndarray | Rejection]:
        """The contact's chains in one arm configuration each (`vkgl.plan.arm.contact_chains`), then why none."""
        return self.chains.solve(step, state, label)

    def _step(
        self, k: int, step: PlanStepRecord, state: ArmState, *, releases_next: bool = False, places: bool = False
    ) -> tuple[tuple[ArmSegment, ...], PendingTransit | None] | Rejection:
        """The step's straight moves from where `state` has the arm, and the transit before its approach (for
        a step that `places` a carried body, the transit with the body in the hand, then down onto its place)."""
        label = f"step {k} ({step.title()})"
        segments: list[ArmSegment] = []
        if state.lift:
            lift = self.moves.lift(state, step.poses_start, label)
            if isinstance(lift, Rejection):
                return lift
            segments.append(lift)
            state.lift = False
        if step.op == "remove" and step.motion != "free" and releases_next:
            # the tool is let go of where it touched (where the search leaves it), and the hand lifts from there:
            # backing the tool out first would put it down a stand-off away from where the plan says it lies
            return tuple(segments), None
        if step.op == "remove" and step.motion != "free":
            retreat = self.moves.retreat(step, state, label)
            if isinstance(retreat, Rejection):
                return retreat
            return (*segments, retreat), None
        if step.op == "remove" and places:
            return self._place(k, step, state, segments, label)
        if step.op == "remove":  # a release: the tool stays where the plan put it; the hand lifts next
            state.held, state.lift = None, True
            return tuple(segments), None
        approach = self.moves.into_contact(step, state, label)
        if isinstance(approach, Rejection):
            return approach
        transit = PendingTransit(
            k - 1, len(segments), state.q.copy(), approach.pre_contact, step.poses_start, state.held, label, step.body
        )
        segments.append(approach.segment)
        if step.motion != "free":
            state.entered = self.moves.entered(step, approach)
        if step.motion == "free":  # a grasp: the tool rides in the hand from here on
            in_hand = np.linalg.inv(self.problem.arm.fk(step.q_start)) @ step.poses_start[step.body]
            state.held, state.lift = (
                held_tool(self.problem, step.body, step.affordance.partition(".")[2], in_hand),
                True,
            )
        state.q = np.asarray(step.q_end, dtype=float)
        return tuple(segments), transit

    def _place(
        self, k: int, step: PlanStepRecord, state: ArmState, segments: list[ArmSegment], label: str
    ) -> tuple[tuple[ArmSegment, ...], PendingTransit | None] | Rejection:
        """A carried body set down: the transit with it in the hand (lifted clear: over the others when they
        are in the way) to above its place, then straight down onto it (`GRASP_STANDOFF`, after the held
        body's `TOOL_DESCENT`), where the hand lets go and lifts next."""
        down = self.moves.approach(step, state, f"{label}, setting {step.body} down", DOWN, GRASP_STANDOFF)
        if isinstance(down, Rejection):
            return down
        transit = PendingTransit(
            k - 1, len(segments), state.q.copy(), down.pre_contact, step.poses_start, state.held, label, clear=True
        )
        state.held, state.lift, state.placed = None, True, step.body
        state.q = np.asarray(step.q_start, dtype=float)
        return (*segments, down.segment), transit

    def _transit(self, transit: PendingTransit, deadline: float | None) -> ArmSegment | Rejection:
        """`transit` planned, or why it cannot be (naming what blocks one of its ends when one is blocked)."""
        limit = TRANSIT_TIME_LIMIT
        if deadline is not None:
            limit = max(0.05, min(limit, deadline - time.perf_counter()))
        self.transit_count += 1
        held = transit.held
        spaces = [self.geometry.transit_space(held, transit.body)]
        if held is not None and transit.body is not None:
            # a held tool passes the body it is going to with the same room as the others where it can (a hook
            # swinging over a tall crate it is to pull touched its top in DART 2 mm above it), as close as its
            # stand-off needs only when that way is blocked
            spaces.insert(0, self.geometry.transit_space(held))
        if transit.clear:
            # a carried body swings with the arm through free space: with room to spare from the others (the
            # grown bodies), unless its ends lie closer than that (a neighbour beside where it is picked up)
            spaces.insert(0, self.geometry.transit_collision)
        began = time.perf_counter()
        try:
            for collision in spaces:
                found = transit_segment(
                    collision, transit.start, transit.goal, transit.poses, held, seed=transit.step + 1,
                    time_limit=limit, exact=self.geometry.arm_collision,
                )  # fmt: skip
                if not isinstance(found, TransitFailure):
                    break
        finally:
            self.transit_seconds += time.perf_counter() - began
        if isinstance(found, TransitFailure):
            blocker, bodies = self._blocker(found.reason, transit)
            why = f"{transit.label}: no collision-free way for the arm to the contact: {blocker}"
            return Rejection(Kind.TRANSIT, why, 1.0, bodies=bodies)
        return found

    def _blocker(self, reason: str, transit: PendingTransit) -> tuple[str, frozenset[str]]:
        """The transit's failure in words, naming what blocks an end configuration when one is blocked: where
        the arm stands before the first step is named as such (a scene body beside the arm's ready pose blocks
        every plan), and a body only the transit's room reaches is told from one the arm would enter; and that
        body (`Rejection.bodies`), if any."""
        for name, q in (("start", transit.start), ("goal", transit.goal)):
            clash = self.moves.first_overlap(
                np.asarray([q]), transit.poses, transit.held, set(), collision=self.geometry.transit_collision
            )
            if clash is None:
                continue
            where = f"at the {name} of the transit"
            if name == "start" and transit.step == 0 and transit.at == 0:
                where = f"where the arm starts ({self._start_words(q)})"
            real = self.moves.first_overlap(np.asarray([q]), transit.poses, transit.held, set())
            if real is None and self._has_way_out(q, transit):
                continue  # the transit leaves the room from there (`vkgl.motion.escape`): not what blocks it
            if real is None:
                return (
                    f"{where} the arm keeps less than the {TRANSIT_CLEARANCE * 100:g} cm of room a transit needs "
                    f"({clash.words}, with the bodies grown by that room)"
                ), clash.bodies
            return f"{where} {real.words}", real.bodies
        return reason, frozenset()

    def _has_way_out(self, q: np.ndarray, transit: PendingTransit) -> bool:
        """Whether the arm at `q` (inside the transit's room, clear of the real shapes) has a way out of the room."""
        room, exact = self.geometry.transit_collision, self.geometry.arm_collision
        room.scene.place(transit.poses)
        exact.scene.place(transit.poses)
        return way_out(room, exact, q, transit.held) is not None

    def _start_words(self, q: np.ndarray) -> str:
        """The arm's start in words: the hand's position, and whether it is the arm's ready pose."""
        x, y, z = self.problem.arm.fk(q)[:3, 3]
        ready = "its ready pose, " if np.allclose(q, self.problem.arm.home) else ""
        return f"{ready}the hand at ({x:.2f}, {y:.2f}, {z:.2f}) m, before the first step"


def _places(step: PlanStepRecord | None, previous: PlanStepRecord | None) -> bool:
    """Whether `step` sets a body down somewhere else than the hand holds it: a body carried since the step
    before grasped it (pick and place: the search lets go of a tool it has just grasped never,
    `vkgl.plan.graphs.graph.successors`), or a tool set down where it was picked up, away from where its last
    contact left it (`vkgl.plan.search.put_back`)."""
    if step is None or previous is None or step.op != "remove" or step.motion != "free":
        return False
    if previous.op == "add" and previous.motion == "free":
        return previous.body == step.body and previous.effector == step.effector
    there, here = previous.poses_end.get(step.body), step.poses_start.get(step.body)
    return there is not None and here is not None and float(np.hypot(*(there[:2, 3] - here[:2, 3]))) > PLACED_AWAY


PLACED_AWAY = 1e-3
"""m: a released tool set down farther than this (horizontally) from where its last contact left it is carried
there (`_places`); one put down where it was used keeps its place's x and y (`rollout.put_down`)."""


def _releases(following: PlanStepRecord | None, held: Held | None) -> bool:
    """Whether `following` lets go of the tool `held` (the step after a contact's removal)."""
    return (
        following is not None
        and held is not None
        and following.op == "remove"
        and following.motion == "free"
        and following.body == held.body
    )


__all__ = ["ArmPathPlanner", "PendingTransit", "StraightPaths"]
