"""How a grip that gives way is told (`vkgl.plan.geometry.grip_load`): which load, which limit, by how much, and
what the task's author can change.

A researcher who hands the arm a 3 kg bar reads "the bar would slip in the hand: its own weight twists the grip
by 4.4 N m about the fingers' axis, where the pads hold 0.47 N m", and then what would let it through: a lighter
tool, a hold nearer its centre of mass, a tool with more friction, a grasp that presses harder, or a lighter or
more slippery body to push. Only the changes that bear on the load that decides are offered: a force in the pads'
plane is the same wherever the tool is held, a twist is not.
"""

from __future__ import annotations

from dataclasses import dataclass

from vkgl.robot.grip import GRIP_FORCE, PAD_FRICTION, Grip


@dataclass(frozen=True)
class Strain:
    """One load on the grip (`Grip.usage`'s parts): the pushed body's resistance (counted some times) with the
    tool's weight, or the tool's weight alone; and which of the two weighs more in it."""

    usage: float  # of what the grip carries (1: all of it)
    in_plane: float  # N in the pads' plane
    twist: float  # N m about the pads' normal (the fingers' axis)
    pushed: bool  # whether the push is in it (else the tool's weight alone)
    by_weight: bool  # whether the tool's weight alone asks more of the grip than the push alone
    lever: float  # m from the fingers to where the larger part acts (the tool's weight, or its contact)


@dataclass(frozen=True)
class Slip:
    """What a grip that would give way needs told: the tool, its hold, the push, and the load that decides."""

    tool: str  # the scene body held
    tool_type: str
    tool_mass: float  # kg
    tool_friction: float  # as declared, or the default
    friction_stated: bool  # whether the tool's type declares its friction
    grasp: str  # the affordance that holds it
    stated_force: bool  # whether the grasp states its `force` (else the hand's continuous force)
    grip: Grip
    effector: str  # the tool's frame that pushes (`stick.tip`)
    body: str  # the body it pushes
    body_mass: float  # kg
    body_friction: float
    resists: float  # N the body resists with (its weight times its friction, or its joint's resistance)
    factor: float  # times the push is counted
    strain: Strain  # the load that decides: the larger of the push's and the weight's alone
    weight_usage: float  # of the grip the tool's weight alone takes, held as it is at this push's start
    allowed: float  # the fraction of the grip a plan may use
    joint: str = ""  # how its joint resists (`grip_load._joint_words`), "" for a body on the table


def slip_why(slip: Slip, note: str = "") -> str:
    """The rejection's sentence: which load, against which limit, by how much; `note` follows the limit."""
    s = slip.strain
    g = slip.grip
    twisted = s.twist / g.max_torque >= s.in_plane / g.max_force
    if twisted:
        load = (
            f"twists the grip by {s.twist:.2f} N m about the fingers' axis, where the pads hold {g.max_torque:.2f} N m"
        )
    else:
        load = f"loads the grip with {s.in_plane:.1f} N in the pads' plane, where they hold {g.max_force:.1f} N"
    how = slip.joint or "its weight times its friction"
    push = (
        f"{slip.effector} pushing {slip.body} ({slip.resists:.1f} N: {how}, the push "
        f"counted {_times(slip.factor)} for what the estimate leaves out"
    )
    if not s.pushed:
        cause = f"its own weight ({slip.tool_mass:.2f} kg, {s.lever * 100:.1f} cm from the fingers)"
    elif s.by_weight:
        cause = f"its own weight ({slip.tool_mass:.2f} kg, {s.lever * 100:.1f} cm from the fingers), with {push}),"
    else:
        cause = f"{push}; {s.lever * 100:.1f} cm from the fingers), with its own weight ({slip.tool_mass:.2f} kg),"
    alone = ""
    if s.pushed and slip.weight_usage > slip.allowed:  # no lighter push would do: a deeper search will not help
        alone = f"; its weight alone takes {slip.weight_usage:.0%}: held this way, no push with it can pass"
    return (
        f"{slip.tool} would slip in the hand: {cause} {load} "
        f"({slip.tool_type} held by `{slip.grasp}`: {g.text()}): {s.usage:.0%} of the grip, "
        f"{s.usage / slip.allowed:.1f} times the {slip.allowed:.0%} a plan may use{f' {note}' if note else ''}{alone}"
    )


def slip_advice(slip: Slip) -> str:
    """What the task's author can change for the grip to hold, the changes that bear on the deciding load first."""
    s = slip.strain
    g = slip.grip
    twisted = s.twist / g.max_torque >= s.in_plane / g.max_force
    changes = []
    if s.by_weight:
        changes.append(f"a lighter {slip.tool_type} (`mass` {slip.tool_mass:g} kg)")
        if twisted:
            changes.append(f"a hold nearer its centre of mass (`{slip.grasp}` holds it {s.lever * 100:.1f} cm away)")
    else:
        changes.append(_lighter_body(slip))
        if twisted:
            changes.append(f"a hold nearer {slip.effector} ({s.lever * 100:.1f} cm from the fingers now)")
    if slip.tool_friction < PAD_FRICTION:
        now = f"`friction` {slip.tool_friction:g}" + ("" if slip.friction_stated else ", the default")
        changes.append(f"a {slip.tool_type} with more friction ({now}; the pads' is {PAD_FRICTION:g})")
    if slip.stated_force and g.force < GRIP_FORCE:
        changes.append(
            f"a grasp that presses harder (`force` {g.force:g} N; the Panda's hand holds up to {GRIP_FORCE:g} N)"
        )
    if len(changes) > 1:
        changes[-1] = f"or {changes[-1]}"
    return f"for the grip to hold {slip.tool}: " + ", ".join(changes)


def _lighter_body(slip: Slip) -> str:
    """The change to the pushed body that lightens the push: its mass and friction, or its joint's."""
    if not slip.joint:
        return (
            f"a lighter or more slippery {slip.body} (`mass` {slip.body_mass:g} kg, `friction` {slip.body_friction:g})"
        )
    return f"a {slip.body} whose joint resists less ({slip.joint}: its `damping` and `friction`)"


def _times(factor: float) -> str:
    return {1.0: "once", 2.0: "twice"}.get(factor, f"{factor:g} times")


__all__ = ["Slip", "Strain", "slip_advice", "slip_why"]
