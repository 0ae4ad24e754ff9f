"""A contact's arm configurations: joints along its whole motion, in one configuration from start to end.

The search solved the arm's joints at the start and end of each mode
(`vkgl.plan.task_space.joint_space`); a contact's motion must also be carried
without a switch of configuration (a joint jump in contact) and with no link
hitting a body on the way. `ContactChains.solve` gives the chains that do, in
turn (`vkgl.plan.arm.paths` takes the first whose approach works):

1. from the plan's configuration at the contact, then from IK started at the
   arm's home, with the hand upright and then leaned back by `PITCHES`;
2. only when none of those does, from the arm's other configurations at the
   contact: IK from its spread seeds (`Arm.spread_seeds`), each distinct answer
   once. Without them, a contact whose chain from home broke was found only
   after another contact had left the arm elsewhere, so that the joint-space
   IK started from there: gen1_024 of the physical bench planned a 0 cm push
   (and its release) before the arc push it needed (docs/planning.md,
   "A step that moves nothing").
3. for a grasped handle, instead of 2, chains solved backwards from the motion's end from the spread seeds.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from vkgl.formats.plan import PlanStepRecord
from vkgl.motion.approach import CartesianFailure, follow_poses
from vkgl.plan.arm.straight_moves import ArmState, Overlap, StraightMoves
from vkgl.plan.problem.problem import Problem
from vkgl.plan.problem.rejection import Kind, Rejection
from vkgl.robot.pad import FINGERTIP_RADIUS, turned_pad
from vkgl.rotations import axis_matrix
from vkgl.se3 import screw_motion

CHAIN_SPACING = 0.01
"""m of hand travel between two checked configurations of a contact's motion."""

CLASH_PARTS = 4
"""Each interval between two configurations of a contact's chain is checked against the bodies at this many
evenly spaced configurations (`between`): the hand travels at most `CHAIN_SPACING` / 4 (2.5 mm) between two
checks, not 1 cm. gen15_028 of the physical bench: the hand turned 90 deg about its axis passed 0.8 mm deep
through a cube beside its push between two configurations 1 cm apart, both clear. Checked only for a chain
clear at its own configurations (most clashes show there), so it costs a chain that is kept about three times
its first check, and nothing to one that is not."""

CHAIN_LEVER = 0.2
"""m: a turn of the hand counts as this lever arm times its angle, for `CHAIN_SPACING`."""


def chain_count(length: float) -> int:
    """How many configurations check a contact's motion of `length` (m of hand travel, or a turn's lever): one
    every `CHAIN_SPACING` or nearer, both ends included. A length within a micrometre above a multiple of the
    spacing counts as that multiple: a drawer pulled exactly 15 cm measured 15.000000000000002 spacings on one
    CPU and 15 on another, and the plan had 17 configurations on one, 16 on the other."""
    return max(2, math.ceil(length / CHAIN_SPACING - 1e-4) + 1)


PITCHES = tuple(np.radians((0.0, 30.0, 45.0, 60.0)))
"""rad: how far the hand may lean back from upright at a contact (tried in turn)."""

ROLLS = tuple(np.radians((20.0, -20.0)))
"""rad: how far the hand may roll about the push's direction, at each lean of `PITCHES` where the hand hit a body
beside the one it pushes: the pad stays on the face (its axis turns within it), one side of the 20 cm
wide hand rises over a low body beside the way (gen3_000 of the physical bench: the hand 0.1 cm in a cube 6 cm
beside a pull)."""

SAME_CONFIGURATION = 0.01
"""rad: IK answers at a contact no joint of which differs by more than this are one arm configuration (the chain
along the motion from either ends the same way): the spread seeds' answers are followed once each."""


