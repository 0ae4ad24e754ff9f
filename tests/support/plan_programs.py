"""Shared fixture of the planner tests: the example tasks, compiled once per session.

(A module, not a conftest.py: the project's tests import `conftest` by name.)
"""

from __future__ import annotations

from pathlib import Path

import pytest

from vkgl.lang.compiler import compile_file

EXAMPLE_TASKS = Path(__file__).resolve().parents[2] / "examples" / "tasks"
_CACHE: dict[str, object] = {}


@pytest.fixture(scope="session")
def compiled():
    """`compiled(name)`: the Program of examples/tasks/<name>.vkg (compiled once)."""

    def get(name: str):
        if name not in _CACHE:
            _CACHE[name] = compile_file(str(EXAMPLE_TASKS / f"{name}.vkg"))
        return _CACHE[name]

    return get
