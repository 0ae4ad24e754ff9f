"""One member of an affordance's contact family: the point affordance at a chosen offset along the face.

`family along DIR from LO to HI UNIT [drift VEC] [sigma Q]` (docs/language.md,
"Families") lets the contact be the action's pose moved by `s * DIR` for any
offset `s` in [LO, HI]. `at_offset(affordance, s)` is that member as a plain
affordance (no family): its action moved along the face; a slide unchanged, or
with an `arc` the turn a push off the centre makes (`vkgl.lang.ir.arcs`); a
turn about its pivot moved by `s * drift`. Offset 0 is the affordance itself.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

from vkgl.lang.ir.arcs import arc_motion, law_beyond, unit
from vkgl.lang.ir.nodes import Affordance, FixedC, PrismaticC, RevoluteC
from vkgl.lang.ir.values import Vector


def offset_bounds(affordance: Affordance) -> tuple[float, float]:
    """The offsets (m) its contact may take: the family's band, or (0, 0) for a point affordance."""
    family = affordance.family
    return (0.0, 0.0) if family is None else (float(family.lower.value), float(family.upper.value))


def arc_beyond(affordance: Affordance) -> float:
    """The offset (m, from the centre) from which its family's arc law was measured (`arc ... beyond Q`): nearer
    the centre its members' turn is not known (`vkgl.lang.ir.arcs.law_known`); 0 when the law holds over the whole
    band (or there is no arc)."""
    family = affordance.family
    return 0.0 if family is None or family.arc is None else law_beyond(family.arc)


def at_offset(affordance: Affordance, offset: float) -> Affordance:
    """The member of `affordance`'s family at `offset` (m along its direction), without a family.

    Raises ValueError for an offset outside the band (or any but 0 without a family).
    """
    lower, upper = offset_bounds(affordance)
    if not lower - 1e-12 <= offset <= upper + 1e-12:
        raise ValueError(f"offset {offset:g} m is outside the family's band [{lower:g}, {upper:g}] m")
    family = affordance.family
    if family is None or offset == 0.0:
        return affordance.model_copy(update={"family": None})
    along = unit(family.along.values)
    action = affordance.action
    if isinstance(action, FixedC) and action.pose is not None:
        position = _moved(action.pose.position, along, offset)
        action = action.model_copy(update={"pose": action.pose.model_copy(update={"position": position})})
    motion = affordance.motion
    if isinstance(motion, PrismaticC) and family.arc is not None and isinstance(affordance.action, FixedC):
        assert affordance.action.pose is not None  # checked (E470)
        contact = affordance.action.pose.position.values
        motion = arc_motion(motion, contact, along, family.arc, offset)
    elif isinstance(motion, RevoluteC) and family.drift is not None:
        motion = motion.model_copy(update={"center": _moved(motion.center, family.drift.values, offset)})
    return affordance.model_copy(update={"action": action, "motion": motion, "family": None})


def slide_member(affordance: Affordance, offset: float) -> Affordance:
    """A slide enacted `offset` (m) along its face by a tool's flat face: its action moved along the action
    frame's y axis, its motion the same (and no family: a point's arc does not apply). The planner names such
    members (`NAME@+2.00cm/straight`) only for a tool whose flat face still covers the body's centre line there
    (`vkgl.plan.graphs.tool_faces`); the motion is what DART then shows."""
    action = affordance.action
    if offset == 0.0 or not isinstance(action, FixedC) or action.pose is None:
        return affordance.model_copy(update={"family": None})
    along = tuple(float(v) for v in action.pose.matrix()[:3, 1])
    position = _moved(action.pose.position, along, offset)
    action = action.model_copy(update={"pose": action.pose.model_copy(update={"position": position})})
    return affordance.model_copy(update={"action": action, "family": None})


def over_member(affordance: Affordance, roll: float, lift: float) -> Affordance:
    """A slide (or an arc's member, a turn) enacted by a tool rolled `roll` (rad) about the push direction and raised
    `lift` (m): its action pose rolled about the action frame's x axis (positive: its y axis toward the body's up)
    and moved up by `lift`, its motion the same (no family). The planner names such members
    (`NAME/over+30deg+1.00cm`, `NAME@-1.74cm/over+20deg+0.50cm`) for a tool whose parts beside its contact would
    stand in the body lying flat and pass over its top rolled (`vkgl.plan.problem.over`).

    Raises ValueError for an action that is not a fixed pose with a yaw alone (a flat face pushed level)."""
    action = affordance.action
    if not isinstance(action, FixedC) or action.pose is None or action.pose.rpy is not None:
        raise ValueError(f"{affordance.name} has no level action to roll")
    yaw = action.pose.yaw.value if action.pose.yaw is not None else 0.0
    position = _moved(action.pose.position, (0.0, 0.0, 1.0), lift)
    rpy = Vector(values=(roll, 0.0, yaw), unit="deg")  # extrinsic x then z: the yaw's frame rolled about its own x
    pose = action.pose.model_copy(update={"position": position, "yaw": None, "rpy": rpy})
    return affordance.model_copy(update={"action": action.model_copy(update={"pose": pose}), "family": None})