class ContactChains:
    """Solves the arm's chains along contacts' motions for one problem (`solve`)."""

    def __init__(self, problem: Problem, moves: StraightMoves) -> None:
        """Chains of `problem`'s arm, their links checked with `moves`' collision checks."""
        self.problem = problem
        self.moves = moves
        self._hand_links: frozenset[str] | None = None  # the links beyond the arm's last joint, when first asked

    def solve(self, step: PlanStepRecord, state: ArmState, label: str) -> Iterator[np.ndarray | Rejection]:
        """Joints every `CHAIN_SPACING` along `step`'s contact motion, in one arm configuration from start to
        end, in the order of the module docstring; the last item is the Rejection naming the closest miss.

        The plan's configuration at the contact first; if the arm would have
        to switch configuration on the way (a joint jump: IK branch switch) or
        its links hit a body on the way (the hand of a vertical gripper
        overhangs the pad by 2.5 cm, so it meets a face more than about 4 cm
        above the contact), IK from the arm's home, then the hand pitched back about the pad's axis by
        `PITCHES` (the pad touches the face the same way, the hand leans away
        from it); then the arm's other configurations.
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
        count = chain_count(max(travel, turn * CHAIN_LEVER))
        closest = _ClosestMiss()
        # leaning the hand back keeps the pad where it is, but would turn a tool held in the hand
        # nor may a grasp lean: the fingers close on the handle as the grasp says
        grasp = self.moves.grasps(step)
        pitches = PITCHES if state.held is None and not grasp else PITCHES[:1]
        leans = {pitch: _Lean() for pitch in pitches}
        poses: list[np.ndarray] = []
        # a grasp's other configurations: its chains solved backwards from the end (`_grasp_chains`), as before
        for others in (False, True) if not grasp else (False,):
            for pitch in pitches:
                if others and not leans[pitch].worth_others:
                    continue
                # the spread seeds only when wanted: drawing them costs a solve's start (`InverseKinematics`)
                seeds = arm.spread_seeds()[1:] if others else (step.q_start, arm.home)
                hand = upright @ _pitched_back(pitch)
                poses = [motion.at(s) @ hand for s in np.linspace(0.0, 1.0, count)]
                lean = f"the hand leaned back {np.degrees(pitch):.0f} deg: " if pitch else ""
                yield from self._from_seeds(step, state, (hand, poses), seeds, leans[pitch], closest, lean)
        for pitch in [pitch for pitch in pitches if leans[pitch].hand_hit] if len(pitches) > 1 else ():
            for roll in ROLLS:
                hand = upright @ _rolled(roll) @ _pitched_back(pitch)
                rolled = [motion.at(s) @ hand for s in np.linspace(0.0, 1.0, count)]
                lean = f", leaned back {np.degrees(pitch):.0f} deg" if pitch else ""
                words = f"the hand rolled {np.degrees(roll):+.0f} deg{lean}: "
                seeds = (step.q_start, arm.home)
                yield from self._from_seeds(step, state, (hand, rolled), seeds, _Lean(), closest, words)
        if len(pitches) > 1 and any(lean.hand_beside for lean in leans.values()):
            yield from self._turned(step, state, (upright, motion, count), closest)
        if grasp:
            yield from self._grasp_chains(step, state, poses, closest)
        why = f"{label}: no arm configuration carries the whole motion (closest: {closest.words})"
        yield Rejection(Kind.IK, why, 1.0, bodies=closest.bodies)

    def _from_seeds(
        self,
        step: PlanStepRecord,
        state: ArmState,
        hand_and_poses: tuple[np.ndarray, list[np.ndarray]],
        seeds: Sequence[np.ndarray],
        lean: _Lean,
        closest: _ClosestMiss,
        words: str,
    ) -> Iterator[np.ndarray]:
        """The chains along the poses that carry the motion clear of the bodies, from the IK answers at the hand
        from `seeds` in turn (`lean` keeps what was tried at this lean, and whether other configurations may
        do better; `closest` notes why a chain fails, `words` says how the hand leans)."""
        arm = self.problem.arm
        hand, poses = hand_and_poses
        first = not lean.tried
        for seed in seeds:
            q0 = arm.ik(hand, q0=seed)
            if q0 is None:
                # IK restarts from home and the same fixed seeds after the given one: from another seed it would
                # fail again (19 local runs for nothing)
                closest.note((0, 0.0), f"{words}no IK solution at the contact")
                lean.worth_others = False
                return
            # the plan's and home's answers are always followed (as before the spread seeds); later ones once each
            if not first and any(np.abs(q0 - other).max() < SAME_CONFIGURATION for other in lean.tried):
                continue
            lean.tried.append(q0)
            chain = follow_poses(arm, poses, q0)
            if isinstance(chain, CartesianFailure):
                closest.note((1, chain.index / len(poses)), words + chain.reason)
                lean.worth_others = True  # a joint jump: another elbow may follow the poses smoothly
                continue
            clash = self._contact_clash(step, state, chain.joints)
            if clash is not None:
                closest.note((2, -clash.depth), words + clash.words, clash.bodies)
                # a link before the wrist may pass elsewhere in another configuration; the hand (and what it
                # holds) is where the contact puts it in every one
                rigid = self._rigid_with_hand(clash)
                lean.worth_others |= not rigid
                lean.hand_hit |= rigid
                lean.hand_beside |= rigid and bool(clash.bodies - {step.body})
                continue
            yield chain.joints.copy()

    def _turned(
        self,
        step: PlanStepRecord,
        state: ArmState,
        contact: tuple[np.ndarray, Any, int],
        closest: _ClosestMiss,
    ) -> Iterator[np.ndarray]:
        """The chains with the hand turned about its axis (`TURNS`), the rounded end of the pad at the contact
        (`vkgl.robot.pad.turned_pad`): tried when no lean or roll carried the motion and the hand hit a body beside
        the one it pushes at some lean (not when only the pushed body's tall face stands in its way: turned, the
        hand's width lies over that body).
        A person pushing a small body that lies close beside a bigger one turns the hand so that its 20 cm width
        does not lie along the face (gen3_018 of the physical bench: a cube 1.8 cm before a crate's
        face, pushed sideways; every lean and roll of the hand overlaps the crate by 3.1 cm)."""
        upright, motion, count = contact
        for angle in TURNS:
            hand = upright @ turned_pad(angle)
            words = f"the hand turned {np.degrees(angle):+.0f} deg about its axis: "
            # the arm at the contact first, one IK solve and one collision query: a chain is followed and checked
            # along the whole motion (tens of solves) only where the turned hand stands clear at its start
            q0 = self.problem.arm.ik(hand, q0=step.q_start)
            if q0 is None:
                closest.note((0, 0.0), f"{words}no IK solution at the contact")
                continue
            clash = self._contact_clash(step, state, q0[None, :])
            if clash is not None:
                closest.note((2, -clash.depth), words + clash.words, clash.bodies)
                continue
            poses = [motion.at(s) @ hand for s in np.linspace(0.0, 1.0, count)]
            yield from self._from_seeds(step, state, (hand, poses), (q0,), _Lean(), closest, words)

    def _rigid_with_hand(self, clash: Overlap) -> bool:
        """Whether what overlaps in `clash` moves rigidly with the hand: a held tool, or a link beyond the arm's
        last joint."""
        if self._hand_links is None:
            collision = self.moves.geometry.arm_collision
            last = collision.skeleton.getJoint(self.problem.arm.joint_names[-1]).getChildBodyNode()
            self._hand_links = frozenset(_subtree(last))
        return not clash.link or clash.link in self._hand_links  # no link: a held tool

    def _grasp_chains(
        self, step: PlanStepRecord, state: ArmState, poses: list[np.ndarray], closest: _ClosestMiss
    ) -> Iterator[np.ndarray]:
        """More arm configurations for a grasped handle's motion (a door's arc turns the hand with it, which the
        configuration at its start may not carry to its end): chains solved backwards from the motion's end,
        from the arm's spread IK seeds, each kept when it carries the whole motion clear of the bodies."""
        arm = self.problem.arm
        for seed in arm.spread_seeds():
            q_end = arm.ik(poses[-1], q0=seed)
            if q_end is None:
                continue
            chain = follow_poses(arm, poses[::-1], q_end)
            if isinstance(chain, CartesianFailure):
                closest.note((1, chain.index / len(poses)), "solved from the end: " + chain.reason)
                continue
            joints = chain.joints[::-1].copy()
            clash = self._contact_clash(step, state, joints)
            if clash is not None:
                closest.note((2, -clash.depth), clash.words, clash.bodies)
                continue
            yield joints

    def _contact_clash(self, step: PlanStepRecord, state: ArmState, chain: np.ndarray) -> Overlap | None:
        """What the arm hits along a contact's motion, and how deep: every configuration of `chain` (evenly
        spaced along the motion) with the moving bodies where the motion has them then, then the configurations
        between them (`CLASH_PARTS`). Only the pad may touch the pushed body; the rest of the hand, leaned back or
        turned, sweeps past the bodies beside it."""
        clash = self._clash_along(step, state, chain, np.linspace(0.0, 1.0, len(chain)))
        if clash is None and len(chain) > 1:  # the chain's own configurations first: most clashes show there
            clash = self._clash_along(step, state, *between(chain))
        return clash

    def _clash_along(
        self, step: PlanStepRecord, state: ArmState, joints: np.ndarray, fractions: np.ndarray
    ) -> Overlap | None:
        """The first overlap of the arm at `joints`, the moving bodies at `fractions` of the contact's motion."""
        held = state.held
        if held is not None:
            held = dataclasses.replace(held, acts_on=frozenset({step.body}))
        grasp = self.moves.grasps(step)
        moving = {
            name: screw_motion(pose, step.poses_end[name]).along(fractions) @ pose
            for name, pose in step.poses_start.items()
            if name in step.poses_end and np.abs(pose - step.poses_end[name]).max() > 1e-9
        }
        for i, q in enumerate(joints):
            poses = {**step.poses_start, **{name: along[i] for name, along in moving.items()}}
            if grasp:  # the fingers close on the body: only they may touch it
                clash = self.moves.grasp_overlap(np.asarray([q]), poses, held, step.body)
            else:
                clash = self.moves.first_overlap(np.asarray([q]), poses, held, set(), {step.body})
            if clash is not None:
                where = "at the contact" if fractions[i] == 0.0 else f"{fractions[i]:.0%} along the contact's motion"
                return clash._replace(words=f"{where} {clash.words}")
        return None


