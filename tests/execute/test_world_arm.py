"""The arm in the execution world (`vkgl.execute.world_arm`): a held tool stays in the hand whatever it is asked."""

from __future__ import annotations

import json

import numpy as np
from conftest import EXAMPLES, REPO

import vkgl
from vkgl.execute.replay import Replay
from vkgl.formats.plan import from_json


def test_a_held_tool_stays_in_the_hand_when_the_joints_are_asked_past_their_velocity_limits() -> None:
    # DART holds a velocity-driven joint to its URDF limit. The tool used to be driven to where the commanded joints
    # would put the hand: asked past the limit (gen5_007's lift near a singularity), the hand lagged, the tool did
    # not, and the two parted (5.4 cm) until the tool was snapped back, throwing what it had just pulled
    program = vkgl.compile(EXAMPLES / "tasks" / "c_hook_pull.vkg")
    plan = from_json(json.loads((REPO / "tests" / "formats" / "golden" / "c_hook_pull.json").read_text()))
    assert plan.steps[0].affordance == "Hook.wield"
    replay = Replay(program, program.scenes[program.task("c_hook_pull").scene.name], plan.robot, record=False)
    replay.run_step(1, plan.steps[0])  # grasp the hook
    sim = replay.sim
    replay.moves.straight("lift", np.array([0.0, 0.0, 0.1]), 0.03, "test")  # clear of the table
    q = sim.arm.q
    wrist = q.copy()
    wrist[6] += 0.6  # joint 7 by 0.6 rad in 40 ms: 15 rad/s, its limit is 2.61 rad/s
    sim.arm.follow_joints(np.array([q, wrist]), np.array([0.0, 0.04]), lambda n, s: sim.advance(n))
    assert abs(sim.arm.q[6] - q[6]) < 0.2  # the joint was held to its limit
    held = sim.arm.held
    assert held is not None
    expected = sim.arm.effector_pose() @ np.linalg.inv(held.grasp)
    real = held.body_node.getWorldTransform().matrix()
    assert np.linalg.norm(real[:3, 3] - expected[:3, 3]) < 1e-3, "the hook left the hand"
