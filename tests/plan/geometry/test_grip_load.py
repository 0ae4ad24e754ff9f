"""The planner never pushes harder with a held tool than the grip carries (`vkgl.plan.geometry.grip_load`)."""

from __future__ import annotations

from pathlib import Path

import vkgl
import vkgl.plan.geometry.grip_load as grip_load

EXAMPLES = Path(__file__).resolve().parents[3] / "examples" / "tasks"


def test_the_stick_pushes_the_block_within_the_grip():
    plan = vkgl.solve(vkgl.compile(EXAMPLES / "b_stick_push.vkg"))
    assert plan.status == "solved"
    assert any(step["effector"] == "stick.tip" for step in plan.to_json()["steps"])


def test_a_block_too_heavy_for_the_grip_is_not_pushed_with_the_stick(monkeypatch):
    """A body that resists with 60 N (a 12 kg block): the grip on the stick (2 x 70 N at mu 0.5: 70 N in the
    pads' plane) would carry it at 86 %, and with the push counted twice (what the estimate leaves out) at more
    than all of it: no plan, and the reason says so with the numbers."""
    monkeypatch.setattr(grip_load, "resisting_force", lambda mass, friction: 60.0)
    plan = vkgl.solve(vkgl.compile(EXAMPLES / "b_stick_push.vkg"))
    assert plan.status == "infeasible"
    assert "would push harder with a held tool than its grip carries" in plan.reason
    assert "(60.0 N: its weight times its friction)" in plan.reason and "the push counted twice" in plan.reason