def between(chain: np.ndarray, parts: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The arm's configurations between those of `chain` (joints at evenly spaced phases of a contact's
    motion), each interval cut in `parts` (`CLASH_PARTS`) by joints linearly between its ends, as the executor
    follows a chain (`vkgl.execute.world_arm`): (joints, their phases), the chain's own ones left out."""
    parts = CLASH_PARTS if parts is None else parts
    intervals = len(chain) - 1
    fractions = np.linspace(0.0, 1.0, intervals * parts + 1)
    fractions = fractions[np.arange(len(fractions)) % parts != 0]
    position = fractions * intervals
    low = np.minimum(np.floor(position).astype(int), intervals - 1)
    t = (position - low)[:, None]
    return chain[low] * (1.0 - t) + chain[low + 1] * t, fractions


@dataclass
class _Lean:
    """What was tried for a contact at one lean of the hand: the IK answers followed, and whether the arm's
    other configurations may do better (a chain broke off, or a link before the wrist hit a body; not when
    there is no IK answer, nor when only the hand or what it holds hit something)."""

    tried: list[np.ndarray] = field(default_factory=list)
    worth_others: bool = False
    hand_hit: bool = False  # the hand (or what it holds) hit a body beside: a roll may lift it over
    hand_beside: bool = False  # what it hit is not the body it pushes: the hand turned may stand clear of it


