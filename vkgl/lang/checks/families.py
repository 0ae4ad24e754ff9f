"""Checks of an affordance's contact family (`family along DIR from LO to HI UNIT [drift VEC] [sigma Q]`).

The codes are E470 to E473 (vkgl/lang/diagnostics/codes_families.py); the
meaning is in docs/language.md, "Families".
"""

from __future__ import annotations

import math

from vkgl.lang.checks.body import check_direction
from vkgl.lang.checks.context import CheckContext, shown
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import dimension_of

ACROSS = math.sin(math.radians(1.0))
"""A family's direction may lean this much (the sine of 1 deg) towards a slide's direction or a turn's axis."""


def check_family(affordance: ir.Affordance, ctx: CheckContext) -> None:
    """Report what makes `affordance.family` meaningless: no contact, a direction off the face, a band without
    the action's contact, a drift or sigma that does not fit the motion."""
    family = affordance.family
    if family is None:
        return
    motion = affordance.motion
    action = affordance.action
    if not isinstance(motion, (ir.PrismaticC, ir.RevoluteC)) or not (
        isinstance(action, ir.FixedC) and action.pose is not None
    ):
        why = "no pose" if isinstance(motion, (ir.PrismaticC, ir.RevoluteC)) else f"a `{motion.type}` motion"
        ctx.error(
            codes.FAMILY_WITHOUT_CONTACT,
            f"affordance `{affordance.name}` has {why}: a family moves a push's contact along its face",
            _head(family, ctx),
            "a family needs `action fixed at POSE` and a `prismatic` or `revolute` motion; remove the `family` line",
        )
        return
    check_direction(family.along, "a family's direction", ctx)
    _check_across(family, motion, ctx)
    _check_band(family, ctx)
    _check_spread(family, motion, ctx)
    _check_arc(family, motion, ctx)


def _head(family: ir.Family, ctx: CheckContext) -> ir.Span | None:
    return ctx.narrow(family.span, r"^\s*(family)\b")


def _unit(values: tuple[float, ...]) -> tuple[float, ...] | None:
    length = math.sqrt(sum(v * v for v in values))
    return tuple(v / length for v in values) if length > 0 and math.isfinite(length) else None


def _check_across(family: ir.Family, motion: ir.PrismaticC | ir.RevoluteC, ctx: CheckContext) -> None:
    along, axis = _unit(family.along.values), _unit(motion.axis.values)
    if along is None or axis is None or len(along) != len(axis):
        return  # reported as a zero direction (or a wrong component count)
    lean = abs(sum(a * b for a, b in zip(along, axis)))
    if lean > ACROSS:
        what = "slide's direction" if isinstance(motion, ir.PrismaticC) else "turn's axis"
        ctx.error(
            codes.FAMILY_OFF_THE_FACE,
            f"the family's direction leans {math.degrees(math.asin(min(lean, 1.0))):.1f} deg towards the {what}: "
            "the contact would leave the face",
            family.along.span,
            f"write a direction at right angles to the {what} (within 1 deg), along the face",
        )


def _check_band(family: ir.Family, ctx: CheckContext) -> None:
    lower, upper = family.lower, family.upper
    if lower.value > upper.value:
        ctx.error(
            codes.FAMILY_WITHOUT_ITS_CONTACT,
            f"the family's lower offset {shown(lower)} is above its upper offset {shown(upper)}",
            ctx.narrow(family.span, r"\b(from\s+\S+\s+to\s+\S+(?:\s+(?:m|cm|mm)\b)?)"),
            "write `from LOWER to UPPER UNIT`: swap them",
        )
    elif lower.value > 0 or upper.value < 0:
        ctx.error(
            codes.FAMILY_WITHOUT_ITS_CONTACT,
            f"the family's offsets {shown(lower)} to {shown(upper)} leave out the action's own contact (offset 0)",
            ctx.narrow(family.span, r"\b(from\s+\S+\s+to\s+\S+(?:\s+(?:m|cm|mm)\b)?)"),
            "offsets are measured from the action's pose, where the motion was measured: the band must hold 0",
        )


