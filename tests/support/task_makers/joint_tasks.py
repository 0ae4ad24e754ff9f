"""Shared by the execution tests of the drawer and door tasks (examples/tasks/g, h, i): a program whose
scene starts a jointed body elsewhere than the plan expects."""

from __future__ import annotations

from vkgl.lang.ir.geometry import joint_pose, scene_body_anchor
from vkgl.lang.ir.program import Program


def started_open(program: Program, task: str, body: str, value: float) -> Program:
    """`program` with scene body `body` of `task`'s scene starting with its joint at `value` (m or rad)."""
    scene = program.scenes[program.task(task).scene.name]
    placed = next(b for b in scene.bodies if b.name == body)
    kind = program.bodies[placed.type.name]
    assert kind.joint is not None
    pose = joint_pose(kind.joint, scene_body_anchor(scene, placed, kind), value)
    return program.with_start_poses(task, {body: pose})
