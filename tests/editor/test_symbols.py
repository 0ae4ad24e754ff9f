"""Hover, definition and completion logic in-process (the LSP round trip is in test_lsp.py)."""

from __future__ import annotations

from pathlib import Path

from vkgl.editor.analysis import analyze
from vkgl.editor.completion import candidates
from vkgl.editor.hover import quantity_hover, symbol_hover
from vkgl.editor.symbols import declaration_span, symbol_at

REPO = Path(__file__).resolve().parents[2]
TOOLS = REPO / "stdlib" / "tools.vkg"


def test_a_name_in_a_comment_is_no_symbol() -> None:
    text = TOOLS.read_text(encoding="utf-8") + "# Stick is a tool\n"
    program = analyze(TOOLS, {TOOLS.resolve(): text}).program
    last = len(text.split("\n")) - 2
    assert symbol_at(program, TOOLS.resolve(), text, last, 3) is None


def test_an_effector_and_its_robot() -> None:
    text = TOOLS.read_text(encoding="utf-8")
    analysis = analyze(TOOLS)
    line = text.split("\n").index("    Hook.tip ~ fingertip")
    symbol = symbol_at(analysis.program, TOOLS.resolve(), text, line, 20)
    assert symbol is not None and symbol.kind == "effector" and symbol.owner == "Panda"
    span = declaration_span(symbol, analysis.sources)
    assert span is not None and span.file.endswith("panda.vkg") and span.end_col - span.col == len("fingertip")
    assert "link `panda_hand`" in symbol_hover(symbol, span)


def test_after_a_body_and_a_dot_only_its_frames_and_affordances_are_offered() -> None:
    program = analyze(REPO / "examples" / "tasks" / "b_stick_push.vkg").program
    found = {(c.label, c.kind) for c in candidates(program, "    Stick.")}
    assert ("handle", "frame") in found and ("tip", "frame") in found
    assert {kind for _, kind in found} <= {"frame", "affordance"} and any(k == "affordance" for _, k in found)


def test_quantities_with_units_on_each_component_and_plain_numbers() -> None:
    assert quantity_hover("    shape box (50cm, 10cm, 2.5cm)", 16) == (
        "`50cm` = 0.5 m (length)",
        15,
        19,
    )
    assert quantity_hover("    friction 0.5", 14) is None
    assert quantity_hover("    mass 500 g", 11) == ("`500 g` = 0.5 kg (mass)", 9, 14)
    assert quantity_hover("    frame tip = (18, 12, 0) cm yaw 180deg", 20)[0] == (
        "`(18, 12, 0) cm` = (0.18, 0.12, 0) m (length)"
    )


def test_after_a_motion_range_only_open_is_offered() -> None:
    for before in ("        motion prismatic along (1, 0, 0) range 0 to 8 cm ", "    range 0 cm to 8 cm op"):
        assert [(c.label, c.kind) for c in candidates(None, before)] == [("open", "keyword")]
    assert ("open", "keyword") in {(c.label, c.kind) for c in candidates(None, "    motion prismatic along ")}
