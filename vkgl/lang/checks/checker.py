"""Semantic checks over a whole compilation: names, kinds, values and files.

`check_program` walks every module once (dependencies first), builds the flat
namespace and reports every problem as a Diagnostic; it never raises for bad
input. It also fills in what the back ends need resolved: absolute mesh and
URDF paths.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from vkgl.lang.checks.body import check_body, check_direction, check_robot
from vkgl.lang.checks.context import (
    CheckContext,
    did_you_mean,
    duplicates,
    goals_with_types,
    lookup,
    shown,
    shown_vector,
    unknown_frame,
    where_declared,
)
from vkgl.lang.checks.families import check_family
from vkgl.lang.checks.geometry.placement import place_relative_bodies
from vkgl.lang.checks.geometry.regions import check_regions
from vkgl.lang.checks.geometry.relative import place_relative_goals
from vkgl.lang.checks.geometry.scene import check_scenes
from vkgl.lang.checks.goal_pairs import check_goal_pairs
from vkgl.lang.checks.grasps import check_grasp_affordance
from vkgl.lang.checks.joints import check_joint_goals
from vkgl.lang.checks.learn_hint import affordance_hint
from vkgl.lang.checks.ranges import check_evidence_ranges, check_search_ranges
from vkgl.lang.checks.tipping import check_tipping
from vkgl.lang.diagnostics import codes
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.program import Program


def check_program(
    modules: dict[str, ir.Module],
    root: str,
    sources: dict[str, str],
    folders: dict[str, Path] | None = None,
) -> tuple[Program, list[Diagnostic]]:
    """Check every module and assemble the Program (valid only when no error is returned).

    `folders` gives the directory a module's relative file paths start from (default: its file's).
    """
    ctx = CheckContext(sources=sources)
    folders = folders or {}
    resolved = {key: _resolve_files(module, folders.get(key)) for key, module in modules.items()}
    for key, module in resolved.items():
        _declare(module, key, ctx)
    program = _assemble(resolved, root, sources, ctx)
    for module in resolved.values():
        for decl in module.decls:
            _check_decl(decl, program, ctx)
    place_relative_bodies(program, ctx)  # `in B`, `at B.F`: the world pose from B's start and its type's frame
    _check_tasks_can_move(program, ctx)
    check_joint_goals(program, ctx)  # joint goals: a body with a joint, the right kind of opening, its limits
    _check_tools_have_correspondences(program, ctx)
    place_relative_goals(program, ctx)  # `moved by`, `turned by`: the pose goal from the body's start
    check_regions(program, ctx)  # regions in order and convex (E450, E451); a goal's `in NAME` resolved
    check_scenes(program, ctx)  # scene geometry: overlaps, table edges, resting, goals (E420–E425)
    check_goal_pairs(program, ctx)  # goals of one body that cannot all hold (E427)
    return program, ctx.diagnostics


# ---------------------------------------------------------------- namespace


def _declare(module: ir.Module, key: str, ctx: CheckContext) -> None:
    for decl in module.decls:
        if isinstance(decl, (ir.AffordanceSet, ir.Correspondences)):
            continue
        first = ctx.names.get(decl.name)
        if first is not None:
            ctx.error(
                codes.DUPLICATE_NAME,
                f"`{decl.name}` is declared twice",
                decl.name_span or decl.span,
                f"first declared at {where_declared(first[0])}",
            )
            continue
        ctx.names[decl.name] = (decl, key)


def _assemble(modules: dict[str, ir.Module], root: str, sources: dict[str, str], ctx: CheckContext) -> Program:
    root_module = modules.get(root) or ir.Module(path=root)
    program = Program(root=root_module, modules=dict(modules), sources=dict(sources))
    for decl, _ in ctx.names.values():
        if isinstance(decl, ir.Body):
            program.bodies[decl.name] = decl
        elif isinstance(decl, ir.Robot):
            program.robots[decl.name] = decl
        elif isinstance(decl, ir.Scene):
            program.scenes[decl.name] = decl
        elif isinstance(decl, ir.Task):
            program.tasks[decl.name] = decl
    for module in modules.values():
        for block in module.decls:
            if isinstance(block, ir.AffordanceSet):
                program.affordances.setdefault(block.body.name, []).extend(block.affordances)
                program.tipping.setdefault(block.body.name, []).extend(block.tipping)
            elif isinstance(block, ir.Correspondences):
                program.correspondences.extend(block.items)
    return program


# ---------------------------------------------------------------- declarations


def _check_decl(decl: Any, program: Program, ctx: CheckContext) -> None:
    if isinstance(decl, ir.Body):
        check_body(decl, ctx)
    elif isinstance(decl, ir.Robot):
        check_robot(decl, ctx)
    elif isinstance(decl, ir.AffordanceSet):
        _check_affordances(decl, ctx)
    elif isinstance(decl, ir.Correspondences):
        _check_correspondences(decl, program, ctx)
    elif isinstance(decl, ir.Scene):
        _check_scene(decl, ctx)
    elif isinstance(decl, ir.Task):
        _check_task(decl, ctx)


def _check_affordances(block: ir.AffordanceSet, ctx: CheckContext) -> None:
    body = lookup(block.body, "body", ctx)
    duplicates(block.affordances, "affordance", ctx)
    check_tipping(block, body if isinstance(body, ir.Body) else None, ctx)
    for affordance in block.affordances:
        for constraint in (affordance.action, affordance.motion):
            if isinstance(constraint, (ir.PrismaticC, ir.RevoluteC)):
                check_direction(constraint.axis, "an axis", ctx)
        _check_motion_range(affordance.motion, ctx)
        check_grasp_affordance(affordance, ctx)
        check_family(affordance, ctx)
        evidence = affordance.evidence
        if evidence is not None:
            check_evidence_ranges(evidence, ctx)
        if evidence is not None and (evidence.posterior < 0 or evidence.posterior > 1):  # (NaN fails both)
            ctx.error(
                codes.POSTERIOR_OUT_OF_RANGE,
                f"a posterior is a probability in [0, 1], got `{evidence.posterior:g}`",
                ctx.narrow(evidence.span, r"posterior\s+(\S+)"),
            )
    del body


def _check_motion_range(motion: ir.Constraint, ctx: CheckContext) -> None:
    """A motion's `range`: lower first, never below zero (plans use non-negative values only), `open` on slides only."""
    bounds = motion.range if isinstance(motion, (ir.PrismaticC, ir.RevoluteC)) else None
    if bounds is None:
        return
    lower, upper = bounds.lower, bounds.upper
    if lower.value < 0:  # (NaN, already reported, fails every comparison)
        ctx.error(
            codes.NEGATIVE_RANGE,
            f"a motion range starts at 0 or above, got {shown(lower)}",
            lower.span or bounds.span,
            "motion values are >= 0 (the sense the exploring force produced): write `range 0 to ...`",
        )
    if bounds.open and isinstance(motion, ir.RevoluteC):
        ctx.error(
            codes.OPEN_TURN,
            "only a slide's range can be `open`: a turn is known only over the angles it was explored over",
            ctx.narrow(bounds.span, r"\b(open)\s*$"),
            "remove `open` (a turn's pivot drifts as it turns further), or explore the turn further",
        )
    if lower.value > upper.value:
        ctx.error(
            codes.REVERSED_RANGE,
            f"the range's lower bound {shown(lower)} is above its upper bound {shown(upper)}",
            bounds.span,
            "write `range LOWER to UPPER UNIT`: swap them",
        )


