"""Semantic checks of `explore` blocks: every rule the explorer (vkgl/sim/policy.py) relies on.

A checked exploration is either a push (`contacts on faces ... steps K` or
`contacts at FRAME, ...`, with `force normal Q`) or a grasp (`grasp FRAME`
with `force directions I x J x K Q`), has a positive force and duration,
pushes only faces the fingertip can reach, and every contact point lies on the
body's surface (a contact frame: its origin, with its x axis into the body).
"""

from __future__ import annotations

import re

from vkgl.lang.checks.context import CheckContext, shown, unknown_frame
from vkgl.lang.checks.ranges import check_explore_ranges
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.limits import HEIGHTS, STEPS

PUSH_EXAMPLE = "contacts on faces +x, -x steps 9"
FORCE_EXAMPLE = "`force normal 1 N` (pushes) or `force directions 3 x 3 x 3 1 N` (grasps)"


def check_explore(explore: ir.Explore, body: ir.Body, shape_ok: bool, ctx: CheckContext) -> None:
    """Report every problem of one `explore` block of `body` (`shape_ok`: the body's shape had no error)."""
    _check_kind(explore, ctx)
    if explore.grasp is not None and body.frame(explore.grasp.name) is None:
        unknown_frame(body, explore.grasp.name, explore.grasp.span, ctx)
    contacts = explore.contacts
    if contacts is not None and contacts.steps <= 0:
        ctx.error(
            codes.NON_POSITIVE_VALUE,
            f"`steps` must be at least 1, got {contacts.steps}",
            ctx.narrow(contacts.span, r"steps\s+(\S+)"),
        )
    if contacts is not None and contacts.heights <= 0:
        ctx.error(
            codes.NON_POSITIVE_VALUE,
            f"`heights` must be at least 1, got {contacts.heights}",
            ctx.narrow(contacts.span, r"heights\s+(\S+)"),
        )
    _check_force(explore, ctx)
    if explore.duration is not None and explore.duration.value <= 0:
        ctx.error(
            codes.NON_POSITIVE_VALUE,
            f"the duration must be positive, got {shown(explore.duration)}",
            explore.duration.span,
        )
    check_explore_ranges(explore, ctx)
    if contacts is not None:
        _check_faces(contacts, body, ctx)
        if shape_ok and 1 <= contacts.steps <= STEPS.high and 1 <= contacts.heights <= HEIGHTS.high:
            _check_contact_points(contacts, body, ctx)
        known = [f for f in contacts.frames if body.frame(f.name) is not None]
        for ref in contacts.frames:
            if body.frame(ref.name) is None:
                unknown_frame(body, ref.name, ref.span, ctx)
        if shape_ok and known:
            _check_contact_frames(known, body, ctx)


def _check_kind(explore: ir.Explore, ctx: CheckContext) -> None:
    """A push or a grasp, not both and not neither; with a force and a duration."""
    owner = f"explore `{explore.name}`"
    if explore.contacts is not None and explore.grasp is not None:
        ctx.error(
            codes.PUSH_AND_GRASP_MIXED,
            f"{owner} has both `contacts` and `grasp`; split them into two `explore` blocks",
            explore.span,
        )
    elif explore.contacts is None and explore.grasp is None:
        ctx.error(
            codes.STATEMENT_MISSING,
            f"{owner} says neither where to touch the body nor what to hold: add `{PUSH_EXAMPLE}` or `grasp FRAME`",
            explore.span,
        )
    if explore.force is None:
        ctx.error(codes.STATEMENT_MISSING, f"{owner} has no `force`: add {FORCE_EXAMPLE}", explore.span)
    if explore.duration is None:
        ctx.error(codes.STATEMENT_MISSING, f"{owner} has no `duration`: add e.g. `duration 2 s`", explore.span)


def _check_force(explore: ir.Explore, ctx: CheckContext) -> None:
    force = explore.force
    if force is None:
        return
    if force.magnitude.value <= 0:
        ctx.error(
            codes.NON_POSITIVE_VALUE,
            f"the force must be positive, got {shown(force.magnitude)}",
            force.magnitude.span,
        )
    if force.grid is not None and min(force.grid) < 1:
        ctx.error(codes.NON_POSITIVE_VALUE, "each direction grid size must be at least 1", force.span)
    elif force.grid is not None and tuple(force.grid) == (1, 1, 1):
        ctx.error(
            codes.ZERO_DIRECTION,
            "the direction grid 1 x 1 x 1 holds only the zero direction; use e.g. 3 x 3 x 3",
            force.span,
        )
    if explore.contacts is not None and explore.grasp is not None:
        return  # already reported as mixed
    if explore.contacts is not None and force.mode != "normal":
        along = "the frame's x axis" if explore.contacts.frames else "the face's inward normal"
        ctx.error(
            codes.PUSH_AND_GRASP_MIXED,
            f"explore `{explore.name}` pushes at contacts: its force must be `force normal Q` (along {along})",
            force.span,
        )
    elif explore.grasp is not None and force.mode != "directions":
        ctx.error(
            codes.PUSH_AND_GRASP_MIXED,
            f"explore `{explore.name}` holds the body: its force must be `force directions I x J x K Q`",
            force.span,
        )


