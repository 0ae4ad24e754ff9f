"""Hover texts built from the IR (the LSP tests cover the protocol)."""

from __future__ import annotations

from vkgl.editor.hover import body_hover
from vkgl.lang.syntax.parser import parse_module


def test_a_bodys_hover_shows_its_joints_damping_and_friction() -> None:
    body = parse_module(
        "body Slide { shape box (30, 40, 10) cm mass 2 kg "
        "joint prismatic axis (1, 0, 0) limits (0, 30) cm damping 5 N*s/m friction 2 N }",
        "slide.vkg",
    ).decls[0]
    assert "- joint `prismatic axis (1, 0, 0) limits (0, 30) cm damping 5 N*s/m friction 2 N`" in body_hover(body)


def test_a_scene_bodys_hover_says_where_its_joint_starts() -> None:
    from vkgl.editor.hover import _instance_hover

    scene = parse_module(
        "scene s { door : Door open 60deg at (0.55, -0.33, 0.25) m yaw 180deg  block : Block on table at (0.4, 0) m }",
        "s.vkg",
    ).decls[0]
    door, block = scene.bodies
    assert _instance_hover(door, "s").endswith("its joint starting open `60deg`")
    assert "open" not in _instance_hover(block, "s")
