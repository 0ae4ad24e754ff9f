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

SLOWEST_FIRST = [
    "tests/execute/test_closed_loop.py",
    "tests/execute/test_tall_bodies.py",
    "tests/execute/test_hook_drawer.py",
    "tests/infer/test_learn.py",
    "tests/test_tooling.py",
    "tests/test_docs_api.py",
    "tests/lang/test_robustness.py",
    "tests/sim/test_ray_runner.py",
    "tests/sim/test_furniture.py",
    "tests/plan/test_geometry_check.py",
    "tests/execute/test_execute_cli.py",
    "tests/lang/test_printer.py",
    "tests/execute/test_drawer_and_door.py",
    "tests/sim/test_interrupt.py",
    "tests/execute/test_contact_chain.py",
    "tests/execute/test_generated_execution.py",
    "tests/sim/test_explore.py",
    "tests/execute/test_disturbed.py",
    "tests/execute/test_animate.py",
    "tests/execute/test_long_stick.py",
    "tests/plan/test_picture.py",
    "tests/cli/test_execution_progress.py",
    "tests/execute/test_resolving.py",
    "tests/test_docs_samples.py",
]
"""The test files that take longest (all their tests together, measured with `--durations=0`), slowest first.

They run first, in this order, and the many quick files after them, as collected: xdist hands each worker a
whole file at a time (`--dist loadfile`, `--no-loadscope-reorder` in pyproject.toml), so a long file started
last would keep one worker busy while the other has nothing left to do. Its own default order (files with more
tests first) put the one-test physics files and mypy at the very end.
"""


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Run the files of `SLOWEST_FIRST` first, in its order; the rest keep the order they were collected in."""
    rank = {path: k for k, path in enumerate(SLOWEST_FIRST)}
    missing = [path for path in SLOWEST_FIRST if not (REPO / path).is_file()]
    assert not missing, f"SLOWEST_FIRST names files that are not there: {missing}"
    items.sort(key=lambda item: rank.get(item.nodeid.split("::")[0], len(rank)))  # stable: in-file order kept


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
