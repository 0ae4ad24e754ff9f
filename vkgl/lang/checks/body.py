"""Semantic checks of bodies (shape, mass, frames, joint, explorations) and robots (URDF, effectors).

Every rule about an `explore` block lives here, so the explorer
(vkgl/sim/policy.py) can trust checked IR.
"""

from __future__ import annotations

import math
import os
import re
import sys
from functools import lru_cache
from typing import Any

from vkgl.lang.checks.context import CheckContext, did_you_mean, duplicates, shown, shown_vector
from vkgl.lang.checks.explore import check_explore
from vkgl.lang.checks.grasps import check_grasp_policy
from vkgl.lang.checks.joints import check_joint_dynamics
from vkgl.lang.checks.ranges import check_body_ranges
from vkgl.lang.checks.urdf import urdf_links
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.mesh_limits import file_too_large, flat_problem, too_many_faces
from vkgl.lang.syntax.sources import not_a_regular_file


def check_body(body: ir.Body, ctx: CheckContext) -> None:
    """Report every problem of a body: mass, shape and its files, friction, frames, joint and explorations."""
    if body.mass.value <= 0:
        ctx.error(
            codes.NON_POSITIVE_MASS,
            f"the mass of `{body.name}` must be positive, got {shown(body.mass)}",
            body.mass.span,
        )
    before = len(ctx.diagnostics)
    _check_shape(body.shape, ctx)
    shape_ok = len(ctx.diagnostics) == before
    if body.friction is not None and body.friction < 0:
        ctx.error(
            codes.NEGATIVE_FRICTION,
            f"friction must not be negative, got `{body.friction:g}`",
            ctx.narrow(body.friction_span or body.span, r"friction\s+(\S+)"),
        )
    duplicates(body.frames, "frame", ctx)
    if body.joint is not None:
        _check_joint(body.joint, ctx)
        check_joint_dynamics(body, ctx)
    duplicates(body.explores, "exploration", ctx)
    for explore in body.explores:
        check_explore(explore, body, shape_ok, ctx)
    if body.grasps is not None:
        check_grasp_policy(body.grasps, ctx)
    check_body_ranges(body, ctx)


def _check_shape(shape: Any, ctx: CheckContext) -> None:
    if isinstance(shape, ir.BoxShape):
        if any(v <= 0 for v in shape.size.values):
            ctx.error(
                codes.NON_POSITIVE_SIZE, f"box sizes must be positive, got {shown_vector(shape.size)}", shape.size.span
            )
    elif isinstance(shape, ir.CylinderShape):
        for q, what in ((shape.radius, "radius"), (shape.height, "height")):
            if q.value <= 0:
                ctx.error(codes.NON_POSITIVE_SIZE, f"the cylinder's {what} must be positive, got {shown(q)}", q.span)
    elif isinstance(shape, ir.MeshShape):
        if shape.scale <= 0:
            ctx.error(
                codes.NON_POSITIVE_SIZE,
                f"a mesh scale must be positive, got `{shape.scale:g}`",
                ctx.narrow(shape.span, r"scale\s+(\S+)"),
            )
        _check_mesh_file(shape, ctx)
    elif isinstance(shape, ir.UnionShape):
        for part in shape.parts:
            _check_shape(part.shape, ctx)


def _check_mesh_file(shape: ir.MeshShape, ctx: CheckContext) -> None:
    problem = _mesh_problem(shape.resolved or shape.path)
    if problem and problem.startswith(_TOO_LARGE):
        ctx.error(
            codes.MESH_TOO_LARGE,
            f"cannot use mesh `{shape.path}`: {problem.removeprefix(_TOO_LARGE)}",
            ctx.narrow(shape.span, r'mesh\s+("[^"]*")'),
            "simplify it (decimate it: a collision shape rarely needs more than a few thousand triangles)",
        )
    elif problem:
        ctx.error(
            codes.MESH_UNREADABLE,
            f"cannot use mesh `{shape.path}`: {problem}",
            ctx.narrow(shape.span, r'mesh\s+("[^"]*")'),
            _looked_for(shape.resolved, problem),
        )


