"""E101's note for a statement whose `at POSE` was left out (vkgl/lang/syntax/syntax_errors.py, `_missing_at`).

The parser stops at whatever follows the statement (the next line, or a `}`), so without the note the caret points
past the mistake and the message reads "expected `at`" alone. Each statement that needs its pose gets its note.
"""

from __future__ import annotations

import pytest

from vkgl.errors import CompileError
from vkgl.lang.compiler import compile_source
from vkgl.lang.syntax.syntax_errors import MISSING_AT_NOTES

SCENE = "use stdlib.robots.panda\nuse stdlib.bodies.block\n\nscene s {{\n{statements}\n}}\n"
TABLE = "    table size (1.6, 1.2) m at (0.5, 0, 0) m"
ROBOT = "    robot arm : Panda at (0, 0, 0) m"


def _notes(source: str) -> list[str]:
    with pytest.raises(CompileError) as failed:
        compile_source(source, "case.vkg")
    found = [d for d in failed.value.diagnostics if d.code == "E101"]
    assert found and "expected `at`" in found[0].message
    return list(found[0].notes)


@pytest.mark.parametrize(
    ("statements", "note"),
    [
        (f"    table size (1.6, 1.2) m\n{ROBOT}", "TABLE_SIZE"),
        (f"{TABLE}\n    robot arm : Panda", "ROBOT"),
        (f"{TABLE}\n{ROBOT}\n    b : Block on table (0.4, 0) m", "ON_TABLE"),
    ],
)
def test_a_scene_statement_without_its_pose_is_told_what_to_write(statements: str, note: str) -> None:
    assert _notes(SCENE.format(statements=statements)) == [MISSING_AT_NOTES[note]]


def test_a_union_part_without_its_pose_is_told_even_when_the_next_part_follows() -> None:
    body = (
        "body B {\n    shape union {\n        box (1, 1, 1) cm\n"
        "        box (1, 2, 1) cm at (0, 0, 1) cm\n    }\n    mass 1 kg\n}\n"
    )
    assert _notes(body) == [MISSING_AT_NOTES["UNION"]]


def test_a_placement_that_could_take_several_words_gets_no_such_note() -> None:
    # `b : Block` may go on with `on table at`, `at`, `in` or `open`: not a missing `at` alone.
    with pytest.raises(CompileError) as failed:
        compile_source(SCENE.format(statements=f"{TABLE}\n{ROBOT}\n    b : Block"), "case.vkg")
    assert all(note not in MISSING_AT_NOTES.values() for d in failed.value.diagnostics for note in d.notes)
