"""Semantic checks over a whole compilation: names, kinds, values and files.

`check_program` walks every module once (dependencies first), builds the flat
namespace and reports every problem as a Diagnostic; it never raises for bad
input. It also fills in what the back ends need resolved: absolute mesh and
URDF paths.
"""

from __future__ import annotations

import difflib
import os
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from vkgl.lang import ir
from vkgl.lang.diagnostics import Diagnostic
from vkgl.lang.program import Program

Named = ir.Body | ir.Robot | ir.Scene | ir.Task
KIND_WORD = {"body": "a body", "robot": "a robot", "scene": "a scene", "task": "a task"}


@dataclass
class _Context:
    diagnostics: list[Diagnostic] = field(default_factory=list)
    names: dict[str, tuple[Named, str]] = field(default_factory=dict)
    sources: dict[str, str] = field(default_factory=dict)

    def narrow(self, span: ir.Span | None, pattern: str) -> ir.Span | None:
        """The span of `pattern`'s first group inside `span` (e.g. one value of a statement), else `span` itself.

        The IR keeps spans of statements, not of every word; the source text finds the word.
        """
        source = self.sources.get(span.file) if span is not None else None
        if span is None or source is None:
            return span
        lines = source.split("\n")
        if not 1 <= span.line <= len(lines):
            return span
        line = lines[span.line - 1]
        end = span.end_col - 1 if span.end_line == span.line else len(line)
        match = re.search(pattern, line[span.col - 1 : end])
        if match is None:
            return span
        start = span.col + match.start(1)
        return ir.Span(
            file=span.file, line=span.line, col=start, end_line=span.line, end_col=start + len(match.group(1))
        )

    def error(self, code: str, message: str, span: ir.Span | None, *notes: str) -> None:
        self.diagnostics.append(Diagnostic(code, message, span, notes=tuple(n for n in notes if n)))

    def warn(self, code: str, message: str, span: ir.Span | None, *notes: str) -> None:
        self.diagnostics.append(Diagnostic(code, message, span, "warning", tuple(n for n in notes if n)))


def check_program(
    modules: dict[str, ir.Module], root: str, sources: dict[str, str]
) -> tuple[Program, list[Diagnostic]]:
    """Check every module and assemble the Program (valid only when no error is returned)."""
    ctx = _Context(sources=sources)
    resolved = {key: _resolve_files(module, ctx) for key, module in modules.items()}
    for key, module in resolved.items():
        _declare(module, key, ctx)
    program = _assemble(resolved, root, sources, ctx)
    for module in resolved.values():
        for decl in module.decls:
            _check_decl(decl, program, ctx)
    _check_tasks_can_move(program, ctx)
    _check_tools_have_correspondences(program, ctx)
    return program, ctx.diagnostics


# ---------------------------------------------------------------- namespace


def _declare(module: ir.Module, key: str, ctx: _Context) -> None:
    for decl in module.decls:
        if isinstance(decl, (ir.AffordanceSet, ir.Correspondences)):
            continue
        first = ctx.names.get(decl.name)
        if first is not None:
            ctx.error(
                "E302",
                f"`{decl.name}` is declared twice",
                decl.name_span or decl.span,
                f"first declared at {_where(first[0])}",
            )
            continue
        ctx.names[decl.name] = (decl, key)


def _assemble(modules: dict[str, ir.Module], root: str, sources: dict[str, str], ctx: _Context) -> Program:
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
        for decl in module.decls:
            if isinstance(decl, ir.AffordanceSet):
                program.affordances.setdefault(decl.body.name, []).extend(decl.affordances)
            elif isinstance(decl, ir.Correspondences):
                program.correspondences.extend(decl.items)
    return program


