"""Hover text (Markdown): what a symbol is, and a quantity's SI value.

A body shows its shape, mass, friction, joint and frames; an affordance its
action, motion and evidence; a scene body its type and placement (`in
cabinet`, `at shelf.top` as written); a scene its bodies and regions; a task
its goals as written (relative and region goals included) and its keep-out
regions; a quantity (`10 cm`, `90deg`, `(10, 20, 5) cm`) its value in SI units.
"""

from __future__ import annotations

import re

from vkgl.editor.symbols import Symbol
from vkgl.editor.vocabulary import NUMBER_PATTERN, units
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import DIMENSION, SI_UNIT, to_si
from vkgl.lang.syntax.printer import (
    constraint_text,
    format_number,
    goal_text,
    joint_text,
    keep_out_text,
    placement_text,
    pose_text,
    quantity_text,
    region_text,
    vector_text,
)

_UNIT = "(?:" + "|".join(units()) + r")(?![A-Za-z0-9_])"
_QUANTITY = re.compile(r"(?<![A-Za-z0-9_.])(" + NUMBER_PATTERN + r")(?:[ \t]*(" + _UNIT + "))?")
_VECTOR = re.compile(r"\(([^()\n]*)\)(?:[ \t]*(" + _UNIT + "))?")


def quantity_hover(line: str, char: int) -> tuple[str, int, int] | None:
    """Markdown for the quantity or vector under `char` of `line`, with its (start, end) columns."""
    for match in _VECTOR.finditer(line):
        if match.group(2) and match.start() <= char <= match.end():
            text = _vector_si(match.group(1), match.group(2))
            if text is not None:
                return f"`{match.group(0)}` = {text}", match.start(), match.end()
    for match in _QUANTITY.finditer(line):
        if match.group(2) and match.start() <= char <= match.end():
            unit = match.group(2)
            dimension = DIMENSION[unit]
            shown = f"{_si(match.group(1), unit)} {SI_UNIT[dimension]}"
            return (
                f"`{match.group(0)}` = {shown} ({dimension})",
                match.start(),
                match.end(),
            )
    return None


def _vector_si(inside: str, unit: str) -> str | None:
    """`(0.1, 0.2, 0.05) m (length)` for the components of a vector written in `unit`."""
    values = []
    for part in inside.split(","):
        match = re.fullmatch(r"\s*(" + NUMBER_PATTERN + r")\s*(" + _UNIT + r")?\s*", part)
        if match is None:
            return None
        values.append(_si(match.group(1), match.group(2) or unit))
    dimension = DIMENSION[unit]
    return f"({', '.join(values)}) {SI_UNIT[dimension]} ({dimension})"


def _si(number: str, unit: str) -> str:
    """The SI value of `number` written in `unit`, to 6 significant digits."""
    return f"{to_si(number, unit):.6g}"


