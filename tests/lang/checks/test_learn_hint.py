"""W601's note (vkgl/lang/checks/learn_hint.py): where a body's learned affordances are, or how to learn them.

A user who ran `vkgc learn bodies/bracket.vkg` and then forgot to `use` the module it wrote is told the `use`
line itself, relative to the task file; a module there that `vkgc learn` did not write is not offered.
"""

from __future__ import annotations

from pathlib import Path

from vkgl.api import GENERATED_MARK
from vkgl.lang.checks.learn_hint import LEARNED_MARK, default_learn_folder, learned_module
from vkgl.lang.compiler import check_files
from vkgl.lang.diagnostics.diagnostic import Diagnostic

BODY = """\
body Bracket {
    shape box (30, 10, 4) cm
    mass 1.2 kg
    explore pushes {
        contacts on faces +x steps 1
        force normal 3 N
        duration 3 s
    }
}
"""
AFFORDANCES = """\
use "../bodies/bracket.vkg"

affordances Bracket {
    affordance push_center_px {
        action fixed at (-15, 0, 0) cm yaw 0deg
        motion prismatic along (1, 0, 0) from (0, 0, 0) cm
    }
}
"""
TASK = """\
use stdlib.robots.panda
use "../lib/bodies/bracket.vkg"

scene shop {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    bracket : Bracket on table at (0.5, 0) m
}

task push_bracket {
    scene shop
    goal bracket at (0.6, 0) m
}
"""


def _project(tmp_path: Path, module_header: str | None) -> Path:
    """lib/bodies/bracket.vkg, lib/affordances/bracket.vkg when `module_header` is given, tasks/push.vkg."""
    (tmp_path / "lib" / "bodies").mkdir(parents=True)
    (tmp_path / "lib" / "bodies" / "bracket.vkg").write_text(BODY, encoding="utf-8")
    if module_header is not None:
        (tmp_path / "lib" / "affordances").mkdir()
        (tmp_path / "lib" / "affordances" / "bracket.vkg").write_text(module_header + AFFORDANCES, encoding="utf-8")
    (tmp_path / "tasks").mkdir()
    task = tmp_path / "tasks" / "push.vkg"
    task.write_text(TASK, encoding="utf-8")
    return task


def _w601_notes(task: Path) -> list[str]:
    diagnostics: list[Diagnostic] = check_files([str(task)])[0]
    return [note for d in diagnostics if d.code == "W601" for note in d.notes]


def test_a_learned_module_not_imported_is_named_with_its_use_line(tmp_path: Path) -> None:
    header = f"{LEARNED_MARK}` from 1 trials of the body file ../bodies/bracket.vkg (relative to this file).\n"
    notes = _w601_notes(_project(tmp_path, header))
    assert len(notes) == 1
    assert notes[0].startswith("`vkgc learn` wrote them to ")
    assert notes[0].endswith('add `use "../lib/affordances/bracket.vkg"`')


def test_without_a_learned_module_the_note_gives_the_learn_command(tmp_path: Path) -> None:
    notes = _w601_notes(_project(tmp_path, None))
    assert len(notes) == 1 and "learn them with `vkgc learn " in notes[0] and "bracket.vkg`" in notes[0]


def test_a_hand_written_module_in_the_learned_place_is_not_offered(tmp_path: Path) -> None:
    notes = _w601_notes(_project(tmp_path, "# Hand-written affordances of the Bracket.\n"))
    assert len(notes) == 1 and "learn them with `vkgc learn " in notes[0]


def test_the_learned_place_follows_the_learn_commands_layout(tmp_path: Path) -> None:
    assert default_learn_folder(tmp_path / "lib" / "bodies" / "b.vkg") == (tmp_path / "lib" / "affordances").resolve()
    assert default_learn_folder(tmp_path / "b.vkg") == (tmp_path / "affordances").resolve()
    assert learned_module(tmp_path / "b.vkg", "Bracket").name == "bracket.vkg"
    assert LEARNED_MARK == GENERATED_MARK  # the note offers exactly the modules `vkgc learn` may replace
