"""Scene geometry at `vkgc check` (vkgl/lang/checks/geometry/scene.py): impossible starts and goals are errors.

Each finding of the issue is reproduced with its own input: a goal inside the
robot's base, a block floating at z = 0.5 m, two overlapping blocks, a block on
the stick, a body at y = -1e308 on the table, a block at x = 2.0 m on a 1.6 m
table, a hook overhanging the table's edge. Touching is allowed; so is resting
on another body.
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import pytest
import trimesh
from conftest import vkg_files

from vkgl.lang.checks import checker as checks
from vkgl.lang.compiler import check_files
from vkgl.lang.diagnostics.diagnostic import Diagnostic

HEADER = """\
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.bodies.stick
use stdlib.bodies.hook
use stdlib.bodies.drawer
use stdlib.affordances.block
use stdlib.affordances.stick
use stdlib.affordances.hook
use stdlib.tools
"""
TABLE = "    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"


def _check(tmp_path: Path, text: str) -> list[Diagnostic]:
    path = tmp_path / "case.vkg"
    path.write_text(text, encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow or NaN warning from numpy either
        diagnostics, _ = check_files([str(path)])
    return diagnostics


def _scene(tmp_path: Path, *bodies: str, task: str = "", header: str = HEADER) -> list[Diagnostic]:
    rows = "".join(f"    {b}\n" for b in bodies)
    return _check(tmp_path, f"{header}\nscene s {{\n{TABLE}{rows}}}\n{task}")


def _goal(tmp_path: Path, goal: str, *bodies: str, header: str = HEADER) -> list[Diagnostic]:
    task = f"task t {{\n    scene s\n    goal {goal}\n}}\n"
    return _scene(tmp_path, "block : Block on table at (0.45, 0) m", *bodies, task=task, header=header)


def _only(diagnostics: list[Diagnostic], code: str) -> list[str]:
    assert {d.code for d in diagnostics} == {code}, [d.headline() for d in diagnostics]
    return [d.message for d in diagnostics]


# ---------------------------------------------------------------- the findings


def test_a_goal_inside_the_robots_base_is_an_error(tmp_path: Path) -> None:
    (message,) = _only(_goal(tmp_path, "block at (0, 0) m yaw 0deg within 1 cm, 3 deg"), "E424")
    assert message.startswith("the goal puts `block` 5.0 cm deep into the base of robot `arm`")


def test_a_block_floating_at_half_a_metre_is_an_error(tmp_path: Path) -> None:
    (message,) = _only(_scene(tmp_path, "block : Block at (0.45, 0, 0.5) m"), "E422")
    assert message.startswith("`block` floats 47.5 cm above the table top")


def test_two_overlapping_blocks_are_an_error(tmp_path: Path) -> None:
    found = _scene(tmp_path, "block : Block on table at (0.45, 0) m", "block2 : Block on table at (0.52, 0.1) m")
    (message,) = _only(found, "E420")
    assert message == "`block` and `block2` overlap by 3.0 cm at the start: move one of them"


def test_a_block_on_the_stick_is_an_error(tmp_path: Path) -> None:
    found = _scene(tmp_path, "stick : Stick on table at (0.3, -0.4) m", "block : Block on table at (0.3, -0.4) m")
    (message,) = _only(found, "E420")
    assert message.startswith("`stick` and `block` overlap by 2.0 cm")


def test_a_body_at_minus_1e308_is_off_the_table_without_overflow(tmp_path: Path) -> None:
    (message,) = _only(_scene(tmp_path, "block : Block on table at (0.45, -1e308) m"), "E421")
    assert message.startswith("`block` is far off the table: it is at (x, y) = (0.45, -1e+308) m")


def test_a_goal_at_minus_1e308_is_off_the_table_without_overflow(tmp_path: Path) -> None:
    (message,) = _only(_goal(tmp_path, "block at (0.45, -1e308) m"), "E423")
    assert message.startswith("the goal puts `block` off the table")


def test_a_block_at_two_metres_on_a_1_6_m_table_is_off_the_table(tmp_path: Path) -> None:
    (message,) = _only(_scene(tmp_path, "block : Block on table at (2.0, 0) m"), "E421")
    assert message.startswith("`block` is off the table: it spans x from 1.95 to 2.05 m")


def test_a_hook_overhanging_the_edge_is_an_error(tmp_path: Path) -> None:
    (message,) = _only(_scene(tmp_path, "hook : Hook on table at (1.14, 0.4) m"), "E421")
    assert message.startswith("`hook` overhangs the table's edge by 4.0 cm: it spans x from 0.94 to 1.34 m")


def test_a_goal_in_a_body_nothing_can_move_is_an_error(tmp_path: Path) -> None:
    crate = "body Crate {\n    shape box (30, 30, 20) cm\n    mass 5 kg\n}\n"
    found = _goal(tmp_path, "block at (0.7, 0.3) m", "crate : Crate on table at (0.7, 0.35) m", header=HEADER + crate)
    (message,) = _only(found, "E425")
    assert "deep into `crate`, which nothing can move" in message


def test_a_goal_in_a_movable_body_is_left_to_the_planner(tmp_path: Path) -> None:
    assert _goal(tmp_path, "block at (0.45, 0.3) m", "block2 : Block on table at (0.45, 0.3) m") == []


def test_a_goal_overhanging_the_table_is_an_error_only_if_no_allowed_heading_fits(tmp_path: Path) -> None:
    assert _goal(tmp_path, "block at (0.45, 0.53) m") == []  # turned 90 deg it fits
    (message,) = _only(_goal(tmp_path, "block at (0.45, 0.53) m yaw 0deg within 1 cm, 3 deg"), "E423")
    assert message.startswith("the goal makes `block` overhang the table's edge by 3.")


def test_a_goal_at_the_edge_within_its_tolerance_is_fine(tmp_path: Path) -> None:
    assert _goal(tmp_path, "block at (1.255, 0) m yaw 0deg within 1 cm, 3 deg") == []


# ---------------------------------------------------------------- what stays allowed


def test_blocks_side_by_side_in_contact_are_fine(tmp_path: Path) -> None:
    assert _scene(tmp_path, "block : Block on table at (0.45, 0) m", "block2 : Block on table at (0.55, 0) m") == []


def test_a_penetration_within_a_millimetre_is_contact(tmp_path: Path) -> None:
    assert _scene(tmp_path, "block : Block on table at (0.45, 0) m", "block2 : Block on table at (0.5495, 0) m") == []
    found = _scene(tmp_path, "block : Block on table at (0.45, 0) m", "block2 : Block on table at (0.548, 0) m")
    assert _only(found, "E420") == ["`block` and `block2` overlap by 0.2 cm at the start: move one of them"]


def test_a_block_resting_on_another_is_fine(tmp_path: Path) -> None:
    found = _scene(tmp_path, "block : Block on table at (0.45, 0) m", "top : Block at (0.47, 0.05, 0.075) m yaw 30deg")
    assert found == []


def test_a_block_resting_on_the_table_at_a_full_pose_is_fine(tmp_path: Path) -> None:
    assert _scene(tmp_path, "block : Block at (0.45, 0, 0.0255) m rpy (0, 0, 45) deg") == []


def test_a_body_sunk_into_the_table_is_an_error(tmp_path: Path) -> None:
    (message,) = _only(_scene(tmp_path, "block : Block at (0.45, 0, 0.01) m"), "E422")
    assert message.startswith("`block` sinks 1.5 cm into the table")


def test_a_body_with_a_physical_joint_may_hang_anywhere(tmp_path: Path) -> None:
    assert _scene(tmp_path, "drawer : Drawer at (1.4, 0, 0.3) m") == []


def test_cylinders_are_round(tmp_path: Path) -> None:
    can = "body Can {\n    shape cylinder radius 5 cm height 12 cm\n    mass 0.3 kg\n}\n"
    at = ("a : Can on table at (0.5, 0) m", "b : Can on table at (0.5707, 0.0707) m")  # centres 10 cm apart
    assert _scene(tmp_path, *at, header=HEADER + can) == []
    found = _scene(tmp_path, at[0], "b : Can on table at (0.5636, 0.0636) m", header=HEADER + can)
    (message,) = _only(found, "E420")
    assert message.startswith("`a` and `b` overlap by 1.0 cm")


def test_meshes_count_by_their_convex_hull(tmp_path: Path) -> None:
    trimesh.creation.box(extents=(0.1, 0.1, 0.1)).export(tmp_path / "cube.stl")
    cube = 'body Cube {\n    shape mesh "cube.stl"\n    mass 1 kg\n}\n'
    at = ("a : Cube on table at (0.5, 0) m", "b : Cube on table at (0.58, 0) m")
    found = _scene(tmp_path, *at, header=HEADER + cube)
    assert _only(found, "E420") == ["`a` and `b` overlap by 2.0 cm at the start: move one of them"]


def test_unions_are_checked_by_their_parts(tmp_path: Path) -> None:
    """The block sits in the hook's bend, clear of both of its bars: no overlap though their boxes overlap."""
    found = _scene(tmp_path, "hook : Hook on table at (0.5, 0.3) m", "block : Block on table at (0.62, 0.412) m")
    assert found == []


