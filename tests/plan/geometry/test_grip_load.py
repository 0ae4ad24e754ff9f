"""The planner never pushes harder with a held tool than the grip carries (`vkgl.plan.geometry.grip_load`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from task_makers.generated_tasks import fixture_library, task_spec, write_task

import vkgl
import vkgl.plan.geometry.grip_load as grip_load
from vkgl.plan.geometry.bodies import GeometryCheck
from vkgl.plan.problem.problem import build_problem
from vkgl.plan.problem.rejection import Kind

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
    first, change = plan.reason.splitlines()[:2]  # the grip decides: said first, then what to change
    assert first.startswith("no sequence of at most 6 graphs reaches the goal: stick would slip in the hand: ")
    assert "stick.tip pushing block (60.0 N: its weight times its friction" in first and "counted twice" in first
    assert "in the pads' plane, where they hold 70.0 N" in first
    assert change.startswith("  for the grip to hold stick: a lighter or more slippery block")
    assert f"6 {Kind.GRIP.words}" in plan.reason


def test_the_fingers_closed_on_a_held_tool_are_checked_where_the_executor_closes_them(tmp_path: Path) -> None:
    """gen2_038 of the physical bench: the Hook held by its cross-piece (`grasp_top_x_p1`, 2 cm wide), rolled
    20 deg over a 6 cm slab to pull it by its far face. With the fingers checked closed, the hand was clear of
    the slab; closed onto the cross-piece they stand 1.05 cm open, and the inner one is 6.5 mm inside the slab's
    top edge: in DART it caught the slab before the hook did and turned it 5 deg off its goal."""
    spec = task_spec(2, 38)
    program = vkgl.compile(write_task(spec, tmp_path / spec.name, fixture_library()))
    problem = build_problem(program, program.task(spec.name))
    q = np.array([0.618871, 1.242566, -0.884291, -1.232755, 0.573860, 2.074865, 2.373948])  # the plan's pull start
    in_hand = np.linalg.inv(problem.action("hook", "grasp_top_x_p1"))
    hook = problem.arm.fk(q) @ in_hand
    rolled = Rotation.from_euler("ZX", [-10.0, -20.0], degrees=True).as_matrix()
    assert np.allclose(hook[:3, 3], (0.5359, -0.0357, 0.0811), atol=2e-3) and np.allclose(
        hook[:3, :3], rolled, atol=2e-3
    )
    poses = {name: body.rest for name, body in problem.bodies.items()}
    poses["hook"] = hook
    poses["clutter1"] = poses["clutter1"].copy()
    poses["clutter1"][:2, 3] = (0.3476, 0.3325)  # where the plan's first step pushed it
    held = grip_load.held(problem, "hook", "grasp_top_x_p1", in_hand, frozenset({"target"}))
    assert held.opening == pytest.approx(0.0105)
    arm = GeometryCheck(problem).arm_collision
    assert arm.overlap(q, poses, ignore={"hook"}, held=replace(held, opening=0.0)) == []  # the fingers closed
    hits = arm.overlap(q, poses, ignore={"hook"}, held=held)
    assert {c.body_b for c in hits} == {"target"} and {c.body_a for c in hits} <= set(arm.finger_links)
    assert max(c.depth for c in hits) == pytest.approx(0.0065, abs=0.002)


_WIDE_BAR = """
use stdlib.robots.panda
use stdlib.bodies.block
use stdlib.affordances.block

body WideBar {
    shape box (40, 12, 2) cm
    mass 0.1 kg
    frame tip = (20, 0, 0) cm
}

affordances WideBar {
    affordance wield {
        action fixed at (-15, 0, 0) cm yaw 0deg
        motion free
    }
}

correspondences { WideBar.tip ~ fingertip }

scene bench {
    table size (1.6, 1.2) m at (0.5, 0, 0) m
    robot arm : Panda at (0, 0, 0) m
    block : Block on table at (0.7, 0) m yaw 0deg
    bar : WideBar on table at (0.3, -0.4) m yaw 0deg
}

