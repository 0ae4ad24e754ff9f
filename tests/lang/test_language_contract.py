"""docs/language.md is the language's contract: the snippets of "The language in one example" parse, check and
mean what they say.

The snippets are read at test time from that section. Each is compiled in the
module it would live in: bodies alone, the robot beside a copy of the stdlib's
URDF, the affordances and correspondences with the stdlib modules they name, the
scene as examples/scenes/tabletop.vkg and the task as a goal file beside it. The
`text` block is an expected rendering: our rendering of the same bad line matches it.
"""

from __future__ import annotations

import math
import re
import shutil
import textwrap
from pathlib import Path

import numpy as np
import pytest

from vkgl.cli import main
from vkgl.lang.compiler import check_files, compile_file
from vkgl.lang.ir.nodes import PrismaticC, RevoluteC
from vkgl.lang.syntax.parser import parse_module
from vkgl.resources import stdlib_dir

DOCS_LANGUAGE = Path(__file__).resolve().parents[2] / "docs" / "language.md"
SECTION = "## The language in one example"

USE_ROBOT_AND_BODIES = (
    "use stdlib.robots.panda\nuse stdlib.bodies.block\nuse stdlib.bodies.stick\nuse stdlib.bodies.hook\n\n"
)


def _section() -> str:
    """The text of docs/language.md's "The language in one example", up to the next section."""
    text = DOCS_LANGUAGE.read_text(encoding="utf-8")
    assert text.count(SECTION + "\n") == 1, f"docs/language.md has no single `{SECTION}` section"
    after = text.split(SECTION + "\n", 1)[1]
    return re.split(r"^## ", after, maxsplit=1, flags=re.MULTILINE)[0]


def _blocks() -> list[str]:
    """Every fenced code block of the section, in order."""
    return re.findall(r"^```[^\n]*\n(.*?)^```", _section(), re.MULTILINE | re.DOTALL)


def _block(starting: str) -> str:
    """The one VKG block whose first statement (comments and `use` lines skipped) starts with `starting`."""
    found = [b for b in _blocks() if _first_statement(b).startswith(starting)]
    assert len(found) == 1, f"the section has {len(found)} blocks starting with `{starting}`"
    return found[0]


def _first_statement(block: str) -> str:
    for line in block.splitlines():
        stripped = line.strip()
        if stripped and not stripped.startswith(("#", "use ")):
            return stripped
    return ""


def _write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def _assert_clean(path: Path) -> None:
    diagnostics, _ = check_files([str(path)])
    assert [d.headline() for d in diagnostics] == []


