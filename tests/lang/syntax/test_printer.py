"""The printer: canonical source from the IR, exact numbers, and parse(print(ir)) == ir."""

from __future__ import annotations

import math

import pytest
from conftest import vkg_files
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from module_strategies import modules
from strategies import PATH, UNITS

from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import to_si
from vkgl.lang.syntax.printer import print_module
from vkgl.lang.syntax.quantities import format_number, format_scaled

# Deterministic (derandomize) and quick; the round trip runs a few hundred modules in seconds.
FAST = settings(derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow])
ALL_UNITS = [u for group in UNITS.values() for u in group]


def parse(text: str, path: str = PATH) -> ir.Module:
    from vkgl.lang.syntax.parser import parse_module

    return parse_module(text, path)


# ---------------------------------------------------------------- numbers


@pytest.mark.parametrize(
    ("value", "unit", "text"),
    [
        (0.1, "cm", "10"),
        (0.103, "cm", "10.3"),
        (-0.3, "mm", "-300"),
        (0.5, "kg", "0.5"),
        (0.001, "g", "1"),
        (math.pi, "deg", "180"),
        (-math.pi / 6, "deg", "-30"),
        (0.0, "cm", "0"),
        (-0.0, "deg", "0"),
        (2.0, "ms", "2000"),
        (1e-9, "m", "1e-9"),
        (1.5e20, "N", "1.5e20"),
    ],
)
def test_values_print_in_their_display_unit_with_the_shortest_text(value: float, unit: str, text: str) -> None:
    assert format_scaled(value, unit) == text


def test_integers_have_no_trailing_point_zero() -> None:
    assert [format_number(x) for x in (3.0, -12.0, 100.0, 0.5)] == ["3", "-12", "100", "0.5"]


def test_non_finite_numbers_are_refused() -> None:
    with pytest.raises(ValueError, match="non-finite"):
        format_number(math.inf)


@FAST
@given(st.floats(allow_nan=False, allow_infinity=False), st.sampled_from(ALL_UNITS))
def test_every_float_has_an_exact_text_in_every_unit(value: float, unit: str) -> None:
    text = format_scaled(value, unit)
    assert text is not None
    assert to_si(text, unit) == value


@FAST
@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False), st.sampled_from(["cm", "mm", "deg", "g"]))
def test_no_shorter_decimal_converts_to_the_same_value(value: float, unit: str) -> None:
    text = format_scaled(value, unit)
    assert text is not None
    digits = len(text.lstrip("-").split("e")[0].replace(".", "").strip("0"))
    in_unit = value / float(to_si("1", unit))
    for k in range(1, digits - 1):
        shorter = f"{in_unit:.{k}g}"
        assert to_si(shorter, unit) != value, (text, shorter)


# ---------------------------------------------------------------- canonical layout


BLOCK = ir.Module(
    path="block.vkg",
    doc="Block: a wooden block.\n\nExplored by pushing.",
    uses=[ir.Use(target="stdlib.robots.panda", by_path=False), ir.Use(target="../x.vkg", by_path=True)],
    decls=[
        ir.Body(
            name="Block",
            shape=ir.BoxShape(size=ir.Vector(values=(0.1, 0.2, 0.05), unit="cm")),
            mass=ir.Quantity(value=0.5, unit="kg"),
            friction=0.5,
            frames=[ir.Frame(name="com", pose=ir.Pose(position=ir.Vector(values=(0.0, 0.0, 0.0), unit="cm")))],
            explores=[
                ir.Explore(
                    name="pushes",
                    contacts=ir.ContactSpec(faces=["+x", "-x"], steps=9),
                    force=ir.ForceSpec(mode="normal", magnitude=ir.Quantity(value=1.0, unit="N")),
                    duration=ir.Quantity(value=2.0, unit="s"),
                )
            ],
        ),
        ir.Task(
            name="a_push",
            scene=ir.Ref(name="tabletop"),
            goals=[
                ir.Goal(
                    body=ir.Ref(name="block"),
                    position=ir.Vector(values=(0.6, 0.0), unit="m"),
                    yaw=ir.Quantity(value=0.0, unit="deg"),
                    tol_position=ir.Quantity(value=0.01, unit="cm"),
                    tol_yaw=ir.Quantity(value=to_si("3", "deg"), unit="deg"),
                ),
                ir.Goal(body=ir.Ref(name="stick"), yaw=ir.Quantity(value=-math.pi / 2, unit="deg")),
            ],
            search=ir.SearchSpec(max_depth=6, timeout=ir.Quantity(value=30.0, unit="s")),
        ),
    ],
)

