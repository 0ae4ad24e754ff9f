"""Golden tests: the exact output of `vkgc check` for one small bad input per diagnostic code.

Each case is tests/lang/golden/<CODE>_<short_name>.vkg with its expected output
beside it in <same>.expected: every diagnostic as vkgl.lang.diagnostics.diagnostic.render
shows it (docs/language.md, "The language in one example") followed by the summary line. Paths in the
output are relative to the repository root, so the test runs `vkgc check` from there.
Files in tests/lang/golden/lib/ are helpers the cases `use`, not cases.

Some messages print computed numbers (`overlap by 3.0 cm`, `spans x from 1.95 to 2.05 m`), and they are
compared as text on purpose: they are the source's round numbers after a few additions and products
(exactly rounded IEEE arithmetic, the same on every x86-64 CPU) or a contact query between boxes, printed
to 0.1 cm or 0.01 m by Python's own formatting. Each printed value lies in the middle of its rounding
interval, half a last digit (0.5 mm or more) from a boundary: orders of magnitude beyond last-bit differences.

To regenerate the .expected files after an intended change of a message, run

    VKG_UPDATE_GOLDEN=1 .venv/bin/pytest tests/lang/diagnostics/test_golden.py

then review the diff (`git diff tests/lang/golden/`) and regenerate docs/errors.md, which
quotes every output (a test checks it is exactly the generated text):

    python -m vkgl.lang.diagnostics.errors_doc > docs/errors.md
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from vkgl.cli import main
from vkgl.lang.diagnostics.codes import CODES
from vkgl.lang.diagnostics.errors_doc import errors_doc
from vkgl.resources import stdlib_dir

REPO = Path(__file__).resolve().parents[3]
GOLDEN = REPO / "tests" / "lang" / "golden"
ERRORS_DOC = REPO / "docs" / "errors.md"
UPDATE = os.environ.get("VKG_UPDATE_GOLDEN", "") not in ("", "0")

CASES = sorted(GOLDEN.glob("*.vkg"))


def _code_of(case: Path) -> str:
    return case.name.split("_", 1)[0]


def _run_check(case: Path, capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    status = main(["check", str(case.relative_to(REPO))])
    return status, _as_from_the_checkout(capsys.readouterr().out)


def _as_from_the_checkout(out: str) -> str:
    """The output as if the stdlib were the checkout's: a non-editable install (CI) shows the
    installed stdlib's files by their absolute site-packages path, which the golden files cannot know."""
    installed_parent = stdlib_dir().resolve().parent
    if installed_parent == REPO:
        return out
    # Shown absolute, or relative to the current directory when the environment is inside the
    # checkout (the README makes it at `.venv/`).
    forms = [installed_parent.as_posix()]
    if installed_parent.is_relative_to(REPO):
        forms.append(installed_parent.relative_to(REPO).as_posix())
    for form in forms:
        shown = f"{form}/"
        out = out.replace(f"{shown} (the installed", "./ (the installed").replace(shown, "")
    return out


TOO_LARGE = GOLDEN / "lib" / "too_large.vkg"
MANY_TOKENS = GOLDEN / "lib" / "many_tokens.vkg"
HUGE_MESH = GOLDEN / "lib" / "huge_mesh.stl"


@pytest.fixture(autouse=True, scope="module")
def too_large_source() -> None:
    """E507's case uses an 11 MiB file: made sparse here (not stored in git; see .gitignore)."""
    if not TOO_LARGE.is_file() or TOO_LARGE.stat().st_size != 11 * 1024 * 1024:
        with open(TOO_LARGE, "wb") as stream:
            stream.truncate(11 * 1024 * 1024)


@pytest.fixture(autouse=True, scope="module")
def past_the_size_limits() -> None:
    """E510's and E511's cases use files made here (not stored in git; see .gitignore): a module of 20,001
    lines of 10 tokens, and a binary STL whose header says 600,000 triangles (sparse: never read)."""
    lines = "# 20,001 lines of 10 tokens: the 200,001st token starts the last line\n" + "x = (1, 2, 3) m\n" * 20_001
    if not MANY_TOKENS.is_file() or MANY_TOKENS.read_text(encoding="utf-8") != lines:
        MANY_TOKENS.write_text(lines, encoding="utf-8")
    size = 84 + 50 * 600_000
    if not HUGE_MESH.is_file() or HUGE_MESH.stat().st_size != size:
        with open(HUGE_MESH, "wb") as stream:
            stream.write(b"binary STL made by test_golden.py".ljust(80, b" ") + (600_000).to_bytes(4, "little"))
            stream.truncate(size)


@pytest.fixture
def at_repo_root(monkeypatch: pytest.MonkeyPatch) -> None:
    """Paths rendered relative to the repository root; no user VKG_PATH leaking into the output."""
    monkeypatch.chdir(REPO)
    monkeypatch.delenv("VKG_PATH", raising=False)


@pytest.mark.parametrize("case", CASES, ids=[c.stem for c in CASES])
def test_check_output_matches_golden(case: Path, at_repo_root: None, capsys: pytest.CaptureFixture[str]) -> None:
    status, out = _run_check(case, capsys)
    expected_file = case.with_suffix(".expected")
    if UPDATE:
        expected_file.write_text(out, encoding="utf-8")
    assert expected_file.is_file(), f"no {expected_file.name}: run with VKG_UPDATE_GOLDEN=1 to create it"
    assert out == expected_file.read_text(encoding="utf-8")
    code = _code_of(case)
    # The case must really show its own code, and errors (not warnings) must fail the run.
    assert re.search(rf"(error|warning)\[{code}\]", out), f"{case.name} does not produce {code}"
    assert status == (1 if code.startswith("E") else 0)


def test_every_code_has_a_golden_case() -> None:
    covered = {_code_of(c) for c in CASES}
    assert sorted(set(CODES) - covered) == []
    assert sorted(covered - set(CODES)) == [], "a golden case is named after a code that codes.py does not define"


def test_every_code_is_documented_with_an_example() -> None:
    text = ERRORS_DOC.read_text(encoding="utf-8")
    for code in CODES:
        assert re.search(rf"^## {code}\b", text, re.MULTILINE), f"docs/errors.md has no `## {code}` section"
        assert re.search(rf"(error|warning)\[{code}\]: ", text), f"docs/errors.md shows no rendered example of {code}"


def test_golden_inputs_show_one_code_each_where_possible(
    at_repo_root: None, capsys: pytest.CaptureFixture[str]
) -> None:
    """A case that reports other codes too would hide cascades: each case reports only its own code."""
    mixed = []
    for case in CASES:
        _, out = _run_check(case, capsys)
        codes = set(re.findall(r"(?:error|warning)\[(\w+)\]", out))
        if codes != {_code_of(case)}:
            mixed.append(f"{case.name}: {sorted(codes)}")
    assert mixed == []


def test_docs_show_the_golden_outputs_verbatim() -> None:
    """docs/errors.md quotes each golden case's output, so the docs cannot drift from what `vkgc check` prints."""
    text = ERRORS_DOC.read_text(encoding="utf-8")
    stale = [c.name for c in CASES if c.with_suffix(".expected").read_text(encoding="utf-8").rstrip("\n") not in text]
    assert stale == [], "update docs/errors.md with the new output of these cases"


def test_errors_doc_is_the_generated_text() -> None:
    """docs/errors.md is generated from the code registry and the golden cases: regenerate, never edit by hand."""
    assert ERRORS_DOC.read_text(encoding="utf-8") == errors_doc(REPO), (
        "docs/errors.md is stale: run `python -m vkgl.lang.diagnostics.errors_doc > docs/errors.md`"
    )