def _lookup(ref: ir.Ref, kind: str, ctx: _Context) -> Any:
    """The declaration `ref` names if it is of `kind`; otherwise an error with a suggestion."""
    entry = ctx.names.get(ref.name)
    if entry is None:
        candidates = [n for n, (d, _) in ctx.names.items() if d.kind == kind]
        ctx.error("E301", f"unknown {kind} `{ref.name}`", ref.span, _did_you_mean(ref.name, candidates))
        return None
    decl = entry[0]
    if decl.kind != kind:
        ctx.error(
            "E305",
            f"`{ref.name}` is {KIND_WORD[decl.kind]}, not {KIND_WORD[kind]}",
            ref.span,
            f"`{ref.name}` is declared at {_where(decl)}",
        )
        return None
    return decl


def _did_you_mean(name: str, candidates: list[str]) -> str:
    match = difflib.get_close_matches(name, sorted(set(candidates)), n=1, cutoff=0.6)
    if match:
        return f"did you mean `{match[0]}`?"
    if candidates and len(candidates) <= 8:
        return "known: " + ", ".join(f"`{c}`" for c in sorted(set(candidates)))
    return ""


def _where(node: ir.Node) -> str:
    span = getattr(node, "name_span", None) or node.span
    return str(span) if span is not None else "<unknown>"


def _duplicates(items: list[Any], what: str, ctx: _Context, name_of: Any = lambda x: x.name) -> None:
    seen: dict[str, Any] = {}
    for item in items:
        name = name_of(item)
        if name in seen:
            ctx.error("E302", f"{what} `{name}` is declared twice", item.span, f"first declared at {seen[name].span}")
        else:
            seen[name] = item


# ---------------------------------------------------------------- declarations


def _check_decl(decl: Any, program: Program, ctx: _Context) -> None:
    if isinstance(decl, ir.Body):
        _check_body(decl, ctx)
    elif isinstance(decl, ir.Robot):
        _check_robot(decl, ctx)
    elif isinstance(decl, ir.AffordanceSet):
        _check_affordances(decl, ctx)
    elif isinstance(decl, ir.Correspondences):
        _check_correspondences(decl, program, ctx)
    elif isinstance(decl, ir.Scene):
        _check_scene(decl, ctx)
    elif isinstance(decl, ir.Task):
        _check_task(decl, ctx)


def _check_body(body: ir.Body, ctx: _Context) -> None:
    if body.mass.value <= 0:
        ctx.error("E401", f"the mass of `{body.name}` must be positive, got {_shown(body.mass)}", body.mass.span)
    _check_shape(body.shape, ctx)
    if body.friction is not None and body.friction < 0:
        ctx.error(
            "E403",
            f"friction must not be negative, got `{body.friction:g}`",
            ctx.narrow(body.friction_span or body.span, r"friction\s+(\S+)"),
        )
    _duplicates(body.frames, "frame", ctx)
    if body.joint is not None:
        _check_joint(body.joint, ctx)
    _duplicates(body.explores, "exploration", ctx)
    for explore in body.explores:
        _check_explore(explore, body, ctx)


def _check_shape(shape: Any, ctx: _Context) -> None:
    if isinstance(shape, ir.BoxShape):
        if any(v <= 0 for v in shape.size.values):
            ctx.error("E402", f"box sizes must be positive, got {_shown_vector(shape.size)}", shape.size.span)
    elif isinstance(shape, ir.CylinderShape):
        for q, what in ((shape.radius, "radius"), (shape.height, "height")):
            if q.value <= 0:
                ctx.error("E402", f"the cylinder's {what} must be positive, got {_shown(q)}", q.span)
    elif isinstance(shape, ir.MeshShape):
        if shape.scale <= 0:
            ctx.error(
                "E402",
                f"a mesh scale must be positive, got `{shape.scale:g}`",
                ctx.narrow(shape.span, r"scale\s+(\S+)"),
            )
        _check_mesh_file(shape, ctx)
    elif isinstance(shape, ir.UnionShape):
        for part in shape.parts:
            _check_shape(part.shape, ctx)


