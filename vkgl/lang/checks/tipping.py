"""Semantic checks of `tips above Q [on faces F, ...]` in an `affordances` block (E417).

The height is over the table, from 0 up to the body's height; the faces are
side faces (the top is pushed down, the underside never pushed). The planner
(vkgl/plan/problem/tipping.py) relies on both.
"""

from __future__ import annotations

import re

from vkgl.lang.checks.context import CheckContext, shown
from vkgl.lang.checks.geometry.rays import shape_surface
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir

SIDE_FACES = ("+x", "-x", "+y", "-y")


def check_tipping(block: ir.AffordanceSet, body: ir.Body | None, ctx: CheckContext) -> None:
    """Report every impossible `tips above` clause of `block` (`body`: the body it is about, if known)."""
    if not block.tipping:
        return
    top = _body_height(body) if body is not None else None
    for clause in block.tipping:
        height = clause.height.value
        if height < 0 or (top is not None and height > top + 1e-9):  # (NaN, already reported, fails both)
            limit = f"its height, {100 * top:g} cm" if top is not None else "its height"
            ctx.error(
                codes.TIPPING_HEIGHT,
                f"a tipping height is over the table, from 0 to {limit}; got {shown(clause.height)}",
                clause.height.span or clause.span,
            )
        for face in clause.faces:
            if face not in SIDE_FACES:
                ctx.error(
                    codes.TIPPING_HEIGHT,
                    f"only a push on a side face can tip `{block.body.name}`, not one on `{face}`",
                    ctx.narrow(clause.span, rf"({re.escape(face)})"),
                    "name side faces: `on faces +x, -x, +y, -y`",
                )


def _body_height(body: ir.Body) -> float | None:
    """The body's height (m) as it rests, or None when its shape cannot be read (another error says why)."""
    try:
        surface = shape_surface(body.shape)  # boxes, cylinders and unions: their mesh's triangles, without trimesh
    except ValueError:  # a size or a part's pose of the wrong length: the builder reports it
        return None
    if surface is not None:
        lo, hi = surface.bounds
        return hi[2] - lo[2]
    from vkgl.lang.ir.geometry import body_mesh  # trimesh: only for a mesh file

    try:
        low, high = body_mesh(body).bounds
    except Exception:  # an unreadable or invalid shape is reported by the body's own checks
        return None
    return float(high[2] - low[2])
