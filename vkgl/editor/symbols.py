"""What a name under the cursor refers to, and where it is declared (hover and go to definition).

Names are looked up in the checked program of the file (every module it
`use`s, transitively): body types, robots, scenes, tasks, affordances,
frames (`grasp handle`, `Stick.tip`), effectors (`~ fingertip`), scene
bodies (`goal block at ...`), and the module of a `use` line.
Positions here are 0-based (line, character) in code points.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.program import Program

_WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_USE = re.compile(r"^\s*use\s+(\"[^\"\n]*\"|[A-Za-z_][A-Za-z0-9_.]*)")


@dataclass(frozen=True)
class Symbol:
    """A declared thing: its kind, name, IR node and where it is declared.

    `kind` is one of body, robot, scene, task, affordance, frame, effector,
    instance, module. `owner` is the body type of a frame or an affordance,
    the robot of an effector, the scene of an instance. `span` is the
    declaration's name where it can be found (else the whole declaration);
    a module has `file` instead.
    """

    kind: str
    name: str
    node: object
    span: ir.Span | None
    owner: str | None = None
    file: Path | None = None


def word_at(line: str, char: int) -> tuple[str, int, int] | None:
    """The name under (or just before) `char` in `line`: (word, start, end)."""
    for match in _WORD.finditer(line):
        if match.start() <= char <= match.end():
            return match.group(), match.start(), match.end()
    return None


def symbol_at(program: Program, path: Path, text: str, line: int, char: int) -> Symbol | None:
    """The symbol at 0-based (`line`, `char`) of the file `path` whose current text is `text`."""
    lines = text.split("\n")
    if not 0 <= line < len(lines):
        return None
    source_line = lines[line]
    if "#" in re.sub(r'"[^"\n]*"', "", source_line[:char]):
        return None  # in a comment
    module = _module_of(program, path)
    used = _use_at(module, source_line, line)
    if used is not None:
        return used
    found = word_at(source_line, char)
    if found is None:
        return None
    word, start, _ = found
    enclosing = _enclosing(module, line + 1, char + 1)
    if start > 0 and source_line[start - 1] == ".":
        qualifier = word_at(source_line, start - 2)
        if qualifier is not None:
            return _member(program, _body_type(program, enclosing, qualifier[0]), word)
    return _lookup(program, enclosing, word, source_line[:start])


def declaration_span(symbol: Symbol, sources: dict[str, str]) -> ir.Span | None:
    """The span of the declared name (narrowed from the whole declaration when needed)."""
    span = symbol.span
    if span is None or symbol.kind not in {"affordance", "effector", "instance"}:
        return span
    text = sources.get(span.file)
    if text is None:  # not a module of the compilation: nothing is read from disk for it
        return span
    lines = text.split("\n")
    if not 1 <= span.line <= len(lines):
        return span
    match = re.compile(r"\b" + re.escape(symbol.name) + r"\b").search(lines[span.line - 1], span.col - 1)
    if match is None:
        return span
    return ir.Span(
        file=span.file,
        line=span.line,
        col=match.start() + 1,
        end_line=span.line,
        end_col=match.end() + 1,
    )


def all_instances(program: Program) -> list[tuple[str, ir.SceneBody | ir.SceneRobot]]:
    """Every scene body and scene robot of the program, with its scene's name."""
    found: list[tuple[str, ir.SceneBody | ir.SceneRobot]] = []
    for scene in program.scenes.values():
        found.extend((scene.name, r) for r in scene.robots)
        found.extend((scene.name, b) for b in scene.bodies)
    return found


# ---------------------------------------------------------------- lookup


def _module_of(program: Program, path: Path) -> ir.Module | None:
    for key, module in program.modules.items():
        if Path(key).resolve() == path:
            return module
    return None


def _use_at(module: ir.Module | None, source_line: str, line: int) -> Symbol | None:
    match = _USE.match(source_line)
    if match is None or module is None:
        return None
    for use in module.uses:
        if use.span is not None and use.span.line == line + 1 and use.resolved:
            return Symbol("module", use.target, use, use.span, file=Path(use.resolved))
    return None


