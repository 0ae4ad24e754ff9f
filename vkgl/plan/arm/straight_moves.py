"""The arm's straight moves around contacts: into a contact, back out of it, up after a grasp or a release.

Each move is a straight Cartesian path of the hand (`vkgl.motion.approach`:
chained IK, no joint jumps), checked against the bodies and the table where
the step has them (`vkgl.motion.arm_collision`), and timed at `CARTESIAN_SPEED`:

- **approach**: the last `STANDOFF` straight into the contact along its push
  direction, solved from the contact outward so that the arm arrives in the
  configuration the search checked. A tall body is thus approached from the
  side at contact height; a tool is grasped from above (`GRASP_STANDOFF`).
  When the way back along the push is blocked, the contact is approached from
  above instead: the fingertip hooked behind a handle's bar pushes away from
  the body it pulls, so backing off along its push would put the hand into
  that body; it comes down into the gap (and so does a held hook's
  cross-piece, behind a bar it pulls). When neither way works, it comes in
  slanted, along its push and `SLANT` down: the fingertip on the far face of
  a tall crate, the hand leaned outward at the edge of the arm's reach, has
  no room to back off 3 cm level, and coming straight down along the face
  would start the transit's goal within its clearance of it. A held tool
  comes down `TOOL_DESCENT` to its stand-off first. When all three rules
  fail, the ways of `vkgl.plan.arm.approaches.searched` are tried in turn (a
  cone about the push, from the side along a handle's bar, higher and lower,
  shorter and longer stand-offs), and a failure names what was tried.
- **retreat**: straight back out of a contact by `STANDOFF`, against the way
  it pushed (straight up when that way is blocked: a hook behind a handle's
  bar); out the way it came first when it came in from the side
  (`vkgl.motion.moves.way_out`). Execution leaves a plan's last contact by
  that rule, and `leave` checks it;
- **lift**: straight up `LIFT` after a grasp or a release.

The joint-space transit that brings the arm to an approach's first
configuration is planned by `vkgl.plan.arm.paths`, after the search; that
configuration is checked here, with the transit's clearance
(`GeometryCheck.transit_space`): an approach the transit could not end in
is rejected at once (kind "transit"), and the next way in is tried.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np

from vkgl.formats.plan import ArmSegment, PlanStepRecord
from vkgl.motion.approach import APPROACH_STEP, CartesianFailure, approach_poses, follow_poses
from vkgl.motion.arm_collision import ArmCollision, Held
from vkgl.motion.moves import CARTESIAN_SPEED, GRASP_STANDOFF, LIFT, STANDOFF, TOOL_DESCENT, WayOut, way_out
from vkgl.motion.timing import arm_velocity_limits, straight_times
from vkgl.plan.arm.approaches import DOWN, SLANT, Way, rules, searched, summary
from vkgl.plan.arm.remembered import Remembered, step_key
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.graphs.graph import is_grasp
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection

CONTACT_SLACK = 0.003
"""m: how deep a held tool may seem to overlap the body it pushes at the contact (its tip on the face) before
the contact itself counts as blocked."""


class Overlap(NamedTuple):
    """What the arm (or the tool in its hand) would overlap at a configuration (`StraightMoves.first_overlap`):
    in words, how deep (m), the scene's body it would overlap (none for the table), for `Rejection.bodies`, and
    the arm's link that overlaps it (empty when it is a held tool)."""

    words: str
    depth: float
    bodies: frozenset[str] = frozenset()
    link: str = ""


@dataclass
class ArmState:
    """Where the previous step left the arm: its joints, a tool in the hand, whether it must lift first, and how
    it leaves the contact it is in."""

    q: np.ndarray
    held: Held | None = None
    lift: bool = False
    entered: tuple[WayOut, np.ndarray] | None = None  # the contact the arm is in: how it leaves (`entered`)
    placed: str | None = None  # a body the open fingers are still around, set down on its place: lifted off

    def copy(self) -> ArmState:
        """The same state with joints of its own (a trial that may be dropped)."""
        return ArmState(np.asarray(self.q, dtype=float).copy(), self.held, self.lift, self.entered, self.placed)


