"""The arm's paths between contacts: lift, retreat, transit and approach, planned for every step of a plan.

A plan step's action (make a contact and move with it, grasp a tool, let go,
put a tool down) needs the arm to get there first. For each step this module
plans, from where the previous step left the arm:

- **lift**: after a grasp or a release, straight up `LIFT` (the hand or the
  held tool leaves the table before anything else);
- **retreat** (a REMOVE of a push): straight back out of the contact by
  `STANDOFF`, against the direction the contact pushed (straight up when that
  way is blocked: a hook behind a handle's bar);
- **transit**: a collision-free joint-space path (`vkgl.plan.transit`: the
  straight line when it is clear, else OMPL's RRTConnect) to the step's
  pre-contact configuration; valid means the arm's links and a held tool
  clear every body and the table (`vkgl.plan.arm_collision`);
- **approach**: the last `STANDOFF` straight into the contact along its push
  direction (`vkgl.plan.approach`, chained IK from the contact outward, so the
  arm arrives in the configuration the search checked). A tall body is thus
  approached from the side at contact height; a tool is grasped from above
  (`GRASP_STANDOFF`). When the way back along the push is blocked, the
  contact is approached from above instead: the fingertip hooked behind a
  handle's bar pushes away from the body it pulls, so backing off along its
  push would put the hand into that body; it comes down into the gap (and so
  does a held hook's cross-piece, behind a bar it pulls). When neither way
  works, it comes in slanted, along its push and `SLANT` down: the fingertip
  on the far face of a tall crate, the hand leaned outward at the edge of the
  arm's reach, has no room to back off 3 cm level, and coming straight down
  along the face would start the transit's goal within its clearance of it.

Every segment is timed: transits within the URDF's joint velocity limits
(scaled by `TRANSIT_SPEED_SCALE`), the straight moves at `CARTESIAN_SPEED`.
The search calls `ArmPathPlanner.plan` on every candidate that passed the
other checks, so a plan whose contact cannot be approached is rejected there
(kinds "approach" and "transit"), not discovered in physics. Deterministic:
transit `k` of a plan is seeded with `k`.
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TypeVar

import numpy as np
from scipy.spatial.transform import Rotation

from vkgl.formats.plan import ArmSegment, PlanStepRecord
from vkgl.plan.approach import APPROACH_STEP, CartesianFailure, approach_poses, follow_poses
from vkgl.plan.arm_collision import ArmCollision, Held
from vkgl.plan.geometry_check import GeometryCheck
from vkgl.plan.model import Problem
from vkgl.plan.reach import Rejection
from vkgl.plan.transit import TransitFailure
from vkgl.plan.transit_segment import TRANSIT_TIME_LIMIT, transit_segment
from vkgl.robot.pad import FINGERTIP_RADIUS
from vkgl.se3 import screw_motion

STANDOFF = 0.03
"""m: the pre-contact pose is this far back from the contact, against its push direction."""

GRASP_STANDOFF = 0.05
"""m: a tool is grasped from this high above its grasp frame, straight down."""

LIFT = 0.04
"""m: the hand rises this much after a grasp or a release, before it moves on."""

TOOL_DESCENT = 0.03
"""m: a held tool comes straight down this much to its stand-off before its straight approach."""

CARTESIAN_SPEED = 0.03
"""m/s of the effector on the straight moves (approach, retreat, lift): slow, as they start or end in contact."""

CHAIN_SPACING = 0.01
"""m of hand travel between two checked configurations of a contact's motion."""

CHAIN_LEVER = 0.2
"""m: a turn of the hand counts as this lever arm times its angle, for `CHAIN_SPACING`."""

SLANT = np.radians(30.0)
"""rad: below the push direction, the last way tried into a contact (after along the push and from above);
less than 45 deg, so that execution leaves such a contact straight back, as `ArmPathPlanner._leave` checks."""

PITCHES = tuple(np.radians((0.0, 30.0, 45.0, 60.0)))
"""rad: how far the hand may lean back from upright at a contact (tried in turn)."""

StepT = TypeVar("StepT", bound=PlanStepRecord)

DOWN = np.array([0.0, 0.0, -1.0])


@dataclass
class _ArmState:
    """Where the previous step left the arm: its joints, a tool in the hand, whether it must lift first."""

    q: np.ndarray
    held: Held | None = None
    lift: bool = False