def _check_correspondences(block: ir.Correspondences, program: Program, ctx: CheckContext) -> None:
    effectors = {e.name for robot in program.robots.values() for e in robot.effectors}
    duplicates(block.items, "correspondence", ctx, lambda c: f"{c.frame.body}.{c.frame.frame}")
    for item in block.items:
        body = lookup(ir.Ref.model_construct(name=item.frame.body, span=item.frame.span), "body", ctx)
        if body is not None and body.frame(item.frame.frame) is None:
            unknown_frame(body, item.frame.frame, item.frame.span, ctx)
        if item.effector.name not in effectors:
            hint = (
                did_you_mean(item.effector.name, sorted(effectors))
                or "no robot in this compilation declares effectors; `use` one"
            )
            ctx.error(
                codes.UNKNOWN_EFFECTOR,
                f"no robot declares an effector `{item.effector.name}`",
                item.effector.span,
                hint,
            )


def _check_scene(scene: ir.Scene, ctx: CheckContext) -> None:
    where = scene.name_span or scene.span
    if scene.table is None:
        ctx.error(
            codes.SCENE_WITHOUT_TABLE,
            f"scene `{scene.name}` has no table: add e.g. `table size (1.6, 1.2) m at (0.5, 0, 0) m`",
            where,
        )
    elif any(v <= 0 for v in scene.table.size.values):
        ctx.error(
            codes.NON_POSITIVE_SIZE,
            f"table sizes must be positive, got {shown_vector(scene.table.size)}",
            scene.table.size.span,
        )
    if not scene.robots:
        ctx.error(
            codes.SCENE_WITHOUT_ROBOT,
            f"scene `{scene.name}` has no robot: add e.g. `robot arm : Panda at (0, 0, 0) m`",
            where,
        )
    for robot in scene.robots:
        lookup(robot.type, "robot", ctx)
    for body in scene.bodies:
        lookup(body.type, "body", ctx)
    duplicates([*scene.robots, *scene.bodies], "scene object", ctx)