def _looked_for(resolved: str | None, problem: str) -> str:
    """For a missing file: where it was looked for (paths are relative to the module that names them)."""
    if problem != "no such file" or not resolved:
        return ""
    try:
        relative = os.path.relpath(resolved)
    except ValueError:  # another drive on Windows
        relative = resolved
    shown = resolved if relative.startswith("..") else relative
    return f"looked for `{shown}`: the path is relative to the module's file"


_TOO_LARGE = "too large: "  # how _mesh_problem marks a mesh past the limits (E511, not E503)


@lru_cache(maxsize=64)
def _mesh_problem(path: str) -> str | None:
    """Why trimesh cannot give triangles for `path`, or None when it can."""
    problem = not_a_regular_file(path)  # a FIFO would hang trimesh, /dev/zero never ends
    if problem:
        return problem
    refused = file_too_large(path)
    if refused is not None:
        return _TOO_LARGE + refused
    import trimesh

    try:
        loaded = trimesh.load(path, force="mesh")
    except Exception as exc:  # trimesh raises many types; its message says why
        return f"trimesh cannot read it ({type(exc).__name__}: {exc})"
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        return "the file holds no triangles"
    refused = too_many_faces(len(loaded.faces))
    if refused is not None:
        return _TOO_LARGE + refused
    return flat_problem(loaded.vertices)


def _check_joint(joint: ir.Joint, ctx: CheckContext) -> None:
    check_direction(joint.axis, "a joint axis", ctx)
    if joint.lower.value > joint.upper.value:
        ctx.error(
            codes.REVERSED_LIMITS,
            f"joint limits are reversed: lower {shown(joint.lower)} > upper {shown(joint.upper)}; write (lower, upper)",
            joint.lower.span,
        )


def check_direction(vector: ir.Vector, what: str, ctx: CheckContext) -> None:
    """Report a direction vector (`what`, e.g. "a joint axis") that is zero, or whose length is not a normal
    positive float: it is divided by its length, which underflows to 0 (or overflows) and gives a NaN axis."""
    if not len(vector.values):
        return
    values = [float(v) for v in vector.values]
    if all(v == 0 for v in values):
        ctx.error(codes.ZERO_DIRECTION, f"{what} must not be zero", vector.span)
        return
    if not all(math.isfinite(v) for v in values):
        return  # reported where the number was read
    squared = sum(v * v for v in values)  # as the simulator normalises it: v / sqrt(v . v); inf past the range
    if math.isfinite(squared) and squared >= sys.float_info.min:
        return
    scale = max(abs(v) for v in values)
    length = scale * math.sqrt(sum((v / scale) ** 2 for v in values))
    why = "underflows to 0" if squared < sys.float_info.min else "overflows"
    ctx.error(
        codes.ZERO_DIRECTION,
        f"{what} of length {length:.3g} gives no direction: its length squared {why} in floating point",
        vector.span,
        "write the direction with ordinary numbers, e.g. `(1, 0, 0)`: only its direction counts",
    )


def check_robot(robot: ir.Robot, ctx: CheckContext) -> None:
    """Report a robot's duplicate effectors, an unusable URDF and effector links the URDF lacks."""
    duplicates(robot.effectors, "effector", ctx)
    path = robot.urdf_resolved or robot.urdf
    links, problem = urdf_links(path)
    if problem:
        ctx.error(
            codes.URDF_UNREADABLE,
            f"cannot use URDF `{robot.urdf}`: {problem}",
            ctx.narrow(robot.urdf_span or robot.span, r'urdf\s+("[^"]*")'),
            _looked_for(robot.urdf_resolved, problem),
        )
        return
    for effector in robot.effectors:
        if effector.link not in links:
            ctx.error(
                codes.UNKNOWN_LINK,
                f"the URDF of `{robot.name}` has no link `{effector.link}`",
                ctx.narrow(effector.span, rf"link\s+({re.escape(effector.link)})\b"),
                did_you_mean(effector.link, sorted(links)),
            )