def _check_faces(contacts: ir.ContactSpec, body: ir.Body, ctx: CheckContext) -> None:
    if contacts.heights > 1 and "+z" in contacts.faces:
        ctx.error(
            codes.HEIGHTS_ON_TOP,
            f"`heights {contacts.heights}` spreads contacts up side faces, but `+z` is the top, pushed down",
            ctx.narrow(contacts.span, r"(\+z)"),
            "explore `+z` in a block of its own, without `heights`",
        )
    if "-z" in contacts.faces:
        ctx.error(
            codes.UNREACHABLE_FACE,
            f"face -z of `{body.name}` is its underside, which lies on the table: "
            "the fingertip cannot reach it; explore side faces or +z",
            ctx.narrow(contacts.span, r"(-z)"),
        )


def _check_contact_points(contacts: ir.ContactSpec, body: ir.Body, ctx: CheckContext) -> None:
    """Every contact point of a pushed face must lie on the body's surface (the first miss of each face)."""
    if not isinstance(body.shape, (ir.UnionShape, ir.MeshShape)):
        return  # boxes and cylinders are convex: every point of a face's centre line is on the surface
    import numpy as np

    from vkgl.lang.ir.geometry import FACES, at_heights, body_mesh, face_line, surface_point  # trimesh: lazily

    try:
        mesh = body_mesh(body)
    except Exception:  # an unreadable mesh is E503's business
        return
    for face in contacts.faces:
        outward = FACES.get(face)
        if outward is None or face == "-z":
            continue
        line_axis, points = face_line(mesh, outward, contacts.steps)
        along = int(np.argmax(line_axis))
        for k, height, point in at_heights(mesh, points, contacts.heights):
            if surface_point(mesh, point, outward) is None:
                up = f", {100 * height:.1f} cm up the face" if contacts.heights > 1 else ""
                ctx.error(
                    codes.CONTACT_OFF_SURFACE,
                    f"face {face} of `{body.name}` has no surface at contact point {k + 1} of {contacts.steps} "
                    f"({'xyz'[along]} = {100 * point[along]:.1f} cm on its centre line{up}): "
                    "the shape is hollow or flat there; use fewer steps or another face",
                    ctx.narrow(contacts.span, rf"({re.escape(face)})"),
                )
                break


FRAME_REACH = 0.01  # m behind a contact frame's origin from which the fingertip comes
FRAME_TOLERANCE = 0.001  # m: how far from the body's surface a contact frame's origin may be


def _check_contact_frames(frames: list[ir.Ref], body: ir.Body, ctx: CheckContext) -> None:
    """A contact frame's origin must lie on the surface, its x axis into the body, with room behind it.

    A ray from FRAME_REACH behind the origin along the frame's x must first
    enter the body within FRAME_TOLERANCE of the origin: the fingertip comes
    from there (behind a handle's bar, say) and pushes along x.
    """
    from vkgl.lang.ir.geometry import body_mesh, ray_hit  # trimesh: only when needed

    try:
        mesh = body_mesh(body)
    except Exception:  # an unreadable mesh is E503's business
        return
    for ref in frames:
        frame = body.frame(ref.name)
        assert frame is not None
        pose = frame.pose.matrix()
        origin, x = pose[:3, 3], pose[:3, 0]
        hit = ray_hit(mesh, origin - FRAME_REACH * x, x)
        distance = None if hit is None else float((hit[0] - origin) @ x)
        if hit is not None and distance is not None and hit[1] @ x < 0 and abs(distance) <= FRAME_TOLERANCE:
            continue
        if hit is None or distance is None:
            found = "pushing along its x axis, the fingertip meets nothing"
        elif hit[1] @ x > 0:
            found = f"{100 * FRAME_REACH:.0f} cm behind it, where the fingertip comes from, is inside the body"
        elif distance > 0:
            found = f"pushing along its x axis, the fingertip meets the body {100 * distance:.1f} cm beyond it"
        else:
            found = f"the body is in the way {100 * -distance:.1f} cm before it, where the fingertip comes from"
        ctx.error(
            codes.CONTACT_OFF_SURFACE,
            f"contact frame `{ref.name}` of `{body.name}` is not on its surface: {found}",
            ref.span,
            "a contact frame sits on the surface to push, its x axis pointing into the body "
            f"(the effector frame convention), with {100 * FRAME_REACH:.0f} cm of room behind it",
        )
