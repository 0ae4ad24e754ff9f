"""The member of a slide's arc family at an offset: the turn that a push off the centre makes.

`family along DIR from LO to HI UNIT arc lever L bias B ahead A` (docs/language.md, "Arcs") on a slide
pushed from the contact P (the action's position) along N (the slide's direction, unit): pushed at offset s
along DIR (unit), the body turns about the pivot

    P + A * N - sign(s) * (L**2 / |s| + B) * DIR

about the axis -sign(s) * (N x DIR), so that the contact moves forward along N as it starts to turn. A turn of
angle t moves the contact along its arc by t * hypot(L**2 / |s| + B, A); the member's range is the slide's range
in that travel, `open` when the slide's is (the body was still moving when exploration ended: pushed on, it goes
on turning, as a pushed slide goes on sliding). At s = 0 the member is the slide itself (the pivot is at infinity).

The family's `sigma` (an angle) is the law's RMS error in the turn over `SIGMA_TRAVEL` (10 cm) of the contact's
travel: a member turned by t is uncertain by sigma * t * hypot(...) / 10 cm (`arc_turn_error`). With `beyond D`
that holds for |s| >= D only: nearer the centre (but at 0) the turn is not known (`law_known`).
"""

from __future__ import annotations

import math

from vkgl.lang.ir.nodes import Arc, MotionRange, PrismaticC, RevoluteC
from vkgl.lang.ir.values import Quantity, Vector


def arc_radius(arc: Arc, offset: float) -> float:
    """The pivot's distance across the push from the centre line (m) at `offset` (m); inf at 0."""
    if offset == 0.0:
        return math.inf
    return arc.lever.value**2 / abs(offset) + arc.bias.value


def law_beyond(arc: Arc) -> float:
    """The offset (m, from the centre) from which the law was measured (`beyond`); 0: up to the centre."""
    return 0.0 if arc.beyond is None else float(arc.beyond.value)


def law_known(arc: Arc, offset: float) -> bool:
    """Whether the law's turn at `offset` (m) is known: at the centre (the slide) and from `beyond` out. Between
    them the explored pushes never showed how the pivot comes in from the slide's infinity (CrateT turned 13 deg
    slower over 10 cm than its law there): the member's turn is only known to lie between the slide's (none) and
    the turn at `beyond`, the turn growing with the offset."""
    return offset == 0.0 or abs(offset) >= law_beyond(arc) - 1e-9


SIGMA_TRAVEL = 0.10
"""m: an arc family's `sigma` is the RMS error of the law's turn over this much of the contact's travel
(docs/language.md, "Arcs"; `vkgl.infer.faces.arc` scales each explored push's error to it)."""


def arc_turn_error(arc: Arc, sigma: float, offset: float, turn: float) -> float:
    """The RMS error (rad) of the turn the law predicts for its member at `offset` (m, not 0) turned by `turn`
    (rad): `sigma` (rad over 10 cm of travel) times the contact's travel along the arc in tens of centimetres (the
    error grows with the push: the law turns the body at its own rate, DART at the body's)."""
    return sigma * abs(turn) * arc_lever_arm(arc, offset) / SIGMA_TRAVEL


def arc_lever_arm(arc: Arc, offset: float) -> float:
    """The contact's distance from the pivot (m) at `offset`: its travel per radian of turn; inf at 0."""
    return math.hypot(arc_radius(arc, offset), arc.ahead.value)


def arc_motion(
    slide: PrismaticC, contact: tuple[float, ...], along: tuple[float, ...], arc: Arc, offset: float
) -> RevoluteC:
    """The turn of the member at `offset` (m, not 0) of a slide's arc family whose offset-0 contact is `contact`
    (body frame, m) and whose face direction is `along` (unit)."""
    if offset == 0.0:
        raise ValueError("the member at offset 0 of an arc family is the slide itself")
    normal = unit(slide.axis.values)
    side = 1.0 if offset > 0 else -1.0
    across = arc_radius(arc, offset)
    ahead = arc.ahead.value
    center = tuple(p + ahead * n - side * across * a for p, n, a in zip(contact, normal, along))
    axis = tuple(0.0 - side * v for v in _cross(normal, along))  # 0.0 -: no -0 in printed axes
    turn_range = None
    if slide.range is not None:
        lever = arc_lever_arm(arc, offset)
        turn_range = MotionRange(
            lower=Quantity(value=slide.range.lower.value / lever, unit="deg"),
            upper=Quantity(value=slide.range.upper.value / lever, unit="deg"),
            open=slide.range.open,  # still sliding when exploration ended: so is the arc (the planner caps it)
        )
    return RevoluteC(center=Vector(values=center, unit="cm"), axis=Vector(values=axis), range=turn_range)


def unit(values: tuple[float, ...]) -> tuple[float, ...]:
    """`values` scaled to length 1 (plain floats: the IR's vectors need no numpy)."""
    length = math.sqrt(sum(v * v for v in values))
    return tuple(v / length for v in values)


def _cross(a: tuple[float, ...], b: tuple[float, ...]) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
