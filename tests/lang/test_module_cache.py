"""Parses of module files read back from the cache folder compile exactly as fresh ones (vkgl.lang.module_cache).

The second `vkgc check` of a task parses nothing it parsed before: it needs neither Lark nor the grammar's
tables. Whatever changes (the text, the code), or whatever is found in the folder in place of a parse, the
file is parsed again.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import EXAMPLES, REPO

from vkgl.lang import module_cache
from vkgl.lang.compiler import check_file, compile_source
from vkgl.lang.diagnostics.diagnostic import render
from vkgl.lang.syntax import parser

TASK = EXAMPLES / "tasks" / "b_stick_push.vkg"
BROKEN = REPO / "tests" / "lang" / "golden" / "E105_misspelled_unit.vkg"


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    folder = tmp_path / "cache"
    monkeypatch.setenv("VKGL_CACHE_DIR", str(folder))
    _forget()
    yield folder
    _forget()


def _forget() -> None:
    parser.parse_cache().clear()
    module_cache.forget_read_back()


def _compiled(path: Path) -> tuple[str, list[str]]:
    program, diagnostics = check_file(path)
    root = repr(program.root.model_dump()) if program is not None else "none"
    return root, [render(d, None) for d in diagnostics]


def _parses(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The paths parsed from now on (parses read back are not)."""
    parsed: list[str] = []
    real = parser.parse_collecting

    def counting(text: str, path: str) -> object:
        parsed.append(path)
        return real(text, path)

    monkeypatch.setattr(parser, "parse_collecting", counting)
    return parsed


@pytest.mark.parametrize("path", [TASK, BROKEN], ids=["task", "syntax-error"])
def test_a_parse_read_back_compiles_as_a_fresh_one(cache: Path, monkeypatch: pytest.MonkeyPatch, path: Path) -> None:
    monkeypatch.setenv("VKGL_CACHE_DIR", "off")
    fresh = _compiled(path)
    monkeypatch.setenv("VKGL_CACHE_DIR", str(cache))
    assert _compiled(path) == fresh  # parsed, and kept
    _forget()
    parsed = _parses(monkeypatch)
    assert _compiled(path) == fresh  # read back
    assert parsed == []
    assert list(cache.glob("parse-*.pickle"))


def test_an_edited_module_is_parsed_again_and_replaces_its_parse(
    cache: Path, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    module = tmp_path / "m.vkg"
    module.write_text("body A {\n    shape box (1, 1, 1) cm\n    mass 1 kg\n}\n", encoding="utf-8")
    assert _compiled(module)[1] == []
    kept = set(cache.glob("parse-*.pickle"))
    module.write_text("body A {\n    shape box (1, 1, 1) cm\n    mass 1 kgs\n}\n", encoding="utf-8")
    _forget()
    parsed = _parses(monkeypatch)
    assert any("E105" in line for line in _compiled(module)[1])
    assert parsed == [str(module)]
    assert set(cache.glob("parse-*.pickle")) == kept  # one file per module: replaced, not added


def test_other_code_reads_none_of_the_parses_back(cache: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    _compiled(TASK)
    _forget()
    kept = set(cache.glob("parse-*.pickle"))
    monkeypatch.setattr(module_cache, "code_identity", lambda: "the front end, edited")
    parsed = _parses(monkeypatch)
    _compiled(TASK)
    assert any(p.endswith("b_stick_push.vkg") for p in parsed) and any("stdlib" in p for p in parsed)
    assert set(cache.glob("parse-*.pickle")) == kept  # the new parses replace the old ones


@pytest.mark.parametrize("damage", ["garbage", "torn", "first-line", "other-type"])
def test_what_is_not_a_parse_is_ignored_and_written_again(
    cache: Path, monkeypatch: pytest.MonkeyPatch, damage: str
) -> None:
    fresh = _compiled(TASK)
    files = sorted(cache.glob("parse-*.pickle"))
    for file in files:
        data = file.read_bytes()
        first, _, rest = data.partition(b"\n")
        damaged = {
            "garbage": b"\x00not a parse",
            "torn": data[: len(data) // 2],
            "first-line": b"0" * 64 + b"\n" + rest,
            "other-type": first + b"\n" + pickle.dumps({"module": None}),
        }[damage]
        file.write_bytes(damaged)
    _forget()
    assert _compiled(TASK) == fresh
    assert all(f.read_bytes() != b"\x00not a parse" for f in files)
    _forget()
    parsed = _parses(monkeypatch)
    assert _compiled(TASK) == fresh and parsed == []  # written again: read back now


def test_texts_from_an_editor_are_never_kept(cache: Path) -> None:
    compile_source("body A {\n    shape box (1, 1, 1) cm\n    mass 1 kg\n}\n", "buffer.vkg")
    assert not list(cache.glob("parse-*.pickle"))


def test_without_a_cache_folder_nothing_is_kept(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("VKGL_CACHE_DIR", "off")
    _forget()
    assert _compiled(TASK)[1] == []
    assert not list(tmp_path.rglob("parse-*"))


def test_a_second_check_imports_no_lark(tmp_path: Path) -> None:
    env = {**os.environ, "VKGL_CACHE_DIR": str(tmp_path), "PYTHONPATH": str(REPO)}
    code = (
        f"import sys; from vkgl.cli import main; assert main(['check', {str(TASK)!r}]) == 0; "
        "print('lark:', 'lark' in sys.modules)"
    )
    runs = [
        subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, env=env, timeout=120)
        for _ in range(2)
    ]
    assert all(r.returncode == 0 for r in runs), runs[-1].stderr[-2000:]
    assert "lark: True" in runs[0].stdout and "lark: False" in runs[1].stdout
