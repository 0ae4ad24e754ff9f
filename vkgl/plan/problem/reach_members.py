"""A tool's pull started nearer the arm: the contact moved along the far face until the hand is within reach.

A tool holds the hand beside its contact: the Hook's handle lies 33 cm back along the shaft and 12 cm to the side
of its tip. Pulling a body at the middle of its far face puts the hand where that chain ends, and for a body lying
at a slant the side can be the one away from the arm: the Block at (0.906, -0.172) m, yaw 30 deg, pulled by the
Hook at the middle of its +x face, has the hand 0.835 m from the arm's base, 4 cm beyond the 0.795 m the arm
reaches hand-down at that height (gen2_027 of the physical bench: "no plan", every such pull cut at once for the
hand's reach). A person takes the same pull nearer the arm: the cross-piece slid along the far face toward the
arm's side, still covering the body's centre line, so that the flat face drives the body straight
(`vkgl.plan.graphs.tool_faces`: a line contact) while the hand is 4 cm nearer; where the shaft then lies across the
body's top, the hook is rolled so that it passes over it (`vkgl.plan.problem.over.roll_for`).

`reach_members` offers that member for each slide of a goal body lying flat that every grasp of a tool holds the
hand out of reach for at its written contact, with the body where it rests: the least offset along the face
(`OFFSET_STEP` steps, the cross-piece covering the centre line by `COVER_MARGIN`, the contact on the body's face)
at which some grasp holds the hand `REACH_SLACK` inside the arm's reach there; named `NAME@+5.00cm/straight`
lying flat, `NAME@+5.00cm/straight/over+20deg+0.50cm` rolled (`vkgl.lang.ir.families`), and only that tool
effector may enact it (`PlanBody.tool_members`). Its motion is the slide's own: the collision, grip and arm
checks decide the rest, as for any contact.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from vkgl.lang.ir.families import MEMBER_MARK, OVER_MARK, member_name, over_member, over_name, slide_member
from vkgl.lang.ir.nodes import Affordance, Body, FixedC, FreeC, GraspC, PrismaticC
from vkgl.plan.problem.over import COVER_MARGIN, FLAT, PART_CLEARANCE, roll_for, tool_parts
from vkgl.rotations import yaw_matrix
from vkgl.se3 import wrap_angle, yaw_of

if TYPE_CHECKING:  # (problem.py builds the members: these are its types)
    from vkgl.plan.problem.problem import EffectorSpec, GoalSpec, PlanBody
    from vkgl.robot import Arm

OFFSET_STEP = 0.005
"""m: the contact is moved along the face in these steps, nearest the written contact first."""

REACH_SLACK = 0.015
"""m: the hand at the moved contact lies at least this far inside the arm's reach interval at its height: the 5 mm
that task space keeps for inverse kinematics, and 1 cm for the pull's start (the approach, the body's tolerance)."""

AIM_LIMIT = math.radians(45.0)
"""rad: the most a slide's start heading is turned from the body's rest to aim the slide at the goal (two of the
stdlib's turns, about 20 deg each, or one of the Block's widest)."""


AIM_LEAST = math.radians(1.0)
"""rad: a smaller turn to aim the slide at the goal is not asked apart (its member would be the rest's)."""


def reach_members(
    body: PlanBody,
    bodies: dict[str, PlanBody],
    effectors: list[EffectorSpec],
    body_points: np.ndarray,
    arm: Arm,
    goal: GoalSpec,
) -> tuple[tuple[Affordance, ...], frozenset[tuple[str, str]]]:
    """The members (module docstring) of `body`'s slides (its hull points `body_points`, body frame) for each tool
    effector of `effectors` (the tools among `bodies`), on the way to `goal`; with the (member, effector) pairs
    that may enact them. Each slide is asked where the body rests, and where it rests turned so that the slide
    carries it at its goal (at the goal's heading when the goal states one; `start_headings`)."""
    found: dict[str, Affordance] = {}
    pairs: set[tuple[str, str]] = set()
    tools = [
        (e.name, bodies[e.tool].type, e.frame, tool_grasps(bodies[e.tool].affordances))
        for e in effectors
        if e.tool is not None and e.tool != body.name
    ]
    for affordance in body.affordances:
        action = affordance.action
        if not isinstance(affordance.motion, PrismaticC) or MEMBER_MARK in affordance.name:
            continue
        if OVER_MARK in affordance.name or not isinstance(action, FixedC) or action.pose is None:
            continue
        if action.pose.rpy is not None:
            continue  # only a level pull: a yaw alone
        contact = action.pose.matrix()
        for start in start_poses(body.rest, affordance.motion, goal):
            for effector, kind, frame, grasps in tools:
                member = _moved_member(affordance, start @ contact, contact, body_points, (kind, frame, grasps), arm)
                if member is not None:
                    found.setdefault(member.name, member)
                    pairs.add((member.name, effector))
    return tuple(found.values()), frozenset(pairs)


def start_poses(rest: np.ndarray, slide: PrismaticC, goal: GoalSpec) -> list[np.ndarray]:
    """Where a slide towards `goal` may start (world poses): where the body rests, and there turned about its
    origin to the goal's heading, or (a goal with no heading) to the heading at which the slide's axis points at
    the goal position (a turn of less than `AIM_LEAST` or more than `AIM_LIMIT` left out); of those, the ones at
    which the slide's axis points within `AIM_LIMIT` of the goal position (a slide away from the goal needs no
    pull nearer the arm)."""
    if goal.position is None:
        return []
    way = np.asarray(goal.position[:2], dtype=float) - rest[:2, 3]
    along = np.asarray(slide.axis.values, dtype=float)
    axis = (rest[:3, :3] @ (along / np.linalg.norm(along)))[:2]
    if float(np.linalg.norm(way)) < 1e-9 or float(np.linalg.norm(axis)) < 1e-9:
        return []
    aim = math.atan2(way[1], way[0]) - math.atan2(axis[1], axis[0])
    turn = wrap_angle(goal.yaw - yaw_of(rest) if goal.yaw is not None else aim)
    out = []
    for angle in (0.0, turn) if AIM_LEAST <= abs(turn) <= AIM_LIMIT else (0.0,):
        if abs(wrap_angle(aim - angle)) <= AIM_LIMIT:
            pose = rest.copy()
            pose[:3, :3] = np.asarray(yaw_matrix(angle), dtype=float) @ rest[:3, :3]
            out.append(pose)
    return out


def _moved_member(
    affordance: Affordance,
    world_contact: np.ndarray,
    contact: np.ndarray,
    body_points: np.ndarray,
    tool: tuple[Body, np.ndarray, list[np.ndarray]],
    arm: Arm,
) -> Affordance | None:
    """The member of `affordance` enacted by `tool` (its type, frame, grasps) at the least offset along the face
    that brings the hand within reach, or None: the written contact does already, or no offset does."""
    kind, frame, grasps = tool
    frame_inverse = np.linalg.inv(frame)
    hands = [frame_inverse @ grasp for grasp in grasps]
    if not hands or any(_inside(world_contact @ hand, arm) for hand in hands):
        return None
    parts = [p @ frame_inverse[:3, :3].T + frame_inverse[:3, 3] for p in tool_parts(kind.shape)]
    face = [p for p in parts if abs(float(p[:, 0].max())) <= FLAT]
    if not face:
        return None
    into_contact = np.linalg.inv(contact)
    body = body_points @ into_contact[:3, :3].T + into_contact[:3, 3]
    centre = float(into_contact[1, 3])
    low = max(centre + COVER_MARGIN - max(float(p[:, 1].max()) for p in face), float(body[:, 1].min()))
    high = min(centre - COVER_MARGIN - min(float(p[:, 1].min()) for p in face), float(body[:, 1].max()))
    for offset in _offsets(low, high):
        shift = np.eye(4)
        shift[1, 3] = offset
        if not any(_inside(world_contact @ shift @ hand, arm) for hand in hands):
            continue
        moved = body - np.array([0.0, offset, 0.0])
        beside = [p for p in parts if float(p[:, 0].max()) > FLAT]
        name = member_name(affordance.name, offset, straight=True)
        straight = slide_member(affordance, offset).model_copy(update={"name": name})
        if not any(_stands_in_flat(p, moved) for p in beside):
            return straight
        pose = roll_for(parts, moved, centre - offset, fixed=True)
        if pose is not None:
            rolled = over_name(name, *pose)
            return over_member(straight, *pose).model_copy(update={"name": rolled})
    return None


def tool_grasps(affordances: tuple[Affordance, ...]) -> list[np.ndarray]:
    """The hand's pose in a tool's frame for each of its grasps (its affordances with a free motion: wielded)."""
    return [
        a.action.pose.matrix()
        for a in affordances
        if isinstance(a.motion, FreeC) and isinstance(a.action, (FixedC, GraspC)) and a.action.pose is not None
    ]


def _offsets(low: float, high: float) -> list[float]:
    """The offsets in [low, high] at `OFFSET_STEP` steps, nearest 0 first (0 itself left out: the written contact)."""
    ups = np.arange(OFFSET_STEP, high + 1e-9, OFFSET_STEP) if high > 0.0 else np.zeros(0)
    downs = -np.arange(OFFSET_STEP, -low + 1e-9, OFFSET_STEP) if low < 0.0 else np.zeros(0)
    return sorted((float(v) for v in np.concatenate([ups, downs])), key=lambda v: (abs(v), v))


def _inside(hand: np.ndarray, arm: Arm) -> bool:
    """Whether the hand at world pose `hand` lies `REACH_SLACK` inside the arm's reach interval at its height."""
    r_min, r_max = arm.reach(float(hand[2, 3]))
    radius = float(np.hypot(*(hand[:2, 3] - arm.base[:2, 3])))
    return r_max > 0.0 and r_min + REACH_SLACK <= radius <= r_max - REACH_SLACK


def _stands_in_flat(part: np.ndarray, body: np.ndarray) -> bool:
    """Whether a tool part past the contact plane (the Hook's shaft), lying flat, comes within `PART_CLEARANCE` of
    the body's width, at its height (as `over.roll_for` asks)."""
    across = (
        part[:, 1].min() < body[:, 1].max() + PART_CLEARANCE and part[:, 1].max() > body[:, 1].min() - PART_CLEARANCE
    )
    up = part[:, 2].min() < body[:, 2].max() + PART_CLEARANCE and part[:, 2].max() > body[:, 2].min()
    return bool(across and up)


__all__ = ["AIM_LEAST", "AIM_LIMIT", "OFFSET_STEP", "REACH_SLACK", "reach_members", "start_poses", "tool_grasps"]
