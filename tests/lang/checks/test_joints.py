"""Joint damping and friction, and joint goals (`goal B open Q`): parsing, units, printing and checks."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from vkgl.lang.compiler import check_files
from vkgl.lang.syntax.parser import parse_collecting, parse_module
from vkgl.lang.syntax.printer import print_module

GOLDEN_LIB = Path(__file__).resolve().parents[1] / "golden" / "lib"


def codes_of(text: str) -> list[str]:
    """The diagnostic codes of parsing `text` alone (no names resolved)."""
    _, _, diagnostics = parse_collecting(text, "joints.vkg")
    return [d.code for d in diagnostics]


def body(joint: str, extra: str = "") -> str:
    return f"body Slide {{\n    shape box (30, 40, 10) cm\n    mass 2 kg\n    joint {joint}\n{extra}}}\n"


PRISMATIC = "prismatic axis (1, 0, 0) limits (0, 30) cm"
REVOLUTE = "revolute axis (0, 0, 1) through (0, -20, 0) cm limits (0, 90) deg"


# ---------------------------------------------------------------- damping and friction


def test_damping_and_friction_are_read_in_si_with_the_unit_kept() -> None:
    slide = parse_module(body(PRISMATIC + " damping 5 N*s/m friction 2 N"), "a.vkg").decls[0]
    assert slide.joint.damping.value == 5.0 and slide.joint.damping.unit == "N*s/m"
    assert slide.joint.friction.value == 2.0 and slide.joint.friction.unit == "N"
    hinge = parse_module(body(REVOLUTE + " friction 0.25 N*m damping 1.5 N*m*s/rad"), "a.vkg").decls[0]
    assert (hinge.joint.damping.value, hinge.joint.damping.unit) == (1.5, "N*m*s/rad")
    assert (hinge.joint.friction.value, hinge.joint.friction.unit) == (0.25, "N*m")


def test_a_joint_without_them_has_neither() -> None:
    slide = parse_module(body(PRISMATIC), "a.vkg").decls[0]
    assert slide.joint.damping is None and slide.joint.friction is None


def test_a_unitless_friction_after_the_joint_is_still_the_bodys_coefficient() -> None:
    """Before joints had friction, `joint ... friction 0.4` meant the body's friction: it still does."""
    slide = parse_module(body(PRISMATIC, "    friction 0.4\n"), "a.vkg").decls[0]
    assert slide.friction == 0.4 and slide.joint.friction is None
    both = parse_module(body(PRISMATIC + " friction 2 N friction 0.4"), "a.vkg").decls[0]
    assert both.friction == 0.4 and both.joint.friction.value == 2.0
    assert codes_of(body(PRISMATIC, "    friction 0.4\n    friction 0.5\n")) == ["E406"]


@pytest.mark.parametrize(
    ("joint", "code", "words"),
    [
        (REVOLUTE + " damping 2 N*s/m", "E201", "`N*s/m` is for a prismatic joint's damping"),
        (PRISMATIC + " damping 2 N*m*s/rad", "E201", "a prismatic joint's is in `N*s/m`"),
        (PRISMATIC + " friction 2 N*m", "E201", "`N*m` is for a revolute joint's friction"),
        (REVOLUTE + " friction 2 N", "E201", "a revolute joint's is in `N*m`"),
        (PRISMATIC + " damping 2 kg", "E201", "use `N*s/m`"),
        (PRISMATIC + " damping 5", "E202", "add a unit: `N*s/m`"),
        (PRISMATIC + " damping 5 N*s/m damping 6 N*s/m", "E406", "first given at"),
        (PRISMATIC + " damping 5 N*m*s", "E105", "unknown unit `N*m*s`"),
        (PRISMATIC + " damping 5 Ns/m", "E105", "unknown unit `Ns/m`"),
        (PRISMATIC + " damping 5 N * s / m", "E105", "write compound units without spaces: `N*s/m`"),
    ],
)
def test_wrong_units_on_a_joints_dynamics_say_what_to_write(joint: str, code: str, words: str) -> None:
    _, _, diagnostics = parse_collecting(body(joint), "a.vkg")
    assert [d.code for d in diagnostics] == [code]
    assert words in diagnostics[0].message + " ".join(diagnostics[0].notes)


def test_a_compound_unit_error_points_at_the_whole_unit() -> None:
    text = body(PRISMATIC + " damping 5 N*m*s")
    _, _, diagnostics = parse_collecting(text, "a.vkg")
    span = diagnostics[0].span
    line = text.split("\n")[span.line - 1]
    assert line[span.col - 1 : span.end_col - 1] == "N*m*s"


