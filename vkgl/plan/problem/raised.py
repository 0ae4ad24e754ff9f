"""The fingertip raised on a tall face: a pull whose hand, upright at the written contact, would stand in the body.

The Panda's closed fingers stand no farther forward than the pad only up to about `PAD_CLEAR` above it (the
arm's collision meshes, through the contact chains' check: a face whose top is 4 cm above the pad overlaps the
fingers by 1.0 cm, 3 cm above by 0.2 cm, 2 cm above not at all). A learned push presses its face where
exploration pressed it, at the body's mid-height; where the face rises more than that above it, the contact
chains lean the hand back (`vkgl.plan.arm.contact_chains.PITCHES`). On a pull, the push pointing toward the arm
(the hand at the body's far face), leaning back takes the wrist farther from the arm's base: out of reach where
such pulls start. gen1_018 of the physical bench, a CrateM 18 cm tall whose far face stands 0.77 m from the
base: upright the hand stands 3.0 cm in the crate, leaned back 30 to 60 deg it has no IK solution, and no plan
pulls it, with or without the cube in its way. A person hooks the fingers near the top edge.

`raised_members` offers that member for each level slide of a goal body lying flat whose push points toward the
arm's base (at the body's rest) and whose face rises more than `PAD_CLEAR` above the contact: the same slide, its
contact raised by the least lift (`LIFT_STEP` steps) that brings the face's top within `PAD_CLEAR` of the pad,
named `NAME/over+0deg+7.00cm` (`vkgl.lang.ir.families.over_member` with no roll: plans and execution read it as
they read a tool rolled over a body, `vkgl.plan.problem.over`), for the arm's fingertip alone. Only when the
raised contact stays low enough not to tip the body:

- quasi-statically, the push's force is the body's friction on the table, mu m g (the table's friction is 1.0,
  above every body's: the body's own decides), applied `h` above the table; it tips the body about its leading
  bottom edge, `d` ahead of its centre along the push, when mu m g h > m g d. The lift is kept to
  h <= `TIP_SHARE` d / mu (the crate: d = 10 cm, mu = 0.5, h at most 16 cm; raised 7 cm it is pulled at 16 cm);
- the body's `tips above` clauses, where exploration measured one (`vkgl.plan.problem.tipping`), are applied to
  the raised contact as to any other.

The arm's checks then decide as for any contact (the raised pad is still the pad, its hand upright).
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.families import over_member, over_name
from vkgl.lang.ir.geometry import shape_vertices
from vkgl.lang.ir.nodes import Affordance, Body, FixedC, PrismaticC, Tipping
from vkgl.plan.problem.tipping import split_by_tipping
from vkgl.robot.grip import DEFAULT_FRICTION

PAD_CLEAR = 0.025
"""m: how far above the pad's centre a face may rise for the upright hand's closed fingers to stay out of it
(module docstring: measured with the arm's collision model)."""

LIFT_STEP = 0.005
"""m: the contact is raised in these steps."""

TIP_SHARE = 0.8
"""The share of the quasi-static tipping height (d / mu) a raised contact may reach: the pull also accelerates the
body, and DART's contact forces vary about the static ones."""

TOWARD_ARM = 0.0
"""The least cosine between a slide's push (at the body's rest) and the direction from the contact to the arm's
base for the slide to count as a pull (the hand at the body's far side)."""


def raised_members(
    body: Body, affordances: tuple[Affordance, ...], rest: np.ndarray, base: np.ndarray, clauses: list[Tipping]
) -> tuple[Affordance, ...]:
    """The raised members (module docstring) of the pulls among `affordances` of `body` lying flat at `rest`
    (world pose), for an arm based at `base` (world position), but those that push above a `tips above` clause
    among `clauses`."""
    friction = DEFAULT_FRICTION if body.friction is None else body.friction
    members = _raised(affordances, np.asarray(shape_vertices(body.shape)), rest, base, friction)
    return split_by_tipping(body, members, clauses)[0]


def _raised(
    affordances: tuple[Affordance, ...], body_points: np.ndarray, rest: np.ndarray, base: np.ndarray, friction: float
) -> tuple[Affordance, ...]:
    """The raised members of the pulls among `affordances` (`body_points`: the body's vertices, its frame, z up;
    `friction`: its friction coefficient on the table), before the tipping clauses."""
    bottom, top = float(body_points[:, 2].min()), float(body_points[:, 2].max())
    found: list[Affordance] = []
    for affordance in affordances:
        action = affordance.action
        if not isinstance(affordance.motion, PrismaticC) or not isinstance(action, FixedC) or action.pose is None:
            continue
        if action.pose.rpy is not None:
            continue  # only a level push: a yaw alone
        contact = action.pose.matrix()
        if not _pulls(rest, contact, base):
            continue
        lift = needed_lift(float(contact[2, 3]), top)
        if lift <= 0.0:
            continue
        height = float(contact[2, 3]) + lift - bottom
        if height > TIP_SHARE * leading_edge(body_points, contact[:3, 0]) / friction + 1e-9:
            continue
        name = over_name(affordance.name, 0.0, lift)
        found.append(over_member(affordance, 0.0, lift).model_copy(update={"name": name}))
    return tuple(found)


def needed_lift(contact_z: float, top: float) -> float:
    """m: the least lift, in `LIFT_STEP` steps, that brings a face's `top` within `PAD_CLEAR` of a contact at
    `contact_z` (both in the body frame); 0 when it is already."""
    rise = top - contact_z - PAD_CLEAR
    if rise <= 1e-9:
        return 0.0
    return LIFT_STEP * math.ceil(rise / LIFT_STEP - 1e-9)


def leading_edge(body_points: np.ndarray, push: np.ndarray) -> float:
    """m: how far ahead of the body's origin, along the level part of `push` (body frame), its farthest bottom
    point lies: the lever of its weight about the edge a push tips it over."""
    level = np.asarray(push, dtype=float)[:2]
    level = level / max(float(np.linalg.norm(level)), 1e-12)
    bottom = body_points[body_points[:, 2] <= float(body_points[:, 2].min()) + 1e-6]
    return float((bottom[:, :2] @ level).max())


def _pulls(rest: np.ndarray, contact: np.ndarray, base: np.ndarray) -> bool:
    """Whether the push at `contact` (body frame) points toward the arm's base with the body at `rest`."""
    push = rest[:2, :2] @ contact[:2, 0]
    at = (rest @ contact)[:2, 3]
    toward = np.asarray(base, dtype=float)[:2] - at
    norms = float(np.linalg.norm(push) * np.linalg.norm(toward))
    return norms > 1e-12 and float(push @ toward) / norms > TOWARD_ARM


__all__ = ["LIFT_STEP", "PAD_CLEAR", "TIP_SHARE", "leading_edge", "needed_lift", "raised_members"]