def _moved(point: Vector, direction: tuple[float, ...], offset: float) -> Vector:
    return point.model_copy(update={"values": tuple(p + offset * d for p, d in zip(point.values, direction))})


MEMBER_MARK = "@"
"""`push_center_px@+3.12cm`: the member of `push_center_px`'s family at offset +3.12 cm (how plans name it)."""

STRAIGHT_MARK = "/straight"
"""`push_center_nx@+2.00cm/straight`: the slide itself, its contact 2 cm along the face (`slide_member`)."""


OVER_MARK = "/over"
"""`push_center_nx/over+30deg+1.00cm`: the slide enacted by a tool rolled 30 deg about the push and raised 1 cm
(`over_member`)."""


def over_name(name: str, roll: float, lift: float) -> str:
    """The name of the slide `name` enacted rolled by `roll` (rad, to 1 deg) and raised by `lift` (m, to 0.01 cm)."""
    return f"{name}{OVER_MARK}{math.degrees(roll):+.0f}deg{100.0 * lift:+.2f}cm"


def over_pose(name: str) -> tuple[str, float, float] | None:
    """(the slide's name, the roll in rad, the lift in m) of an over member's name (`over_name`); None for any
    other name. Raises ValueError for a name with the mark but no `+Ndeg+N.NNcm` after it."""
    base, mark, rest = name.partition(OVER_MARK)
    if not mark:
        return None
    roll, _, lift = rest.partition("deg")
    try:
        if not lift.endswith("cm"):
            raise ValueError(rest)
        return base, math.radians(float(roll)), float(lift[:-2]) / 100.0
    except ValueError:
        raise ValueError(f"`{name}` names no rolled slide (write `NAME/over+30deg+1.00cm`)") from None


def member_name(name: str, offset: float, *, straight: bool = False) -> str:
    """The name of the member at `offset` (m), to 0.01 cm: `name@+3.12cm`; `name` itself at offset 0.

    `straight`: a slide a tool's flat face enacts off the centre (`slide_member`), `name@+2.00cm/straight`: its
    own name, since the same slide's arc family (if it has one) names the turn a point makes there."""
    text = f"{100.0 * offset:+.2f}"
    if float(text) == 0.0:
        return name
    return f"{name}{MEMBER_MARK}{text}cm{STRAIGHT_MARK if straight else ''}"


def member_offset(name: str) -> tuple[str, float]:
    """(the family's name, the offset in m) of a member's name; (name, 0) for a plain name.

    Raises ValueError for a name with a mark but no `+N.NNcm` after it.
    """
    base, mark, rest = name.partition(MEMBER_MARK)
    if not mark:
        return name, 0.0
    rest = rest.removesuffix(STRAIGHT_MARK)
    if not rest.endswith("cm"):
        raise ValueError(f"`{name}` names no member of a family (write `NAME@+1.25cm`)")
    return base, float(rest[:-2]) / 100.0


def is_straight_member(name: str) -> bool:
    """Whether `name` names a slide enacted straight off the centre by a tool's flat face (`NAME@+2.00cm/straight`)."""
    return MEMBER_MARK in name and name.endswith(STRAIGHT_MARK)


def tool_only(name: str) -> bool:
    """Whether `name` names a member that only the tool effector it was made for may enact: a slide or an arc's
    member by a tool rolled (`NAME/over+20deg+1.00cm`), or a slide by a tool's flat face off the centre
    (`NAME@+2.00cm/straight`), listed in its body's `PlanBody.tool_members` with that effector."""
    return OVER_MARK in name or is_straight_member(name)


def find_member(affordances: Iterable[Affordance], name: str) -> Affordance | None:
    """The affordance called `name` among `affordances`, or the member `name` names (`push@+3.12cm`, a slide rolled
    `push/over+20deg+1.00cm`, an arc's member rolled `push@-1.74cm/over+20deg+0.50cm`, a straight member rolled
    `push@-4.00cm/straight/over+20deg+0.50cm`), renamed so; None when there
    is none (or the offset is outside the family's band by more than its rounding)."""
    over = over_pose(name)
    if over is not None:
        if (
            MEMBER_MARK in over[0]
        ):  # an arc's member rolled (`push@-1.74cm/over..`), or a straight one (`../straight/over..`)
            moved = find_member(affordances, over[0])
            return None if moved is None else over_member(moved, over[1], over[2]).model_copy(update={"name": name})
        slide = next((a for a in affordances if a.name == over[0]), None)
        if slide is None or not isinstance(slide.motion, PrismaticC):
            return None
        return over_member(slide, over[1], over[2]).model_copy(update={"name": name})
    base, offset = member_offset(name)
    found = next((a for a in affordances if a.name == base), None)
    if found is None or base == name:
        return found
    if is_straight_member(name):
        if not isinstance(found.motion, PrismaticC):
            return None
        return slide_member(found, offset).model_copy(update={"name": name})
    lower, upper = offset_bounds(found)
    if not lower - 5e-5 <= offset <= upper + 5e-5:  # names round offsets to 0.01 cm
        return None
    return at_offset(found, min(max(offset, lower), upper)).model_copy(update={"name": name})
