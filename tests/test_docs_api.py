"""Every Python example of docs/api.md runs, in order, in one namespace, from the repository root."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOC = REPO / "docs" / "api.md"


def _blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", DOC.read_text(encoding="utf-8"), flags=re.S | re.M)


def test_the_page_has_examples() -> None:
    assert len(_blocks()) >= 8


def test_every_example_runs(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(REPO)
    namespace: dict[str, object] = {"__name__": "docs_api"}
    for number, block in enumerate(_blocks(), start=1):
        try:
            exec(compile(block, f"docs/api.md block {number}", "exec"), namespace)
        except Exception as error:  # name the block, keep the cause
            raise AssertionError(f"docs/api.md example {number} failed:\n{block}") from error
    out = capsys.readouterr().out
    assert "solved 2" in out
    assert "reached" in out
    assert "error[E202]" in out