def symbol_hover(symbol: Symbol, declared: ir.Span | None = None) -> str:
    """Markdown describing `symbol`: a heading line, its parts, and where it is `declared`."""
    node = symbol.node
    declared = declared or symbol.span
    where = f"\n\n*declared at {declared}*" if declared is not None else ""
    if isinstance(node, ir.Body):
        return body_hover(node) + where
    if isinstance(node, ir.Affordance):
        return affordance_hover(node, symbol.owner or "?") + where
    if isinstance(node, ir.Frame):
        return f"**frame** `{symbol.owner}.{node.name}` = `{pose_text(node.pose)}`" + where
    if isinstance(node, ir.Robot):
        effectors = "".join(
            f"\n- effector `{e.name}` = link `{e.link}` offset `{pose_text(e.offset)}`" for e in node.effectors
        )
        return f"**robot** `{node.name}`\n\nurdf `{node.urdf}`{effectors}" + where
    if isinstance(node, ir.Effector):
        return (
            f"**effector** `{symbol.owner}.{node.name}` = link `{node.link}` offset `{pose_text(node.offset)}`"
        ) + where
    if isinstance(node, (ir.SceneBody, ir.SceneRobot)):
        return _instance_hover(node, symbol.owner or "?") + where
    if isinstance(node, ir.Scene):
        members: list[ir.SceneBody | ir.SceneRobot] = [*node.robots, *node.bodies]
        inside = ", ".join(f"`{x.name} : {x.type.name}`" for x in members)
        regions = "".join(f"\n- region `{r.name} = {region_text(r)}`" for r in node.regions)
        return f"**scene** `{node.name}`\n\n{inside}{regions}" + where
    if isinstance(node, ir.Task):
        goals = "".join(f"\n- goal `{goal_text(g)}`" for g in node.goals)
        goals += "".join(f"\n- `{keep_out_text(k)}`" for k in node.keep_out)
        return f"**task** `{node.name}`\n\nscene `{node.scene.name}`{goals}" + where
    if symbol.kind == "module":
        return f"**module** `{symbol.name}`\n\n`{symbol.file}`"
    return f"`{symbol.name}`"


def body_hover(body: ir.Body) -> str:
    """A body: shape, mass (with SI value), friction, joint, frames."""
    lines = [
        f"**body** `{body.name}`",
        "",
        f"- shape `{shape_text(body.shape)}`",
        f"- mass `{quantity_text(body.mass)}` = {format_number(body.mass.value)} kg",
    ]
    if body.friction is not None:
        lines.append(f"- friction `{format_number(body.friction)}`")
    if body.joint is not None:
        lines.append(f"- joint `{joint_text(body.joint)}`")
    if body.frames:
        lines.append("- frames: " + ", ".join(f"`{f.name} = {pose_text(f.pose)}`" for f in body.frames))
    else:
        lines.append("- frames: none")
    return "\n".join(lines)


def affordance_hover(affordance: ir.Affordance, body: str) -> str:
    """An affordance: its motion (object-world), action (robot-object) and evidence."""
    lines = [
        f"**affordance** `{body}.{affordance.name}`",
        "",
        f"- motion `{constraint_text(affordance.motion)}`",
        f"- action `{constraint_text(affordance.action)}`",
    ]
    evidence = affordance.evidence
    if evidence is not None:
        lines.append(
            f"- evidence: {evidence.trials} trials, loglik {format_number(evidence.loglik)}, "
            f"posterior {format_number(evidence.posterior)}"
            + ("" if evidence.slip is None else f", slip {format_number(round(evidence.slip * 1000, 3))} mm")
        )
    else:
        lines.append("- evidence: none (written by hand)")
    return "\n".join(lines)


def shape_text(shape: ir.Shape) -> str:
    """A shape as it is written (a union as `union of N parts`)."""
    if isinstance(shape, ir.BoxShape):
        return "box " + vector_text(shape.size)
    if isinstance(shape, ir.CylinderShape):
        return f"cylinder radius {quantity_text(shape.radius)} height {quantity_text(shape.height)}"
    if isinstance(shape, ir.MeshShape):
        return f'mesh "{shape.path}"' + ("" if shape.scale == 1.0 else f" scale {format_number(shape.scale)}")
    parts = "; ".join(f"{shape_text(p.shape)} at {pose_text(p.pose)}" for p in shape.parts)
    return f"union {{ {parts} }}"


def _instance_hover(node: ir.SceneBody | ir.SceneRobot, scene: str) -> str:
    if isinstance(node, ir.SceneRobot):
        return f"**robot** `{node.name} : {node.type.name}` in scene `{scene}` at `{pose_text(node.pose)}`"
    opened = f", its joint starting open `{quantity_text(node.opening)}`" if node.opening is not None else ""
    return (
        f"**scene body** `{node.name} : {node.type.name}` in scene `{scene}`, "
        f"`{placement_text(node.placement)}`{opened}"
    )
