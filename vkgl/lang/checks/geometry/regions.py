"""Checks of regions (E450, E451) and the region goals of tasks, whose named regions are resolved here.

A keep-out region must not hold a body it keeps out at the start (E452).
A region goal's body must fit in its region at some heading the goal allows
(E453). Every region, declared in a scene (`region NAME = ...`) or written in a goal
(`goal B in region ...`), must be a region: a box's corners in order (E450), a
polygon convex with some area (E451). A goal's `in NAME` names a region of
its task's scene (E301 otherwise, E302 for a name declared twice); the
checker copies that region into the goal (`Goal.region`), so that the
planner and the executor need no scene lookup.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from vkgl.lang.checks.context import CheckContext, did_you_mean
from vkgl.lang.checks.geometry.placed import TOUCH, Table
from vkgl.lang.checks.geometry.placed import m as _m
from vkgl.lang.checks.geometry.relative import start_pose
from vkgl.lang.checks.geometry.scene import EDGE, scene_table
from vkgl.lang.checks.geometry.unit_slip import unit_slip_note
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.program import Program
from vkgl.lang.ir.regions import KeepOut, Region, footprint, overlap_depth, region_problem
from vkgl.lang.syntax.quantities import format_number

if TYPE_CHECKING:  # numpy is imported where a region is measured: a check of a scene without regions needs none
    import numpy as np


def check_regions(program: Program, ctx: CheckContext) -> None:
    """Report bad regions of every scene and task; fill in the regions named by goals."""
    for scene in program.scenes.values():
        seen: dict[str, Region] = {}
        for region in scene.regions:
            if region.name in seen:
                first = seen[region.name].name_span
                ctx.error(
                    codes.DUPLICATE_NAME,
                    f"region `{region.name}` is declared twice in scene `{scene.name}`",
                    region.name_span or region.span,
                    f"first declared at {first}",
                )
                continue
            seen[region.name] = region
            check_region(region, ctx)
    for name, task in list(program.tasks.items()):
        task_scene = program.scenes.get(task.scene.name)
        if task_scene is None:
            continue
        goals = [_resolved(goal, task_scene, ctx) for goal in task.goals]
        for goal in goals:
            _check_fits(goal, task_scene, program, ctx)
        keep_out = [_resolved(keep, task_scene, ctx) for keep in task.keep_out]
        for keep in keep_out:
            _check_keep_out(keep, task_scene, program, ctx)
        program.tasks[name] = task.model_copy(update={"goals": goals, "keep_out": keep_out})


def check_region(region: Region, ctx: CheckContext) -> bool:
    """Report `region` if its corners make no region (E450, E451); True when it is a region."""
    problem = region_problem(region)
    if problem is None:
        return True
    if problem == "reported":
        return False
    what = f"region `{region.name}`" if region.name else "the region"
    if problem == "swapped":
        (x0, y0), (x1, y1) = (c.values[:2] for c in region.corners)
        axes = " and ".join(a for a, lo, hi in (("x", x0, x1), ("y", y0, y1)) if lo > hi)
        fixed = (
            f"({format_number(min(x0, x1))}, {format_number(min(y0, y1))}) to "
            f"({format_number(max(x0, x1))}, {format_number(max(y0, y1))}) m"
        )
        ctx.error(
            codes.REGION_CORNERS_SWAPPED,
            f"{what} has its corners swapped along {axes}: the first corner is the lower-left one",
            region.span,
            f"write `{fixed}`",
        )
        return False
    why = {
        "few": "a polygon needs at least three vertices",
        "flat": "it encloses no area (narrower than 1 mm)",
        "repeated": "two vertices in a row are the same point (closer than 1 mm)",
        "concave": "the polygon is not convex (its vertices turn both ways)",
        "far": "a corner lies farther than 1 km from the origin",
    }[problem]
    ctx.error(
        codes.REGION_NOT_CONVEX,
        f"{what} is not a region: {why}",
        region.span,
        "give the vertices of a convex polygon in order around it, or a box `(x0, y0) to (x1, y1) m`",
    )
    return False


FIT_YAWS = 72
"""Headings tried (every 5 deg) for a region goal that leaves the yaw free."""


def _check_fits(goal: ir.Goal, scene: ir.Scene, program: Program, ctx: CheckContext) -> None:
    """E453: at no heading the goal allows does the body's footprint fit in its region (within the tolerance)."""
    if goal.region is None or region_problem(goal.region) is not None:
        return
    placed = next((b for b in scene.bodies if b.name == goal.body.name), None)
    body = program.bodies.get(placed.type.name) if placed is not None else None
    start = start_pose(scene, goal.body.name, program)
    tolerance = goal.tolerance()[0]
    if body is None or start is None or not (math.isfinite(tolerance) and tolerance > 0):
        return
    import numpy as np

    from vkgl.lang.ir.geometry import shape_vertices

    try:
        points = shape_vertices(body.shape)
    except (ValueError, OSError):  # a mesh that cannot be read: E503 says why
        return
    level = _level(start) @ points.T  # the body's points about its origin, its start tilt kept, heading 0
    planes = goal.region.halfplanes()
    if _fits(planes, level, goal, tolerance):
        table = scene_table(scene)
        if table is not None and body.joint is None and not _fits(_on_table(planes, table), level, goal, tolerance):
            _report_region_off_table(goal, table, ctx)
        return
    width = np.ptp(level[:2], axis=1)
    region = goal.region.points()
    ctx.error(
        codes.REGION_TOO_SMALL,
        f"`{goal.body.name}` does not fit in the goal's {goal.region.words()} at any heading the goal allows: the "
        f"region spans {_cm(np.ptp(region[:, 0]))} x {_cm(np.ptp(region[:, 1]))}, the body's footprint "
        f"{_cm(width[0])} x {_cm(width[1])} unturned",
        goal.region.span or goal.span,
        "make the region larger" + (", or leave the heading free" if goal.yaw is not None else ""),
    )


