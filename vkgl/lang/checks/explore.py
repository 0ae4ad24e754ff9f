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
from vkgl.lang.checks.geometry.rays import FACE_NORMALS, MeshSurface, Surface, at_heights, face_line, shape_surface
from vkgl.lang.checks.geometry.rigid import Vec3
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
    surface = _surface(body)
    if surface is None:
        return
    for face in contacts.faces:
        miss = first_miss(surface, face, contacts.steps, contacts.heights)
        if miss is None:
            continue
        k, height, along, where = miss
        up = f", {100 * height:.1f} cm up the face" if contacts.heights > 1 else ""
        ctx.error(
            codes.CONTACT_OFF_SURFACE,
            f"face {face} of `{body.name}` has no surface at contact point {k + 1} of {contacts.steps} "
            f"({'xyz'[along]} = {100 * where:.1f} cm on its centre line{up}): "
            "the shape is hollow or flat there; use fewer steps or another face",
            ctx.narrow(contacts.span, rf"({re.escape(face)})"),
        )


def first_miss(surface: Surface, face: str, steps: int, heights: int) -> tuple[int, float, int, float] | None:
    """The first contact point of `face` (`steps` along its centre line, at `heights` heights) where the
    explorer's ray meets no surface: (index along the line, height, axis of the line, coordinate on it), or None.
    The underside and unknown faces have none (other checks report them)."""
    outward = FACE_NORMALS.get(face)
    if outward is None or face == "-z":
        return None
    along, points = face_line(surface.bounds, outward, steps)
    inward = (-outward[0], -outward[1], -outward[2])
    for k, height, point in at_heights(surface.bounds, points, heights):
        if surface.ray_hit(point, inward) is None:
            return k, height, along, point[along]
    return None


def _surface(body: ir.Body) -> Surface | None:
    """The body's surface as the explorer sees it (its mesh's triangles), or None when its mesh is unreadable.

    Boxes, cylinders and their unions are triangulated in plain Python (no trimesh, nor SciPy with it)."""
    try:
        surface = shape_surface(body.shape)
    except ValueError:  # a part's pose or size of the wrong length (reported by the builder), as trimesh fails
        return None
    if surface is not None:
        return surface
    from vkgl.lang.ir.geometry import body_mesh  # trimesh: only for a mesh file

    try:
        return MeshSurface(body_mesh(body))
    except Exception:  # an unreadable mesh is E503's business
        return None


FRAME_REACH = 0.01  # m behind a contact frame's origin from which the fingertip comes
FRAME_TOLERANCE = 0.001  # m: how far from the body's surface a contact frame's origin may be


def _check_contact_frames(frames: list[ir.Ref], body: ir.Body, ctx: CheckContext) -> None:
    """A contact frame's origin must lie on the surface, its x axis into the body, with room behind it.

    A ray from FRAME_REACH behind the origin along the frame's x must first
    enter the body within FRAME_TOLERANCE of the origin: the fingertip comes
    from there (behind a handle's bar, say) and pushes along x.
    """
    surface = _surface(body)
    if surface is None:
        return
    for ref in frames:
        frame = body.frame(ref.name)
        assert frame is not None
        values = frame.pose.position.values
        if len(values) > 3:  # `= (1, 2, 3, 4) cm`: reported by the builder
            continue
        origin = (*(float(v) for v in values), 0.0, 0.0, 0.0)[:3]
        r = frame.pose.rotation_matrix()
        found = contact_frame_problem(surface, (origin[0], origin[1], origin[2]), (r[0][0], r[1][0], r[2][0]))
        if found is None:
            continue
        ctx.error(
            codes.CONTACT_OFF_SURFACE,
            f"contact frame `{ref.name}` of `{body.name}` is not on its surface: {found}",
            ref.span,
            "a contact frame sits on the surface to push, its x axis pointing into the body "
            f"(the effector frame convention), with {100 * FRAME_REACH:.0f} cm of room behind it",
        )


def contact_frame_problem(surface: Surface, origin: Vec3, x: Vec3) -> str | None:
    """What is wrong with a contact frame at `origin` pushing along its unit `x` (the words of E415), or None."""
    start = (origin[0] - FRAME_REACH * x[0], origin[1] - FRAME_REACH * x[1], origin[2] - FRAME_REACH * x[2])
    hit = surface.ray_hit(start, x)
    if hit is None:
        return "pushing along its x axis, the fingertip meets nothing"
    point, normal = hit
    distance = _dot(_minus(point, origin), x)
    if _dot(normal, x) < 0 and abs(distance) <= FRAME_TOLERANCE:
        return None
    if _dot(normal, x) > 0:
        return f"{100 * FRAME_REACH:.0f} cm behind it, where the fingertip comes from, is inside the body"
    if distance > 0:
        return f"pushing along its x axis, the fingertip meets the body {100 * distance:.1f} cm beyond it"
    return f"the body is in the way {100 * -distance:.1f} cm before it, where the fingertip comes from"


def _minus(p: Vec3, q: Vec3) -> Vec3:
    return (p[0] - q[0], p[1] - q[1], p[2] - q[2])


def _dot(p: Vec3, q: Vec3) -> float:
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]
