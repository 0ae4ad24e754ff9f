"""Relative goals: where `B moved by V [in F] [turned by Q]` and `B turned by Q` put the body.

A relative goal is measured from where its body starts in the task's scene
(`geometry.scene_body_pose`): `moved by (dx, dy) cm` adds the displacement to
the start position in the world frame, `moved by V in F` turns `V` by the
rotation of body `F` at its start (`in carton` for the body's own frame), and
`turned by Q` adds `Q` to the start heading. `place_relative_goals` fills each
such goal's `position` and `yaw` with the result, so that the scene checks
(E423-E425), the planner and the executor see an ordinary pose goal; the
written form stays in the goal (`moved_by`, `moved_in`, `turned_by`) for the
printer and the editor. A displacement of two components leaves the height
free, as `B at (x, y)` does.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from vkgl.lang.checks.context import CheckContext, did_you_mean
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.program import Program

if TYPE_CHECKING:  # numpy (and the IR's geometry) only for tasks with relative goals: `vkgc check` stays light
    import numpy as np


def place_relative_goals(program: Program, ctx: CheckContext) -> None:
    """Fill the `position` and `yaw` of every relative goal of `program`'s tasks (E306 for an unknown `in F`).

    Goals on bodies or scenes that other checks report as unknown, or with
    values that are not finite numbers, are left as they are.
    """
    for name, task in list(program.tasks.items()):
        scene = program.scenes.get(task.scene.name)
        if scene is None or not any(g.relative for g in task.goals):
            continue
        goals = [_placed(goal, scene, program, ctx) if goal.relative else goal for goal in task.goals]
        program.tasks[name] = task.model_copy(update={"goals": goals})


def start_pose(scene: ir.Scene, name: str, program: Program) -> np.ndarray | None:
    """The world pose where scene body `name` starts, or None when it or its type is unknown or not finite."""
    scene_body = next((b for b in scene.bodies if b.name == name), None)
    body = program.bodies.get(scene_body.type.name) if scene_body is not None else None
    if scene_body is None or body is None:
        return None
    import numpy as np  # the pose the planner starts from: computed as `vkgl.lang.ir.geometry` computes it

    from vkgl.lang.ir.geometry import scene_body_pose

    try:
        with np.errstate(all="ignore"):
            pose = scene_body_pose(scene, scene_body, body)
    except (ValueError, IndexError, RuntimeError):  # a shape or pose that other checks report
        return None
    return pose if np.all(np.isfinite(pose)) else None


def _placed(goal: ir.Goal, scene: ir.Scene, program: Program, ctx: CheckContext) -> ir.Goal:
    frame_name = goal.moved_in.name if goal.moved_in is not None else None
    if goal.moved_in is not None and frame_name not in {b.name for b in scene.bodies}:
        ctx.error(
            codes.GOAL_NOT_IN_SCENE,
            f"`moved by ... in {frame_name}`: `{frame_name}` is not a body of scene `{scene.name}`",
            goal.moved_in.span,
            did_you_mean(frame_name or "", [b.name for b in scene.bodies])
            or "name a body of the scene, or leave out `in ...` for the world frame",
        )
        return goal
    import numpy as np

    start = start_pose(scene, goal.body.name, program)
    frame = start_pose(scene, frame_name, program) if frame_name is not None else np.eye(4)
    if start is None or frame is None:
        return goal
    update: dict[str, object] = {}
    if goal.moved_by is not None:
        offset = np.asarray(goal.moved_by.values, dtype=float)
        if not np.all(np.isfinite(offset)):
            return goal
        moved = frame[:3, :3] @ np.r_[offset, np.zeros(3 - len(offset))]  # a 2-vector lies in the frame's x-y plane
        target = start[: len(offset), 3] + moved[: len(offset)]
        # model_construct: floats already; validating would build pydantic's validators (and scan for plugins)
        update["position"] = ir.Vector.model_construct(
            values=tuple(float(v) for v in target), unit="m", span=goal.moved_by.span
        )
    if goal.turned_by is not None:
        if not math.isfinite(goal.turned_by.value):
            return goal
        heading = math.atan2(start[1, 0], start[0, 0]) + goal.turned_by.value
        yaw = math.remainder(heading, 2 * math.pi)
        update["yaw"] = ir.Quantity.model_construct(value=yaw, unit="rad", span=goal.turned_by.span)
    return goal.model_copy(update=update)


__all__ = ["place_relative_goals", "start_pose"]
