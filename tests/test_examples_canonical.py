"""Examples and the stdlib are written in canonical form: `vkgc fmt --check` has nothing to change."""

from __future__ import annotations

from pathlib import Path

from vkgl.cli import main

REPO = Path(__file__).resolve().parents[1]


def test_examples_and_stdlib_are_canonical(capsys) -> None:
    files = sorted(str(p) for folder in ("examples", "stdlib") for p in (REPO / folder).rglob("*.vkg"))
    assert len(files) >= 15
    status = main(["fmt", "--check", *files])
    assert status == 0, capsys.readouterr().out
