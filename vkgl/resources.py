"""Where the shipped data lives: the grammar and the standard library.

In a wheel they are inside the package (`vkgl/grammar`, `vkgl/stdlib`); in a
source checkout (editable install, tests) they are at the repository root.
"""

from __future__ import annotations

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def _find(name: str) -> Path:
    inside = _PACKAGE / name
    if inside.is_dir():
        return inside
    return _PACKAGE.parent / name


def grammar_path() -> Path:
    """The path of `vkg.lark`."""
    return _find("grammar") / "vkg.lark"


def stdlib_dir() -> Path:
    """The directory `stdlib/` (its parent is an import root)."""
    return _find("stdlib")
