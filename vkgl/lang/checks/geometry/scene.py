"""Checks of scene geometry: where bodies start and where goals put them (E420–E425).

A scene must be physically possible at the start and a goal reachable in
principle, with every body's real shape (vkgl/lang/checks/geometry/solids.py):

- E420 no two bodies (or a body and a robot's base) interpenetrate by more than
  `TOUCH` (touching is fine);
- E421 a body without a physical joint lies on the table: its shadow on the
  table passes the table's rectangle by at most `EDGE`; a position farther
  than `FAR` from the table is reported without any geometry;
- E422 a body placed `at (x, y, z)` without a physical joint rests: its lowest
  point within `REST` of the table top, or of the top of another body whose
  shadow overlaps its own;
- E426 a body on a physical joint, where the simulator hangs it (`JOINT_LIFT` above
  where it is placed), stays at least `JOINT_GAP` clear of every other body:
  touching one, it rubs on it when it moves on its joint and drags it along;
- E423–E425 at its goal (the goal's yaw, or the best heading if the yaw is
  free; the goal's tolerances count in its favour) a body stays on the table,
  out of the robots' bases and out of the bodies nothing can move (no
  affordance in the compilation and no physical joint).

Checks skip what other checks report: a missing table, an unknown type, an
invalid shape or a value that is not a finite number.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from vkgl.lang.checks.context import CheckContext
from vkgl.lang.checks.geometry.overlaps import check_joint_clearance, check_overlaps
from vkgl.lang.checks.geometry.placed import Base, Placed, Table
from vkgl.lang.checks.geometry.placed import cm as _cm
from vkgl.lang.checks.geometry.placed import m as _m
from vkgl.lang.checks.geometry.placed import where as _where
from vkgl.lang.checks.geometry.rigid import Rigid, Vec3, compose, inverse, joint_pose, lifted, norm, product
from vkgl.lang.checks.geometry.solids import (
    Piece,
    bounds,
    footprint_overlap,
    lowest,
    pieces_depth,
    pose_matrix,
    robot_base,
    shape_pieces,
    yawed,
)
from vkgl.lang.checks.geometry.unit_slip import unit_slip_note
from vkgl.lang.checks.joints import opening_problem
from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.program import Program
from vkgl.rotations import yaw_matrix

EDGE = 0.001
"""m: a body may pass the table's edge this much."""
REST = 0.001
"""m: a body `at` a pose rests when its lowest point is this close to the table top or a body's top."""
FAR = 1000.0
"""m: a body farther than this from the table's centre is off the table, whatever its shape."""
FREE_YAWS = 72
"""Headings tried (every 5 deg) for a goal that leaves the yaw free."""


def check_scenes(program: Program, ctx: CheckContext) -> None:
    """Report impossible starts of every scene and impossible goals of every task (E420–E425)."""
    shapes: dict[str, list[Piece] | None] = {}
    placed: dict[str, tuple[Table | None, list[Placed], list[Base]]] = {}
    for scene in program.scenes.values():
        placed[scene.name] = _check_scene(scene, program, shapes, ctx)
    for task in program.tasks.values():
        if task.scene.name in placed:
            _check_goals(task, program, *placed[task.scene.name], ctx)


# ---------------------------------------------------------------- scenes


def _check_scene(
    scene: ir.Scene, program: Program, shapes: dict[str, list[Piece] | None], ctx: CheckContext
) -> tuple[Table | None, list[Placed], list[Base]]:
    table = scene_table(scene)
    bases = _bases(scene, program)
    bodies: list[Placed] = []
    seen: set[str] = set()
    for scene_body in scene.bodies:
        body = program.bodies.get(scene_body.type.name)
        if body is None or scene_body.name in seen:
            continue
        seen.add(scene_body.name)
        if scene_body.type.name not in shapes:
            shapes[scene_body.type.name] = shape_pieces(body.shape)
        local = shapes[scene_body.type.name]
        pose = _start_pose(scene_body, local, table)
        if local is None or pose is None:
            continue
        pose = _opened(scene_body, body, pose)
        if body.joint is not None:
            pose = lifted(pose)  # where the simulator hangs it on its joint
        if table is not None and _far(pose, table):
            _report_far(scene_body, pose, table, ctx)
            continue
        pieces = [p.moved(pose) for p in local]
        low, high = bounds(pieces)
        bodies.append(Placed(scene_body, body, pose, pieces, low, high))
    if table is not None:
        for item in bodies:
            overhang = _overhang((item.low, item.high), table)
            if overhang > EDGE and item.body.joint is None:
                _report_off_table(item, overhang, table, ctx)
    check_overlaps(bodies, bases, ctx, table)
    check_joint_clearance(bodies, ctx)
    if table is not None:
        for item in bodies:
            if item.body.joint is None and not item.scene_body.placement.on_table:
                _check_rests(item, bodies, table, ctx)
    return table, bodies, bases


