"""Every Python example of docs/api.md runs, in order, in one namespace, from the repository root."""

from __future__ import annotations

import inspect
import re
from pathlib import Path
from typing import Any

import pytest

from vkgl.formats.trials import Trials
from vkgl.lang.ir.nodes import Body

REPO = Path(__file__).resolve().parents[1]
DOC = REPO / "docs" / "api.md"


def _blocks() -> list[str]:
    return re.findall(r"^```python\n(.*?)^```", DOC.read_text(encoding="utf-8"), flags=re.S | re.M)


def test_the_page_has_examples() -> None:
    assert len(_blocks()) >= 8


def _explored_once(monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """`vkgl.explore` (and `learn`'s call of it) runs a body's exploration once per set of arguments and returns
    that dataset again when asked again: the page learns the Stick and then explores it again with the same
    arguments to show the two halves of `learn`, and the second, identical exploration cost 2 to 5 CPU-seconds
    of physics. Returns the bodies it explored, one entry per exploration run."""
    import vkgl
    import vkgl.api

    explore = vkgl.api.explore
    signature = inspect.signature(explore)
    made: dict[str, Trials] = {}
    explored: list[str] = []

    def explore_once(body: Body, **arguments: Any) -> Trials:
        called = signature.bind(body, **arguments)
        called.apply_defaults()
        key = repr(sorted(called.arguments.items()))
        if key not in made:
            explored.append(body.name)
            made[key] = explore(body, **arguments)
        return made[key]

    monkeypatch.setattr(vkgl.api, "explore", explore_once)
    monkeypatch.setattr(vkgl, "explore", explore_once)
    return explored


def test_every_example_runs(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(REPO)
    explored = _explored_once(monkeypatch)
    namespace: dict[str, object] = {"__name__": "docs_api"}
    for number, block in enumerate(_blocks(), start=1):
        try:
            exec(compile(block, f"docs/api.md block {number}", "exec"), namespace)
        except Exception as error:  # name the block, keep the cause
            raise AssertionError(f"docs/api.md example {number} failed:\n{block}") from error
    out = capsys.readouterr().out
    assert "solved 2" in out
    assert "reached" in out
    assert "timeout" not in out  # no example waits out a search's timeout (30 s of wall time, as CPU as it gets)
    assert "error[E202]" in out
    assert explored == ["Stick"]  # explored once, by `learn`; `vkgl.explore` of the same body was given its trials
