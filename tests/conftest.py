"""Shared fixtures: paths of the repository's examples and stdlib."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest

# the arm's reach kept between processes (vkgl.formats.reach_cache): in a folder of this test run, never the
# user's; subprocesses the tests start inherit it
os.environ.setdefault("VKGL_CACHE_DIR", tempfile.mkdtemp(prefix="vkgl-test-cache-"))

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
