"""Never a traceback, never a hang: malformed input of any kind becomes diagnostics.

Mutations of every example and stdlib file (characters and whole tokens deleted,
inserted, duplicated, swapped or replaced; truncation; random bytes, including
non-UTF-8) go through `check_files` in-process. Each result must be a sorted
list of Diagnostics with valid positions that render without error; a run that
takes longer than a few seconds counts as a hang.
"""

from __future__ import annotations

import random
import re
from pathlib import Path

import pytest
from conftest import vkg_files
from fuzzing import check_data
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from vkgl.cli import main
from vkgl.lang.diagnostics.diagnostic import Diagnostic

SOURCES = {p.name + ":" + str(i): p.read_text(encoding="utf-8") for i, p in enumerate(vkg_files())}
TOKEN = re.compile(r'"[^"\n]*"|#[^\n]*|[+-]?\d+(?:\.\d*)?(?:[eE][+-]?\d+)?|[A-Za-z_]\w*|[+-][xyz]|\S')
# Pieces of VKG (and near-VKG) that mutations insert: keywords, units, punctuation, bad characters.
VOCABULARY = [
    "body",
    "robot",
    "scene",
    "task",
    "use",
    "affordances",
    "affordance",
    "correspondences",
    "union",
    "box",
    "mesh",
    "cylinder",
    "shape",
    "mass",
    "frame",
    "joint",
    "explore",
    "goal",
    "and",
    "within",
    "at",
    "on",
    "table",
    "yaw",
    "rpy",
    "{",
    "}",
    "(",
    ")",
    ",",
    ".",
    "=",
    ":",
    "~",
    "#",
    '"',
    '"x.vkg"',
    "cm",
    "deg",
    "kg",
    "N",
    "s",
    "lb",
    "-1",
    "0",
    "1e999",
    "2.5",
    "+x",
    "-q",
    ";",
    "@",
    "\t",
    "\n",
    "\x00",
    "é",
    "\u202e",
    "\r",
]
MUTANTS = 5000
"""Seeded mutants of the examples and stdlib checked in-process (about 5 ms each: see the module docstring)."""


def _check_text(tmp: Path, data: str | bytes) -> list[Diagnostic]:
    return check_data(tmp, data)


def _mutate(text: str, rng: random.Random) -> str:
    """One to three random edits: on characters, on tokens, or a truncation."""
    for _ in range(rng.randint(1, 3)):
        text = rng.choice(_EDITS)(text, rng)
    return text


def _delete_chars(text: str, rng: random.Random) -> str:
    i = rng.randrange(len(text) + 1)
    return text[:i] + text[i + rng.randint(1, 8) :]


def _insert_piece(text: str, rng: random.Random) -> str:
    i = rng.randrange(len(text) + 1)
    return text[:i] + rng.choice(VOCABULARY) + text[i:]


def _truncate(text: str, rng: random.Random) -> str:
    return text[: rng.randrange(len(text) + 1)]


def _token_edit(text: str, rng: random.Random) -> str:
    spans = [m.span() for m in TOKEN.finditer(text)]
    if not spans:
        return text
    k = rng.randrange(len(spans))
    a, b = spans[k]
    kind = rng.choice(("delete", "duplicate", "swap", "replace"))
    if kind == "delete":
        return text[:a] + text[b:]
    if kind == "duplicate":
        return text[:b] + " " + text[a:b] + text[b:]
    if kind == "replace":
        return text[:a] + rng.choice(VOCABULARY) + text[b:]
    c, d = spans[rng.randrange(len(spans))]
    if (c, d) < (a, b):
        (a, b), (c, d) = (c, d), (a, b)
    if c < b:
        return text
    return text[:a] + text[c:d] + text[b:c] + text[a:b] + text[d:]


_EDITS = [_delete_chars, _insert_piece, _truncate, _token_edit, _token_edit]