def _check_spread(family: ir.Family, motion: ir.PrismaticC | ir.RevoluteC, ctx: CheckContext) -> None:
    if family.drift is not None and isinstance(motion, ir.PrismaticC):
        ctx.error(
            codes.FAMILY_WRONG_SPREAD,
            "a slide has no pivot to drift: `drift` is for turns",
            ctx.narrow(family.span, r"\b(drift)\b"),
            "remove `drift` (a slide is the same at every offset of its family)",
        )
    sigma = family.sigma
    if sigma is None or sigma.value != sigma.value:
        return
    want = "length" if isinstance(motion, ir.RevoluteC) and family.arc is None else "angle"
    if sigma.unit and dimension_of(sigma.unit) != want:
        ctx.error(
            codes.FAMILY_WRONG_SPREAD,
            f"a {'turn' if want == 'length' else 'slide'}'s sigma is {'a length' if want == 'length' else 'an angle'}"
            f", got {shown(sigma)}",
            ctx.narrow(family.span, r"\b(sigma\s+.+)$"),
            "a turn's sigma is the spread of its pivot (e.g. `0.3 cm`), a slide's the spread of its direction "
            "(e.g. `0.1deg`)",
        )
    elif sigma.value < 0:
        ctx.error(
            codes.FAMILY_WRONG_SPREAD,
            f"a sigma is a spread, never negative: got {shown(sigma)}",
            ctx.narrow(family.span, r"\b(sigma\s+.+)$"),
            "write how far the explored contacts spread about the family, 0 or more",
        )


def _check_arc(family: ir.Family, motion: ir.PrismaticC | ir.RevoluteC, ctx: CheckContext) -> None:
    arc = family.arc
    if arc is None:
        return
    where = ctx.narrow(family.span, r"\b(arc\b.*?ahead\s+\S+(?:\s+(?:m|cm|mm)\b)?)")
    if isinstance(motion, ir.RevoluteC) or family.drift is not None:
        ctx.error(
            codes.FAMILY_BAD_ARC,
            "an `arc` is a slide's: "
            + ("a turn's family moves its pivot with `drift`" if family.drift is None else "it has no `drift`"),
            where,
            "write `arc` in the family of a `prismatic` motion, without `drift`",
        )
        return
    lever, bias = arc.lever.value, arc.bias.value
    if lever != lever or bias != bias:
        return  # a bad quantity, reported where it was read
    if lever <= 0:
        ctx.error(
            codes.FAMILY_BAD_ARC,
            f"an arc's lever is more than 0, got {shown(arc.lever)}",
            where,
            "the lever is the length whose square over the offset places the pivot, e.g. `lever 4.8 cm`",
        )
        return
    farthest = max(abs(family.lower.value), abs(family.upper.value))
    if farthest == farthest and farthest > 0 and lever * lever / farthest + bias <= 0:
        ctx.error(
            codes.FAMILY_BAD_ARC,
            f"at the band's end ({farthest * 100:.3g} cm off the centre) the arc's pivot would lie "
            f"{-(lever * lever / farthest + bias) * 100:.3g} cm on the contact's own side of the centre line",
            where,
            "the pivot lies beyond the centre line over the whole band: raise `bias`, widen `lever` or narrow the band",
        )
    beyond = arc.beyond
    if beyond is not None and beyond.value == beyond.value and not 0 < beyond.value <= farthest:
        ctx.error(
            codes.FAMILY_BAD_ARC,
            f"an arc's `beyond` lies off the centre inside the band, got {shown(beyond)} (the band reaches "
            f"{farthest * 100:.3g} cm)",
            ctx.narrow(family.span, r"\b(beyond\s+\S+(?:\s+(?:m|cm|mm)\b)?)"),
            "`beyond` is the offset nearest the centre where the law holds, e.g. `beyond 2.67 cm`",
        )
