"""Bodies placed relative to another: `drawer : Drawer in cabinet` and `drawer : Drawer at cabinet.slot`.

`in B` places the body at the frame `slot` of B's type, `at B.F` at its frame
`F`, both where B starts in the scene (`geometry.scene_body_pose`; B may itself
be placed relative to another). `place_relative_bodies` fills each such
placement's `pose` with the world pose, so that every later check (E420-E425)
and every back end sees an ordinary `at POSE` placement; the written form
stays in the placement (`relative_to`, `inside`) for the printer and the editor.
A name that is no body of the scene is E301, a frame its type does not
declare E303, and bodies placed in one another in a cycle E303 as well
(no frame can be found for them).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from vkgl.lang.checks.context import CheckContext, did_you_mean
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.program import Program

if TYPE_CHECKING:  # numpy (and the IR's geometry) only for scenes with relative placements: `vkgc check` stays light
    import numpy as np


def place_relative_bodies(program: Program, ctx: CheckContext) -> None:
    """Fill the `pose` of every scene body placed `in B` or `at B.F` (E301, E303 for what cannot be placed)."""
    for name, scene in list(program.scenes.items()):
        if any(b.placement.relative_to is not None for b in scene.bodies):
            program.scenes[name] = _placed_scene(scene, program, ctx)


def _placed_scene(scene: ir.Scene, program: Program, ctx: CheckContext) -> ir.Scene:
    # The poses placed here flow into plans: they are computed with numpy, as `vkgl.lang.ir.geometry` computes
    # where a body starts (the planner's own poses), imported only for a scene that places a body so.
    import numpy as np

    bodies = {b.name: b for b in scene.bodies}
    waiting = [b.name for b in scene.bodies if b.placement.relative_to is not None]
    while waiting:
        progress = False
        for name in list(waiting):
            ref = bodies[name].placement.relative_to
            assert ref is not None
            if ref.body in waiting and ref.body != name:
                continue  # its host is not placed yet (a body placed in itself is reported below)
            waiting.remove(name)
            progress = True
            pose = _frame_pose(bodies[name], ref, bodies, scene, program, ctx)
            # a body that cannot be placed gets no position (NaN): the scene checks then skip it
            placed = _pose_node(pose if pose is not None else np.full((4, 4), math.nan), ref.span)
            placement = bodies[name].placement.model_copy(update={"pose": placed})
            bodies[name] = bodies[name].model_copy(update={"placement": placement})
        if not progress:  # the rest are placed in one another, or in a body that is
            for name in waiting:
                ref = bodies[name].placement.relative_to
                assert ref is not None
                cycle = _cycle(name, bodies)
                why = (
                    f"it is placed in a cycle ({' in '.join(f'`{n}`' for n in cycle)})"
                    if cycle
                    else f"`{ref.body}` cannot be placed itself"
                )
                ctx.error(
                    codes.UNKNOWN_FRAME,
                    f"`{name}` cannot be placed at `{ref.body}.{ref.frame}`: {why}",
                    ref.span,
                    "place one of them on the table or at a pose" if cycle else "",
                )
                nowhere = _pose_node(np.full((4, 4), math.nan), ref.span)  # the scene checks skip it
                bodies[name] = bodies[name].model_copy(
                    update={"placement": bodies[name].placement.model_copy(update={"pose": nowhere})}
                )
            break
    return scene.model_copy(update={"bodies": [bodies[b.name] for b in scene.bodies]})


def _cycle(name: str, bodies: dict[str, ir.SceneBody]) -> list[str]:
    """The cycle of hosts that leads from `name` back to it (`a`, `b`, `a`), or [] when it leads elsewhere."""
    path = [name]
    ref = bodies[name].placement.relative_to
    while ref is not None and ref.body in bodies and ref.body not in path:
        path.append(ref.body)
        ref = bodies[ref.body].placement.relative_to
    return [*path, name] if ref is not None and ref.body == name else []


def _frame_pose(
    placed: ir.SceneBody,
    ref: ir.FrameRef,
    bodies: dict[str, ir.SceneBody],
    scene: ir.Scene,
    program: Program,
    ctx: CheckContext,
) -> np.ndarray | None:
    """The world pose of frame `ref` (a scene body's frame at its start), or None after reporting why not."""
    host = bodies.get(ref.body)
    if host is None or ref.body == placed.name:
        names = [b for b in bodies if b != placed.name]
        ctx.error(
            codes.UNKNOWN_NAME,
            f"`{ref.body}` is not another body of scene `{scene.name}`",
            ref.span,
            did_you_mean(ref.body, names) or "name the scene body that holds it, e.g. its cabinet",
        )
        return None
    host_type = program.bodies.get(host.type.name)
    if host_type is None:
        return None  # E301 on the host's type says why
    frame = host_type.frame(ref.frame)
    if frame is None:
        frames = [f.name for f in host_type.frames]
        how = "`in` places a body at the frame `slot` of its host's type" if placed.placement.inside else ""
        ctx.error(
            codes.UNKNOWN_FRAME,
            f"`{ref.body}` (a `{host_type.name}`) has no frame `{ref.frame}` to place `{placed.name}` at",
            ref.span,
            "; ".join(
                part
                for part in (
                    how,
                    did_you_mean(ref.frame, frames),
                    f"declare it in body {host_type.name}: `frame {ref.frame} = (0, 0, 0) cm`",
                )
                if part
            ),
        )
        return None
    import numpy as np

    from vkgl.lang.ir.geometry import scene_body_pose

    try:
        with np.errstate(all="ignore"):
            start = scene_body_pose(scene, host, host_type)
    except (ValueError, IndexError, RuntimeError):  # a shape or pose that other checks report
        return None
    pose = start @ frame.pose.matrix()
    return pose if np.all(np.isfinite(pose)) else None


def _pose_node(pose: np.ndarray, span: ir.Span | None) -> ir.Pose:
    """`pose` as an IR pose in metres, with a yaw when it only turns about z, else roll-pitch-yaw in radians.

    The nodes are made with `model_construct` (their values are floats already): validating them would build
    pydantic's validators and scan every installed package for pydantic plugins, a tenth of a `vkgc check`."""
    import numpy as np

    position = ir.Vector.model_construct(values=tuple(float(v) for v in pose[:3, 3]), unit="m", span=span)
    rotation = pose[:3, :3]
    if not np.all(np.isfinite(rotation)) or abs(rotation[2, 2] - 1.0) < 1e-12:
        yaw = ir.Quantity.model_construct(value=math.atan2(rotation[1, 0], rotation[0, 0]), unit="rad")
        return ir.Pose.model_construct(position=position, yaw=yaw, span=span)
    from scipy.spatial.transform import Rotation  # only for hosts tilted off level: `vkgc check` stays light

    rpy = Rotation.from_matrix(rotation).as_euler("xyz")
    rpy_node = ir.Vector.model_construct(values=tuple(float(v) for v in rpy), unit="rad")
    return ir.Pose.model_construct(position=position, rpy=rpy_node, span=span)


__all__ = ["place_relative_bodies"]