def scene_table(scene: ir.Scene) -> Table | None:
    """The scene's table as a rectangle and the height of its top; None when it has none or a bad one."""
    if scene.table is None:
        return None
    size, position = scene.table.size.values, scene.table.position.values
    if len(size) != 2 or len(position) < 2 or not all(math.isfinite(v) and v > 0 for v in size):
        return None
    if not all(math.isfinite(v) and abs(v) <= FAR for v in position):
        return None
    top = float(position[2]) if len(position) > 2 else 0.0
    (x, y), (sx, sy) = position[:2], size
    return Table((x - sx / 2, y - sy / 2), (x + sx / 2, y + sy / 2), top)


def _bases(scene: ir.Scene, program: Program) -> list[Base]:
    bases = []
    for placed in scene.robots:
        robot, pose = program.robots.get(placed.type.name), pose_matrix(placed.pose)
        if robot is not None and pose is not None and all(abs(v) < FAR for v in pose[1]):
            bases.append(Base(placed.name, robot_base(robot, pose)))
    return bases


def _opened(scene_body: ir.SceneBody, body: ir.Body, placed: Rigid) -> Rigid:
    """Where a body placed at `placed` starts: there, or, when it starts `open Q` on its joint, with the joint
    at Q (an opening of the wrong kind or past the joint's limits is reported by `checks_joints`: placed as 0)."""
    joint, opening = body.joint, scene_body.opening
    if joint is None or opening is None or opening_problem(opening, joint) is not None:
        return placed
    axis = joint.axis.values
    if len(axis) != 3 or not all(math.isfinite(v) for v in axis) or not norm(axis) > 0:
        return placed
    return joint_pose(joint, placed, opening.value)


def _start_pose(scene_body: ir.SceneBody, local: list[Piece] | None, table: Table | None) -> Rigid | None:
    """The world pose where the body starts (as `geometry.scene_body_pose` puts it), or None if not finite."""
    placement = scene_body.placement
    if not placement.on_table:
        return pose_matrix(placement.pose)
    values = placement.pose.position.values
    yaw = placement.pose.yaw.value if placement.pose.yaw is not None else 0.0
    if len(values) < 2 or not local:
        return None
    if not (math.isfinite(values[0]) and math.isfinite(values[1]) and math.isfinite(yaw)):
        return None
    c, s = math.cos(yaw), math.sin(yaw)
    top = table.top if table is not None else 0.0
    # a turn about z keeps heights
    return ((c, -s, 0.0), (s, c, 0.0), (0.0, 0.0, 1.0)), (float(values[0]), float(values[1]), top - lowest(local))


def _far(pose: Rigid, table: Table) -> bool:
    x, y, _ = pose[1]
    cx, cy = (table.low[0] + table.high[0]) / 2, (table.low[1] + table.high[1]) / 2
    return abs(x - cx) > FAR or abs(y - cy) > FAR


def _report_far(scene_body: ir.SceneBody, pose: Rigid, table: Table, ctx: CheckContext) -> None:
    x, y, _ = pose[1]
    ctx.error(
        codes.OFF_TABLE,
        f"`{scene_body.name}` is far off the table: it is at (x, y) = ({_m(x)}, {_m(y)}) m, and the table spans "
        f"{_span_xy(table.low, table.high)}",
        _where(scene_body),
        unit_slip_note(scene_body.placement.pose.position, table) or "move it onto the table",
    )


def _report_off_table(item: Placed, overhang: float, table: Table, ctx: CheckContext) -> None:
    """E421: the body's shadow passes the table's rectangle by `overhang` (> EDGE)."""
    lo, hi = item.low[:2], item.high[:2]
    x, y, _ = item.pose[1]
    inside = table.low[0] <= x <= table.high[0] and table.low[1] <= y <= table.high[1]
    what = f"overhangs the table's edge by {_cm(overhang)}" if inside else "is off the table"
    ctx.error(
        codes.OFF_TABLE,
        f"`{item.name}` {what}: it spans {_span_xy(lo, hi)}, the table {_span_xy(table.low, table.high)}",
        _where(item.scene_body),
        "move it inward, or turn it along the edge"
        if inside
        else unit_slip_note(item.scene_body.placement.pose.position, table) or "move it onto the table",
    )