def check_text(tmp_path: Path, text: str, name: str = "t.vkg") -> list:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return check_files([str(path)])[0]


@pytest.mark.parametrize(
    ("dynamics", "codes"),
    [
        ("damping 0 N*s/m friction 0 N", []),
        ("damping -5 N*s/m", ["E440"]),
        ("friction -1 N", ["E440"]),
        ("damping 20000 N*s/m", ["E209"]),
        ("friction 1001 N", ["E209"]),
    ],
)
def test_damping_and_friction_are_zero_or_positive_and_plausible(tmp_path: Path, dynamics: str, codes: list) -> None:
    diagnostics = check_text(tmp_path, body(f"{PRISMATIC} {dynamics}"))
    assert [d.code for d in diagnostics] == codes


def test_printing_keeps_damping_friction_and_joint_goals() -> None:
    text = (
        body(PRISMATIC + " damping 5 N*s/m friction 2 N", "    friction 0.4\n")
        + "\ntask t {\n    scene s\n    goal d open 20 cm within 1 cm\n        and e open 45deg\n}\n"
    )
    module = parse_module(text, "a.vkg")
    printed = print_module(module)
    assert "    friction 0.4\n    joint prismatic axis (1, 0, 0) limits (0, 30) cm damping 5 N*s/m friction 2 N\n" in (
        printed
    )
    assert "goal d open 20 cm within 1 cm\n        and e open 45deg\n" in printed
    assert parse_module(printed, "a.vkg") == module


# ---------------------------------------------------------------- joint goals


def test_a_joint_goal_is_read_in_si_with_its_default_tolerance() -> None:
    task = parse_module("task t { scene s goal d open 20 cm and e open 45deg within 2deg }", "a.vkg").decls[0]
    drawer, door = task.goals
    assert drawer.opening.value == pytest.approx(0.2) and drawer.opening.unit == "cm"
    assert drawer.position is None and drawer.yaw is None
    assert drawer.opening_tolerance() == pytest.approx(0.01)  # 1 cm, as pose goals
    assert door.opening.value == pytest.approx(math.radians(45))
    assert door.opening_tolerance() == pytest.approx(math.radians(2))
    free = parse_module("task t { scene s goal e open 1 rad }", "a.vkg").decls[0].goals[0]
    assert free.opening_tolerance() == pytest.approx(math.radians(3))


@pytest.mark.parametrize(
    ("goal", "code"),
    [
        ("d open 20", "E202"),
        ("d open 2 kg", "E201"),
        ("d open 20 cm within 2 deg", "E201"),
        ("d open 20 cm within 1 cm, 2 cm", "E204"),
    ],
)
def test_a_joint_goal_is_a_length_or_an_angle_with_one_tolerance_of_its_kind(goal: str, code: str) -> None:
    assert codes_of(f"task t {{ scene s goal {goal} }}") == [code]


KITCHEN = f'use "{GOLDEN_LIB / "kitchen.vkg"}"\n\n'


@pytest.mark.parametrize(
    ("goal", "codes"),
    [
        ("drawer open 20 cm within 1 cm", []),
        ("drawer open 30.5 cm within 1 cm", []),  # within its tolerance of the limit: reachable
        ("drawer open 0 cm", []),
        ("door open 45deg within 3deg", []),
        ("door open 1 rad", []),
        ("drawer open 35 cm within 1 cm", ["W604"]),
        ("drawer open -2 cm", ["W604"]),
        ("door open 100deg", ["W604"]),
        ("door open 20 cm", ["E201"]),
        ("drawer open 20deg within 1deg", ["E201"]),
        ("block open 5 cm", ["E441"]),
        ("drawer open 5 cm within 0 cm", ["E411"]),
        ("drawer open 5 cm and drawer at (0.5, 0) m", []),  # both must hold: the planner's question
    ],
)
def test_joint_goals_are_checked_against_the_bodys_joint(tmp_path: Path, goal: str, codes: list) -> None:
    diagnostics = check_text(tmp_path, KITCHEN + f"task t {{ scene kitchen goal {goal} }}\n")
    assert [d.code for d in diagnostics] == codes


