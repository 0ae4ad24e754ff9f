"""Checks of physical joints' dynamics (`damping`, `friction`), of joint goals (`goal B open Q`) and of
joints' starts (`B : T at POSE open Q` in a scene).

A joint goal names a scene body whose type must have a physical joint (E441);
its opening is a length for a prismatic joint and an angle for a revolute one
(E201); and it should lie within the joint's limits, give or take its
tolerance (W604: a warning, because the task is well formed and the planner
answers it with "no plan", with the same numbers). A scene body that starts
`open Q` needs a joint too (E441), an opening of the joint's kind (E201), and
one within the joint's limits (E442: an error, since no simulated joint can
start beyond its stops); one placed without `open` starts at 0, so its limits
must include 0 (E442 too).
"""

from __future__ import annotations

import math

from vkgl.lang.checks.context import CheckContext, goals_with_types, shown
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import limits
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.limits import Limit
from vkgl.lang.ir.program import Program
from vkgl.lang.ir.units import dimension_of, unit_list

# The range of a joint's damping and friction, by the kind of joint (the units the builder checked).
_DYNAMICS_LIMITS: dict[str, dict[str, Limit]] = {
    "prismatic": {"damping": limits.LINEAR_DAMPING, "friction": limits.JOINT_FORCE},
    "revolute": {"damping": limits.ANGULAR_DAMPING, "friction": limits.JOINT_TORQUE},
}
# How a joint of each kind is called in messages, and what its coordinate is.
_JOINT_WORD = {"prismatic": "slide", "revolute": "hinge"}
_OPENING_DIMENSION = {"prismatic": "length", "revolute": "angle"}


def check_joint_dynamics(body: ir.Body, ctx: CheckContext) -> None:
    """E440 for a negative damping or friction of the body's joint, E209 for one beyond its range."""
    joint = body.joint
    if joint is None:
        return
    for what, q in (("damping", joint.damping), ("friction", joint.friction)):
        if q is None:
            continue
        if q.value < 0:  # (NaN, already reported, fails every comparison)
            ctx.error(
                codes.NEGATIVE_JOINT_DYNAMICS,
                f"the {what} of `{body.name}`'s joint must not be negative, got {shown(q)}",
                q.span,
                f"{what} resists the joint's motion; 0 means none",
            )
        elif not _DYNAMICS_LIMITS[joint.type][what].holds(q.value):
            limit = _DYNAMICS_LIMITS[joint.type][what]
            ctx.error(
                codes.OUT_OF_RANGE,
                f"the {what} of `{body.name}`'s joint must be {limit.shown}, got {shown(q)}",
                q.span,
            )


def opening_problem(opening: ir.Quantity, joint: ir.Joint) -> str | None:
    """What is wrong with `opening` as a coordinate of `joint`: "unit" (none, or of the other kind), "limits"
    (outside them, which must hold and be in order), or None when it is a coordinate the joint can take."""
    if not opening.unit or not math.isfinite(opening.value):
        return "unit"
    if dimension_of(opening.unit) != _OPENING_DIMENSION[joint.type]:
        return "unit"
    lower, upper = joint.lower.value, joint.upper.value
    if not (math.isfinite(lower) and math.isfinite(upper) and lower <= upper):
        return "limits"
    return None if lower - 1e-12 <= opening.value <= upper + 1e-12 else "limits"


def check_joint_goals(program: Program, ctx: CheckContext) -> None:
    """Every joint goal of every task: a body with a joint (E441), the right kind of value (E201), the limits (W604);
    every scene body that starts `open Q`: a joint (E441), the right kind (E201), within its limits (E442)."""
    for each in program.scenes.values():
        for placed in each.bodies:
            body = program.bodies.get(placed.type.name)
            if placed.opening is not None and body is not None:
                _check_start_opening(placed, placed.opening, body, ctx)
            elif body is not None and body.joint is not None:
                _check_implicit_start(placed, body.joint, ctx)
    for goal, kind in goals_with_types(program):
        body = program.bodies.get(kind)
        if goal.opening is not None and body is not None:
            _check_joint_goal(goal, goal.opening, body, ctx)


def _check_joint_goal(goal: ir.Goal, opening: ir.Quantity, body: ir.Body, ctx: CheckContext) -> None:
    name = goal.body.name
    joint = body.joint
    if joint is None:
        ctx.error(
            codes.NO_JOINT_TO_OPEN,
            f"`{name}` has no physical joint to open: its type `{body.name}` declares no `joint`",
            goal.body.span,
            f"give `{name}` a pose goal instead (`goal {name} at (x, y) m`), or declare a joint in `{body.name}`",
        )
        return
    also = " (and for its tolerance)" if goal.tol_opening is not None else ""
    if _of_the_joints_kind(name, opening, joint, ctx, also):
        _check_within_limits(goal, opening, joint, ctx)