def test_mutants_of_the_examples_give_only_diagnostics(tmp_path: Path) -> None:
    """MUTANTS seeded mutants, a share of them as bytes that are not UTF-8, each under the time limit."""
    rng = random.Random(20261122)
    names = sorted(SOURCES)
    errors = 0
    for i in range(MUTANTS):
        text = _mutate(SOURCES[names[i % len(names)]], rng)
        data: str | bytes = text
        if i % 50 == 0:
            raw = bytearray(text.encode("utf-8"))
            raw.insert(rng.randrange(len(raw) + 1), rng.choice((0xFF, 0xC3, 0x80, 0xFE)))
            data = bytes(raw)
        errors += any(d.is_error for d in _check_text(tmp_path, data))
    assert errors > MUTANTS // 2  # the mutants are mostly broken: the test really exercises the error paths


@settings(
    max_examples=150, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    name=st.sampled_from(sorted(SOURCES)),
    edits=st.lists(
        st.tuples(
            st.sampled_from(["delete", "insert", "replace", "truncate"]),
            st.integers(0, 10**6),
            st.sampled_from(VOCABULARY),
        ),
        min_size=1,
        max_size=4,
    ),
)
def test_hypothesis_mutants_give_only_diagnostics(tmp_path: Path, name: str, edits: list[tuple[str, int, str]]) -> None:
    text = SOURCES[name]
    for kind, where, piece in edits:
        i = where % (len(text) + 1)
        if kind == "delete":
            text = text[:i] + text[i + 1 + where % 7 :]
        elif kind == "insert":
            text = text[:i] + piece + text[i:]
        elif kind == "replace":
            text = text[:i] + piece + text[i + len(piece) :]
        else:
            text = text[:i]
    _check_text(tmp_path, text)


@settings(
    max_examples=100, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=200) | st.sampled_from(VOCABULARY).map(str)
)
def test_random_text_gives_only_diagnostics(tmp_path: Path, text: str) -> None:
    _check_text(tmp_path, text)


@settings(max_examples=60, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.binary(max_size=200))
def test_random_bytes_give_only_diagnostics(tmp_path: Path, data: bytes) -> None:
    _check_text(tmp_path, data)


@pytest.mark.parametrize(
    "text",
    [
        "",
        "# only a comment",
        "body",
        "body B {" * 2000,
        "body B { shape " + "union { " * 3000,
        "body B { shape "
        + "union { " * 3000
        + "box (1, 1, 1) cm at (0, 0, 0) m "
        + "} at (0, 0, 0) m " * 2999
        + "} mass 1 kg }",
        "body B { shape box (" + "1, " * 5000 + "1) cm mass 1 kg }",
        "body B { shape box (1e999, 1, 1) cm mass 1e-999 kg }",
        "body B { shape box (1, 1, 1) m mass 99999999999999999999999999 kg "
        "explore e { contacts on faces +x steps 99999999999999999999 } }",
        "x" * 100_000,
        "body B { mass = 1 kg }\n" * 3000,
    ],
    ids=[
        "empty",
        "comment",
        "keyword",
        "open-braces",
        "open-unions",
        "deep-unions",
        "long-vector",
        "overflow",
        "huge-ints",
        "long-name",
        "many-broken",
    ],
)
def test_pathological_inputs_give_only_diagnostics(tmp_path: Path, text: str) -> None:
    _check_text(tmp_path, text)


def test_vkgc_check_on_a_binary_file_says_it_is_not_utf8(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "image.vkg"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe")
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out
    assert "error[E508]" in out and "not UTF-8 text" in out and "save it as UTF-8" in out
    assert "at line 1, column 1" in out and "PNG" not in out  # where, never the bytes


def test_vkgc_check_on_a_directory_says_to_name_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check", str(tmp_path)]) == 1
    out = capsys.readouterr().out
    assert "error[E506]" in out and "is a directory" in out and "*.vkg" in out


def test_each_broken_declaration_gives_one_error_without_cascade(tmp_path: Path) -> None:
    """After a syntax error the parser resumes at the next declaration: one error per broken body, none for good."""
    text = "body A { mass = 1 kg }\nbody B { shape box (1, 1, 1) cm mass 1 kg }\nbody C { mass 1 kg frame }\n"
    diagnostics = _check_text(tmp_path, text)
    assert [(d.code, d.span.line) for d in diagnostics] == [("E101", 1), ("E101", 3)]


def test_syntax_error_recovery_stays_bounded_on_big_files(tmp_path: Path) -> None:
    diagnostics = _check_text(tmp_path, "body B { mass = 1 kg }\n" * 3000)
    assert 1 <= len(diagnostics) <= 20