def _fits(planes: np.ndarray, level: np.ndarray, goal: ir.Goal, tolerance: float) -> bool:
    """Whether the footprint of the body's points `level` (about its origin, heading 0) fits inside `planes`
    at some heading the goal allows, within `tolerance`."""
    import numpy as np

    for yaw in _headings(goal):
        c, s = math.cos(yaw), math.sin(yaw)
        turned = np.array([[c, -s], [s, c]]) @ level[:2]
        reach = (planes[:, :2] @ turned).max(axis=1)  # per edge, how far out the footprint reaches from its origin
        if translation_fits(planes, reach, tolerance):
            return True
    return False


def _on_table(planes: np.ndarray, table: Table) -> np.ndarray:
    """The region's half-planes and the table's four edges, each `EDGE` farther out (as E423 allows a goal)."""
    import numpy as np

    (x0, y0), (x1, y1) = table.low, table.high
    edges = [(-1.0, 0.0, -x0 + EDGE), (1.0, 0.0, x1 + EDGE), (0.0, -1.0, -y0 + EDGE), (0.0, 1.0, y1 + EDGE)]
    return np.vstack([planes, np.array(edges)])


def _report_region_off_table(goal: ir.Goal, table: Table, ctx: CheckContext) -> None:
    """E423 for a region goal: the body fits in its region, but not where the region lies on the table."""
    region = goal.region
    assert region is not None
    corner = region.corners[0]
    slip = unit_slip_note(corner, table) if not region.name else ""
    ctx.error(
        codes.GOAL_OFF_TABLE,
        f"the goal's {region.words()} leaves no room for `{goal.body.name}` on the table: the table spans "
        f"x from {_m(table.low[0])} to {_m(table.high[0])} m and y from {_m(table.low[1])} to {_m(table.high[1])} m",
        region.span or goal.span,
        slip or "move the region onto the table",
    )


FIT_SLACK = 1e-9
"""m: how far a footprint may overreach an edge and still fit (rounding, far below the checks' millimetres)."""


