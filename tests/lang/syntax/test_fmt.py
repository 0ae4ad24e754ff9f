"""`vkgc fmt`: canonical text that keeps the comments and the meaning, idempotently."""

from __future__ import annotations

import re
import textwrap

import pytest
from conftest import REPO, vkg_files

from vkgl.cli import main
from vkgl.errors import CompileError
from vkgl.lang.syntax.printer import format_source

PATH = "fmt.vkg"


def parse(text: str, path: str = PATH):
    from vkgl.lang.syntax.parser import parse_module

    return parse_module(text, path)


def comments_of(text: str) -> list[str]:
    """The comment texts of a source, in order (doc comment included)."""
    from vkgl.lang.syntax.parser import parse_module_with_comments

    _, comments = parse_module_with_comments(text, PATH)
    return [c.text.rstrip() for c in sorted(comments, key=lambda c: (c.line, c.col))]


def fmt(text: str) -> str:
    return format_source(textwrap.dedent(text), PATH)


# ---------------------------------------------------------------- the repository's files


@pytest.mark.parametrize("path", vkg_files(), ids=lambda p: str(p.relative_to(p.parents[1])))
def test_fmt_is_idempotent_and_keeps_meaning_and_comments(path) -> None:
    text = path.read_text(encoding="utf-8")
    once = format_source(text, str(path))
    assert format_source(once, str(path)) == once
    assert parse(once, str(path)) == parse(text, str(path))
    assert comments_of(once) == comments_of(text)


def language_snippets() -> list[str]:
    """The `vkg` code blocks of docs/language.md, the language's reference."""
    text = (REPO / "docs" / "language.md").read_text(encoding="utf-8")
    return re.findall(r"^```vkg\n(.*?)^```", text, flags=re.S | re.M)


def test_language_md_has_snippets() -> None:
    assert len(language_snippets()) >= 10


@pytest.mark.parametrize("snippet", language_snippets(), ids=lambda s: s.split("\n")[0][:30])
def test_formatting_language_md_snippets_keeps_their_meaning(snippet: str) -> None:
    once = format_source(snippet, PATH)
    assert parse(once) == parse(snippet)
    assert format_source(once, PATH) == once
    assert comments_of(once) == comments_of(snippet)


# ---------------------------------------------------------------- layout


def test_messy_source_becomes_canonical() -> None:
    messy = """\
        body   Block{mass 500g shape box(10cm,20cm,5cm)
        friction 0.50 frame com=(0,0,0.0)cm}
        use stdlib.robots.panda
        task t { scene s  goal block at (0.60, 0.0) m yaw 0deg within 1 cm, 3 deg goal b yaw 90 deg
        search { max_depth 6 timeout 30 s } }
    """
    assert fmt(messy) == textwrap.dedent("""\
        use stdlib.robots.panda

        body Block {
            shape box (10, 20, 5) cm
            mass 500 g
            friction 0.5
            frame com = (0, 0, 0) cm
        }

        task t {
            scene s
            goal block at (0.6, 0) m yaw 0deg within 1 cm, 3deg
                and b yaw 90deg
            search { max_depth 6  timeout 30 s }
        }
    """)


def test_single_blank_lines_between_statements_are_kept_and_runs_collapsed() -> None:
    source = """\
        scene s {
            table size (1, 1) m at (0, 0, 0) m


            robot arm : Panda at (0, 0, 0) m
            a : A on table at (0.5, 0) m
        }
    """
    assert fmt(source) == textwrap.dedent("""\
        scene s {
            table size (1, 1) m at (0, 0, 0) m

            robot arm : Panda at (0, 0, 0) m
            a : A on table at (0.5, 0) m
        }
    """)


# ---------------------------------------------------------------- comments


def test_full_line_and_trailing_comments_stay_with_their_statements() -> None:
    source = """\
        # The doc comment.

        # about the body
        body B {   # opening
          mass 1 kg    # mass after shape in the canonical order
            # the shape
          shape box (1, 1, 1) m
        # a frame
                frame f = (0, 0, 0) m # trailing
            # last words in the block
        }
        # the end
    """
    assert fmt(source) == textwrap.dedent("""\
        # The doc comment.

        # about the body
        body B {  # opening
            # the shape
            shape box (1, 1, 1) m
            mass 1 kg  # mass after shape in the canonical order
            # a frame
            frame f = (0, 0, 0) m  # trailing
            # last words in the block
        }
        # the end
    """)


def test_trailing_comments_of_consecutive_lines_are_aligned() -> None:
    source = """\
        body B {
            shape box (1, 1, 1) m     # a
            mass 1 kg # b
        }
    """
    assert fmt(source) == textwrap.dedent("""\
        body B {
            shape box (1, 1, 1) m  # a
            mass 1 kg              # b
        }
    """)


def test_a_comment_after_a_one_line_block_ends_its_closing_line() -> None:
    source = "correspondences { Stick.tip ~ fingertip }  # one line\n"
    out = fmt(source)
    assert out == "correspondences {\n    Stick.tip ~ fingertip\n}  # one line\n"
    assert fmt(out) == out


def test_comments_inside_a_union_and_an_explore_block() -> None:
    source = """\
        body Hook {
            shape union {
                # the long bar
                box (40, 2, 2) cm at (0, 0, 0) cm
                box (2, 12, 2) cm at (19, 5, 0) cm   # the cross-piece
            }
            mass 0.12 kg
            explore wield {
                grasp handle   # held here
                # unit force
                force directions 3 x 3 x 3  1 N
            }
        }
    """
    out = fmt(source)
    assert out == textwrap.dedent("""\
        body Hook {
            shape union {
                # the long bar
                box (40, 2, 2) cm at (0, 0, 0) cm
                box (2, 12, 2) cm at (19, 5, 0) cm  # the cross-piece
            }
            mass 0.12 kg
            explore wield {
                grasp handle  # held here
                # unit force
                force directions 3 x 3 x 3  1 N
            }
        }
    """)
    assert fmt(out) == out


# ---------------------------------------------------------------- errors and the command line


def test_syntax_errors_raise_compile_error_with_a_position() -> None:
    with pytest.raises(CompileError) as info:
        format_source("body B {\n    mass 1 kg\n", PATH)
    assert info.value.diagnostics
    assert info.value.diagnostics[0].span is not None


def test_vkgc_fmt_check_reports_and_fmt_rewrites(tmp_path, capsys) -> None:
    messy = tmp_path / "messy.vkg"
    messy.write_text("body B { shape box (1,1,1) m mass 1 kg }\n", encoding="utf-8")
    clean = tmp_path / "clean.vkg"
    clean.write_text(format_source(messy.read_text(encoding="utf-8"), str(messy)), encoding="utf-8")

    assert main(["fmt", "--check", str(messy), str(clean)]) == 1
    assert capsys.readouterr().out.strip() == f"{messy}: would reformat"

    assert main(["fmt", str(messy)]) == 0
    assert messy.read_text(encoding="utf-8") == clean.read_text(encoding="utf-8")
    assert main(["fmt", "--check", str(messy), str(clean)]) == 0
