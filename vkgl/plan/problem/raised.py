"""The fingertip raised on a tall face: where the upright hand at the written contact stands in a body.

The Panda's closed fingers stand no farther forward than the pad only up to about `PAD_CLEAR` above it (the
arm's collision meshes, through the contact chains' check: a face whose top is 4 cm above the pad overlaps the
fingers by 1.0 cm, 3 cm above by 0.2 cm, 2.5 cm above not at all), and the hand's body (20 cm wide along the
face) hangs 8 cm above the pad. A learned push presses its face where exploration pressed it, at the body's
mid-height. Two ways that fails where a person would just push a little higher:

- a pull (the hand at the body's far face, pushing toward the arm) of a body whose face rises more than
  `PAD_CLEAR` above the contact: the contact chains lean the hand back (`vkgl.plan.arm.contact_chains.PITCHES`),
  which takes the wrist farther from the arm's base, out of reach where such pulls start. gen1_018 of the
  physical bench, a CrateM 18 cm tall whose far face stands 0.77 m from the base: upright the hand stands 3.0 cm
  in the crate, leaned back 30 to 60 deg it has no IK solution, and no plan pulled it, with or without the cube
  in its way;
- a push of a low body beside a taller one (a cube pushed out of the way of a 12 cm cube 4 cm behind it,
  gen2_008 and gen2_036): the hand, 20 cm wide along the face, passes 0.2 cm through the taller body.

`raised_name` names the same motion (a level slide, or an arc's member: a turn made by a push off the face's
centre, `vkgl.plan.problem.arcs`) with its contact raised by the least lift (`LIFT_STEP` steps) that brings the
face's top within `PAD_CLEAR` of the pad: `NAME/over+0deg+6.50cm` or `NAME@-2.45cm/over+0deg+6.50cm`
(`vkgl.lang.ir.families.over_member` with no roll; plans and execution read it as they read a tool rolled over a
body, `vkgl.plan.problem.over`). The search offers it when the arm's checks reject the written contact
(`vkgl.plan.task_space.raised_contacts`). A push's height does not enter its planar motion while the body slides
flat (the friction under it and the push's line in the plane are the same; the Hook's rolled members are raised
so too), as long as it does not tip the body:

- quasi-statically, the push's force is the body's friction on the table, mu m g (the table's friction is 1.0,
  above every body's: the body's own decides), applied `h` above the table; it tips the body about its leading
  bottom edge, `d` ahead of its centre along the push, when mu m g h > m g d. The lift is kept to
  h <= `TIP_SHARE` d / mu (the crate: d = 10 cm, mu = 0.5, h at most 16 cm; raised 6.5 cm it is pulled at
  15.5 cm);
- the body's `tips above` clauses, where exploration measured one (`vkgl.plan.problem.tipping`), are applied to
  the raised contact as to any other.
"""

from __future__ import annotations

import math

import numpy as np

from vkgl.lang.ir.families import OVER_MARK, over_member, over_name
from vkgl.lang.ir.geometry import shape_vertices
from vkgl.lang.ir.nodes import Affordance, Body, FixedC, PrismaticC, Tipping
from vkgl.plan.problem.over import is_arc_turn
from vkgl.plan.problem.tipping import split_by_tipping
from vkgl.robot.grip import DEFAULT_FRICTION

PAD_CLEAR = 0.025
"""m: how far above the pad's centre a face may rise for the upright hand's closed fingers to stay out of it
(module docstring: measured with the arm's collision model)."""

LIFT_STEP = 0.005
"""m: the contact is raised in these steps."""

TIP_SHARE = 0.8
"""The share of the quasi-static tipping height (d / mu) a raised contact may reach: the push also accelerates the
body, and DART's contact forces vary about the static ones."""


def raised_name(body: Body, affordance: Affordance, clauses: list[Tipping]) -> str | None:
    """The name of `affordance` of `body` (lying flat, its frame's z up) enacted by the fingertip raised on its face
    (module docstring), or None: it is no level slide nor an arc's member, its face rises no more than `PAD_CLEAR`
    above its contact, or the raised contact could tip the body (quasi-statically, or above one of `clauses`)."""
    action = affordance.action
    if OVER_MARK in affordance.name or not (isinstance(affordance.motion, PrismaticC) or is_arc_turn(affordance)):
        return None
    if not isinstance(action, FixedC) or action.pose is None or action.pose.rpy is not None:
        return None  # only a level push: a yaw alone
    points = np.asarray(shape_vertices(body.shape))
    contact = action.pose.matrix()
    lift = needed_lift(float(contact[2, 3]), float(points[:, 2].max()))
    if lift <= 0.0:
        return None
    friction = DEFAULT_FRICTION if body.friction is None else body.friction
    height = float(contact[2, 3]) + lift - float(points[:, 2].min())
    if height > TIP_SHARE * leading_edge(points, contact[:3, 0]) / friction + 1e-9:
        return None
    name = over_name(affordance.name, 0.0, lift)
    member = over_member(affordance, 0.0, lift).model_copy(update={"name": name})
    return name if split_by_tipping(body, (member,), clauses)[0] else None


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


__all__ = ["LIFT_STEP", "PAD_CLEAR", "TIP_SHARE", "leading_edge", "needed_lift", "raised_name"]