class ArmPathPlanner:
    """Plans the arm's segments for the steps of one problem's plans (built once per search)."""

    def __init__(self, problem: Problem, geometry: GeometryCheck) -> None:
        """Paths for `problem`'s arm, checked with `geometry`'s collision world."""
        self.problem = problem
        self.geometry = geometry
        self.transits = 0
        self.seconds = 0.0
        self.transit_seconds = 0.0  # of `seconds`, in transit planning (the rest: IK of straight moves, checks)

    def plan(
        self,
        steps: Sequence[StepT],
        q_start: np.ndarray | None = None,
        *,
        deadline: float | None = None,
    ) -> list[StepT] | Rejection:
        """The steps with their `path` (the segments before each step's action), or why one cannot be planned.

        A contact whose arm configuration cannot carry the whole motion (the
        arm would have to switch configuration in contact) gets one that can:
        the returned steps' `q_start`/`q_end` may differ from the given ones.
        `q_start`: the arm's joints before the first step (the arm's home by default).
        """
        began = time.perf_counter()
        try:
            state = _ArmState(np.asarray(self.problem.arm.home if q_start is None else q_start, dtype=float))
            out = []
            for k, step in enumerate(steps, start=1):
                following = steps[k] if k < len(steps) else None
                planned = self._planned_step(k, step, state, deadline, last=following is None, following=following)
                if isinstance(planned, Rejection):
                    return planned
                out.append(planned)
            return out
        finally:
            self.seconds += time.perf_counter() - began

    def _planned_step(
        self,
        k: int,
        step: StepT,
        state: _ArmState,
        deadline: float | None,
        *,
        last: bool = False,
        following: PlanStepRecord | None = None,
    ) -> StepT | Rejection:
        """The step with its path; a contact tries each arm configuration that carries its motion in turn,
        until one can be approached (and, for the `last` step, left again). A release happens where the
        arm is (its `q_start`/`q_end` become those joints)."""
        if step.op != "add" or step.motion == "free":
            q_before = state.q
            found = self._step(k, step, state, deadline, releases_next=_releases(following, state.held))
            if isinstance(found, Rejection):
                return found
            if step.op == "remove" and step.motion == "free":
                return replace(step, path=found, q_start=q_before, q_end=q_before)
            return replace(step, path=found)
        label = f"step {k} ({step.title()})"
        first: Rejection | None = None
        for chain in self._contact_chain(step, state, label):
            if isinstance(chain, Rejection):
                return first or chain
            attempt = _ArmState(state.q.copy(), state.held, state.lift)
            # the whole chain goes into the plan: execution follows this configuration, not one of its own
            moved = replace(step, q_start=chain[0], q_end=chain[-1], contact=chain)
            found = self._step(k, moved, attempt, deadline)
            if not isinstance(found, Rejection) and last:
                found = self._leave(moved, attempt, label) or found
            if not isinstance(found, Rejection):
                state.q, state.held, state.lift = attempt.q, attempt.held, attempt.lift
                return replace(moved, path=found)
            first = first or found
            if found.kind != "approach":
                return found
        return first or Rejection("ik", f"{label}: no arm configuration carries the whole motion", 1.0)

    def _contact_chain(self, step: PlanStepRecord, state: _ArmState, label: str) -> Iterator[np.ndarray | Rejection]:
        """Joints every `CHAIN_SPACING` along a contact's motion, in one arm configuration from start to end.

        The plan's configuration at the contact first; if the arm would have
        to switch configuration on the way (a joint jump: IK branch switch) or
        its links hit the body it pushes (the hand of a vertical gripper
        overhangs the pad by 2.5 cm, so it meets a face more than about 4 cm
        above the contact), IK from the arm's home, then the hand pitched back about the pad's axis by
        `PITCHES` (the pad touches the face the same way, the hand leans away
        from it).
        """
        arm = self.problem.arm
        motion = screw_motion(step.poses_start[step.body], step.poses_end[step.body])
        upright = arm.fk(step.q_start)
        if step.effector == self.problem.robot_effector.name:
            # the pad pushes flat on the face only when it lies along it: the action frame's yaw, not whatever
            # yaw IK chose where the search let the hand's yaw free
            _, _, name = step.affordance.partition(".")
            upright = step.poses_start[step.body] @ self.problem.action(step.body, name)
        turn = float(np.linalg.norm(motion.rotvec))
        end = motion.at(1.0)
        travel = float(np.linalg.norm(end[:3, :3] @ upright[:3, 3] + end[:3, 3] - upright[:3, 3]))
        count = max(2, int(np.ceil(max(travel, turn * CHAIN_LEVER) / CHAIN_SPACING)) + 1)
        first: str | None = None
        # leaning the hand back keeps the pad where it is, but would turn a tool held in the hand
        for pitch in PITCHES if state.held is None else PITCHES[:1]:
            hand = upright @ _pitched_back(pitch)
            poses = [motion.at(s) @ hand for s in np.linspace(0.0, 1.0, count)]
            for seed in (step.q_start, arm.home):
                q0 = arm.ik(hand, q0=seed)
                if q0 is None:
                    # IK restarts from home and the same fixed seeds after the given one: from home it would
                    # fail again (19 local runs for nothing)
                    break
                chain = follow_poses(arm, poses, q0)
                if isinstance(chain, CartesianFailure):
                    first = first or chain.reason
                    continue
                clash = self._contact_clash(step, state, chain.joints[0], chain.joints[-1])
                if clash is not None:
                    first = first or clash
                    continue
                yield chain.joints.copy()
        yield Rejection("ik", f"{label}: no arm configuration carries the whole motion ({first})", 1.0)

    def _contact_clash(
        self, step: PlanStepRecord, state: _ArmState, q_start: np.ndarray, q_end: np.ndarray
    ) -> str | None:
        """What the arm hits at the start or end of a contact's motion (only the pad may touch the pushed body)."""
        held = state.held
        if held is not None:
            held = Held(held.body, held.in_hand, frozenset({step.body}))
        for q, poses in ((q_start, step.poses_start), (q_end, step.poses_end)):
            clash = self._first_clash(np.asarray([q]), poses, held, set(), {step.body})
            if clash is not None:
                return f"at the contact {clash}"
        return None

    # ------------------------------------------------------------ step kinds

    def _step(
        self, k: int, step: PlanStepRecord, state: _ArmState, deadline: float | None, *, releases_next: bool = False
    ) -> tuple[ArmSegment, ...] | Rejection:
        label = f"step {k} ({step.title()})"
        segments: list[ArmSegment] = []
        if state.lift:
            lift = self._lift(state, step.poses_start, label)
            if isinstance(lift, Rejection):
                return lift
            segments.append(lift)
            state.lift = False
        if step.op == "remove" and step.motion != "free" and releases_next:
            # the tool is let go of where it touched (where the search leaves it), and the hand lifts from there:
            # backing the tool out first would put it down a stand-off away from where the plan says it lies
            return tuple(segments)
        if step.op == "remove" and step.motion != "free":
            retreat = self._retreat(step, state, label)
            if isinstance(retreat, Rejection):
                return retreat
            return (*segments, retreat)
        if step.op == "remove":  # a release: the tool stays where the plan put it; the hand lifts next
            state.held, state.lift = None, True
            return tuple(segments)
        found = self._reach_contact(k, step, state, label, deadline)
        if isinstance(found, Rejection):
            return found
        segments.extend(found)
        if step.motion == "free":  # a grasp: the tool rides in the hand from here on
            in_hand = np.linalg.inv(self.problem.arm.fk(step.q_start)) @ step.poses_start[step.body]
            state.held, state.lift = Held(step.body, in_hand), True
        state.q = np.asarray(step.q_end, dtype=float)
        return tuple(segments)

    def _reach_contact(
        self, k: int, step: PlanStepRecord, state: _ArmState, label: str, deadline: float | None
    ) -> list[ArmSegment] | Rejection:
        """Transit to the step's pre-contact configuration, then the straight approach into the contact.

        A push is approached along its push direction; when that way is blocked (a hook behind a handle's
        bar would back into the body it pulls), from above, down into the contact (the gap behind the bar);
        when that fails too, slanted: along the push and `SLANT` down (the stand-off above and behind).
        """
        grasp = step.motion == "free"
        if grasp:
            return self._approach(k, step, state, label, deadline, DOWN, GRASP_STANDOFF)
        push = self._push_direction(step, step.poses_start)
        first = self._approach(k, step, state, label, deadline, push, STANDOFF)
        if not isinstance(first, Rejection) or first.kind != "approach":
            return first
        slanted = np.cos(SLANT) * push + np.sin(SLANT) * DOWN
        for way in (DOWN, slanted / np.linalg.norm(slanted)):
            found = self._approach(k, step, state, label, deadline, way, STANDOFF)
            if not isinstance(found, Rejection):
                return found
        return first

    def _approach(
        self,
        k: int,
        step: PlanStepRecord,
        state: _ArmState,
        label: str,
        deadline: float | None,
        direction: np.ndarray,
        standoff: float,
    ) -> list[ArmSegment] | Rejection:
        """Transit to `standoff` back from the contact against `direction`, then straight along it into the contact."""
        grasp = step.motion == "free"
        contact = self.problem.arm.fk(step.q_start)
        poses = approach_poses(contact, standoff, APPROACH_STEP, direction)
        length = standoff
        if state.held is not None:
            # a tool works at table height: it comes down to its stand-off first, so that the transit
            # ends clear of the table (a joint-space line between two poses at table height dips into it)
            poses = approach_poses(poses[0], TOOL_DESCENT, APPROACH_STEP, DOWN)[:-1] + poses
            length += TOOL_DESCENT
        # solved from the contact outward, so the arm arrives in the configuration the search checked
        outward = follow_poses(self.problem.arm, poses[::-1], step.q_start)
        if isinstance(outward, CartesianFailure):
            return Rejection("approach", f"{label}: no straight approach into the contact ({outward.reason})", 1.0)
        joints = outward.joints[::-1].copy()
        joints[-1] = step.q_start
        # the gripper closes around a tool it grasps; a pushing hand must clear the body it pushes until contact
        ignore = {step.body} if grasp else set()
        clash = self._first_clash(joints[:-1], step.poses_start, state.held, ignore, {step.body})
        if clash is not None:
            return Rejection("approach", f"{label}: the straight approach into the contact is blocked: {clash}", 1.0)
        transit = self._transit(k, state, joints[0], step.poses_start, label, deadline)
        if isinstance(transit, Rejection):
            return transit
        return [transit, self._straight("approach", joints, length)]

    def _leave(self, step: PlanStepRecord, state: _ArmState, label: str) -> Rejection | None:
        """Why the arm could not leave the plan's last contact as execution leaves it (straight back out of it,
        or up where that is blocked, then up), or None. Nothing is added to the plan: a plan ends in its last
        contact, and execution breaks it with that move (`vkgl.execute.steps`)."""
        after = _ArmState(np.asarray(state.q, dtype=float).copy(), state.held, False)
        retreat = self._retreat(replace(step, poses_start=step.poses_end), after, f"{label}, at the end")
        if isinstance(retreat, Rejection):
            return retreat
        lift = self._lift(after, step.poses_end, f"{label}, at the end")
        return lift if isinstance(lift, Rejection) else None

    def _retreat(self, step: PlanStepRecord, state: _ArmState, label: str) -> ArmSegment | Rejection:
        """Straight back out of the contact the step removes, against the way it pushed; when that way is
        blocked (a fingertip or a held hook behind a handle's bar), straight up."""
        away = -self._push_direction(step, step.poses_start)
        what = ("retreat", "no straight retreat from the contact", "the straight retreat from the contact is blocked")
        first = self._move_away(state, away, STANDOFF, step.poses_start, {step.body}, label, what)
        if not isinstance(first, Rejection):
            return first
        above = self._move_away(state, -DOWN, STANDOFF, step.poses_start, {step.body}, label, what)
        return first if isinstance(above, Rejection) else above

    def _lift(self, state: _ArmState, poses: Mapping[str, np.ndarray], label: str) -> ArmSegment | Rejection:
        """Straight up `LIFT` from where the arm is (after a grasp or a release)."""
        what = ("lift", "the hand cannot rise straight up", "the way straight up is blocked")
        return self._move_away(state, -DOWN, LIFT, poses, set(), label, what)

    def _move_away(
        self,
        state: _ArmState,
        way: np.ndarray,
        length: float,
        poses: Mapping[str, np.ndarray],
        pad_may_touch: set[str],
        label: str,
        what: tuple[str, str, str],
    ) -> ArmSegment | Rejection:
        """A straight move of the hand by `length` along `way` from where the arm is; `what`: the segment's
        phase and the words for no IK path and for a blocked one. The arm's joints end at its last pose."""
        phase, no_path, blocked = what
        start = self.problem.arm.fk(state.q)
        out = approach_poses(start, length, APPROACH_STEP, -way)[::-1]  # from `start` to `length` along `way`
        path = follow_poses(self.problem.arm, out, state.q)
        if isinstance(path, CartesianFailure):
            return Rejection("approach", f"{label}: {no_path} ({path.reason})", 1.0)
        joints = path.joints.copy()
        joints[0] = state.q
        clash = self._first_clash(joints[1:], poses, state.held, set(), pad_may_touch)
        if clash is not None:
            return Rejection("approach", f"{label}: {blocked}: {clash}", 1.0)
        state.q = joints[-1]
        return self._straight(phase, joints, length)

    def _transit(
        self,
        k: int,
        state: _ArmState,
        goal: np.ndarray,
        poses: Mapping[str, np.ndarray],
        label: str,
        deadline: float | None,
    ) -> ArmSegment | Rejection:
        limit = TRANSIT_TIME_LIMIT
        if deadline is not None:
            limit = max(0.05, min(limit, deadline - time.perf_counter()))
        self.transits += 1
        # a held tool works close to the body it acts on (a hook's shaft along the block it pulls): its transits
        # keep no clearance beyond the exact geometry; the bare arm's keep `TRANSIT_CLEARANCE`
        collision = self.geometry.transit_collision if state.held is None else self.geometry.arm_collision
        began = time.perf_counter()
        found = transit_segment(collision, state.q, goal, poses, state.held, seed=k, time_limit=limit)
        self.transit_seconds += time.perf_counter() - began
        if isinstance(found, TransitFailure):
            blocker = self._blocker(found.reason, state.q, goal, state.held)
            return Rejection("transit", f"{label}: no collision-free way for the arm to the contact: {blocker}", 1.0)
        return found

    # ------------------------------------------------------------ helpers

    def _push_direction(self, step: PlanStepRecord, poses: Mapping[str, np.ndarray]) -> np.ndarray:
        """The world direction the step's contact pushes along: the x axis of its action frame on the body."""
        _, _, name = step.affordance.partition(".")
        pusher = poses[step.body] @ self.problem.action(step.body, name)
        return np.asarray(pusher[:3, 0], dtype=float)

    def _first_clash(
        self,
        joints: np.ndarray,
        poses: Mapping[str, np.ndarray],
        held: Held | None,
        ignore: set[str],
        pad_may_touch: set[str] | None = None,
        collision: ArmCollision | None = None,
    ) -> str | None:
        """What the arm (or a held tool) would overlap at the first blocked configuration of `joints`, or None.

        `ignore`: bodies nothing of the arm is checked against; `pad_may_touch`: bodies only the fingertip pad
        may touch (the one a straight approach or retreat pushes: its yaw about the push direction is free).
        """
        collision = collision or self.geometry.arm_collision
        collision.scene.place(poses)
        pad = pad_may_touch or set()
        for q in joints:
            if collision.free(q, ignore=ignore, held=held, pad_may_touch=pad):
                continue
            found = collision.overlap(q, ignore=ignore, held=held, pad_may_touch=pad)
            if not found:
                continue
            deepest = max(found, key=lambda c: c.depth)
            what = deepest.body_a if deepest.body_a in collision.scene.names else f"the arm's {deepest.body_a}"
            return f"{what} would overlap {deepest.body_b} by {deepest.depth * 100:.1f} cm"
        return None

    def _blocker(self, reason: str, start: np.ndarray, goal: np.ndarray, held: Held | None) -> str:
        """The transit's failure in words, naming what blocks an end configuration when one is blocked."""
        for name, q in (("start", start), ("goal", goal)):
            clash = self._first_clash(np.asarray([q]), {}, held, set(), collision=self.geometry.transit_collision)
            if clash is not None:
                return f"at the {name} of the transit {clash}"
        return reason

    def _straight(self, phase: str, joints: np.ndarray, length: float) -> ArmSegment:
        """A straight Cartesian move of `length` (m) through `joints` (evenly spaced poses), at `CARTESIAN_SPEED`."""
        count = len(joints) - 1
        times = np.linspace(0.0, max(length / CARTESIAN_SPEED, 1e-3), count + 1) if count else np.zeros(1)
        return ArmSegment(phase, times, np.asarray(joints, dtype=float))


def _releases(following: PlanStepRecord | None, held: Held | None) -> bool:
    """Whether `following` lets go of the tool `held` (the step after a contact's removal)."""
    return (
        following is not None
        and held is not None
        and following.op == "remove"
        and following.motion == "free"
        and following.body == held.body
    )


def _pitched_back(angle: float) -> np.ndarray:
    """The effector frame turned by `angle` about the pad's axis (the frame's y through the pad's centre),
    leaning the hand away from the face it pushes (the frame's z toward -x)."""
    about = np.eye(4)
    about[:3, :3] = Rotation.from_euler("y", -angle).as_matrix()
    to_axis = np.eye(4)
    to_axis[0, 3] = -FINGERTIP_RADIUS
    return to_axis @ about @ np.linalg.inv(to_axis)


__all__ = [
    "CARTESIAN_SPEED",
    "GRASP_STANDOFF",
    "LIFT",
    "STANDOFF",
    "ArmPathPlanner",
]