# ---------------------------------------------------------------- the examples and speed


def test_every_example_and_stdlib_file_checks_clean() -> None:
    diagnostics, _ = check_files([str(p) for p in vkg_files()])
    assert [d.headline() for d in diagnostics] == []


def _crowded(n: int) -> str:
    """A scene of `n` blocks in rows of ten, 10 cm apart, on a 3 x 3 m table."""
    rows = [f"b{i} : Block on table at ({0.2 + i % 10 * 0.2:.2f}, {-1.2 + i // 10 * 0.25:.2f}) m" for i in range(n)]
    table = "    table size (3, 3) m at (1, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
    return f"{HEADER}\nscene crowded {{\n{table}" + "".join(f"    {r}\n" for r in rows) + "}\n"


def test_a_hundred_body_scene_costs_well_under_a_second(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "crowded.vkg"
    path.write_text(_crowded(100), encoding="utf-8")
    check_files([str(path)])  # warm up: imports, URDF, stdlib parses

    def timed() -> float:
        start = time.perf_counter()
        diagnostics, _ = check_files([str(path)])
        assert diagnostics == []
        return time.perf_counter() - start

    with_checks = min(timed() for _ in range(3))
    monkeypatch.setattr(checks, "check_scenes", lambda program, ctx: None)
    without = min(timed() for _ in range(3))
    assert with_checks - without < 1.0


def test_the_pandas_base_is_its_first_links_collision_cylinder(tmp_path: Path) -> None:
    """`panda_link0` collides as a cylinder of radius 9 cm around the robot's position."""
    assert _scene(tmp_path, "block : Block on table at (0.14, 0) m") == []
    found = _scene(tmp_path, "block : Block on table at (0.13, 0) m")
    assert _only(found, "E420") == ["`block` overlaps the base of robot `arm` by 1.0 cm at the start: move it"]


def test_a_robot_without_simple_collision_geometry_has_a_base_of_10_cm_radius(tmp_path: Path) -> None:
    (tmp_path / "bare.urdf").write_text(
        '<robot name="bare"><link name="base"/><link name="hand"/>'
        '<joint name="j" type="revolute"><parent link="base"/><child link="hand"/><axis xyz="0 0 1"/>'
        '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>',
        encoding="utf-8",
    )
    robot = 'robot Bare {\n    urdf "bare.urdf"\n    effector tip = link hand offset (0, 0, 0) cm\n}\n'
    bare = f"use stdlib.bodies.block\n\n{robot}"
    table = "    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Bare at (0, 0, 0) m\n"
    for x, expected in (("0.15", []), ("0.14", ["E420"])):
        text = f"{bare}\nscene s {{\n{table}    block : Block on table at ({x}, 0) m\n}}\n"
        assert [d.code for d in _check(tmp_path, text)] == expected


@pytest.mark.parametrize(
    ("goal", "note"),
    [
        ("block at (600, 100) m", "did you mean `mm`? `(600, 100) mm` is (0.6, 0.1) m, on the table"),
        ("block at (45, 10) m", "did you mean `cm`? `(45, 10) cm` is (0.45, 0.1) m, on the table"),
        ("block at (1.4, 0.1) m", None),  # just past the edge: a goal past the edge, not a unit written wrong
        ("block at (4500, 100) mm", None),  # 4.5 m: no smaller unit than `mm`
        ("block moved by (1500, 0) cm", None),  # a displacement: the position checked was never written
    ],
)
def test_a_far_goal_names_the_unit_that_would_put_it_on_the_table(tmp_path: Path, goal: str, note: str | None) -> None:
    found = _scene(tmp_path, "block : Block on table at (0.45, 0.0) m", task=f"task t {{ scene s goal {goal} }}")
    (error,) = [d for d in found if d.code == "E423"]
    slips = [n for n in error.notes if n.startswith("did you mean")]
    assert slips == ([note] if note else []), error.notes