def _check_rests(item: Placed, bodies: list[Placed], table: Table, ctx: CheckContext) -> None:
    """E422: a body `at` a pose whose lowest point is neither on the table top nor on a body's top under it."""
    lowest = item.low[2]
    if abs(lowest - table.top) <= REST:
        return
    tops = []
    for other in bodies:
        if other is item or not _shadows_meet(other, item):
            continue
        under = [p for p in other.pieces if footprint_overlap([p], item.pieces) > 0]
        if under:
            top = max(p.high[2] for p in under)
            if abs(top - lowest) <= REST:
                return
            if top < lowest:
                tops.append((top, other.name))
    z = item.pose[1][2]
    if lowest < table.top:
        message = f"`{item.name}` sinks {_cm(table.top - lowest)} into the table (its lowest point is at z = "
        message += f"{_m(lowest)} m, the table top at {_m(table.top)} m)"
        fix = f"raise it to z = {_m(z + table.top - lowest)} m, or place it `on table at (x, y) m`"
    else:
        top, below = max(tops) if tops else (table.top, "the table top")
        under_it = f"`{below}`" if tops else below
        message = f"`{item.name}` floats {_cm(lowest - top)} above {under_it} (its lowest point is at z = "
        message += f"{_m(lowest)} m): nothing holds it"
        fix = f"lower it to z = {_m(z - (lowest - top))} m, or place it `on table at (x, y) m`"
    ctx.error(codes.FLOATING_BODY, message, _position_span(item.scene_body), fix)


# ---------------------------------------------------------------- goals


def _shadows_meet(a: Placed, b: Placed) -> bool:
    """Whether the x-y bounds of two bodies overlap (strictly)."""
    return all(a.low[k] < b.high[k] and a.high[k] > b.low[k] for k in (0, 1))


def _check_goals(
    task: ir.Task, program: Program, table: Table | None, bodies: list[Placed], bases: list[Base], ctx: CheckContext
) -> None:
    by_name = {b.name: b for b in bodies}
    for goal in task.goals:
        item = by_name.get(goal.body.name)
        if item is None or goal.position is None or len(goal.position.values) < 2:
            continue
        values = tuple(float(v) for v in goal.position.values)
        yaws, tolerance = _goal_yaws(goal), goal.tolerance()[0]
        finite = all(math.isfinite(v) for v in values) and math.isfinite(tolerance) and tolerance > 0
        if not finite or yaws is None:
            continue  # E208 or E411 says why
        if table is not None and any(abs(values[k] - (table.low[k] + table.high[k]) / 2) > FAR for k in (0, 1)):
            if item.body.joint is None:
                _report_goal_off(goal, item, None, table, ctx)
            continue
        local, position = _goal_frame(item, values, table)
        poses = [yawed(local, yaw, position) for yaw in yaws]
        allowance = EDGE + tolerance
        if table is not None and item.body.joint is None:
            overhangs = [(_overhang(bounds(p), table), k) for k, p in enumerate(poses)]
            least, k = min(overhangs)
            if least > allowance:
                _report_goal_off(goal, item, bounds(poses[k]), table, ctx)
        reach = norm([*_minus(item.low, item.pose[1]), *_minus(item.high, item.pose[1])])
        for base in bases:
            depth = min(pieces_depth(p, base.pieces, allowance) for p in poses)
            if depth > allowance:
                ctx.error(
                    codes.GOAL_IN_ROBOT_BASE,
                    f"the goal puts `{item.name}` {_cm(depth)} deep into the base of robot `{base.name}`: move the "
                    f"goal away from the robot",
                    _goal_span(goal),
                    _free_yaw_note(goal),
                )
        for other in bodies:
            if other is item or not _immovable(other, program) or _apart(other, position, reach):
                continue
            depth = min(pieces_depth(p, other.pieces, allowance) for p in poses)
            if depth > allowance:
                ctx.error(
                    codes.GOAL_IN_FIXED_BODY,
                    f"the goal puts `{item.name}` {_cm(depth)} deep into `{other.name}`, which nothing can move: "
                    f"move the goal",
                    _goal_span(goal),
                    f"`{other.body.name}` has no affordance in this compilation and no joint",
                )