BLOCK_TEXT = """\
# Block: a wooden block.
#
# Explored by pushing.

use stdlib.robots.panda
use "../x.vkg"

body Block {
    shape box (10, 20, 5) cm
    mass 0.5 kg
    friction 0.5
    frame com = (0, 0, 0) cm
    explore pushes {
        contacts on faces +x, -x steps 9
        force normal 1 N
        duration 2 s
    }
}

task a_push {
    scene tabletop
    goal block at (0.6, 0) m yaw 0deg within 1 cm, 3deg
        and stick yaw -90deg
    search { max_depth 6  timeout 30 s }
}
"""


def test_canonical_text_of_a_module() -> None:
    assert print_module(BLOCK) == BLOCK_TEXT


def test_union_shapes_nest_with_their_poses_after_the_closing_brace() -> None:
    inner = ir.UnionShape(
        parts=[
            ir.ShapePart(
                shape=ir.CylinderShape(
                    radius=ir.Quantity(value=0.01, unit="m"), height=ir.Quantity(value=0.02, unit="mm")
                ),
                pose=ir.Pose(
                    position=ir.Vector(values=(0.0, 0.0, 0.0), unit="m"),
                    rpy=ir.Vector(values=(0.0, 0.0, math.pi / 2), unit="deg"),
                ),
            )
        ]
    )
    body = ir.Body(
        name="B",
        shape=ir.UnionShape(
            parts=[
                ir.ShapePart(
                    shape=inner,
                    pose=ir.Pose(
                        position=ir.Vector(values=(0.19, 0.05, 0.0), unit="cm"),
                        yaw=ir.Quantity(value=math.pi, unit="rad"),
                    ),
                )
            ]
        ),
        mass=ir.Quantity(value=0.12, unit="g"),
    )
    text = print_module(ir.Module(path="b.vkg", decls=[body]))
    assert (
        text
        == """\
body B {
    shape union {
        union {
            cylinder radius 0.01 m height 20 mm at (0, 0, 0) m rpy (0, 0, 90) deg
        } at (19, 5, 0) cm yaw 3.141592653589793 rad
    }
    mass 120 g
}
"""
    )


# ---------------------------------------------------------------- parse(print(ir)) == ir


@settings(FAST, max_examples=150)
@given(modules())
def test_parse_of_print_is_the_same_ir(module: ir.Module) -> None:
    text = print_module(module)
    assert parse(text) == module, text


@settings(FAST, max_examples=40)
@given(modules())
def test_print_is_a_fixed_point(module: ir.Module) -> None:
    text = print_module(module)
    assert print_module(parse(text)) == text


@pytest.mark.parametrize("path", vkg_files(), ids=lambda p: p.name)
def test_repository_files_survive_print_and_parse(path) -> None:
    module = parse(path.read_text(encoding="utf-8"), str(path))
    assert parse(print_module(module), str(path)) == module


def test_an_open_range_round_trips_and_a_closed_one_stays_closed() -> None:
    source = (
        "use stdlib.bodies.block\n\naffordances Block {\n"
        "    affordance a {\n        action fixed at (-5, 0, 0) cm yaw 0deg\n"
        "        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 5.7 cm open\n    }\n"
        "    affordance b {\n        action fixed at (-5, 0, 0) cm yaw 0deg\n"
        "        motion prismatic along (1, 0, 0) from (0, 0, 0) cm range 0 to 5.7 cm\n    }\n}\n"
    )
    module = parse(source)
    slides = [a.motion for a in module.decls[0].affordances]  # type: ignore[union-attr]
    assert [m.range.open for m in slides] == [True, False]
    assert [m.range.upper.value for m in slides] == pytest.approx([0.057, 0.057])
    assert print_module(module) == source
