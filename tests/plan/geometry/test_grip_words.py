"""A grip that gives way is told by the load that decides, its limit, by how much, and what to change
(`vkgl.plan.geometry.grip_words`)."""

from __future__ import annotations

from dataclasses import replace

from vkgl.plan.geometry.grip_words import Slip, Strain, slip_advice, slip_why
from vkgl.robot.grip import Grip

_HEAVY_BAR = Slip(
    tool="bar",
    tool_type="SteelBar",
    tool_mass=3.0,
    tool_friction=0.5,
    friction_stated=False,
    grasp="wield",
    stated_force=False,
    grip=Grip(force=70.0, friction=0.5),
    effector="bar.tip",
    body="block",
    body_mass=0.5,
    body_friction=0.5,
    resists=2.45,
    factor=2.0,
    strain=Strain(usage=9.47, in_plane=30.0, twist=4.41, pushed=True, by_weight=True, lever=0.15),
    weight_usage=9.45,
    allowed=0.54,
)


def test_a_tool_too_heavy_for_its_grip_is_told_by_its_weight_and_the_twist() -> None:
    why = slip_why(_HEAVY_BAR)
    assert why.startswith("bar would slip in the hand: its own weight (3.00 kg, 15.0 cm from the fingers)")
    assert "twists the grip by 4.41 N m about the fingers' axis, where the pads hold 0.47 N m" in why
    assert why.endswith(
        "947% of the grip, 17.5 times the 54% a plan may use; its weight alone takes 945%: held this way, no push "
        "with it can pass"
    )
    advice = slip_advice(_HEAVY_BAR)
    assert advice == (
        "for the grip to hold bar: a lighter SteelBar (`mass` 3 kg), a hold nearer its centre of mass (`wield` "
        "holds it 15.0 cm away), or a SteelBar with more friction (`friction` 0.5, the default; the pads' is 1)"
    )


def test_a_body_too_heavy_to_push_is_told_by_the_push_and_the_force_in_the_pads_plane() -> None:
    """A force in the pads' plane is the same wherever the tool is held: no "hold it nearer" then."""
    slip = replace(
        _HEAVY_BAR,
        tool_mass=0.1,
        body_mass=12.0,
        resists=60.0,
        weight_usage=0.2,
        strain=Strain(usage=1.74, in_plane=120.0, twist=0.1, pushed=True, by_weight=False, lever=0.35),
    )
    why = slip_why(slip)
    assert why.startswith("bar would slip in the hand: bar.tip pushing block (60.0 N: its weight times its friction")
    assert "the push counted twice" in why and "loads the grip with 120.0 N in the pads' plane" in why
    advice = slip_advice(slip)
    assert "a lighter or more slippery block (`mass` 12 kg, `friction` 0.5)" in advice
    assert "nearer" not in advice


def test_a_weak_stated_grasp_is_told_to_press_harder_up_to_the_hand_s_force() -> None:
    slip = replace(_HEAVY_BAR, stated_force=True, grip=Grip(force=20.0, friction=1.0), tool_friction=1.0)
    advice = slip_advice(slip)
    assert advice.endswith("or a grasp that presses harder (`force` 20 N; the Panda's hand holds up to 70 N)")
    assert "more friction" not in advice  # the tool's friction is the pads' already


def test_a_push_the_tool_s_weight_alone_allows_says_nothing_of_the_weight() -> None:
    assert "weight alone" not in slip_why(replace(_HEAVY_BAR, weight_usage=0.5))