def _of_the_joints_kind(name: str, opening: ir.Quantity, joint: ir.Joint, ctx: CheckContext, also: str = "") -> bool:
    """Whether `opening` is a length for a prismatic joint, an angle for a revolute one (else E201, reported);
    False too for a quantity whose unit was already reported."""
    if not opening.unit or math.isnan(opening.value):
        return False  # its unit was already reported
    wanted = _OPENING_DIMENSION[joint.type]
    if dimension_of(opening.unit) == wanted:
        return True
    article = "a length" if wanted == "length" else "an angle"
    got = "an angle" if wanted == "length" else "a length"
    ctx.error(
        codes.WRONG_DIMENSION,
        f"expected {article} for the {joint.type} joint of `{name}`, got {got} {shown(opening)}",
        opening.span,
        f"a {_JOINT_WORD[joint.type]} opens by {article}: use {unit_list(wanted)}{also}",
    )
    return False


def _check_start_opening(placed: ir.SceneBody, opening: ir.Quantity, body: ir.Body, ctx: CheckContext) -> None:
    """`B : T at POSE open Q`: T has a joint (E441), Q is of its kind (E201) and within its limits (E442)."""
    name, joint = placed.name, body.joint
    if joint is None:
        ctx.error(
            codes.NO_JOINT_TO_OPEN,
            f"`{name}` has no physical joint to start open: its type `{body.name}` declares no `joint`",
            opening.span,
            f"leave out `open {opening.value if not opening.unit else shown(opening).strip('`')}`: a body "
            "without a joint starts where it is placed",
        )
        return
    if not _of_the_joints_kind(name, opening, joint, ctx):
        return
    if opening_problem(opening, joint) != "limits":
        return
    lower, upper = joint.lower.value, joint.upper.value
    if not (math.isfinite(lower) and math.isfinite(upper) and lower <= upper):
        return  # the limits themselves were reported

    def said(value: float) -> str:  # in the opening's unit
        return shown(ir.Quantity(value=value, unit=opening.unit)).strip("`")

    stop = upper if opening.value > upper else lower
    ctx.error(
        codes.START_PAST_JOINT_LIMIT,
        f"`{name}` cannot start open {shown(opening)}: its {_JOINT_WORD[joint.type]} stops at {said(stop)} "
        f"(its limits are {said(lower).split()[0]} to {said(upper)})",
        opening.span,
        "the joint starts within its limits: give an opening between them, or widen them if the real joint goes "
        "further",
    )


def _check_implicit_start(placed: ir.SceneBody, joint: ir.Joint, ctx: CheckContext) -> None:
    """E442 for a body placed without `open Q` (it starts at 0, where it is placed) whose limits exclude 0."""
    lower, upper = joint.lower.value, joint.upper.value
    if not (math.isfinite(lower) and math.isfinite(upper) and lower <= upper):
        return  # the limits themselves were reported
    if lower - 1e-12 <= 0.0 <= upper + 1e-12:
        return
    unit = joint.lower.unit or joint.upper.unit

    def said(value: float) -> str:  # in the limits' unit
        return shown(ir.Quantity(value=value, unit=unit)).strip("`")

    inside = said(lower if lower > 0 else upper)
    ctx.error(
        codes.START_PAST_JOINT_LIMIT,
        f"`{placed.name}` starts at 0 (where it is placed, no `open` given), outside its "
        f"{_JOINT_WORD[joint.type]}'s limits {said(lower).split()[0]} to {said(upper)}",
        placed.span or placed.placement.span,
        f"start it within them (`{placed.name} : {placed.type.name} ... open {inside}`), or give limits that "
        "include 0 (limits are measured from where the body is placed)",
    )


def _check_within_limits(goal: ir.Goal, opening: ir.Quantity, joint: ir.Joint, ctx: CheckContext) -> None:
    """W604 when the opening, give or take its tolerance, lies outside the joint's limits."""
    tolerance = goal.opening_tolerance()
    lower, upper = joint.lower.value, joint.upper.value
    if opening.value - tolerance > upper:
        stop = upper
    elif opening.value + tolerance < lower:
        stop = lower
    else:
        return  # within the limits (or limits already reported as reversed or NaN)

    def said(value: float) -> str:  # in the goal's unit, so that the numbers compare at a glance
        return shown(ir.Quantity(value=value, unit=opening.unit)).strip("`")

    word = _JOINT_WORD[joint.type]
    ctx.warn(
        codes.JOINT_GOAL_PAST_LIMIT,
        f"`{goal.body.name}` cannot open {shown(opening)}: its {word} stops at {said(stop)} "
        f"(its limits are {said(lower).split()[0]} to {said(upper)})",
        opening.span,
        f"no plan can reach it, even within the goal's tolerance of {said(tolerance)}: open it within the "
        "limits, or widen them if the real joint goes further",
    )
