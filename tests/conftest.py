"""Shared fixtures: paths of the repository's examples and stdlib."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
EXAMPLES = REPO / "examples"
STDLIB = REPO / "stdlib"
DESIGN = REPO.parent / "shared" / "design"


@pytest.fixture
def repo() -> Path:
    """The repository root."""
    return REPO


def vkg_files() -> list[Path]:
    """Every .vkg file of examples/ and stdlib/, sorted."""
    return sorted([*EXAMPLES.rglob("*.vkg"), *STDLIB.rglob("*.vkg")])


def example_tasks() -> list[Path]:
    """The task files of examples/tasks/, sorted."""
    return sorted((EXAMPLES / "tasks").glob("*.vkg"))