def _contains(span: ir.Span | None, line: int, col: int) -> bool:
    if span is None:
        return False
    after_start = (line, col) >= (span.line, span.col)
    before_end = (line, col) <= (span.end_line, span.end_col)
    return after_start and before_end


def _enclosing(module: ir.Module | None, line: int, col: int) -> ir.Node | None:
    if module is None:
        return None
    return next((d for d in module.decls if _contains(d.span, line, col)), None)


def _scene_of(program: Program, enclosing: ir.Node | None) -> ir.Scene | None:
    if isinstance(enclosing, ir.Scene):
        return enclosing
    if isinstance(enclosing, ir.Task):
        return program.scenes.get(enclosing.scene.name)
    return None


def _instance(scene: ir.Scene | None, name: str) -> ir.SceneBody | ir.SceneRobot | None:
    if scene is None:
        return None
    members: list[ir.SceneBody | ir.SceneRobot] = [*scene.robots, *scene.bodies]
    return next((x for x in members if x.name == name), None)


def _body_type(program: Program, enclosing: ir.Node | None, qualifier: str) -> str:
    """The body type a qualifier names: a type itself, or a scene body's type."""
    if qualifier in program.bodies:
        return qualifier
    found = _instance(_scene_of(program, enclosing), qualifier)
    if found is None:
        found = next((x for _, x in all_instances(program) if x.name == qualifier), None)
    return found.type.name if found is not None else qualifier


def _member(program: Program, body_type: str, name: str) -> Symbol | None:
    """`Body.name`: a frame or an affordance of the body type."""
    body = program.bodies.get(body_type)
    if body is not None and (frame := body.frame(name)) is not None:
        return Symbol("frame", name, frame, frame.name_span or frame.span, owner=body_type)
    for affordance in program.affordances.get(body_type, []):
        if affordance.name == name:
            return Symbol("affordance", name, affordance, affordance.span, owner=body_type)
    return None


def _lookup(program: Program, enclosing: ir.Node | None, word: str, before: str) -> Symbol | None:
    """A plain name: local things first (frames of this body, bodies of this scene), then global ones."""
    if isinstance(enclosing, ir.Body) and (frame := enclosing.frame(word)) is not None:
        return Symbol("frame", word, frame, frame.name_span or frame.span, owner=enclosing.name)
    if isinstance(enclosing, ir.AffordanceSet) and re.search(r"\baffordance\s+$", before):
        member = _member(program, enclosing.body.name, word)
        if member is not None:
            return member
    declared = _declared(program, word)
    if declared is not None:
        return declared
    scene = _scene_of(program, enclosing)
    found = _instance(scene, word)
    if found is not None and scene is not None:
        return Symbol("instance", word, found, found.span, owner=scene.name)
    for robot in program.robots.values():
        if (effector := robot.effector(word)) is not None:
            return Symbol("effector", word, effector, effector.span, owner=robot.name)
    for body_type, affordances in program.affordances.items():
        for affordance in affordances:
            if affordance.name == word:
                return Symbol("affordance", word, affordance, affordance.span, owner=body_type)
    for scene_name, instance in all_instances(program):
        if instance.name == word:
            return Symbol("instance", word, instance, instance.span, owner=scene_name)
    return None


def _declared(program: Program, word: str) -> Symbol | None:
    """A top-level declaration: body, robot, scene or task."""
    if word in program.bodies:
        body = program.bodies[word]
        return Symbol("body", word, body, body.name_span or body.span)
    if word in program.robots:
        robot = program.robots[word]
        return Symbol("robot", word, robot, robot.name_span or robot.span)
    if word in program.scenes:
        scene = program.scenes[word]
        return Symbol("scene", word, scene, scene.name_span or scene.span)
    if word in program.tasks:
        task = program.tasks[word]
        return Symbol("task", word, task, task.name_span or task.span)
    return None
