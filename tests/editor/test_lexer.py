"""The Pygments lexer: real files lex cleanly, every keyword is highlighted, the entry point is declared and works."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from pygments.token import Comment, Error, Keyword, Name, Number, String

from vkgl.editor.lexer import VkgLexer
from vkgl.editor.vocabulary import DECLARATIONS, TYPES, keywords, units

REPO = Path(__file__).resolve().parents[2]
FILES = sorted([*(REPO / "examples").rglob("*.vkg"), *(REPO / "stdlib").rglob("*.vkg")])
DOCS = sorted((REPO / "docs").glob("*.md"))


def tokens(text: str) -> list[tuple[object, str]]:
    """The non-blank tokens of `text`."""
    return [(kind, value) for kind, value in VkgLexer().get_tokens(text) if value.strip()]


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(REPO)))
def test_every_example_and_stdlib_file_lexes_without_an_error_token(path: Path) -> None:
    found = [(kind, value) for kind, value in VkgLexer().get_tokens(path.read_text(encoding="utf-8")) if kind in Error]
    assert not found


def test_the_file_list_is_not_empty() -> None:
    assert len(FILES) >= 15


def test_the_vkg_blocks_of_the_docs_lex_without_an_error_token() -> None:
    blocks = [
        b
        for doc in DOCS
        for b in re.findall(
            r"^ *```vkg\n(.*?)^ *```",
            doc.read_text(encoding="utf-8"),
            re.MULTILINE | re.DOTALL,
        )
    ]
    assert len(blocks) >= 15
    for block in blocks:
        assert not [t for t in tokens(block) if t[0] in Error], block


def test_a_character_outside_the_language_is_an_error_token() -> None:
    assert (Error, "$") in tokens("body B { $ }")


@pytest.mark.parametrize("word", keywords())
def test_every_grammar_keyword_is_highlighted_as_a_keyword(word: str) -> None:
    kind, value = tokens(word)[0]
    assert value == word and kind in Keyword


def test_keyword_categories_are_grammar_keywords() -> None:
    assert set(DECLARATIONS) <= set(keywords()) and set(TYPES) <= set(keywords())


def test_declarations_quantities_faces_strings_and_comments() -> None:
    found = tokens(
        "body Block { shape box (10, 20, 5) cm  # size\n mass 0.5 kg\n"
        ' explore p { contacts on faces +x, -x steps 9 } mesh "a.stl" }\n'
        "scene s { robot arm : Panda at (0, 0, 0) m }"
    )
    assert (Keyword.Declaration, "body") in found and (Name.Class, "Block") in found
    assert (Keyword.Type, "box") in found and (Name.Builtin, "cm") in found
    assert (Number, "0.5") in found and (Name.Builtin, "kg") in found
    assert (Name.Constant, "+x") in found and (Name.Constant, "-x") in found
    assert (String.Double, '"a.stl"') in found and (Comment.Single, "# size") in found
    assert (Name.Variable, "arm") in found and (Name.Class, "Panda") in found


@pytest.mark.parametrize("unit", units())
def test_every_unit_is_highlighted_after_a_number(unit: str) -> None:
    assert tokens(f"mass 2 {unit}")[-1] == (Name.Builtin, unit)
    assert tokens(f"mass 2{unit}")[-1] == (Name.Builtin, unit)


def test_a_name_that_looks_like_a_unit_is_a_name_when_no_number_precedes_it() -> None:
    assert tokens("goal m at (1, 2) m")[1] == (Name, "m")


def test_pyproject_declares_the_lexer_entry_point() -> None:
    project = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert project["entry-points"]["pygments.lexers"] == {"vkg": "vkgl.editor.lexer:VkgLexer"}
    assert any(d.startswith("pygments") for d in project["dependencies"])


def test_pygmentize_finds_the_lexer_through_the_entry_point(tmp_path: Path) -> None:
    """Pygments' plugin discovery, fed the pyproject's entry point as an installed package would be."""
    entry = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]["entry-points"]
    dist = tmp_path / "site" / "vkgl_probe-0.dist-info"
    dist.mkdir(parents=True)
    (dist / "METADATA").write_text("Metadata-Version: 2.1\nName: vkgl-probe\nVersion: 0\n", encoding="utf-8")
    lines = [
        "[pygments.lexers]",
        *(f"{k} = {v}" for k, v in entry["pygments.lexers"].items()),
    ]
    (dist / "entry_points.txt").write_text("\n".join(lines) + "\n", encoding="utf-8")
    env_path = f"{tmp_path / 'site'}:{REPO}"
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "pygments",
            "-l",
            "vkg",
            "-f",
            "raw",
            str(REPO / "stdlib" / "bodies" / "block.vkg"),
        ],
        check=False,
        capture_output=True,
        text=True,
        timeout=60,
        env={"PYTHONPATH": env_path, "PATH": "/usr/bin:/bin"},
    )
    assert done.returncode == 0, done.stderr
    assert "Token.Keyword.Declaration\t'body'" in done.stdout
    assert "Token.Name.Builtin\t'cm'" in done.stdout
