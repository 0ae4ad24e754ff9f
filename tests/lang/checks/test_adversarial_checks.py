"""The second adversarial review's check findings (issue 25): each was a clean check, a NaN or an exit 4.

A joint axis whose length squared underflows (or overflows) is E404, not a NaN
axis that "solves"; a flat mesh placed on a table is E503, not an internal
error, also in a file that only `use`s it; a joint whose limits exclude 0 and
that is placed without `open` is E442 (it would start past its stops).
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from vkgl.lang.compiler import check_files

GOLDEN_LIB = Path(__file__).resolve().parents[1] / "golden" / "lib"
DRAWER = """body Drawer {{
    shape box (30, 40, 10) cm
    mass 1 kg
    joint {kind} axis {axis} limits {limits}
}}
"""
SCENE = """use stdlib.robots.panda
use "sheet.vkg"

scene flat {
    table size (1, 1) m at (0, 0, 0) m
    robot arm : Panda at (-0.5, 0, 0) m
    sheet : Sheet on table at (0.3, 0) m
}
"""


def codes_of(path: Path) -> list[str]:
    diagnostics, _ = check_files([str(path)])
    return [d.code for d in diagnostics]


@pytest.mark.parametrize(
    ("axis", "expected"),
    [
        ("(1e-300, 0, 0)", ["E404"]),
        ("(1e-160, 1e-160, 0)", ["E404"]),  # the square is subnormal: the direction loses its digits
        ("(1e200, 0, 0)", ["E404"]),  # the square overflows
        ("(1e-100, 0, 0)", []),  # small, but its square is a normal float
        ("(0.001, 0, 0)", []),
    ],
)
def test_a_joint_axis_must_have_a_length_whose_square_is_a_normal_float(
    tmp_path: Path, axis: str, expected: list[str]
) -> None:
    path = tmp_path / "drawer.vkg"
    path.write_text(DRAWER.format(kind="prismatic", axis=axis, limits="(0, 30) cm"), encoding="utf-8")
    assert codes_of(path) == expected


@pytest.mark.parametrize(
    ("kind", "limits", "expected"),
    [
        ("prismatic", "(10, 20) cm", ["E442"]),
        ("prismatic", "(-20, -10) cm", ["E442"]),
        ("revolute", "(30, 90) deg", ["E442"]),
        ("prismatic", "(0, 20) cm", []),
        ("revolute", "(-90, 0) deg", []),
    ],
)
def test_a_body_placed_without_open_starts_at_0_which_must_be_within_its_limits(
    tmp_path: Path, kind: str, limits: str, expected: list[str]
) -> None:
    body = DRAWER.format(kind=kind, axis="(0, 0, 1)", limits=limits)
    scene = (
        "use stdlib.robots.panda\n\n" + body + "\nscene s {\n    table size (1.6, 1.2) m at (0.5, 0, 0) m\n"
        "    robot arm : Panda at (0, 0, 0) m\n    drawer : Drawer on table at (0.45, 0) m\n}\n"
    )
    path = tmp_path / "scene.vkg"
    path.write_text(scene, encoding="utf-8")
    assert codes_of(path) == expected


def test_a_flat_mesh_on_a_table_is_e503_in_its_file_and_in_a_file_that_uses_it(tmp_path: Path) -> None:
    shutil.copy(GOLDEN_LIB / "one_triangle.stl", tmp_path / "sheet.stl")
    (tmp_path / "sheet.vkg").write_text('body Sheet {\n    shape mesh "sheet.stl"\n    mass 0.2 kg\n}\n')
    (tmp_path / "scene.vkg").write_text(SCENE, encoding="utf-8")
    (tmp_path / "user.vkg").write_text('use "scene.vkg"\n', encoding="utf-8")
    for name in ("sheet.vkg", "scene.vkg", "user.vkg"):
        assert codes_of(tmp_path / name) == ["E503"], name


def test_a_robot_placed_at_a_four_component_position_is_e204_not_an_internal_error(tmp_path: Path) -> None:
    # Found by the language-server fuzz run (tests/editor/lsp_fuzz.py): exit 4 in the scene checks.
    path = tmp_path / "scene.vkg"
    path.write_text(
        "use stdlib.robots.panda\nscene s {\n    table size (1.6, 1.2) m at (0.5, 0, 0) m\n"
        "    robot arm : Panda at (0, 0, 0.7, 0) m yaw 0deg\n}\n",
        encoding="utf-8",
    )
    assert codes_of(path) == ["E204"]