def _goal_yaws(goal: ir.Goal) -> list[float] | None:
    """The headings to try: every 5 deg when the yaw is free, else the goal's yaw and, at most 5 deg apart, the
    headings within its tolerance (both ends included); None when a value is not a finite number."""
    if goal.yaw is None:
        return [2 * math.pi * k / FREE_YAWS for k in range(FREE_YAWS)]
    yaw, tol = goal.yaw.value, goal.tolerance()[1]
    if not (math.isfinite(yaw) and math.isfinite(tol)):
        return None
    tol = min(abs(tol), math.pi)
    steps = max(1, math.ceil(tol / (2 * math.pi / FREE_YAWS)))
    return [yaw + tol * k / steps for k in range(-steps, steps + 1)]


def _minus(a: Sequence[float], b: Sequence[float]) -> Vec3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _goal_frame(item: Placed, values: Sequence[float], table: Table | None) -> tuple[list[Piece], Vec3]:
    """The body's pieces about its origin with its start orientation less its yaw, and its position at the goal.

    The height: the goal's z if it gives one, else resting on the table (a body `on table`), else the start's.
    """
    rotation = item.pose[0]
    yaw = math.atan2(rotation[1][0], rotation[0][0])
    level = (product(yaw_matrix(-yaw), rotation), (0.0, 0.0, 0.0))
    start = [p.moved(compose(level, inverse(item.pose))) for p in item.pieces]
    if len(values) > 2:
        z = float(values[2])
    elif item.scene_body.placement.on_table:
        z = (table.top if table is not None else 0.0) - lowest(start)
    else:
        z = item.pose[1][2]
    return start, (float(values[0]), float(values[1]), z)


def _overhang(box: tuple[Sequence[float], Sequence[float]], table: Table) -> float:
    """How far the x-y extent of `box` passes the table's rectangle (<= 0: inside it)."""
    low, high = box
    return max(table.low[0] - low[0], table.low[1] - low[1], high[0] - table.high[0], high[1] - table.high[1])


def _report_goal_off(
    goal: ir.Goal, item: Placed, box: tuple[Vec3, Vec3] | None, table: Table, ctx: CheckContext
) -> None:
    x, y = goal.position.values[:2] if goal.position is not None else (math.nan, math.nan)
    inside = bool(table.low[0] <= x <= table.high[0] and table.low[1] <= y <= table.high[1])
    if box is None:
        extent = f"(x, y) = ({_m(x)}, {_m(y)}) m"
    else:
        extent = _span_xy(box[0][:2], box[1][:2])
    if inside and box is not None:
        what = f"makes `{item.name}` overhang the table's edge by {_cm(_overhang(box, table))}"
    else:
        what = f"puts `{item.name}` off the table"
    # a relative goal's position is computed from a displacement: no unit was written for it
    slip = unit_slip_note(goal.position, table) if goal.position is not None and not (inside or goal.relative) else ""
    ctx.error(
        codes.GOAL_OFF_TABLE,
        f"the goal {what}: there it spans {extent}, the table {_span_xy(table.low, table.high)}",
        _goal_span(goal),
        slip or _free_yaw_note(goal) or "move the goal onto the table",
    )


def _immovable(item: Placed, program: Program) -> bool:
    return item.body.joint is None and not program.affordances.get(item.body.name)


def _apart(other: Placed, position: Vec3, reach: float) -> bool:
    """True when `other`'s bounds are farther than `reach` from `position` along some axis."""
    return any(other.low[k] > position[k] + reach or other.high[k] < position[k] - reach for k in range(3))


def _free_yaw_note(goal: ir.Goal) -> str:
    return "the goal leaves the yaw free: no heading helps" if goal.yaw is None else ""


# ---------------------------------------------------------------- messages


def _span_xy(low: Sequence[float], high: Sequence[float]) -> str:
    return f"x from {_m(low[0])} to {_m(high[0])} m and y from {_m(low[1])} to {_m(high[1])} m"


def _position_span(scene_body: ir.SceneBody) -> ir.Span | None:
    return scene_body.placement.pose.position.span or _where(scene_body)


def _goal_span(goal: ir.Goal) -> ir.Span | None:
    return (goal.position.span if goal.position is not None else None) or goal.span
