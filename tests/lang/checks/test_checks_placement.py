"""Bodies placed relative to another (vkgl/lang/checks/geometry/placement.py): `in B` and `at B.F`.

The checker puts the body at the frame of its host's type where the host
starts; a missing frame is E303, an unknown host E301, a cycle E303; E420's
note says where an overlapping body clears, and for a relative placement how
to move the frame.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from vkgl.errors import CompileError
from vkgl.lang.compiler import compile_source
from vkgl.lang.ir.geometry import scene_body_pose
from vkgl.lang.syntax.parser import parse_module
from vkgl.lang.syntax.printer import print_module

ROOT = Path(__file__).resolve().parents[3]
HEADER = """\
use stdlib.robots.panda
use stdlib.bodies.drawer
use stdlib.bodies.door
use stdlib.furniture.drawer_cabinet
use stdlib.furniture.door_cabinet

body Shelf {
    shape box (30, 50, 2) cm
    mass 2 kg
    frame top = (0, 0, 8.3) cm  # where a DrawerCabinet's frame is when it rests on the shelf
}
"""


def _scene(*lines: str) -> str:
    body = "\n".join(f"    {line}" for line in lines)
    table = "    table size (1.6, 1.2) m at (0.5, 0, 0) m\n    robot arm : Panda at (0, 0, 0) m\n"
    return HEADER + f"scene s {{\n{table}{body}\n}}\n"


def _codes(text: str) -> list[str]:
    with pytest.raises(CompileError) as error:
        compile_source(text, base_dir=ROOT)
    return [d.code for d in error.value.diagnostics]


def test_in_places_a_body_at_its_hosts_slot_where_the_host_starts() -> None:
    program = compile_source(
        _scene("cabinet : DrawerCabinet on table at (0.68, 0.3) m yaw 160deg", "drawer : Drawer in cabinet"),
        base_dir=ROOT,
    )
    scene = program.scenes["s"]
    cabinet, drawer = scene.bodies
    host = scene_body_pose(scene, cabinet, program.bodies["DrawerCabinet"])
    placed = scene_body_pose(scene, drawer, program.bodies["Drawer"])
    assert np.allclose(placed, host, atol=1e-12)  # the DrawerCabinet's slot is its own frame
    assert placed[2, 3] == pytest.approx(0.073)


def test_at_a_named_frame_and_a_chain_of_hosts() -> None:
    text = _scene(
        "shelf : Shelf on table at (0.6, 0.2) m yaw 90deg",
        "cabinet : DrawerCabinet at shelf.top",
        "drawer : Drawer open 5 cm in cabinet",
    )
    program = compile_source(text, base_dir=ROOT)
    scene = program.scenes["s"]
    poses = {b.name: scene_body_pose(scene, b, program.bodies[b.type.name]) for b in scene.bodies}
    assert poses["cabinet"][:3, 3] == pytest.approx((0.6, 0.2, 0.093))  # resting on the 2 cm shelf
    assert np.allclose(poses["cabinet"][:3, :3], poses["shelf"][:3, :3])
    assert poses["drawer"][:3, 3] - poses["cabinet"][:3, 3] == pytest.approx(
        poses["cabinet"][:3, :3] @ (0.05, 0.0, 0.0)
    )  # placed in the cabinet, and started 5 cm open along its slide


def test_misplaced_bodies_are_errors() -> None:
    assert _codes(_scene("shelf : Shelf on table at (0.6, 0.2) m", "drawer : Drawer in shelf")) == ["E303"]
    assert _codes(_scene("shelf : Shelf on table at (0.6, 0.2) m", "drawer : Drawer at shelf.side")) == ["E303"]
    assert _codes(_scene("drawer : Drawer in cabinet")) == ["E301"]
    assert _codes(_scene("a : DrawerCabinet in b", "b : DrawerCabinet in a")) == ["E303", "E303"]


def test_e420_says_how_to_move_the_frame_of_a_relative_placement() -> None:
    text = _scene("cabinet : DrawerCabinet on table at (0.7, 0.25) m yaw 180deg", "drawer : Drawer in cabinet")
    text = text.replace("use stdlib.furniture.drawer_cabinet\n", "")
    text = text.replace(
        "body Shelf {",
        "body DrawerCabinet {\n    shape union {\n        box (32.8, 44.6, 1.8) cm at (-1.4, 0, -6.4) cm\n"
        "        box (32.8, 44.6, 1.8) cm at (-1.4, 0, 6.4) cm\n    }\n    mass 4.8 kg\n"
        "    frame slot = (0, 0, -1) cm\n}\n\nbody Shelf {",
    )
    with pytest.raises(CompileError) as error:
        compile_source(text, base_dir=ROOT)
    (overlap,) = error.value.diagnostics
    assert overlap.code == "E420"
    assert "`drawer` clears it moved up by 0.5 cm, to (0.7, 0.25, 0.068) m" in overlap.notes
    frame = "it is placed at `cabinet.slot`: move the frame `slot` of `DrawerCabinet` by (0, 0, 0.45) cm"
    assert frame in overlap.notes


def test_relative_placements_print_as_written() -> None:
    text = _scene(
        "shelf : Shelf on table at (0.6, 0.2) m",
        "cabinet : DrawerCabinet at shelf.top",
        "drawer : Drawer open 5 cm in cabinet",
    )
    module = parse_module(text, "t.vkg")
    printed = print_module(module)
    assert "    cabinet : DrawerCabinet at shelf.top\n    drawer : Drawer open 5 cm in cabinet\n" in printed
    assert parse_module(printed, "t.vkg") == module
