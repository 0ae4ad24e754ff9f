"""The grip model's load of a push with a held tool (`vkgl.robot.grip.push_load`): statics, checked by hand."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vkgl.robot.grip import DEFAULT_FRICTION, GRAVITY, PAD_FRICTION, Grip, push_load, resisting_force
from vkgl.sim.fingertip import FINGERTIP_FRICTION
from vkgl.sim.world import DEFAULT_FRICTION as SIM_DEFAULT_FRICTION


def test_the_model_uses_the_simulators_frictions():
    assert PAD_FRICTION == FINGERTIP_FRICTION and DEFAULT_FRICTION == SIM_DEFAULT_FRICTION


def test_a_push_at_the_tip_of_a_stick_held_at_its_handle():
    """A top grasp (effector z down, fingers along world y): a 2 N push back along the stick 30 cm ahead of the
    hand, at the hand's height, is a force in the pads' plane and no twist about the pads' normal; 1 cm lower,
    0.02 N m about it. The weight (0.1 kg, 10 cm ahead) twists the grip by 0.098 N m."""
    effector = np.diag([1.0, -1.0, -1.0, 1.0])  # x forward, y left -> -y, z down
    effector[:3, 3] = [0.4, 0.0, 0.1]
    force, torque = push_load(effector, [0.7, 0.0, 0.1], [1.0, 0.0, 0.0], 2.0, [0.4, 0.0, 0.1], 0.0)
    assert force == pytest.approx([-2.0, 0.0, 0.0]) and torque == pytest.approx([0.0, 0.0, 0.0])
    _, torque = push_load(effector, [0.7, 0.0, 0.09], [1.0, 0.0, 0.0], 2.0, [0.4, 0.0, 0.1], 0.0)
    assert abs(torque[1]) == pytest.approx(0.02)
    force, torque = push_load(effector, [0.7, 0.0, 0.1], [1.0, 0.0, 0.0], 0.0, [0.5, 0.0, 0.1], 0.1)
    assert force == pytest.approx([0.0, 0.0, 0.1 * GRAVITY])  # down is the effector's +z
    assert abs(torque[1]) == pytest.approx(0.1 * GRAVITY * 0.1)


@settings(max_examples=50, deadline=None)
@given(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(0.0, 20.0), st.floats(0.0, np.pi))
def test_the_load_does_not_depend_on_the_direction_s_length_and_turns_with_the_hand(x, y, force, yaw):
    direction = np.array([x, y, 0.0]) + np.array([1e-3, 0.0, 0.0])
    c, s = np.cos(yaw), np.sin(yaw)
    effector = np.eye(4)
    effector[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    a = push_load(effector, [0.3, 0.1, 0.0], direction, force, [0.1, 0.0, 0.0], 0.2)
    b = push_load(effector, [0.3, 0.1, 0.0], 3.0 * direction, force, [0.1, 0.0, 0.0], 0.2)
    assert np.allclose(a[0], b[0]) and np.allclose(a[1], b[1])
    world_force = effector[:3, :3] @ a[0]
    assert np.linalg.norm(world_force[:2]) == pytest.approx(force, abs=1e-9)


def test_a_body_resists_with_its_weight_times_its_friction():
    assert resisting_force(1.0, 0.5) == pytest.approx(0.5 * GRAVITY)
    assert resisting_force(2.0, None) == pytest.approx(2.0 * DEFAULT_FRICTION * GRAVITY)
    assert Grip(20.0, 0.5).usage(np.array([20.0, 0.0, 0.0]), np.zeros(3)) == pytest.approx(1.0)


def test_the_fingers_stand_open_around_a_tool_by_its_stated_width_else_its_measured_one():
    """As the executor closes them: onto the tool's faces, `TOUCH_GAP` short. The Hook's grasp states 2 cm; its
    `wield` (a fixed action) states none, and its shaft measures 2 cm across where the hand holds it."""
    import vkgl
    from vkgl.lang.ir.geometry import body_mesh
    from vkgl.robot.grip import TOUCH_GAP, holding_opening

    program = vkgl.compile_source("use stdlib.affordances.hook\n")
    hook = program.bodies["Hook"]
    by_name = {a.name: a for a in program.affordances["Hook"]}
    mesh = body_mesh(hook)
    grasp = by_name["grasp_top_x_p1"].action
    assert holding_opening(grasp, mesh, np.eye(4)) == pytest.approx(0.01 + TOUCH_GAP)
    wield = by_name["wield"].action
    at_handle = np.eye(4)
    at_handle[:3, 3] = (-0.15, 0.0, 0.0)
    assert holding_opening(wield, mesh, at_handle) == pytest.approx(0.01 + TOUCH_GAP)
    far_off = np.eye(4)
    far_off[:3, 3] = (0.0, 0.0, 1.0)  # the pads' plane misses the tool: nothing between them
    assert holding_opening(wield, mesh, far_off) == pytest.approx(TOUCH_GAP)