@pytest.fixture
def project(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A scratch project laid out like examples/: scenes/ and tasks/ side by side."""
    monkeypatch.delenv("VKG_PATH", raising=False)
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_every_vkg_block_is_covered_by_a_test() -> None:
    """A new snippet in the section must be added here: the known kinds cover every block."""
    kinds = ("body ", "robot ", "affordances ", "correspondences", "scene ", "task ")
    for block in _blocks():
        first = _first_statement(block)
        assert first.startswith(kinds) or "error[" in block, f"unclassified snippet: {first!r}"


def test_body_snippets_check_alone_and_mean_what_they_say(project: Path) -> None:
    text = _block("body Block")
    _assert_clean(_write(project / "bodies.vkg", text))
    program = compile_file(project / "bodies.vkg")
    assert set(program.bodies) == {"Block", "Stick", "Hook", "Drawer"}
    block = program.bodies["Block"]
    assert block.shape.size.values == pytest.approx((0.10, 0.20, 0.05))
    assert block.mass.value == pytest.approx(0.5) and block.friction == pytest.approx(0.5)
    pushes = block.explores[0]
    assert pushes.contacts.faces == ["+x", "-x"] and pushes.contacts.steps == 9
    assert pushes.force.mode == "normal" and pushes.force.magnitude.value == pytest.approx(1.0)
    stick = program.bodies["Stick"]
    assert stick.frame("tip").pose.position.values == pytest.approx((0.20, 0.0, 0.0))
    assert stick.explores[0].grasp.name == "handle" and stick.explores[0].force.grid == (3, 3, 3)
    hook_tip = program.bodies["Hook"].frame("tip").pose
    assert hook_tip.yaw.value == pytest.approx(math.pi)
    drawer_joint = program.bodies["Drawer"].joint
    assert drawer_joint.type == "prismatic" and drawer_joint.upper.value == pytest.approx(0.30)


def test_body_snippets_match_the_stdlib_bodies() -> None:
    """The stdlib ships the section's bodies as written (the stdlib may add comments).

    Hook is the exception: stdlib/bodies/hook.vkg lengthens the cross-piece on
    purpose (its header says why), and is also explored held at its shaft's end
    (`frame end`, `explore wield_end`: docs/stdlib.md), so only the section's
    frames and exploration must come first.
    The stdlib Block explores the section's `pushes` and, after it, a longer `slides`
    block (stdlib/bodies/block.vkg says why: the slides' explored range); the
    Block of the section is the stdlib's without that addition.
    The stdlib Drawer is the section's drawer with a handle (its shape is a union whose
    first part is the section's box, in place), a real drawer's mass, and explorations
    of both directions (stdlib/bodies/drawer.vkg says why); its joint is the section's,
    with the damping and friction of a real drawer's runners (docs/stdlib.md).
    """
    snippet = parse_module(_block("body Block"), "snippet.vkg")
    by_name = {d.name: d for d in snippet.decls}
    hook = parse_module((stdlib_dir() / "bodies" / "hook.vkg").read_text(encoding="utf-8"), "x.vkg").decls[0]
    assert [f.name for f in hook.frames] == ["handle", "tip", "end"]
    assert list(hook.explores[:1]) == list(by_name["Hook"].explores)
    drawer = parse_module((stdlib_dir() / "bodies" / "drawer.vkg").read_text(encoding="utf-8"), "x.vkg").decls[0]
    first = drawer.shape.parts[0]
    assert first.shape == by_name["Drawer"].shape and first.pose.matrix() == pytest.approx(np.eye(4))
    assert drawer.joint.damping is not None and drawer.joint.friction is not None
    assert drawer.joint.model_copy(update={"damping": None, "friction": None}) == by_name["Drawer"].joint
    for name in ("Block", "Stick"):
        shipped = parse_module((stdlib_dir() / "bodies" / f"{name.lower()}.vkg").read_text(encoding="utf-8"), "x.vkg")
        (body,) = [d for d in shipped.decls if d.name == name]
        if name == "Block":
            assert [e.name for e in body.explores] == ["pushes", "slides"]
            body = body.model_copy(update={"explores": body.explores[:1]})
        assert body == by_name[name]


def test_robot_snippet_checks_beside_its_urdf(project: Path) -> None:
    shutil.copy(stdlib_dir() / "robots" / "panda.urdf", project / "panda.urdf")
    path = _write(project / "panda.vkg", _block("robot Panda"))
    _assert_clean(path)
    robot = compile_file(path).robots["Panda"]
    assert robot.effectors[0].name == "fingertip" and robot.effectors[0].link == "panda_hand"
    assert robot.effectors[0].offset.position.values == pytest.approx((0.0, 0.0, 0.103))


def test_affordance_snippet_checks_with_its_body(project: Path) -> None:
    path = _write(project / "block_affordances.vkg", _block("affordances Block"))
    _assert_clean(path)
    program = compile_file(path)
    push, turn = program.affordances["Block"]  # only this module's: the stdlib affordances are not imported
    assert push.action.pose.position.values == pytest.approx((-0.05, 0.0, 0.0))
    assert isinstance(push.motion, PrismaticC) and push.motion.axis.values == (1.0, 0.0, 0.0)
    assert isinstance(turn.motion, RevoluteC) and turn.motion.axis.values == (0.0, 0.0, -1.0)
    assert push.evidence.trials == 3 and push.evidence.posterior == pytest.approx(0.998)


def test_correspondence_snippet_checks_with_the_tools_and_robot(project: Path) -> None:
    path = _write(project / "tools.vkg", USE_ROBOT_AND_BODIES + _block("correspondences"))
    _assert_clean(path)
    items = compile_file(path).correspondences
    assert [(c.frame.body, c.frame.frame, c.effector.name) for c in items] == [
        ("Stick", "tip", "fingertip"),
        ("Hook", "tip", "fingertip"),
    ]


def test_scene_and_task_snippets_check_as_a_goal_file_beside_its_scene(project: Path) -> None:
    _write(project / "scenes" / "tabletop.vkg", USE_ROBOT_AND_BODIES + _block("scene tabletop"))
    task = _write(project / "tasks" / "a_push.vkg", _block("task a_push"))
    _assert_clean(task)
    program = compile_file(task)
    scene = program.scenes["tabletop"]
    assert scene.table.size.values == pytest.approx((1.6, 1.2))
    assert [b.name for b in scene.bodies] == ["block", "stick", "hook"]
    assert all(b.placement.on_table for b in scene.bodies)
    goal = program.tasks["a_push"].goals[0]
    assert goal.position.values == pytest.approx((0.60, 0.0))
    assert goal.tol_position.value == pytest.approx(0.01) and goal.tol_yaw.value == pytest.approx(math.radians(3))
    search = program.tasks["a_push"].search
    assert search.max_depth == 6 and search.timeout.value == pytest.approx(30.0)


def test_section_9_rendering_matches_ours(project: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The section's diagnostic, reproduced: same path:line:col, code and message; carets under the same text."""
    block = next(b for b in _blocks() if "error[" in b)
    headline, shown, carets = block.rstrip("\n").split("\n")[:3]
    match = re.fullmatch(r"(.+?):(\d+):(\d+): error\[(E\d+)\]: (.+)", headline)
    assert match, headline
    path, line, col = match.group(1), int(match.group(2)), int(match.group(3))
    statement = shown.strip()
    offset = carets.index("^") - (len(shown) - len(shown.lstrip()))
    indent = col - 1 - offset
    assert indent >= 0
    _write(project / "examples" / "scenes" / "tabletop.vkg", USE_ROBOT_AND_BODIES + _block("scene tabletop"))
    header = [
        'use "../scenes/tabletop.vkg"',
        "use stdlib.affordances.block",
        "use stdlib.tools",
        "task bad {",
        "  scene tabletop",
    ]
    header[3:3] = ["#"] * (line - 1 - len(header))  # pad with comments so the goal lands on the same line
    _write(project / path, "\n".join(header + [" " * indent + statement, "}"]) + "\n")

    assert main(["check", path]) == 1
    out = capsys.readouterr().out.split("\n")
    assert out[0] == headline
    assert textwrap.dedent("\n".join(out[1:3])) == textwrap.dedent("\n".join([shown, carets]))
    assert out[3].startswith("    note: ")  # the unit hint follows the contract's three lines
    assert out[-2] == "1 error in 1 file"


def test_every_vkg_example_of_the_language_reference_parses() -> None:
    """docs/language.md promises that each of its `vkg` blocks is a complete module that parses."""
    blocks = re.findall(r"^```vkg\n(.*?)^```", DOCS_LANGUAGE.read_text(encoding="utf-8"), re.MULTILINE | re.DOTALL)
    assert len(blocks) >= 10
    for block in blocks:
        parse_module(block, "docs/language.md")