def translation_fits(planes: np.ndarray, reach: np.ndarray, tolerance: float) -> bool:
    """Whether some origin `t` has `n . t + reach <= d + tolerance` for every edge `(n, d)` of `planes`.

    A 2-variable linear program, solved exactly: the origins that fit form the
    intersection of one half-plane per edge, a convex polygon (bounded, as the
    region's normals surround every direction) that, unless empty, has a corner
    where the lines of two edges cross. A region has a few edges, so every
    crossing is tried (no SciPy: `vkgc check` stays light). An edge of no length
    (a corner written twice) bounds nothing.
    """
    rows = [
        (nx, ny, d + tolerance - r)
        for (nx, ny, d), r in zip(planes.tolist(), reach.tolist(), strict=True)
        if math.isfinite(nx) and math.isfinite(ny)
    ]
    for i, (a1, b1, c1) in enumerate(rows):
        for a2, b2, c2 in rows[i + 1 :]:
            det = a1 * b2 - a2 * b1
            if abs(det) < 1e-12:
                continue  # parallel edges: their lines do not cross
            x, y = (c1 * b2 - c2 * b1) / det, (a1 * c2 - a2 * c1) / det
            if all(a * x + b * y <= c + FIT_SLACK for a, b, c in rows):
                return True
    return False


def _headings(goal: ir.Goal) -> list[float]:
    if goal.yaw is None:
        return [2 * math.pi * k / FIT_YAWS for k in range(FIT_YAWS)]
    yaw, tol = goal.yaw.value, min(abs(goal.tolerance()[1]), math.pi)
    steps = max(1, math.ceil(tol / (2 * math.pi / FIT_YAWS)))
    return [yaw + tol * k / steps for k in range(-steps, steps + 1)]


def _level(pose: np.ndarray) -> np.ndarray:
    """The body's start rotation less its heading (a body on the table: the identity)."""
    import numpy as np

    yaw = math.atan2(pose[1, 0], pose[0, 0])
    c, s = math.cos(-yaw), math.sin(-yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ pose[:3, :3]


def _cm(metres: float) -> str:
    return f"{metres * 100:.1f} cm"


def _check_keep_out(keep: KeepOut, scene: ir.Scene, program: Program, ctx: CheckContext) -> None:
    """E301 for `keep B out of R` naming no body of the scene; E452 for a body that starts inside R."""
    names = [b.name for b in scene.bodies]
    if keep.body is not None and keep.body.name not in names:
        ctx.error(
            codes.UNKNOWN_NAME,
            f"`{keep.body.name}` is not a body of scene `{scene.name}`",
            keep.body.span,
            did_you_mean(keep.body.name, names) or "name a body of the scene, or write `keep out R` for all of them",
        )
        return
    if keep.region is None or region_problem(keep.region) is not None:
        return  # unknown or not a region: reported
    from vkgl.lang.ir.geometry import shape_vertices

    region = keep.region.points()
    for placed in scene.bodies:
        body = program.bodies.get(placed.type.name)
        pose = start_pose(scene, placed.name, program)
        if not keep.applies_to(placed.name) or body is None or pose is None:
            continue
        try:
            points = shape_vertices(body.shape)
        except (ValueError, OSError):  # a mesh that cannot be read: E503 says why
            continue
        depth = overlap_depth(region, footprint(points, pose))
        if depth > TOUCH:
            ctx.error(
                codes.KEEP_OUT_AT_START,
                f"`{placed.name}` starts {depth * 100:.1f} cm inside the keep-out {keep.region.words()}",
                keep.span,
                f"no plan can keep `{placed.name}` out of a region it starts in: move the region, or name the "
                f"bodies it is for (`keep BODY out of ...`)",
            )


def _resolved(goal: Any, scene: ir.Scene, ctx: CheckContext) -> Any:
    """A goal or keep-out with its scene region copied in (`region_ref` -> `region`); reports unknown names."""
    if goal.region is not None:
        check_region(goal.region, ctx)
        return goal
    if goal.region_ref is None:
        return goal
    name = goal.region_ref.name
    region = next((r for r in scene.regions if r.name == name), None)
    if region is None:
        names = [r.name for r in scene.regions]
        ctx.error(
            codes.UNKNOWN_NAME,
            f"no region `{name}` in scene `{scene.name}`",
            goal.region_ref.span,
            did_you_mean(name, names)
            or "declare it in the scene: `region NAME = (x0, y0) to (x1, y1) m`, or write "
            "it in place: `in region (x0, y0) to (x1, y1) m`",
        )
        return goal
    return goal.model_copy(update={"region": region})


__all__ = ["check_region", "check_regions"]