def _check_mesh_file(shape: ir.MeshShape, ctx: _Context) -> None:
    problem = _mesh_problem(shape.resolved or shape.path)
    if problem:
        ctx.error(
            "E503",
            f"cannot use mesh `{shape.path}`: {problem}",
            ctx.narrow(shape.span, r'mesh\s+("[^"]*")'),
            _looked_for(shape.resolved, problem),
        )


def _looked_for(resolved: str | None, problem: str) -> str:
    """For a missing file: where it was looked for (paths are relative to the module that names them)."""
    if problem != "no such file" or not resolved:
        return ""
    try:
        relative = os.path.relpath(resolved)
    except ValueError:  # another drive on Windows
        relative = resolved
    shown = resolved if relative.startswith("..") else relative
    return f"looked for `{shown}`: the path is relative to the module's file"


@lru_cache(maxsize=64)
def _mesh_problem(path: str) -> str | None:
    """Why trimesh cannot give triangles for `path`, or None when it can."""
    if not Path(path).is_file():
        return "no such file"
    import trimesh

    try:
        loaded = trimesh.load(path, force="mesh")
    except Exception as exc:  # trimesh raises many types; its message says why
        return f"trimesh cannot read it ({type(exc).__name__}: {exc})"
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        return "the file holds no triangles"
    return None


def _check_joint(joint: ir.Joint, ctx: _Context) -> None:
    _check_direction(joint.axis, "a joint axis", ctx)
    if joint.lower.value > joint.upper.value:
        ctx.error(
            "E405",
            f"joint limits are reversed: lower {_shown(joint.lower)} > upper {_shown(joint.upper)}; write (lower, upper)",
            joint.lower.span,
        )


def _check_direction(vector: ir.Vector, what: str, ctx: _Context) -> None:
    if len(vector.values) and not np.any(np.asarray(vector.values) != 0):
        ctx.error("E404", f"{what} must not be zero", vector.span)


def _check_explore(explore: ir.Explore, body: ir.Body, ctx: _Context) -> None:
    if explore.grasp is not None and body.frame(explore.grasp.name) is None:
        _unknown_frame(body, explore.grasp.name, explore.grasp.span, ctx)
    if explore.contacts is not None and explore.contacts.steps <= 0:
        ctx.error(
            "E411",
            f"`steps` must be at least 1, got {explore.contacts.steps}",
            ctx.narrow(explore.contacts.span, r"steps\s+(\S+)"),
        )
    if explore.force is not None:
        if explore.force.magnitude.value <= 0:
            ctx.error(
                "E411",
                f"the force must be positive, got {_shown(explore.force.magnitude)}",
                explore.force.magnitude.span,
            )
        if explore.force.grid is not None and min(explore.force.grid) < 1:
            ctx.error("E411", "each direction grid size must be at least 1", explore.force.span)
    if explore.duration is not None and explore.duration.value <= 0:
        ctx.error("E411", f"the duration must be positive, got {_shown(explore.duration)}", explore.duration.span)


def _unknown_frame(body: ir.Body, name: str, span: ir.Span | None, ctx: _Context) -> None:
    frames = [f.name for f in body.frames]
    ctx.error(
        "E303", f"body `{body.name}` has no frame `{name}`", span, _did_you_mean(name, frames) or _no_frames(frames)
    )


def _no_frames(frames: list[str]) -> str:
    return "" if frames else "it declares no frames: add e.g. `frame tip = (20, 0, 0) cm`"


def _check_robot(robot: ir.Robot, ctx: _Context) -> None:
    _duplicates(robot.effectors, "effector", ctx)
    path = robot.urdf_resolved or robot.urdf
    links, problem = _urdf_links(path)
    if problem:
        ctx.error(
            "E504",
            f"cannot use URDF `{robot.urdf}`: {problem}",
            ctx.narrow(robot.urdf_span or robot.span, r'urdf\s+("[^"]*")'),
            _looked_for(robot.urdf_resolved, problem),
        )
        return
    for effector in robot.effectors:
        if effector.link not in links:
            ctx.error(
                "E307",
                f"the URDF of `{robot.name}` has no link `{effector.link}`",
                ctx.narrow(effector.span, rf"link\s+({re.escape(effector.link)})\b"),
                _did_you_mean(effector.link, sorted(links)),
            )