def _subtree(node: Any) -> Iterator[str]:
    """The names of a DART body node and of every body node below it."""
    yield node.getName()
    for i in range(node.getNumChildBodyNodes()):
        yield from _subtree(node.getChildBodyNode(i))


class _ClosestMiss:
    """The failure that came closest among a contact's arm configurations: an IK failure at the contact is
    farthest, then a chain that broke off (the later, the closer), then one whose links overlap the body (the
    shallower, the closer); the first among equals. `bodies`: those its links overlap (`Rejection.bodies`)."""

    def __init__(self) -> None:
        self.rank: tuple[int, float] | None = None
        self.words = "no configuration tried"
        self.bodies: frozenset[str] = frozenset()

    def note(self, rank: tuple[int, float], words: str, bodies: frozenset[str] = frozenset()) -> None:
        if self.rank is None or rank > self.rank:
            self.rank, self.words, self.bodies = rank, words, bodies


def _rolled(angle: float) -> np.ndarray:
    """The effector frame turned by `angle` about its x axis, the push's direction through the pad's centre: the
    pad keeps its place on the face, its axis turned within the face, the hand's sides one up, one down."""
    about = np.eye(4)
    about[:3, :3] = axis_matrix(0, angle)
    return about


TURNS = tuple(np.radians((90.0, -90.0, 120.0, -120.0, 60.0, -60.0)))
"""rad: the turns of the hand about its axis tried at a contact where the hand, as written, leaned and rolled, hit a
body beside the one it pushes (`ContactChains._turned`), the pad's rounded end at the contact
(`vkgl.robot.pad.turned_pad`)."""


def _pitched_back(angle: float) -> np.ndarray:
    """The effector frame turned by `angle` about the pad's axis (the frame's y through the pad's centre),
    leaning the hand away from the face it pushes (the frame's z toward -x)."""
    about = np.eye(4)
    about[:3, :3] = axis_matrix(1, -angle)
    to_axis = np.eye(4)
    to_axis[0, 3] = -FINGERTIP_RADIUS
    return to_axis @ about @ np.linalg.inv(to_axis)


__all__ = ["CHAIN_LEVER", "CHAIN_SPACING", "PITCHES", "ROLLS", "ContactChains"]
