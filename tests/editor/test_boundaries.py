"""The editor package is a front-end tool; its command-line arguments all say what they do."""

from __future__ import annotations

import argparse
import ast
from pathlib import Path

import pytest

from vkgl.cli import build_parser

PACKAGE = Path(__file__).resolve().parents[2] / "vkgl" / "editor"
ALLOWED = ("vkgl.editor", "vkgl.lang", "vkgl.errors", "vkgl.resources", "vkgl.atomic")


@pytest.mark.parametrize("path", sorted(PACKAGE.glob("*.py")), ids=lambda p: p.name)
def test_the_editor_package_imports_only_the_front_end(path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    modules = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    modules += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    ours = [m for m in modules if m == "vkgl" or m.startswith("vkgl.")]
    assert all(m.startswith(ALLOWED) for m in ours), ours


@pytest.mark.parametrize("path", sorted(PACKAGE.glob("*.py")), ids=lambda p: p.name)
def test_editor_modules_are_small(path: Path) -> None:
    assert len(path.read_text(encoding="utf-8").splitlines()) < 500


@pytest.mark.parametrize("command", ["lsp", "learn"])
def test_every_argument_of_lsp_and_learn_has_help(command: str) -> None:
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    parser = sub.choices[command]
    for action in parser._actions:
        if action.dest in (
            "help",
            "debug",
        ):  # argparse's own, and --debug (hidden on purpose)
            continue
        assert action.help, f"vkgc {command} {action.option_strings or action.dest} has no help"