def _check_task(task: ir.Task, ctx: CheckContext) -> None:
    scene = lookup(task.scene, "scene", ctx) if task.scene.name else None
    for goal in task.goals:
        if scene is not None and goal.body.name not in {b.name for b in scene.bodies}:
            names = [b.name for b in scene.bodies]
            ctx.error(
                codes.GOAL_NOT_IN_SCENE,
                f"`{goal.body.name}` is not a body of scene `{scene.name}`",
                goal.body.span,
                did_you_mean(goal.body.name, names),
            )
        for tol in (goal.tol_position, goal.tol_yaw, goal.tol_opening):
            if tol is not None and tol.value <= 0:
                ctx.error(codes.NON_POSITIVE_VALUE, f"a tolerance must be positive, got {shown(tol)}", tol.span)
    if task.search is not None:
        check_search_ranges(task.search, ctx)
        if task.search.max_depth is not None and task.search.max_depth < 1:
            ctx.error(
                codes.NON_POSITIVE_VALUE,
                f"`max_depth` must be at least 1, got {task.search.max_depth}",
                ctx.narrow(task.search.span, r"max_depth\s+(\S+)"),
            )
        if task.search.timeout is not None and task.search.timeout.value <= 0:
            ctx.error(
                codes.NON_POSITIVE_VALUE,
                f"the timeout must be positive, got {shown(task.search.timeout)}",
                task.search.timeout.span,
            )


def _check_tasks_can_move(program: Program, ctx: CheckContext) -> None:
    """Warn about goal bodies of a task that no affordance in the compilation can move."""
    for goal, kind in goals_with_types(program):
        if kind in program.bodies and not program.affordances.get(kind):
            ctx.warn(
                codes.NOTHING_CAN_MOVE,
                f"no affordance of `{kind}` is imported, so nothing can move `{goal.body.name}`",
                goal.body.span,
                affordance_hint(program.bodies[kind], goal.body.span.file if goal.body.span else None),
            )


def _check_tools_have_correspondences(program: Program, ctx: CheckContext) -> None:
    """Warn about tools (bodies explored while grasped) in a task's scene that no correspondence names.

    Without `Tool.frame ~ effector` the planner can pick the tool up but never use it.
    """
    with_correspondence = {c.frame.body for c in program.correspondences}
    scenes = {task.scene.name for task in program.tasks.values()}
    for name in sorted(scenes):
        scene = program.scenes.get(name)
        if scene is None:
            continue
        for placed in scene.bodies:
            body = program.bodies.get(placed.type.name)
            if body is None:
                continue
            grasps = [e.grasp.name for e in body.explores if e.grasp is not None]
            if grasps and body.name not in with_correspondence:
                ctx.warn(
                    codes.TOOL_WITHOUT_CORRESPONDENCE,
                    f"`{placed.name}` is a tool (`{body.name}` is explored held by `{grasps[0]}`), "
                    f"but no correspondence names a frame of `{body.name}`, so no task can use it",
                    placed.type.span,
                    f"add e.g. `correspondences {{ {body.name}.tip ~ fingertip }}`, or `use stdlib.tools`",
                )


# ---------------------------------------------------------------- files


def _resolve_files(module: ir.Module, folder: Path | None) -> ir.Module:
    """The module with mesh and URDF paths made absolute (relative to `folder`, by default the module's file's)."""
    folder = folder if folder is not None else _real(Path(module.path)).parent
    decls: list[Any] = []
    for decl in module.decls:
        if isinstance(decl, ir.Body):
            decl = decl.model_copy(update={"shape": _resolve_shape(decl.shape, folder)})
        elif isinstance(decl, ir.Robot):
            decl = decl.model_copy(update={"urdf_resolved": str(_real(folder / decl.urdf))})
        decls.append(decl)
    return module.model_copy(update={"decls": decls})


def _resolve_shape(shape: Any, folder: Path) -> Any:
    if isinstance(shape, ir.MeshShape):
        return shape.model_copy(update={"resolved": str(_real(folder / shape.path))})
    if isinstance(shape, ir.UnionShape):
        parts = [p.model_copy(update={"shape": _resolve_shape(p.shape, folder)}) for p in shape.parts]
        return shape.model_copy(update={"parts": parts})
    return shape


def _real(path: Path) -> Path:
    """`path` resolved through symbolic links; absolute but unresolved for a link loop (reported as missing)."""
    try:
        return path.resolve()
    except (OSError, RuntimeError):  # RuntimeError: Python 3.11's "Symlink loop"
        return Path(os.path.abspath(path))
