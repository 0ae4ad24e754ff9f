"""A slide pulled or pushed by a tool's flat face off the body's centre line: where along the face it may touch.

A slide (a prismatic affordance) is learned at its face's centre, and a point
pushed by position off that centre turns the body (`members.has_family`). A
tool whose flat face touches the body along a segment is another contact: its
reaction may sit anywhere on the segment, so as long as the segment covers the
line through the body's origin along the slide, the tool can drive the body
straight along it (quasi-static pushing with a line contact). The Hook's
cross-piece is such a face: 16 cm flat on the far face, the tip 3 cm from its
free end. Its shaft, 12 cm beside the tip, lies along the body: at the middle of
a 24 cm wide face (the generated CrateT) it would lie 1 cm inside the body, so
the pull at the centre is refused, while the same pull with the contact 2 cm
toward the shaft's side covers the centre line and clears the body (executed in
DART: the body arrives within 0.03 cm and 0.01 deg of the plan;
docs/planning.md, "Wide hook pulls").

`slide_band(problem, engagement)` is that range of offsets (m, along the
action frame's y axis, the contact's direction along the face): the tool's flat
face still covers the centre line by `COVER_MARGIN`, and the tool's parts that
reach past the contact plane (the shaft) stay `PART_CLEARANCE` clear of the
body's width; only for a body the tool at the centre would stand in (elsewhere
the written contact serves). The stick's 2 cm end covers too little to leave
any band, and a body with a joint (a drawer pulled at its handle) has none: its
slide is the joint's, its contact the handle's. The planner moves the contact
within the band like a family's (`Sequence.offsets`), only when the written
contact fails; the slide's motion does not change with the offset, only where
the tool and the hand are.
"""

from __future__ import annotations

import numpy as np

from vkgl.lang.ir.families import MEMBER_MARK, OVER_MARK
from vkgl.lang.ir.nodes import PrismaticC
from vkgl.plan.graphs.graph import Engagement
from vkgl.plan.problem.over import COVER_MARGIN, FLAT, PART_CLEARANCE, tool_parts
from vkgl.plan.problem.problem import Problem

__all__ = ["COVER_MARGIN", "FLAT", "PART_CLEARANCE", "slide_band", "tool_parts"]

_BANDS: dict[tuple[int, int, str], tuple[object, object, tuple[float, float] | None]] = {}


def slide_band(problem: Problem, engagement: Engagement) -> tuple[float, float] | None:
    """The offsets (lower, upper; m) at which a tool may enact this slide off the centre (module docstring), or
    None: no tool, not a slide, a family's member already, or no offset but the centre (or none at all) holds."""
    if MEMBER_MARK in engagement.affordance or OVER_MARK in engagement.affordance:
        return None  # a member already (an over member's tool passes over the body: `vkgl.plan.problem.over`)
    effector = problem.effector(engagement.effector)
    if effector.tool is None:
        return None
    affordance = problem.affordance(engagement.body, engagement.affordance)
    tool = problem.bodies[effector.tool].type
    key = (id(affordance), id(tool), effector.name)
    cached = _BANDS.get(key)
    if cached is None or cached[0] is not affordance or cached[1] is not tool:
        cached = (affordance, tool, _band(problem, engagement))  # both kept, so that their ids stay their own
        _BANDS[key] = cached
    return cached[2]


def _band(problem: Problem, engagement: Engagement) -> tuple[float, float] | None:
    affordance = problem.affordance(engagement.body, engagement.affordance)
    if not isinstance(affordance.motion, PrismaticC):  # a slide's family (an arc) is a point's: not a flat face's
        return None
    if problem.bodies[engagement.body].joint is not None or not problem.bodies[engagement.body].on_table:
        return None  # a drawer's slide is its joint's, and its contact a handle's: only bodies sliding on the table
    effector = problem.effector(engagement.effector)
    assert effector.tool is not None
    into_contact = np.linalg.inv(problem.action(engagement.body, engagement.affordance))
    body_y = (problem.footprint_points(engagement.body) @ into_contact[:3, :3].T + into_contact[:3, 3])[:, 1]
    centre = float(into_contact[1, 3])  # the body's origin, along the face, seen from the contact
    face: list[tuple[float, float]] = []
    beside: list[tuple[float, float]] = []
    for part in tool_parts(problem.bodies[effector.tool].type.shape):
        local = part @ effector.frame_inverse[:3, :3].T + effector.frame_inverse[:3, 3]
        span = (float(local[:, 1].min()), float(local[:, 1].max()))
        front = float(local[:, 0].max())  # how far the part reaches past the contact plane, toward the body
        if abs(front) <= FLAT:
            face.append(span)
        elif front > FLAT:
            beside.append(span)
    if not face:
        return None
    band = (centre - max(h for _, h in face) + COVER_MARGIN, centre - min(lo for lo, _ in face) - COVER_MARGIN)
    for low, high in beside:  # at offset s the body spans body_y - s: the part keeps clear on one side of it
        below = (band[0], min(band[1], float(body_y.min()) - high - PART_CLEARANCE))
        above = (max(band[0], float(body_y.max()) - low + PART_CLEARANCE), band[1])
        band = max((below, above), key=lambda b: (b[0] <= 0.0 <= b[1], b[1] - b[0]))
    if band[1] - band[0] < 1e-4 or band[0] > band[1]:
        return None
    if band[0] <= 0.0 <= band[1]:
        # the written contact leaves the tool clear of the body itself: moved only to clear other bodies, it
        # solved none of the far tasks and cost 29 % more CPU on one (gen6_015, gen6_035: cubes; docs/planning.md)
        return None
    return band
