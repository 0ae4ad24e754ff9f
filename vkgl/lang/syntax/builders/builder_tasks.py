"""The builder's rules for tasks: scene, goals (pose, heading, joint and relative goals) and the search block.

`TaskBuilder` holds the methods of the task rules of grammar/vkg.lark; the
`Builder` (vkgl/lang/syntax/builder.py) derives from it. A joint goal's opening is a
length or an angle here; whether it is the right one for the body's joint is
the checker's question (vkgl/lang/checks/joints.py), since the body's type is
only known once names are resolved.
"""

from __future__ import annotations

from typing import Any

from lark import Token

from vkgl.lang.diagnostics import codes
from vkgl.lang.ir import nodes as ir
from vkgl.lang.ir.units import ARTICLE_NAME, dimension_of
from vkgl.lang.syntax.builders.builder_regions import POSITION_TOLERANCE_NOTE, RegionBuilder
from vkgl.lang.syntax.values import INVALID, Item, RawQ, new_node

OPENING_UNITS = "a length (`cm`) for a prismatic joint, an angle (`deg`) for a revolute one"


class TaskBuilder(RegionBuilder):
    """The IR of `task` blocks; one method per grammar rule, as in `Builder`."""

    def task(self, meta: Any, children: list[Any]) -> ir.Task:
        name, items = children[0], children[1:]
        owner = f"task `{name}`"
        fields = self.single(
            [i for i in items if i.key not in ("goal", "keep")], owner, {"scene": "scene tabletop"}, self.tspan(name)
        )
        goals = [g for i in items if i.key == "goal" for g in i.value]
        if not goals:
            self.error(
                codes.TASK_WITHOUT_GOAL,
                f"{owner} has no goal: add e.g. `goal block at (0.6, 0) m within 1 cm`",
                self.tspan(name),
            )
        return new_node(
            ir.Task,
            name=str(name),
            scene=fields.get("scene", new_node(ir.Ref, name="")),
            goals=goals,
            search=fields.get("search"),
            keep_out=[i.value for i in items if i.key == "keep"],
            span=self.span(meta),
            name_span=self.tspan(name),
        )

    def task_scene(self, meta: Any, children: list[Token]) -> Item:
        return Item("scene", new_node(ir.Ref, name=str(children[0]), span=self.tspan(children[0])), self.span(meta))

    def task_goal(self, meta: Any, children: list[Any]) -> Item:
        return Item("goal", children, self.span(meta))

    def goal_at(self, meta: Any, children: list[Any]) -> ir.Goal:
        body, vector = children[0], children[1]
        rest = children[2:]
        yaw = self.to_quantity(rest.pop(0), "angle") if rest and isinstance(rest[0], RawQ) else None
        tolerances: list[RawQ] = rest[0] if rest else []
        tol_position = self.to_quantity(tolerances[0], "length", POSITION_TOLERANCE_NOTE) if tolerances else None
        tol_yaw = self.to_quantity(tolerances[1], "angle") if len(tolerances) > 1 else None
        return new_node(
            ir.Goal,
            body=new_node(ir.Ref, name=str(body), span=self.tspan(body)),
            position=self.to_vector(vector, "length", (2, 3), "a goal position"),
            yaw=yaw,
            tol_position=tol_position,
            tol_yaw=tol_yaw,
            span=self.span(meta),
        )

    def goal_yaw(self, meta: Any, children: list[Any]) -> ir.Goal:
        body, yaw = children[0], children[1]
        tolerances: list[RawQ] = children[2] if len(children) > 2 else []
        if len(tolerances) > 1:
            self.error(
                codes.WRONG_COMPONENT_COUNT,
                "a heading goal takes one tolerance, an angle: `within 3 deg`",
                tolerances[1].span,
            )
        return new_node(
            ir.Goal,
            body=new_node(ir.Ref, name=str(body), span=self.tspan(body)),
            yaw=self.to_quantity(yaw, "angle"),
            tol_yaw=self.to_quantity(tolerances[0], "angle") if tolerances else None,
            span=self.span(meta),
        )

    def goal_moved(self, meta: Any, children: list[Any]) -> ir.Goal:
        """`B moved by V [in F] [turned by Q] [within L[, A]]`: a displacement from the body's start."""
        body, vector = children[0], children[1]
        parts = {c.key: c.value for c in children[2:] if isinstance(c, Item)}
        tolerances: list[RawQ] = next((c for c in children[2:] if isinstance(c, list)), [])
        turned = parts.get("turned")
        return new_node(
            ir.Goal,
            body=new_node(ir.Ref, name=str(body), span=self.tspan(body)),
            moved_by=self.to_vector(vector, "length", (2, 3), "a displacement"),
            moved_in=parts.get("in"),
            turned_by=self.to_quantity(turned, "angle") if turned is not None else None,
            tol_position=self.to_quantity(tolerances[0], "length", POSITION_TOLERANCE_NOTE) if tolerances else None,
            tol_yaw=self.to_quantity(tolerances[1], "angle") if len(tolerances) > 1 else None,
            span=self.span(meta),
        )

    def moved_in(self, meta: Any, children: list[Token]) -> Item:
        return Item("in", new_node(ir.Ref, name=str(children[0]), span=self.tspan(children[0])), self.span(meta))

    def turned_by(self, meta: Any, children: list[RawQ]) -> Item:
        return Item("turned", children[0], self.span(meta))

    def goal_turned(self, meta: Any, children: list[Any]) -> ir.Goal:
        """`B turned by Q [within A]`: a turn about z from the body's start heading."""
        body, turned = children[0], children[1]
        tolerances: list[RawQ] = children[2] if len(children) > 2 else []
        if len(tolerances) > 1:
            self.error(
                codes.WRONG_COMPONENT_COUNT,
                "a turn goal takes one tolerance, an angle: `within 3 deg`",
                tolerances[1].span,
            )
        return new_node(
            ir.Goal,
            body=new_node(ir.Ref, name=str(body), span=self.tspan(body)),
            turned_by=self.to_quantity(turned.value, "angle"),
            tol_yaw=self.to_quantity(tolerances[0], "angle") if tolerances else None,
            span=self.span(meta),
        )

    def goal_open(self, meta: Any, children: list[Any]) -> ir.Goal:
        """`B open Q [within Q]`: a length or an angle, the tolerance of the same kind as the opening."""
        body, raw = children[0], children[1]
        tolerances: list[RawQ] = children[2] if len(children) > 2 else []
        if len(tolerances) > 1:
            self.error(
                codes.WRONG_COMPONENT_COUNT,
                "a joint goal takes one tolerance, of the opening's kind: `within 1 cm` or `within 3 deg`",
                tolerances[1].span,
            )
        opening = self._opening(raw)
        tolerance = None
        if tolerances:
            kind = dimension_of(raw.unit)
            # The tolerance is of the opening's kind; when the opening's own unit was wrong, either kind will do.
            if kind in ("length", "angle"):
                tolerance = self.to_quantity(tolerances[0], kind)
            else:
                tolerance = self._opening(tolerances[0])
        return new_node(
            ir.Goal,
            body=new_node(ir.Ref, name=str(body), span=self.tspan(body)),
            opening=opening,
            tol_opening=tolerance,
            span=self.span(meta),
        )

    def _opening(self, raw: RawQ) -> ir.Quantity:
        """A joint coordinate as written: a length or an angle (which one the body's joint decides later)."""
        got = dimension_of(raw.unit)
        if got in ("length", "angle"):
            return new_node(ir.Quantity, value=self.si(raw, raw.unit), unit=raw.unit, span=raw.span)
        message = f"expected a length or an angle, got {ARTICLE_NAME[got]} `{raw.written}`"
        if got == "number":
            self.error(codes.MISSING_UNIT, message, raw.span, f"add a unit: {OPENING_UNITS}")
        else:
            self.error(codes.WRONG_DIMENSION, message, raw.span, f"use {OPENING_UNITS}")
        return new_node(ir.Quantity, value=INVALID, unit="", span=raw.span)

    def within(self, meta: Any, children: list[RawQ]) -> list[RawQ]:
        return children

    def task_search(self, meta: Any, children: list[Any]) -> Item:
        fields = self.single(children, "`search`", {}, self.span(meta))
        spec = new_node(
            ir.SearchSpec, max_depth=fields.get("max_depth"), timeout=fields.get("timeout"), span=self.span(meta)
        )
        return Item("search", spec, self.span(meta))

    def max_depth(self, meta: Any, children: list[Any]) -> Item:
        return Item("max_depth", self.integer(children[0], "`max_depth`"), self.span(meta))

    def timeout(self, meta: Any, children: list[Any]) -> Item:
        return Item("timeout", self.to_quantity(children[0], "time"), self.span(meta))