@lru_cache(maxsize=16)
def _urdf_links(path: str) -> tuple[frozenset[str], str | None]:
    """The link names of a URDF and, if it cannot be used, why (XML first, then DART)."""
    if not Path(path).is_file():
        return frozenset(), "no such file"
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        return frozenset(), f"not valid XML ({exc})"
    if root.tag != "robot":
        return frozenset(), f"the root element is <{root.tag}>, not <robot>"
    links = frozenset(link.get("name", "") for link in root.iter("link"))
    if not links:
        return links, "it declares no <link>"
    return links, _dart_problem(path)


def _dart_problem(path: str) -> str | None:
    import dartpy as dart

    skeleton = dart.utils.DartLoader().parseSkeleton(str(Path(path).resolve()))
    return None if skeleton is not None else "DART cannot load it (see its messages above)"


def _check_affordances(block: ir.AffordanceSet, ctx: _Context) -> None:
    body = _lookup(block.body, "body", ctx)
    _duplicates(block.affordances, "affordance", ctx)
    for affordance in block.affordances:
        for constraint in (affordance.action, affordance.motion):
            if isinstance(constraint, (ir.PrismaticC, ir.RevoluteC)):
                _check_direction(constraint.axis, "an axis", ctx)
        posterior = affordance.evidence.posterior if affordance.evidence is not None else 0.5
        if posterior < 0 or posterior > 1:  # (NaN, a value already reported, fails both)
            ctx.error(
                "E412",
                f"a posterior is a probability in [0, 1], got `{affordance.evidence.posterior:g}`",
                ctx.narrow(affordance.evidence.span, r"posterior\s+(\S+)"),
            )
    del body


def _check_correspondences(block: ir.Correspondences, program: Program, ctx: _Context) -> None:
    effectors = {e.name for robot in program.robots.values() for e in robot.effectors}
    _duplicates(block.items, "correspondence", ctx, lambda c: f"{c.frame.body}.{c.frame.frame}")
    for item in block.items:
        body = _lookup(ir.Ref(name=item.frame.body, span=item.frame.span), "body", ctx)
        if body is not None and body.frame(item.frame.frame) is None:
            _unknown_frame(body, item.frame.frame, item.frame.span, ctx)
        if item.effector.name not in effectors:
            hint = (
                _did_you_mean(item.effector.name, sorted(effectors))
                or "no robot in this compilation declares effectors; `use` one"
            )
            ctx.error("E304", f"no robot declares an effector `{item.effector.name}`", item.effector.span, hint)


def _check_scene(scene: ir.Scene, ctx: _Context) -> None:
    where = scene.name_span or scene.span
    if scene.table is None:
        ctx.error(
            "E408", f"scene `{scene.name}` has no table: add e.g. `table size (1.6, 1.2) m at (0.5, 0, 0) m`", where
        )
    elif any(v <= 0 for v in scene.table.size.values):
        ctx.error("E402", f"table sizes must be positive, got {_shown_vector(scene.table.size)}", scene.table.size.span)
    if not scene.robots:
        ctx.error("E409", f"scene `{scene.name}` has no robot: add e.g. `robot arm : Panda at (0, 0, 0) m`", where)
    for robot in scene.robots:
        _lookup(robot.type, "robot", ctx)
    for body in scene.bodies:
        _lookup(body.type, "body", ctx)
    _duplicates([*scene.robots, *scene.bodies], "scene object", ctx)


