"""What the semantic checks share: the context of one compilation and the helpers of messages.

Used by vkgl/lang/checks/checker.py (names, scenes, tasks) and vkgl/lang/checks/body.py
(bodies, robots, explorations).
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from vkgl.lang.checks.learn_hint import stdlib_use_hint
from vkgl.lang.diagnostics import codes
from vkgl.lang.diagnostics.codes import Code
from vkgl.lang.diagnostics.diagnostic import Diagnostic
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import SCALE

if TYPE_CHECKING:
    from vkgl.lang.ir.program import Program

Named = ir.Body | ir.Robot | ir.Scene | ir.Task
KIND_WORD = {"body": "a body", "robot": "a robot", "scene": "a scene", "task": "a task"}


@dataclass
class CheckContext:
    """What the checks of one compilation share: the diagnostics so far, the flat namespace, the sources."""

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
        # model_construct: the values are typed already, and validating would build pydantic's validator of
        # Span and scan every installed package for pydantic plugins, a tenth of `vkgc check`'s start.
        return ir.Span.model_construct(
            file=span.file, line=span.line, col=start, end_line=span.line, end_col=start + len(match.group(1))
        )

    def error(self, code: Code, message: str, span: ir.Span | None, *notes: str) -> None:
        """Report an error of `code` (empty notes are dropped)."""
        self.diagnostics.append(code.diagnostic(message, span, *notes))

    def warn(self, code: Code, message: str, span: ir.Span | None, *notes: str) -> None:
        """Report a warning of `code` (a W code; empty notes are dropped)."""
        self.diagnostics.append(code.diagnostic(message, span, *notes))


def lookup(ref: ir.Ref, kind: str, ctx: CheckContext) -> Any:
    """The declaration `ref` names if it is of `kind`; otherwise an error with a suggestion."""
    entry = ctx.names.get(ref.name)
    if entry is None:
        candidates = [n for n, (d, _) in ctx.names.items() if d.kind == kind]
        note = did_you_mean(ref.name, candidates)
        if kind in ("body", "robot") and not note.startswith("did you mean"):
            note = stdlib_use_hint(ref.name, kind) or note  # a forgotten `use` of the stdlib
            note = note or f"declare `{kind} {ref.name} {{ ... }}` or `use` the module that declares it"
        ctx.error(codes.UNKNOWN_NAME, f"unknown {kind} `{ref.name}`", ref.span, note)
        return None
    decl = entry[0]
    if decl.kind != kind:
        ctx.error(
            codes.WRONG_KIND,
            f"`{ref.name}` is {KIND_WORD[decl.kind]}, not {KIND_WORD[kind]}",
            ref.span,
            f"`{ref.name}` is declared at {where_declared(decl)}",
        )
        return None
    return decl


def goals_with_types(program: Program) -> Iterator[tuple[ir.Goal, str]]:
    """Every goal of every task whose scene is known, with the type name of the scene body it is on ("" when
    the scene has no such body)."""
    for task in program.tasks.values():
        scene = program.scenes.get(task.scene.name)
        if scene is None:
            continue
        types = {b.name: b.type.name for b in scene.bodies}
        for goal in task.goals:
            yield goal, types.get(goal.body.name, "")


def did_you_mean(name: str, candidates: list[str]) -> str:
    """A note suggesting the closest candidate, or listing a few; "" when there is nothing to say."""
    match = difflib.get_close_matches(name, sorted(set(candidates)), n=1, cutoff=0.6)
    if match:
        return f"did you mean `{match[0]}`?"
    if candidates and len(candidates) <= 8:
        return "known: " + ", ".join(f"`{c}`" for c in sorted(set(candidates)))
    return ""


def where_declared(node: ir.Node) -> str:
    """`path:line:col` of a declaration's name (or of the node)."""
    span = getattr(node, "name_span", None) or node.span
    return str(span) if span is not None else "<unknown>"


def duplicates(items: list[Any], what: str, ctx: CheckContext, name_of: Any = lambda x: x.name) -> None:
    """Report each item whose name an earlier item of `items` already has."""
    seen: dict[str, Any] = {}
    for item in items:
        name = name_of(item)
        if name in seen:
            ctx.error(
                codes.DUPLICATE_NAME,
                f"{what} `{name}` is declared twice",
                item.span,
                f"first declared at {seen[name].span}",
            )
        else:
            seen[name] = item


def shown(q: ir.Quantity) -> str:
    """A quantity in its display unit, quoted for a message: `10 cm`."""
    value = q.value / float(SCALE.get(q.unit, 1)) if q.unit in SCALE else q.value
    return f"`{value:g} {q.unit}`" if q.unit else f"`{value:g}`"


def shown_vector(v: ir.Vector) -> str:
    """A vector in its display unit, quoted for a message: `(10, 20, 5) cm`."""
    scale = float(SCALE.get(v.unit, 1))
    inner = ", ".join(f"{x / scale:g}" for x in v.values)
    return f"`({inner}) {v.unit}`" if v.unit else f"`({inner})`"


def unknown_frame(body: ir.Body, name: str, span: ir.Span | None, ctx: CheckContext) -> None:
    """Report that `body` has no frame `name`, suggesting the closest frame."""
    frames = [f.name for f in body.frames]
    ctx.error(
        codes.UNKNOWN_FRAME,
        f"body `{body.name}` has no frame `{name}`",
        span,
        did_you_mean(name, frames) or _no_frames(frames),
    )


def _no_frames(frames: list[str]) -> str:
    return "" if frames else "it declares no frames: add e.g. `frame tip = (20, 0, 0) cm`"
