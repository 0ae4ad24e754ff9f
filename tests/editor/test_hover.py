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


def test_hovers_and_completion_show_goals_regions_keep_outs_and_placements_as_written() -> None:
    from vkgl.editor.completion import candidates
    from vkgl.editor.hover import _instance_hover, symbol_hover
    from vkgl.editor.symbols import Symbol

    module = parse_module(
        "scene s { cabinet : DrawerCabinet on table at (0.7, 0.25) m yaw 180deg  drawer : Drawer in cabinet "
        "shelf_box : Block at cabinet.slot  region tray = (0.55, -0.16) to (0.75, 0.12) m }\n"
        "task t { scene s  goal drawer moved by (0, 5) cm in cabinet turned by 10deg and shelf_box in tray yaw 0deg "
        "keep out region (0.1, 0.2) to (0.3, 0.4) m  keep drawer out of tray }",
        "s.vkg",
    )
    scene, task = module.decls
    assert _instance_hover(scene.bodies[1], "s").endswith("`in cabinet`")
    assert _instance_hover(scene.bodies[2], "s").endswith("`at cabinet.slot`")
    assert "- region `tray = (0.55, -0.16) to (0.75, 0.12) m`" in symbol_hover(Symbol("scene", "s", scene, None))
    shown = symbol_hover(Symbol("task", "t", task, None))
    assert "- goal `drawer moved by (0, 5) cm in cabinet turned by 10deg`" in shown
    assert "- goal `shelf_box in tray yaw 0deg`" in shown
    assert "- `keep out region (0.1, 0.2) to (0.3, 0.4) m`" in shown and "- `keep drawer out of tray`" in shown
    words = {c.label for c in candidates(None, "    goal ")}
    assert {"moved", "turned", "by", "in", "region", "polygon", "keep", "out", "of"} <= words


def test_a_grasp_and_its_slip_on_hover() -> None:
    from vkgl.editor.hover import affordance_hover
    from vkgl.lang.ir import nodes as ir
    from vkgl.lang.syntax.parser import parse_module

    text = """affordances Carton {
    affordance grasp_top_y {
        action grasp at (0.6, 0, 3.2) cm yaw 0deg width 6 cm force 20 N
        motion free
        evidence trials 3 loglik 0 posterior 1 slip 0.4 mm
    }
}
"""
    (block,) = parse_module(text, "carton.vkg").decls
    assert isinstance(block, ir.AffordanceSet)
    shown = affordance_hover(block.affordances[0], "Carton")
    assert "action `grasp at (0.6, 0, 3.2) cm yaw 0deg width 6 cm force 20 N`" in shown
    assert "posterior 1, slip 0.4 mm" in shown