def _check_task(task: ir.Task, ctx: _Context) -> None:
    scene = _lookup(task.scene, "scene", ctx) if task.scene.name else None
    for goal in task.goals:
        if scene is not None and goal.body.name not in {b.name for b in scene.bodies}:
            names = [b.name for b in scene.bodies]
            ctx.error(
                "E306",
                f"`{goal.body.name}` is not a body of scene `{scene.name}`",
                goal.body.span,
                _did_you_mean(goal.body.name, names),
            )
        for tol in (goal.tol_position, goal.tol_yaw):
            if tol is not None and tol.value <= 0:
                ctx.error("E411", f"a tolerance must be positive, got {_shown(tol)}", tol.span)
    if task.search is not None:
        if task.search.max_depth is not None and task.search.max_depth < 1:
            ctx.error(
                "E411",
                f"`max_depth` must be at least 1, got {task.search.max_depth}",
                ctx.narrow(task.search.span, r"max_depth\s+(\S+)"),
            )
        if task.search.timeout is not None and task.search.timeout.value <= 0:
            ctx.error(
                "E411", f"the timeout must be positive, got {_shown(task.search.timeout)}", task.search.timeout.span
            )


def _check_tasks_can_move(program: Program, ctx: _Context) -> None:
    """Warn about goal bodies of a task that no affordance in the compilation can move."""
    for task in program.tasks.values():
        scene = program.scenes.get(task.scene.name)
        if scene is None:
            continue
        types = {b.name: b.type.name for b in scene.bodies}
        for goal in task.goals:
            kind = types.get(goal.body.name)
            if kind is not None and kind in program.bodies and not program.affordances.get(kind):
                ctx.warn(
                    "W601",
                    f"no affordance of `{kind}` is imported, so nothing can move `{goal.body.name}`",
                    goal.body.span,
                    f"add `use stdlib.affordances.{kind.lower()}` or learn one with `vkgc learn`",
                )


def _check_tools_have_correspondences(program: Program, ctx: _Context) -> None:
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
            grasps = [e.grasp.name for e in body.explores if e.grasp is not None] if body is not None else []
            if grasps and body.name not in with_correspondence:
                ctx.warn(
                    "W602",
                    f"`{placed.name}` is a tool (`{body.name}` is explored held by `{grasps[0]}`), but no correspondence "
                    f"names a frame of `{body.name}`, so no task can use it",
                    placed.type.span,
                    f"add e.g. `correspondences {{ {body.name}.tip ~ fingertip }}`, or `use stdlib.tools`",
                )


# ---------------------------------------------------------------- files


def _resolve_files(module: ir.Module, ctx: _Context) -> ir.Module:
    """The module with mesh and URDF paths made absolute (relative to the module's file)."""
    folder = Path(module.path).resolve().parent
    decls: list[Any] = []
    for decl in module.decls:
        if isinstance(decl, ir.Body):
            decl = decl.model_copy(update={"shape": _resolve_shape(decl.shape, folder)})
        elif isinstance(decl, ir.Robot):
            decl = decl.model_copy(update={"urdf_resolved": str((folder / decl.urdf).resolve())})
        decls.append(decl)
    return module.model_copy(update={"decls": decls})


def _resolve_shape(shape: Any, folder: Path) -> Any:
    if isinstance(shape, ir.MeshShape):
        return shape.model_copy(update={"resolved": str((folder / shape.path).resolve())})
    if isinstance(shape, ir.UnionShape):
        parts = [p.model_copy(update={"shape": _resolve_shape(p.shape, folder)}) for p in shape.parts]
        return shape.model_copy(update={"parts": parts})
    return shape


# ---------------------------------------------------------------- display


def _shown(q: ir.Quantity) -> str:
    from vkgl.lang.units import SCALE

    value = q.value / float(SCALE.get(q.unit, 1)) if q.unit in SCALE else q.value
    return f"`{value:g} {q.unit}`" if q.unit else f"`{value:g}`"


def _shown_vector(v: ir.Vector) -> str:
    from vkgl.lang.units import SCALE

    scale = float(SCALE.get(v.unit, 1))
    inner = ", ".join(f"{x / scale:g}" for x in v.values)
    return f"`({inner}) {v.unit}`" if v.unit else f"`({inner})`"