def test_the_limit_warning_says_the_numbers_in_the_goals_unit(tmp_path: Path) -> None:
    (diagnostic,) = check_text(tmp_path, KITCHEN + "task t { scene kitchen goal drawer open 350 mm within 1 cm }\n")
    assert diagnostic.severity == "warning"
    assert diagnostic.message == (
        "`drawer` cannot open `350 mm`: its slide stops at 300 mm (its limits are 0 to 300 mm)"
    )
    assert "tolerance of 10 mm" in diagnostic.notes[0]
    (door,) = check_text(tmp_path, KITCHEN + "task t { scene kitchen goal door open 100deg }\n")
    assert "its hinge stops at 90 deg (its limits are 0 to 90 deg)" in door.message


def test_open_stays_a_legal_name_outside_goals(tmp_path: Path) -> None:
    """`open` and `damping` are keywords only where the grammar expects them."""
    text = KITCHEN + (
        "body damping {\n    shape box (10, 10, 10) cm\n    mass 1 kg\n}\n"
        "scene open {\n    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
        "    open : KitchenDrawer on table at (0.45, 0) m\n}\n"
        "task t { scene open goal open open 5 cm }\n"
    )
    assert check_text(tmp_path, text) == []


# ---------------------------------------------------------------- a joint's start: `B : T open Q at POSE`


def test_a_scene_body_starts_open_in_si_and_prints_back() -> None:
    text = (
        "scene s {\n    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
        "    drawer : KitchenDrawer open 12 cm on table at (0.45, 0) m\n"
        "    door : KitchenDoor open 60deg at (0.7, 0.35, 0.25) m yaw 180deg\n"
        "    block : Block on table at (0.45, -0.4) m yaw 0deg\n}\n"
    )
    module = parse_module(text, "a.vkg")
    drawer, door, block = module.decls[0].bodies
    assert (drawer.opening.value, drawer.opening.unit) == (pytest.approx(0.12), "cm") and drawer.placement.on_table
    assert door.start_opening() == pytest.approx(math.radians(60)) and not door.placement.on_table
    assert block.opening is None and block.start_opening() == 0.0
    printed = print_module(module)
    assert "    drawer : KitchenDrawer open 12 cm on table at (0.45, 0) m\n" in printed
    assert "    door : KitchenDoor open 60deg at (0.7, 0.35, 0.25) m yaw 180deg\n" in printed
    assert parse_module(printed, "a.vkg") == module


OPEN_KITCHEN = (
    KITCHEN + "scene opened {{\n    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
    "    {body}\n}}\n"
)


@pytest.mark.parametrize(
    ("placed", "codes"),
    [
        ("drawer : KitchenDrawer open 12 cm on table at (0.45, 0) m", []),
        ("drawer : KitchenDrawer open 0.3 m on table at (0.45, 0) m", []),  # at its upper limit
        ("door : KitchenDoor open 1 rad on table at (0.7, 0.35) m", []),
        ("drawer : KitchenDrawer open 31 cm on table at (0.45, 0) m", ["E442"]),
        ("door : KitchenDoor open -5deg on table at (0.7, 0.35) m", ["E442"]),
        ("door : KitchenDoor open 5 cm on table at (0.7, 0.35) m", ["E201"]),
        ("drawer : KitchenDrawer open 5 on table at (0.45, 0) m", ["E202"]),
        ("block : Block open 5 cm on table at (0.45, -0.4) m", ["E441"]),
    ],
)
def test_a_start_opening_is_checked_against_the_bodys_joint(tmp_path: Path, placed: str, codes: list) -> None:
    diagnostics = check_text(tmp_path, OPEN_KITCHEN.format(body=placed))
    assert [d.code for d in diagnostics] == codes


def test_the_scene_checks_see_the_body_where_it_starts_open(tmp_path: Path) -> None:
    """A block 25 cm in front of the closed drawer is clear of it; with the drawer started 30 cm open, it is not."""
    block = "block : Block on table at (0.75, 0) m yaw 0deg"
    shut = OPEN_KITCHEN.format(body=f"drawer : KitchenDrawer on table at (0.45, 0) m\n    {block}")
    assert check_text(tmp_path, shut) == []
    opened = OPEN_KITCHEN.format(body=f"drawer : KitchenDrawer open 30 cm on table at (0.45, 0) m\n    {block}")
    (overlap,) = check_text(tmp_path, opened)
    # the 5 cm tall block's shortest way out is up, 4.9 cm: the drawer hangs 1 mm above the table on its joint
    assert overlap.code == "E420" and "`drawer` and `block` overlap by 4.9 cm" in overlap.message