@dataclass(frozen=True)
class Approach:
    """A way into a contact: the straight move's segment, from `pre_contact` (the joints a transit must reach),
    and the `way` it comes in."""

    pre_contact: np.ndarray
    segment: ArmSegment
    way: np.ndarray  # world, unit: the direction of its last straight move into the contact

    def copy(self) -> Approach:
        """The same approach with arrays of its own (a plan keeps its segment; another plan may keep the same)."""
        segment = replace(self.segment, times=self.segment.times.copy(), joints=self.segment.joints.copy())
        return Approach(self.pre_contact.copy(), segment, self.way.copy())


class StraightMoves:
    """The straight moves of one problem's arm, checked with `geometry`'s collision world."""

    def __init__(self, problem: Problem, geometry: GeometryCheck) -> None:
        """Moves for `problem`'s arm among its bodies."""
        self.problem = problem
        self.geometry = geometry
        self._approaches: Remembered[Approach | Rejection] = Remembered()

    def into_contact(self, step: PlanStepRecord, state: ArmState, label: str) -> Approach | Rejection:
        """The straight approach into the step's contact (`solved_into_contact`), remembered by what it depends
        on (`remembered.step_key`: the step, the tool in the hand, the label): candidates share steps."""
        key = step_key(step, state.held, label)
        found = self._approaches.get(key)
        if found is None:
            found = self._approaches.keep(key, self.solved_into_contact(step, state, label))
        return found.copy() if isinstance(found, Approach) else found

    def solved_into_contact(self, step: PlanStepRecord, state: ArmState, label: str) -> Approach | Rejection:
        """The straight approach into the step's contact.

        A push is approached by the three rules (`approaches.rules`): along its push direction; when that way
        is blocked (a hook behind a handle's bar would back into the body it pulls), from above, down into the
        contact (the gap behind the bar); when that fails too, slanted: along the push and `SLANT` down (the
        stand-off above and behind). When all three fail, the searched ways (`approaches.searched`: a cone
        about the push, from the side along a handle's bar, higher and lower, shorter and longer stand-offs),
        in order; when none works, the reason says which were tried and which came closest.
        """
        if step.motion == "free":  # a grasp of a free body: from above, as it lies
            return self.approach(step, state, label, DOWN, GRASP_STANDOFF)
        if self.grasps(step):  # a handle's grasp: along the hand's axis (from the side for a bar held level)
            return self.approach(step, state, label, self.hand_axis(step), GRASP_STANDOFF)
        push = self.push_direction(step, step.poses_start)
        tried: list[Way] = []
        closest: tuple[float, str, frozenset[str]] | None = None
        kind = Kind.APPROACH  # the first rule's failure's: a stand-off the transit cannot end in, or no way in
        for way in rules(push):
            found = self._approach(step, state, label, way.direction, way.standoff)
            if not isinstance(found, tuple):
                return found
            if not tried:
                kind = found[0].kind
                if kind not in (Kind.APPROACH, Kind.TRANSIT):
                    return found[0]
            tried.append(way)
            closest = _closer(closest, way, found, label)
        hopeless = self.tool_overlap_at_contact(step, state)
        if hopeless is not None:
            why = f"{label}: at the contact itself {hopeless.words}: no way into it can be clear"
            return Rejection(Kind.APPROACH, why, hopeless.depth, bodies=hopeless.bodies)
        for way in searched(push):
            found = self._approach(step, state, label, way.direction, way.standoff)
            if not isinstance(found, tuple):
                return found
            tried.append(way)
            closest = _closer(closest, way, found, label)
        assert closest is not None  # the rules were tried
        why = f"{label}: no straight approach into the contact ({summary(tried)}; closest: {closest[1]})"
        # how far it missed: the shallowest overlap of a blocked way (the search reports the closest miss)
        return Rejection(kind, why, closest[0] if np.isfinite(closest[0]) else 1.0, bodies=closest[2])

    def tool_overlap_at_contact(self, step: PlanStepRecord, state: ArmState) -> Overlap | None:
        """What a held tool overlaps, deeper than `CONTACT_SLACK`, at the contact itself (its tip touches the
        body it pushes; the rest of it must clear that body): no way into such a contact is clear. None for the
        bare hand (the contact's own checks cover it) or when the tool only touches."""
        if state.held is None:
            return None
        clash = self.first_overlap(np.asarray([step.q_start]), step.poses_start, state.held, set(), {step.body})
        return clash if clash is not None and clash.depth > CONTACT_SLACK else None

    def approach(
        self, step: PlanStepRecord, state: ArmState, label: str, direction: np.ndarray, standoff: float
    ) -> Approach | Rejection:
        """Straight along `direction` into the contact from `standoff` back (a held tool first comes down)."""
        found = self._approach(step, state, label, direction, standoff)
        return found[0] if isinstance(found, tuple) else found

    def _approach(
        self, step: PlanStepRecord, state: ArmState, label: str, direction: np.ndarray, standoff: float
    ) -> Approach | tuple[Rejection, float]:
        """`approach`, a failure with how far it missed: the overlap (m) of a blocked way, infinite otherwise."""
        grasp = self.grasps(step)
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
            why = f"{label}: no straight approach into the contact ({outward.reason})"
            return Rejection(Kind.APPROACH, why, 1.0), float("inf")
        joints = outward.joints[::-1].copy()
        joints[-1] = step.q_start
        # the gripper closes around a tool it grasps; a pushing hand must clear the body it pushes until contact
        ignore = {step.body} if grasp else set()
        clash = self.first_overlap(joints[:-1], step.poses_start, state.held, ignore, {step.body})
        if clash is not None:
            why = f"{label}: the straight approach into the contact is blocked: {clash.words}"
            return Rejection(Kind.APPROACH, why, 1.0, bodies=clash.bodies), clash.depth
        # the transit planned later must end here: with room to spare, or another way in is tried
        space = self.geometry.transit_space(state.held, step.body)
        clash = self.first_overlap(joints[:1], step.poses_start, state.held, set(), collision=space)
        if clash is not None:
            why = f"{label}: no collision-free way for the arm to the contact: at the goal of the transit {clash.words}"
            return Rejection(Kind.TRANSIT, why, 1.0, bodies=clash.bodies), float("inf")
        way = np.asarray(direction, dtype=float)
        return Approach(joints[0].copy(), self.straight("approach", joints, length), way)

    def entered(self, step: PlanStepRecord, approach: Approach) -> tuple[WayOut, np.ndarray]:
        """How the arm will leave the contact `approach` makes (`vkgl.motion.moves.way_out`), and the way it came
        in turned with the pushed body to the end of the step's motion (where a reverse retreat backs out)."""
        rule = way_out(approach.way, self.push_direction(step, step.poses_start))
        turn = step.poses_end[step.body][:3, :3] @ step.poses_start[step.body][:3, :3].T
        return rule, turn @ approach.way

    def leave(self, step: PlanStepRecord, state: ArmState, label: str) -> Rejection | None:
        """Why the arm could not leave the plan's last contact as execution leaves it, or None. Nothing is added
        to the plan: a plan ends in its last contact, and execution breaks it (`vkgl.execute.steps.let_go`) by
        the rule of the way it came in (`vkgl.motion.moves.way_out`): straight up after coming down into it;
        straight back against the push (straight up where the arm has no straight path back), then up; or back
        out the way it came, then up."""
        rule, way = state.entered or ("back", None)
        after = ArmState(np.asarray(state.q, dtype=float).copy(), state.held, False)
        label, poses = f"{label}, at the end", step.poses_end
        what = ("retreat", "no straight retreat from the contact", "the straight retreat from the contact is blocked")
        held = step.body if self.grasps(step) else None  # the opened fingers slide off the body they held
        if rule == "reverse" and way is not None:
            out = self._move_away(after, -way, STANDOFF, poses, {step.body}, label, what, grasped=held)
        else:
            back = -self.push_direction(step, poses) if rule == "back" else -DOWN
            out = self._move_away(after, back, STANDOFF, poses, {step.body}, label, what, grasped=held)
            if isinstance(out, tuple) and not out[1]:  # no straight path back: execution goes up instead
                out = self._move_away(after, -DOWN, STANDOFF, poses, {step.body}, label, what, grasped=held)
        if isinstance(out, tuple):
            return out[0]
        lift = self.lift(after, poses, label)
        return lift if isinstance(lift, Rejection) else None

    def retreat(
        self, step: PlanStepRecord, state: ArmState, label: str, poses: Mapping[str, np.ndarray] | None = None
    ) -> ArmSegment | Rejection:
        """Straight back out of the contact the step removes, with the bodies at `poses` (the step's start by
        default): out the way it came in when that was neither along the push nor from above
        (`vkgl.motion.moves.way_out`), else (or when that is blocked) against the way it pushed; when that is
        blocked too (a fingertip or a held hook behind a handle's bar), straight up."""
        poses = step.poses_start if poses is None else poses
        rule, way = state.entered or ("back", None)
        state.entered = None
        what = ("retreat", "no straight retreat from the contact", "the straight retreat from the contact is blocked")
        grasped = step.body if self.grasps(step) else None  # the opened fingers slide off the body they held
        if rule == "reverse" and way is not None:
            reverse = self.move_away(state, -way, STANDOFF, poses, {step.body}, label, what, grasped=grasped)
            if not isinstance(reverse, Rejection):
                return reverse
        away = -self.push_direction(step, poses)
        first = self.move_away(state, away, STANDOFF, poses, {step.body}, label, what, grasped=grasped)
        if not isinstance(first, Rejection):
            return first
        above = self.move_away(state, -DOWN, STANDOFF, poses, {step.body}, label, what, grasped=grasped)
        return first if isinstance(above, Rejection) else above

    def lift(self, state: ArmState, poses: Mapping[str, np.ndarray], label: str) -> ArmSegment | Rejection:
        """Straight up `LIFT` from where the arm is (after a grasp or a release); the open fingers may touch a
        body just set down on its place (`ArmState.placed`: a held tool's grasp has them around its handle)."""
        what = ("lift", "the hand cannot rise straight up", "the way straight up is blocked")
        placed, state.placed = state.placed, None
        return self.move_away(state, -DOWN, LIFT, poses, set(), label, what, grasped=placed)

    def move_away(
        self,
        state: ArmState,
        way: np.ndarray,
        length: float,
        poses: Mapping[str, np.ndarray],
        pad_may_touch: set[str],
        label: str,
        what: tuple[str, str, str],
        *,
        grasped: str | None = None,
    ) -> ArmSegment | Rejection:
        """A straight move of the hand by `length` along `way` from where the arm is; `what`: the segment's
        phase and the words for no IK path and for a blocked one. The arm's joints end at its last pose.
        `grasped`: a body the fingers held (they may touch it, `grasp_overlap`)."""
        found = self._move_away(state, way, length, poses, pad_may_touch, label, what, grasped=grasped)
        return found[0] if isinstance(found, tuple) else found

    def _move_away(
        self,
        state: ArmState,
        way: np.ndarray,
        length: float,
        poses: Mapping[str, np.ndarray],
        pad_may_touch: set[str],
        label: str,
        what: tuple[str, str, str],
        *,
        grasped: str | None = None,
    ) -> ArmSegment | tuple[Rejection, bool]:
        """`move_away`; a failure says whether the way was blocked (True) or had no straight IK path (False)."""
        phase, no_path, blocked = what
        start = self.problem.arm.fk(state.q)
        out = approach_poses(start, length, APPROACH_STEP, -way)[::-1]  # from `start` to `length` along `way`
        path = follow_poses(self.problem.arm, out, state.q)
        if isinstance(path, CartesianFailure):
            return Rejection(Kind.APPROACH, f"{label}: {no_path} ({path.reason})", 1.0), False
        joints = path.joints.copy()
        joints[0] = state.q
        if grasped is not None:
            clash = self.grasp_overlap(joints[1:], poses, state.held, grasped)
        else:
            clash = self.first_overlap(joints[1:], poses, state.held, set(), pad_may_touch)
        if clash is not None:
            return Rejection(Kind.APPROACH, f"{label}: {blocked}: {clash.words}", 1.0, bodies=clash.bodies), True
        state.q = joints[-1]
        return self.straight(phase, joints, length)

    def grasps(self, step: PlanStepRecord) -> bool:
        """Whether the step's contact is a grasp (`vkgl.plan.graphs.graph.is_grasp`): the fingers close on it."""
        _, _, name = step.affordance.partition(".")
        return is_grasp(self.problem, step.body, name)

    def hand_axis(self, step: PlanStepRecord) -> np.ndarray:
        """The world direction the hand points at the step's contact (the effector frame's -z: the frame's z is
        up when the hand points down), the way it comes into a grasp."""
        return -np.asarray(self.problem.arm.fk(step.q_start)[:3, 2], dtype=float)

    def push_direction(self, step: PlanStepRecord, poses: Mapping[str, np.ndarray]) -> np.ndarray:
        """The world direction the step's contact pushes along: the x axis of its action frame on the body."""
        _, _, name = step.affordance.partition(".")
        pusher = poses[step.body] @ self.problem.action(step.body, name)
        return np.asarray(pusher[:3, 0], dtype=float)

    def first_overlap(
        self,
        joints: np.ndarray,
        poses: Mapping[str, np.ndarray],
        held: Held | None,
        ignore: set[str],
        pad_may_touch: set[str] | None = None,
        collision: ArmCollision | None = None,
    ) -> Overlap | None:
        """What the arm (or a held tool) would overlap at the first blocked configuration of `joints`, in words,
        how deep (m) and which body; None when nothing is blocked.

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
            link = "" if deepest.body_a in collision.scene.names else deepest.body_a
            what = f"the arm's {link}" if link else deepest.body_a
            words = f"{what} would overlap {deepest.body_b} by {deepest.depth * 100:.1f} cm"
            bodies = frozenset({deepest.body_b}) & self.problem.bodies.keys()
            return Overlap(words, deepest.depth, bodies, link)
        return None

    def grasp_overlap(
        self, joints: np.ndarray, poses: Mapping[str, np.ndarray], held: Held | None, body: str
    ) -> Overlap | None:
        """`first_overlap` of a hand whose fingers close on `body`: the whole arm against everything else, and
        the arm but its fingers (`GeometryCheck.palm_collision`) against `body` too."""
        clash = self.first_overlap(joints, poses, held, {body})
        if clash is not None:
            return clash
        palm = self.geometry.palm_collision
        others = set(palm.scene.names) - {body}
        return self.first_overlap(joints, poses, None, others, {body}, collision=palm)

    def straight(self, phase: str, joints: np.ndarray, length: float) -> ArmSegment:
        """A straight Cartesian move of `length` (m) through `joints` (evenly spaced poses), at `CARTESIAN_SPEED`
        where every joint stays within its share of its velocity limit (`vkgl.motion.timing.straight_times`)."""
        joints = np.asarray(joints, dtype=float)
        times = straight_times(joints, length, CARTESIAN_SPEED, arm_velocity_limits(self.problem.arm))
        return ArmSegment(phase, times, joints)


__all__ = [
    "CARTESIAN_SPEED",
    "DOWN",
    "GRASP_STANDOFF",
    "LIFT",
    "SLANT",
    "STANDOFF",
    "TOOL_DESCENT",
    "Approach",
    "ArmState",
    "Overlap",
    "StraightMoves",
]


def _closer(
    closest: tuple[float, str, frozenset[str]] | None, way: Way, found: tuple[Rejection, float], label: str
) -> tuple[float, str, frozenset[str]]:
    """The closer of two misses (how deep, in words, the bodies in the way): the shallower overlap of a blocked
    way; among others the first."""
    rejection, depth = found
    if closest is not None and closest[0] <= depth:
        return closest
    return depth, f"{way.name}: {rejection.why.removeprefix(label + ': ')}", rejection.bodies
