"""Plausibility ranges (E209, E210): positive but absurd masses, sizes, forces, durations, counts, ...

The ranges live in vkgl/lang/ir/limits.py (and docs/language.md states them).
Values at or below zero are left to their own codes (E401, E402, E403, E411),
and NaN marks a value already reported, so each value gets at most one error.
"""

from __future__ import annotations

from typing import Any

from vkgl.lang.checks.context import CheckContext, shown, shown_vector
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import limits
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.limits import Limit


def _positive_out(value: float, limit: Limit) -> bool:
    return value > 0 and not limit.holds(value)


def check_quantity(q: ir.Quantity | None, what: str, limit: Limit, ctx: CheckContext) -> None:
    """E209 when the positive quantity `q` (`what`: "the mass of `B`") lies outside `limit`."""
    if q is not None and _positive_out(q.value, limit):
        ctx.error(codes.OUT_OF_RANGE, f"{what} must be {limit.shown}, got {shown(q)}", q.span)


def check_number(value: float | None, what: str, limit: Limit, span: ir.Span | None, ctx: CheckContext) -> None:
    """E209 for a plain number (friction, mesh scale) outside `limit`; negative ones have their own codes."""
    if value is not None and value >= 0 and not limit.holds(value) and (value > 0 or limit.low <= 0):
        ctx.error(codes.OUT_OF_RANGE, f"{what} must be {limit.shown}, got `{value:g}`", span)


def check_count(value: int | None, what: str, limit: Limit, span: ir.Span | None, ctx: CheckContext) -> None:
    """E210 for a count above its limit (counts below 1 are E411's)."""
    if value is not None and value > limit.high:
        ctx.error(codes.COUNT_OUT_OF_RANGE, f"{what} must be {limit.shown}, got {value}", span)


def check_body_ranges(body: ir.Body, ctx: CheckContext) -> None:
    """Mass, shape sizes, mesh scales and friction of a body."""
    check_quantity(body.mass, f"the mass of `{body.name}`", limits.MASS, ctx)
    _check_shape(body.shape, ctx)
    if body.friction is not None:
        span = ctx.narrow(body.friction_span or body.span, r"friction\s+(\S+)")
        check_number(body.friction, "friction", limits.FRICTION, span, ctx)


def _check_shape(shape: Any, ctx: CheckContext) -> None:
    if isinstance(shape, ir.BoxShape):
        bad = [v for v in shape.size.values if _positive_out(v, limits.SIZE)]
        if bad and all(v > 0 for v in shape.size.values):
            ctx.error(
                codes.OUT_OF_RANGE,
                f"box sizes must be {limits.SIZE.shown}, got {shown_vector(shape.size)}",
                shape.size.span,
            )
    elif isinstance(shape, ir.CylinderShape):
        check_quantity(shape.radius, "the cylinder's radius", limits.SIZE, ctx)
        check_quantity(shape.height, "the cylinder's height", limits.SIZE, ctx)
    elif isinstance(shape, ir.MeshShape):
        span = ctx.narrow(shape.span, r"scale\s+(\S+)")
        if shape.scale > 0:
            check_number(shape.scale, "a mesh scale", limits.MESH_SCALE, span, ctx)
    elif isinstance(shape, ir.UnionShape):
        for part in shape.parts:
            _check_shape(part.shape, ctx)


def check_explore_ranges(explore: ir.Explore, ctx: CheckContext) -> None:
    """Steps, heights, direction grid sizes, force and duration of an `explore` block."""
    if explore.contacts is not None:
        span = ctx.narrow(explore.contacts.span, r"steps\s+(\S+)")
        check_count(explore.contacts.steps, "`steps`", limits.STEPS, span, ctx)
        if explore.contacts.heights != 1:
            span = ctx.narrow(explore.contacts.span, r"heights\s+(\S+)")
            check_count(explore.contacts.heights, "`heights`", limits.HEIGHTS, span, ctx)
    force = explore.force
    if force is not None:
        if force.grid is not None and max(force.grid) > limits.GRID.high:
            span = ctx.narrow(force.span, r"directions\s+(\S+\s*x\s*\S+\s*x\s*\S+)")
            grid = " x ".join(str(n) for n in force.grid)
            ctx.error(
                codes.COUNT_OUT_OF_RANGE, f"each direction grid size must be {limits.GRID.shown}, got {grid}", span
            )
        check_quantity(force.magnitude, "the force", limits.FORCE, ctx)
    check_quantity(explore.duration, "the duration", limits.DURATION, ctx)


def check_search_ranges(search: ir.SearchSpec, ctx: CheckContext) -> None:
    """`max_depth` (at most the CLI's --max-depth limit) and the timeout of a task's search."""
    span = ctx.narrow(search.span, r"max_depth\s+(\S+)")
    check_count(search.max_depth, "`max_depth`", limits.MAX_DEPTH, span, ctx)
    check_quantity(search.timeout, "the timeout", limits.TIMEOUT, ctx)


def check_evidence_ranges(evidence: ir.Evidence, ctx: CheckContext) -> None:
    """The trial count of an affordance's evidence (0 to a million)."""
    span = ctx.narrow(evidence.span, r"trials\s+(\S+)")
    if evidence.trials < 0:
        ctx.error(codes.COUNT_OUT_OF_RANGE, f"`trials` must be {limits.TRIALS.shown}, got {evidence.trials}", span)
    check_count(evidence.trials, "`trials`", limits.TRIALS, span, ctx)
