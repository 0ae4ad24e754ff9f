"""What the robustness tests share: a time limit per case and the shape every result must have.

Used by tests/lang/test_robustness.py (mutants) and tests/lang/syntax/test_fuzz_targeted.py (targeted cases).
"""

from __future__ import annotations

import signal
import unicodedata
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from vkgl.lang.compiler import check_files
from vkgl.lang.diagnostics.codes import CODES
from vkgl.lang.diagnostics.diagnostic import Diagnostic, render, source_lines

HANG_SECONDS = 10
"""A single check that runs longer than this counts as a hang."""

# Codes about a whole file (given on the command line): their position is the file itself.
FILE_CODES = {"E505", "E506", "E507", "E509"}  # E509: a command-line file linking to a non-module


@contextmanager
def no_hang(seconds: int = HANG_SECONDS) -> Iterator[None]:
    """Fail instead of hanging: SIGALRM interrupts a check that runs away."""
    if not hasattr(signal, "SIGALRM"):  # Windows: no alarm, the tests then only find exceptions
        yield
        return

    def interrupt(signum: int, frame: object) -> None:
        raise TimeoutError(f"check took longer than {seconds} s")

    previous = signal.signal(signal.SIGALRM, interrupt)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def assert_well_formed(diagnostics: list[Diagnostic], sources: dict[str, str]) -> None:
    """Sorted registered diagnostics, each positioned (a span, or the file for file-level codes), that render
    on one line each with no control character reaching the terminal."""
    assert isinstance(diagnostics, list)
    assert all(isinstance(d, Diagnostic) for d in diagnostics)
    assert diagnostics == sorted(diagnostics, key=Diagnostic.sort_key)
    for diag in diagnostics:
        assert diag.code in CODES, diag
        assert diag.message and "\n" not in diag.message, diag
        if diag.span is None:
            assert diag.code in FILE_CODES and diag.file, f"no position: {diag}"
        source = sources.get(diag.span.file) if diag.span is not None else None
        if diag.span is not None and source is not None:
            assert 1 <= diag.span.line <= len(source_lines(source)), f"line out of range: {diag}"
            assert diag.span.col >= 1, diag
        shown = render(diag, source)
        assert not any(unicodedata.category(c) == "Cc" and c != "\n" for c in shown), repr(shown)


def check_data(folder: Path, data: str | bytes, name: str = "mutant.vkg") -> list[Diagnostic]:
    """`vkgc check` in-process on `data` written to `folder/name`, within the time limit; the diagnostics."""
    path = folder / name
    if isinstance(data, bytes):
        path.write_bytes(data)
    else:
        path.write_text(data, encoding="utf-8")
    return check_path(path)


def check_path(path: Path | str) -> list[Diagnostic]:
    """`vkgc check` in-process on `path`, within the time limit; the diagnostics, checked for shape."""
    with no_hang():
        diagnostics, sources = check_files([str(path)])
    assert_well_formed(diagnostics, sources)
    return diagnostics
