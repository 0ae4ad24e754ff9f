"""The grammar's tables kept between processes (vkgl/lang/syntax/tables.py) make the same parser as building them.

A loaded parser must parse every file as the built one does, name the same syntax errors, and call the
same comment collector; a stale or torn file is ignored and written again; with the cache off nothing
is written.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import EXAMPLES, REPO, STDLIB
from lark import Lark
from lark.exceptions import UnexpectedInput

from vkgl.lang.diagnostics.diagnostic import render
from vkgl.lang.syntax import parser as vkg_parser
from vkgl.lang.syntax.syntax_errors import syntax_diagnostics
from vkgl.lang.syntax.tables import load_or_build
from vkgl.resources import CACHE_ENV, CACHE_OFF, grammar_path

GRAMMAR = grammar_path().read_text(encoding="utf-8")
GOLDEN = REPO / "tests" / "lang" / "golden"
SOURCES = sorted([*GOLDEN.glob("*.vkg"), *EXAMPLES.rglob("*.vkg"), *STDLIB.rglob("*.vkg")])


def _build() -> Lark:
    return Lark(GRAMMAR, lexer_callbacks={"COMMENT": vkg_parser._comments}, **vkg_parser._OPTIONS)


def _never() -> Lark:
    raise AssertionError("the tables were built, not loaded")


def _outcome(parser: Lark, text: str, path: str) -> object:
    """The tree and the comments lexed, or the syntax diagnostics."""
    try:
        with vkg_parser._comments.collect() as comments:
            tree = parser.parse(text)
        return tree, [(t.line, t.column, str(t)) for t in comments]
    except UnexpectedInput as exc:
        return [render(d, text) for d in syntax_diagnostics(parser, exc, text, path)]


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv(CACHE_ENV, str(tmp_path))
    return tmp_path


def test_a_loaded_parser_parses_and_fails_as_the_built_one(cache: Path) -> None:
    built = load_or_build(GRAMMAR, vkg_parser._OPTIONS, _build)
    assert len(list(cache.glob("*.lark-tables"))) == 1
    loaded = load_or_build(GRAMMAR, vkg_parser._OPTIONS, _never)
    assert loaded is not built
    assert loaded.lexer_conf.callbacks["COMMENT"] is vkg_parser._comments
    failures = 0
    for source in SOURCES:
        text = source.read_text(encoding="utf-8")
        expected = _outcome(built, text, source.name)
        assert _outcome(loaded, text, source.name) == expected, source.name
        failures += isinstance(expected, list)
    assert failures >= 5  # the golden syntax errors were among them


def test_a_stale_or_torn_file_is_built_again(cache: Path) -> None:
    load_or_build(GRAMMAR, vkg_parser._OPTIONS, _build)
    (kept,) = cache.glob("*.lark-tables")
    whole = kept.read_bytes()
    builds = []

    def counted() -> Lark:
        builds.append(1)
        return _build()

    for n, broken in enumerate((b"another key\n" + whole.split(b"\n", 1)[1], whole[: len(whole) // 2], b"")):
        kept.write_bytes(broken)
        load_or_build(GRAMMAR, vkg_parser._OPTIONS, counted)
        assert len(builds) == n + 1
        assert kept.read_bytes().split(b"\n", 1)[0] == whole.split(b"\n", 1)[0]  # written again, whole
        load_or_build(GRAMMAR, vkg_parser._OPTIONS, _never)


def test_other_options_or_grammars_are_other_files(cache: Path) -> None:
    load_or_build(GRAMMAR, vkg_parser._OPTIONS, _build)
    with pytest.raises(AssertionError, match="built"):
        load_or_build(GRAMMAR + "\n// changed\n", vkg_parser._OPTIONS, _never)
    with pytest.raises(AssertionError, match="built"):
        load_or_build(GRAMMAR, {**vkg_parser._OPTIONS, "propagate_positions": False}, _never)


def test_with_the_cache_off_nothing_is_kept(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(CACHE_ENV, CACHE_OFF)
    monkeypatch.chdir(tmp_path)
    load_or_build(GRAMMAR, vkg_parser._OPTIONS, _build)
    assert not list(tmp_path.rglob("*"))