task push {
    scene bench
    goal block at (0.95, 0) m yaw 0deg within 1 cm, 3deg
    search { max_depth 3 }
}
"""


def test_a_tool_wider_than_the_hand_opens_is_never_held(tmp_path: Path) -> None:
    """A 12 cm bar held by a `fixed` action across its width: the fingers open 8 cm (it was planned, in the hand)."""
    program = vkgl.compile_source(_WIDE_BAR, str(tmp_path / "wide.vkg"), base_dir=tmp_path)
    problem = build_problem(program, program.task("push"))
    rejection = grip_load.width_rejection(problem, "bar", "wield")
    assert rejection is not None and rejection.kind == Kind.GRIP
    assert rejection.why.startswith("bar is 12.0 cm across where `wield` holds it")
    assert "the hand's fingers open 8 cm at most" in rejection.why
    assert rejection.advice.startswith("for the hand to hold bar: hold it where it is at most 8 cm across")
    stick = vkgl.compile(EXAMPLES / "b_stick_push.vkg")
    assert grip_load.width_rejection(build_problem(stick, stick.task()), "stick", "wield") is None  # 2 cm


def test_the_hand_opens_as_far_as_its_urdf_fingers_travel(tmp_path: Path) -> None:
    """The width check reads the arm's own finger joints (the Panda's travel 4 cm each: 8 cm); an arm without
    the Panda's finger joints falls back on the language's `HAND_OPENING`, by which E461 judged its grasps."""
    from vkgl.lang.ir.grasps import HAND_OPENING
    from vkgl.sim.grasp.run import panda_urdf

    assert abs(grip_load.hand_opening(panda_urdf()) - 0.08) < 1e-6
    bare = tmp_path / "bare.urdf"
    bare.write_text('<robot name="bare"><link name="base"/></robot>')
    assert grip_load.hand_opening(str(bare)) == HAND_OPENING


def test_a_body_on_a_joint_resists_with_its_joints_friction_and_damping_at_the_push_speed() -> None:
    """The stdlib Drawer's slide (1.5 N, 4 N s/m) at the executor's 5 cm/s: 1.7 N wherever it is pushed; the
    Door's hinge (0.2 N m, 0.3 N m s/rad) over the contact's distance from the hinge's line."""
    from vkgl.execute.effector_path import PUSH_SPEED

    assert grip_load.JOINT_PUSH_SPEED == PUSH_SPEED
    drawer = vkgl.compile(EXAMPLES / "i_hook_drawer.vkg")
    problem = build_problem(drawer, drawer.task())
    assert grip_load.resistance(problem, "drawer", problem.bodies["drawer"].rest[:3, 3]) == pytest.approx(1.7)
    door = vkgl.compile(EXAMPLES / "h_close_door.vkg")
    problem = build_problem(door, door.task())
    hinge = (problem.bodies["door"].rest @ np.array([0.0, -0.2, 0.0, 1.0]))[:3]
    for lever in (0.4, 0.1):
        at = hinge + np.array([lever, 0.0, 0.05])
        expected = (0.2 + 0.3 * PUSH_SPEED / lever) / lever
        assert grip_load.resistance(problem, "door", at) == pytest.approx(expected)


def test_a_slide_that_resists_more_than_the_grip_carries_is_not_pulled_with_the_hook(monkeypatch):
    """The drawer's slide at 30 m/s: its damping resists with 121.5 N, beyond the Hook's grip; the pull that
    opens it in example i is refused for the grip, and the reason says how the slide resists."""
    monkeypatch.setattr(grip_load, "JOINT_PUSH_SPEED", 30.0)
    plan = vkgl.solve(vkgl.compile(EXAMPLES / "i_hook_drawer.vkg"), max_depth=3)
    assert plan.status == "infeasible"
    assert "hook would slip in the hand: hook.tip pushing drawer (121.5 N: its slide's friction 1.5 N and damping " in (
        plan.reason
    )
    assert "a drawer whose joint resists less" in plan.reason
