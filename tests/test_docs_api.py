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


def _explored_once(monkeypatch: pytest.MonkeyPatch, given: Trials) -> list[str]:
    """`vkgl.explore` (and `learn`'s call of it) runs a body's exploration once per set of arguments and returns
    that dataset again when asked again: the page learns the Stick and then explores it again with the same
    arguments to show the two halves of `learn`, and each of these explorations costs 2 to 3 CPU-seconds of
    physics. `given`: the stdlib Stick's exploration with the page's arguments (`jobs=2`), made once per run for
    this test and tests/sim/test_explore.py (`stick_trials`, tests/conftest.py). Returns the bodies explored here,
    one entry per exploration run."""
    import vkgl
    import vkgl.api

    explore = vkgl.api.explore
    signature = inspect.signature(explore)

    def key(body: Body, **arguments: Any) -> str:
        called = signature.bind(body, **arguments)
        called.apply_defaults()
        return repr(sorted(called.arguments.items()))

    stick = vkgl.compile(REPO / "stdlib" / "bodies" / "stick.vkg").body()
    made: dict[str, Trials] = {key(stick, jobs=2): given}
    explored: list[str] = []

    def explore_once(body: Body, **arguments: Any) -> Trials:
        called = key(body, **arguments)
        if called not in made:
            explored.append(body.name)
            made[called] = explore(body, **arguments)
        return made[called]

    monkeypatch.setattr(vkgl.api, "explore", explore_once)
    monkeypatch.setattr(vkgl, "explore", explore_once)
    return explored


def test_every_example_runs(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str], stick_trials: Trials
) -> None:
    monkeypatch.chdir(REPO)
    explored = _explored_once(monkeypatch, stick_trials)
    namespace: dict[str, object] = {"__name__": "docs_api"}
    for number, block in enumerate(_blocks(), start=1):
        try:
            exec(compile(block, f"docs/api.md block {number}", "exec"), namespace)
        except Exception as error:  # name the block, keep the cause
            raise AssertionError(f"docs/api.md example {number} failed:\n{block}") from error
    out = capsys.readouterr().out
    assert "solved 2" in out
    assert "reached" in out
    assert "timeout" not in out  # no example waits out a search timeout (30 s of wall time, as much CPU as it gets)
    assert "error[E202]" in out
    assert explored == []  # the page's learn and explore of the Stick were given `stick_trials` (its arguments)
